"""Granular rheology with dilatancy of a dense immersed suspension, and the permeability beside it.

**Friction** (Boyer, Guazzelli & Pouliquen 2011, *Phys. Rev. Lett.* 107, 188301), with the
viscous number I_v = η_f γ̇ / P_s [-]:

    μ(I_v) = μ_s + (μ_2 − μ_s) / (1 + I_0/I_v) + I_v + (5/2) φ_c √I_v ,
    φ_eq(I_v) = φ_c / (1 + √I_v) .

The last two terms of μ are the hydrodynamic part of the stress: ``I_v P_s = η_f γ̇`` is the
liquid's own viscous stress and ``(5/2) φ_c √I_v`` Einstein's correction in the dense limit.
They are the **one** term for the liquid's viscosity in a model that uses this law: the liquid
carries no viscous shear stress of its own beside it, so η_f is not counted twice.

**Dilatancy** (Pailha & Pouliquen 2009, *J. Fluid Mech.* 633, 115): the dilatancy angle
tan ψ = K (φ − φ_eq(I_v)) adds to the friction and sets the volume change,

    τ / P_s = μ(I_v) + tan ψ ,       Dφ/Dt = −φ γ̇ tan ψ .

A dense layer (φ > φ_eq) must dilate to shear, which raises its friction; a loose one contracts.
Below the yield condition ``τ/P_s ≤ μ_s + K (φ − φ_c)`` it does not shear (γ̇ = 0). Given the
stress ratio and φ, :func:`viscous_number` inverts the law; its left side is increasing in I_v
(μ increases, φ_eq decreases), so the shear rate is unique.

**Permeability**: Carman–Kozeny, k = d² (1 − φ)³ / (180 φ²) [m²], the Darcy drag of the liquid
through the skeleton in the Stokes limit (the liquid flux relative to the solids is
q = −(k/η_f) ∂p/∂z).

>>> round(float(boyer_pailha(1e-3, 0.585)[0]), 4)   # μ(1e-3) + K (0.585 − φ_eq(1e-3))
0.6136
"""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from .registry import register

__all__ = ["RHEOLOGY_DEFAULTS", "NONLOCAL_AMPLITUDE", "boyer_pailha", "mu_iv", "phi_eq", "viscous_number",
           "nonlocal_shear_rate", "carman_kozeny"]

#: the sedFoam 1DWetAvalanche tutorial's set (μ_s, μ_2, I_0, φ_c) and K = 4.09, the value quoted for
#: Pailha & Pouliquen (2009) (its text was not available to check it; sedFoam's own K_dila is a
#: different, pressure-based dilatancy); the bundled case states its own calibrated values
RHEOLOGY_DEFAULTS = {"mu_s": 0.425, "mu_2": 0.765, "i_0": 0.004, "phi_c": 0.585, "k_dil": 4.09}
#: nonlocal amplitude A [-] of the granular fluidity model for glass beads (Henann & Kamrin 2013,
#: *PNAS* 110, 6730, their calibration on glass beads: μ_s 0.3819, b 0.9377, A 0.48)
NONLOCAL_AMPLITUDE = 0.48


def mu_iv(iv: ArrayLike, mu_s: float = 0.425, mu_2: float = 0.765, i_0: float = 0.004,
          phi_c: float = 0.585) -> np.ndarray:
    """Boyer et al. (2011) friction μ(I_v) [-], hydrodynamic terms included (module docstring).

    >>> float(mu_iv(0.0))
    0.425
    """
    iv = np.maximum(np.asarray(iv, dtype=float), 0.0)
    return mu_s + (mu_2 - mu_s) * iv / (iv + i_0) + iv + 2.5 * phi_c * np.sqrt(iv)


def phi_eq(iv: ArrayLike, phi_c: float = 0.585) -> np.ndarray:
    """Steady solid fraction φ_eq(I_v) = φ_c / (1 + √I_v) [-] (Boyer et al. 2011).

    >>> float(phi_eq(0.0, 0.6))
    0.6
    """
    return phi_c / (1.0 + np.sqrt(np.maximum(np.asarray(iv, dtype=float), 0.0)))


@register("granular_rheology", "boyer_pailha", params=dict(RHEOLOGY_DEFAULTS), porosity_range=(0.35, 0.5),
          reference="Boyer, Guazzelli & Pouliquen (2011) μ(I_v), φ(I_v); Pailha & Pouliquen (2009) dilatancy")
def boyer_pailha(iv: ArrayLike, phi: ArrayLike, mu_s: float = 0.425, mu_2: float = 0.765, i_0: float = 0.004,
                 phi_c: float = 0.585, k_dil: float = 4.09) -> tuple[np.ndarray, np.ndarray]:
    """Boyer–Pailha friction with dilatancy: (μ(I_v) + tan ψ, tan ψ) [-], tan ψ = K (φ − φ_eq(I_v)).

    ``iv`` viscous number [-], ``phi`` solid fraction [-]; parameters μ_s, μ_2, I_0, φ_c [-] and
    the dilatancy constant K = ``k_dil`` [-].

    >>> mu, tp = boyer_pailha(0.0, 0.585)
    >>> float(mu), float(tp)
    (0.425, 0.0)
    """
    tan_psi = k_dil * (np.asarray(phi, dtype=float) - phi_eq(iv, phi_c))
    return mu_iv(iv, mu_s, mu_2, i_0, phi_c) + tan_psi, tan_psi


def viscous_number(ratio: ArrayLike, phi: ArrayLike, mu_s: float = 0.425, mu_2: float = 0.765,
                   i_0: float = 0.004, phi_c: float = 0.585, k_dil: float = 4.09) -> np.ndarray:
    """I_v ≥ 0 [-] at which μ(I_v) + K (φ − φ_eq(I_v)) equals the stress ratio τ/P_s; 0 below yield.

    Solved for s = √I_v by Newton's method safeguarded by bisection on [0, s_hi], where
    s_hi² = τ/P_s − μ_s − K (φ − φ_c) bounds the root (every other term of the friction is ≥ 0
    in s), to round-off.

    >>> iv = viscous_number(0.6, 0.58)
    >>> round(float(boyer_pailha(iv, 0.58)[0]), 12)
    0.6
    >>> float(viscous_number(0.3, 0.58))
    0.0
    """
    r = np.asarray(ratio, dtype=float)
    phi = np.asarray(phi, dtype=float)
    r, phi = np.broadcast_arrays(r, phi)
    excess = r - mu_s - k_dil * (phi - phi_c)
    out = np.zeros(r.shape)
    act = excess > 0.0
    if not act.any():
        return out
    r, phi, excess = r[act], phi[act], excess[act]
    lo, hi = np.zeros(r.shape), np.sqrt(excess)
    s = 0.5 * hi
    a, b = mu_2 - mu_s, k_dil * phi_c
    for _ in range(200):
        s2 = s * s
        f = mu_s + a * s2 / (s2 + i_0) + s2 + 2.5 * phi_c * s + k_dil * phi - b / (1.0 + s) - r
        df = a * 2.0 * s * i_0 / (s2 + i_0) ** 2 + 2.0 * s + 2.5 * phi_c + b / (1.0 + s) ** 2
        lo = np.where(f < 0.0, s, lo)
        hi = np.where(f > 0.0, s, hi)
        new = s - f / df
        bad = (new <= lo) | (new >= hi)
        new = np.where(bad, 0.5 * (lo + hi), new)
        done = np.abs(new - s) <= 1e-15 * np.maximum(hi, 1e-300) + 1e-300
        s = new
        if done.all():
            break
    out[act] = s * s
    return out


@register("granular_rheology", "boyer_pailha_nonlocal",
          params={**RHEOLOGY_DEFAULTS, "amplitude": NONLOCAL_AMPLITUDE}, porosity_range=(0.35, 0.5),
          reference="Boyer et al. (2011); Pailha & Pouliquen (2009); nonlocal granular fluidity of Kamrin & Koval "
                    "(2012), A of Henann & Kamrin (2013)")
def nonlocal_shear_rate(ratio: ArrayLike, phi: ArrayLike, p_s: ArrayLike, dz: ArrayLike, eta_f: float, d: float,
                        amplitude: float = NONLOCAL_AMPLITUDE, mu_s: float = 0.425, mu_2: float = 0.765,
                        i_0: float = 0.004, phi_c: float = 0.585, k_dil: float = 4.09) -> np.ndarray:
    """Shear rate γ̇ [1/s] of the Boyer–Pailha law made nonlocal by the granular fluidity g = γ̇/μ.

    Kamrin & Koval (2012, *Phys. Rev. Lett.* 108, 178301) replace the local law γ̇ = μ g_loc(μ) by

        g = g_loc + ξ² ∂²g/∂z² ,   ξ = A d / √|μ − μ_y| ,

    on a column of cells (thicknesses ``dz`` [m], bottom first) with no flux of g through either end
    (∂g/∂z = 0). Here μ = τ/P_s is the stress ratio ``ratio`` [-], g_loc = γ̇_loc/μ with γ̇_loc =
    I_v P_s/η_f of the local law (:func:`viscous_number`), and μ_y = μ_s + K (φ − φ_c) the local
    yield friction, which takes the place of Kamrin & Koval's μ_s in ξ (the dilatant law's static
    friction). A flowing zone thus fluidises its neighbours over ξ, a few grain diameters ``d`` [m]:
    a shear band has a width of its own, and material below yield next to it creeps. A uniform
    state is unchanged (g = g_loc). ``amplitude`` A = 0 gives the local law. ``p_s`` [Pa], ``eta_f``
    [Pa·s]. Finite volumes, solved as one tridiagonal system.

    >>> r = nonlocal_shear_rate([0.6, 0.6], [0.58, 0.58], [30.0, 30.0], [1e-4, 1e-4], 0.096, 160e-6)
    >>> bool(np.allclose(r, viscous_number(0.6, 0.58) * 30.0 / 0.096, rtol=1e-12))
    True
    """
    from scipy.linalg import solve_banded

    ratio = np.asarray(ratio, dtype=float)
    phi = np.asarray(phi, dtype=float)
    p_s = np.asarray(p_s, dtype=float)
    dz = np.asarray(dz, dtype=float)
    local = viscous_number(ratio, phi, mu_s, mu_2, i_0, phi_c, k_dil) * p_s / eta_f
    if amplitude <= 0.0 or ratio.size < 2:
        return local
    g_loc = np.divide(local, ratio, out=np.zeros_like(local), where=ratio > 0.0)
    # 1/ξ², floored at |μ − μ_y| = 1e-12 so that the system stays regular where μ = μ_y everywhere
    c = np.maximum(np.abs(ratio - mu_s - k_dil * (phi - phi_c)), 1e-12) / (amplitude * d) ** 2
    w = 1.0 / (0.5 * (dz[1:] + dz[:-1]))  # face conductances
    ab = np.zeros((3, ratio.size))
    ab[1] = c * dz
    ab[1, :-1] += w
    ab[1, 1:] += w
    ab[0, 1:] = -w
    ab[2, :-1] = -w
    return ratio * solve_banded((1, 1), ab, c * dz * g_loc)


@register("permeability", "carman_kozeny", params={"constant": 180.0}, porosity_range=(0.3, 0.6),
          reference="Carman (1937); Kozeny (1927)")
def carman_kozeny(phi: ArrayLike, d: float, constant: float = 180.0) -> np.ndarray:
    """Carman–Kozeny permeability k = d² (1 − φ)³ / (C φ²) [m²], C = 180, d [m], φ solid fraction [-].

    >>> round(float(carman_kozeny(0.5, 1e-3)) * 1e9, 6)
    2.777778
    """
    phi = np.asarray(phi, dtype=float)
    return d * d * (1.0 - phi) ** 3 / (constant * phi * phi)
