"""A fluidized bed from a flow rate and a column diameter (docs/fluidized-beds.md), and the
Richardson–Zaki exponent of Richardson & Zaki (1954) with its wall term d/D."""
import math
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from twofluid.casefile.bed import L_MIN, M3_H, richardson_zaki_1954_exponent
from twofluid.casefile.loader import load_case
from twofluid.casefile.schema import CaseError
from twofluid.closures.drag import archimedes_number, khan_richardson_exponent
from twofluid.fluidization_curve import fluidization_curve

DOC = Path(__file__).resolve().parents[2] / "docs" / "fluidized-beds.md"


def _doc_case() -> str:
    return re.search(r"```toml\n(.*?)```", DOC.read_text(encoding="utf-8"), re.S).group(1)


def _write(tmp_path, text, name="beads.toml") -> Path:
    p = tmp_path / name
    p.write_text(text, encoding="utf-8")
    return p


def test_the_documented_case_converts_its_flow_rate_at_the_edge(tmp_path):
    case = load_case(_write(tmp_path, _doc_case()))
    area = math.pi * 0.05 ** 2 / 4
    assert case["mesh"]["area"] == pytest.approx(area, rel=1e-15)
    b = case["boundary"]["bottom"]
    assert b["velocities"] == pytest.approx([2.0 / 60e3 / area, 3.0 / 60e3 / area], rel=1e-12)
    assert b["flow_rates_l_min"] == [] and case["mesh"].get("diameter", -1.0) == -1.0  # SI only from here on


def test_m3_h_and_l_min_and_velocities_give_one_resolved_case(tmp_path):
    text = _doc_case()
    by_l_min = load_case(_write(tmp_path, text, "a.toml"))
    q = [2.0 * L_MIN / M3_H, 3.0 * L_MIN / M3_H]
    by_m3_h = load_case(_write(tmp_path, text.replace("flow_rates_l_min = [2.0, 3.0]",
                                                      f"flow_rates_m3_h = [{q[0]!r}, {q[1]!r}]"), "b.toml"))
    v = by_l_min["boundary"]["bottom"]["velocities"]
    by_u = load_case(_write(tmp_path, text.replace("flow_rates_l_min = [2.0, 3.0]", f"velocities = [{v[0]!r}, {v[1]!r}]")
                            .replace("diameter = 0.05", f"area = {math.pi * 0.05 ** 2 / 4!r}"), "c.toml"))
    for other in (by_m3_h, by_u):
        assert other["boundary"]["bottom"]["velocities"] == pytest.approx(v, rel=1e-12)
        assert other["mesh"]["area"] == pytest.approx(by_l_min["mesh"]["area"], rel=1e-12)


@pytest.mark.parametrize("edit, key", [
    (("flow_rates_l_min = [2.0, 3.0]", "flow_rates_l_min = [2.0, 3.0]\nvelocities = [0.01, 0.02]"), "flow_rates_l_min"),
    (("flow_rates_l_min = [2.0, 3.0]", "flow_rates_l_min = [2.0, -3.0]"), "flow_rates_l_min"),
    (("diameter = 0.05", "diameter = 0.05\narea = 0.002"), "[mesh] diameter"),
    (("diameter = 0.05", "diameter = 0.0"), "[mesh] diameter"),
    (('kind = "outlet"', 'kind = "outlet"\nflow_rates_m3_h = [0.1]'), "[boundary.top] flow_rates_m3_h"),
])
def test_bad_flow_rate_input_is_one_line_naming_the_key(tmp_path, edit, key):
    path = _write(tmp_path, _doc_case().replace(*edit))
    with pytest.raises(CaseError) as exc:
        load_case(path)
    assert key in str(exc.value) and "\n" not in str(exc.value)
    exe = Path(sys.executable).with_name("twofluid")  # the installed command
    r = subprocess.run([str(exe), "run", str(path), "--out", str(tmp_path / "out")],
                       capture_output=True, text=True, cwd=tmp_path)
    assert r.returncode == 2 and key in r.stderr and "Traceback" not in r.stderr


@pytest.mark.parametrize("re_t, wall, k", [(0.1, 0.0, 4.65), (0.1, 0.02, 4.65 + 0.39), (0.5, 0.01, 4.525 * 0.5 ** -0.03),
                                           (40.0, 0.01, 4.63 * 40 ** -0.1), (300.0, 0.05, 4.45 * 300 ** -0.1),
                                           (1e4, 0.05, 2.39)])
def test_richardson_zaki_1954_exponent_branches(re_t, wall, k):
    assert float(richardson_zaki_1954_exponent(re_t, wall)) == pytest.approx(k, rel=1e-12)


def test_wall_term_for_half_millimetre_beads_in_a_50_mm_column():
    """k = 3.20 with the wall term against 2.98 of Khan & Richardson (the documented example)."""
    ar = archimedes_number(0.5e-3, 2500.0, 1000.0, 1e-3)
    assert float(khan_richardson_exponent(ar)) == pytest.approx(2.98, abs=0.005)
    assert float(richardson_zaki_1954_exponent(40.0, 0.5e-3 / 0.05)) == pytest.approx(3.20, abs=0.005)
    assert float(richardson_zaki_1954_exponent(40.0, 0.01)) > float(richardson_zaki_1954_exponent(40.0, 0.0))


def test_bed_figures_and_fluidization_curve_offer_the_wall_corrected_exponent(tmp_path):
    case = load_case(_write(tmp_path, _doc_case()))
    kr = fluidization_curve(case, points=12)
    rz = fluidization_curve(case, points=12, exponent="richardson_zaki_1954")
    re_t = case["materials"]["liquid_density"] * rz["figures"]["U_t_m_s"] * 0.5e-3 / case["materials"]["liquid_viscosity"]
    assert rz["figures"]["richardson_zaki_exponent"] == pytest.approx(float(richardson_zaki_1954_exponent(re_t, 0.01)))
    assert rz["figures"]["richardson_zaki_velocity_m_s"] == pytest.approx(rz["figures"]["U_t_m_s"] * 10 ** -0.01)
    top_kr, top_rz = kr["rows"][0]["porosity_richardson_zaki"], rz["rows"][0]["porosity_richardson_zaki"]
    assert top_rz > top_kr  # a larger k: a more expanded bed at the same U
    assert [r["porosity"] for r in kr["rows"]] == [r["porosity"] for r in rz["rows"]]  # the model's own: unchanged
    with pytest.raises(CaseError, match="rz-exponent"):
        fluidization_curve(case, exponent="rowe")
    from twofluid.runners import run_case

    case["time"]["end"], case["output"]["times"] = 0.5, [0.5]
    case["output"]["plots"] = False
    bed = run_case(case, tmp_path / "run").summary["bed"]
    assert bed["column_diameter_m"] == pytest.approx(0.05) and bed["particle_to_column_diameter"] == pytest.approx(0.01)
    assert bed["richardson_zaki_exponent_1954_wall"] == pytest.approx(rz["figures"]["richardson_zaki_exponent"])
    exp = bed["expanded"]
    assert exp["richardson_zaki_1954_wall"]["height_m"] > exp["richardson_zaki"]["height_m"]
    assert np.isfinite(exp["model"]["height_m"])
