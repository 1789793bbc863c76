"""The hysteretic law's dilation zone (cyclic mobility): the dilation stress beyond the zone
|γ − γ_c| ≤ γ_d, the strength envelope it raises, and the widening of the zone once the element
has liquefied (module docstring of :mod:`twofluid.closures.hysteretic`, "Cyclic mobility").
Scalar functions numba compiles with the law's kernel and that also run un-jitted.
"""
from __future__ import annotations

import math

from . import hysteretic_backbone as _hb
from . import hysteretic_flow as _hf
from .hysteretic_layout import (C_GC, C_GD, C_GDR, C_LIQ, C_TDMAX, NPARAM, NSTATE, P_DGD, P_GLIM, S_GC, S_GD)

__all__ = ['widen_zone']


def _dil(ex, c):
    """(τ_d ≥ 0 [Pa], dτ_d/dγ [Pa]): the dilation stress at ``ex`` = γ − γ_c from the centre of the
    cycles (0 inside the zone |ex| ≤ γ_d, in sand that generates no pore pressure, and on the side of
    a static shear τ_s that exceeds the residual strength S_r: flow liquefaction, module docstring
    "Flow liquefaction"); ``c`` the element's constants."""
    over = abs(ex) - c[C_GD]
    if over <= 0.0 or c[C_LIQ] <= 0.0:
        return 0.0, 0.0
    if _hf.flows(ex, c):
        return 0.0, 0.0  # flow liquefaction: no dilation on the side of a static shear above S_r
    r = over / c[C_GDR]
    if r >= 1.0:
        return c[C_TDMAX] * 1.0, 0.0  # capped
    k = c[C_TDMAX] * 6.0 * r * (1.0 - r) / c[C_GDR]  # smooth onset: S(r) = r²(3 − 2r)
    return c[C_TDMAX] * (r * r * (3.0 - 2.0 * r)), (k if ex > 0.0 else -k)


def _dilation(ex, st, par, e):
    """Dilation stress τ_d ≥ 0 [Pa] of element ``e`` at ``ex`` = γ − γ_c (:func:`_dil`)."""
    return _dil(ex, _hb._constants(st, par, e))[0]


def _env(g, d, tau, k, s, ex0, td0, c):
    """(τ [Pa], dτ/dγ [Pa]): ``tau`` (slope ``k``) limited by the strength envelope max(τ_max, τ_d),
    and raised by the dilation stress gained since the branch's origin γ_0 (``ex0`` = γ_0 − γ_c,
    ``td0`` = τ_d there) when loading outwards beyond γ_d (module docstring, "Cyclic mobility"):
    τ_d(γ) − τ_d(γ_0) where the origin lies beyond γ_d on the same side, so a branch that turns back
    outwards within the dilation zone starts from its reversal stress, not from τ_d above it (a jump
    at the reversal)."""
    upper = s
    ku = 0.0
    lower = -s
    kl = 0.0
    ex = g - c[C_GC]
    td, kd = _dil(ex, c)
    if td > 0.0:
        gain = td
        if ex0 * ex > 0.0:
            gain = td - td0
        if ex > 0.0:
            if td > upper:
                upper = td
                ku = kd
            if d > 0.0 and gain > 0.0:
                tau += gain
                k += kd
        else:
            if -td < lower:
                lower = -td
                kl = -kd
            if d < 0.0 and gain > 0.0:
                tau -= gain
                k -= kd
    if tau > upper:
        tau = upper
        k = ku
    if tau < lower:
        tau = lower
        k = kl
    return tau, k


def _env_value(g, d, tau, s, ex0, td0, c):
    """:func:`_env`'s stress alone [Pa] (the same operations on ``tau``, so the same number)."""
    upper = s
    lower = -s
    ex = g - c[C_GC]
    td = _dil(ex, c)[0]
    if td > 0.0:
        gain = td
        if ex0 * ex > 0.0:
            gain = td - td0
        if ex > 0.0:
            if td > upper:
                upper = td
            if d > 0.0 and gain > 0.0:
                tau += gain
        else:
            if -td < lower:
                lower = -td
            if d < 0.0 and gain > 0.0:
                tau -= gain
    if tau > upper:
        tau = upper
    if tau < lower:
        tau = lower
    return tau


def widen_zone(g_old, g, st, par, e):
    """Widen the zone without dilation of a liquefied element ``e`` by the strain travelled inside it
    from ``g_old`` to ``g``: d(γ_d²) = Δγ_d |dγ| for |γ − γ_c| < γ_d, up to γ_lim (module docstring
    of :mod:`twofluid.closures.hysteretic`, "Cyclic mobility").

    >>> import numpy as np
    >>> st = np.zeros((1, NSTATE)); par = np.zeros((1, NPARAM)); st[0, S_GD] = 0.01
    >>> par[0, P_GLIM] = 0.05; par[0, P_DGD] = 0.001
    >>> widen_zone(-0.02, 0.02, st, par, 0); round(float(st[0, S_GD]), 6)   # √(1e-4 + 0.001 · 0.02)
    0.010954
    """
    gc = st[e, S_GC]
    gd = st[e, S_GD]
    inside = min(max(g_old, g), gc + gd) - max(min(g_old, g), gc - gd)
    if inside > 0.0 and gd < par[e, P_GLIM]:
        st[e, S_GD] = min(par[e, P_GLIM], math.sqrt(gd * gd + par[e, P_DGD] * inside))
