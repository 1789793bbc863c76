"""Units and defaults that cannot be mistaken and progress where stderr is not a
terminal."""
from __future__ import annotations

import io
import warnings

import pytest

import twofluid
from twofluid.casefile.loader import load_case
from twofluid.casefile.schema import CaseError, CaseWarning, validate
from twofluid.cli import main


def _liq_doc(**layer):
    base = {"case": {"name": "u", "model": "liquefaction_1d"},
            "materials": {"liquid_density": 1000.0, "liquid_viscosity": 1e-3, "particle_density": 2650.0},
            "site": {"water_table_depth": 0.0},
            "layers": [{"name": "sand", "thickness": 10.0, "elements": 20, "particle_diameter": 8e-4,
                        "porosity": 0.44, **layer}],
            "time": {"end": 1.0, "step": 0.02}, "ground_motion": {"duration": 0.5}}
    return base


def test_relative_density_as_a_fraction_is_refused_with_what_was_meant():
    with pytest.raises(CaseError, match=r"relative_density: 0.45 is outside the valid range \(1, 100\] \[%\]; "
                                        r"the unit is per cent: did you mean 45 \(×100\)\?") as exc:
        validate(_liq_doc(relative_density=0.45), "c.toml")
    assert "\n" not in str(exc.value)
    validate(_liq_doc(relative_density=45.0), "c.toml")


def test_the_cli_refuses_a_fraction_with_exit_2(tmp_path, capsys):
    import tomli_w

    (tmp_path / "c.toml").write_text(tomli_w.dumps(_liq_doc(relative_density=0.45)))
    for cmd in (["simplified", str(tmp_path / "c.toml")], ["run", str(tmp_path / "c.toml")],
                ["element-test", "--dr", "0.45"]):
        assert main(cmd) == 2
        assert "did you mean 45" in capsys.readouterr().err


def test_the_simplified_table_prints_per_cent():
    from twofluid.runners.liquefaction import simplified_table

    res = simplified_table(load_case("liquefaction-elcentro"))
    assert "Dr [%]" in res.table().splitlines()[0]
    assert {r["Dr [%]"] for r in res.to_rows()} == {47.0}


def test_keys_without_effect_warn():
    # n160cs describes the crust's soil, so its relative_density has no effect (without n160cs it sets
    # the crust's friction angle and backbone under the hysteretic model: no warning then)
    crust = {"name": "crust", "thickness": 2.0, "elements": 4, "unit_weight": 18e3, "relative_density": 60.0,
             "n160cs": 20.0}
    doc = _liq_doc(shear_wave_velocity=150.0, k2max=40.0)
    doc["layers"].insert(0, crust)
    doc["site"]["water_table_depth"] = 2.0
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        validate(doc, "c.toml")
    text = [str(w.message) for w in caught if issubclass(w.category, CaseWarning)]
    assert any("'crust'] relative_density: ignored above the water table" in t for t in text), text
    assert any("'sand'] k2max: ignored (shear_wave_velocity = 150" in t for t in text), text
    doc["layers"][0].pop("n160cs")  # the crust's relative_density now acts: no warning for it
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        validate(doc, "c.toml")
    assert not any("relative_density" in str(w.message) for w in caught)
    doc["layers"][0].pop("relative_density")
    doc["layers"][1].pop("k2max")
    with warnings.catch_warnings():
        warnings.simplefilter("error", CaseWarning)
        validate(doc, "c.toml")  # the defaults are not "given"


def test_default_report_depths_fit_a_deep_water_table():
    from twofluid.casefile.schema_liquefaction import report_depths

    doc = _liq_doc()
    doc["layers"].insert(0, {"name": "crust", "thickness": 3.0, "elements": 6, "unit_weight": 18e3})
    doc["site"]["water_table_depth"] = 3.0
    case = validate(doc, "c.toml")  # the old default 1 … 9 m stopped this site (exit 2)
    assert report_depths(case) == pytest.approx([3.0 + k for k in range(1, 10)])
    case["report"]["depths"] = [1.0]
    with pytest.raises(CaseError, match=r"\[report\] depths: 1 lies outside \[3, 13\] m"):
        twofluid.run_case(case)


def test_progress_lines_every_ten_per_cent_or_thirty_seconds():
    from twofluid.runners.common import LineProgress

    now = [0.0]
    out = io.StringIO()
    bar = LineProgress(100.0, stream=out, clock=lambda: now[0])
    for _ in range(100):  # 1 s of simulated time per 0.5 s of wall time: 50 s in all
        now[0] += 0.5
        bar.update(1.0)
    lines = out.getvalue().splitlines()
    assert [ln.split("(")[1].split(")")[0] for ln in lines] == [f"{p} %" for p in range(10, 101, 10)]
    out = io.StringIO()
    bar = LineProgress(1000.0, stream=out, clock=lambda: now[0])
    start = now[0]
    for _ in range(100):  # slow: 1 % per 2 s; lines by the clock (30 s) and by 10 %
        now[0] += 2.0
        bar.update(1.0)
    stamps = [float(ln.rsplit(",", 1)[1].split()[0]) for ln in out.getvalue().splitlines()]
    assert stamps and max(b - a for a, b in zip([0.0] + stamps, stamps)) <= 30.0 + 2.0
    assert now[0] - start - stamps[-1] <= 30.0 + 2.0


def test_a_quick_run_prints_no_progress_lines(tmp_path, capsys):
    case = load_case("settling-illite")
    case["time"]["end"], case["output"]["times"] = 5 * case["time"]["step"], []
    case["output"]["plots"] = False
    twofluid.run_case(case, tmp_path / "o", progress="lines")
    assert capsys.readouterr().err == ""
