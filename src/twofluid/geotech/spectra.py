"""Linear elastic response spectra of an acceleration record (Nigam & Jennings 1969).

A single-degree-of-freedom oscillator of natural period T and damping ratio ζ on the
moving ground obeys, for the displacement u relative to the ground,

    ü + 2ζω u̇ + ω² u = −a_g(t),        ω = 2π/T.

With the record linearly interpolated between samples, the state x = (u, u̇) is
advanced exactly over each step Δt (Nigam & Jennings 1969):

    x_{n+1} = E x_n − (Γ0 − Γ1) a_n − Γ1 a_{n+1},
    E = exp(AΔt),  Γ0 = A⁻¹(E − I) e₂,  Γ1 = (A⁻²(E − I)/Δt − A⁻¹) e₂,

A = [[0, 1], [−ω², −2ζω]], e₂ = (0, 1); E is written in closed form with the damped
frequency ω_d = ω√(1 − ζ²). The recurrence has no stability or accuracy limit on
Δt/T other than the piecewise-linear reading of the record. The spectral values are
S_d = max|u|, the pseudo-velocity S_v = ω S_d and the pseudo-acceleration S_a = ω² S_d.
At T = 0 (a rigid oscillator) S_a is the peak ground acceleration and S_d = S_v = 0.

Units follow the record: acceleration in m/s² gives S_a [m/s²], S_v [m/s], S_d [m];
in g it gives S_a [g], S_v [g·s], S_d [g·s²].

Reference: Nigam, N. C. & Jennings, P. C. (1969). Calculation of response spectra from
strong-motion earthquake records. Bull. Seismol. Soc. Am. 59(2), 909–922.
"""
from __future__ import annotations

import sys

import numpy as np

from ..casefile.schema import CaseError

__all__ = ["sdof_history", "response_spectrum", "amplification", "standard_periods", "MAX_PERIOD_STEPS"]

# T/Δt above this loses more than ~1e-8 to cancellation in Γ1 (terms of order 1/ω²
# cancel to order Δt²), so longer periods need a finer record.
MAX_PERIOD_STEPS = 5.0e4


def _check(accel, dt, periods, damping, source):
    a = np.asarray(accel, dtype=float)
    if a.ndim != 1 or a.size < 2 or not np.all(np.isfinite(a)):
        raise CaseError(source, "accel", f"must be a 1-D finite array of at least 2 samples, got shape {a.shape}")
    try:
        dt = float(dt)
    except (TypeError, ValueError):
        raise CaseError(source, "dt", f"must be one number > 0 s, got {dt!r}") from None
    if not (np.isfinite(dt) and dt > 0.0):
        raise CaseError(source, "dt", f"must be > 0 s, got {dt:g}")
    t = np.atleast_1d(np.asarray(periods, dtype=float))
    if t.ndim != 1 or t.size == 0 or not np.all(np.isfinite(t)) or np.any(t < 0.0):
        raise CaseError(source, "periods", "must be a non-empty 1-D array of periods >= 0 s")
    if np.any(t > MAX_PERIOD_STEPS * dt):
        raise CaseError(source, "periods", f"must be <= {MAX_PERIOD_STEPS:g} dt = {MAX_PERIOD_STEPS * dt:g} s "
                        "(resample the record finer for longer periods)")
    try:
        z = float(damping)
    except (TypeError, ValueError):
        raise CaseError(source, "damping", f"must be a ratio in [0, 1), got {damping!r}") from None
    if not 0.0 <= z < 1.0:
        raise CaseError(source, "damping", f"must be a ratio in [0, 1), got {z:g}")
    return a, dt, t, z


def _coefficients(omega, z, dt):
    """Step matrices E (2x2) and load vectors of a_n, a_{n+1}, each entry shaped like omega."""
    wd = omega * np.sqrt(1.0 - z * z)
    e = np.exp(-z * omega * dt)
    c, s = np.cos(wd * dt), np.sin(wd * dt)
    e11 = e * (c + z * omega / wd * s)
    e12 = e * s / wd
    e21 = -e * omega * omega / wd * s
    e22 = e * (c - z * omega / wd * s)
    w2 = omega * omega
    g0u = -2.0 * z / omega * e12 - (e22 - 1.0) / w2      # Γ0 = A⁻¹ (E − I) e₂
    g0v = e12
    g1u = -2.0 * z / omega * g0u / dt - g0v / (w2 * dt) + 1.0 / w2  # Γ1 = A⁻¹ Γ0/Δt − A⁻¹ e₂
    g1v = g0u / dt
    return (e11, e12, e21, e22), (g1u - g0u, g1v - g0v), (-g1u, -g1v)


def _march(a, dt, omega, z, keep):
    """Peak |u| of each oscillator from rest, and the u, v histories if ``keep``."""
    (e11, e12, e21, e22), (cu, cv), (du, dv) = _coefficients(omega, z, dt)
    compiled = None if keep else _compiled_peaks()
    if compiled is not None:
        args = [np.ascontiguousarray(x, dtype=float) for x in (a, e11, e12, e21, e22, cu, cv, du, dv)]
        return compiled(*args, np.zeros(omega.size)), None
    u = np.zeros_like(omega)
    v = np.zeros_like(omega)
    peak = np.zeros_like(omega)
    hist = [np.zeros((omega.size, a.size)) for _ in range(2)] if keep else None
    for n in range(a.size - 1):
        u, v = (e11 * u + e12 * v + cu * a[n] + du * a[n + 1],
                e21 * u + e22 * v + cv * a[n] + dv * a[n + 1])
        np.maximum(peak, np.abs(u), out=peak)
        if keep:
            hist[0][:, n + 1], hist[1][:, n + 1] = u, v
    return peak, hist


def _peaks(a, e11, e12, e21, e22, cu, cv, du, dv, peak):
    """:func:`_march`'s peaks, oscillator by oscillator: the same arithmetic in the same order."""
    for p in range(peak.size):
        u = 0.0
        v = 0.0
        top = 0.0
        for n in range(a.size - 1):
            u, v = (e11[p] * u + e12[p] * v + cu[p] * a[n] + du[p] * a[n + 1],
                    e21[p] * u + e22[p] * v + cv[p] * a[n] + dv[p] * a[n + 1])
            if not abs(u) <= top:  # as np.maximum: a NaN stays
                top = abs(u)
        peak[p] = top
    return peak


_PEAKS_SIGNATURE = "f8[::1](" + ", ".join(["f8[::1]"] * 10) + ")"


def _compiled_peaks():
    """:func:`_peaks` compiled (:mod:`twofluid.compiled`: the cached ahead-of-time module, built
    once where numba is installed, or numba's JIT where numba is already loaded), or None: then
    the NumPy march (0.03 s for 100 periods and 7 000 samples) costs less than importing numba."""
    from ..compiled import kernel

    return kernel("spectra_peaks", _peaks, _PEAKS_SIGNATURE, jit="numba" in sys.modules)


def standard_periods(n: int = 100, t_min: float = 0.01, t_max: float = 10.0) -> np.ndarray:
    """Periods [s] for plotting a spectrum: 0 (the peak ground acceleration), then ``n``
    log-spaced periods from ``t_min`` to ``t_max``.

    >>> p = standard_periods(3, 0.1, 10.0)
    >>> p.tolist()
    [0.0, 0.1, 1.0, 10.0]
    """
    if not (int(n) >= 1 and 0.0 < t_min < t_max):
        raise CaseError("standard_periods", "n, t_min, t_max", "need n >= 1 and 0 < t_min < t_max")
    return np.concatenate(([0.0], np.logspace(np.log10(t_min), np.log10(t_max), int(n))))


def sdof_history(accel, dt, periods, damping=0.05):
    """Relative displacement and velocity histories of SDOF oscillators, from rest.

    Parameters: ``accel`` ground acceleration samples (1-D, spacing ``dt`` [s]),
    ``periods`` natural periods T > 0 [s], ``damping`` ζ in [0, 1). Returns ``(u, v)``,
    each shaped (len(periods), len(accel)), in the record's length and time units.

    A quasi-static check: a constant a_g = 1 applied from rest settles at u = −1/ω²:

    >>> u, v = sdof_history(np.ones(2001), 0.01, [0.5], 0.7)
    >>> round(float(u[0, -1] * (2 * np.pi / 0.5) ** 2), 6)
    -1.0
    """
    a, dt, t, z = _check(accel, dt, periods, damping, "sdof_history")
    if np.any(t <= 0.0):
        raise CaseError("sdof_history", "periods", "must be > 0 s")
    _, (u, v) = _march(a, dt, 2.0 * np.pi / t, z, keep=True)
    return u, v


def response_spectrum(accel, dt, periods, damping=0.05):
    """Pseudo-spectral acceleration, pseudo-velocity and displacement (S_a, S_v, S_d).

    Parameters
    ----------
    accel : array (N,)
        Ground acceleration samples, spacing ``dt`` [s]; any unit (see the module).
    dt : float
        Sample spacing [s], > 0.
    periods : array (P,)
        Natural periods [s], ≥ 0 and ≤ 5e4 dt.
    damping : float
        Damping ratio ζ in [0, 1); 0.05 is the usual 5 % spectrum.

    Returns
    -------
    Sa, Sv, Sd : arrays (P,)
        ω² S_d, ω S_d and max|u| (T = 0: peak |a_g|, 0, 0).

    Examples
    --------
    A rigid oscillator follows the ground; a very flexible one stays put (S_d → peak
    ground displacement, S_a → 0):

    >>> t = np.arange(0.0, 10.0, 0.01)
    >>> sa, sv, sd = response_spectrum(0.3 * np.sin(2 * np.pi * t), 0.01, [0.0, 1.0])
    >>> float(sa[0]) == float(np.max(np.abs(0.3 * np.sin(2 * np.pi * t))))
    True
    >>> bool(sa[1] > 2.0)      # near resonance: grows towards 0.3/(2 * 0.05) = 3
    True
    """
    a, dt, t, z = _check(accel, dt, periods, damping, "response_spectrum")
    sa = np.empty_like(t)
    sv = np.zeros_like(t)
    sd = np.zeros_like(t)
    rigid = t == 0.0
    sa[rigid] = np.max(np.abs(a))
    if np.any(~rigid):
        omega = 2.0 * np.pi / t[~rigid]
        peak, _ = _march(a, dt, omega, z, keep=False)
        sd[~rigid], sv[~rigid], sa[~rigid] = peak, omega * peak, omega * omega * peak
    return sa, sv, sd


def amplification(sa_surface, sa_input):
    """Spectral amplification ratio S_a,surface / S_a,input [-], period by period.

    Both arrays on the same periods and damping; ``sa_input`` must be > 0 everywhere
    (a ratio to a zero spectrum is undefined and is refused, not returned as NaN).

    >>> amplification([0.6, 0.9], [0.3, 0.3]).tolist()
    [2.0, 3.0]
    """
    s = np.asarray(sa_surface, dtype=float)
    r = np.asarray(sa_input, dtype=float)
    if s.shape != r.shape:
        raise CaseError("amplification", "sa_input", f"must have the shape of sa_surface {s.shape}, got {r.shape}")
    if not np.all(np.isfinite(r) & (r > 0.0)):
        raise CaseError("amplification", "sa_input", "must be finite and > 0 at every period")
    return s / r
