"""Reliability: impossible combinations at load time, paths, signals, NaN, escapes, order of checks."""
from __future__ import annotations

import json
import os
import signal
import warnings

import numpy as np
import pytest

from twofluid.casefile.loader import load_case
from twofluid.casefile.schema import CaseError, CaseWarning, revalidate
from twofluid.cli import main
from twofluid.io.folders import LOCK, MANIFEST
from twofluid.io.results import CsvStream, NonFiniteOutput, ResultWriter, reset_nonfinite
from twofluid.runners import column_1d
from twofluid.runners.common import run_case


def _short(name="settling-illite", steps=1):
    case = load_case(name)
    case["time"]["end"] = steps * case["time"]["step"]
    case["output"].update(times=[], probes=[])
    return case


def _refused(case, match):
    with pytest.raises(CaseError, match=match) as exc:
        revalidate(case, "c.toml")
    assert "\n" not in str(exc.value)


# ---------------------------------------------------------------- together impossible
def test_a_fluidized_inlet_needs_particles_denser_than_the_liquid():
    case = load_case("fluidized-bed-step")
    case["initial"].update(state="uniform", porosity=0.65, bed_height=0.7, settled_height=-1.0)
    case["boundary"]["bottom"].update(porosities=[0.65, 0.716], velocities=[])  # an inlet given by porosities
    case["materials"]["particle_density"] = 0.9 * case["materials"]["liquid_density"]
    _refused(case, r"\[boundary.bottom\] porosities: .*denser than the liquid")


@pytest.mark.parametrize("key, value", [("particle_diameter", 1e-90), ("sphericity", 1e-90),
                                        ("liquid_viscosity", 1e90)])
def test_derived_velocities_and_drag_that_are_not_usable_are_refused(key, value):
    case = load_case("fluidized-bed-step")
    case["materials"][key] = value
    _refused(case, r"\[materials\].*(terminal|fluidiz|drag|slip|physically implausible)")


@pytest.mark.parametrize("value", [1e308, 1e-300, float("nan"), float("inf")])
def test_numbers_outside_the_working_range_are_refused(value):
    case = load_case("settling-illite")
    case["materials"]["particle_density"] = value
    _refused(case, r"\[materials\] particle_density: .*(finite|working range)")


def test_a_run_of_more_than_ten_million_steps_is_refused():
    case = load_case("settling-illite")
    case["time"]["step"] = case["time"]["end"] * 1e-8
    _refused(case, r"\[time\] step: .* steps, more than 1e\+07")


def test_a_liquefaction_column_counts_its_shaking_steps_over_the_shaking_only():
    """The shear sub-steps run while the ground shakes, the reconsolidation steps after: a long
    reconsolidation does not make the shear step a run that would not end, a too-fine one does."""
    case = load_case("liquefaction-layered-site")
    case["time"]["end"] = 2e5  # 4e7 shear steps of 5 ms if counted over the whole run
    revalidate(case, "<test>")
    case["shear_wave"]["step"] = case["ground_motion"]["duration"] * 2e-8
    _refused(case, r"\[shear_wave\] step: .*\[ground_motion\] duration = 10 s .* more than 1e\+07")


def test_2d_cut_outside_or_covering_the_domain_is_refused():
    case = load_case("viscometer")
    case["mesh"]["cut"] = [1.0, 2.0, 1.0, 2.0]
    _refused(case, r"\[mesh\] cut: .*removes no element")
    case["mesh"]["cut"] = [-1.0, 2.0, -1.0, 2.0]
    _refused(case, r"\[mesh\] cut: .*removes every element")


def test_2d_missing_groups_axis_off_the_axis_duplicates_and_inverted_elements_are_refused():
    case = load_case("viscometer")
    case["mesh"]["x0"] = 0.01
    case["mesh"]["cut"] = [0.0, 0.02, 0.04, 0.16]
    _refused(case, r"\[boundary.axis\] kind: the mesh has no boundary group 'axis'")
    case = load_case("viscometer")
    case["boundary"]["axis"]["group"] = "outer"
    _refused(case, r"\[boundary.axis\] (group|kind): .*(already has a condition|r = 0)")
    case = load_case("viscometer")
    case["boundary"]["outer"]["group"] = "Wall"
    _refused(case, r"\[boundary.outer\] group: the mesh has no boundary group 'Wall'")
    case = load_case("viscometer")
    case["mesh"]["grading_y"] = 1e40
    _refused(case, r"\[mesh\] grading_x/grading_y: .*(collapsed|finite)")


def test_2d_inlet_schedules_and_list_entries_are_checked():
    case = load_case("viscometer")
    case["boundary"]["bottom"]["porosities"] = [-0.6]
    _refused(case, r"\[boundary.bottom\] porosities: entry 1 \(-0.6\) is outside")
    case = load_case("viscometer")
    case["boundary"]["bottom"]["times"] = [float("nan")]
    _refused(case, r"\[boundary.bottom\] times: entry 1 \(nan\) must be finite")


def test_2d_profile_height_at_the_top_is_the_top_row(tmp_path):
    from twofluid.casefile.mesh_2d import build_mesh, element_row

    case = load_case("viscometer")
    mesh = build_mesh(case)
    top = element_row(mesh, case["mesh"]["y1"])
    assert top.size > 0 and np.allclose(mesh.points[mesh.cells[top]][:, :, 1].max(axis=1), case["mesh"]["y1"])
    case["profiles"]["heights"] = [case["mesh"]["y1"] + 0.01]
    _refused(case, r"\[profiles\] heights: .* lies outside the mesh")


def test_keys_without_effect_are_warned():
    case = load_case("viscometer")
    case["output"]["probes"] = [0.05]
    case["mesh"]["file"] = "x.msh"
    case["boundary"]["outer"]["omega"] = 3.0
    case["single_fluid"]["enabled"] = False
    doc = {k: v for k, v in case.items() if not k.startswith("_")}
    from twofluid.casefile.schema import validate

    with warnings.catch_warnings(record=True) as got:
        warnings.simplefilter("always")
        validate(doc, "c.toml")
    text = " | ".join(str(w.message) for w in got if issubclass(w.category, CaseWarning))
    for key in ("[output] probes", "[mesh] file", "[boundary.outer] omega", "[single_fluid] density"):
        assert key in text, text


def test_meshio_exit_on_an_unreadable_file_is_a_case_error(tmp_path):
    (tmp_path / "mesh.msh").write_text("x\n")
    text = (tmp_path / "c.toml")
    text.write_text('[case]\nname = "g"\nmodel = "two_fluid_2d"\n[mesh]\nkind = "gmsh"\nfile = "mesh.msh"\n'
                    '[materials]\nliquid_density = 1000.0\nliquid_viscosity = 1e-3\nparticle_density = 2600.0\n'
                    'particle_diameter = 1e-3\n[initial]\nporosity = 0.5\n[boundary.top]\nkind = "outlet"\n'
                    '[time]\nend = 1.0\nstep = 0.1\n')
    with pytest.raises(CaseError, match=r"\[mesh\] file: .*cannot read mesh"):
        load_case(text)


# ---------------------------------------------------------------- paths
@pytest.mark.parametrize("argv", [
    ["run", "settling-illite", "--out", "{f}/sub"],
    ["verify", "--quick", "--only", "hydrostatic", "--out", "{f}/v.md"],
    ["element-test", "--max-cycles", "1", "--out", "{f}/e"],
    ["sensitivity", "settling-illite", "--vary", "materials.particle_diameter", "--csv", "{f}/s.csv"],
    ["run", "settling-illite", "--out", "{f}"],
    ["run", "settling-illite", "--out", "{long}"],
])
def test_outputs_that_cannot_be_written_are_one_line_before_computing(argv, tmp_path, capsys):
    f = tmp_path / "a-file"
    f.write_text("x")
    argv = [a.format(f=f, long=tmp_path / ("x" * 300)) for a in argv]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("twofluid: error: ") and "\n" not in err and "running the checks" not in err


def test_a_binary_case_file_is_one_line(tmp_path, capsys):
    (tmp_path / "b.toml").write_bytes(b"\x00\xff\xfe\x80")
    for cmd in ("show", "run"):
        assert main([cmd, str(tmp_path / "b.toml")]) == 2
        assert "is not UTF-8 text" in capsys.readouterr().err


def test_a_bad_case_touches_no_folder_and_no_older_run(tmp_path):
    out = tmp_path / "out"
    run_case(_short(), out)
    before = {p.name: p.stat().st_mtime_ns for p in out.iterdir()}
    bad = _short()
    bad["mesh"]["elements"] = 0
    with pytest.raises(CaseError):
        run_case(bad, out)
    with pytest.raises(CaseError):
        run_case(bad, tmp_path / "new")
    assert {p.name: p.stat().st_mtime_ns for p in out.iterdir()} == before
    assert not (tmp_path / "new").exists()


# ---------------------------------------------------------------- folders: stale files, locks
def test_a_reused_folder_keeps_no_file_of_the_earlier_run(tmp_path):
    out = tmp_path / "out"
    case = _short()
    case["output"]["plots"] = True
    run_case(case, out)
    assert list(out.glob("*.png"))
    (out / "my-notes.txt").write_text("mine")  # a file of the user's stays
    case["output"]["plots"] = False
    run_case(case, out)
    assert not list(out.glob("*.png"))
    assert (out / "my-notes.txt").read_text() == "mine"
    listed = json.loads((out / MANIFEST).read_text())["files"]
    assert "summary.json" in listed and "my-notes.txt" not in listed and not (out / LOCK).exists()


def test_a_non_empty_folder_of_someone_else_is_refused(tmp_path):
    (tmp_path / "thesis.tex").write_text("x")
    with pytest.raises(CaseError, match="not empty and holds no earlier twofluid run"):
        run_case(_short(), tmp_path)


def test_two_runs_into_one_folder_are_refused_and_a_stale_lock_is_taken_over(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / LOCK).write_text(f"{os.getppid()}\n")  # a live process holds it
    with pytest.raises(CaseError, match="in use by another run"):
        run_case(_short(), out)
    (out / LOCK).write_text("999999999\n")  # no such process
    assert run_case(_short(), out).status == "completed"


# ---------------------------------------------------------------- signals, interrupts
def _with_signal_after(monkeypatch, steps, sig=signal.SIGTERM):
    real = column_1d.integrate

    def integrate(*a, **k):
        for i, s in enumerate(real(*a, **k)):
            yield s
            if i + 1 == steps:
                os.kill(os.getpid(), sig)

    monkeypatch.setattr(column_1d, "integrate", integrate)


def test_sigterm_is_handled_like_ctrl_c_and_writes_the_state_it_stopped_at(tmp_path, monkeypatch):
    _with_signal_after(monkeypatch, 3)
    res = run_case(_short(steps=10), tmp_path / "o")
    s = json.loads((tmp_path / "o" / "summary.json").read_text())
    assert res.status == s["status"] == "interrupted" and "SIGTERM" in s["reason"]
    assert 0.0 < s["stopped_at_s"] < res.summary["end_time_s"]
    t = np.genfromtxt(tmp_path / "o" / "profiles.csv", delimiter=",", names=True)["time_s"]
    assert np.isclose(t.max(), s["stopped_at_s"])  # the state it stopped at is in profiles.csv
    assert signal.getsignal(signal.SIGTERM) is signal.SIG_DFL  # restored


def test_interrupts_in_set_up_and_in_the_plots_say_so(tmp_path, monkeypatch, capsys):
    def stop(*a, **k):
        raise KeyboardInterrupt

    with monkeypatch.context() as m:
        m.setattr(column_1d, "build", stop)
        res = run_case(_short(), tmp_path / "a")
    assert res.status == "interrupted" and "set-up" in res.summary["reason"]
    assert json.loads((tmp_path / "a" / "summary.json").read_text())["status"] == "interrupted"
    case = _short()
    case["output"]["plots"] = True
    monkeypatch.setattr(column_1d, "_plots", stop)
    path = tmp_path / "c.toml"
    import tomli_w

    doc = {}
    for where, table in case.items():
        if not where.startswith("_"):
            node = doc
            *parents, last = where.split(".")
            for p in parents:
                node = node.setdefault(p, {})
            node[last] = table
    path.write_text(tomli_w.dumps(doc))
    assert main(["run", str(path), "--out", str(tmp_path / "b")]) == 130
    s = json.loads((tmp_path / "b" / "summary.json").read_text())
    assert s["status"] == "interrupted" and "plots" in s["reason"] and "completed" in s["reason"]


# ---------------------------------------------------------------- NaN, whole rows
def test_no_nan_reaches_an_output_without_the_run_failing(tmp_path, monkeypatch):
    real = column_1d._probe_values
    calls = []

    def probe(model, s, probes, heights):
        calls.append(s.t)
        v = real(model, s, probes, heights)
        if len(calls) > 3:
            v["bed_height_m"] = float("nan")
        return v

    monkeypatch.setattr(column_1d, "_probe_values", probe)
    case = _short(steps=10)
    case["output"]["probe_interval"] = 0.0  # a probe row every step
    res = run_case(case, tmp_path / "o")
    assert res.status == "failed" and "bed_height_m" in res.summary["reason"] and "t = " in res.summary["reason"]
    for name in ("profiles.csv", "probes.csv"):
        assert "nan" not in (tmp_path / "o" / name).read_text().lower()


def test_writers_refuse_non_finite_values_but_leave_undefined_cells_empty(tmp_path):
    reset_nonfinite()
    w = ResultWriter(tmp_path, ["porosity", "Us_m_s"], ["p"])
    w.profile(0.0, {"porosity": np.array([0.5, 0.6]), "Us_m_s": np.array([0.1, np.nan])})
    with pytest.raises(NonFiniteOutput, match=r"profiles.csv, column porosity, element 1, at t = 1 s"):
        w.profile(1.0, {"porosity": np.array([0.5, np.inf]), "Us_m_s": np.array([0.1, 0.2])})
    w.close()
    lines = (tmp_path / "profiles.csv").read_text().splitlines()
    assert lines == ["time_s,porosity,Us_m_s", "0,0.5,0.1", "0,0.6,"]


def test_a_full_disk_leaves_no_half_row(tmp_path, monkeypatch):
    s = CsvStream(tmp_path / "t.csv", ["a", "b"])
    s.rows([[1.0, 2.0]])
    real = os.write

    def half_then_full(fd, data):  # the disk takes half the rows, then is full
        real(fd, bytes(data[: len(data) // 2]))
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(os, "write", half_then_full)
    with pytest.raises(OSError, match="t.csv"):
        s.rows([[3.0, 4.0], [5.0, 6.0]])
    monkeypatch.undo()
    assert (tmp_path / "t.csv").read_bytes() == b"a,b\r\n1,2\r\n"


def _coarse_viscometer():
    case = load_case("viscometer")
    case["mesh"].update(nx=10, ny=16)
    case["time"]["end"] = case["time"]["step"]
    case["output"].update(times=[], plots=False)
    case["single_fluid"]["enabled"] = False
    return case


def test_a_2d_run_with_a_profile_at_the_top_writes_its_summary(tmp_path):
    case = _coarse_viscometer()
    case["profiles"]["heights"] = [case["mesh"]["y1"]]
    res = run_case(case, tmp_path / "o")
    assert res.status == "completed" and f"{case['mesh']['y1']:g} m" in res.summary["profiles"]
    assert "nan" not in (tmp_path / "o" / "steps.csv").read_text().lower()


def test_the_2d_initial_flow_field_uses_the_cases_picard_settings(monkeypatch):
    from twofluid.runners import flow_2d

    seen = []
    real = flow_2d.picard_step

    def spy(model, state, dt, settings, *a, **k):
        seen.append(settings)
        return real(model, state, dt, settings, *a, **k)

    monkeypatch.setattr(flow_2d, "picard_step", spy)
    case = _coarse_viscometer()
    case["time"].update(picard_tol=3e-6, picard_max_iter=77)
    flow_2d.build_2d(revalidate(case, "c.toml"))
    assert (seen[0].tol, seen[0].max_iter) == (3e-6, 77)


def test_verify_prints_the_validation_table_and_writes_nothing_by_default(tmp_path, monkeypatch, capsys):
    from twofluid.verification import slis_check
    from twofluid.verification.slis import load_slis_table

    rows = load_slis_table()[:2]
    fake = [{"row": i + 1, "material": r.material, "d_mm": 1e3 * r.d, "n0": r.n0, "n1": r.n1,
             "t1_exp": r.t1_exp, "t1_thesis": r.t1_thesis, "t1_twofluid": 1.1 * r.t1_exp, "t1_reach": r.t1_exp,
             "err_thesis": (r.t1_thesis - r.t1_exp) / r.t1_exp, "err_twofluid": 0.1, "note": ""}
            for i, r in enumerate(rows)]
    monkeypatch.setattr(slis_check, "slis_table", lambda rows=None: fake)
    monkeypatch.chdir(tmp_path)
    assert main(["verify", "--quick", "--only", "hydrostatic"]) == 0
    out = capsys.readouterr().out
    thesis = sum(abs(r["err_thesis"]) for r in fake) / len(fake)
    assert "| check |" in out and "t1 thesis FEA [s]" in out
    assert f"mean absolute t1 error twofluid 10.0 %, thesis FEA {100 * thesis:.1f} %" in out
    assert list(tmp_path.iterdir()) == []  # nothing written without --out
    assert main(["verify", "--quick", "--only", "hydrostatic", "--out", "r.md"]) == 0
    assert "## Validation: Slis" in (tmp_path / "r.md").read_text()


def test_show_prints_a_cases_readme(capsys):
    assert main(["show", "--readme", "pipe-flow"]) == 0
    assert capsys.readouterr().out.startswith("#")
    assert main(["show", "--readme", "settling-illite"]) == 2  # it has none: one line
    assert main(["cases"]) == 0
    listing = capsys.readouterr().out
    assert "pipe-flow" in listing and "R: has a README" in listing
