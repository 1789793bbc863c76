"""Hysteretic backbones of sand: GQ/H and MKZ, their Masing damping, and the MRDF reduction.

A backbone is written normalised, T(x) = τ/τ_ref against x = γ/γ_r, so that it does not change
with the effective stress: only the scales do. With γ_r = τ_max/G_max (GQ/H), τ_max ∝ P_s and
G_max ∝ P_s^0.5, the reference strain γ_r ∝ P_s^0.5 and τ = τ_max T(γ/γ_r). Reversal points
stored as (x, T) stay on the shrunken backbone when P_s falls.

- **GQ/H** (Groholski et al. 2016), τ_ref = τ_max, γ_r = τ_max/G_max:

      T(x) = [1 + x − √((1 + x)² − 4 θ_τ x)] / (2 θ_τ) = 2x / (1 + x + √((1 + x)² − 4 θ_τ x)),
      θ_τ(x) = θ1 + θ2 θ4 x^θ5 / (θ3^θ5 + θ4 x^θ5)      (θ_τ ≤ 1 for all x),

  T → x for small x (initial slope G_max) and T → 1 for large x (the strength τ_max); θ_τ = 0 is
  the hyperbola x/(1 + x), θ_τ = 1 elastic–perfectly plastic. The second form is used: it has no
  0/0 at θ_τ = 0. G/G_max = T/x = 2/(1 + x + √(…)).
- **MKZ** (modified Kondner–Zelasko; Matasovic & Vucetic 1993), τ_ref = G_max γ_r:

      T(x) = x / (1 + β x^s),   G/G_max = 1/(1 + β x^s).

  Its strength is unbounded for s < 1: use it where τ_max is not needed or fit GQ/H.
- **Masing damping** of a backbone at amplitude x_m (Masing loop: branches 2 T((x ∓ x_rev)/2)):
  loop area 8 ∫₀^{x_m} g(u) du with g = T(u) − (T_m/x_m) u, so D = 4 ∫₀^{x_m} g du / (π T_m x_m).
- **MRDF** (Phillips & Hashash 2009): the unload–reload branch from a reversal (x_rev, T_rev),

      T = F(γ_m) [2 T((x − x_rev)/2) − S_m (x − x_rev)] + S_m (x − x_rev) + T_rev,
      F(γ_m) = p1 − p2 (1 − G(γ_m)/G_max)^p3,

  S_m = T(x_m)/x_m the normalised secant at the largest strain x_m: the loop closes at ±x_m and its
  damping is F(γ_m) times the Masing damping.

The per-point functions (``gqh_*``, ``mkz_*``, ``mrdf_factor``) take and return floats, use only
arithmetic, ``abs`` and ``**``, and compile with ``numba.njit`` unchanged; a compiled kernel
that calls them must compile the functions in ``SCALAR_HELPERS`` with it (the ``helpers`` of
:func:`twofluid.compiled.group`). The ``_core`` functions take x ≥ 0 as a float or an array;
the NumPy wrappers (:func:`gqh_backbone`, :func:`gqh_modulus_reduction`,
:func:`masing_damping`, ...) are for users and fitting.

>>> round(gqh_ratio(1.0, 0.0, 0.0, 1.0, 1.0, 1.0), 12)      # θ = 0: the hyperbola, 1/(1 + 1)
0.5

References
----------
Groholski, D. R., Hashash, Y. M. A., Kim, B., Musgrove, M. & Olson, S. M. (2016). Simplified
model for small-strain nonlinearity and strength in 1D seismic site response analysis.
J. Geotech. Geoenviron. Eng. 142(9), 04016042.
Matasovic, N. & Vucetic, M. (1993). Cyclic characterization of liquefiable sands.
J. Geotech. Eng. 119(11), 1805–1822.
Phillips, C. & Hashash, Y. M. A. (2009). Damping formulation for nonlinear 1D site response
analyses. Soil Dyn. Earthq. Eng. 29(7), 1143–1158.
"""
from __future__ import annotations

import numpy as np

__all__ = ["gqh_core", "gqh_core_c", "gqh_core_slope_c", "gqh_slope_w", "gqh_slope_core", "gqh_ratio", "gqh_slope", "gqh_stress", "gqh_tangent",
           "gqh_branch_ratio", "gqh_branch_slope", "mkz_core", "mkz_slope_core", "mkz_ratio",
           "mkz_slope", "mkz_stress", "mkz_tangent", "mrdf_factor", "gqh_backbone",
           "gqh_modulus_reduction", "mkz_modulus_reduction", "masing_damping", "gqh_masing_damping",
           "mkz_masing_damping", "SCALAR_HELPERS"]


# ---- per point: floats in, floats out (arithmetic only; numba.njit compiles them) -------------

def gqh_core(x, t1, t2, t3, t4, t5):
    """GQ/H backbone T = τ/τ_max at x = γ/γ_r ≥ 0 (float or array) [-]; θ_τ(x) ≤ 1 required.

    >>> round(gqh_core(1.0, 1.0, 0.0, 1.0, 1.0, 1.0), 12)     # θ = 1: min(x, 1)
    1.0
    """
    return gqh_core_c(x, t1, t2, t3 ** t5, t4, t5)


def gqh_core_c(x, t1, t2, c3, t4, t5):
    """:func:`gqh_core` with ``c3`` = θ3^θ5 given: a kernel that evaluates one element's backbone
    many times computes that power once (the same number, so the same result to the bit).

    >>> gqh_core_c(1.0, 0.0, 0.0, 1.0, 1.0, 1.0) == gqh_core(1.0, 0.0, 0.0, 1.0, 1.0, 1.0)
    True
    """
    w = t4 * x ** t5
    th = t1 + t2 * w / (c3 + w)
    r = ((1.0 + x) * (1.0 + x) - 4.0 * th * x) ** 0.5
    return 2.0 * x / (1.0 + x + r)


def gqh_core_slope_c(x, t1, t2, c3, t4, t5):
    """(T, dT/dx) of the GQ/H backbone at x > 0 in one pass (one power, one root), ``c3`` = θ3^θ5:
    T to the bit as :func:`gqh_core_c` gives it, dT/dx as :func:`gqh_slope_core` (the mean of the
    two sides, 1/2, at the kink R = 0 of the elastic–perfectly plastic limit θ_τ = 1, x = 1).

    >>> t, k = gqh_core_slope_c(2.0, -2.0, 2.5, 0.5 ** 1.2, 1.0, 1.2)
    >>> t == gqh_core(2.0, -2.0, 2.5, 0.5, 1.0, 1.2), abs(k - gqh_slope_core(2.0, -2.0, 2.5, 0.5, 1.0, 1.2)) < 1e-15
    (True, True)
    """
    return gqh_slope_w(x, t4 * x ** t5, t1, t2, c3, t5)


def gqh_slope_w(x, w, t1, t2, c3, t5):
    """:func:`gqh_core_slope_c` from w = θ4 x^θ5 given: (T, dT/dx) at x > 0 [-]. The power is the
    costly part; where T is needed at x and x/2 (a Masing/MRDF branch), w(x/2) = w(x) 2^−θ5.

    >>> gqh_slope_w(2.0, 2.0, -2.0, 2.5, 1.0, 1.0) == gqh_core_slope_c(2.0, -2.0, 2.5, 1.0, 1.0, 1.0)
    True
    """
    th = t1 + t2 * w / (c3 + w)
    r = ((1.0 + x) * (1.0 + x) - 4.0 * th * x) ** 0.5
    d = 1.0 + x + r
    xdth = t2 * t5 * w * c3 / ((c3 + w) * (c3 + w))
    dr = ((1.0 + x) - 2.0 * th - 2.0 * xdth) / r if r > 0.0 else 0.0
    return 2.0 * x / d, 2.0 * (d - x * (1.0 + dr)) / (d * d)


def gqh_slope_core(x, t1, t2, t3, t4, t5):
    """dT/dx of the GQ/H backbone at x ≥ 0 (float or array) [-]; 1 at x = 0 (G_max).

    With D = 1 + x + R, R = √((1 + x)² − 4 θ_τ x): dT/dx = 2 (D − x (1 + R′))/D²,
    R′ = ((1 + x) − 2 θ_τ − 2 x θ_τ′)/R, x θ_τ′ = θ2 θ5 w θ3^θ5 / (θ3^θ5 + w)², w = θ4 x^θ5.

    >>> gqh_slope_core(0.0, -2.0, 2.5, 0.5, 1.0, 1.2)
    1.0
    """
    w = t4 * x ** t5
    c = t3 ** t5
    th = t1 + t2 * w / (c + w)
    xdth = t2 * t5 * w * c / ((c + w) * (c + w))
    r = ((1.0 + x) * (1.0 + x) - 4.0 * th * x) ** 0.5
    d = 1.0 + x + r
    dr = ((1.0 + x) - 2.0 * th - 2.0 * xdth) / r
    return 2.0 * (d - x * (1.0 + dr)) / (d * d)


def gqh_ratio(x, t1, t2, t3, t4, t5):
    """GQ/H τ/τ_max at x = γ/γ_r of either sign (odd) [-]; a float.

    >>> round(gqh_ratio(-1.0, 0.0, 0.0, 1.0, 1.0, 1.0), 12)
    -0.5
    """
    t = gqh_core(abs(x), t1, t2, t3, t4, t5)
    return t if x >= 0.0 else -t


def gqh_slope(x, t1, t2, t3, t4, t5):
    """GQ/H tangent d(τ/τ_max)/dx at x of either sign (even) [-] = (dτ/dγ)/G_max; a float.

    >>> round(gqh_slope(-1.0, 0.0, 0.0, 1.0, 1.0, 1.0), 12)      # hyperbola: 1/(1 + x)²
    0.25
    """
    return gqh_slope_core(abs(x), t1, t2, t3, t4, t5)


def gqh_stress(gamma, g_max, tau_max, t1, t2, t3, t4, t5):
    """GQ/H backbone stress τ [Pa] at shear strain γ [-]; G_max, τ_max [Pa] (0 if τ_max ≤ 0).

    >>> round(gqh_stress(1e-3, 60e6, 60e3, 0.0, 0.0, 1.0, 1.0, 1.0))   # x = 1: τ_max/2
    30000
    """
    if tau_max <= 0.0:
        return 0.0
    return tau_max * gqh_ratio(gamma * g_max / tau_max, t1, t2, t3, t4, t5)


def gqh_tangent(gamma, g_max, tau_max, t1, t2, t3, t4, t5):
    """GQ/H tangent modulus dτ/dγ [Pa] at γ [-] (0 if τ_max ≤ 0).

    >>> round(gqh_tangent(1e-3, 60e6, 60e3, 0.0, 0.0, 1.0, 1.0, 1.0))   # G_max/(1 + 1)²
    15000000
    """
    if tau_max <= 0.0:
        return 0.0
    return g_max * gqh_slope(gamma * g_max / tau_max, t1, t2, t3, t4, t5)


def gqh_branch_ratio(x, x_rev, t_rev, f_m, s_m, t1, t2, t3, t4, t5):
    """τ/τ_max on the MRDF unload–reload branch from the reversal (x_rev, t_rev) [-].

    T = f_m [2 T_bb((x − x_rev)/2) − s_m (x − x_rev)] + s_m (x − x_rev) + t_rev, with f_m from
    :func:`mrdf_factor` and s_m = T_bb(x_m)/x_m the secant at the largest |x| reached; f_m = 1 is
    Masing's rule. All normalised (x = γ/γ_r, T = τ/τ_max).

    >>> b = gqh_branch_ratio(-1.0, 1.0, 0.5, 1.0, 0.5, 0.0, 0.0, 1.0, 1.0, 1.0)  # Masing: closes
    >>> round(b, 12)
    -0.5
    """
    dx = x - x_rev
    return f_m * (2.0 * gqh_ratio(0.5 * dx, t1, t2, t3, t4, t5) - s_m * dx) + s_m * dx + t_rev


def gqh_branch_slope(x, x_rev, f_m, s_m, t1, t2, t3, t4, t5):
    """d(τ/τ_max)/dx on the MRDF branch of :func:`gqh_branch_ratio` [-].

    >>> gqh_branch_slope(1.0, 1.0, 0.8, 0.5, 0.0, 0.0, 1.0, 1.0, 1.0)    # 0.8 (1 - 0.5) + 0.5
    0.9
    """
    return f_m * (gqh_slope(0.5 * (x - x_rev), t1, t2, t3, t4, t5) - s_m) + s_m


def mkz_core(x, beta, s):
    """MKZ T = τ/(G_max γ_r) = x/(1 + β x^s) at x = γ/γ_r ≥ 0 (float or array) [-].

    >>> mkz_core(1.0, 1.0, 1.0)
    0.5
    """
    return x / (1.0 + beta * x ** s)


def mkz_slope_core(x, beta, s):
    """dT/dx of MKZ at x ≥ 0 = (1 + β (1 − s) x^s)/(1 + β x^s)² [-].

    >>> mkz_slope_core(1.0, 1.0, 1.0)
    0.25
    """
    w = beta * x ** s
    return (1.0 + (1.0 - s) * w) / ((1.0 + w) * (1.0 + w))


def mkz_ratio(x, beta, s):
    """MKZ τ/(G_max γ_r) at x of either sign (odd) [-]; a float.

    >>> mkz_ratio(-1.0, 1.0, 1.0)
    -0.5
    """
    t = mkz_core(abs(x), beta, s)
    return t if x >= 0.0 else -t


def mkz_slope(x, beta, s):
    """MKZ tangent (dτ/dγ)/G_max at x of either sign [-]; a float.

    >>> mkz_slope(-1.0, 1.0, 1.0)
    0.25
    """
    return mkz_slope_core(abs(x), beta, s)


def mkz_stress(gamma, g_max, gamma_r, beta, s):
    """MKZ stress τ = G_max γ/(1 + β (|γ|/γ_r)^s) [Pa]; γ, γ_r [-], G_max [Pa].

    >>> round(mkz_stress(1e-3, 60e6, 1e-3, 1.0, 1.0))
    30000
    """
    return g_max * gamma_r * mkz_ratio(gamma / gamma_r, beta, s)


def mkz_tangent(gamma, g_max, gamma_r, beta, s):
    """MKZ tangent modulus dτ/dγ [Pa].

    >>> round(mkz_tangent(1e-3, 60e6, 1e-3, 1.0, 1.0))
    15000000
    """
    return g_max * mkz_slope(gamma / gamma_r, beta, s)


def mrdf_factor(g_ratio, p1, p2, p3):
    """MRDF damping reduction F = p1 − p2 (1 − G(γ_m)/G_max)^p3 [-] (Phillips & Hashash 2009).

    g_ratio [-] the secant G(γ_m)/G_max at the largest strain reached, in (0, 1].

    >>> round(mrdf_factor(0.5, 1.0, 0.6, 1.0), 12)
    0.7
    """
    return p1 - p2 * (1.0 - g_ratio) ** p3


#: per-point functions that other per-point functions call: compile them with a kernel
SCALAR_HELPERS = (gqh_core, gqh_core_c, gqh_core_slope_c, gqh_slope_w, gqh_slope_core, gqh_ratio, gqh_slope, mkz_core, mkz_slope_core, mkz_ratio,
                  mkz_slope)


# ---- NumPy wrappers -----------------------------------------------------------------------------

def gqh_backbone(gamma, g_max, tau_max, theta):
    """GQ/H backbone stress τ [Pa] at strains γ [-] (array); θ = (θ1, …, θ5).

    >>> [round(float(t)) for t in gqh_backbone([-1e-3, 0.0, 1e-3], 60e6, 60e3, (0, 0, 1, 1, 1))]
    [-30000, 0, 30000]
    """
    g = np.asarray(gamma, dtype=float)
    x = np.abs(g) * g_max / tau_max
    return np.sign(g) * tau_max * gqh_core(x, *theta)


def gqh_modulus_reduction(gamma, gamma_r, theta):
    """GQ/H secant G/G_max = T(x)/x = 2/(1 + x + √((1 + x)² − 4 θ_τ x)) at γ [-], γ_r = τ_max/G_max.

    >>> [round(float(v), 6) for v in gqh_modulus_reduction([0.0, 1e-3], 1e-3, (0, 0, 1, 1, 1))]
    [1.0, 0.5]
    """
    x = np.abs(np.asarray(gamma, dtype=float)) / gamma_r
    t1, t2, t3, t4, t5 = theta
    w = t4 * x ** t5
    th = t1 + t2 * w / (t3 ** t5 + w)
    return 2.0 / (1.0 + x + np.sqrt((1.0 + x) ** 2 - 4.0 * th * x))


def mkz_modulus_reduction(gamma, gamma_r, beta, s):
    """MKZ G/G_max = 1/(1 + β (|γ|/γ_r)^s) [-].

    >>> float(mkz_modulus_reduction(1e-3, 1e-3, 1.0, 1.0))
    0.5
    """
    x = np.abs(np.asarray(gamma, dtype=float)) / gamma_r
    return 1.0 / (1.0 + beta * x ** s)


# composite Gauss–Legendre on segments geometric in u/x_m: the backbone's knee may sit anywhere
# between 1e-6 x_m and x_m; 16 nodes on each of 14 segments integrate it to ~1e-12
_EDGES = np.concatenate(([0.0], np.logspace(-12, 0, 14)))
_GL_X, _GL_W = np.polynomial.legendre.leggauss(16)


def masing_damping(core, x_m, *args):
    """Masing damping ratio D [-] of the normalised backbone ``core(u, *args)`` at amplitudes x_m.

    D = 4 ∫₀^{x_m} [T(u) − (T(x_m)/x_m) u] du / (π T(x_m) x_m): the area of the Masing loop
    over 4π times the energy ½ τ_m γ_m. ``core`` must accept arrays of u ≥ 0 (the ``_core``
    functions do). Relative accuracy about 1e-10 for the backbones here; for the hyperbola
    x/(1 + x) it is the closed form D = (1/π)[4 (x − ln(1 + x))(1 + x)/x² − 2].

    >>> x = 2.0
    >>> exact = (4 * (x - np.log1p(x)) * (1 + x) / x**2 - 2) / np.pi
    >>> bool(abs(masing_damping(gqh_core, x, 0, 0, 1, 1, 1) - exact) < 1e-12)
    True
    """
    xm = np.atleast_1d(np.asarray(x_m, dtype=float))
    a = _EDGES[:-1, None] * xm                     # (segments, amplitudes)
    h = 0.5 * (_EDGES[1:, None] - _EDGES[:-1, None]) * xm
    u = a[..., None] + h[..., None] * (_GL_X + 1.0)   # (segments, amplitudes, nodes)
    tm = core(xm, *args)
    g = core(u, *args) - (tm / xm)[None, :, None] * u
    area = np.sum(h * np.sum(g * _GL_W, axis=-1), axis=0)
    d = 4.0 * area / (np.pi * tm * xm)
    return d if np.ndim(x_m) else float(d[0])


def gqh_masing_damping(gamma, gamma_r, theta):
    """Masing damping ratio D [-] of the GQ/H backbone at strain amplitudes γ [-] > 0.

    >>> round(gqh_masing_damping(1e-3, 1e-3, (0, 0, 1, 1, 1)), 6)   # hyperbola, x = 1: (8 (1 - ln 2) - 2)/π
    0.144775
    """
    return masing_damping(gqh_core, np.asarray(gamma, dtype=float) / gamma_r, *theta)


def mkz_masing_damping(gamma, gamma_r, beta, s):
    """Masing damping ratio D [-] of the MKZ backbone at strain amplitudes γ [-] > 0.

    >>> round(mkz_masing_damping(1e-3, 1e-3, 1.0, 1.0), 6)
    0.144775
    """
    return masing_damping(mkz_core, np.asarray(gamma, dtype=float) / gamma_r, beta, s)
