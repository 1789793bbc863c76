"""The bundled case ``immersed-avalanche``: bad values of its keys, a short run's files and balances,
and the determinacy of the onset and the pressure extremum."""
import json
import re

import numpy as np
import pytest

from twofluid.casefile.loader import case_text, load_case
from twofluid.cli import main
from twofluid.runners.avalanche import layer_of
from twofluid.runners.common import run_case
from twofluid.verification import pailha2008 as data

CASE = "immersed-avalanche"


def _edit(section: str, key: str, value: str) -> str:
    """The bundled case with ``key = value`` in ``[section]`` (replaced, or added under the header)."""
    return _edit_text(case_text(CASE), section, key, value)


def _edit_text(text: str, section: str, key: str, value: str) -> str:
    """``text`` with ``key = value`` in ``[section]`` (replaced, or added under the header)."""
    head = f"[{section}]\n"
    start = text.index(head) + len(head)
    end = text.find("\n[", start)
    end = len(text) if end < 0 else end
    body = text[start:end]
    line = re.compile(rf"^{key} = .*$", re.M)
    body = line.sub(f"{key} = {value}", body) if line.search(body) else f"{key} = {value}\n" + body
    return text[:start] + body + text[end:]


BAD = [("layer", "thickness", "0.0"), ("layer", "thickness", "nan"), ("layer", "elements", "1"), ("layer", "grading", "0.5"),
       ("layer", "slope_deg", "60.0"), ("layer", "slope_deg", "-1.0"), ("layer", "solid_fractions", "[0.2]"),
       ("layer", "solid_fractions", "[]"), ("layer", "skeleton_modulus", "0.0"), ("layer", "top", '"open"'),
       ("closures.granular_rheology", "law", '"mu_i"'), ("closures.granular_rheology", "mu_s", "0.0"),
       ("closures.granular_rheology", "mu_2", "0.3"), ("closures.granular_rheology", "i_0", "-0.1"),
       ("closures.granular_rheology", "phi_c", "0.8"), ("closures.granular_rheology", "k_dil", "-1.0"),
       ("closures.granular_rheology", "amplitude", "0.0"), ("closures.granular_rheology", "amplitude", "11.0"),
       ("closures.permeability", "law", '"ergun"'), ("closures.permeability", "constant", "0.0"),
       ("time", "end", "0.0"), ("time", "rtol", "0.1"), ("time", "step", "0.0"),
       ("output", "times", "[-1.0]"), ("output", "samples", "2"), ("output", "compare", '"yes"')]


@pytest.mark.parametrize("section,key,value", BAD, ids=[f"{s}.{k}={v}" for s, k, v in BAD])
def test_bad_value_is_one_line_and_exit_2(section, key, value, tmp_path, capsys):
    path = tmp_path / "case.toml"
    path.write_text(_edit(section, key, value))
    assert main(["run", str(path), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and key in err and "Traceback" not in err, err
    assert not (tmp_path / "out").exists()


def test_a_solid_fraction_without_data_is_refused_when_comparing(tmp_path, capsys):
    path = tmp_path / "case.toml"
    path.write_text(_edit("layer", "solid_fractions", "[0.575]"))
    assert main(["run", str(path), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "[layer] solid_fractions" in err and "0.575" in err


def test_short_run_writes_histories_profiles_and_a_summary_with_balances(tmp_path):
    case = load_case(CASE)
    case["layer"].update(elements=10, solid_fractions=[0.562, 0.584])
    case["time"]["end"] = 30.0
    case["output"].update(times=[10.0], samples=31, plots=False)
    res = run_case(case, tmp_path / "out")
    assert res.status == "completed"
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    loose, dense = s["members"]
    assert loose["base_pressure_20s_Pa"] > 0.5 and dense["base_pressure_20s_Pa"] < -0.5
    assert loose["data"]["onset_measured_s"] == 0.2 and loose["onset_s"] is not None
    for m in s["members"]:
        lay = layer_of(case, m["phi0"])
        # the liquid gained is the change of thickness; the solids are fixed per element
        assert m["liquid_volume_change_m"] == pytest.approx(m["thickness_end_m"] - lay.y0[: lay.n].sum(), abs=1e-15)
        assert m["solids_volume_m"] == pytest.approx(m["phi0"] * case["layer"]["thickness"], rel=1e-14)
    hist = np.genfromtxt(tmp_path / "out" / "history_584.csv", delimiter=",", names=True)
    assert hist["time_s"][-1] == pytest.approx(30.0) and np.all(hist["base_excess_pressure_Pa"][1:] < 0)
    prof = np.genfromtxt(tmp_path / "out" / "profiles_562.csv", delimiter=",", names=True)
    assert sorted(set(prof["time_s"])) == [0.0, 10.0, 30.0] and prof.size == 30
    # the bundled K ends the declared search at its bound: the summary says it is not determined
    assert "not determined" in s["calibration"]["k_dil"] and "4.09" in s["calibration"]["k_dil"]


def test_calibration_status_tells_a_k_at_the_search_bound_from_one_inside_it():
    case = load_case(CASE)
    status = data.calibration_status(case)
    assert "at the bound" in status["k_dil"]
    assert "for this case" in status["mu_s"] and "differs" not in status["mu_s"]  # the bundled μ_s is the fit
    case["closures"]["granular_rheology"]["k_dil"] = 4.09
    inside = data.calibration_status(case)["k_dil"]
    assert "at the bound" not in inside and "not the bundled case's fit" in inside


def test_calibration_status_names_the_nonlocal_amplitude_only_where_the_law_uses_it():
    case = load_case(CASE)
    assert "A = 0.48" in data.calibration_status(case)["fixed_beforehand"]
    case["closures"]["granular_rheology"]["law"] = "boyer_pailha"
    assert "amplitude" not in data.calibration_status(case)["fixed_beforehand"]


def test_the_local_law_ignores_the_amplitude_and_the_nonlocal_law_uses_it():
    case = load_case(CASE)
    assert layer_of(case, 0.588).amplitude == 0.48
    case["closures"]["granular_rheology"]["law"] = "boyer_pailha"
    assert layer_of(case, 0.588).amplitude == 0.0


def test_calibration_status_computes_the_mu_s_fit_for_the_case_it_is_given():
    """An edited case (another slope) gets the declared μ_s fit of its own set-up, not the bundled
    case's number, and the summary says that its μ_s differs from it."""
    case = load_case(CASE)
    fit = data.calibrate_mu_s(case)
    case["layer"]["slope_deg"] = case["layer"]["slope_deg"] + 1.0
    other = data.calibrate_mu_s(case)
    assert abs(other - fit) > 1e-3
    assert f"{other:.4g}" in data.calibration_status(case)["mu_s"] and "differs" in data.calibration_status(case)["mu_s"]


def test_the_command_runs_the_case_and_reports_the_time_reached_and_its_steps(tmp_path, capsys):
    text = _edit("layer", "solid_fractions", "[0.562, 0.584]")
    text = _edit_text(_edit_text(_edit_text(text, "layer", "elements", "6"), "time", "end", "3.0"),
                      "output", "plots", "false")
    path = tmp_path / "case.toml"
    path.write_text(text)
    assert main(["run", str(path), "--out", str(tmp_path / "out")]) == 0
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert s["stopped_at_s"] == pytest.approx(3.0) and s["steps"] == sum(m["steps"] for m in s["members"]) > 0
    assert "at t = 3 s after" in capsys.readouterr().out


def _onset_and_min(case, phi0, elements=None, rtol=1e-7, max_step=None):
    lay = layer_of(case, phi0, elements)
    times = np.linspace(0.0, 120.0, 1201)
    st = lay.run(times, rtol=rtol, max_step=max_step or case["time"]["step"])
    v = np.array([s.surface_velocity for s in st])
    p = np.array([s.base_pressure for s in st])
    return data.onset(times, v), p.min(), lay.steps_taken


def test_onset_and_pressure_minimum_are_determinate_under_halved_steps_and_elements():
    """φ0 = 0.578 (onset ~1 min): elements 20 → 40, the BDF's largest step ``[time] step`` halved,
    and its tolerance 1e-7 → 1e-9 move the onset and the base pressure minimum by ≤ 5 % or ≤ 0.5 s
    (0.5 Pa). Past the first seconds the steps are capped by ``[time] step``, not by the tolerance
    (about as many steps at 1e-9): halving the cap is what adds steps."""
    case = load_case(CASE)
    ref = _onset_and_min(case, 0.578, 20)
    halved = _onset_and_min(case, 0.578, 20, max_step=0.5 * case["time"]["step"])
    assert halved[2] >= 1.2 * ref[2]
    for other in (_onset_and_min(case, 0.578, 40), halved, _onset_and_min(case, 0.578, 20, rtol=1e-9)):
        assert abs(other[0] - ref[0]) <= max(0.05 * ref[0], 0.5)
        assert abs(other[1] - ref[1]) <= max(0.05 * abs(ref[1]), 0.5)


def test_resolved_case_is_nested_toml_and_loads_back(tmp_path):
    import tomllib

    from twofluid.casefile.schema import effective
    from twofluid.io.results import write_resolved_case

    case = load_case(CASE)
    path = tmp_path / "case.resolved.toml"
    write_resolved_case(path, case)
    text = path.read_text(encoding="utf-8")
    assert '["' not in text and "[closures.granular_rheology]" in text
    doc = tomllib.loads(text)
    assert doc == {k: v for k, v in effective(case).items() if not k.startswith("_")}
    again = load_case(path)
    assert {k: v for k, v in again.items() if k != "_source"} == {k: v for k, v in case.items() if k != "_source"}


def test_the_ensemble_file_runs_one_member_per_measured_solid_fraction_and_collects_summary_paths(tmp_path):
    import tomllib
    from importlib import resources

    from twofluid.ensemble.spec import parse_ensemble

    path = resources.files("twofluid") / "data" / "ensembles" / "immersed-avalanche-phi0.toml"
    spec = parse_ensemble(tomllib.loads(path.read_text()), source=str(path))
    assert [v[0] for v in spec.grid["layer.solid_fractions"]] == list(data.PHI0)
    case = load_case(CASE)
    case["layer"].update(elements=6, solid_fractions=[0.562])
    case["time"]["end"] = 2.0
    case["output"].update(times=[], samples=10, plots=False)
    summary = run_case(case, tmp_path / "out").summary
    for key in spec.collect:
        node = summary
        for part in key.split("."):
            node = node[int(part) - 1] if isinstance(node, list) else node[part]
        assert node is None or isinstance(node, float), key
