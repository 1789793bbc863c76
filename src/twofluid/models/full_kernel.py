"""The full 1D model's Newton iterate (element ``1VW/0P/0n``) as compiled loops around the closure calls.

The same equations as the general weak-form assembly of :meth:`TwoFluid1D.assemble
<twofluid.models.two_fluid_1d.TwoFluid1D.assemble>` (``fem/terms_1d`` into a BlockSystem, the
quadratic element's and the Picard linearisation's only path) with :meth:`BandSolver.solve
<twofluid.fem.banded.BandSolver.solve>`, derived independently: the tests compare the band
matrix and right-hand side of an iterate to round-off (``tests/unit/test_full_kernel.py``):

- :func:`_closure_points` — from the iterate (n, V, W) the porosities and slips at which the
  drag law is called, (n, |s|), (n, |s| + δs), (n + δn, |s(n + δn)|), whose last two thirds
  of porosities, (n, n + δn), are also those of μ_s;
- the closures themselves stay pure vectorised functions from the registry, called once per
  iterate by the model (drag at the three points, μ_s at two, P_s and its derivative);
- :func:`_band_system` — from the closure values and the old state, every element and vertex
  term of the iterate (inertia, weight, viscous terms with μ_s and 1/n Newton-linearised, P_s
  Taylor-expanded, the drag with the step's upwind tests ψ, the liquid pressure jumps, the
  upwinded solids flux), summed straight into LAPACK band storage: the unknowns numbered
  along the line as :class:`~twofluid.fem.banded.BandSolver` numbers them, V_i, W_i, P_e, n_e
  at 4i, 4i + 1, 4e + 2, 4e + 3, half-widths kl = ku = 5;
- :func:`_residual` — minus the residual at the iterate (A aᵏ summed term by term as the
  entries are added, as the sparse scatter does), the prescribed rows made identity
  rows on the matrix's scale (a copy: the assembled matrix stays for ``matrix()``);
  :func:`twofluid.fem.banded.band_lu` (LAPACK's algorithm) solves it and :func:`_unpack`
  adds the increment to the iterate.

What the general assembly spends on ~150 array operations of a few hundred entries and a
sparse scatter is here a few loops over the elements. Built ahead of time through
:func:`twofluid.compiled.group` (later processes import the module without numba).

>>> ok = available()
>>> isinstance(ok, bool)
True
"""
from __future__ import annotations

import numpy as np

from ..closures.viscosity import solid_viscosity
from ..fem import banded as _bd
from . import reduced_kernel
from .data_1d import _times

__all__ = ["available", "kernels", "KL", "KU", "LDAB", "band_position"]

_CLEAR = 1e-6  # as two_fluid_1d._CLEAR: floor of 1 − n in the slip and the upwind ratio
KL = KU = 5  # half-widths of the band (V_i − W_{i±1}: 5 apart)
_KV = KL + KU  # row of the main diagonal in LAPACK band storage (the first KL rows: fill-in)
LDAB = 2 * KL + KU + 1
# rows of the model's element constants ``mc``: M (2×2), Kv (2×2), ∫N (2), ∫∇·N (2), ∫BN (2),
# element-mean weights (2), volume
MC_ROWS = 17


def band_position(g: np.ndarray, nv: int, ne: int) -> np.ndarray:
    """Band row of global unknowns ``g`` (V, W, P, n blocks) of the linear element.

    >>> band_position(np.array([0, 3, 4, 6, 8]), 3, 2).tolist()  # V_0, W_0, W_1, P_0, n_0
    [0, 1, 5, 2, 3]
    """
    g = np.asarray(g)
    return np.select([g < nv, g < 2 * nv, g < 2 * nv + ne],
                     [4 * g, 4 * (g - nv) + 1, 4 * (g - 2 * nv) + 2], 4 * (g - 2 * nv - ne) + 3)


def _fmax(x, c):
    """np.maximum(x, c) for a scalar: NaN propagates."""
    return x if not x < c else c


def _put(ab, Aa, ak, r, c, x):
    """Add ``x`` to entry (r, c) of the band matrix and its product with the iterate to row r of
    ``Aa`` = A aᵏ, term by term as the sparse scatter does: Newton terms that appear on both sides
    then cancel exactly in the residual f − A aᵏ (summed into the matrix first, a small term is
    lost against a large diagonal and the residual drifts: solids volume by 1e-14 over a run)."""
    ab[_bd._u(_KV + r - c), _bd._u(c)] += x  # (unsigned indices: banded._u)
    Aa[_bd._u(r)] += x * ak[_bd._u(c)]


def _closure_points(n, V, W, w0, w1, x3, s3):
    """Porosities ``x3`` and slips ``s3`` (3 ne) of the drag-law call of :meth:`TwoFluid1D._drag`."""
    ne = n.size
    for e in range(ne):
        ni = n[e]
        dn = 1e-8 if ni < 0.5 else -1e-8
        omn = 1.0 - 2.0 * ni
        q0 = omn * V[e] + W[e]
        q1 = omn * V[e + 1] + W[e + 1]
        d2 = 2.0 * dn
        qbar = q0 * w0[e] + q1 * w1[e]
        nn = ni + dn
        s_abs = abs(qbar) / (2.0 * ni * _fmax(1.0 - ni, _CLEAR))
        ds = 1e-6 * _fmax(s_abs, 1e-6)
        qnb = (q0 - d2 * V[e]) * w0[e] + (q1 - d2 * V[e + 1]) * w1[e]
        x3[e] = ni
        x3[ne + e] = ni
        x3[2 * ne + e] = nn
        s3[e] = s_abs
        s3[ne + e] = s_abs + ds
        s3[2 * ne + e] = abs(qnb) / (2.0 * nn * _fmax(1.0 - nn, _CLEAR))


def _band_system(n, V, W, P, oldV, oldW, oldn, alpha, K3, mu2, ps, dps, mc, vc, below, have_below,
                 viscous, upwind, rho_f, rho_s, mu_f, g_y, dt, bot_out, p_bot, top_out, p_top, ab, f, Aa):
    """The iterate's matrix in band storage ``ab`` (LDAB, N; entry (r, c) at ab[KV + r − c, c]),
    right-hand side ``f`` (N) and A aᵏ ``Aa`` (N), all in band order: what
    :meth:`TwoFluid1D.assemble` adds up.

    ``mc`` (MC_ROWS, ne) the element constants, ``vc`` (3, nv) the vertex areas and the weights
    ∫N of the elements below and above each vertex; ``below`` (nv) the upwind side as 0/1
    (read if ``have_below``); ``K3``, ``mu2``, ``ps``, ``dps`` the closure values.
    """
    ne = n.size
    nv = ne + 1
    area = vc[0]
    for j in range(ab.shape[1]):  # (in storage order)
        for i in range(ab.shape[0]):
            ab[i, j] = 0.0
    ak = np.empty(f.size)  # the iterate in band order
    for i in range(nv):
        ak[4 * i] = V[i]
        ak[4 * i + 1] = W[i]
    for e in range(ne):
        ak[4 * e + 2] = P[e]
        ak[4 * e + 3] = n[e]
    for j in range(f.size):
        f[j] = 0.0
        Aa[j] = 0.0
    rho_hat = 0.5 * (rho_s + rho_f)
    d_rho = 0.5 * (rho_s - rho_f)
    cV = rho_hat / dt
    cW = -d_rho / dt
    gsrc = rho_f * g_y
    gb = (rho_s - rho_f) * g_y
    for e in range(ne):
        ni = n[e]
        pV0, pW0, pP, pN = 4 * e, 4 * e + 1, 4 * e + 2, 4 * e + 3
        pV1, pW1 = 4 * e + 4, 4 * e + 5
        M00, M01, M10, M11 = mc[0, e], mc[1, e], mc[2, e], mc[3, e]
        K00, K01, K10, K11 = mc[4, e], mc[5, e], mc[6, e], mc[7, e]
        s0, s1, B0, B1 = mc[8, e], mc[9, e], mc[10, e], mc[11, e]
        BN0, BN1, w0, w1 = mc[12, e], mc[13, e], mc[14, e], mc[15, e]
        Va, Vb, Wa, Wb = V[e], V[e + 1], W[e], W[e + 1]
        al = alpha[e]
        # the element's entries: vV_ij row V_i, column V_j (local i, j), vW_ij column W_j, vn_i column
        # n_e; wV, wW, wn the W rows; fV, fW the right-hand side
        # ---- the step's terms (TwoFluid1D._step_terms): inertia, pressure, weight
        vV00, vV01, vV10, vV11 = cV * M00, cV * M01, cV * M10, cV * M11
        vW00, vW01, vW10, vW11 = cW * M00, cW * M01, cW * M10, cW * M11
        u0 = rho_hat * oldV[e] - d_rho * oldW[e]
        u1 = rho_hat * oldV[e + 1] - d_rho * oldW[e + 1]
        fV0 = (M00 * u0 + M01 * u1) / dt + gsrc * s0
        fV1 = (M10 * u0 + M11 * u1) / dt + gsrc * s1
        bsum = (BN0 + BN1) * al
        sp0 = s0 - bsum  # ∫ψ_i: the upwind tests of the buoyant weight
        sp1 = s1 + bsum
        vn0 = gb * sp0
        vn1 = gb * sp1
        fV0 += gb * sp0
        fV1 += gb * sp1
        fW0 = gsrc * s0
        fW1 = gsrc * s1
        f[pN] += 2.0 * mc[16, e] / dt * oldn[e]  # the porosity rows: 2 Vol/Δt nᵗ
        _put(ab, Aa, ak, pV0, pP, -B0)  # −∫ ∇·δV P
        _put(ab, Aa, ak, pV1, pP, -B1)
        _put(ab, Aa, ak, pP, pV0, B0)  # continuity
        _put(ab, Aa, ak, pP, pV1, B1)
        # Mψ = M + α σ_i BN_j (σ = −1, +1) of the drag
        ma = -al
        P00, P01 = M00 + ma * BN0, M01 + ma * BN1
        P10, P11 = M10 + al * BN0, M11 + al * BN1
        ov0 = oldV[e] + oldW[e]
        ov1 = oldV[e + 1] + oldW[e + 1]
        MVWo0 = M00 * ov0 + M01 * ov1
        MVWo1 = M10 * ov0 + M11 * ov1
        # ---- the iterate's terms: liquid inertia per unit liquid volume, h = ρ_f/(2nΔt)
        h = 0.5 * rho_f / dt / ni
        wV00, wV01, wV10, wV11 = h * M00, h * M01, h * M10, h * M11
        wW00, wW01, wW10, wW11 = wV00, wV01, wV10, wV11
        fW0 += h * MVWo0
        fW1 += h * MVWo1
        vk0 = Va + Wa
        vk1 = Vb + Wb
        hn = -h / ni
        dW0 = ((M00 * vk0 + M01 * vk1) - MVWo0) * hn
        dW1 = ((M10 * vk0 + M11 * vk1) - MVWo1) * hn
        dn = 1e-8 if ni < 0.5 else -1e-8
        if viscous:
            mu_s = mu2[e]
            cvv = 0.5 * (mu_f + mu_s)
            cvw = 0.5 * (mu_f - mu_s)
            vV00 += cvv * K00
            vV01 += cvv * K01
            vV10 += cvv * K10
            vV11 += cvv * K11
            vW00 += cvw * K00
            vW01 += cvw * K01
            vW10 += cvw * K10
            vW11 += cvw * K11
            ml = 0.5 * mu_f / ni
            wV00 += ml * K00
            wV01 += ml * K01
            wV10 += ml * K10
            wV11 += ml * K11
            wW00 += ml * K00
            wW01 += ml * K01
            wW10 += ml * K10
            wW11 += ml * K11
            dmu = (mu2[ne + e] - mu_s) / dn
            hd = 0.5 * dmu
            dv0 = Va - Wa
            dv1 = Vb - Wb
            dV0 = hd * (K00 * dv0 + K01 * dv1)
            dV1 = hd * (K10 * dv0 + K11 * dv1)
            vn0 += dV0
            vn1 += dV1
            fV0 += dV0 * ni
            fV1 += dV1 * ni
            cm = 0.5 * mu_f / (ni * ni)
            dW0 -= cm * (K00 * vk0 + K01 * vk1)
            dW1 -= cm * (K10 * vk0 + K11 * vk1)
        wn0 = dW0
        wn1 = dW1
        fW0 += dW0 * ni
        fW1 += dW1 * ni
        # P_s Taylor-expanded about the iterate
        vn0 += (-B0) * dps[e]
        vn1 += (-B1) * dps[e]
        fV0 += B0 * (ps[e] - dps[e] * ni)
        fV1 += B1 * (ps[e] - dps[e] * ni)
        # drag K Mψ q/(2n²), Newton in V, W (exact) and n (finite difference)
        omn = 1.0 - 2.0 * ni
        q0 = omn * Va + Wa
        q1 = omn * Vb + Wb
        d2 = 2.0 * dn
        qn0 = q0 - d2 * Va
        qn1 = q1 - d2 * Vb
        qbar = q0 * w0 + q1 * w1
        nn = ni + dn
        s_abs = abs(qbar) / (2.0 * ni * _fmax(1.0 - ni, _CLEAR))
        ds = 1e-6 * _fmax(s_abs, 1e-6)
        K0 = K3[e]
        dK = (K3[ne + e] - K0) / ds * s_abs
        gain = dK / qbar if abs(qbar) > 0.0 else 0.0
        Mq0 = P00 * q0 + P01 * q1
        Mq1 = P10 * q0 + P11 * q1
        c0 = K0 / (2.0 * ni * ni)
        D0 = c0 * Mq0
        D1 = c0 * Mq1
        cn = K3[2 * ne + e] / (2.0 * nn * nn)
        Jn0 = (cn * (P00 * qn0 + P01 * qn1) - D0) / dn
        Jn1 = (cn * (P10 * qn0 + P11 * qn1) - D1) / dn
        gq = gain / (2.0 * ni * ni)
        J00 = c0 * P00 + gq * Mq0 * w0
        J01 = c0 * P01 + gq * Mq0 * w1
        J10 = c0 * P10 + gq * Mq1 * w0
        J11 = c0 * P11 + gq * Mq1 * w1
        wV00 += omn * J00
        wV01 += omn * J01
        wV10 += omn * J10
        wV11 += omn * J11
        wW00 += J00
        wW01 += J01
        wW10 += J10
        wW11 += J11
        wn0 += Jn0
        wn1 += Jn1
        fW0 += ((J00 * q0 + J01 * q1) + Jn0 * ni) - D0
        fW1 += ((J10 * q0 + J11 * q1) + Jn1 * ni) - D1
        # scatter the element's V and W rows
        _put(ab, Aa, ak, pV0, pV0, vV00)
        _put(ab, Aa, ak, pV0, pV1, vV01)
        _put(ab, Aa, ak, pV1, pV0, vV10)
        _put(ab, Aa, ak, pV1, pV1, vV11)
        _put(ab, Aa, ak, pV0, pW0, vW00)
        _put(ab, Aa, ak, pV0, pW1, vW01)
        _put(ab, Aa, ak, pV1, pW0, vW10)
        _put(ab, Aa, ak, pV1, pW1, vW11)
        _put(ab, Aa, ak, pV0, pN, vn0)
        _put(ab, Aa, ak, pV1, pN, vn1)
        _put(ab, Aa, ak, pW0, pV0, wV00)
        _put(ab, Aa, ak, pW0, pV1, wV01)
        _put(ab, Aa, ak, pW1, pV0, wV10)
        _put(ab, Aa, ak, pW1, pV1, wV11)
        _put(ab, Aa, ak, pW0, pW0, wW00)
        _put(ab, Aa, ak, pW0, pW1, wW01)
        _put(ab, Aa, ak, pW1, pW0, wW10)
        _put(ab, Aa, ak, pW1, pW1, wW11)
        _put(ab, Aa, ak, pW0, pN, wn0)
        _put(ab, Aa, ak, pW1, pN, wn1)
        f[pV0] += fV0
        f[pV1] += fV1
        f[pW0] += fW0
        f[pW1] += fW1
    # ---- vertices: the liquid pressure jumps A [[P]] and the solids flux (TwoFluid1D._solids_flux)
    for v in range(1, ne):  # [[P]] = P_above − P_below at the inner vertices
        pW = 4 * v + 1
        _put(ab, Aa, ak, pW, 4 * v + 2, area[v])
        _put(ab, Aa, ak, pW, 4 * v - 2, -area[v])
    if bot_out:
        _put(ab, Aa, ak, 1, 2, area[0])
        f[1] += area[0] * p_bot
        f[0] += (1.0 * p_bot) * area[0]  # the traction of the outlet pressure in the mixture row
    if top_out:
        pW, pP = 4 * ne + 1, 4 * ne - 2
        _put(ab, Aa, ak, pW, pP, -area[ne])
        f[pW] += (-area[ne]) * p_top
        f[4 * ne] += (-1.0 * p_top) * area[ne]
    g_prev = 0.0  # 2 A F, dr_b, dr_a and A r of the vertex below the element
    drb_prev = 0.0
    dra_prev = 0.0
    a_prev = 0.0
    for v in range(nv):
        F = 0.5 * (V[v] - W[v])
        if upwind:
            nb = 1.0 if v == 0 else n[v - 1]
            na = 1.0 if v == ne else n[v]
            wbv, wav = vc[1, v], vc[2, v]
            nf = (wbv * nb + wav * na) / (wbv + wav)
            tb = wbv / (wbv + wav)
            bel = (below[v] != 0.0) if have_below else (F >= 0.0)
            one_f = 1.0 - nf
            inv = 1.0 / one_f if one_f > _CLEAR else 0.0
            r = (1.0 - (nb if bel else na)) * inv
            drb = (-inv if bel else 0.0) + r * inv * tb
            dra = (0.0 if bel else -inv) + r * inv * (1.0 - tb)
            if v == 0:
                drb = 0.0
            if v == ne:
                dra = 0.0
        else:
            r, drb, dra = 1.0, 0.0, 0.0
        av = area[v] * r
        g = 2.0 * area[v] * F
        if v > 0:  # element e = v − 1 through its top vertex v
            e = v - 1
            pN = 4 * e + 3
            # in the order of the sparse scatter's sums: V, W entries, then n (below, diag, above)
            _put(ab, Aa, ak, pN, 4 * v, -av)  # V_{e+1}
            _put(ab, Aa, ak, pN, 4 * e, a_prev)  # V_e
            _put(ab, Aa, ak, pN, 4 * v + 1, av)  # W_{e+1}
            _put(ab, Aa, ak, pN, 4 * e + 1, -a_prev)  # W_e
            diag = g_prev * dra_prev - g * drb
            rhs = diag * n[e]
            if e > 0:
                bl = g_prev * drb_prev
                _put(ab, Aa, ak, pN, pN - 4, bl)
                rhs += bl * n[e - 1]
            _put(ab, Aa, ak, pN, pN, diag)
            if e < ne - 1:
                abv = -g * dra
                _put(ab, Aa, ak, pN, pN + 4, abv)
                rhs += abv * n[e + 1]
            f[pN] += rhs
        g_prev, drb_prev, dra_prev, a_prev = g, drb, dra, av
    for e in range(ne):  # the porosity rows' 2 Vol/Δt, the step's block: summed after the fluxes' entries
        _put(ab, Aa, ak, 4 * e + 3, 4 * e + 3, 2.0 * mc[16, e] / dt)


def _residual(ab, f, Aa, V, W, n, fixed, vals, abo, b):
    """Minus the residual at the iterate, ``b`` = f − A aᵏ, and ``abo`` = ``ab`` with the prescribed
    rows ``fixed`` (band rows) made identity rows scaled to the diagonal (b = scale (val − aᵏ)):
    :meth:`BandSolver.solve <twofluid.fem.banded.BandSolver.solve>`. Returns 1 if an entry is not
    finite, else 0. ``ab`` and ``abo`` in Fortran order (read and written as flat arrays)."""
    N = f.size
    src = ab.T.reshape(ab.size)  # (views: the columns one after another)
    dst = abo.T.reshape(abo.size)
    for i in range(dst.size):
        dst[i] = src[i]
    for c in range(N):
        b[c] = f[c] - Aa[c]
    for j in range(fixed.size):
        p = fixed[j]
        scale = abs(abo[_KV, p]) + 1.0
        for c in range(max(0, p - KL), min(N, p + KU + 1)):
            abo[_KV + p - c, c] = 0.0
        abo[_KV, p] = scale
        ak = V[p // 4] if p % 4 == 0 else W[p // 4]  # prescribed values are V or W
        b[p] = scale * (vals[j] - ak)
    bad = False  # (no early exit: one pass the compiler can vectorise)
    for i in range(dst.size):
        x = dst[i]
        bad |= x - x != 0.0  # NaN or ±inf
    for c in range(N):
        x = b[c]
        bad |= x - x != 0.0
    return 1 if bad else 0


def _unpack(V, W, P, n, x, fixed, vals, out):
    """``out`` (global order V, W, P, n) = the iterate + the band solution ``x``; prescribed values exact."""
    ne = n.size
    nv = ne + 1
    for i in range(nv):
        out[i] = V[i] + x[4 * i]
        out[nv + i] = W[i] + x[4 * i + 1]
    for e in range(ne):
        out[2 * nv + e] = P[e] + x[4 * e + 2]
        out[2 * nv + ne + e] = n[e] + x[4 * e + 3]
    for j in range(fixed.size):
        p = fixed[j]
        out[p // 4 if p % 4 == 0 else nv + p // 4] = vals[j]


def _closure_points_entry(n, V, W, w0, w1, x3, s3):
    """:func:`_closure_points` as exported (the stepper's iterate, :mod:`~twofluid.models.full_iterate`):
    a call of the helper, compiled once per build for the argument types of the one-call step too
    (:mod:`~twofluid.models.full_step_kernel`, whose group these exports are part of)."""
    _closure_points(n, V, W, w0, w1, x3, s3)


def _band_system_entry(n, V, W, P, oldV, oldW, oldn, alpha, K3, mu2, ps, dps, mc, vc, below, have_below,
                       viscous, upwind, rho_f, rho_s, mu_f, g_y, dt, bot_out, p_bot, top_out, p_top, ab, f, Aa):
    """:func:`_band_system` as exported (as :func:`_closure_points_entry`)."""
    _band_system(n, V, W, P, oldV, oldW, oldn, alpha, K3, mu2, ps, dps, mc, vc, below, have_below,
                 viscous, upwind, rho_f, rho_s, mu_f, g_y, dt, bot_out, p_bot, top_out, p_top, ab, f, Aa)


def _residual_entry(ab, f, Aa, V, W, n, fixed, vals, abo, b):
    """:func:`_residual` as exported (as :func:`_closure_points_entry`)."""
    return _residual(ab, f, Aa, V, W, n, fixed, vals, abo, b)


def _unpack_entry(V, W, P, n, x, fixed, vals, out):
    """:func:`_unpack` as exported (as :func:`_closure_points_entry`)."""
    _unpack(V, W, P, n, x, fixed, vals, out)


def _band_lu_entry(ab, b):
    """:func:`twofluid.fem.banded._gbsv55` (the band LU for half-widths :data:`KL`, :data:`KU`) as exported
    (as :func:`_closure_points_entry`)."""
    return _bd._gbsv55(ab, b)


C1, C2, F2, I1 = "f8[::1]", "f8[:,::1]", "f8[::1,:]", "i8[::1]"
#: the stepper's kernels, exported from the group ``full_1d`` beside the one-call step (:func:`kernels`),
#: for the argument types the step calls them with (C-contiguous vectors, the band storage in Fortran order)
ENTRIES = {
    "closure_points": (_closure_points_entry, "void(" + ",".join([C1] * 7) + ")"),
    "band_system": (_band_system_entry, "void(" + ",".join([C1] * 12 + [C2, C2, C1] + ["b1"] * 3 + ["f8"] * 5
                                                           + ["b1", "f8", "b1", "f8", F2, C1, C1]) + ")"),
    "residual": (_residual_entry, "i8(" + ",".join([F2] + [C1] * 5 + [I1, C1, F2, C1]) + ")"),
    "unpack": (_unpack_entry, "void(" + ",".join([C1] * 5 + [I1, C1, C1]) + ")"),
    "band_lu": (_band_lu_entry, "i8(" + F2 + "," + C1 + ")"),
}
_COMPILED = None
_TRIED = False


def _compile():
    global _COMPILED, _TRIED
    if not _TRIED:
        _TRIED = True
        from . import full_step_kernel  # (the group: the one-call step and these)

        ker = full_step_kernel.group_kernels()
        if ker is not None:
            _COMPILED = {name: ker[name] for name in ENTRIES}
    return _COMPILED


def available() -> bool:
    """Whether the compiled kernels can be used (numba installed, or the module built)."""
    return _compile() is not None


def kernels() -> dict | None:
    """{closure_points, band_system, residual, unpack, band_lu} compiled (:mod:`twofluid.compiled`, group
    ``full_1d``; ``band_lu(ab, b)``: :func:`twofluid.fem.banded._gbsv55`)."""
    return _compile()


# ----------------------------------------------------------------- the model's side
class BandIterate:
    """One iterate assembled by the kernels: the matrix in band storage and the right-hand side in
    band order, about ``iterate`` (the model's packed unknowns); ``matrix()`` and ``rhs`` give them
    in the global order of :class:`~twofluid.fem.assembly.BlockSystem` (for checks and tests)."""

    def __init__(self, model, k, old, ab, f, Aa):
        self.model, self.k, self.old, self.ab, self.f, self.Aa = model, k, old, ab, f, Aa
        self.size = f.size

    @property
    def iterate(self) -> np.ndarray:
        return self.model.pack(self.k)

    @property
    def rhs(self) -> np.ndarray:
        return self.f[self.model._band.pos]

    def matrix(self):
        """The assembled matrix as ``scipy.sparse.csr_matrix`` (global order; SciPy imported on use)."""
        import scipy.sparse as sp

        N, perm = self.size, self.model._band.perm
        rows, cols, vals = [], [], []
        for d in range(-KU, KL + 1):  # A[i, i − d] at ab[KV + d, i − d]
            i = np.arange(max(0, d), min(N, N + d))
            rows.append(perm[i])
            cols.append(perm[i - d])
            vals.append(self.ab[_KV + d, i - d])
        return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(N, N))


def _below_mask(model, unread):
    """The model's ``_below`` mask (None or a bool array) and the float copy the band system reads,
    kept on the model while the mask is the same object; ``unread`` stands in without a mask."""
    below = getattr(model, "_below", None)
    if below is None:
        return None, unread
    cached = model._fk_below
    if cached is None or cached[0] is not below:
        cached = model._fk_below = (below, below.astype(float))
    return below, cached[1]


def _vector(x, size: int) -> np.ndarray:
    """``x`` as a C-contiguous float array of ``size`` entries (a scalar broadcast)."""
    x = np.asarray(x, dtype=float)
    if x.shape != (size,) or not x.flags.c_contiguous:
        x = np.ascontiguousarray(np.broadcast_to(x, (size,)))
    return x


def constants(model) -> tuple[np.ndarray, np.ndarray]:
    """The element constants ``mc`` (MC_ROWS, ne) and vertex constants ``vc`` (3, nv) of
    :func:`_band_system` from the model's element arrays."""
    ne = model.mesh.n_elements
    mc = np.vstack([model.M.reshape(ne, 4).T, model.Kvis.reshape(ne, 4).T, model.src.T, model.B0[:, 0, :].T,
                    model.BN.T, model.avg_weights, model.volumes[None, :]])
    vc = np.vstack([model.vert_area, model.w_below, model.w_above])
    return np.ascontiguousarray(mc, dtype=float), np.ascontiguousarray(vc, dtype=float)


def assemble(model, ker: dict, k, old, dt: float, t_new: float) -> BandIterate:
    """:meth:`TwoFluid1D.assemble` by the kernels (the closures called as there)."""

    mat, clo = model.mat, model.clo
    mc, vc = model._fk_constants
    st = model._fk_step
    if st is None or st[0] is not old or st[1] != dt or st[2] != t_new:
        st = model._fk_step = (old, dt, t_new, _vector(model.bed_force_shift(old), old.n.size))
    alpha = st[3]
    n, V, W = k.n, k.V, k.W
    ne = n.size
    x3, s3 = np.empty(3 * ne), np.empty(3 * ne)
    ker["closure_points"](n, V, W, mc[14], mc[15], x3, s3)
    laws = model.compiled_laws()
    ps, dps = model.solids_pressure(n, k.n_bar, derivative=True)
    if laws is not None:  # the same laws compiled (closures.kernels)
        K3 = laws.beta_per_solids(x3, s3)
        mu2 = laws.solid_viscosity(x3[ne:]) if clo.viscous else K3
    else:
        K3 = _vector(clo.beta_per_solids(x3, s3, model._materials_times(3)), 3 * ne)
        if clo.viscous:  # μ_s at n and n + δn: the last two thirds of the drag's porosities
            mu2 = _vector(solid_viscosity(x3[ne:], model._materials_times(2).mu_f,
                                          **_times(clo.viscosity_params, ne, 2)), 2 * ne)
        else:
            mu2 = K3  # not read
    below, belf = _below_mask(model, vc[0])
    upwind = model.solids_flux == "upwind"
    N = 2 * model.nv + 2 * ne
    ab = np.empty((N, LDAB)).T  # LAPACK band storage, Fortran order
    f, Aa = np.empty(N), np.empty(N)
    bot, top = model.bottom, model.top
    ker["band_system"](n, V, W, k.P, old.V, old.W, old.n, alpha, K3, mu2, _vector(ps, ne), _vector(dps, ne), mc, vc,
                       belf, below is not None, clo.viscous, upwind, float(mat.rho_f), float(mat.rho_s),
                       float(mat.mu_f), float(model.g_y), float(dt), bot.kind == "outlet", float(bot.pressure),
                       top.kind == "outlet", float(top.pressure), ab, f, Aa)
    return BandIterate(model, k, old, ab, f, Aa)


def solve(model, ker: dict, S: BandIterate, t: float) -> np.ndarray:
    """:meth:`TwoFluid1D.solve` of an iterate assembled by :func:`assemble`: minus the residual, the
    prescribed rows, the band LU, the increment added to the iterate (NaN if it cannot be solved)."""
    idx, val = model.dirichlet(t)
    cached = model._fk_fixed  # (the band rows, kept while the indices are the same array)
    if cached is None or cached[0] is not idx:
        cached = model._fk_fixed = (idx, np.ascontiguousarray(model._band.pos[idx], dtype=np.int64))
    fixed, vals = cached[1], np.ascontiguousarray(val, dtype=float)
    k, N = S.k, S.size
    abo = np.empty((N, LDAB)).T
    b = np.empty(N)
    out = np.empty(N)
    if ker["residual"](S.ab, S.f, S.Aa, k.V, k.W, k.n, fixed, vals, abo, b) != 0 \
            or ker["band_lu"](abo, b) != 0:
        out.fill(np.nan)
        return out
    ker["unpack"](k.V, k.W, k.P, k.n, b, fixed, vals, out)
    return out


def force_shift(model, s, laws=None, xs=None) -> np.ndarray | None:
    """:meth:`TwoFluid1D._force_shift_at` by the reduced model's compiled shift kernels (the same
    arithmetic, :mod:`~twofluid.models.reduced_kernel`; they read the mass matrix from rows 10–13
    of their element constants), or None where they are not available. ``laws``: the model's
    compiled laws, called directly (the one-call iterate, :mod:`~twofluid.models.full_iterate`: the
    same numbers as through the model's methods); ``xs``: two work arrays of 2 ne for the points."""
    rk = reduced_kernel.common_kernels()
    if rk is None:
        return None
    mc = model._fk_constants[0]
    shift_mc = model.__dict__.get("_fk_shift_mc")
    if shift_mc is None:
        shift_mc = model._fk_shift_mc = np.zeros((19, mc.shape[1]))
        shift_mc[10:14] = mc[0:4]
    n = s.n
    ne = n.size
    x, s_abs = (np.empty(2 * ne), np.empty(2 * ne)) if xs is None else xs
    rk["shift_points"](n, s.V, s.W, mc[14], mc[15], x, s_abs)
    if laws is not None:
        K = laws.beta_per_solids(x, s_abs)
        dps = laws.solids_pressure(n, s.n_bar)[1]
    else:
        laws = model.compiled_laws()
        K = laws.beta_per_solids(x, s_abs) if laws is not None else \
            _vector(model.clo.beta_per_solids(x, s_abs, model._materials_times(2)), 2 * ne)
        dps = _vector(model.solids_pressure(n, s.n_bar, derivative=True)[1], ne)
    alpha = np.empty(ne)
    mat = model.mat
    rk["shift"](n, s.V, s.W, x, K, dps, shift_mc, mc[16], model.mesh.lengths,
          float(mat.rho_s - mat.rho_f), float(model.g_y), float(mat.g), alpha)
    return alpha
