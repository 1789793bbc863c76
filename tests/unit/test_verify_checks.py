"""Verification checks at cheap settings (the full ones run in `twofluid verify`)."""
import pytest

from twofluid.verification import kynch_check, order_check, properties_check, terzaghi_check


def _all_pass(rows):
    bad = [r for r in rows if not r["pass"]]
    assert not bad, bad
    return rows


def test_kynch_contraction_t1_and_front_speeds():
    rows = _all_pass(kynch_check.step_change_rows(0.80, 0.70, dx=2e-3, dt=0.1))
    assert [r["quantity"] for r in rows] == ["t1", "surface speed U1 − U0", "shock speed"]
    assert all(r["tolerance"] == 0.03 for r in rows)


def test_kynch_expansion_front_speeds():
    _all_pass(kynch_check.step_change_rows(0.70, 0.80, dx=2e-3, dt=0.1, with_t1=False))


def test_kynch_settling_interface():
    _all_pass(kynch_check.settling_rows(dx=2e-3, dt=0.1))


@pytest.mark.parametrize("model, elements", [("reduced_1d", 100), ("two_fluid_1d", 50)])
def test_terzaghi_degree_of_consolidation(model, elements):
    rows = _all_pass(terzaghi_check.consolidation_rows(elements=elements, model=model))
    assert len(rows) == len(terzaghi_check.T_V) and all(r["tolerance"] == 0.02 for r in rows)


@pytest.mark.parametrize("model", ["two_fluid_1d", "reduced_1d"])
def test_hydrostatic_consistency(model):
    _all_pass(properties_check.hydrostatic_rows(model))


def test_gauge_invariance_and_conservation():
    _all_pass(properties_check.gauge_rows("fluidized-bed-step", "two_fluid_1d", 2.0))
    _all_pass(properties_check.gauge_rows("settling-illite", "reduced_1d", 20.0))
    _all_pass(properties_check.conservation_rows("settling-illite", "reduced_1d", 20.0))


def test_observed_order_in_space_and_time():
    _all_pass(order_check.space_rows(levels=(50, 100, 200), ref=1600)[:1])
    _all_pass(order_check.time_rows(divs=(10, 20, 40), ref=320, elements=100)[:1])
