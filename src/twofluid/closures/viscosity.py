"""Mixture and solid-phase shear viscosity, Newtonian region (Pringle 2001 sec. 3.3.1).

The thesis fits rotating-viscometer data for Barnes sand in water with a
modified Mooney law. The fit is valid for solids fractions 0.2 ≲ ε_s ≤ 0.5 and
tends to e (not 1) at ε_s = 0 (correction 6 of docs/model.md), so below
``eps_blend`` it is replaced by the cubic 1 + 2.5 ε_s + b ε_s² + c ε_s³
(Einstein's slope at zero concentration) matched in value and slope to the fit
at ``eps_blend``. Above
the Newtonian region (ε_s > 1 − n_c) the mixture viscosity is held at its
value at n_c: denser states are the elastic skeleton of the dense region.
"""
from __future__ import annotations

from functools import lru_cache

import numpy as np

from .registry import register

__all__ = ["mooney_pringle", "solid_viscosity"]

K1, K2 = 1.1721, -1.7172


def _fit(eps, k1, k2):
    """The fit's relative viscosity exp(exp(ε_s/(k1 + k2 ε_s))) and its slope in ε_s."""
    x = eps / (k1 + k2 * eps)
    ex = np.exp(x)
    mu = np.exp(ex)
    dmu = mu * ex * k1 / (k1 + k2 * eps) ** 2
    return mu, dmu


def _fit_value(eps, k1, k2):
    """The first value of :func:`_fit` alone (the same operations)."""
    return np.exp(np.exp(eps / (k1 + k2 * eps)))


@lru_cache(maxsize=16)
def _blend_coefficients(eps_b: float, k1: float, k2: float) -> tuple[float, float]:
    """(b, c) of the cubic blend; cached: it depends only on the parameters."""
    value, slope = _fit(eps_b, k1, k2)
    rhs = np.array([value - 1.0 - 2.5 * eps_b, slope - 2.5])
    mat = np.array([[eps_b ** 2, eps_b ** 3], [2 * eps_b, 3 * eps_b ** 2]])
    b, c = np.linalg.solve(mat, rhs)
    return float(b), float(c)


@register("viscosity", "mooney_pringle",
          params={"k1": K1, "k2": K2, "eps_blend": 0.2, "n_c": 0.5},
          porosity_range=(0.5, 1.0), reference="Mooney (1951) as modified by Pringle (2001) eq. 3.36")
def mooney_pringle(n, mu_f, *, k1=K1, k2=K2, eps_blend=0.2, n_c=0.5):
    """Modified Mooney mixture viscosity μ_m = μ_f exp(exp(ε_s/(k1 + k2 ε_s))) [Pa·s].

    ε_s = 1 − n. Cubic blend to μ_f at ε_s = 0 below ``eps_blend``; held constant
    for n < ``n_c``. Continuous, increasing in ε_s, equal to μ_f in clear liquid.

    >>> round(float(mooney_pringle(1.0, 1e-3)) * 1e3, 12)
    1.0
    >>> round(float(mooney_pringle(0.7, 1.0)), 3)   # exp(exp(0.3/(1.1721-0.51516)))
    4.849

    Reference: Pringle (2001), section 3.3.1 (Barnes sand in water, R² = 0.97).
    """
    eps = np.minimum(np.maximum(1.0 - np.asarray(n, dtype=float), 0.0), 1.0 - n_c)  # clip to [0, 1 − n_c]
    low = eps < eps_blend
    if not low.any():  # only the fit (the where below would take it everywhere)
        return mu_f * _fit_value(np.maximum(eps, eps_blend), k1, k2)
    b, c = _blend_coefficients(float(eps_blend), float(k1), float(k2))
    blend = 1.0 + eps * (2.5 + eps * (b + c * eps))
    if low.all():
        return mu_f * blend
    return mu_f * np.where(low, blend, _fit_value(np.maximum(eps, eps_blend), k1, k2))


def solid_viscosity(n, mu_f, **params):
    """Solid-phase viscosity μ_s = (μ_m − n μ_f)/(1 − n) [Pa·s], finite at n = 1.

    At n = 1 the analytic limit μ_f (1 + dμ_r/dε_s(0)) = 3.5 μ_f is used.

    >>> round(float(solid_viscosity(1.0, 1e-3)) * 1e3, 6)
    3.5
    >>> bool(abs(solid_viscosity(1 - 1e-7, 1e-3) - 3.5e-3) < 1e-8)
    True
    """
    n = np.asarray(n, dtype=float)
    eps = 1.0 - n
    mu_m = mooney_pringle(n, mu_f, **params)
    solid = eps > 1e-6
    if solid.all():  # no clear liquid: the where below would take its first branch everywhere
        return (mu_m - n * mu_f) / eps
    safe = np.where(solid, eps, 1.0)
    return np.where(solid, (mu_m - n * mu_f) / safe, 3.5 * mu_f)
