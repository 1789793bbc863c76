"""Response spectra (Nigam & Jennings 1969 recurrence) against independent SDOF integrations."""
import numpy as np
import pytest
from scipy import signal
from scipy.integrate import solve_ivp

from twofluid.casefile.schema import CaseError
from twofluid.geotech.spectra import amplification, response_spectrum, sdof_history

DT = 0.01
PERIODS = np.array([0.05, 0.1, 0.3, 0.5, 1.0, 2.0, 4.0])
ZETA = 0.05


def sine_burst(f=2.0, cycles=3, duration=10.0, dt=DT):
    """Three cycles of a 2 Hz sine, then 7 s of free vibration (so the peak of a
    long-period oscillator comes after the burst)."""
    t = np.arange(0.0, duration + dt / 2, dt)
    return t, np.where(t <= cycles / f, np.sin(2 * np.pi * f * t), 0.0)


def test_matches_lsim_first_order_hold():
    """scipy.signal.lsim with interp=True integrates the same piecewise-linear input
    exactly through its own matrix exponential: the two agree to round-off growth over
    1000 steps (≤ 1e-10 of the peak; observed ~3e-14)."""
    t, a = sine_burst()
    u, _ = sdof_history(a, DT, PERIODS, ZETA)
    for i, period in enumerate(PERIODS):
        w = 2 * np.pi / period
        sys = signal.StateSpace([[0, 1], [-w * w, -2 * ZETA * w]], [[0], [-1]], [[1, 0]], [[0]])
        _, y, _ = signal.lsim(sys, a, t, interp=True)
        assert np.max(np.abs(y - u[i])) <= 1e-10 * np.max(np.abs(u[i]))


def test_matches_adaptive_runge_kutta():
    """solve_ivp (DOP853, rtol 1e-11) on the linearly interpolated record is a fully
    independent integration; the kinks of the input at every sample lower its local
    order, observed error ≤ 2e-8 of the peak, bound 1e-6. The spectral values are the
    peaks of the same histories."""
    t, a = sine_burst()
    sa, sv, sd = response_spectrum(a, DT, PERIODS, ZETA)
    for i, period in enumerate(PERIODS[[1, 4, 6]]):
        w = 2 * np.pi / period

        def rhs(s, x):
            return [x[1], -np.interp(s, t, a) - 2 * ZETA * w * x[1] - w * w * x[0]]

        sol = solve_ivp(rhs, (0.0, t[-1]), [0.0, 0.0], method="DOP853", rtol=1e-11, atol=1e-14,
                        t_eval=t, max_step=DT)
        ref = np.max(np.abs(sol.y[0]))
        j = [1, 4, 6][i]
        assert sd[j] == pytest.approx(ref, rel=1e-6)
        assert sv[j] == pytest.approx(w * ref, rel=1e-6)
        assert sa[j] == pytest.approx(w * w * ref, rel=1e-6)


def test_resonance_amplitude_is_one_over_two_zeta():
    """A long harmonic input A sin(ωt) at the oscillator's own period: the steady
    amplitude of u is A/(2ζω²), so S_a = A/(2ζ). The piecewise-linear reading of the
    sine carries its fundamental at sinc²(ωΔt/2) of the amplitude (1 − 8.2e-5 for 200
    samples a period), the record lasts 20/(ζω) so the start-up transient has decayed to
    exp(−20) = 2e-9 of the amplitude, and
    the images of the interpolation at 2πk/Δt ± ω are off resonance by (ωΔt/2π)²; the
    bound 1e-6 covers these with margin."""
    period, amp = 1.0, 0.3
    dt = period / 200
    for zeta in (0.02, 0.05, 0.10):
        t = np.arange(0.0, 20.0 / (zeta * 2 * np.pi / period), dt)
        sa, _, _ = response_spectrum(amp * np.sin(2 * np.pi * t / period), dt, [period], zeta)
        x = np.pi * dt / period
        expected = amp / (2 * zeta) * (np.sin(x) / x) ** 2
        assert sa[0] == pytest.approx(expected, rel=1e-6)


def test_rigid_and_stiff_oscillators_follow_the_ground():
    """T = 0 gives the peak ground acceleration exactly; T = 1 ms (ω = 6283 rad/s) lags
    the ground by about 2ζ/ω, a relative error 2ζ f/f_n = 2e-4 for the 2 Hz burst."""
    t, a = sine_burst()
    pga = np.max(np.abs(a))
    sa, sv, sd = response_spectrum(0.4 * a, DT, [0.0, 0.001], ZETA)
    assert sa[0] == 0.4 * pga and sv[0] == 0.0 and sd[0] == 0.0
    assert sa[1] == pytest.approx(0.4 * pga, rel=1e-3)


def test_linear_in_the_record():
    """Spectra scale with the record (units follow the input)."""
    t, a = sine_burst()
    s1 = np.array(response_spectrum(a, DT, PERIODS))
    s2 = np.array(response_spectrum(9.81 * a, DT, PERIODS))
    np.testing.assert_allclose(s2, 9.81 * s1, rtol=1e-12)


def test_amplification():
    np.testing.assert_allclose(amplification([0.5, 1.2], [0.25, 0.4]), [2.0, 3.0])
    with pytest.raises(CaseError, match="sa_input"):
        amplification([0.5, 1.2], [0.25, 0.0])
    with pytest.raises(CaseError, match="shape"):
        amplification([0.5, 1.2], [0.25])


@pytest.mark.parametrize("kwargs, key", [
    (dict(accel=[1.0]), "accel"),
    (dict(accel=[0.0, np.nan, 1.0]), "accel"),
    (dict(dt=0.0), "dt"),
    (dict(dt="x"), "dt"),
    (dict(periods=[-1.0]), "periods"),
    (dict(periods=[]), "periods"),
    (dict(periods=[1e4]), "periods"),
    (dict(damping=1.0), "damping"),
    (dict(damping=-0.1), "damping"),
    (dict(damping="five"), "damping"),
])
def test_bad_arguments_name_the_argument(kwargs, key):
    args = dict(accel=np.sin(np.arange(100) * 0.1), dt=0.01, periods=[0.5], damping=0.05)
    args.update(kwargs)
    with pytest.raises(CaseError) as err:
        response_spectrum(**args)
    assert f": {key}:" in str(err.value) and "\n" not in str(err.value)


def test_compiled_peaks_are_the_numpy_march():
    """The compiled march (used where numba is loaded) does the NumPy march's arithmetic in the same
    order, oscillator by oscillator: peaks equal to round-off (1e-12 relative is far above it)."""
    pytest.importorskip("numba")
    from twofluid.geotech import spectra

    rng = np.random.default_rng(3)
    a = rng.standard_normal(3001)
    omega = 2.0 * np.pi / np.logspace(-2, 1, 40)
    ref, _ = spectra._march(a, 0.01, omega, 0.05, keep=True)  # keep: always the NumPy loop
    (e11, e12, e21, e22), (cu, cv), (du, dv) = spectra._coefficients(omega, 0.05, 0.01)
    python = spectra._peaks(a[:301], e11, e12, e21, e22, cu, cv, du, dv, np.zeros_like(omega))
    assert np.allclose(python, spectra._march(a[:301], 0.01, omega, 0.05, keep=True)[0], rtol=1e-12, atol=0.0)
    assert spectra._compiled_peaks() is not None  # numba is loaded here
    fast, hist = spectra._march(a, 0.01, omega, 0.05, keep=False)
    assert hist is None and np.allclose(fast, ref, rtol=1e-12, atol=0.0)
