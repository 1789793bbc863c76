r"""Kynch (1952) kinematic-wave theory of a 1D fluidized bed or suspension.

Physics (y upward, n porosity, φ = 1 − n solids fraction)
---------------------------------------------------------
With inertia and granular pressure neglected the slip obeys Richardson–Zaki,
n (U_f − U_s) = U_t n^k, and the total volume flux j = n U_f + (1 − n) U_s is
uniform in y (∇·V = 0) and equal to the inlet superficial velocity (the
distributor holds the solids back). Hence U_s = j − U_t n^k and the solids
balance ∂φ/∂t + ∂F/∂y = 0 is a scalar conservation law with flux

    F(n; j) = (1 − n)(j − U_t n^k)                                 [m/s].

Wave speed (sign convention). Characteristics carry φ at speed dF/dφ; since
dφ = −dn, c = −dF/dn. Differentiating,
dF/dn = −(j − U_t n^k) − k U_t (1 − n) n^(k−1), so

    c(n; j) = j − U_t n^k + k U_t (1 − n) n^(k−1)                 [m/s],

which is Kynch's (1952) wave speed and the thesis's eq. 5.8 expanded
(w = [k n^(k−1) − (k+1) n^k] U_t + j). c is positive = upward.
dc/dn = k U_t n^(k−2) [(k − 1) − (k + 1) n] < 0 for n > n_i = (k − 1)/(k + 1),
the inflection porosity: above it F is convex in φ, denser states travel
faster, and the classical picture holds. Outside it the waves are compound and
the functions here raise ``ValueError``.

Shock (Rankine–Hugoniot): s = [F]/[φ] = (F_b − F_a)/(n_a − n_b).

Step change U0 → U1 of a steady bed (height H0, porosity n0, U0 = U_t n0^k;
n1 = (U1/U_t)^(1/k), H1 = H0 (1 − n0)/(1 − n1) by solids conservation). The
bottom state becomes n1 (U_s = 0 there), the initial state is n0, and the bed
surface (a shock against clear liquid, F(1) = 0) moves at U_s = j − U_t n^k of
the state just below it; all characteristics reach it from below, none reflect.

* Expansion (n1 > n0): c(n1) < c(n0), a centred rarefaction fan y = c(n) t.
  The slowest characteristic c(n1) = k U_t (1 − n1) n1^(k−1) (j = U_t n1^k) ends
  the transient when it meets the surface, which is then at rest at H1:
  t1 = H1 / (k U_t (1 − n1) n1^(k−1)). Fan front speeds:
  c(n0) (fastest, leading) and c(n1) (slowest, trailing); surface U1 − U0 until
  the leading characteristic arrives at t* = H0/(k U_t (1 − n0) n0^(k−1)).
  Afterwards, solids conservation over the fan (φ dc − dF = d(φ c − F) and
  φ c − F = k U_t φ² n^(k−1)) gives the surface parametrically in its porosity
  n_h: t = H0 (1 − n0) / (k U_t (1 − n_h)² n_h^(k−1)), h = c(n_h) t.
* Contraction (n1 < n0): a shock from the inlet at s = (1 − n0)(U0 − U1)/(n0 − n1)
  (F(n1) = 0); the surface falls at U0 − U1. They meet when s t = H0 − (U0 − U1) t,
  i.e. t1 = H0 (n0 − n1)/((1 − n1)(U0 − U1)) = (H0 − H1)/(U0 − U1).

Batch settling (j = 0): the top interface is the shock n0 | 1, speed
F(n0)/(1 − n0) = −U_t n0^k (falls at U_t n0^k). A deposit at rest (n_d, solids
flux zero, carried by P_s not by drag) grows by the shock n_d | n0 at
s = (1 − n0) U_t n0^k / (n0 − n_d) upward.

References
----------
Kynch, G. J. (1952). A theory of sedimentation. Trans. Faraday Soc. 48, 166–176.
Slis, P. L., Willemse, Th. W., Kramers, H. (1959). The response of the level of a
liquid fluidized bed to a sudden change in the fluidizing velocity. Appl. Sci.
Res. A 8, 209–218.
Richardson, J. F., Zaki, W. N. (1954). Sedimentation and fluidisation: part I.
Trans. Inst. Chem. Eng. 32, 35–53.
Pringle (2001), thesis section 5.1.2, eqs. 5.1–5.8.
"""

from __future__ import annotations

from typing import Callable, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "stokes_terminal_velocity", "richardson_zaki_n", "solids_flux", "wave_speed",
    "shock_speed", "StepChangeFronts", "step_change_fronts", "step_change_t1",
    "bed_height", "step_change_profile", "batch_settling_speeds", "step_change_t1_law",
]

Array = NDArray[np.float64]


def stokes_terminal_velocity(d: ArrayLike, rho_s: ArrayLike, rho_f: ArrayLike,
                             mu_f: ArrayLike, g: float = 9.81) -> Array:
    """Stokes terminal velocity U_t = (ρ_s − ρ_f) g d² / (18 μ_f) [m/s].

    Valid for particle Reynolds number ρ_f U_t d/μ_f ≲ 0.2.
    Parameters: d [m], rho_s, rho_f [kg/m³], mu_f [Pa·s], g [m/s²].

    Examples
    --------
    >>> round(float(stokes_terminal_velocity(1e-4, 2650.0, 1000.0, 1e-3)), 8)
    0.0089925

    Reference: Stokes, G. G. (1851). Trans. Camb. Phil. Soc. 9, 8–106.
    """
    d = np.asarray(d, dtype=float)
    return (np.asarray(rho_s) - np.asarray(rho_f)) * g * d**2 / (18.0 * np.asarray(mu_f))


def richardson_zaki_n(U: ArrayLike, U_t: float, k: float) -> Array:
    """Porosity of a steady fluidized bed, n = (U/U_t)^(1/k) [-].

    U superficial velocity [m/s], U_t terminal velocity [m/s], k exponent [-].

    >>> float(richardson_zaki_n(0.25, 1.0, 2.0))
    0.5

    Reference: Richardson & Zaki (1954).
    """
    return (np.asarray(U, dtype=float) / U_t) ** (1.0 / k)


def solids_flux(n: ArrayLike, j: ArrayLike, U_t: float, k: float) -> Array:
    """Solids volume flux F = (1 − n)(j − U_t n^k) [m/s], positive upward.

    >>> float(solids_flux(0.5, 0.0, 1.0, 2.0))
    -0.125
    """
    n = np.asarray(n, dtype=float)
    return (1.0 - n) * (np.asarray(j, dtype=float) - U_t * n**k)


def wave_speed(n: ArrayLike, j: ArrayLike, U_t: float, k: float) -> Array:
    """Kinematic-wave speed c = dF/d(1 − n) = j − U_t n^k + k U_t (1 − n) n^(k−1) [m/s].

    >>> float(wave_speed(0.5, 0.0, 1.0, 2.0))  # -0.25 + 2*0.5*0.5
    0.25
    """
    n = np.asarray(n, dtype=float)
    return np.asarray(j, dtype=float) - U_t * n**k + k * U_t * (1.0 - n) * n ** (k - 1.0)


def shock_speed(n_a: ArrayLike, n_b: ArrayLike, j: ArrayLike, U_t: float,
                k: float) -> Array:
    """Rankine–Hugoniot speed s = (F(n_b) − F(n_a)) / (n_a − n_b) [m/s].

    Symmetric in (n_a, n_b); where the states coincide (|n_a − n_b| < 1e-12) the
    limit c(n_a) is returned.

    >>> float(shock_speed(0.5, 1.0, 0.0, 1.0, 2.0))  # top of a settling suspension
    -0.25
    """
    n_a, n_b = np.broadcast_arrays(np.asarray(n_a, float), np.asarray(n_b, float))
    dn = n_a - n_b
    same = np.abs(dn) < 1e-12
    safe = np.where(same, 1.0, dn)
    s = (solids_flux(n_b, j, U_t, k) - solids_flux(n_a, j, U_t, k)) / safe
    return np.where(same, wave_speed(n_a, j, U_t, k), s)


def _check_convex(n: ArrayLike, k: float) -> None:
    n_i = (k - 1.0) / (k + 1.0)
    if np.any(np.asarray(n) <= n_i) or np.any(np.asarray(n) >= 1.0):
        raise ValueError(f"porosities must lie in ({n_i:.4f}, 1) for k = {k}: "
                         "outside, F is not convex in 1 − n and the waves are compound")


def _invert_decreasing(f: Callable[[Array], Array], target: ArrayLike,
                       lo: float, hi: float, iters: int = 60) -> Array:
    """Vectorised bisection for f(x) = target with f decreasing on [lo, hi]."""
    target = np.asarray(target, dtype=float)
    a, b = np.full(target.shape, lo), np.full(target.shape, hi)
    for _ in range(iters):  # 60 halvings: interval < 1e-18 of its width
        mid = 0.5 * (a + b)
        above = f(mid) > target
        a, b = np.where(above, mid, a), np.where(above, b, mid)
    return 0.5 * (a + b)


class StepChangeFronts(NamedTuple):
    """Front speeds [m/s] of a step change, upward positive.

    ``slow``/``fast``: trailing/leading edge of the fan (equal to the shock speed
    for a contraction); ``surface``: initial speed of the bed surface, U1 − U0.
    """

    slow: Array
    fast: Array
    surface: Array


def step_change_fronts(n0: ArrayLike, n1: ArrayLike, U_t: float,
                       k: float) -> StepChangeFronts:
    """Front speeds after a step U_t n0^k → U_t n1^k of the inlet velocity.

    >>> f = step_change_fronts(0.5, 0.6, 1.0, 2.0)  # expansion
    >>> round(float(f.slow), 6), round(float(f.fast), 6), round(float(f.surface), 6)
    (0.48, 0.61, 0.11)
    """
    _check_convex([n0, n1], k)
    n0, n1 = np.broadcast_arrays(np.asarray(n0, float), np.asarray(n1, float))
    j = U_t * n1**k
    expansion = n1 > n0
    s = shock_speed(n0, n1, j, U_t, k)
    slow = np.where(expansion, wave_speed(n1, j, U_t, k), s)
    fast = np.where(expansion, wave_speed(n0, j, U_t, k), s)
    return StepChangeFronts(slow, fast, j - U_t * n0**k)


def step_change_t1(n0: ArrayLike, n1: ArrayLike, H0: ArrayLike, U_t: float,
                   k: float) -> Array:
    """Time t1 [s] to the new steady state after a step change (module docstring).

    Expansion: t1 = H1/(k U_t (1 − n1) n1^(k−1)); contraction:
    t1 = (H0 − H1)/(U0 − U1); H1 = H0 (1 − n0)/(1 − n1); H0 [m].

    >>> round(float(step_change_t1(0.5, 0.6, 1.0, 1.0, 2.0)), 6)  # H1/c(n1) = 1.25/0.48
    2.604167
    >>> round(float(step_change_t1(0.6, 0.5, 1.0, 1.0, 2.0)), 6)  # (1 - 0.8)/0.11
    1.818182
    """
    _check_convex([n0, n1], k)
    n0, n1 = np.asarray(n0, float), np.asarray(n1, float)
    H0 = np.asarray(H0, float)
    H1 = H0 * (1.0 - n0) / (1.0 - n1)
    U0, U1 = U_t * n0**k, U_t * n1**k
    t_exp = H1 / (k * U_t * (1.0 - n1) * n1 ** (k - 1.0))
    with np.errstate(divide="ignore", invalid="ignore"):
        t_con = (H0 - H1) / (U0 - U1)
    return np.where(n1 > n0, t_exp, np.where(n1 == n0, 0.0, t_con))


def bed_height(t: ArrayLike, n0: float, n1: float, H0: float, U_t: float,
               k: float) -> Array:
    """Height h(t) [m] of the bed surface after the step change at t = 0 [s].

    >>> bool(np.isclose(bed_height(10.0, 0.5, 0.6, 1.0, 1.0, 2.0), 1.25))
    True
    """
    _check_convex([n0, n1], k)
    t = np.asarray(t, dtype=float)
    H1 = H0 * (1.0 - n0) / (1.0 - n1)
    U0, U1 = U_t * n0**k, U_t * n1**k
    t1 = float(step_change_t1(n0, n1, H0, U_t, k))
    linear = H0 + (U1 - U0) * np.minimum(t, t1)
    if n1 <= n0:
        return linear
    t_star = H0 / (k * U_t * (1.0 - n0) * n0 ** (k - 1.0))
    g = lambda n: k * U_t * (1.0 - n) ** 2 * n ** (k - 1.0)  # noqa: E731
    tc = np.clip(t, t_star, t1)
    n_h = _invert_decreasing(g, H0 * (1.0 - n0) / tc, n0, n1)
    h_fan = wave_speed(n_h, U1, U_t, k) * tc
    return np.where(t < t_star, linear, np.where(t >= t1, H1, h_fan))


def step_change_profile(y: ArrayLike, t: ArrayLike, n0: float, n1: float,
                        H0: float, U_t: float, k: float) -> Array:
    """Exact porosity n(y, t) [-] after the step change; y [m] ≥ 0, t [s] ≥ 0.

    n1 below the lowest front, n0 above the leading one, the self-similar fan
    c(n; U1) = y/t between them (expansion), clear liquid (n = 1) above the
    surface. y and t broadcast.

    >>> n = step_change_profile([0.1, 0.7, 1.2], 1.0, 0.5, 0.6, 1.0, 1.0, 2.0)
    >>> [round(float(v), 4) for v in n]
    [0.6, 0.5, 1.0]
    """
    y, t = np.broadcast_arrays(np.asarray(y, float), np.asarray(t, float))
    fr = step_change_fronts(n0, n1, U_t, k)
    h = bed_height(t, n0, n1, H0, U_t, k)
    U1 = U_t * n1**k
    ratio = np.divide(y, t, out=np.full(y.shape, np.inf), where=t > 0)
    if n1 > n0:
        inside = np.where(ratio <= fr.slow, n1, n0)
        in_fan = (ratio > fr.slow) & (ratio < fr.fast) & (y < h)
        inside[in_fan] = _invert_decreasing(lambda n: wave_speed(n, U1, U_t, k),
                                            ratio[in_fan], n0, n1)
    else:
        inside = np.where(ratio < fr.slow, n1, n0)
    return np.where(y >= h, 1.0, inside)


def batch_settling_speeds(n0: ArrayLike, n_d: ArrayLike, U_t: float,
                          k: float) -> tuple[Array, Array]:
    """Batch settling (j = 0): (descent speed of the top, rise speed of the deposit) [m/s].

    Top: U_t n0^k. Deposit surface (n_d at rest): (1 − n0) U_t n0^k / (n0 − n_d).

    >>> top, rise = batch_settling_speeds(0.9, 0.5, 1.0, 4.65)
    >>> round(float(top), 4), round(float(rise), 4)  # 0.9**4.65, 0.1*0.6127/0.4
    (0.6127, 0.1532)
    """
    _check_convex(n0, k)
    n0, n_d = np.asarray(n0, float), np.asarray(n_d, float)
    if np.any(n_d >= n0):
        raise ValueError("deposit porosity n_d must be below the suspension's n0")
    top = U_t * n0**k
    rise = (1.0 - n0) * top / (n0 - n_d)
    if np.any(rise < wave_speed(n0, 0.0, U_t, k)):
        raise ValueError("c(n0) exceeds the deposit-shock speed: Kynch rarefaction "
                         "above the deposit, not a single shock")
    return top, rise


def step_change_t1_law(n0: float, n1: float, H0: float, u_eq: Callable[[float], float],
                       dn: float = 1e-6) -> float:
    """t1 [s] of a step change n0 → n1 with a general equilibrium law U = u_eq(n) [m/s] in place of
    Richardson–Zaki: Kynch's theory with the flux F = (1 − n)(j − u_eq(n)).

    Expansion: t1 = H1/c(n1), c(n1) = (1 − n1) u_eq'(n1) (central difference of step ``dn``);
    contraction: t1 = (H0 − H1)/(u_eq(n0) − u_eq(n1)); H1 = H0 (1 − n0)/(1 − n1), H0 [m]. As for
    :func:`step_change_t1`, the states are taken to lie where F is convex (a single fan or shock).
    With u_eq = U_t n^k it is :func:`step_change_t1`:

    >>> rz = lambda n: 1.0 * n**2.0
    >>> round(step_change_t1_law(0.5, 0.6, 1.0, rz), 5), round(step_change_t1_law(0.6, 0.5, 1.0, rz), 5)
    (2.60417, 1.81818)
    """
    H1 = H0 * (1.0 - n0) / (1.0 - n1)
    if n1 > n0:
        c = (1.0 - n1) * (u_eq(n1 + dn) - u_eq(n1 - dn)) / (2.0 * dn)
        return H1 / c
    if n1 == n0:
        return 0.0
    return (H0 - H1) / (u_eq(n0) - u_eq(n1))
