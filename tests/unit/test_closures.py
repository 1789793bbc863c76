"""Closures: every registry entry, hand values, Richardson–Zaki identity, limits."""
import numpy as np
import pytest

from twofluid.closures import drag, registry, solids_pressure, viscosity

N = np.linspace(0.36, 1.0, 33)


@pytest.mark.parametrize("name", ["ergun", "wen_yu", "gidaspow"])
@pytest.mark.parametrize("stokes", [True, False])
def test_every_drag_law_is_finite_positive_and_vectorised(name, stokes):
    law = registry.get("drag", name).func
    slip = np.linspace(0.0, 0.1, N.size)
    beta = law(N, slip, 3e-4, 1000.0, 1e-3, stokes=stokes)
    k = law(N, slip, 3e-4, 1000.0, 1e-3, stokes=stokes, per_solids=True)
    assert beta.shape == N.shape and np.all(np.isfinite(k)) and np.all(k[:-1] > 0)
    if name != "ergun":  # Ergun alone is a dense-bed law: its β/(1−n) vanishes in clear liquid
        assert k[-1] > 0
    np.testing.assert_allclose(beta, (1 - N) * k, rtol=1e-14)
    assert beta[-1] == 0.0  # no drag in clear liquid, but β/(1−n) stays finite there


def test_stokes_wen_yu_gives_richardson_zaki_exactly():
    d, rs, rf, mu = 1e-4, 2500.0, 1000.0, 1e-3
    ut = (rs - rf) * 9.81 * d * d / (18 * mu)
    for n in (0.45, 0.6, 0.75, 0.9, 0.99):
        u = drag.steady_fluidization_velocity(drag.wen_yu, n, d, rs, rf, mu, stokes=True)
        assert u == pytest.approx(ut * n ** 4.65, rel=1e-10)


def test_ergun_inertial_term_matches_hand_value():
    # 1.75 (1 − n) ρ_f |s| / d with n = 0.5, s = 0.02, d = 1 mm: no extra 1/n (correction 3, docs/model.md)
    b = drag.ergun(0.5, 0.02, 1e-3, 1000.0, 1e-3) - drag.ergun(0.5, 0.02, 1e-3, 1000.0, 1e-3, stokes=True)
    assert b == pytest.approx(1.75 * 0.5 * 1000 * 0.02 / 1e-3, rel=1e-12)


def test_schiller_naumann_switches_at_re_1000():
    cd = drag.schiller_naumann_cd(np.array([999.999, 1000.0])) / np.array([999.999, 1000.0])
    assert cd[1] == pytest.approx(0.44)
    assert cd[0] == pytest.approx(24 / 999.999 * (1 + 0.15 * 999.999 ** 0.687), rel=1e-12)


def test_stokes_ergun_conductivity_is_kozeny_carman():
    n, d, mu, rf = 0.4, 1e-3, 1e-3, 1000.0
    beta = drag.ergun(n, 0.0, d, rf, mu, stokes=True)
    k = drag.hydraulic_conductivity(beta, n, rf)
    assert k == pytest.approx(rf * 9.81 / mu * d * d * n ** 3 / (150 * (1 - n) ** 2), rel=1e-12)


def test_blend_is_continuous_and_exact_outside_band():
    n = np.linspace(0.55, 0.65, 2001)
    b = drag.gidaspow(n, 0.01, 3e-4, 1000.0, 1e-3, blend_width=0.02)
    assert np.max(np.abs(np.diff(b))) / b.max() < 2e-3
    far = np.array([0.5, 0.7])
    np.testing.assert_allclose(drag.gidaspow(far, 0.01, 3e-4, 1000.0, 1e-3, blend_width=0.02),
                               [drag.ergun(0.5, 0.01, 3e-4, 1000., 1e-3), drag.wen_yu(0.7, 0.01, 3e-4, 1000., 1e-3)])


def test_mooney_viscosity_blend_continuous_increasing_and_one_at_zero():
    n = np.linspace(0.5, 1.0, 5001)
    mu = viscosity.mooney_pringle(n, 1.0)
    assert mu[-1] == pytest.approx(1.0)
    assert np.all(np.diff(mu) < 0)  # decreasing in n = increasing in solids fraction
    i = np.searchsorted(n, 0.8)
    assert abs(mu[i] - mu[i - 1]) < 1e-2  # continuous at the blend point ε_s = 0.2
    eps = 0.3
    assert viscosity.mooney_pringle(1 - eps, 1.0) == pytest.approx(np.exp(np.exp(eps / (1.1721 - 1.7172 * eps))))


def test_solid_viscosity_limit_in_clear_liquid():
    n = 1 - np.logspace(-5, -9, 5)
    mus = viscosity.solid_viscosity(n, 1e-3)
    np.testing.assert_allclose(mus, 3.5e-3, rtol=5e-3)


def test_solids_pressure_derivative_matches_finite_difference():
    n = np.linspace(0.41, 0.6, 20)
    p, dp = solids_pressure.exponential(n, 0.45, 0.015, derivative=True)
    h = 1e-7
    fd = (solids_pressure.exponential(n + h, 0.45, 0.015) - solids_pressure.exponential(n - h, 0.45, 0.015)) / (2 * h)
    np.testing.assert_allclose(dp, fd, rtol=1e-5)


def test_registry_lists_closures_with_summaries():
    for entry in registry.entries():
        assert entry.summary, entry.name
        assert callable(entry.func)
    with pytest.raises(KeyError, match="choose one of"):
        registry.get("drag", "nonexistent")


def test_terminal_velocity_is_stokes_law_in_the_stokes_limit_and_lower_with_inertia():
    d, rho_s, rho_f, mu = 0.3e-3, 2600.0, 998.2, 1.002e-3
    stokes = drag.terminal_velocity(drag.wen_yu, d, rho_s, rho_f, mu, stokes=True)
    assert stokes == pytest.approx((rho_s - rho_f) * 9.81 * d**2 / (18 * mu), rel=1e-10)
    full = drag.terminal_velocity(drag.wen_yu, d, rho_s, rho_f, mu)
    re = rho_f * full * d / mu
    cd = 24 / re * (1 + 0.15 * re**0.687)
    # force balance of one sphere: C_D (π d²/4) ρ_f U²/2 = (ρ_s − ρ_f) g π d³/6
    assert cd * 0.75 * rho_f * full**2 / d == pytest.approx((rho_s - rho_f) * 9.81, rel=1e-9)
    assert full < stokes


def test_saturated_slip_is_increasing_bounded_and_identity_for_small_slip():
    s = np.logspace(-6, 6, 400)
    eff = drag.saturated_slip(s, 1.0)
    assert np.all(np.diff(eff) >= 0) and np.all(np.diff(eff[s < 100]) > 0) and eff.max() <= 1.0
    assert eff[s < 0.1] == pytest.approx(s[s < 0.1], rel=3e-5)
    assert np.array_equal(drag.saturated_slip(s, np.inf), s)


def test_foscolo_gibilaro_pressure_integrates_its_modulus():
    """P_e(1) = 0 and −∂P_e/∂n = E = 3.2 g d (ρ_s − ρ_f)(1 − n): central differences and the integral."""
    n = np.linspace(0.4, 1.0, 61)
    args = (4e-3, 1140.0, 998.2, 9.81)
    p, dp = solids_pressure.foscolo_gibilaro(n, *args, derivative=True)
    modulus = 3.2 * 9.81 * 4e-3 * (1140.0 - 998.2) * (1.0 - n)
    np.testing.assert_allclose(-dp, modulus, rtol=1e-12)
    h = 1e-6
    fd = (solids_pressure.foscolo_gibilaro(n[:-1] + h, *args) - solids_pressure.foscolo_gibilaro(n[:-1] - h, *args)) / (2 * h)
    np.testing.assert_allclose(fd, dp[:-1], rtol=1e-6)
    assert p[-1] == 0.0 and np.all(np.diff(p) < 0)


def test_case_key_adds_the_fluidized_pressure_to_the_models_ps():
    from twofluid.casefile.builder import build
    from twofluid.casefile.loader import load_case

    case = load_case("slis-step-change")
    on = build(case).model
    case["closures"]["solids_pressure"]["fluidized"] = "none"
    off = build(case).model
    n, nb = np.array([0.5, 0.7, 1.0]), np.full(3, 0.4)
    pe = solids_pressure.foscolo_gibilaro(n, 3e-3, 1140.0, 998.2, 9.81)
    np.testing.assert_allclose(on.solids_pressure(n, nb) - off.solids_pressure(n, nb), pe, rtol=1e-12)
    d_on, d_off = on.solids_pressure(n, nb, derivative=True)[1], off.solids_pressure(n, nb, derivative=True)[1]
    np.testing.assert_allclose(d_on - d_off, solids_pressure.foscolo_gibilaro(n, 3e-3, 1140.0, 998.2, 9.81,
                                                                             derivative=True)[1], rtol=1e-12)
