"""The bundled ``immersed-avalanche`` against Pailha, Nicolas & Pouliquen (2008).

The seven initial solid fractions are run once (module fixture) from the bundled case at 20
elements, graded 30:1 towards the base as the case's, with its nonlocal rheology (the determinacy
tests here and in tests/unit/test_avalanche_case.py bound what 40 elements, uniform elements and
halved steps change).
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


_SIGN_071 = ("φ0 = 0.571 contracts: the steady φ_eq(I*) = 0.5723 (φ_c 0.585) lies above it, so its base "
             "pressure stays positive (max 0.07 Pa, measured min -1.26 Pa)")


@pytest.mark.parametrize("phi0", [pytest.param(0.571, marks=pytest.mark.xfail(strict=True, reason=_SIGN_071)), 0.578,
                                  0.588, 0.592])
def test_dense_layer_base_pressure_is_negative_with_its_minimum_within_30_percent_or_half_a_pascal(runs, phi0):
    m = runs[phi0][1]
    model, measured = m["pressure_extremum_Pa"], m["pressure_extremum_measured_Pa"]
    assert model < 0.0
    assert abs(model - measured) <= max(0.3 * abs(measured), 0.5)


@pytest.mark.parametrize("phi0", [0.562, pytest.param(0.571, marks=pytest.mark.xfail(
    strict=True, reason="at φ0 = 0.571 the model contracts and flows at once (onset 0.1 s against 8.6 s)")),
    pytest.param(0.578, marks=pytest.mark.xfail(
        strict=True, reason="φ0 = 0.578 creeps at 0.16 mm/s from the first second (measured 0.10 mm/s) and "
                            "crosses 0.2 mm/s at 22 s against 82 s; its velocity history (rms 0.13) and pressure "
                            "minimum (-2.91 Pa against -2.50 Pa) are met")), 0.588])
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


_RMS_092 = ("φ0 = 0.592: rms 0.45; its basal band (~0.9 mm, 5-6 grains) forms at ~330-400 s, so it is still at "
            "0.01 mm/s at 365 s against 0.18 mm/s measured (its static friction mu_s + K (phi0 - phi_c) = 0.462 is "
            "within 0.004 of tan 25°: it creeps with almost no suction, -0.12 Pa at 20 s against -3.4 Pa); at K = 9, "
            "which 0.584's misfit cannot tell from 9.97 (0.113 against 0.110), the rms is 0.04")


_XFAIL_092 = pytest.mark.xfail(strict=True, reason=_RMS_092)


@pytest.mark.parametrize("phi0", [p if p != 0.592 else pytest.param(p, marks=_XFAIL_092) for p in VALIDATED])
def test_velocity_history_rms_log10_at_most_0_3(runs, phi0):
    assert runs[phi0][1]["rms_log10_velocity"] <= 0.3


def test_calibration_holds_mu_s_on_the_late_plateau_and_k_at_the_end_of_its_search(runs):
    """μ_s: the steady uniform flow of φ0 = 0.568 runs at the measured late plateau (t ≥ 100 s) to
    the fit's resolution, and the run approaches it (end of run within 0.01 decade); K: the rms
    misfit of φ0 = 0.584 falls towards the end of the declared search [1, 10], which the fit reaches
    (within its 0.05 resolution), and is higher at K − 1."""
    case = load_case("immersed-avalanche")
    rh = case["closures"]["granular_rheology"]
    plateau = data.plateau_velocity(0.568)
    assert data.calibrate_mu_s(case) == pytest.approx(rh["mu_s"], abs=5e-4)
    v_steady = data.steady_surface_velocity(case, 0.568)[0]
    assert abs(np.log10(v_steady / plateau)) <= 0.01
    assert abs(np.log10(runs[0.568][0]["v"][-1] / v_steady)) <= 0.01
    k = rh["k_dil"]
    assert 10.0 - 0.05 <= k <= 10.0
    best = runs[0.584][1]["rms_log10_velocity"]
    assert data.metrics(0.584, _run(0.584, k_dil=k - 1.0))["rms_log10_velocity"] > best


def _densest(elements, grading):
    c = load_case("immersed-avalanche")
    c["layer"]["grading"] = grading
    lay = layer_of(c, 0.592, elements)
    states, h = data.member(lay, member_times(c, 0.592), rtol=c["time"]["rtol"], max_step=c["time"]["step"])
    return states, h


def test_densest_layer_pressure_minimum_is_determinate_under_halved_elements(runs):
    """φ0 = 0.592's minimum is made by a shear band at the base; 40 graded elements move it by
    ≤ 5 % (or 0.5 Pa)."""
    _, h = _densest(2 * ELEMENTS, 30.0)
    coarse, fine = runs[0.592][1]["pressure_extremum_Pa"], data.metrics(0.592, h)["pressure_extremum_Pa"]
    assert abs(fine - coarse) <= max(0.05 * abs(coarse), 0.5)


def test_densest_layer_band_is_grains_wide_and_needs_no_grading(runs):
    """The nonlocal rheology gives the basal band a width of its own: at φ0 = 0.592's pressure
    minimum the layer shearing faster than half the largest rate is at least 3 grain diameters
    thick, and 20 uniform elements (0.245 mm, 1.5 d each) give the graded elements' minimum within
    5 %. With the local law the band was 0.06 mm (0.4 d) thick and uniform elements missed its
    minimum by 80 % (-2.86 against -1.57 Pa; docs/avalanche.md)."""
    states, h = _densest(ELEMENTS, 1.0)
    d = load_case("immersed-avalanche")["materials"]["particle_diameter"]
    graded = runs[0.592][1]["pressure_extremum_Pa"]
    uniform = data.metrics(0.592, h)["pressure_extremum_Pa"]
    assert abs(uniform - graded) <= 0.05 * abs(graded)
    at = states[int(np.argmin(h["p"]))]
    fast = at.shear_rate > 0.5 * at.shear_rate.max()
    assert fast[0] and at.z[1:][fast].max() >= 3.0 * d
