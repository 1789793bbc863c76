r"""Terzaghi one-dimensional consolidation, and its c_v in the two-fluid model.

Exact solution
--------------
A layer of thickness H, drained at the top (z = 0, z depth [m]) and impervious
at the base (z = H), loaded instantly so the excess pore pressure is u0
throughout at t = 0⁺, obeys ∂u/∂t = c_v ∂²u/∂z², u(0, t) = 0, ∂u/∂z(H, t) = 0.
With ζ = z/H, T_v = c_v t/H² and M_m = π(2m + 1)/2:

    u/u0 = Σ_m (2/M_m) sin(M_m ζ) exp(−M_m² T_v)                     (Fourier)
    U(T_v) = 1 − Σ_m (2/M_m²) exp(−M_m² T_v)                         (average degree)

For small T_v the same solution is summed faster by images:

    u/u0 = 1 − Σ_m (−1)^m [erfc((2m + ζ)/(2√T_v)) + erfc((2m + 2 − ζ)/(2√T_v))]
    U = 2√(T_v/π) + 4√T_v Σ_{m≥1} (−1)^m ierfc(m/√T_v),  ierfc(x) = e^(−x²)/√π − x erfc(x)

so the classical T_v = (π/4)U² is U = 2√(T_v/π) with the image terms dropped.

Truncation. Fourier terms fall at least geometrically (ratio ≤ e^(−2π² T_v)),
so the tail after N terms is below (2/M_N) e^(−M_N² T_v)/(1 − e^(−2π² T_v)) for
u/u0 (2/M_N² … for U); the image series alternates with decreasing terms, so its
tail is below its first omitted term, ≤ 2 erfc(N/√T_v). N is chosen from these
bounds for an absolute error ``tol`` (default 1e-12); Fourier is used for
T_v ≥ 0.1 and images below (at most ~10 terms either way).

Two-fluid model (inertia and viscous terms dropped, y upward, V = 0 for an
impervious base; P = P_hyd + u with ∂P_hyd/∂y = −ρ_f g):

1. Liquid: 0 = −n ∂P/∂y − n ρ_f g − β (U_f − U_s) ⇒ −n ∂u/∂y = β (U_f − U_s), so
   the Darcy flux relative to the solids is q = n (U_f − U_s) = −(n²/β) ∂u/∂y
   = −(k/(ρ_f g)) ∂u/∂y with k = ρ_f g n²/β (docs/model.md, "Drag"): one n from the n∇P
   buoyancy form, one from turning the interstitial slip into a flux.
2. Mixture: ∂(P + P_s)/∂y = −ρ̄ g: total stress is fixed in time (small strain),
   so ∂u/∂t = −∂P_s/∂t.
3. Mass: V = q + U_s = 0 ⇒ U_s = −q. Solids: ∂n/∂t = (1 − n) ∂U_s/∂y (convective
   term U_s ∂n/∂y dropped). Compressive volumetric strain of the skeleton
   dε_v = −dn/(1 − n) (solid volume fixed: V_tot ∝ 1/(1 − n)), so ε̇_v = −∂U_s/∂y = ∂q/∂y.
4. P_s = p_ref exp[(1/A)(1 − (1 − n̄)/(1 − n))]: ∂P_s/∂n = −P_s (1 − n̄)/(A (1 − n)²),
   M = dP_s/dε_v = −(1 − n) ∂P_s/∂n = P_s (1 − n̄)/(A (1 − n)) > 0.

Then ∂u/∂t = −M ε̇_v = M ∂/∂y[(k/(ρ_f g)) ∂u/∂y], i.e. Terzaghi with

    c_v = k M/(ρ_f g) = n² M/β = n² P_s (1 − n̄)/(β A (1 − n))        [m²/s].

This is the soil-mechanics c_v = k/(m_v γ_w) exactly, provided k carries n²
(taking k = ρ_f g n/β, from the slip instead of the flux, would be a factor n
too small). The match needs uniform c_v: a surcharge large against the layer's
buoyant self-weight (M ∝ P_s varies with depth otherwise) and a load step small
against P_s (M and β depend on n).

References
----------
Terzaghi, K. (1943). *Theoretical Soil Mechanics*, Wiley, ch. XIII.
Carslaw, H. S., Jaeger, J. C. (1959). *Conduction of Heat in Solids*, 2nd ed.,
Oxford, §3.3 (Fourier and image series).
Verruijt, A. (2018). *An Introduction to Soil Mechanics*, Springer, ch. 15.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "time_factor", "excess_pressure_ratio", "average_degree",
    "time_factor_classical", "constrained_modulus", "consolidation_coefficient",
]

Array = NDArray[np.float64]
_T_SWITCH = 0.1  # below: image series; above: Fourier series


def erfc(x):
    """``scipy.special.erfc``, imported on first use: the liquefaction runner takes only
    :func:`consolidation_coefficient` from here, and ``scipy.special`` costs ~0.25 s to import."""
    from scipy.special import erfc as _erfc

    return _erfc(x)


def _ierfc(x: Array) -> Array:
    return np.exp(-x * x) / np.sqrt(np.pi) - x * erfc(x)


def _n_fourier(T: float, tol: float) -> int:
    r = np.exp(-2.0 * np.pi**2 * T)
    # 2/M <= 4/pi and 2/M**2 <= 8/pi**2 for all m, so one bound serves both series
    M_needed = np.sqrt(np.log(4.0 / (np.pi * tol * (1.0 - r))) / T)
    return max(1, int(np.ceil(M_needed / np.pi)))  # M_N >= M_needed when N >= M/pi


def _n_images(T: float, tol: float) -> int:
    N = 1
    while 2.0 * erfc(N / np.sqrt(T)) > tol:
        N += 1
    return N + 1


def time_factor(t: ArrayLike, c_v: float, H: float) -> Array:
    """Time factor T_v = c_v t / H² [-]; t [s], c_v [m²/s], H drainage path [m].

    >>> float(time_factor(100.0, 1e-3, 1.0))
    0.1
    """
    return c_v * np.asarray(t, dtype=float) / H**2


def excess_pressure_ratio(z: ArrayLike, t: ArrayLike, H: float, c_v: float,
                          tol: float = 1e-12) -> Array:
    """Excess pore pressure u/u0 [-] at depth z [m] below the drained top, time t [s].

    Broadcasts z and t. At t = 0 returns the initial state (1 inside, 0 at z = 0).
    Absolute truncation error < tol (module docstring).

    >>> u = excess_pressure_ratio(1.0, 0.848e3, 1.0, 1e-3)  # base, T_v = 0.848
    >>> round(float(u), 4), round(4 / np.pi * float(np.exp(-np.pi**2 / 4 * 0.848)), 4)  # 1 term
    (0.1571, 0.1571)
    """
    z, t = np.broadcast_arrays(np.asarray(z, float), np.asarray(t, float))
    zeta, T = z / H, time_factor(t, c_v, H)
    out = np.where(zeta > 0.0, 1.0, 0.0)
    big, small = T >= _T_SWITCH, (T > 0.0) & (T < _T_SWITCH)
    if np.any(big):
        zb, Tb, acc = zeta[big], T[big], np.zeros(np.count_nonzero(big))
        for m in range(_n_fourier(float(Tb.min()), tol)):
            M = np.pi * (2 * m + 1) / 2.0
            acc += 2.0 / M * np.sin(M * zb) * np.exp(-M * M * Tb)
        out[big] = acc
    if np.any(small):
        zs, rt = zeta[small], 2.0 * np.sqrt(T[small])
        acc = np.ones(np.count_nonzero(small))
        for m in range(_n_images(float(T[small].max()), tol)):
            acc -= (-1) ** m * (erfc((2 * m + zs) / rt) + erfc((2 * m + 2 - zs) / rt))
        out[small] = acc
    return out


def average_degree(T_v: ArrayLike, tol: float = 1e-12) -> Array:
    """Average degree of consolidation U(T_v) [-], absolute truncation error < tol.

    >>> round(float(average_degree(0.197)), 3), round(float(average_degree(0.848)), 3)
    (0.5, 0.9)
    """
    T = np.asarray(T_v, dtype=float)
    out = np.zeros(T.shape)
    big, small = T >= _T_SWITCH, (T > 0.0) & (T < _T_SWITCH)
    if np.any(big):
        Tb, acc = T[big], np.ones(np.count_nonzero(big))
        for m in range(_n_fourier(float(Tb.min()), tol)):
            M = np.pi * (2 * m + 1) / 2.0
            acc -= 2.0 / M**2 * np.exp(-M * M * Tb)
        out[big] = acc
    if np.any(small):
        Ts = T[small]
        acc = 2.0 * np.sqrt(Ts / np.pi)
        for m in range(1, _n_images(float(Ts.max()), tol)):
            acc += 4.0 * np.sqrt(Ts) * (-1) ** m * _ierfc(m / np.sqrt(Ts))
        out[small] = acc
    return out


def time_factor_classical(U: ArrayLike) -> Array:
    """Classical approximations T_v(U) [-] (Terzaghi 1943; Casagrande).

    T_v = (π/4) U² for U < 0.6, T_v = 1.781 − 0.933 log10(100 (1 − U)) above.

    >>> round(float(time_factor_classical(0.5)), 4), round(float(time_factor_classical(0.9)), 4)
    (0.1963, 0.848)
    """
    U = np.asarray(U, dtype=float)
    with np.errstate(divide="ignore"):
        late = 1.781 - 0.933 * np.log10(100.0 * (1.0 - U))
    return np.where(U < 0.6, np.pi / 4.0 * U**2, late)


def constrained_modulus(P_s: ArrayLike, n: ArrayLike, n_bar: ArrayLike,
                        A: float) -> Array:
    """Constrained (oedometric) modulus M = dP_s/dε_v = P_s (1 − n̄)/(A (1 − n)) [Pa].

    P_s granular pressure [Pa], n, n̄ porosity and reference porosity [-], A [-].

    >>> round(float(constrained_modulus(1e5, 0.4, 0.45, 0.015)), 1)
    6111111.1
    """
    return (np.asarray(P_s, float) * (1.0 - np.asarray(n_bar, float))
            / (A * (1.0 - np.asarray(n, float))))


def consolidation_coefficient(n: ArrayLike, n_bar: ArrayLike, P_s: ArrayLike,
                              A: float, beta: ArrayLike) -> Array:
    """Two-fluid-model c_v = n² M / β = k M/(ρ_f g) [m²/s] (derivation above).

    beta drag coefficient [N·s/m⁴]; other arguments as :func:`constrained_modulus`.

    >>> round(float(consolidation_coefficient(0.4, 0.45, 1e5, 0.015, 1e6)), 5)
    0.97778
    """
    n = np.asarray(n, float)
    return n**2 * constrained_modulus(P_s, n, n_bar, A) / np.asarray(beta, float)
