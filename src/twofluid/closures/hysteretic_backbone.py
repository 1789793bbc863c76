"""The hysteretic law's backbone: strength and stiffness from the current effective stress, and the
GQ/H curve (module docstring of :mod:`twofluid.closures.hysteretic`, "Strength and stiffness",
"Backbone"). Scalar functions numba compiles with the law's kernel and that also run un-jitted.
"""
from __future__ import annotations

import math

from . import backbones as _bb
from . import hysteretic_ratchet as _hr
from .hysteretic_layout import (C_C3, C_TH1, C_TH2, C_TH4, C_TH5, KPA, P_GDR, P_GMAXFIX, P_K2, P_LIQ, P_PSFIX, P_SIG0, P_SR,
    P_TANPHI, P_TAUS, P_TH1, P_TH2, P_TH3, P_TH4, P_TH5, S_GC, S_GD)

__all__ = ['gqh_ratio', 'strength_modulus']


def gqh_ratio(x, th1, th2, th3, th4, th5):
    """τ/τ_max of the GQ/H backbone at normalised strain x = |γ|/γ_r ≥ 0 [-] (module docstring;
    :func:`twofluid.closures.backbones.gqh_core`, 0 at x ≤ 0).

    >>> round(gqh_ratio(0.0, 0.0, 0.0, 1.0, 1.0, 1.0), 6)
    0.0
    """
    if x <= 0.0:
        return 0.0
    return _bb.gqh_core(x, th1, th2, th3, th4, th5)


def strength_modulus(ps, par, e):
    """(τ_max [Pa], G_max [Pa]) of element ``e`` at effective vertical stress ``ps`` [Pa]."""
    return _strength_modulus_of(ps, par[e, P_TANPHI], par[e, P_GMAXFIX], par[e, P_PSFIX], par[e, P_SR], par[e, P_K2])


def _strength_modulus_of(ps, tanphi, gmaxfix, psfix, sr, k2):
    """:func:`strength_modulus` from the element's tan φ′, fixed G_max and P_s (crust), S_r and K2max
    given: the same operations, with no array in a function that branches (compiled, each array
    such a function takes costs a reference count in and out per call)."""
    if gmaxfix > 0.0:
        return max(psfix * tanphi, sr), gmaxfix
    p = max(ps, sr / tanphi, 1e-3)
    return p * tanphi, 218.8 * KPA * k2 * math.sqrt(p / KPA)


def _constants(st, par, e):
    """Constants of element ``e`` for the scalar functions of the law (``C_*``): GQ/H θ1, θ2,
    θ3^θ5, θ4, θ5; whether it dilates (P_LIQ), τ_s, S_r, γ_dr (:func:`.hysteretic_ratchet.dilation_strain`), σ′_v0 tan φ′; γ_c and γ_d; 2^−θ5."""
    th5 = par[e, P_TH5]
    return (par[e, P_TH1], par[e, P_TH2], par[e, P_TH3] ** th5, par[e, P_TH4], th5, par[e, P_LIQ],
            par[e, P_TAUS], par[e, P_SR], _hr.dilation_strain(st, par, e), par[e, P_SIG0] * par[e, P_TANPHI],
            st[e, S_GC], st[e, S_GD], 0.5 ** th5)


def _gqh(x, c):
    """(:func:`gqh_ratio`, its slope d/dx) at x ≥ 0 with the constants ``c`` (:func:`_constants`)."""
    if x <= 0.0:
        return 0.0, 1.0
    return _bb.gqh_core_slope_c(x, c[C_TH1], c[C_TH2], c[C_C3], c[C_TH4], c[C_TH5])


def _gqh_w(x, w, c):
    """:func:`gqh_ratio` alone at x > 0 from w = θ4 x^θ5 given, with the constants ``c``: the first of
    :func:`twofluid.closures.backbones.gqh_slope_w`'s two values, the same operations in the same
    order (so the same number, to the bit), without the slope's three divisions, for the evaluations
    whose slope nothing uses (:func:`twofluid.closures.hysteretic._stress_value`)."""
    return _gqh_value_w(x, w, c[C_TH1], c[C_TH2], c[C_C3])


def _gqh_value_w(x, w, th1, th2, c3):
    """:func:`_gqh_w` with the constants it takes given alone (θ1, θ2, θ3^θ5): the same operations."""
    th = th1 + th2 * w / (c3 + w)
    r = ((1.0 + x) * (1.0 + x) - 4.0 * th * x) ** 0.5
    return 2.0 * x / (1.0 + x + r)
