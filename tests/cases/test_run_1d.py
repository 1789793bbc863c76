"""The 1D run driver and CLI end to end: bad input, short bundled runs, interruption."""
import json
import subprocess
import sys

import numpy as np
import pytest

from twofluid.runners import column_1d, common
from twofluid.casefile.loader import case_text, load_case
from twofluid.casefile.builder import build
from twofluid.cli import main
from twofluid.timestepping.backward_euler import StepFailure

BAD = [  # (substitution in settling-illite's TOML, key named, range or reason named)
    (("\nporosity = 0.95", "\nporosity = 1.5"), "[initial] porosity", "(0, 1]"),
    (("step = 0.1", "step = -0.1"), "[time] step", "(0, inf)"),
    (("elements = 16", 'elements = "many"'), "[mesh] elements", "integer"),
    (("[mesh]\n", "[mesh]\nlenght = 2.0\n"), "[mesh] lenght", "unknown key"),
    (('kind = "outlet"', 'kind = "wall"'), "kind", "outlet"),
    (('kind = "wall"', 'kind = "outlet"'), "kind", "inlet or a wall"),
    (("particle_diameter = ", "particle_diameter = -"), "[materials] particle_diameter", "(0, inf)"),
]


def _write(tmp_path, old, new, name="bad.toml"):
    text = case_text("settling-illite")
    assert old in text
    path = tmp_path / name
    path.write_text(text.replace(old, new, 1))
    return path


@pytest.mark.parametrize("sub, key, why", BAD)
def test_bad_case_file_gives_one_line_naming_file_key_and_range(tmp_path, capsys, sub, key, why):
    path = _write(tmp_path, *sub)
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1
    assert "bad.toml" in err and key in err and why in err
    assert not out.exists()  # validated before any computation


def test_bad_case_exit_status_and_no_traceback_from_the_console(tmp_path):
    path = _write(tmp_path, "\nporosity = 0.95", "\nporosity = 0.0")
    p = subprocess.run([sys.executable, "-m", "twofluid.cli", "run", str(path)], capture_output=True,
                       text=True, cwd=tmp_path)
    assert p.returncode == 2
    assert "Traceback" not in p.stderr and "[initial] porosity" in p.stderr


def _short(name, end):
    c = load_case(name)
    c["time"]["end"] = end
    c["output"]["times"] = [t for t in c["output"]["times"] if t < end]
    return c


@pytest.mark.parametrize("name, end", [("fluidized-bed-step", 2.0), ("settling-illite", 10.0)])
def test_short_bundled_run_writes_readable_results(tmp_path, name, end):
    res = common.run_case(_short(name, end), tmp_path, progress=False)
    assert res.status == "completed"
    for f in ("case.resolved.toml", "profiles.csv", "probes.csv", "summary.json", "porosity.png",
              "heights.png"):
        assert (tmp_path / f).stat().st_size > 0, f
    s = json.loads((tmp_path / "summary.json").read_text())
    assert s["case"] == name and s["steps"] > 0 and s["stopped_at_s"] == pytest.approx(end)
    assert abs(s["solids_volume_balance_error"]) < 1e-10
    prof = np.genfromtxt(tmp_path / "profiles.csv", delimiter=",", names=True)
    assert set(np.unique(prof["time_s"])) >= {0.0, end}
    assert np.all((prof["porosity"] > 0) & (prof["porosity"] <= 1))
    # the resolved case file runs as it is
    assert load_case(tmp_path / "case.resolved.toml")["time"]["end"] == end


def _stopping_after(k, exc):
    real = column_1d.integrate

    def integrate(*args, **kw):
        for i, step in enumerate(real(*args, **kw)):
            if i == k:
                raise exc(step.state)
            yield step
    return integrate


@pytest.mark.parametrize("kind", ["interrupted", "failed", "singular"])
def test_interrupted_or_failed_run_keeps_what_it_wrote(tmp_path, monkeypatch, kind):
    exc = {"interrupted": lambda s: KeyboardInterrupt(),
           "failed": lambda s: StepFailure(s.t, 1e-9, "test failure", s),
           "singular": lambda s: RuntimeError("Factor is exactly singular")}[kind]
    monkeypatch.setattr(column_1d, "integrate", _stopping_after(30, exc))
    c = _short("settling-illite", 10.0)
    c["output"]["probe_interval"] = 0.1
    res = common.run_case(c, tmp_path)
    status = "failed" if kind == "singular" else kind
    assert res.status == status
    s = json.loads((tmp_path / "summary.json").read_text())
    assert s["status"] == status and 0.0 < s["stopped_at_s"] < 10.0 and s["reason"]
    probes = np.genfromtxt(tmp_path / "probes.csv", delimiter=",", names=True)
    assert probes["time_s"].max() == pytest.approx(s["stopped_at_s"], abs=0.11)
    assert (tmp_path / "porosity.png").exists()


def test_a_key_without_effect_is_a_warning_naming_file_and_key(tmp_path, capsys):
    import warnings

    from twofluid.casefile.schema import CaseWarning

    path = _write(tmp_path, 'kind = "wall"', 'kind = "wall"\npressure = 5.0', name="unused.toml")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        load_case(path)
    msgs = [str(w.message) for w in caught if issubclass(w.category, CaseWarning)]
    assert len(msgs) == 1 and "unused.toml" in msgs[0] and "[boundary.bottom] pressure" in msgs[0]
    # the bundled cases carry no such keys
    with warnings.catch_warnings():
        warnings.simplefilter("error", CaseWarning)
        for name in ("fluidized-bed-step", "settling-illite"):
            load_case(name)


def test_no_plots_option_writes_results_without_pngs(tmp_path):
    """``twofluid run --no-plots`` overrides the case's ``[output] plots = true`` (the default)."""
    path = tmp_path / "short.toml"
    text = case_text("settling-illite").replace("end = 300.0", "end = 1.0")
    path.write_text(text.replace("times = [30.0, 90.0, 180.0, 300.0]", "times = [0.5]"))
    assert load_case(path)["output"]["plots"] is True
    out = tmp_path / "run"
    assert main(["run", str(path), "--out", str(out), "--quiet", "--no-plots"]) == 0
    assert (out / "summary.json").stat().st_size > 0 and (out / "profiles.csv").stat().st_size > 0
    assert not list(out.glob("*.png"))


@pytest.mark.parametrize("model", ["two_fluid_1d", "reduced_1d"])
def test_initial_pressure_is_that_of_the_unstepped_inlet(model):
    """fluidized-bed-step starts as a uniform bed at its fluidization velocity, the inlet stepped at
    t = 0+. Its initial pressure (one 1e-6 Δt step with the inlet held) is the pressure of the same
    bed with the inlet not stepped at all, to the Picard tolerance: no impulse of the step (which
    gave 2e8 Pa instead of 1.4e4 Pa when the models' own solves read the stepped inlet)."""
    P = {}
    for por in ([0.65, 0.716], [0.65, 0.65]):
        c = load_case("fluidized-bed-step")
        c["case"]["model"] = model
        c["boundary"]["bottom"]["porosities"] = por
        b = build(c)
        P[por[-1]] = column_1d._initial_pressure(b.model, b.state, b.dt).P
    assert np.abs(P[0.716] - P[0.65]).max() < b.settings.tol * np.abs(P[0.65]).max()
    assert np.abs(P[0.65]).max() < 2e4  # the column's weight per area, ~1.4e4 Pa
