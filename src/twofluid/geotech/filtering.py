"""Low-passed peak accelerations and spectral ordinates of a computed surface motion.

A computed surface acceleration holds frequencies the mesh does not resolve (a linear element
carries a wave to about a tenth of its wavelength: f ≲ V_s/(10 h), 15–30 Hz for the bundled
columns' soft layers and 0.25–0.5 m elements) and the short spikes of a dilating liquefied layer.
Engineers compare a *low-passed* PGA: here the zero-phase 4th-order Butterworth low-pass, the
filter a forward and backward pass of the digital 4th-order Butterworth makes,
|H(f)|² = 1/(1 + (tan(π f Δt)/tan(π f_c Δt))^8) (−6 dB at the cut-off), by default at 15 Hz, on the record resampled to a uniform step. It is
applied in the frequency domain (NumPy's real FFT, the record padded with zeros to four times its
length so that its ends do not wrap around): the same magnitude and zero phase as SciPy's
``sosfiltfilt`` without the 1 s it costs to import ``scipy.signal``.

>>> import numpy as np
>>> t = np.arange(0.0, 4.0, 0.005)
>>> a = np.sin(2 * np.pi * 2.0 * t) + 0.5 * np.sin(2 * np.pi * 60.0 * t)
>>> round(low_passed_peak(t, a), 2)  # the 60 Hz part is gone, the 2 Hz part kept
1.0
"""
from __future__ import annotations

import numpy as np

from ..postprocess import median

__all__ = ["CUTOFF_HZ", "low_pass", "low_passed_peak", "spectral_ordinates", "SA_PERIODS_S"]

#: default cut-off of the low-passed PGA [Hz]
CUTOFF_HZ = 15.0
#: periods of the spectral ordinates written to the summary [s]
SA_PERIODS_S = (0.1, 0.2, 0.3, 0.5, 1.0)


def _uniform(t, a):
    t = np.asarray(t, dtype=float)
    a = np.asarray(a, dtype=float)
    if t.size < 2:
        raise ValueError("low_pass: at least two samples are needed")
    dt = median(np.diff(t))  # (np.median's value, without its import of numpy.ma)
    if not dt > 0.0:
        raise ValueError("low_pass: times must increase")
    tu = np.arange(t[0], t[-1] + 0.5 * dt, dt)
    return tu, np.interp(tu, t, a), dt


def low_pass(t, a, cutoff_hz: float = CUTOFF_HZ, order: int = 4):
    """(t_uniform [s], a_filtered) of acceleration ``a`` at times ``t`` [s]: resampled to the median
    step, then the zero-phase digital Butterworth low-pass of ``order`` at ``cutoff_hz`` [Hz]
    (module docstring). A cut-off at or above the Nyquist frequency returns
    the resampled record.

    >>> t = np.arange(0.0, 2.0, 0.001)
    >>> _, y = low_pass(t, np.sin(2 * np.pi * 15.0 * t), 15.0)
    >>> round(float(np.max(np.abs(y[500:1500]))), 3)  # -6 dB at the cut-off
    0.5
    """
    tu, au, dt = _uniform(t, a)
    if cutoff_hz >= 0.5 / dt:
        return tu, au
    n = 4 * au.size
    f = np.fft.rfftfreq(n, dt)
    # the digital Butterworth's magnitude (bilinear transform, cut-off pre-warped), squared
    ratio = np.tan(np.pi * np.minimum(f * dt, 0.5 - 1e-12)) / np.tan(np.pi * cutoff_hz * dt)
    gain = 1.0 / (1.0 + ratio ** (2 * order))
    return tu, np.fft.irfft(np.fft.rfft(au, n) * gain, n)[:au.size]


def low_passed_peak(t, a, cutoff_hz: float = CUTOFF_HZ) -> float:
    """Peak |a| of the low-passed record (:func:`low_pass`), in the units of ``a``."""
    return float(np.max(np.abs(low_pass(t, a, cutoff_hz)[1])))


def spectral_ordinates(t, a, periods=SA_PERIODS_S, damping: float = 0.05) -> dict:
    """{period [s]: Sa} of the 5 %-damped pseudo-acceleration spectrum of ``a`` (resampled to a
    uniform step; :func:`twofluid.geotech.spectra.response_spectrum`), in the units of ``a``."""
    from .spectra import response_spectrum

    tu, au, dt = _uniform(t, a)
    sa = response_spectrum(au, dt, np.asarray(periods, dtype=float), damping)[0]
    return {float(p): float(v) for p, v in zip(periods, sa)}
