"""Exact steady (and start-up) flows of a layer on an infinite slope, to verify the column on a slope.

A layer of thickness h [m] (measured normal to the bed) on a bed inclined at α, no slip at the
bed (z = 0), a stress-free surface (z = h), fully developed: the momentum balance along the
slope reduces to

    dτ/dz = −ρ g sin α,   τ(h) = 0   ⇒   τ(z) = ρ g sin α (h − z)      [Pa],

with ρ [kg/m³] the density whose weight the layer carries in shear (the mixture density of a
saturated layer with a free surface; its buoyant density under still water) and z [m] the
distance from the bed. The shear stress is linear, largest at the bed, τ_b = ρ g h sin α.

(a) **Newtonian film** (viscosity μ [Pa s], τ = μ du/dz; Bird, Stewart & Lightfoot 2002, §2.2):

    u(z) = ρ g sin α (h z − z²/2)/μ,   u_s = ρ g sin α h²/(2μ),   q = ρ g sin α h³/(3μ).

(b) **Bingham layer** (yield stress τ_y [Pa], plastic viscosity μ_p [Pa s]; τ = τ_y + μ_p du/dz
where sheared; Liu & Mei 1989). The material shears only where τ > τ_y, that is below

    z_p = h − τ_y/(ρ g sin α)                        (the base of the plug) [m];

    u(z) = ρ g sin α (z_p z − z²/2)/μ_p              0 ≤ z ≤ z_p   (sheared layer)
    u(z) = u_p = ρ g sin α z_p²/(2μ_p)               z_p ≤ z ≤ h   (rigid plug)
    q    = ρ g sin α z_p² (3h − z_p)/(6μ_p)           flux per unit width [m²/s].

   No flow (u ≡ 0) when τ_y ≥ ρ g h sin α (z_p ≤ 0). As τ_y → 0, z_p → h and (b) becomes (a).

(c) **Start-up of the Newtonian film from rest** (the same problem with ∂u/∂t = ν ∂²u/∂z² +
g sin α, ν = μ/ρ, u(z, 0) = 0), by separation of variables with the eigenfunctions sin(λ_n z),
λ_n = (2n − 1)π/(2h), of the no-slip bed and the stress-free surface:

    u(z, t) = (g sin α/ν) [h z − z²/2 − (2/h) Σ_n sin(λ_n z) exp(−ν λ_n² t)/λ_n³],

   using ∫₀^h (h z − z²/2) sin(λ_n z) dz = 1/λ_n³. The slowest mode decays as
   exp(−π² ν t/(4h²)): the steady state (a) is reached to 1e-6 after t ≈ 5.6 h²/ν.

All functions are pure NumPy, angles in radians (α = atan(S/100) for a slope S in per cent).

References
----------
Bird, R. B., Stewart, W. E. & Lightfoot, E. N. (2002). Transport Phenomena, 2nd ed. Wiley, §2.2
(flow of a falling film).
Liu, K. F. & Mei, C. C. (1989). Slow spreading of a sheet of Bingham fluid on an inclined plane.
J. Fluid Mech. 207, 505–529.
"""
from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from twofluid.casefile.schema import CaseError

__all__ = ["G", "film_flow_velocity", "film_flow_surface_velocity", "film_flow_flux",
           "film_flow_startup", "bingham_plug_base", "bingham_slope_velocity",
           "bingham_plug_velocity", "bingham_slope_flux"]

G = 9.80665  # standard gravity [m/s²]
SOURCE = "slope_flow"


def _positive(name: str, value) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise CaseError(SOURCE, name, f"must be one number > 0, got {value!r}") from None
    if not (math.isfinite(v) and v > 0.0):
        raise CaseError(SOURCE, name, f"must be finite and > 0, got {v!r}")
    return v


def _angle(alpha_rad) -> float:
    try:
        a = float(alpha_rad)
    except (TypeError, ValueError):
        raise CaseError(SOURCE, "alpha_rad", f"must be one number in [0, pi/2], got {alpha_rad!r}") from None
    if not (math.isfinite(a) and 0.0 <= a <= 0.5 * math.pi):
        raise CaseError(SOURCE, "alpha_rad", f"must be in [0, pi/2] rad (atan(S/100) for S in %), got {a!r}")
    return a


def _heights(z_m, h: float) -> NDArray:
    z = np.asarray(z_m, dtype=float)
    if not np.all(np.isfinite(z)) or np.any(z < 0.0) or np.any(z > h * (1.0 + 1e-12)):
        raise CaseError(SOURCE, "z_m", f"must lie in [0, h] = [0, {h:g}] m (height above the bed)")
    return z


def film_flow_velocity(z_m: ArrayLike, h_m: float, rho: float, mu: float, alpha_rad: float,
                       g: float = G) -> NDArray:
    """Velocity u(z) = ρ g sin α (h z − z²/2)/μ [m/s] of a Newtonian film on a slope (module (a)).

    Parameters
    ----------
    z_m : array_like
        Height above the bed [m], 0 ≤ z ≤ h.
    h_m : float
        Layer thickness normal to the bed [m], > 0.
    rho : float
        Density whose weight drives [kg/m³], > 0.
    mu : float
        Viscosity [Pa s], > 0.
    alpha_rad : float
        Bed inclination α [rad], in [0, π/2].
    g : float
        Gravity [m/s²].

    Examples
    --------
    ρ = 2000 kg/m³, μ = 1000 Pa s, h = 2 m, sin α = 0.02 (g = 9.80665): ρ g sin α/μ = 0.392266 s⁻¹ m⁻¹;
    at the surface (h²/2 = 2) u = 0.784532 m/s, at mid-height (1.5) 0.588399 m/s:

    >>> a = math.asin(0.02)
    >>> [round(float(u), 6) for u in film_flow_velocity([0.0, 1.0, 2.0], 2.0, 2000.0, 1000.0, a)]
    [0.0, 0.588399, 0.784532]
    """
    h = _positive("h_m", h_m)
    k = _positive("rho", rho) * _positive("g", g) * math.sin(_angle(alpha_rad)) / _positive("mu", mu)
    z = _heights(z_m, h)
    return k * (h * z - 0.5 * z * z)


def film_flow_surface_velocity(h_m: float, rho: float, mu: float, alpha_rad: float, g: float = G) -> float:
    """Surface velocity u_s = ρ g sin α h²/(2μ) [m/s] of the Newtonian film (module (a)).

    >>> round(film_flow_surface_velocity(2.0, 2000.0, 1000.0, math.asin(0.02)), 6)
    0.784532
    """
    return float(film_flow_velocity(h_m, h_m, rho, mu, alpha_rad, g))


def film_flow_flux(h_m: float, rho: float, mu: float, alpha_rad: float, g: float = G) -> float:
    """Flux per unit width q = ∫₀^h u dz = ρ g sin α h³/(3μ) [m²/s] of the Newtonian film.

    The mean velocity q/h is 2/3 of the surface velocity.

    >>> round(film_flow_flux(2.0, 2000.0, 1000.0, math.asin(0.02)), 6)    # 0.392266 * 8/3
    1.046043
    """
    h = _positive("h_m", h_m)
    k = _positive("rho", rho) * _positive("g", g) * math.sin(_angle(alpha_rad)) / _positive("mu", mu)
    return k * h ** 3 / 3.0


def film_flow_startup(z_m: ArrayLike, t_s: float, h_m: float, rho: float, mu: float, alpha_rad: float,
                      g: float = G, n_terms: int | None = None) -> NDArray:
    """Velocity u(z, t) [m/s] of the Newtonian film started from rest at t = 0 (module (c)).

    ``n_terms`` terms of the series (default: enough for the truncation to stay below 5e-10 of
    the surface velocity at t = 0, where it converges slowest, as 1/n³); t [s] ≥ 0.

    >>> a = math.asin(0.02)
    >>> float(np.max(np.abs(film_flow_startup([0.5, 1.0, 2.0], 0.0, 2.0, 2000.0, 1000.0, a)))) < 5e-10
    True
    >>> u = film_flow_startup([1.0, 2.0], 1e4, 2.0, 2000.0, 1000.0, a)      # t >> h²/ν = 8 s
    >>> bool(np.allclose(u, film_flow_velocity([1.0, 2.0], 2.0, 2000.0, 1000.0, a), rtol=1e-14))
    True
    """
    h = _positive("h_m", h_m)
    r = _positive("rho", rho)
    nu = _positive("mu", mu) / r
    gs = _positive("g", g) * math.sin(_angle(alpha_rad))
    t = float(t_s)
    if not (math.isfinite(t) and t >= 0.0):
        raise CaseError(SOURCE, "t_s", f"must be finite and >= 0 s, got {t_s!r}")
    z = _heights(z_m, h)
    if n_terms is None:
        # truncation at t = 0: |tail| <= 8/(pi^3 (2N - 1)^2) u_s, <= 5e-10 u_s for N = 12 000;
        # for t > 0 the modes with nu lambda_n^2 t > 40 are below e^-40 of their size and dropped
        n_terms = 12_000 if t == 0.0 else min(12_000, int(h / math.pi * math.sqrt(40.0 / (nu * t))) + 2)
    n = np.arange(1, int(n_terms) + 1)
    lam = (2 * n - 1) * math.pi / (2.0 * h)
    coef = np.exp(-nu * lam * lam * t) / lam ** 3
    zf = np.atleast_1d(z).ravel()
    series = np.empty_like(zf)
    for i in range(0, zf.size, 256):              # blocks of heights: bounded memory
        series[i:i + 256] = np.sin(np.multiply.outer(zf[i:i + 256], lam)) @ coef
    u = gs / nu * (h * zf - 0.5 * zf * zf - 2.0 / h * series)
    return u.reshape(np.shape(z))


def bingham_plug_base(h_m: float, rho: float, tau_y: float, alpha_rad: float, g: float = G) -> float:
    """Height of the plug's base z_p = h − τ_y/(ρ g sin α) [m] of a Bingham layer (module (b)).

    z_p ≤ 0: the bed shear stress ρ g h sin α does not exceed τ_y and the layer does not flow
    (returned as is, negative or zero). τ_y [Pa] ≥ 0; z_p = h for τ_y = 0.

    ρ g sin α = 392.266 Pa/m for ρ = 2000, sin α = 0.02; τ_y = 392.266 Pa gives z_p = h − 1:

    >>> round(bingham_plug_base(2.0, 2000.0, 392.266, math.asin(0.02)), 6)
    1.0
    """
    h = _positive("h_m", h_m)
    ty = float(tau_y)
    if not (math.isfinite(ty) and ty >= 0.0):
        raise CaseError(SOURCE, "tau_y", f"must be finite and >= 0 Pa, got {tau_y!r}")
    drive = _positive("rho", rho) * _positive("g", g) * math.sin(_angle(alpha_rad))
    if drive == 0.0:
        return -math.inf if ty > 0.0 else h
    return h - ty / drive


def bingham_slope_velocity(z_m: ArrayLike, h_m: float, rho: float, mu_p: float, tau_y: float,
                           alpha_rad: float, g: float = G) -> NDArray:
    """Velocity u(z) [m/s] of a Bingham layer on a slope: sheared below z_p, a plug above (module (b)).

    Parameters as :func:`film_flow_velocity`, with μ_p [Pa s] > 0 the plastic viscosity and
    τ_y [Pa] ≥ 0 the yield stress. Zero everywhere when τ_y ≥ ρ g h sin α.

    Examples
    --------
    ρ g sin α/μ_p = 0.392266 (as in :func:`film_flow_velocity`), h = 2 m, τ_y = 392.266 Pa:
    z_p = 1 m, plug velocity 0.392266/2 = 0.196133 m/s, u(0.5) = 0.392266 · 0.375 = 0.1471:

    >>> a = math.asin(0.02)
    >>> [round(float(u), 6) for u in bingham_slope_velocity([0.0, 0.5, 1.0, 2.0], 2.0, 2000.0, 1000.0, 392.266, a)]
    [0.0, 0.1471, 0.196133, 0.196133]
    >>> float(np.max(bingham_slope_velocity([1.0, 2.0], 2.0, 2000.0, 1000.0, 800.0, a)))   # τ_y > τ_b
    0.0
    """
    h = _positive("h_m", h_m)
    zp = bingham_plug_base(h, rho, tau_y, alpha_rad, g)
    k = _positive("rho", rho) * _positive("g", g) * math.sin(_angle(alpha_rad)) / _positive("mu_p", mu_p)
    z = _heights(z_m, h)
    if zp <= 0.0:
        return np.zeros_like(z)
    zc = np.minimum(z, zp)
    return k * (zp * zc - 0.5 * zc * zc)


def bingham_plug_velocity(h_m: float, rho: float, mu_p: float, tau_y: float, alpha_rad: float,
                          g: float = G) -> float:
    """Plug velocity u_p = ρ g sin α z_p²/(2μ_p) [m/s] (0 when the layer does not flow).

    >>> round(bingham_plug_velocity(2.0, 2000.0, 1000.0, 392.266, math.asin(0.02)), 6)
    0.196133
    """
    return float(bingham_slope_velocity(h_m, h_m, rho, mu_p, tau_y, alpha_rad, g))


def bingham_slope_flux(h_m: float, rho: float, mu_p: float, tau_y: float, alpha_rad: float,
                       g: float = G) -> float:
    """Flux per unit width q = ρ g sin α z_p² (3h − z_p)/(6μ_p) [m²/s] of the Bingham layer.

    τ_y = 0 gives the Newtonian ρ g sin α h³/(3μ); 0 when the layer does not flow.

    >>> round(bingham_slope_flux(2.0, 2000.0, 1000.0, 392.266, math.asin(0.02)), 6)  # 0.392266 * 5/6
    0.326888
    """
    h = _positive("h_m", h_m)
    zp = bingham_plug_base(h, rho, tau_y, alpha_rad, g)
    if zp <= 0.0:
        return 0.0
    k = _positive("rho", rho) * _positive("g", g) * math.sin(_angle(alpha_rad)) / _positive("mu_p", mu_p)
    return k * zp * zp * (3.0 * h - zp) / 6.0
