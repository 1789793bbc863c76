"""Sensitivity studies: parameter parsing, a real study on a small step-change case, CSV, CLI."""
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


def test_t1_falls_as_the_particles_grow(tmp_path):
    """Contraction: t1 = (H0 − H1)/(U0 − U1) ∝ 1/U_t ∝ 1/d², so +10 % in d gives about −17 %."""
    path = tmp_path / "case.toml"
    path.write_text(CASE)
    res = sensitivity_study(str(path), [parse_change("particle.diameter", "10%"),
                                        parse_change("liquid.viscosity", "10%")],
                            csv_path=tmp_path / "s.csv")
    d, mu = res.rows
    assert -0.20 < d["figure_change"] < -0.14
    assert 0.07 < mu["figure_change"] < 0.13  # t1 ∝ μ
    rows = list(csv.DictReader(open(tmp_path / "s.csv")))
    assert [r["parameter"] for r in rows] == ["materials.particle_diameter", "materials.liquid_viscosity"]


def test_cli_sensitivity_and_unknown_parameter(tmp_path, capsys):
    path = tmp_path / "case.toml"
    path.write_text(CASE.replace("end = 75.0", "end = 10.0"))
    assert main(["sensitivity", str(path), "--vary", "materials.nonsense", "--by", "10%"]) == 2
    assert "no such parameter" in capsys.readouterr().err


@pytest.fixture
def no_runs(monkeypatch):
    """Fail the test if any run starts: the inputs must be rejected before."""
    import twofluid.sensitivity as sens

    def boom(*a, **k):
        raise AssertionError("a run started before the inputs were checked")

    monkeypatch.setattr(sens, "key_figure", boom)


@pytest.mark.parametrize("args, words", [
    (["--vary", "materials.particle_diameter", "--by", "abc"], ["--by", "'abc'", "10%"]),
    (["--vary", "materials.particle_diameter", "--by=-100%"], ["--by", "> -100 %"]),
    (["--vary", "materials.particle_diameter", "materials.nonsense", "--by", "10%"],
     ["case.toml", "[materials] nonsense", "no such parameter"]),
    (["--vary", "case.name"], ["[case] name", "not a number"]),
    (["--vary", "initial.porosity", "--by", "50%"],
     ["case.toml", "[initial] porosity", "1.2", "outside the valid range (0, 1]", "+50 %"]),
    (["--vary", "closures.drag.n_switch", "--by", "100%"], ["[closures.drag] n_switch", "[0, 1]"]),
    (["--vary", "materials.particle_diameter", "--figure", "porosity_error@abc"], ["--figure", "(0, 75]"]),
    (["--vary", "materials.particle_diameter", "--figure", "height"], ["--figure", "unknown key figure"]),
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
