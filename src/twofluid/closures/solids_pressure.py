"""Granular (effective) pressure P_s(n, n̄) [Pa] (Pringle 2001 eqs. 3.41–3.54)."""
from __future__ import annotations

import numpy as np

from .registry import register

__all__ = ["exponential", "foscolo_gibilaro", "reference_porosity_for"]

_MAX_EXPONENT = 700.0  # exp(700) ~ 1e304: beyond it the state is meaningless anyway


@register("solids_pressure", "exponential", params={"A": 0.015, "p_ref": 1.0},
          porosity_range=(0.0, 1.0), reference="Pringle (2001) eq. 3.54; linearised as eqs. 4.31-4.32")
def exponential(n, n_bar, A, p_ref=1.0, derivative=False):
    """P_s = p_ref exp[(1/A)(1 − (1 − n̄)/(1 − n))], in Pa, and ∂P_s/∂n if asked.

    ``A`` is the compressibility [-] (thesis: 0.015 sand, 0.1075 illite),
    ``n_bar`` the reference porosity (state variable), ``p_ref`` = 1 Pa.
    ∂P_s/∂n = −P_s (1 − n̄)/(A (1 − n)²). P_s → 0 in clear liquid (n → 1).

    >>> float(exponential(0.4, 0.4, 0.015))
    1.0
    >>> p, dp = exponential(0.45, 0.4, 0.1, derivative=True)
    >>> round(float(p), 6), round(float(dp), 3)
    (0.40289, -7.991)
    >>> float(exponential(1.0, 0.4, 0.015))
    0.0

    Reference: Pringle (2001), eq. 4.30; Gidaspow (1994) ch. 9 for the form.
    """
    n = np.asarray(n, dtype=float)
    one_m = 1.0 - n
    solid = one_m > 0.0
    s_bar = 1.0 - n_bar
    if solid.all():  # the common case, without the masks (the same numbers: every where takes its first branch)
        ps = p_ref * np.exp(np.minimum((1.0 - s_bar / one_m) / A, _MAX_EXPONENT))
        return (ps, -ps * s_bar / (A * one_m * one_m)) if derivative else ps
    safe = np.where(solid, one_m, 1.0)
    expo = np.minimum((1.0 - s_bar / safe) / A, _MAX_EXPONENT)
    ps = np.where(solid, p_ref * np.exp(np.where(solid, expo, 0.0)), 0.0)
    if not derivative:
        return ps
    dps = np.where(solid, -ps * s_bar / (A * safe * safe), 0.0)
    return ps, dps


@register("fluidized_pressure", "foscolo_gibilaro", params={"coefficient": 3.2},
          porosity_range=(0.0, 1.0), reference="Foscolo & Gibilaro (1984), Chem. Eng. Sci. 39, 1667")
def foscolo_gibilaro(n, d, rho_s, rho_f, g, coefficient=3.2, derivative=False):
    """Foscolo–Gibilaro particle-phase pressure of a fluidized bed, P_e = (c/2) g d (ρ_s − ρ_f)(1 − n)² [Pa].

    The "particle bed model" of Foscolo & Gibilaro (1984) gives a fluidized bed an
    elastic modulus E = −∂P_e/∂n = c g d (ρ_s − ρ_f)(1 − n) [Pa] with c = 3.2, which
    comes from the dependence of the drag on the porosity gradient. Its dynamic wave
    speed u_e = √(E/ρ_s) is what makes liquid-fluidized beds stable (particulate)
    where u_e exceeds the kinematic wave speed of the porosity (their criterion); the
    two-component equations without it are unstable at every fluidized porosity
    (Jackson 1963). Integrating E from clear liquid (P_e = 0 at n = 1) gives the
    pressure above. ``d`` [m], densities [kg/m³], ``g`` [m/s²]; returns P_e and, if
    asked, ∂P_e/∂n [Pa].

    >>> round(float(foscolo_gibilaro(0.6, 4e-3, 1140.0, 998.2, 9.81)), 4)
    1.4244
    >>> p, dp = foscolo_gibilaro(1.0, 4e-3, 1140.0, 998.2, 9.81, derivative=True)
    >>> float(p), float(dp)
    (0.0, -0.0)
    """
    one_m = 1.0 - np.asarray(n, dtype=float)
    modulus = coefficient * g * d * (rho_s - rho_f)
    pe = 0.5 * modulus * one_m * one_m
    if not derivative:
        return pe
    return pe, -modulus * one_m


def reference_porosity_for(n, p_s, A, p_ref=1.0):
    """n̄ such that P_s(n, n̄) = p_s: n̄ = 1 − (1 − n)(1 − A ln(p_s/p_ref)) (eq. 3.54 solved for n̄).

    >>> round(float(reference_porosity_for(0.45, 1e5, 0.015)), 6)
    0.544982
    >>> round(float(exponential(0.45, reference_porosity_for(0.45, 1e5, 0.015), 0.015)), 3)
    100000.0
    """
    return 1.0 - (1.0 - np.asarray(n, float)) * (1.0 - A * np.log(np.asarray(p_s, float) / p_ref))
