"""Sensitivity studies: parameter parsing, real studies (1D step change, liquefaction) on the
ensemble engine with a LocalCluster of 2 worker processes, CSV, CLI."""
import csv

import pytest

from twofluid.casefile.schema import CaseError
from twofluid.cli import main
from twofluid.sensitivity import parse_change, sensitivity_study

CASE = """
[case]
name = "small-step"
model = "reduced_1d"
study = "step_change"
[mesh]
length = 0.3
elements = 150
[materials]
liquid_density = 1000.0
liquid_viscosity = 1.0e-3
particle_density = 2500.0
particle_diameter = 1.0e-4
[closures.drag]
law = "wen_yu"
stokes = true
[closures.viscosity]
law = "none"
[closures.solids_pressure]
reference_porosity = 0.3
[initial]
porosity = 0.8
bed_height = 0.2
[boundary.bottom]
kind = "inlet"
times = [0.0, 0.0]
porosities = [0.8, 0.7]
[boundary.top]
kind = "outlet"
[time]
end = 75.0
step = 0.2
[output]
plots = false
"""


def test_parse_change():
    assert parse_change("particle.diameter", "10%") == ("materials", "particle_diameter", 0.1)
    assert parse_change("closures.drag.n_switch", "-0.05") == ("closures.drag", "n_switch", -0.05)
    with pytest.raises(CaseError):
        parse_change("diameter", "10%")


@pytest.fixture(scope="module")
def client():
    from twofluid.ensemble.engine import cluster_client

    with cluster_client(workers=2) as c:
        yield c


def test_t1_falls_as_the_particles_grow(tmp_path, client):
    """Contraction: t1 = (H0 − H1)/(U0 − U1) ∝ 1/U_t ∝ 1/d², so +10 % in d gives about −17 %.

    With inlet porosities the inlet velocities follow U_t (Stokes: ∝ d²/μ), and the report says so."""
    path = tmp_path / "case.toml"
    path.write_text(CASE)
    res = sensitivity_study(str(path), [parse_change("particle.diameter", "10%"),
                                        parse_change("liquid.viscosity", "10%")],
                            csv_path=tmp_path / "s.csv", client=client)
    d, mu = res.rows
    assert d["unit"] == "s" and d["status"] == "completed"
    assert -0.20 < d["figure_change"] < -0.14
    assert 0.07 < mu["figure_change"] < 0.13  # t1 ∝ μ
    rows = list(csv.DictReader(open(tmp_path / "s.csv")))
    assert [r["parameter"] for r in rows] == ["materials.particle_diameter", "materials.liquid_viscosity"]
    assert "inlet velocities" in d["also_changes"] and "inlet velocities" in mu["also_changes"]
    note = next(n for n in res.notes if "particle_diameter" in n)
    v0, v1 = (float(part.split(",")[0]) for part in note.split("inlet velocities ")[1].split(" m/s")[0].split(" -> "))
    # Stokes drag: U ∝ d² at any porosity; the note prints 4 significant digits (±5e-4 each)
    assert v1 / v0 == pytest.approx(1.1 ** 2, rel=1.2e-3)


def test_liquefaction_sensitivity_reports_units_and_the_conductivity(tmp_path, client):
    """A liquefaction case runs too: its figures carry units, and a grain-size change of its
    layer says it changes the hydraulic conductivity (Ergun: k ∝ d² at a porosity)."""
    from twofluid.casefile.loader import case_text

    path = tmp_path / "liq.toml"
    text = case_text("liquefaction-elcentro")
    path.write_text(text.replace("end = 3600.0", "end = 1.0").replace(
        "times = [6.0, 10.0, 20.0, 30.0, 60.0, 120.0]", "times = [1.0]").replace("duration = 6.0", "duration = 1.0"))
    res = sensitivity_study(str(path), [parse_change("layers.1.particle_diameter", "10%")],
                            figure=["settlement_end_m", "base_excess_pore_pressure.peak_Pa"], client=client)
    units = {r["figure"]: r["unit"] for r in res.rows}
    assert units == {"settlement_end_m": "m", "base_excess_pore_pressure.peak_Pa": "Pa"}
    assert all(r["status"] == "completed" and r["figure_value"] is not None for r in res.rows)
    assert "hydraulic conductivity" in res.rows[0]["also_changes"]


def test_cli_sensitivity_and_unknown_parameter(tmp_path, capsys, no_runs):
    path = tmp_path / "case.toml"
    path.write_text(CASE.replace("end = 75.0", "end = 10.0"))
    assert main(["sensitivity", str(path), "--vary", "materials.nonsense", "--by", "10%"]) == 2
    assert "no such parameter" in capsys.readouterr().err


@pytest.fixture
def no_runs(monkeypatch):
    """Fail the test if any run starts: the inputs must be rejected before."""
    import twofluid.ensemble.engine as engine

    def boom(*a, **k):
        raise AssertionError("a run started before the inputs were checked")

    monkeypatch.setattr(engine, "run_members", boom)
    monkeypatch.setattr(engine, "cluster_client", boom)


@pytest.mark.parametrize("args, words", [
    (["--vary", "materials.particle_diameter", "--by", "abc"], ["--by", "'abc'", "10%"]),
    (["--vary", "materials.particle_diameter", "--by=-100%"], ["--by", "> -100 %"]),
    (["--vary", "materials.particle_diameter", "materials.nonsense", "--by", "10%"],
     ["case.toml", "[materials] nonsense", "no such parameter"]),
    (["--vary", "case.name"], ["[case] name", "not a number"]),
    (["--vary", "initial.porosity", "--by", "50%"],
     ["case.toml", "porosit", "1.2", "outside the valid range (0, 1", "+50 %"]),  # or the inlet's copy
    (["--vary", "closures.drag.n_switch", "--by", "100%"], ["[closures.drag] n_switch", "[0, 1]"]),
    (["--vary", "materials.particle_diameter", "--figure", "porosity_error@abc"], ["--figure", "(0, 75]"]),
    (["--vary", "materials.particle_diameter", "--figure", "height?"], ["--figure", "unknown key figure"]),
    (["--vary", "materials.particle_diameter", "--workers", "0"], ["--workers", "[1, 1024]"]),
])
def test_bad_sensitivity_input_is_exit_2_before_any_run(tmp_path, capsys, no_runs, args, words):
    path = tmp_path / "case.toml"
    path.write_text(CASE)
    assert main(["sensitivity", str(path), *args]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "Traceback" not in err
    for w in words:
        assert w in err, err


def test_cli_rejects_a_count_of_changes_that_fits_no_parameter_list(capsys):
    from twofluid.cli import main

    assert main(["sensitivity", "fluidized-bed-step", "--vary", "particle.diameter", "particle.density",
                 "--by", "10%", "5%", "3%"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "--by" in err


def test_a_2d_case_runs_on_the_same_engine(tmp_path, client):
    """The 2D pipe flow on a coarse mesh: the default figure (mean |Δn| of the last state) and
    a summary figure; a larger grain settles faster, so the riser's porosity changes."""
    from twofluid.casefile.loader import case_text

    text = case_text("pipe-flow")
    path = tmp_path / "pipe.toml"
    path.write_text(text.replace("nx = 50 ", "nx = 4 ").replace("ny = 100 ", "ny = 8 "))
    res = sensitivity_study(str(path), [parse_change("particle.diameter", "10%")],
                            figure=["porosity_error@end", "porosity_range.1"], client=client)
    err, low = res.rows
    assert err["status"] == "completed" and err["unit"] == "-"
    assert 0.0 < err["figure_value"] < 0.2  # a mean porosity change: between none and the range of n
    assert low["figure_base"] is not None and low["figure_value"] != low["figure_base"]
