"""The flow of a sloping column after the shaking: the shear wave runs on while the column
flows and stops when it has stopped (``[shear_wave] flow_velocity``, ``flow_window``, ``flow_max``,
``flow_step``).

Compared quantities, each with its definition:

- the window-mean velocity v̄ = (D̄(t − T, t) − D̄(t − 2T, t − T))/T of a synthetic history, a
  constant drift plus a decaying oscillation, against the drift (the oscillation's share is bounded
  by 2A/(π f T²), the tolerance; a pure oscillation gives |v̄| within it);
- a flow slide (the bundled sloping site at 5 %, FS_post < 1 in the loose sand, 4 s of shaking): the
  surface displacement keeps growing after the shaking, the flow stops by itself before flow_max
  (the excess pore pressure dissipates and the strength returns), and the displacement does not
  change after the shear wave stops; flow liquefaction, not cyclic mobility: the localisation
  element's strain passes the limiting strain γ_lim at which the law's dilation would have held it
  (measured: 5.76 against γ_lim = 0.75; 0.29 m during the shaking, 5.96 m in all); halving the flow step
  changes the final displacement by at most 1 % (measured: 2.3e-4, 0.1 against 0.05 s);
- level ground: the flow keys change nothing (the shear wave stops at free_vibration, the run is
  the same to the last bit).
"""
import copy
import math
import re
import warnings

import numpy as np
import pytest

from twofluid.casefile.loader import case_text
from twofluid.cli import main
from twofluid.models.liquefaction_1d import FlowStop
from twofluid.models.shear_column import WaveState
from twofluid.runners.common import run_case
from twofluid.runners.liquefaction import build_column
from slope_cases import CASE, sloping_case as _case


def _run(c):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return run_case(c)


def test_window_mean_velocity_sees_the_drift_not_the_ringing():
    """A ring-down of ±0.2 mm at 1.7 Hz (velocity amplitude 2.1 mm/s, as the bundled site's) on a
    creep of 0.1 mm/s: the window mean finds the creep within 2A/(π f T²) = 19 µm/s."""
    c = _case(ground_motion__duration=2.0)
    col = build_column(c).column
    assert col.flow is not None and col.flow.window == 2.0
    drift, amp, f, T = 1e-4, 2e-4, 1.7, col.flow.window
    bound = 2.0 * amp / (math.pi * f * T * T)
    assert bound < 0.2 * drift and 2 * math.pi * f * amp > 20 * drift
    t = np.arange(0.0, 12.0, 0.01)
    for with_drift in (True, False):
        d = amp * np.sin(2 * math.pi * f * t) * np.exp(-0.05 * t) + (drift * t if with_drift else 0.0)
        col._flow_t, col._flow_d = list(t), list(d)
        v = col.flow_velocity(11.0)
        assert abs(v - (drift if with_drift else 0.0)) <= bound
    assert col.flow_velocity(col.shaking_end + 2 * T - 0.1) is None  # the windows need 2T after the shaking


@pytest.fixture(scope="module")
def flow_slide():
    """The sloping site at 5 %: FS_post < 1 in the loose sand, so it flows after the shaking."""
    c = _case(ground_motion__duration=4.0, time__end=200.0, site__slope=5.0)
    c["shear_wave"]["free_vibration"] = 4.0
    return c, _run(c)


def test_a_flow_slide_flows_after_the_shaking_and_stops_as_strength_returns(flow_slide):
    c, r = flow_slide
    sl = r.summary["slope"]
    loose = next(la for la in sl["layers"] if la["name"] == "loose sand")
    assert loose["flow_slide"] and loose["FS_post_min"] < 1.0
    f = sl["flow_after_shaking"]
    assert f["flow_stopped"] and not sl["still_moving_when_shear_wave_stopped"]
    end = r.summary["shaking"]["shear_wave_end_s"]
    assert end == pytest.approx(f["shear_wave_end_s"])
    # it ran past free_vibration because the column flowed, and stopped before flow_max
    assert c["ground_motion"]["duration"] + c["shear_wave"]["free_vibration"] < end
    assert end < c["ground_motion"]["duration"] + c["shear_wave"]["flow_max"]
    assert abs(f["flow_velocity_end_m_s"]) < c["shear_wave"]["flow_velocity"]
    d, d_s = sl["surface_displacement_end_m"], sl["surface_displacement_end_of_shaking_m"]
    assert d > 2.0 * d_s > 0.0  # most of it after the shaking
    assert sl["share_after_shaking"] == pytest.approx((d - d_s) / d, rel=1e-12)
    assert d == pytest.approx(sl["surface_displacement_end_of_shear_wave_m"], rel=1e-12)
    assert f["time_99_percent_s"] < end
    # flow liquefaction: no dilation downslope, so the strain runs past γ_lim (cyclic mobility's bound)
    from twofluid.closures import hysteretic as law
    col = build_column(c).column
    depth = sl["localisation"]["depth_m"]
    e = int(np.argmin(np.abs(np.asarray(col.depth_all) - depth)))
    assert sl["localisation"]["shear_strain_from_static"] > 2.0 * col.hysteretic[e, law.P_GLIM]


def test_halving_the_flow_step_converges(flow_slide):
    c, r = flow_slide
    c2 = copy.deepcopy(c)
    c2["shear_wave"]["flow_step"] = 0.5 * c["shear_wave"]["flow_step"]
    d1 = r.summary["slope"]["surface_displacement_end_m"]
    d2 = _run(c2).summary["slope"]["surface_displacement_end_m"]
    assert abs(d2 / d1 - 1.0) <= 0.01, (d1, d2)


def test_without_the_criterion_the_shear_wave_stops_at_free_vibration_and_says_it_moved(flow_slide):
    c, r = flow_slide
    c2 = copy.deepcopy(c)
    c2["shear_wave"]["flow_velocity"] = 0.0
    r2 = _run(c2)
    assert r2.summary["shaking"]["shear_wave_end_s"] == pytest.approx(
        c["ground_motion"]["duration"] + c["shear_wave"]["free_vibration"])
    sl = r2.summary["slope"]
    assert sl["flow_after_shaking"] is None and sl["still_moving_when_shear_wave_stopped"]
    assert sl["surface_displacement_end_m"] < r.summary["slope"]["surface_displacement_end_m"]


def test_level_ground_is_unaffected_by_the_flow_keys():
    base = _case(ground_motion__duration=3.0, time__end=40.0, site__slope=0.0, output__times=[10.0])
    base["shear_wave"]["free_vibration"] = 2.0
    col = build_column(base).column
    assert col.flow is None and col.shear_end == pytest.approx(5.0)
    off = copy.deepcopy(base)
    off["shear_wave"]["flow_velocity"] = 0.0
    off["shear_wave"]["flow_step"] = 0.5
    a, b = _run(base), _run(off)
    for key in ("steps", "shear_substeps", "settlement_end_m", "stopped_at_s"):
        assert a.summary[key] == b.summary[key], key
    assert a.summary["shaking"]["shear_wave_end_s"] == pytest.approx(5.0)
    assert "slope" not in a.summary


def test_flow_decision_stops_at_flow_max():
    c = _case(ground_motion__duration=2.0)
    c["shear_wave"]["free_vibration"] = 4.0
    col = build_column(c).column
    col.flow = FlowStop(velocity=1e-5, window=1.0, max_after=6.0, step=0.05)
    col.flow_end_max = col.shaking_end + 6.0
    ne = col.wave.h.size
    for t in np.arange(0.05, 8.0001, 0.05):  # a steady creep of 1 mm/s: never stops by itself
        u = np.zeros(ne + 1)
        u[-1] = 1e-3 * t
        col._flow_decide(float(t), WaveState(float(t), u, u, u, u[:-1], u[:-1]))
        if col.shear_end <= t + 1e-9:
            break
    assert col.shear_end == pytest.approx(8.0) and col.flow_stopped is False
    assert col.flow_velocity_end == pytest.approx(1e-3, rel=1e-9)


@pytest.mark.parametrize("key, value", [("flow_velocity", "-1e-5"), ("flow_velocity", "0.5"),
                                        ("flow_window", "0.0"), ("flow_window", "100.0"),
                                        ("flow_max", "-1.0"), ("flow_step", "0.0"), ("flow_step", "2.0"),
                                        ("flow_step", "\"x\"")])
def test_bad_flow_keys_are_one_line_and_exit_2(key, value, tmp_path, capsys):
    text = case_text(CASE)
    if re.search(rf"^{key} = ", text, flags=re.M):
        text = re.sub(rf"^{key} = [^ ]+", f"{key} = {value}", text, count=1, flags=re.M)
    else:
        text = text.replace("[shear_wave]\n", f"[shear_wave]\n{key} = {value}\n")
    assert f"{key} = {value}" in text
    path = tmp_path / "case.toml"
    path.write_text(text)
    assert main(["run", str(path), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and f"[shear_wave] {key}" in err, err
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("slope, warned", [("0.0", True), ("3.0", False)])
def test_flow_keys_on_level_ground_warn_that_they_are_ignored(slope, warned, tmp_path):
    """The flow keys act on a sloping site only: given on level ground they are a CaseWarning naming
    them (as other keys without effect); on a slope, or left at their defaults, no such warning."""
    from twofluid.casefile.loader import load_case
    from twofluid.casefile.schema import CaseWarning

    text = case_text(CASE).replace("slope = 3.0", f"slope = {slope}")
    text = re.sub(r"^flow_velocity = [^ ]+", "flow_velocity = 2.0e-5", text, count=1, flags=re.M)
    text = text.replace("[shear_wave]\n", "[shear_wave]\nflow_step = 0.05\n")
    path = tmp_path / "case.toml"
    path.write_text(text)
    with warnings.catch_warnings(record=True) as got:
        warnings.simplefilter("always")
        load_case(str(path))
    flow = [str(w.message) for w in got if issubclass(w.category, CaseWarning) and "level ground" in str(w.message)
            and "[shear_wave] flow_" in str(w.message)]  # (the case's distance_km warns of its own on level ground)
    if warned:
        assert len(flow) == 1 and "[shear_wave] flow_step, flow_velocity, flow_window: ignored on level ground" in flow[0], flow
    else:
        assert flow == []
    with warnings.catch_warnings(record=True) as got:  # the defaults alone: nothing to warn of
        warnings.simplefilter("always")
        load_case("liquefaction-layered-site")
    assert not [w for w in got if "level ground" in str(w.message)]


def test_a_run_that_ends_while_the_column_flows_says_so():
    c = _case(ground_motion__duration=4.0, time__end=12.0, site__slope=5.0, output__times=[10.0])
    c["shear_wave"]["free_vibration"] = 4.0
    r = _run(c)
    sl = r.summary["slope"]
    f = sl["flow_after_shaking"]
    assert not f["flow_stopped"] and "end of the run" in f["shear_wave_stopped_by"]
    assert sl["still_moving_when_shear_wave_stopped"] and "raise [time] end" in sl["note"]
    assert r.summary["shaking"]["shear_wave_end_s"] == pytest.approx(12.0)
