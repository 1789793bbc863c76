"""The reduced 1D model's Newton iterate and per-step work: its one source, loops around the closure calls.

:class:`~twofluid.models.reduced_1d.Reduced1D` assembles, solves and recovers its pressure only
through these kernels (compiled by :mod:`twofluid.compiled`; plain Python with
``TWOFLUID_DISABLE_JIT=1``). What checks them: the band matrix against the finite-difference
Jacobian of the residual and the steps against the full model's (``tests/unit/test_reduced_model.py``),
the exact solutions (Kynch, Terzaghi), the golden outputs of the bundled cases
(``tests/cases/test_golden_1d.py``):

- :func:`_closure_points` — from the iterate (n, W) the porosities and slips at which the
  drag law is called (n, |s|), (n + δn, |s(n + δn)|), (n, |s| + δs);
- the closures themselves stay pure vectorised functions from the registry, called once
  per iterate by the model (drag at the three points, μ_s at n and n + δn, P_s);
- :func:`_band_system` — from the closure values, the element integrals of the mixture −
  liquid rows (drag Newton-linearised, P_s Taylor-expanded, μ_s and 1/n Newton) and the
  porosity rows (upwind ratio Newton-linearised), written straight into LAPACK band storage
  (half-width 2, the interleaved (W_0, n_0, W_1, …) numbering) with minus the residual.

What would be about a hundred NumPy operations on arrays of a few hundred entries
(each ~1–3 µs of call overhead) is here a few loops over the elements; the same holds for
what is done once per step (:func:`_step_constants`, the bed-force shift :func:`_shift_points`
/ :func:`_shift`, the pressure recovery :func:`_step_pressure`), and the band is solved as the
block-tridiagonal system it is (:func:`twofluid.fem.banded._bt22`: 2 × 2 blocks of the (W_v, n_v)
pairs, checked by its backward error, LAPACK's band LU where that fails). The closures then take about half
of an iterate's time. Built once ahead of time (``twofluid build-kernels``); a run imports the
module without numba.

>>> ok = available()
>>> isinstance(ok, bool)
True
"""
from __future__ import annotations

import numpy as np

from ..closures import kernels as laws
from ..fem import banded
from . import extrapolation

__all__ = ["available", "kernels", "common_kernels", "whole_iterate", "LAST_ROWS"]

_CLEAR = 1e-6  # as two_fluid_1d._CLEAR: floor of 1 − n in the slip and the upwind ratio
# rows of the per-element pieces of the last iterate kept for the pressure of the step (end_step)
LAST_ROWS = ("Wbar", "h", "m_l", "Mq0", "Mq1", "k0", "kom", "gain", "Jdn0", "Jdn1")


def _fmax(x, c):
    """np.maximum(x, c) for a scalar: NaN propagates."""
    return x if not x < c else c


def _sign(x):
    """np.sign for a scalar (0 at 0, NaN at NaN)."""
    if x > 0.0:
        return 1.0
    if x < 0.0:
        return -1.0
    return x  # 0.0 (or −0.0) or NaN


def _closure_points(n, W, w0, w1, Vbar, dn, dq1, n3, s3, aux):
    """The drag law's porosities ``n3`` and slips ``s3`` (3, ne) at iterate (n, W); ``aux`` keeps
    (q̄, 1/(2n(1 − n)), δs) for :func:`_band_system`."""
    ne = n.size
    for e in range(ne):
        ni = n[e]
        Wbar = w0[e] * W[e] + w1[e] * W[e + 1]
        omn = 1.0 - (ni + ni)
        qb = omn * Vbar[e] + Wbar
        n1 = ni + dn[e]
        i0 = 0.5 / (ni * _fmax(1.0 - ni, _CLEAR))
        i1 = 0.5 / (n1 * _fmax(1.0 - n1, _CLEAR))
        s0 = abs(qb) * i0
        ds = 1e-6 * _fmax(s0, 1e-6)
        n3[0, e] = ni
        n3[1, e] = n1
        n3[2, e] = ni
        s3[0, e] = s0
        s3[1, e] = abs(qb - dq1[e]) * i1
        s3[2, e] = s0 + ds
        aux[0, e] = qb
        aux[1, e] = i0
        aux[2, e] = ds


def _band_system(n, W, kraw, n3, aux, ps, dps, mu2, viscous, mu_f, hc, cw0, upwind, below, have_below,
                 mc, sc, vc, ab, rhs, last):
    """Band storage ``ab`` (7, 2 nv − 1) and minus the residual ``rhs`` of the iterate; ``last``
    (LAST_ROWS, ne) the pieces of the pressure recovery.

    ``mc`` (19, ne) the model's element constants: M0 (2), M1 (2), w0, w1, BN (2), the P_s jump
    areas psA (2), Mt (2×2), Kt (2×2), κ; ``sc`` (16, ne) the step's: V̄, MVe (2), U (2), saV
    (2), sa (2), gs (2), kv, δn, nᵗ, δq, cdt; ``vc`` (4, nv) per vertex: A V, A, t_b, mR.
    """
    ne = n.size
    nv = ne + 1
    # upwind ratio at the vertices and its Newton derivatives (Reduced1D._upwind)
    r = np.empty(nv)
    Pb = np.empty(nv)
    Qa = np.empty(nv)
    G = np.empty(nv)
    for v in range(nv):
        phi = vc[0, v] - vc[1, v] * W[v]
        if upwind:
            nb = 1.0 if v == 0 else n[v - 1]
            na = 1.0 if v == ne else n[v]
            tb = vc[2, v]
            bel = below[v] if have_below else (1.0 if phi >= 0.0 else 0.0)
            diff = nb - na
            oma = 1.0 - na
            one_f = oma - tb * diff
            if one_f > _CLEAR:
                inv = 1.0 / one_f
            elif one_f != one_f:
                inv = one_f
            else:
                inv = 0.0
            rv = (oma - bel * diff) * inv
            pinv = phi * inv
            pb = pinv * (rv * tb - bel)
            qa = pinv * (rv - 1.0) - pb
            r[v] = rv
            Pb[v] = 0.0 if v == 0 else pb
            Qa[v] = 0.0 if v == ne else qa
        else:
            rv = 1.0
            r[v] = 1.0
            Pb[v] = 0.0
            Qa[v] = 0.0
        G[v] = rv * phi
    for i in range(ab.shape[0]):
        for j in range(ab.shape[1]):
            ab[i, j] = 0.0
    X1p = 0.0
    for e in range(ne):
        ni = n[e]
        Wb = W[e]
        Wt = W[e + 1]
        M00, M01, M10, M11 = mc[0, e], mc[1, e], mc[2, e], mc[3, e]  # M0[i], M1[i]
        w0, w1, B0, B1 = mc[4, e], mc[5, e], mc[6, e], mc[7, e]
        MWe0 = M00 * Wb + M10 * Wt
        MWe1 = M01 * Wb + M11 * Wt
        Wbar = w0 * Wb + w1 * Wt
        MVe0, MVe1, U0, U1 = sc[1, e], sc[2, e], sc[3, e], sc[4, e]
        saV0, saV1, sa0, sa1 = sc[5, e], sc[6, e], sc[7, e], sc[8, e]
        gs0, gs1, kv, dn = sc[9, e], sc[10, e], sc[11, e], sc[12, e]
        omn = 1.0 - (ni + ni)
        qb, i0, ds = aux[0, e], aux[1, e], aux[2, e]
        k0 = kraw[e] * (0.5 / (n3[0, e] * n3[0, e]))
        kn = kraw[ne + e] * (0.5 / (n3[1, e] * n3[1, e]))
        k2 = kraw[2 * ne + e] * (0.5 / (n3[2, e] * n3[2, e]))
        gain = (k2 - k0) * (_sign(qb) * i0 / ds)
        kd = (kn - k0) / dn
        BW = B0 * Wb + B1 * Wt
        cor0 = omn * saV0 + sa0 * BW
        cor1 = omn * saV1 + sa1 * BW
        Mq0 = omn * MVe0 + MWe0 + cor0
        Mq1 = omn * MVe1 + MWe1 + cor1
        Jdn0 = kd * Mq0 - (kn + kn) * (MVe0 + saV0)
        Jdn1 = kd * Mq1 - (kn + kn) * (MVe1 + saV1)
        h = hc / ni
        al = (cw0 - h) - k0
        kom = k0 * omn
        psA0, psA1 = mc[8, e], mc[9, e]
        X0 = al * MWe0 - (h * U0 + kom * MVe0) - k0 * cor0 + (psA0 * ps[e] + gs0 * ni)
        X1 = al * MWe1 - (h * U1 + kom * MVe1) - k0 * cor1 + (psA1 * ps[e] + gs1 * ni)
        # JW[i, j] = al Mt[i, j] − gain Mq_i w_j − k0 sa_i BN_j
        J00 = al * mc[10, e] - (gain * Mq0) * w0 - (k0 * sa0) * B0
        J01 = al * mc[11, e] - (gain * Mq0) * w1 - (k0 * sa0) * B1
        J10 = al * mc[12, e] - (gain * Mq1) * w0 - (k0 * sa1) * B0
        J11 = al * mc[13, e] - (gain * Mq1) * w1 - (k0 * sa1) * B1
        hn = h / ni
        Jn0 = (gs0 + psA0 * dps[e]) - Jdn0 + hn * (U0 + MWe0)
        Jn1 = (gs1 + psA1 * dps[e]) - Jdn1 + hn * (U1 + MWe1)
        m_l = 0.0
        if viscous:
            mu_s = mu2[e]
            m_l = (0.5 * mu_f) / ni
            base = 0.5 * mu_f - m_l
            hs = 0.5 * mu_s
            c_w = base - hs
            kw = mc[18, e] * (Wb - Wt)
            vx = (base + hs) * kv + c_w * kw
            X0 += vx
            X1 -= vx
            J00 += c_w * mc[14, e]
            J01 += c_w * mc[15, e]
            J10 += c_w * mc[16, e]
            J11 += c_w * mc[17, e]
            hds = 0.5 * (mu2[ne + e] - mu_s) / dn
            ml_n = m_l / ni
            dvx = (ml_n + hds) * kv + (ml_n - hds) * kw
            Jn0 += dvx
            Jn1 -= dvx
        last[0, e] = Wbar
        last[1, e] = h
        last[2, e] = m_l
        last[3, e] = Mq0
        last[4, e] = Mq1
        last[5, e] = k0
        last[6, e] = kom
        last[7, e] = gain
        last[8, e] = Jdn0
        last[9, e] = Jdn1
        # band storage: entry (i, i + d) at ab[4 − d, i + d]; W_i at 2i, n_e at 2e + 1
        cw = 2 * e  # column of W_e
        ab[6, cw] = J10  # row W_{e+1}, column W_e
        ab[5, cw + 1] = Jn1  # row W_{e+1}, column n_e
        ab[4, cw] += J00  # W_e's diagonal: element e's local row 0 ...
        ab[4, cw + 2] += J11  # ... and element e's local row 1 on W_{e+1}'s
        ab[3, cw + 1] = Jn0  # row W_e, column n_e
        ab[2, cw + 2] = J01  # row W_e, column W_{e+1}
        # n row of element e: n_e − Δt [A r (V − W)]_e^{e+1}/(2 Vol_e) = n_eᵗ
        cdt = sc[15, e]
        if e > 0:
            ab[6, cw - 1] = sc[15, e] * Pb[e]  # row n_e, column n_{e−1}
        ab[5, cw] = (-cdt) * vc[1, e] * r[e]  # row n_e, column W_e
        ab[4, cw + 1] = (Qa[e] - Pb[e + 1]) * cdt + 1.0
        ab[3, cw + 2] = cdt * vc[1, e + 1] * r[e + 1]  # row n_e, column W_{e+1}
        if e < ne - 1:
            ab[2, cw + 3] = (-cdt) * Qa[e + 1]  # row n_e, column n_{e+1}
        rhs[cw + 1] = (sc[13, e] - ni) + cdt * (G[e + 1] - G[e])
        # W row of vertex e: mR − X0 of the element above, then − X1 of the element below
        rhs[cw] = vc[3, e] - X0 if e == 0 else (vc[3, e] - X0) - X1p
        X1p = X1
    rhs[2 * ne] = vc[3, ne] - X1p


def _step_constants(V, oldV, oldW, oldn, alpha, dt, inv2vol, cv0, cw0, cgs, mc, srcT, mR0, area, tb, sc, vc):
    """The step's constants ``sc`` (16, ne) and ``vc`` (4, nv) of :func:`_band_system` (what
    :meth:`Reduced1D._prepare_step` computes once per step) from the old state, the mixture
    velocity V and the bed-force shift α; ``cgs`` = (ρ_s − ρ_f) g_y."""
    ne = oldn.size
    G1p = 0.0
    I1p = 0.0
    for e in range(ne):
        Vb = V[e]
        Vt = V[e + 1]
        M00, M01, M10, M11 = mc[0, e], mc[1, e], mc[2, e], mc[3, e]
        B0, B1 = mc[6, e], mc[7, e]
        Vbar = mc[4, e] * Vb + mc[5, e] * Vt
        MVe0 = M00 * Vb + M10 * Vt
        MVe1 = M01 * Vb + M11 * Vt
        MdV0 = MVe0 - (M00 * oldV[e] + M10 * oldV[e + 1])
        MdV1 = MVe1 - (M01 * oldV[e] + M11 * oldV[e + 1])
        MWo0 = M00 * oldW[e] + M10 * oldW[e + 1]
        MWo1 = M01 * oldW[e] + M11 * oldW[e + 1]
        dn = 1e-8 if oldn[e] < 0.5 else -1e-8
        sa0 = -1.0 * alpha[e]
        sa1 = 1.0 * alpha[e]
        BNs = B0 + B1
        gs0 = cgs * (srcT[0, e] + sa0 * BNs)
        gs1 = cgs * (srcT[1, e] + sa1 * BNs)
        BV = B0 * Vb + B1 * Vt
        sc[0, e] = Vbar
        sc[1, e] = MVe0
        sc[2, e] = MVe1
        sc[3, e] = MdV0 - MWo0
        sc[4, e] = MdV1 - MWo1
        sc[5, e] = sa0 * BV
        sc[6, e] = sa1 * BV
        sc[7, e] = sa0
        sc[8, e] = sa1
        sc[9, e] = gs0
        sc[10, e] = gs1
        sc[11, e] = mc[18, e] * (Vb - Vt)
        sc[12, e] = dn
        sc[13, e] = oldn[e]
        sc[14, e] = dn * (2.0 * Vbar)
        sc[15, e] = dt * inv2vol[e]
        I0 = cv0 * MdV0 - cw0 * MWo0
        I1 = cv0 * MdV1 - cw0 * MWo1
        # mR = mR0 + nodal(gs) − nodal(inertia), nodal(E)_v = E0[v] + E1[v − 1]
        if e == 0:
            vc[3, 0] = (mR0[0] + gs0) - I0
        else:
            vc[3, e] = (mR0[e] + (gs0 + G1p)) - (I0 + I1p)
        G1p = gs1
        I1p = I1
    vc[3, ne] = (mR0[ne] + (0.0 + G1p)) - (0.0 + I1p)
    for v in range(ne + 1):
        vc[0, v] = area[v] * V[v]
        vc[1, v] = area[v]
        vc[2, v] = tb[v]


def _shift_points(n, V, W, w0, w1, x, s_abs):
    """The drag law's porosities ``x`` and slips ``s_abs`` (2 ne) of the bed-force shift at state
    (n, V, W): n and n + δn (:meth:`TwoFluid1D.bed_force_shift` with the linear element)."""
    ne = n.size
    for e in range(ne):
        ni = n[e]
        v = V[e] * w0[e] + V[e + 1] * w1[e]
        w = W[e] * w0[e] + W[e + 1] * w1[e]
        dn = 1e-8 * (1.0 if ni < 0.5 else -1.0)
        for r in range(2):
            xr = ni if r == 0 else ni + dn
            c = 1.0 - 2.0 * xr
            x[r * ne + e] = xr
            s_abs[r * ne + e] = abs((c * v + w) / (2.0 * xr * _fmax(1.0 - xr, _CLEAR)))


def _shift(n, V, W, x, K, dps, mc, vol, h, drho, g_y, g, alpha):
    """Shift α of the bed forces (:meth:`TwoFluid1D.force_shift`) from the drag ``K`` at ``x``."""
    ne = n.size
    adrho = abs(drho)
    for e in range(ne):
        tot0 = 0.0
        tot1 = 0.0
        for r in range(2):
            xr = x[r * ne + e]
            c = 1.0 - 2.0 * xr
            q0 = c * V[e] + W[e]
            q1 = c * V[e + 1] + W[e + 1]
            c0 = K[r * ne + e] / (2.0 * xr * xr)
            t = c0 * (mc[10, e] * q0 + mc[11, e] * q1) + c0 * (mc[12, e] * q0 + mc[13, e] * q1)
            if r == 0:
                tot0 = t
            else:
                tot1 = t
        dn = 1e-8 * (1.0 if n[e] < 0.5 else -1.0)
        phi_n = (tot1 - tot0) / dn / vol[e] - drho * g_y
        stiff = abs(dps[e]) + 1e-3 * h[e] * adrho * g
        den = _fmax(2.0 * h[e] * abs(phi_n), 1e-300)
        q = stiff / den
        against = q if (q < 0.5 or q != q) else 0.5  # np.minimum(0.5, q)
        a = 0.5 - against if phi_n < 0.0 else against - 0.5
        alpha[e] = a if 1.0 - n[e] > _CLEAR else 0.0


def _step_pressure(W, n, nk, last, mc, sc, liq, viscous, area, top_outlet, p_end, P):
    """Element pressures ``P`` of the step from the liquid rows linearised about the last iterate
    (:meth:`Reduced1D.end_step`): [[P]]_i = −L_i/A_i marched from the outlet."""
    ne = n.size
    L = np.empty(ne + 1)
    L1p = 0.0
    for e in range(ne):
        Wb = W[e]
        Wt = W[e + 1]
        MW0 = mc[0, e] * Wb + mc[2, e] * Wt
        MW1 = mc[1, e] * Wb + mc[3, e] * Wt
        dWbar = (mc[4, e] * Wb + mc[5, e] * Wt) - last[0, e]
        BW = mc[6, e] * Wb + mc[7, e] * Wt
        omn = 1.0 - 2.0 * nk[e]
        cor0 = omn * sc[5, e] + sc[7, e] * BW
        cor1 = omn * sc[6, e] + sc[8, e] * BW
        h, k0, kom, gain = last[1, e], last[5, e], last[6, e], last[7, e]
        dn = n[e] - nk[e]
        L0 = (h + k0) * MW0 + (h * sc[3, e] + kom * sc[1, e]) + k0 * cor0 + liq[0, e] + (gain * dWbar) * last[3, e] \
            + last[8, e] * dn
        L1 = (h + k0) * MW1 + (h * sc[4, e] + kom * sc[2, e]) + k0 * cor1 + liq[1, e] + (gain * dWbar) * last[4, e] \
            + last[9, e] * dn
        if viscous:
            vl = last[2, e] * (sc[11, e] + mc[18, e] * (Wb - Wt))
            L0 += vl
            L1 -= vl
        L[e] = L0 if e == 0 else L0 + L1p
        L1p = L1
    L[ne] = 0.0 + L1p
    if top_outlet:  # P_e = P_top − Σ_{v > e} jump_v, summed from the top
        c = 0.0
        for e in range(ne - 1, -1, -1):
            c = (-L[e + 1] / area[e + 1]) if e == ne - 1 else c + (-L[e + 1] / area[e + 1])
            P[e] = p_end - c
    else:
        c = 0.0
        for e in range(ne):
            c = (-L[e] / area[e]) if e == 0 else c + (-L[e] / area[e])
            P[e] = p_end + c


def _iterate_change(a, Vn, Wn, nn, Vk, Wk, nk, floor, out):
    """``out`` = (1 if every entry of ``a`` is finite else 0, max |nn − nk|,
    max(|Vn − Vk|, |Wn − Wk|)/max(|Vn|, |Wn|, floor)): the stepper's test of an iterate
    (TwoFluid1D.iterate_change), the same numbers as its NumPy form."""
    for x in a:
        if not x - x == 0.0:  # inf or NaN
            out[0] = 0.0
            out[1] = out[2] = np.nan
            return
    dn = 0.0
    for i in range(nn.size):
        d = abs(nn[i] - nk[i])
        if d > dn:
            dn = d
    dv = 0.0
    scale = floor
    for i in range(Vn.size):
        d = abs(Vn[i] - Vk[i])
        if d > dv:
            dv = d
        d = abs(Wn[i] - Wk[i])
        if d > dv:
            dv = d
        v = abs(Vn[i])
        if v > scale:
            scale = v
        v = abs(Wn[i])
        if v > scale:
            scale = v
    out[0] = 1.0
    out[1] = dn
    out[2] = dv / scale


def _state_check(n, V):
    """0 if n and V are finite and 0 < n ≤ 1 + 1e-9; else 1 (not finite), 2 (n ≤ 0) or 3 (n > 1 + 1e-9),
    in the order TwoFluid1D.check tests them."""
    for x in n:
        if not x - x == 0.0:
            return 1
    for x in V:
        if not x - x == 0.0:
            return 1
    for x in n:
        if x <= 0.0:
            return 2
    for x in n:
        if x > 1.0 + 1e-9:
            return 3
    return 0


def _iterate_points(n, W, mc, sc, slip_max, d, rho_f, mu_f, wen_yu, n3, s3, aux, re):
    """The closure points of iterate (n, W) (:func:`_closure_points`) and, for Wen–Yu (``wen_yu``), the
    Reynolds numbers ``re`` at them (:func:`twofluid.closures.kernels._wen_yu_reynolds`): the first half
    of a whole iterate, before the two powers of Wen–Yu, which NumPy's SIMD routines compute."""
    _closure_points(n, W, mc[4], mc[5], sc[0], sc[12], sc[14], n3, s3, aux)
    if wen_yu:
        ne = n.size
        laws._wen_yu_reynolds(slip_max, n3.reshape(3 * ne), s3.reshape(3 * ne), d, rho_f, mu_f, re)


def _whole_iterate(n, W, n_bar, kV, V, sc, vc, mc, n3, s3, aux, re, re_pow, n_pow, law, dpar, d, A, p_ref,
                   modulus, fluidized, vpar, viscous, mu_f, hc, cw0, upwind, below, have_below, dir_row, dir_col,
                   dir_val, fixed, floor, last, out, change):
    """The rest of a whole Newton iterate from (n, W) after :func:`_iterate_points` (``V`` the step's
    nodal V, ``sc`` and ``vc`` its constants): the compiled laws at the points
    (:mod:`twofluid.closures.kernels`: drag law ``law`` with ``dpar`` = (stokes, n_switch, blend_width,
    slip_max, ρ_f), Wen–Yu from its powers ``re_pow`` = Re^0.687 and ``n_pow`` = n^−2.65; P_s; μ_s with
    ``vpar``), the band system, its prescribed rows (``dir_*``: band entries; ``fixed``: the vertices
    where W = V), the band solve (:func:`twofluid.fem.banded._bt22`: block tridiagonal, LAPACK's band LU
    where that is not accurate),
    the new iterate ``out`` = [V, W, n] and ``change`` as :func:`_iterate_change` (against the
    iterate's own V ``kV``). The same calls in the same order as :meth:`Reduced1D.assemble
    <twofluid.models.reduced_1d.Reduced1D.assemble>` with the compiled laws, ``solve`` and
    ``iterate_change``; returns LAPACK's ``info``."""
    ne = n.size
    nv = ne + 1
    N = 2 * nv - 1
    n3f = n3.reshape(3 * ne)
    kraw = np.empty(3 * ne)
    if law == laws.WEN_YU:
        laws._wen_yu_given(dpar[0] != 0.0, n3f, re, re_pow, n_pow, d, mu_f, kraw)
    else:
        laws._beta_per_solids(law, dpar[0] != 0.0, dpar[1], dpar[2], dpar[3], n3f, s3.reshape(3 * ne), d,
                              dpar[4], mu_f, kraw)
    ps = np.empty(ne)
    dps = np.empty(ne)
    laws._solids_pressure(n, n_bar, A, p_ref, modulus, fluidized, ps, dps)
    if viscous:
        mu2 = np.empty(2 * ne)
        laws._viscosity(n3f[:2 * ne], mu_f, vpar[0], vpar[1], vpar[2], vpar[3], vpar[4], vpar[5], True, mu2)
    else:
        mu2 = kraw
    ab = np.empty((N, 7)).T  # LAPACK band storage, Fortran order
    rhs = np.empty(N)
    _band_system(n, W, kraw, n3, aux, ps, dps, mu2, viscous, mu_f, hc, cw0, upwind, below, have_below, mc, sc,
                 vc, ab, rhs, last)
    for i in range(dir_row.size):
        ab[dir_row[i], dir_col[i]] = dir_val[i]
    for v in fixed:
        rhs[2 * v] = V[v] - W[v]
    info = banded._bt22(ab, rhs)
    if info != 0:  # singular: the stepper rejects the non-finite result and shrinks the step
        for i in range(out.size):
            out[i] = np.nan
    else:
        for v in range(nv):
            out[v] = V[v]
            out[nv + v] = W[v] + rhs[2 * v]
        for e in range(ne):
            out[2 * nv + e] = n[e] + rhs[2 * e + 1]
        for v in fixed:
            out[nv + v] = V[v]
    _iterate_change(out, out[:nv], out[nv:2 * nv], out[2 * nv:], kV, W, n, floor, change)
    return info


def _shift_law_points(n, V, W, w0, w1, slip_max, d, rho_f, mu_f, wen_yu, x, s_abs, re):
    """:func:`_shift_points` and, for Wen–Yu (``wen_yu``), the Reynolds numbers ``re`` at them: the
    first half of the compiled bed-force shift (:func:`_shift_with_laws`)."""
    _shift_points(n, V, W, w0, w1, x, s_abs)
    if wen_yu:
        laws._wen_yu_reynolds(slip_max, x, s_abs, d, rho_f, mu_f, re)


def _shift_with_laws(n, n_bar, V, W, x, s_abs, re, re_pow, n_pow, law, dpar, d, A, p_ref, modulus, fluidized,
                     mu_f, mc, vol, h, drho, g_y, g, alpha):
    """The bed-force shift ``alpha`` (:func:`_shift`) with the compiled laws at the points of
    :func:`_shift_law_points` (the drag as in :func:`_whole_iterate`, P_s' at n): the same calls as
    :meth:`Reduced1D._force_shift_at <twofluid.models.reduced_1d.Reduced1D._force_shift_at>`."""
    ne = n.size
    K = np.empty(2 * ne)
    if law == laws.WEN_YU:
        laws._wen_yu_given(dpar[0] != 0.0, x, re, re_pow, n_pow, d, mu_f, K)
    else:
        laws._beta_per_solids(law, dpar[0] != 0.0, dpar[1], dpar[2], dpar[3], x, s_abs, d, dpar[4], mu_f, K)
    ps = np.empty(ne)
    dps = np.empty(ne)
    laws._solids_pressure(n, n_bar, A, p_ref, modulus, fluidized, ps, dps)
    _shift(n, V, W, x, K, dps, mc, vol, h, drho, g_y, g, alpha)


def _first_iterate(DW, Dn, order, W, n):
    """The extrapolated first iterate of a step (:meth:`Reduced1D._first_iterate
    <twofluid.models.reduced_1d.Reduced1D._first_iterate>`) in place: if (W, n) is the last state of the
    table (backward differences ``DW``, ``Dn`` of ``order`` rows at equal steps), W and n become
    their prediction (:func:`twofluid.models.extrapolation._predict_entries`), n kept in
    [1e-6, 1] as np.minimum and np.maximum keep it (NaN stays NaN); returns 1, else 0 (nothing done)."""
    for i in range(n.size):
        if n[i] != Dn[0, i]:
            return 0
    for i in range(W.size):
        if W[i] != DW[0, i]:
            return 0
    extrapolation._predict_entries(DW, order, W)
    extrapolation._predict_entries(Dn, order, n)
    for i in range(n.size):
        x = n[i]
        x = x if not x > 1.0 else 1.0
        n[i] = x if not x < _CLEAR else _CLEAR
    return 1


_COMPILED = None
_TRIED = False


# the kernels' arrays, all C-contiguous but the band storage (Fortran order, as LAPACK takes it): constant
# strides let the compiler drop a multiply per access, and the model's parts (closure_points ...
# state_check) are then the very functions the whole iterate and the column's step call (compiled once,
# twofluid.compiled._stub). The ahead-of-time module checks each array's layout on each call (a
# ValueError otherwise: check_layouts, twofluid.compiled._unbox_checked)
C1, C2, F2 = "f8[::1]", "f8[:,::1]", "f8[::1,:]"
# the kernels' signatures for the ahead-of-time build (twofluid.compiled): the argument types the
# model passes, in order
SIGNATURES = {
    "closure_points": "void(" + ",".join([C1] * 7 + [C2] * 3) + ")",
    "band_system": "void(" + ",".join([C1] * 3 + [C2] * 2 + [C1] * 3 + ["b1", "f8", "f8", "f8", "b1", C1, "b1"]
                                      + [C2] * 3 + [F2, C1, C2]) + ")",
    "step_pressure": "void(" + ",".join([C1] * 3 + [C2] * 4 + ["b1", C1, "b1", "f8", C1]) + ")",
    "shift_points": "void(" + ",".join([C1] * 7) + ")",
    "shift": "void(" + ",".join([C1] * 6 + [C2, C1, C1, "f8", "f8", "f8", C1]) + ")",
    "step_constants": "void(" + ",".join([C1] * 5 + ["f8", C1, "f8", "f8", "f8", C2, C2, C1, C1, C1, C2, C2]) + ")",
    "iterate_change": "void(" + ",".join([C1] * 7 + ["f8", C1]) + ")",
    "state_check": f"i8({C1},{C1})",
    "shift_law_points": "void(" + ",".join([C1] * 5 + ["f8", C1, "f8", "f8", "b1"] + [C1] * 3) + ")",
    "shift_with_laws": "void(" + ",".join([C1] * 9 + ["i8"] + [C1] * 5 + ["b1", "f8", C2] + [C1] * 2
                                          + ["f8"] * 3 + [C1]) + ")",
    "first_iterate": f"i8({C2},{C2},i8,{C1},{C1})",
    "iterate_points": "void(" + ",".join([C1] * 2 + [C2] * 2 + ["f8", C1, "f8", "f8", "b1"] + [C2] * 3 + [C1]) + ")",
    "whole_iterate": "i8(" + ",".join([C1] * 5 + [C2] * 6 + [C1] * 3 + ["i8"] + [C1] * 5
                                      + ["b1", C1, "b1", "f8", "f8", "f8", "b1", C1, "b1", "i8[::1]", "i8[::1]", C1,
                                         "i8[::1]", "f8", C2, C1, C1]) + ")",
}


_WHOLE = None


def _compile():
    global _COMPILED, _TRIED, _WHOLE
    if not _TRIED:
        _TRIED = True
        from ..compiled import group
        from ..fem.banded import block_solve_22

        funcs = {"closure_points": _closure_points, "band_system": _band_system,
                 "step_pressure": _step_pressure, "step_constants": _step_constants, "iterate_points": _iterate_points, "whole_iterate": _whole_iterate,
                 "shift_law_points": _shift_law_points, "shift_with_laws": _shift_with_laws,
                 "first_iterate": _first_iterate}
        # (the exports are helpers too: compiled once for this group, the common one and the column's step,
        # which call them with the same argument types; twofluid.compiled._stub)
        helpers = (_fmax, _sign, _closure_points, _band_system, _step_pressure, _step_constants, _state_check,
                   _iterate_change, _shift_points, _shift, banded._u,
                   banded._gbsv22, banded._bt22, extrapolation._predict_entries, _iterate_points, _whole_iterate,
                   _shift_law_points, _shift_with_laws, _first_iterate,
                   laws._beta_per_solids, laws._drag, laws._ergun, laws._wen_yu, laws._saturated, laws._next,
                   laws._wen_yu_reynolds, laws._wen_yu_given,
                   laws._solids_pressure, laws._viscosity, laws._mooney)
        ker = group("reduced_1d", {k: (f, SIGNATURES[k]) for k, f in funcs.items()}, helpers=helpers,
                    check_layouts=True)
        lu = block_solve_22()
        common = common_kernels()
        if ker is None or lu is None or common is None:
            return None
        _COMPILED = (ker["closure_points"], ker["band_system"], lu, ker["step_pressure"],
                     common["shift_points"], common["shift"], ker["step_constants"], common["iterate_change"],
                     common["state_check"])
        _WHOLE = (ker["iterate_points"], ker["whole_iterate"], ker["shift_law_points"], ker["shift_with_laws"],
                  ker["first_iterate"])
    return _COMPILED


_COMMON = None
#: the kernels both 1D models call (the full model these alone of this module): a group of their own,
#: so that the full model builds neither the reduced model's iterate nor its band solver
COMMON = {"iterate_change": _iterate_change, "state_check": _state_check, "shift_points": _shift_points,
          "shift": _shift}


def common_kernels():
    """{iterate_change, state_check, shift_points, shift} (:data:`COMMON`) compiled
    (:mod:`twofluid.compiled`), or None.

    >>> k = common_kernels()
    >>> k is None or sorted(k) == sorted(COMMON)
    True
    """
    global _COMMON
    if _COMMON is None:
        from ..compiled import group

        # (its kernels helpers too: the same functions as the reduced group's and the full step's helpers)
        ker = group("common_1d", {k: (f, SIGNATURES[k]) for k, f in COMMON.items()},
                    helpers=(_fmax, *COMMON.values()), check_layouts=True)
        _COMMON = False if ker is None else ker
    return _COMMON or None


def whole_iterate():
    """(:func:`_iterate_points`, :func:`_whole_iterate`, :func:`_shift_law_points`,
    :func:`_shift_with_laws`, :func:`_first_iterate`) compiled (:mod:`twofluid.compiled`)."""
    _compile()
    return _WHOLE


def available() -> bool:
    """Whether the kernels can be had (always, with numba or their modules built).

    >>> available() == (kernels() is not None)
    True
    """
    return _compile() is not None


def kernels():
    """(closure_points, band_system, band_solve, step_pressure, shift_points, shift, step_constants,
    iterate_change, state_check) compiled (:mod:`twofluid.compiled`).

    >>> k = kernels()
    >>> k is None or len(k) == 9
    True
    """
    return _compile()
