"""The bundled ``immersed-avalanche`` against Pailha, Nicolas & Pouliquen (2008).

The seven initial solid fractions are run once (module fixture) from the bundled case at 20
elements (the determinacy test of tests/unit/test_avalanche_case.py bounds what 40 changes).
Calibrated: φ0 = 0.568 (μ_s) and 0.584 (K); validated: the other five, with nothing fitted.
Velocities are floored at 0.02 mm/s on both sides and compared at the data's times
(:func:`twofluid.verification.pailha2008.metrics`).

Criteria the model does not meet are marked ``xfail(strict=True)`` with the numbers it gives:
they are recorded, not loosened, and the mark fails the suite once the model meets them.
"""
import numpy as np
import pytest

from twofluid.casefile.loader import load_case
from twofluid.runners.avalanche import layer_of, member_times
from twofluid.verification import pailha2008 as data

VALIDATED = (0.562, 0.571, 0.578, 0.588, 0.592)
ELEMENTS = 20


def _run(phi0, **rheology):
    c = load_case("immersed-avalanche")
    c["closures"]["granular_rheology"].update(rheology)
    lay = layer_of(c, phi0, ELEMENTS)
    _, h = data.member(lay, member_times(c, phi0), rtol=c["time"]["rtol"], max_step=c["time"]["step"])
    return h


@pytest.fixture(scope="module")
def runs():
    out = {}
    for phi0 in data.PHI0:
        h = _run(phi0)
        out[phi0] = (h, data.metrics(phi0, h))
    return out


def test_loose_layer_flows_at_once_with_its_pressure_peak_within_30_percent(runs):
    m = runs[0.562][1]
    assert m["onset_s"] is not None and m["onset_s"] <= 10.0
    assert abs(m["pressure_extremum_Pa"] - m["pressure_extremum_measured_Pa"]) <= 0.3 * m["pressure_extremum_measured_Pa"]


_DENSE_FAILS = "dilation too slow: minimum base pressure about half the measured one (0.571 stays positive)"


@pytest.mark.parametrize("phi0", [pytest.param(p, marks=pytest.mark.xfail(strict=True, reason=_DENSE_FAILS))
                                  for p in (0.571, 0.578, 0.588, 0.592)])
def test_dense_layer_base_pressure_is_negative_with_its_minimum_within_30_percent_or_half_a_pascal(runs, phi0):
    m = runs[phi0][1]
    model, measured = m["pressure_extremum_Pa"], m["pressure_extremum_measured_Pa"]
    assert model < 0.0
    assert abs(model - measured) <= max(0.3 * abs(measured), 0.5)


@pytest.mark.parametrize("phi0", [0.562, pytest.param(0.571, marks=pytest.mark.xfail(
    strict=True, reason="at φ0 = 0.571 the model contracts and flows at once (onset 0.1 s against 8.6 s)")),
    0.578, 0.588])
def test_onset_within_a_factor_of_two(runs, phi0):
    m = runs[phi0][1]
    assert m["onset_s"] is not None
    assert 0.5 <= m["onset_s"] / m["onset_measured_s"] <= 2.0


def test_densest_layer_stays_below_onset_until_365_s_as_the_censored_data(runs):
    h = runs[0.592][0]
    assert h["t"][-1] >= 365.0 and np.all(h["v"][(h["t"] >= data.ONSET_AFTER_S) & (h["t"] <= 365.0)] <= data.ONSET_M_S)


def test_onsets_come_in_the_measured_order(runs):
    onsets = [runs[p][1]["onset_s"] for p in data.PHI0]
    key = [np.inf if o is None else o for o in onsets]
    assert all(a <= b for a, b in zip(key, key[1:])), onsets


@pytest.mark.parametrize("phi0", VALIDATED)
def test_velocity_history_rms_log10_at_most_0_3(runs, phi0):
    assert runs[phi0][1]["rms_log10_velocity"] <= 0.3


def test_calibration_holds_mu_s_on_the_late_plateau_and_k_at_its_minimum(runs):
    """μ_s: the late (t ≥ 100 s) mean log10 velocity misfit of φ0 = 0.568 is zero to the fit's
    resolution (0.01 decade); K: the rms misfit of φ0 = 0.584 is no lower at K ± 1."""
    d = data.load(0.568)
    h = runs[0.568][0]
    late = d["v_t"] >= data.PLATEAU_S
    misfit = np.mean(np.log10(np.interp(d["v_t"][late], h["t"], h["v"]) / d["v"][late]))
    assert abs(misfit) <= 0.01
    k = load_case("immersed-avalanche")["closures"]["granular_rheology"]["k_dil"]
    best = runs[0.584][1]["rms_log10_velocity"]
    for other in (k - 1.0, k + 1.0):
        assert data.metrics(0.584, _run(0.584, k_dil=other))["rms_log10_velocity"] >= best - 1e-4
