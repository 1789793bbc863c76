"""Tests of the Terzaghi consolidation solution and the two-fluid c_v (verification/terzaghi.py).

Tolerances: classical tabulated U(T_v) within 0.5 %; the (π/4)U² approximation
within 1 % for U < 0.6 (measured maximum 0.61 %, at U = 0.6) and 1e-5 for
T_v < 0.1; the two series against each other to 1e-10; finite-difference PDE
residuals to their truncation error.
"""

import numpy as np
import pytest

from twofluid.verification import terzaghi as tz


# classical table (e.g. Craig's Soil Mechanics): T_v to 3 decimals for U = 0.4 ... 0.9
@pytest.mark.parametrize("T,U", [(0.126, 0.4), (0.197, 0.5), (0.287, 0.6), (0.403, 0.7),
                                 (0.567, 0.8), (0.848, 0.9)])
def test_average_degree_matches_classical_table(T, U):
    assert tz.average_degree(T) == pytest.approx(U, rel=5e-3)


def test_classical_square_root_law_for_early_times():
    U = np.linspace(0.02, 0.6, 59)
    T = np.pi / 4 * U**2
    rel = np.abs(tz.average_degree(T) - U) / U
    assert rel.max() < 1e-2
    assert rel[T < 0.1].max() < 1e-5  # image corrections ~ ierfc(1/sqrt(T)) are tiny here
    assert np.allclose(tz.time_factor_classical(U[U < 0.6]), T[U < 0.6], rtol=1e-12)


def test_fourier_and_image_series_agree(monkeypatch):
    z, T = np.linspace(0.0, 1.0, 11)[:, None], np.array([0.03, 0.08, 0.3, 0.6])[None, :]
    u_default, U_default = tz.excess_pressure_ratio(z, T, 1.0, 1.0), tz.average_degree(T)
    monkeypatch.setattr(tz, "_T_SWITCH", 0.01)  # Fourier everywhere
    u_f, U_f = tz.excess_pressure_ratio(z, T, 1.0, 1.0), tz.average_degree(T)
    monkeypatch.setattr(tz, "_T_SWITCH", 10.0)  # images everywhere
    u_i, U_i = tz.excess_pressure_ratio(z, T, 1.0, 1.0), tz.average_degree(T)
    assert np.allclose(u_f, u_i, atol=1e-10) and np.allclose(U_f, U_i, atol=1e-10)
    assert np.allclose(u_default, u_f, atol=1e-10) and np.allclose(U_default, U_f, atol=1e-10)


def test_pressure_satisfies_diffusion_equation_and_boundary_conditions():
    H, cv, t = 2.0, 3e-3, 150.0  # T_v = 0.1125
    z, dz, dt = np.linspace(0.1, 1.9, 10), 1e-3, 1e-2
    u = lambda zz, tt: tz.excess_pressure_ratio(zz, tt, H, cv)  # noqa: E731
    u_t = (u(z, t + dt) - u(z, t - dt)) / (2 * dt)
    u_zz = (u(z + dz, t) - 2 * u(z, t) + u(z - dz, t)) / dz**2
    assert np.allclose(u_t, cv * u_zz, atol=1e-8)  # FD errors ~ 1e-9 here
    assert abs(u(0.0, t)) < 1e-12
    assert abs((u(H, t) - u(H - dz, t)) / dz) < 1e-3  # one-sided O(dz) slope at the base


def test_average_of_pressure_is_one_minus_degree():
    zeta = np.linspace(0.0, 1.0, 4001)
    for T in (0.01, 0.05, 0.2, 0.7):
        mean_u = np.trapezoid(tz.excess_pressure_ratio(zeta, T, 1.0, 1.0), zeta)
        assert mean_u == pytest.approx(1.0 - float(tz.average_degree(T)), abs=1e-6)


def test_initial_state_and_truncation_tolerance():
    u0 = tz.excess_pressure_ratio(np.array([0.0, 0.5, 1.0]), 0.0, 1.0, 1.0)
    assert u0.tolist() == [0.0, 1.0, 1.0]
    z, T = np.linspace(0, 1, 21)[:, None], np.array([0.003, 0.05, 0.1, 0.15, 1.0])
    tight = tz.excess_pressure_ratio(z, T, 1.0, 1.0, tol=1e-15)
    U_tight = tz.average_degree(T, tol=1e-15)
    for tol in (1e-2, 1e-4, 1e-8):
        assert np.max(np.abs(tz.excess_pressure_ratio(z, T, 1.0, 1.0, tol=tol) - tight)) < tol
        assert np.max(np.abs(tz.average_degree(T, tol=tol) - U_tight)) < tol


def test_time_factor():
    assert tz.time_factor(3600.0, 2e-6, 0.5) == pytest.approx(2e-6 * 3600 / 0.25, rel=1e-12)


def _p_s(n, n_bar, A):  # Pringle (2001) eq. 3.54, p_ref = 1 Pa, written out independently
    return np.exp((1 - (1 - n_bar) / (1 - n)) / A)


def test_constrained_modulus_is_derivative_wrt_volumetric_strain():
    n, n_bar, A, h = 0.42, 0.45, 0.015, 1e-7
    # dε_v = -dn/(1-n): M = dP_s/dε_v = -(1-n) dP_s/dn
    dPdn = (_p_s(n + h, n_bar, A) - _p_s(n - h, n_bar, A)) / (2 * h)
    M_fd = -(1 - n) * dPdn
    assert tz.constrained_modulus(_p_s(n, n_bar, A), n, n_bar, A) == pytest.approx(M_fd, rel=1e-6)


def test_two_fluid_cv_equals_soil_mechanics_form():
    n, n_bar, A, beta, rho_f, g = 0.42, 0.45, 0.015, 2.5e6, 1000.0, 9.81
    P_s = _p_s(n, n_bar, A)
    k = rho_f * g * n**2 / beta  # hydraulic conductivity [m/s] (docs/model.md, Drag)
    M = tz.constrained_modulus(P_s, n, n_bar, A)
    assert tz.consolidation_coefficient(n, n_bar, P_s, A, beta) == pytest.approx(k * M / (rho_f * g), rel=1e-12)
