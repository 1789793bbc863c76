"""Shear modulus of the dense granular skeleton (SPEC 4.3, dense region n < n_c).

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

__all__ = ["seed_idriss_gmax", "hyperbolic", "tabulated", "shear_modulus",
           "strain_from_stress", "GAMMA_REF_DEFAULT"]

KPA = 1000.0  # [Pa]
#: Default reference strain of the hyperbolic curve [-]; see :func:`hyperbolic`.
GAMMA_REF_DEFAULT = 1e-3


@register("shear_modulus", "seed_idriss", params={"k2max": 30.0}, porosity_range=(0.0, 0.5),
          reference="Seed & Idriss (1970), EERC 70-10; SPEC 4.3")
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

    Below the first strain the first ratio is used, above the last the last.

    >>> s, r = [1e-5, 1e-4, 1e-3, 1e-2], [1.0, 0.9, 0.5, 0.1]
    >>> [round(float(v), 3) for v in tabulated([1e-6, 10**-3.5, 1e-3, 1.0], s, r)]
    [1.0, 0.7, 0.5, 0.1]
    """
    strains = np.asarray(strains, dtype=float)
    ratios = np.asarray(ratios, dtype=float)
    if strains.ndim != 1 or strains.shape != ratios.shape or strains.size < 2:
        raise ValueError("tabulated: strains and ratios must be 1-D of equal length >= 2")
    if np.any(strains <= 0.0) or np.any(np.diff(strains) <= 0.0):
        raise ValueError("tabulated: strains must be positive and strictly increasing")
    if np.any(ratios <= 0.0) or np.any(ratios > 1.0) or np.any(np.diff(ratios) > 0.0):
        raise ValueError("tabulated: ratios must lie in (0, 1] and not increase")
    mag = np.abs(np.asarray(gamma, dtype=float))
    logg = np.log10(np.maximum(mag, strains[0]))
    return np.interp(logg, np.log10(strains), ratios)


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
