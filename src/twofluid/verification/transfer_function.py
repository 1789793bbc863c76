r"""Exact transfer function of a uniform damped linear layer, and its measurement from a run.

Problem
-------
A uniform layer 0 ≤ y ≤ H (y up from the base) of density ρ [kg/m³] and shear
modulus G [Pa], in the relative formulation of :mod:`twofluid.models.shear_column`
(u the displacement relative to the reference motion of acceleration a_g):

    ρ ü + a0 ρ u̇ − ∂/∂y[(G + (η + a1 G) ∂/∂t) ∂u/∂y] = −ρ a_g,    τ(H) = 0,

Rayleigh damping with a mass part a0 ρ u̇ on the *relative* velocity and a stiffness
part a1 G γ̇, plus a Kelvin–Voigt viscosity η [Pa·s]. At the base either

* rigid: u(0) = 0 and a_g is the base acceleration; or
* compliant: τ(0) = c u̇(0) with c = ρ_r V_r [Pa·s/m] and a_g the outcrop acceleration.

The transfer function is the surface's absolute acceleration over a_g,
H(ω) = 1 + Ü(H)/A_g, in steady harmonic motion u = U(y) e^{iωt}, a_g = A_g e^{iωt}.

Solution
--------
With ν = a0/ω, ρ* = ρ(1 − iν), G* = G + iω(η + a1 G) the equation becomes
G* U'' + ω² ρ* U = ρ A_g. Its particular solution is U_p = A_g/(ω²(1 − iν)); with
k* = ω √(ρ*/G*), U = U_p + B cos k*y + C sin k*y. τ(H) = 0 gives C = B tan k*H; the
base condition gives B: rigid, U(0) = 0, B = −U_p; compliant, G* k* C = iωc (U_p + B),
B = −U_p/(1 + iα* tan k*H) with α* = G* k*/(ωc) = √(ρ* G*)/c. Then U(H) = U_p + B/cos k*H and, with −ω² U_p/A_g
= −1/(1 − iν),

    H(ω) = [1/(cos k*H + i α* sin k*H) − iν] / (1 − iν),      α* = 0 on a rigid base.

Without the mass term (ν = 0) this is the classical 1/(cos k*H + iα* sin k*H)
(Kramer 1996, ch. 7; :func:`twofluid.models.shear_column.layer_amplification` is its
modulus). The mass term acts on the velocity relative to the reference motion, so it
is not Galilean invariant: it damps the *relative* motion and leaves the rigid-body
part a_g undamped, hence the −iν in the numerator and the (1 − iν) below.

Measured transfer function
--------------------------
A time-stepping scheme driven by the samples a_g[n] is a linear time-invariant
discrete system. Started at rest and run until its response has died out, the
discrete-time Fourier transforms (DTFT) of the surface's absolute acceleration y[n]
and of the input x[n] satisfy Y(f) = H_d(f) X(f) at every frequency f, with H_d the
transfer function of the *discretised* layer (mesh and time step): the ratio
:func:`fourier_ratio` measures H_d without windowing or spectral leakage. What is
left in the record at its end bounds the error (:func:`fourier_ratio` is exact for a
response that has decayed to zero).

References
----------
Kramer, S. L. (1996). *Geotechnical Earthquake Engineering*, Prentice Hall, ch. 7.
Hughes, T. J. R. (1987). *The Finite Element Method*, Prentice Hall, ch. 9 (Newmark,
phase error of consistent mass).
"""
from __future__ import annotations

import numpy as np

__all__ = ["layer_transfer_function", "fourier_ratio", "peaks"]


def layer_transfer_function(frequency, H: float, rho: float, g: float, a0: float = 0.0,
                            a1: float = 0.0, eta: float = 0.0,
                            base_impedance: float | None = None):
    """Exact complex transfer function H(f) of a uniform damped linear layer [-].

    Surface absolute acceleration over the input acceleration (base acceleration on a
    rigid base, outcrop acceleration on a compliant one); see the module docstring.

    Parameters
    ----------
    frequency : array_like
        Frequencies f > 0 [Hz].
    H : float
        Layer thickness [m].
    rho : float
        Density [kg/m³].
    g : float
        Shear modulus [Pa].
    a0 : float
        Mass coefficient of Rayleigh damping [1/s] (on the relative velocity).
    a1 : float
        Stiffness coefficient of Rayleigh damping [s].
    eta : float
        Kelvin–Voigt viscosity [Pa·s].
    base_impedance : float or None
        c = ρ_r V_r of an elastic half-space [Pa·s/m]; None: rigid base.

    Returns
    -------
    numpy.ndarray of complex
        H(f) [-].

    Examples
    --------
    Undamped on a rigid base, H = 1/cos(kH): at a quarter of the first resonance
    frequency kH = π/8; at f → 0 the layer moves with its base.

    >>> import numpy as np
    >>> f1 = np.sqrt(50e6 / 2000.0) / 40.0  # V_s/(4H), H = 10 m
    >>> h = layer_transfer_function([f1 / 4, 1e-6], 10.0, 2000.0, 50e6)
    >>> np.round(np.abs(h), 6).tolist(), round(1 / float(np.cos(np.pi / 8)), 6)
    ([1.082392, 1.0], 1.082392)

    The mass term alone damps the relative motion only: a stiff layer (kH → 0) keeps
    H = 1 whatever a0.

    >>> round(float(abs(layer_transfer_function(0.5, 1.0, 2000.0, 1e12, a0=5.0))), 6)
    1.0

    A compliant base without damping in the layer: 1/α at resonance (kH = π/2).

    >>> c = 2000.0 * 158.11388 / 0.5  # α = ρ V_s / c = 0.5
    >>> round(float(abs(layer_transfer_function(f1, 10.0, 2000.0, 50e6, base_impedance=c))), 5)
    2.0
    """
    f = np.asarray(frequency, dtype=float)
    w = 2.0 * np.pi * f
    nu = a0 / w
    rho_s = rho * (1.0 - 1j * nu)
    g_s = g + 1j * w * (eta + a1 * g)
    k = w * np.sqrt(rho_s / g_s)
    alpha = 0.0 if base_impedance is None else np.sqrt(rho_s * g_s) / base_impedance
    wave = 1.0 / (np.cos(k * H) + 1j * alpha * np.sin(k * H))
    return (wave - 1j * nu) / (1.0 - 1j * nu)


def fourier_ratio(y, x, dt: float, frequency):
    """Ratio of the DTFTs Y(f)/X(f) of two records sampled at ``dt`` [s], at ``frequency`` [Hz].

    Both records start at t = 0 with the same sampling; the DTFT is summed directly,
    so any frequency can be asked for (no grid, no padding, no window).

    >>> import numpy as np
    >>> x = np.zeros(64); x[3] = 1.0
    >>> y = np.zeros(64); y[5] = 2.0  # a delay of 2 samples and a gain of 2
    >>> r = fourier_ratio(y, x, 0.01, [5.0, 10.0])
    >>> np.round(np.abs(r), 12).tolist(), np.round(np.angle(r), 12).tolist()
    ([2.0, 2.0], [-0.628318530718, -1.256637061436])
    """
    f = np.atleast_1d(np.asarray(frequency, dtype=float))
    y = np.asarray(y, dtype=float)
    x = np.asarray(x, dtype=float)
    if y.shape != x.shape or y.ndim != 1:
        raise ValueError(f"records must be 1-D and of one length, got {y.shape} and {x.shape}")
    t = dt * np.arange(y.size)
    out = np.empty(f.size, dtype=complex)
    for i0 in range(0, f.size, 256):  # bounded memory: 256 frequencies at a time
        e = np.exp(-2j * np.pi * np.outer(f[i0:i0 + 256], t))
        out[i0:i0 + 256] = (e @ y) / (e @ x)
    return out


def peaks(func, f_lo: float, f_hi: float, n: int = 2000, rtol: float = 1e-7):
    """Local maxima of |func(f)| on [f_lo, f_hi] [Hz]: (frequencies [Hz], |func| there).

    A grid of ``n`` points brackets each maximum; a golden-section search on the
    bracket then locates it to ``rtol`` relative in frequency.

    >>> import numpy as np
    >>> f, a = peaks(lambda f: 1.0 / (1.0 + (f - 3.21) ** 2), 0.0, 10.0)
    >>> np.round(f, 6).tolist(), np.round(a, 9).tolist()
    ([3.21], [1.0])
    """
    grid = np.linspace(f_lo, f_hi, n)
    a = np.abs(func(grid))
    idx = [i for i in range(1, n - 1) if a[i] > a[i - 1] and a[i] >= a[i + 1]]
    r = (np.sqrt(5.0) - 1.0) / 2.0
    fs, amps = [], []
    for i in idx:
        lo, hi = grid[i - 1], grid[i + 1]
        while hi - lo > rtol * hi:
            m1, m2 = hi - r * (hi - lo), lo + r * (hi - lo)
            v = np.abs(func(np.array([m1, m2])))
            if v[0] >= v[1]:
                hi = m2
            else:
                lo = m1
        fm = 0.5 * (lo + hi)
        fs.append(fm)
        amps.append(float(np.abs(func(np.array([fm])))[0]))
    return np.array(fs), np.array(amps)
