"""The low-passed PGA (geotech/filtering.py) against SciPy's forward–backward Butterworth."""
import numpy as np

from twofluid.geotech import filtering


def test_low_pass_is_scipys_zero_phase_butterworth_away_from_the_ends():
    """The frequency-domain filter has the magnitude and phase of ``sosfiltfilt`` of a 4th-order
    digital Butterworth: inside the record (one second from each end, where the two pad
    differently: zeros against an odd extension) they agree to 1e-6 of the peak (measured: 1e-11)."""
    from scipy.signal import butter, sosfiltfilt

    rng = np.random.default_rng(1)
    t = np.arange(0.0, 20.0, 0.005)
    a = np.convolve(rng.normal(size=t.size), np.ones(3) / 3.0, "same")
    _, y = filtering.low_pass(t, a, 15.0)
    ref = sosfiltfilt(butter(4, 15.0, fs=200.0, output="sos"), a)
    inner = slice(200, -200)
    assert np.max(np.abs(y[inner] - ref[inner])) <= 1e-6 * np.max(np.abs(ref))


def test_low_passed_peak_keeps_slow_motion_and_removes_spikes():
    t = np.arange(0.0, 10.0, 0.005)
    a = np.sin(2 * np.pi * 1.0 * t)
    spiky = a.copy()
    spiky[1000] += 3.0  # one 5 ms spike
    assert abs(filtering.low_passed_peak(t, a) - 1.0) < 1e-3
    assert filtering.low_passed_peak(t, spiky) < 1.5 < np.max(np.abs(spiky))
