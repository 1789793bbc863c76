"""Tests of the Kynch kinematic-wave exact solutions (verification/kynch.py).

Tolerances: closed-form identities to 1e-12 relative; finite-difference checks to
the truncation error of the difference (stated per test); quadrature of the exact
profile to 5e-5 relative (first-order trapezoid error at the jumps).
"""

import numpy as np
import pytest

from twofluid.verification import kynch

U_T, K = 0.088, 2.54  # roughly 3 mm nylon spheres in water
N0, N1, H0 = 0.54, 0.76, 0.275


def test_stokes_terminal_velocity_hand_value_and_d_squared():
    # (2650-1000)*9.81*(1e-4)^2/(18*1e-3) = 8.9925e-3 m/s
    assert kynch.stokes_terminal_velocity(1e-4, 2650, 1000, 1e-3) == pytest.approx(8.9925e-3, rel=1e-12)
    ratio = kynch.stokes_terminal_velocity(2e-4, 2650, 1000, 1e-3) / kynch.stokes_terminal_velocity(1e-4, 2650, 1000, 1e-3)
    assert ratio == pytest.approx(4.0, rel=1e-12)


def test_richardson_zaki_round_trip():
    n = np.linspace(0.45, 0.95, 11)
    assert np.allclose(kynch.richardson_zaki_n(U_T * n**K, U_T, K), n, rtol=1e-12)


@pytest.mark.parametrize("j", [0.0, 0.02, -0.01])
def test_wave_speed_is_flux_derivative_in_solids_fraction(j):
    # c = dF/d(1-n) = -dF/dn; central difference, error O(h^2) ~ 1e-10
    n, h = np.linspace(0.3, 0.95, 27), 1e-5
    fd = -(kynch.solids_flux(n + h, j, U_T, K) - kynch.solids_flux(n - h, j, U_T, K)) / (2 * h)
    assert np.allclose(kynch.wave_speed(n, j, U_T, K), fd, rtol=0, atol=1e-9)


def test_wave_speed_matches_thesis_eq_5_8():
    n, j = np.linspace(0.5, 0.9, 9), 0.03
    thesis = (K * n ** (K - 1) - (K + 1) * n**K) * U_T + j
    assert np.allclose(kynch.wave_speed(n, j, U_T, K), thesis, rtol=1e-12)


def test_shock_speed_rankine_hugoniot_and_symmetry():
    na, nb, j = 0.55, 0.7, 0.01
    s = kynch.shock_speed(na, nb, j, U_T, K)
    jump_F = kynch.solids_flux(nb, j, U_T, K) - kynch.solids_flux(na, j, U_T, K)
    assert s * ((1 - nb) - (1 - na)) == pytest.approx(jump_F, rel=1e-12)
    assert kynch.shock_speed(nb, na, j, U_T, K) == pytest.approx(s, rel=1e-12)


def test_shock_speed_tends_to_wave_speed_when_states_coincide():
    n, j = 0.65, 0.02
    c = kynch.wave_speed(n, j, U_T, K)
    assert kynch.shock_speed(n, n, j, U_T, K) == pytest.approx(c, rel=1e-12)
    # chord slope about the midpoint differs from c by O(delta^2)
    errs = [abs(kynch.shock_speed(n - d / 2, n + d / 2, j, U_T, K) - c) for d in (1e-2, 5e-3)]
    assert errs[0] < 1e-4 and errs[1] / errs[0] == pytest.approx(0.25, abs=0.01)


def test_hand_checked_step_change_t1():
    # U_t = 1, k = 2: expansion 0.5 -> 0.6, H1 = 1.25, c(n1) = 2*1*0.4*0.6 = 0.48
    assert kynch.step_change_t1(0.5, 0.6, 1.0, 1.0, 2.0) == pytest.approx(1.25 / 0.48, rel=1e-12)
    # contraction 0.6 -> 0.5, H1 = 0.8, U0 - U1 = 0.36 - 0.25
    assert kynch.step_change_t1(0.6, 0.5, 1.0, 1.0, 2.0) == pytest.approx(0.2 / 0.11, rel=1e-12)


def test_contraction_t1_is_meeting_of_shock_and_surface():
    n0, n1 = 0.73, 0.53
    fr = kynch.step_change_fronts(n0, n1, U_T, K)
    assert fr.slow == fr.fast  # a single shock
    # Lax condition: characteristics run into the shock from both sides
    j = U_T * n1**K
    assert kynch.wave_speed(n1, j, U_T, K) > fr.slow > kynch.wave_speed(n0, j, U_T, K)
    t_meet = H0 / (fr.slow - fr.surface)
    assert kynch.step_change_t1(n0, n1, H0, U_T, K) == pytest.approx(t_meet, rel=1e-12)


def test_expansion_fronts_spread_and_bed_reaches_H1_at_t1():
    fr = kynch.step_change_fronts(N0, N1, U_T, K)
    assert fr.fast > fr.slow > 0 and fr.surface == pytest.approx(U_T * (N1**K - N0**K))
    t1 = float(kynch.step_change_t1(N0, N1, H0, U_T, K))
    H1 = H0 * (1 - N0) / (1 - N1)
    assert fr.slow * t1 == pytest.approx(H1, rel=1e-12)
    h = kynch.bed_height(np.array([t1 * (1 - 1e-9), t1, 2 * t1]), N0, N1, H0, U_T, K)
    assert np.allclose(h, H1, rtol=1e-6)


@pytest.mark.parametrize("n0,n1", [(N0, N1), (0.73, 0.53)])
def test_profile_conserves_solids_at_all_times(n0, n1):
    t1 = float(kynch.step_change_t1(n0, n1, H0, U_T, K))
    y = np.linspace(0.0, 1.2 * max(H0, H0 * (1 - n0) / (1 - n1)), 40001)
    for t in np.linspace(0.0, 1.3 * t1, 9):
        solids = np.trapezoid(1 - kynch.step_change_profile(y, t, n0, n1, H0, U_T, K), y)
        assert solids == pytest.approx(H0 * (1 - n0), rel=5e-5), t  # trapezoid error O(dy) at jumps


def test_fan_profile_is_continuous_monotone_and_spans_states():
    # before the leading characteristic reaches the surface, t* = H0/(k U_t (1-n0) n0^(k-1))
    t = 0.5 * H0 / (K * U_T * (1 - N0) * N0 ** (K - 1))
    fr = kynch.step_change_fronts(N0, N1, U_T, K)
    y = np.linspace(0.0, float(kynch.bed_height(t, N0, N1, H0, U_T, K)) * (1 - 1e-9), 4001)
    n = kynch.step_change_profile(y, t, N0, N1, H0, U_T, K)
    assert n.min() == pytest.approx(N0, abs=1e-12) and n.max() == pytest.approx(N1, abs=1e-12)
    assert np.all(np.diff(n) <= 1e-14)  # porosity falls upward through the fan
    assert np.max(np.abs(np.diff(n))) < 20 * (N1 - N0) / y.size  # no jump
    inside = (y > fr.slow * t) & (y < fr.fast * t)
    assert np.allclose(kynch.wave_speed(n[inside], U_T * N1**K, U_T, K), y[inside] / t, rtol=1e-10)


def test_contraction_profile_is_sharp():
    n0, n1 = 0.73, 0.53
    t = 0.5 * float(kynch.step_change_t1(n0, n1, H0, U_T, K))
    s = float(kynch.step_change_fronts(n0, n1, U_T, K).slow)
    n = kynch.step_change_profile(s * t + np.array([-1e-9, 1e-9]), t, n0, n1, H0, U_T, K)
    assert n.tolist() == [n1, n0]


def test_batch_settling_interfaces_meet_at_deposit_height():
    n0, nd, ut, k = 0.85, 0.45, 2e-3, 4.65
    top, rise = kynch.batch_settling_speeds(n0, nd, ut, k)
    assert top == pytest.approx(ut * n0**k, rel=1e-12)
    assert -top == pytest.approx(kynch.shock_speed(n0, 1.0, 0.0, ut, k), rel=1e-12)
    t_meet = H0 / (top + rise)
    assert rise * t_meet == pytest.approx(H0 * (1 - n0) / (1 - nd), rel=1e-12)


def test_states_below_inflection_are_rejected():
    with pytest.raises(ValueError, match="compound"):
        kynch.step_change_t1(0.3, 0.6, H0, U_T, K)  # n_i = (k-1)/(k+1) = 0.435
