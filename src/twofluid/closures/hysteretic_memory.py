"""The hysteretic law's memory: Masing/MRDF unloading–reloading branches from the open reversal
points, loop closure (extended Masing rules) and the move towards Masing's rule as pore pressure
is generated (module docstring of :mod:`twofluid.closures.hysteretic`, "Unloading and
reloading"). Each branch is bounded by the strength envelope of :mod:`.hysteretic_dilation`.
Scalar functions numba compiles with the law's kernel and that also run un-jitted.
"""
from __future__ import annotations

from . import backbones as _bb
from . import hysteretic_backbone as _hb
from . import hysteretic_dilation as _hz
from .hysteretic_layout import (C_C3, C_GC, C_H5, C_TH1, C_TH2, C_TH4, C_TH5, NPARAM, NSTACK, NSTATE, P_LIQ, P_P1, P_P2, P_P3,
    P_RCAP, R_MASING, S_DIR, S_G, S_GM, S_NSTK, S_RG, S_STK, S_T)

__all__ = ['masing_weight', 'direction']


def _branch(y, fm, c):
    """(Φ(y), dΦ/dy): Φ = F (2 f(y/2) − f(y)) + f(y), odd in y = (γ − γ_0)/γ_r, a Masing/MRDF branch
    over τ_max (F = 0: the backbone f, F = 1: Masing's 2 f(y/2)); ``c`` the element's constants
    (:func:`_branch_of` with the six of them it takes)."""
    return _branch_of(y, fm, c[C_TH1], c[C_TH2], c[C_C3], c[C_TH4], c[C_TH5], c[C_H5])


def _branch_of(y, fm, th1, th2, c3, th4, th5, h5):
    """:func:`_branch` from the constants it takes (GQ/H θ1, θ2, θ3^θ5, θ4, θ5 and 2^−θ5) as eight
    floats, which a compiled call passes in registers (the element's 13 constants as a tuple were
    copied into every call)."""
    x = abs(y)
    if fm == 0.0:
        if x <= 0.0:
            phi, k = 0.0, 1.0
        else:
            phi, k = _bb.gqh_slope_w(x, th4 * x ** th5, th1, th2, c3, th5)
    elif fm == 1.0:
        h = 0.5 * x
        if h <= 0.0:
            f2, k = 0.0, 1.0
        else:
            f2, k = _bb.gqh_slope_w(h, th4 * h ** th5, th1, th2, c3, th5)
        phi = 2.0 * f2
    elif x > 0.0:  # f(x) and f(x/2) from one power
        w = th4 * x ** th5
        f1, k1 = _bb.gqh_slope_w(x, w, th1, th2, c3, th5)
        f2, k2 = _bb.gqh_slope_w(0.5 * x, w * h5, th1, th2, c3, th5)
        phi = fm * (2.0 * f2 - f1) + f1
        k = fm * (k2 - k1) + k1
    else:
        phi, k = 0.0, 1.0
    return (phi if y >= 0.0 else -phi), k


def _branch_value(y, fm, c):
    """:func:`_branch`'s Φ(y) alone (the same operations, so the same number, without the slope's)."""
    return _branch_value_of(y, fm, c[C_TH1], c[C_TH2], c[C_C3], c[C_TH4], c[C_TH5], c[C_H5])


def _branch_value_of(y, fm, th1, th2, c3, th4, th5, h5):
    """:func:`_branch_value` from the constants it takes as eight floats (:func:`_branch_of`)."""
    x = abs(y)
    if fm == 0.0:
        phi = 0.0 if x <= 0.0 else _hb._gqh_value_w(x, th4 * x ** th5, th1, th2, c3)
    elif fm == 1.0:
        h = 0.5 * x
        phi = 2.0 * (0.0 if h <= 0.0 else _hb._gqh_value_w(h, th4 * h ** th5, th1, th2, c3))
    elif x > 0.0:
        w = th4 * x ** th5
        f1 = _hb._gqh_value_w(x, w, th1, th2, c3)
        f2 = _hb._gqh_value_w(0.5 * x, w * h5, th1, th2, c3)
        phi = fm * (2.0 * f2 - f1) + f1
    else:
        phi = 0.0
    return phi if y >= 0.0 else -phi


def masing_weight(st, par, e):
    """Weight w ∈ [0, 1] of Masing's rule in the unloading–reloading factor of element ``e``: 0 up to
    a generated ratio r_g = ``R_MASING``, then S((r_g − R_MASING)/(r_cap − R_MASING)), S(x) = x²(3 − 2x),
    1 at r_cap (module docstring, "Unloading and reloading"). A continuous function of r_g, so the
    loops turn from the intact skeleton's into Masing's as the pore pressure is generated, never in
    a jump.

    >>> import numpy as np
    >>> par = np.zeros((1, NPARAM)); par[0, P_RCAP] = 0.999; st = np.zeros((1, NSTATE))
    >>> st[0, S_RG] = 0.5; a = masing_weight(st, par, 0); st[0, S_RG] = 0.999
    >>> a, masing_weight(st, par, 0)
    (0.0, 1.0)
    """
    return _masing_weight_of(st[e, S_RG], par[e, P_RCAP])


def _masing_weight_of(rg, rcap):
    """:func:`masing_weight` from the generated ratio ``rg`` and ``r_cap`` given (no array in a
    function that branches: compiled, each array it takes costs a reference count in and out)."""
    x = (rg - R_MASING) / (rcap - R_MASING)
    if x <= 0.0:
        return 0.0
    if x >= 1.0:
        return 1.0
    return x * x * (3.0 - 2.0 * x)


def _mrdf(st, par, e, gr, c):
    """F of the unloading–reloading branches of element ``e`` (1: Masing): MRDF's factor at the
    largest strain so far, moved towards Masing's F = 1 by :func:`masing_weight` as the pore pressure
    is generated (a liquefied element flows between its dilation stops on Masing branches)."""
    return _mrdf_of(st[e, S_GM], st[e, S_RG], par[e, P_P1], par[e, P_P2], par[e, P_P3], par[e, P_LIQ], par[e, P_RCAP], gr, c)


def _mrdf_of(gm, rg, p1, p2, p3, liq, rcap, gr, c):
    """:func:`_mrdf` from the element's largest strain ``gm``, generated ratio ``rg`` and parameters
    (p1, p2, p3, P_LIQ, r_cap) given: the same operations, with no array in a function that branches
    (compiled, each array such a function takes costs a reference count in and out per call)."""
    f = p1
    if p2 != 0.0:
        xm = gm / gr
        red = 1.0
        if xm > 0.0:
            red = _hb._gqh_w(xm, c[C_TH4] * xm ** c[C_TH5], c) / xm  # (the backbone's ratio alone)
        f = p1 - p2 * max(1.0 - red, 0.0) ** p3
    if liq > 0.0:
        w = _masing_weight_of(rg, rcap)
        if w > 0.0:
            f = f + (1.0 - f) * w
    return f


def _origin(g0, t0, d, s, gr, fm, c):
    """What the branch in direction ``d`` from the reversal (``g0``, ``t0`` τ/τ_max) needs of its
    origin, once per sub-step: (γ_0, τ_0 [Pa], τ_max κ [Pa], κ γ_r, γ_0 − γ_c, τ_d(γ_0 − γ_c) [Pa]).

    From a stress the dilation carried above τ_max the branch is wider (κ > 1), so that it still
    reaches the strength the other way (asymptote d τ_max)."""
    kappa = max(1.0, abs(d - t0) / (1.0 + fm)) if abs(t0) > 1.0 else 1.0
    ex0 = g0 - c[C_GC]
    return g0, t0 * s, s * kappa, kappa * gr, ex0, _hz._dil(ex0, c)[0]


def _on(g, d, g0, ts0, sk, kg, ex0, td0, s, fm, c):
    """(τ [Pa], dτ/dγ [Pa]) at ``g`` of the branch in direction ``d`` from the origin (``g0``,
    ``ts0``, ``sk``, ``kg``, ``ex0``, ``td0``: :func:`_origin`) within the strength envelope, with the
    dilation gained since the origin."""
    phi, k = _branch((g - g0) / kg, fm, c)
    return _hz._env(g, d, ts0 + sk * phi, sk * k / kg, s, ex0, td0, c)


def _on_value(g, d, g0, ts0, sk, kg, ex0, td0, s, fm, c):
    """:func:`_on`'s stress alone [Pa] (the same operations, so the same number)."""
    return _hz._env_value(g, d, ts0 + sk * _branch_value((g - g0) / kg, fm, c), s, ex0, td0, c)


def _reversal_branch(g, d, g0, t0, s, gr, fm, c):
    """Stress [Pa] at ``g`` of the branch from the reversal (``g0``, ``t0`` τ/τ_max) in direction
    ``d`` within the strength envelope, with the dilation gained since ``g0``."""
    o = _origin(g0, t0, d, s, gr, fm, c)
    return _on_value(g, d, o[0], o[1], o[2], o[3], o[4], o[5], s, fm, c)


def _backbone(g, d, s, gr, c):
    """(τ [Pa], dτ/dγ [Pa]) of the backbone at ``g`` within the strength envelope, with the dilation
    gained since the centre of the cycles γ_c (the cap beyond the largest strain so far)."""
    phi, k = _branch(g / gr, 0.0, c)
    return _hz._env(g, d, s * phi, s * k / gr, s, 0.0, 0.0, c)


def _backbone_value(g, d, s, gr, c):
    """:func:`_backbone`'s stress alone [Pa] (the same operations, so the same number)."""
    return _hz._env_value(g, d, s * _branch_value(g / gr, 0.0, c), s, 0.0, 0.0, c)


def _open_count(d, st, e):
    """Open reversal points of element ``e`` while it moves in direction ``d`` from its committed
    state, and whether the last of them is the committed point itself (a reversal now, pushed at
    the commit): a function of the committed state and ``d`` only, fixed over Newton's iterations.

    At a reversal the pairs whose loop the branch just left had already closed (its strain passed
    their target) are dropped, and so is the innermost pair when the stack is full; a reversal at
    the largest strain so far starts afresh."""
    n = int(st[e, S_NSTK])
    d_old = st[e, S_DIR]
    if d_old == 0.0 or d == d_old:
        return n, False
    gc = st[e, S_G]
    if abs(gc) >= st[e, S_GM]:
        return 1, True
    while n >= 2 and d_old * (gc - st[e, S_STK + 2 * (n - 2)]) >= 0.0:
        n -= 2
    if n >= NSTACK:
        n -= 2
    return n + 1, True


def _open_point(k, n, rev, st, e):
    """(γ, τ/τ_max) of open reversal point ``k`` of ``n`` (:func:`_open_count`)."""
    if rev and k == n - 1:
        return st[e, S_G], st[e, S_T]
    return st[e, S_STK + 2 * k], st[e, S_STK + 2 * k + 1]


def _open_stress(g, d, n, rev, st, e, s, gr, fm, c):
    """The lower (in direction ``d``) of the branch from the last open reversal point and the outer
    branch that its loop closes onto (the one from the point before its target), before the
    backbone cap and the envelope [Pa]."""
    g0, t0 = _open_point(n - 1, n, rev, st, e)
    tau = _reversal_branch(g, d, g0, t0, s, gr, fm, c)
    if n >= 3:
        g1, t1 = _open_point(n - 3, n, rev, st, e)
        to = _reversal_branch(g, d, g1, t1, s, gr, fm, c)
        if d * to < d * tau:
            tau = to
    return tau


def direction(g, st, e):
    """Direction (±1) of a strain increment to ``g`` from the committed strain (the last one's if 0)."""
    dg = g - st[e, S_G]
    if dg > 0.0:
        return 1.0
    if dg < 0.0:
        return -1.0
    return st[e, S_DIR] if st[e, S_DIR] != 0.0 else 1.0


def _close_loops(g, d, st, par, e, s, gr, c, fm):
    """Loop closure at the committed strain ``g`` (direction ``d``; the stack already holds this
    sub-step's reversal): drops the innermost open pair once ``g`` has passed its target and the
    outer branch is the active one there, and every point once the backbone is (beyond the largest
    strain so far). Only what no longer sets the stress at ``g`` is dropped, so the stress there is
    unchanged: closing a loop is never a jump. ``c``: the element's constants (:func:`_constants`);
    ``fm``: the branches' F (:func:`_mrdf`, the same before and after the commit's push), < 0 where
    not known yet. (``closures.hysteretic._commit_counted`` calls it only where its two loops below can
    act, n ≥ 3 with g past the innermost target or d g beyond γ_m: the same tests, kept in step.)"""
    n = int(st[e, S_NSTK])
    if n == 0:
        return
    if fm < 0.0:
        fm = _mrdf(st, par, e, gr, c)
    while n >= 3 and d * (g - st[e, S_STK + 2 * (n - 2)]) >= 0.0:
        gi, go = st[e, S_STK + 2 * (n - 1)], st[e, S_STK + 2 * (n - 3)]
        ti = _reversal_branch(g, d, gi, st[e, S_STK + 2 * (n - 1) + 1], s, gr, fm, c)
        to = _reversal_branch(g, d, go, st[e, S_STK + 2 * (n - 3) + 1], s, gr, fm, c)
        if d * ti < d * to:
            break
        n -= 2
    if d * g > st[e, S_GM]:
        tb = _backbone_value(g, d, s, gr, c)
        if d * tb <= d * _open_stress(g, d, n, False, st, e, s, gr, fm, c):
            n = 0
    st[e, S_NSTK] = n
