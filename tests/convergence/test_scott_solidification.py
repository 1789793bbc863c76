"""Scott's (1986) solidification of a liquefied sand column against the theory
(:mod:`twofluid.verification.scott`; set-up, definitions and tolerances in
:mod:`twofluid.verification.scott_check`)."""
import numpy as np
import pytest

from twofluid.verification import scott, scott_check as sc
from twofluid.verification.order import observed_order

LEVELS = (20, 40, 80, 160)


def test_rigid_limit_is_scotts_linear_solution():
    c = scott.ScottColumn(1.0, 0.46, 0.42, 0.0, 7.78e-4, 16186.5)
    vs, vf = c.settling_velocity, c.front_speed_rigid
    t = np.linspace(0.0, 0.99, 7) * c.end_time
    assert np.allclose(c.front(t, level=0.44), vf * t, rtol=1e-12, atol=1e-15)
    assert np.allclose(c.settlement(t), vs * t, rtol=1e-15)
    assert c.end_time == pytest.approx(1.0 / (vs + vf), rel=1e-12)
    assert c.final_settlement == pytest.approx(0.04 / 0.58, rel=1e-12)
    assert np.allclose(c.base_excess_pressure(t), 16186.5 * 0.54 * (1.0 - (vs + vf) * t), rtol=1e-10)
    assert np.allclose(c.fixed_surface_settlement(t), c.c * vs * t, rtol=1e-12)
    # the drained solution tends to it as A -> 0 (its compression is A ln(sigma/p_ref), so slowly)
    e = [abs(scott.ScottColumn(1.0, 0.46, 0.42, A, 7.78e-4, 16186.5).end_time - c.end_time) for A in (1e-3, 1e-4, 1e-5)]
    assert e[0] > e[1] > e[2] and e[2] < 2e-3 * c.end_time


def test_theory_conserves_solids():
    c = scott.ScottColumn(1.0, 0.46, 0.42, 1e-3, 7.78e-4, 16186.5)
    t = np.linspace(0.05, 0.95, 10) * c.end_time
    deposit = (c.base_stress(t) - c.liquefied_pressure) / c.buoyant_unit_weight  # solids volume per area
    suspension = (1.0 - c.porosity) * (c.surface(t) - c.front(t, level=c.porosity))
    assert np.allclose(deposit + suspension, (1.0 - c.porosity) * c.height, rtol=1e-10)
    # the front meets the surface at t_end
    assert float(c.front(c.end_time, level=c.porosity)) == pytest.approx(float(c.surface(c.end_time)), rel=1e-9)


@pytest.fixture(scope="module")
def study():
    return [sc.eulerian_run(sc.A_CHECK, N) for N in LEVELS]


def test_front_and_settlement_within_tolerance(study):
    for r in study:
        th, h, dt = r["theory"], r["h"], r["dt"]
        t = r["t"][:-1]
        ef = np.abs(r["front"][:-1] - th.front(t))
        es = np.abs((1.0 - r["surface"][:-1]) - th.settlement(t))
        assert ef.max() <= h + th.front_speed_rigid * dt, (h, ef)
        assert es.max() <= h + th.settling_velocity * dt, (h, es)
        assert abs((1.0 - r["surface"][-1]) - th.final_settlement) <= 0.5 * h


def test_front_and_settlement_converge_at_first_order(study):
    h = [r["h"] for r in study]
    ef = [np.max(np.abs(r["front"][:-1] - r["theory"].front(r["t"][:-1]))) for r in study]
    es = [np.max(np.abs((1.0 - r["surface"][:-1]) - r["theory"].settlement(r["t"][:-1]))) for r in study]
    # first-order schemes (upwind solids flux, backward Euler at a fixed Courant number)
    for e in (ef, es):
        o = observed_order(h, e)
        assert 0.8 <= o.rate <= 1.3, (e, o)


def test_pore_pressure_lag_vanishes_with_compressibility():
    """Scott's observation: the excess pore pressure lags the drained (rigid-grain) value because the
    accreting layer consolidates; the lag is of the order of the consolidation number, linear in A."""
    As = (3e-3, 1e-3, 3e-4)
    lag = []
    for A in As:
        r = sc.eulerian_run(A, 160)
        th = r["theory"]
        i = 4  # t = 0.5 t_end
        u0 = th.base_stress_end - th.liquefied_pressure
        lag.append((r["u_base"][i] - th.base_excess_pressure(r["t"][i])) / u0)
        assert 0.0 < lag[-1] <= 2.0 * th.consolidation_number + 0.01, (A, lag)
    o = observed_order(As, lag)
    assert o.rate >= 0.7, (lag, o)


def test_liquefaction_column_follows_the_fixed_surface_theory():
    rows = sc.liquefaction_column_rows()
    assert all(r["pass"] for r in rows), rows
    th = sc.column_run(elements=20)["theory"]
    # its small-strain kinematics: rate (1 - n_l)/(1 - n_bar) of the true one, same final settlement
    assert th.fixed_surface_end_time / th.end_time == pytest.approx(1.0 / th.c, rel=0.02)
    assert float(th.fixed_surface_settlement(th.fixed_surface_end_time)) == pytest.approx(th.final_settlement, rel=1e-3)


def test_check_rows_pass():
    rows = sc.solidification_rows()
    assert len(rows) == 6 and all(r["pass"] for r in rows), rows
