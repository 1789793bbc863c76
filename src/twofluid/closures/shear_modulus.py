"""Shear modulus of the dense granular skeleton (n < n_c; Seed & Idriss 1970 in SI units).

G = (G/G_max)(γ) · G_max(P_s): a small-strain modulus from the granular pressure
and a modulus-reduction curve of the shear strain. G → 0 as P_s → 0
(liquefaction).

>>> g = shear_modulus(1e-3, 100e3, k2max=30.0)
>>> round(float(g / 1e6), 4)
32.82
"""
from __future__ import annotations

from typing import Callable

import numpy as np
from numpy.typing import ArrayLike

from .registry import register

__all__ = ["seed_idriss_gmax", "hyperbolic", "tabulated", "tabulated_curve", "table_problem",
           "backbone_dips", "shear_modulus", "strain_from_stress", "GAMMA_REF_DEFAULT"]

KPA = 1000.0  # [Pa]
#: Default reference strain of the hyperbolic curve [-]; see :func:`hyperbolic`.
GAMMA_REF_DEFAULT = 1e-3


@register("shear_modulus", "seed_idriss", params={"k2max": 30.0}, porosity_range=(0.0, 0.5),
          reference="Seed & Idriss (1970), EERC 70-10, SI form")
def seed_idriss_gmax(p_s: ArrayLike, k2max: float = 30.0) -> np.ndarray:
    """Seed–Idriss small-strain modulus G_max = 218.8 K2max √(P_s / 1 kPa) kPa [Pa].

    Parameters
    ----------
    p_s : array_like
        Granular (effective) pressure [Pa]; negative values count as 0.
    k2max : float
        Seed–Idriss modulus number [-]: about 30 for loose, 70 for dense sand.

    Returns
    -------
    ndarray
        Small-strain shear modulus [Pa]. The SI form of Seed & Idriss's
        G_max = 1000 K2max √σ′_m (psf), the thesis's "220 K2max √P_s".

    >>> round(float(seed_idriss_gmax(100e3, 30.0)) / 1e6, 3)
    65.64
    >>> float(seed_idriss_gmax(-5.0, 30.0))
    0.0

    Reference: Seed, H. B. & Idriss, I. M. (1970), Soil moduli and damping factors
    for dynamic response analyses, Report EERC 70-10, UC Berkeley.
    """
    p = np.maximum(np.asarray(p_s, dtype=float), 0.0)
    return 218.8 * KPA * k2max * np.sqrt(p / KPA)


@register("modulus_reduction", "hyperbolic", params={"gamma_ref": GAMMA_REF_DEFAULT},
          porosity_range=(0.0, 0.5), reference="Hardin & Drnevich (1972), JSMFD 98(SM7)")
def hyperbolic(gamma: ArrayLike, gamma_ref: float = GAMMA_REF_DEFAULT) -> np.ndarray:
    """Hyperbolic modulus reduction G/G_max = 1 / (1 + |γ|/γ_ref) [-].

    Parameters
    ----------
    gamma : array_like
        Engineering shear strain γ [-] (not %).
    gamma_ref : float
        Reference strain [-] at which G = G_max / 2. In Hardin–Drnevich's
        hyperbola γ_ref = τ_max / G_max, so the backbone τ = G γ tends to the
        strength τ_max. The default 1e-3 (0.1 %) is that ratio for a loose
        sand at 100 kPa: τ_max ≈ 0.6 σ′ = 60 kPa over G_max = 65.6 MPa
        (K2max = 30) gives 0.9e-3; Darendeli (2001) gives 0.035 %–0.1 % for
        clean sands at 1 atm. The default is constant, so it drifts from
        τ_max / G_max as P_s changes (τ_max then scales like √P_s).

    >>> [round(float(v), 3) for v in hyperbolic([0.0, 1e-3, 1e-2])]
    [1.0, 0.5, 0.091]

    Reference: Hardin, B. O. & Drnevich, V. P. (1972), Shear modulus and damping in
    soils: design equations and curves, J. Soil Mech. Found. Div. 98(SM7), 667–692.
    """
    if not gamma_ref > 0.0:
        raise ValueError(f"hyperbolic: gamma_ref must be > 0, got {gamma_ref}")
    return 1.0 / (1.0 + np.abs(np.asarray(gamma, dtype=float)) / gamma_ref)


def table_problem(strains: ArrayLike, ratios: ArrayLike) -> tuple[str, str] | None:
    """First problem of a G/G_max table as (what, message), or None if the table is valid.

    ``what`` is ``"table"`` (shape), ``"strains"`` or ``"ratios"``. Valid: at least 2 points,
    as many ratios as strains, strains finite, > 0 and strictly increasing, ratios in (0, 1]
    and non-increasing with strain.

    >>> table_problem([1e-5, 1e-4], [1.0, 0.8]) is None
    True
    >>> table_problem([1e-5, 1e-4, 1e-4], [1.0, 0.8, 0.7])
    ('strains', 'strains must strictly increase: 0.0001 (point 2) then 0.0001 (point 3)')
    >>> table_problem([1e-5, 1e-4], [1.0, 1.2])[0]
    'ratios'
    """
    g = np.asarray(strains, dtype=float)
    r = np.asarray(ratios, dtype=float)
    if g.ndim != 1 or r.ndim != 1:
        return "table", "strains and G/G_max must be 1-D lists"
    if g.size != r.size:
        return "table", f"has {g.size} strain(s) but {r.size} G/G_max value(s); valid: one G/G_max per strain"
    if g.size < 2:
        return "table", f"has {g.size} point(s); valid: at least 2 (strain, G/G_max) points"
    for i in range(g.size):
        if not (np.isfinite(g[i]) and g[i] > 0.0):
            return "strains", f"strain {g[i]:g} (point {i + 1}) is outside the valid range (0, inf) [-]"
        if i and not g[i] > g[i - 1]:
            return "strains", (f"strains must strictly increase: {g[i - 1]:g} (point {i}) then "
                               f"{g[i]:g} (point {i + 1})")
    for i in range(r.size):
        if not (np.isfinite(r[i]) and 0.0 < r[i] <= 1.0):
            return "ratios", (f"G/G_max = {r[i]:g} at strain {g[i]:g} (point {i + 1}) is outside the "
                              "valid range (0, 1]")
        if i and r[i] > r[i - 1]:
            return "ratios", (f"G/G_max must not increase with strain: {r[i - 1]:g} at {g[i - 1]:g} then "
                              f"{r[i]:g} at {g[i]:g} (points {i}, {i + 1})")
    return None


def _check(strains, ratios):
    problem = table_problem(strains, ratios)
    if problem is not None:
        raise ValueError(f"tabulated: {problem[0]} {problem[1]}")
    return np.asarray(strains, dtype=float), np.asarray(ratios, dtype=float)


def _interp_log(gamma, strains, ratios):
    logg = np.log10(np.maximum(np.abs(np.asarray(gamma, dtype=float)), strains[0]))
    return np.interp(logg, np.log10(strains), ratios)


@register("modulus_reduction", "tabulated", params={}, porosity_range=(0.0, 0.5),
          reference="user table, e.g. Seed & Idriss (1970) or Darendeli (2001) curves")
def tabulated(gamma: ArrayLike, strains: ArrayLike, ratios: ArrayLike) -> np.ndarray:
    """Tabulated modulus reduction G/G_max(|γ|), interpolated linearly in log10 γ [-].

    Parameters
    ----------
    gamma : array_like
        Shear strain γ [-].
    strains : array_like
        Table strains [-], positive and strictly increasing (not %).
    ratios : array_like
        G/G_max at ``strains``, in (0, 1] and non-increasing.

    Below the first strain the first ratio is used, above the last the last (the
    stress then grows as G_max r_last γ: the table sets no strength). The table is
    checked at every call; :func:`tabulated_curve` checks it once.

    >>> s, r = [1e-5, 1e-4, 1e-3, 1e-2], [1.0, 0.9, 0.5, 0.1]
    >>> [round(float(v), 3) for v in tabulated([1e-6, 10**-3.5, 1e-3, 1.0], s, r)]
    [1.0, 0.7, 0.5, 0.1]
    """
    strains, ratios = _check(strains, ratios)
    return _interp_log(gamma, strains, ratios)


def tabulated_curve(strains: ArrayLike, ratios: ArrayLike) -> Callable[[np.ndarray], np.ndarray]:
    """G/G_max(γ) of a table, checked once: the function γ -> :func:`tabulated` (γ, strains, ratios).

    Raises ValueError (message from :func:`table_problem`) for an invalid table. This is
    what ``[sand] modulus_reduction = "tabulated"`` passes to the shear column.

    >>> curve = tabulated_curve([1e-5, 1e-3], [1.0, 0.5])
    >>> [round(float(v), 3) for v in curve([-1e-6, 1e-4, 1e-3, 0.1])]
    [1.0, 0.75, 0.5, 0.5]
    """
    strains, ratios = _check(strains, ratios)
    strains.setflags(write=False)
    ratios.setflags(write=False)

    def curve(gamma: ArrayLike) -> np.ndarray:
        return _interp_log(gamma, strains, ratios)

    curve.strains, curve.ratios = strains, ratios
    return curve


def backbone_dips(strains: ArrayLike, ratios: ArrayLike, tolerance: float = 0.01) -> list[int]:
    """Table intervals (0-based, point i to i + 1) where log interpolation makes the backbone
    τ/G_max = (G/G_max) γ fall by more than ``tolerance`` of its largest value before it [-].

    Between two points G/G_max = r_i + (r_{i+1} − r_i) s with s = ln(γ/γ_i)/ln(γ_{i+1}/γ_i), so
    d[(G/G_max) γ]/dγ = G/G_max − (r_i − r_{i+1})/ln(γ_{i+1}/γ_i) is smallest at γ_{i+1}: the
    stress falls near the end of an interval where r_{i+1} ln(γ_{i+1}/γ_i) < r_i − r_{i+1}. Coarse
    tables at large strain do this (a drop from 0.3 to 0.12 over 0.3–1 % falls by 2.2 %; a
    hyperbola sampled once per decade by 42 % well above γ_ref, 20 times per decade by 0.1 %).
    Evaluated on 201 points per interval.

    >>> backbone_dips([1e-4, 1e-3, 3e-3, 1e-2], [0.9, 0.5, 0.3, 0.12]), backbone_dips([1e-4, 1e-3], [0.9, 0.5])
    ([2], [])
    """
    g = np.asarray(strains, dtype=float)
    r = np.asarray(ratios, dtype=float)
    t = np.linspace(0.0, 1.0, 201)[:, None]
    tau = (r[:-1] + (r[1:] - r[:-1]) * t) * g[:-1] * np.exp(t * np.log(g[1:] / g[:-1]))
    peak = np.maximum.accumulate(tau, axis=0)
    fall = np.max((peak - tau) / peak, axis=0)
    return [int(i) for i in np.flatnonzero(fall > tolerance)]


def shear_modulus(gamma: ArrayLike, p_s: ArrayLike, k2max: float = 30.0,
                  reduction: Callable[[np.ndarray], np.ndarray] | None = None) -> np.ndarray:
    """Secant shear modulus G = G_max(P_s) · (G/G_max)(γ) [Pa].

    ``reduction`` maps γ to G/G_max; default :func:`hyperbolic` with its default γ_ref.
    """
    ratio = hyperbolic(gamma) if reduction is None else reduction(gamma)
    return seed_idriss_gmax(p_s, k2max) * ratio


def strain_from_stress(tau: ArrayLike, g_max: ArrayLike,
                       reduction: Callable[[np.ndarray], np.ndarray] | None = None,
                       gamma_max: float = 0.1, iterations: int = 60) -> np.ndarray:
    """Invert the backbone τ = G_max (G/G_max)(γ) γ for γ [-], vectorised.

    Returns γ with the sign of τ; where |τ| exceeds the largest stress the
    backbone reaches on [0, ``gamma_max``] the strain runs away and the result
    is ``inf`` (signed). Bisection in log γ; the backbone must increase with γ.

    >>> g = strain_from_stress([3e4, 7e4], 65.6e6, lambda x: hyperbolic(x, 1e-3))
    >>> round(float(g[0]), 7), bool(np.isinf(g[1]))
    (0.0008427, True)
    """
    tau = np.asarray(tau, dtype=float)
    gmax = np.broadcast_to(np.asarray(g_max, dtype=float), tau.shape)
    red = hyperbolic if reduction is None else reduction
    target = np.abs(tau)
    lo = np.full(tau.shape, np.log(1e-12))
    hi = np.full(tau.shape, np.log(gamma_max))
    runaway = target >= gmax * red(gamma_max) * gamma_max
    for _ in range(iterations):
        mid = 0.5 * (lo + hi)
        g = np.exp(mid)
        above = gmax * red(g) * g > target
        hi = np.where(above, mid, hi)
        lo = np.where(above, lo, mid)
    gamma = np.where(target > 0.0, np.exp(0.5 * (lo + hi)), 0.0)
    gamma = np.where(runaway, np.inf, gamma)
    return np.sign(tau) * gamma
