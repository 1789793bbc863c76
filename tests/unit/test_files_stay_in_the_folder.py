"""Files never outside the folder and never the user's; exit statuses and one-line messages.

Each test replays a way a run, an ensemble or a record once wrote outside its folder or lost a user's file, with ``fb.toml`` (the
fluidized-bed step, 5 s) or ``liq.toml`` (a short El Centro column) where a run is needed."""
from __future__ import annotations

import csv
import json
import os
import signal
import subprocess
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import pytest

import twofluid
from twofluid.casefile.loader import case_text, load_case
from twofluid.casefile.schema import CaseError
from twofluid.cli import main
from twofluid.io.folders import LOCK, MANIFEST

ROOT = Path(__file__).resolve().parents[2]


def _fb(folder: Path) -> Path:
    """fb.toml: the bundled fluidized-bed step ending at 5 s, no plots."""
    import tomli_w

    from twofluid.casefile.schema import effective

    case = load_case("fluidized-bed-step")
    case["time"]["end"] = 5.0
    case["output"].update(times=[5.0], plots=False)
    doc: dict = {}
    for where, table in effective(case).items():
        if not where.startswith("_"):
            node = doc
            *parents, last = where.split(".")
            for part in parents:
                node = node.setdefault(part, {})
            node[last] = table
    path = folder / "fb.toml"
    path.write_text(tomli_w.dumps(doc))
    return path


def _fb_case(folder: Path) -> dict:
    case = load_case(_fb(folder))
    case["output"]["plots"] = False
    return case


def _cli(args, cwd, env=None, timeout=120, preexec=None):
    """``twofluid ARGS`` in a process of its own (exit status, stdout, stderr)."""
    e = {**os.environ, **(env or {})}
    p = subprocess.run([sys.executable, "-m", "twofluid.cli", *map(str, args)], cwd=cwd, capture_output=True,
                       text=True, env=e, timeout=timeout, preexec_fn=preexec)
    return p.returncode, p.stdout, p.stderr


def _one_line(err: str) -> str:
    lines = [x for x in err.strip().splitlines() if x.strip()]
    assert len(lines) == 1, err
    assert "Traceback" not in err
    return lines[0]


ENSEMBLE = """
[ensemble]
name = "{name}"
base = "settling-illite"
collect = ["steps"]
[set]
"time.end" = 0.2
"output.times" = [0.2]
"output.plots" = false
[grid]
"materials.particle_diameter" = [6e-5, 7e-5]
"""


def _tree(folder: Path) -> set[str]:
    return {str(p.relative_to(folder)) for p in folder.rglob("*")}


# ---------------------------------------------------------------- 1. ensemble name
def test_an_ensemble_name_cannot_write_outside_twofluid_out(tmp_path):
    from twofluid.ensemble import load_ensemble
    from twofluid.ensemble.engine import ensemble_out_dir

    work = tmp_path / "a" / "b" / "c"
    work.mkdir(parents=True)
    (work / "e.toml").write_text(ENSEMBLE.format(name="../../../escape"))
    spec = load_ensemble(work / "e.toml")
    out = ensemble_out_dir(spec)
    assert out.parts[0] == "twofluid-out" and len(out.parts) == 2 and ".." not in out.parts
    before = _tree(tmp_path)
    rc, _, err = _cli(["ensemble", "e.toml", "--workers", "1", "--quiet"], cwd=work, timeout=300)
    assert rc == 0, err
    new = _tree(tmp_path) - before
    assert new and all(p.startswith("a/b/c/twofluid-out") for p in new), sorted(new)
    assert "a/b/c/twofluid-out/escape/members.csv" in new


# ---------------------------------------------------------------- 2. symbolic links
def test_a_run_never_writes_through_a_link_planted_in_its_folder(tmp_path):
    fb = _fb(tmp_path)
    run = tmp_path / "run"
    run.mkdir()
    (run / MANIFEST).write_text('{"files":[]}')
    (tmp_path / "outside.csv").write_text("mine\n")
    os.symlink("../outside.csv", run / "profiles.csv")
    rc, _, err = _cli(["run", fb, "--out", run], cwd=tmp_path)
    assert rc == 2 and "profiles.csv" in _one_line(err) and "symbolic link" in err
    assert (tmp_path / "outside.csv").read_text() == "mine\n"
    assert os.path.islink(run / "profiles.csv")


def test_no_writer_follows_a_link(tmp_path):
    from twofluid.io.folders import write_atomic
    from twofluid.io.results import CsvStream

    (tmp_path / "target").write_text("mine")
    os.symlink(tmp_path / "target", tmp_path / "a.csv")
    with pytest.raises(OSError, match="symbolic link"):
        CsvStream(tmp_path / "a.csv", ["x"])
    os.symlink(tmp_path / "target", tmp_path / "s.json.tmp")
    with pytest.raises(OSError, match="symbolic link"):
        write_atomic(tmp_path / "s.json", "{}")
    assert (tmp_path / "target").read_text() == "mine"


# ---------------------------------------------------------------- 3. the user's files
def test_a_folder_with_a_resolved_case_and_a_user_file_keeps_the_file(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / "case.resolved.toml").write_text("# not a run of twofluid's\n")
    (out / "my.csv").write_text("mine\n")
    with pytest.raises(CaseError, match="not empty and holds no earlier twofluid run"):
        twofluid.run_case(_fb_case(tmp_path), out)
    assert (out / "my.csv").read_text() == "mine\n"


def test_a_user_file_added_during_a_run_is_not_recorded_and_survives_the_next(tmp_path, monkeypatch):
    from twofluid.runners import column_1d

    out = tmp_path / "out"
    real = column_1d.integrate

    def integrate(*a, **k):
        for i, s in enumerate(real(*a, **k)):
            if i == 3:
                (out / "my.csv").write_text("mine\n")
                (out / "notes.txt").write_text("mine\n")
            yield s

    monkeypatch.setattr(column_1d, "integrate", integrate)
    assert twofluid.run_case(_fb_case(tmp_path), out).status == "completed"
    listed = json.loads((out / MANIFEST).read_text())["files"]
    assert "summary.json" in listed and "my.csv" not in listed and "notes.txt" not in listed
    monkeypatch.undo()
    assert twofluid.run_case(_fb_case(tmp_path), out).status == "completed"
    assert (out / "my.csv").read_text() == "mine\n" and (out / "notes.txt").read_text() == "mine\n"


def test_a_recorded_file_the_user_changed_is_kept_and_refused(tmp_path):
    out = tmp_path / "out"
    twofluid.run_case(_fb_case(tmp_path), out)
    (out / "probes.csv").write_text("edited by me\n")
    with pytest.raises(CaseError, match="probes.csv.*did not write, or one changed since"):
        twofluid.run_case(_fb_case(tmp_path), out)
    assert (out / "probes.csv").read_text() == "edited by me\n"
    assert not (out / LOCK).exists()


# ---------------------------------------------------------------- 4. ensemble folders
def test_ensemble_folders_are_checked(tmp_path):
    (tmp_path / "e.toml").write_text(ENSEMBLE.format(name="e"))
    user = tmp_path / "user"
    user.mkdir()
    (user / "members.csv").write_text("a,b\n1,2\n")
    rc, _, err = _cli(["ensemble", "e.toml", "--out", user], cwd=tmp_path)
    assert rc == 2 and "not empty" in _one_line(err)
    assert (user / "members.csv").read_text() == "a,b\n1,2\n"
    (tmp_path / "afile").write_text("x")
    rc, _, err = _cli(["ensemble", "e.toml", "--out", "afile"], cwd=tmp_path)
    assert rc == 2 and "existing file" in _one_line(err)


def test_two_ensembles_into_one_folder_the_second_is_refused(tmp_path):
    (tmp_path / "e.toml").write_text(ENSEMBLE.format(name="e"))
    out = tmp_path / "eout"
    out.mkdir()
    (out / LOCK).write_text(f"{os.getppid()}\n")  # an ensemble (a live process) holds it
    with pytest.raises(CaseError, match="in use by another run"):
        twofluid.run_ensemble(str(tmp_path / "e.toml"), out, workers=1)
    assert sorted(p.name for p in out.iterdir()) == [LOCK]


def test_a_members_table_that_is_not_ours_is_refused_even_in_an_owned_folder(tmp_path):
    from twofluid.ensemble.results import ResultsTable

    out = tmp_path / "eout"
    out.mkdir()
    (out / "members.csv").write_text("a,b\n1,2\n")
    with pytest.raises(CaseError, match="not a members table"):
        ResultsTable(out / "members.csv", [], ["x"], set())


# ---------------------------------------------------------------- 5. full disk
def _limit(nbytes):
    import resource

    def set_limit():
        resource.setrlimit(resource.RLIMIT_FSIZE, (nbytes, nbytes))
    return set_limit


def test_a_full_disk_leaves_no_half_row_and_names_the_file(tmp_path):
    fb = _fb(tmp_path)
    rc, out, err = _cli(["run", fb, "--out", "o"], cwd=tmp_path, preexec=_limit(8 * 1024))
    assert rc == 1, err
    assert "File too large" in err and ("profiles.csv" in err or "probes.csv" in err)
    assert "Traceback" not in err
    for name in ("profiles.csv", "probes.csv"):
        raw = (tmp_path / "o" / name).read_bytes()
        assert raw.endswith(b"\r\n")
        rows = list(csv.reader(raw.decode().splitlines()))
        assert len({len(r) for r in rows}) == 1, name  # every row whole
    s = json.loads((tmp_path / "o" / "summary.json").read_text())
    assert s["status"] == "failed" and "File too large" in s["reason"]
    json.loads((tmp_path / "o" / MANIFEST).read_text())  # never empty


def test_a_summary_that_cannot_be_written_is_never_left_empty_and_the_message_names_it(tmp_path, monkeypatch):
    from twofluid.io import folders

    out = tmp_path / "o"
    twofluid.run_case(_fb_case(tmp_path), out)
    real = folders.write_all

    def full(fd, data, path):
        if str(path).endswith("summary.json"):
            raise OSError(28, "No space left on device", str(path))
        return real(fd, data, path)

    monkeypatch.setattr(folders, "write_all", full)
    with pytest.raises(OSError, match="summary.json"):
        twofluid.run_case(_fb_case(tmp_path), out)
    monkeypatch.undo()
    assert not (out / "summary.json.tmp").exists() and not (out / LOCK).exists()
    doc = json.loads((out / MANIFEST).read_text())  # whole, listing what the run wrote
    assert {"probes.csv", "profiles.csv"} <= set(doc["files"])
    assert twofluid.run_case(_fb_case(tmp_path), out).status == "completed"  # the next run clears them


def test_a_record_that_cannot_be_written_at_the_end_is_a_warning_naming_it(tmp_path, monkeypatch):
    from twofluid.io import folders

    real = folders.OutputFolder._save

    def save(self, final=False):
        if final:
            raise OSError(28, "No space left on device")
        return real(self, final)

    monkeypatch.setattr(folders.OutputFolder, "_save", save)
    with pytest.warns(folders.OutputWarning, match=r"\.twofluid-run\.json: cannot be written"):
        twofluid.run_case(_fb_case(tmp_path), tmp_path / "o")
    doc = json.loads((tmp_path / "o" / MANIFEST).read_text())  # the one written while it ran
    assert "summary.json" in doc["files"]


# ---------------------------------------------------------------- 6. records
def _liq(folder: Path, record: str | None = None) -> dict:
    case = load_case("liquefaction-elcentro")
    case["time"]["end"] = 0.1
    case["ground_motion"]["duration"] = 0.1
    case["output"].update(times=[], plots=False)
    if record:
        case["ground_motion"]["file"] = record
    return case


def test_a_record_with_uneven_steps_is_refused_before_the_run(tmp_path):
    t = [0.0, 0.013, 0.023, 0.030] + [0.030 + 0.01 * i for i in range(1, 40)]
    rows = "\n".join(f"{x:.6g},{0.01 * np.sin(7 * x):.6g}" for x in t)
    (tmp_path / "rec.csv").write_text("time_s,acceleration_g\n" + rows + "\n")
    with pytest.raises(CaseError, match=r"uneven time steps \(0.013 s, then 0.01 s") as exc:
        twofluid.run_case(_liq(tmp_path, str(tmp_path / "rec.csv")), tmp_path / "o")
    assert "\n" not in str(exc.value)
    assert not (tmp_path / "o").exists()


def test_an_absurd_at2_sample_interval_is_refused(tmp_path):
    vals = " ".join(f"{0.01 * np.sin(i):.6f}" for i in range(50))
    (tmp_path / "r.AT2").write_text("PEER\nx\nACCELERATION TIME SERIES IN UNITS OF G\n"
                                    f"NPTS=   50, DT= 1e-300 SEC\n{vals}\n")
    with pytest.raises(CaseError, match=r"DT = 1e-300 s is outside the valid range"):
        twofluid.run_case(_liq(tmp_path, str(tmp_path / "r.AT2")), tmp_path / "o")


# ---------------------------------------------------------------- 7. member count
def test_a_huge_grid_is_refused_before_it_is_expanded(tmp_path):
    from twofluid.ensemble.spec import parse_ensemble

    grid = {f"materials.{k}": [1.0 + i * 1e-3 for i in range(100)] for k in
            ("particle_density", "liquid_density", "liquid_viscosity", "particle_diameter", "sphericity",
             "gravity")}
    t0 = time.process_time()
    with pytest.raises(CaseError, match=r"gives 1e\+12 members .*more than the 100000"):
        parse_ensemble({"ensemble": {"base": "settling-illite", "collect": ["steps"]}, "grid": grid})
    assert time.process_time() - t0 < 30.0  # refused from the sizes, not after expanding 1e12 members


# ---------------------------------------------------------------- 8. the API
@pytest.mark.parametrize("spec", [None, 42, {}, ""])
def test_run_ensemble_refuses_what_is_not_an_ensemble(spec):
    with pytest.raises(CaseError, match="ensemble: must be an EnsembleSpec or the path"):
        twofluid.run_ensemble(spec)


@pytest.mark.parametrize("kw, match", [({"out_dir": 42}, "must be a path"),
                                       ({"out_dir": "/dev/null"}, "not a folder"),
                                       ({"out_dir": ""}, "is empty"),
                                       ({"workers": -1}, r"workers: -1 is not valid"),
                                       ({"workers": 0}, r"workers: 0 is not valid"),
                                       ({"workers": 2.5}, r"workers: 2.5 is not valid")])
def test_run_ensemble_refuses_bad_arguments(tmp_path, kw, match):
    (tmp_path / "e.toml").write_text(ENSEMBLE.format(name="e"))
    with pytest.raises(CaseError, match=match) as exc:
        twofluid.run_ensemble(str(tmp_path / "e.toml"), **kw)
    assert "\n" not in str(exc.value)


def test_a_case_with_a_source_that_is_not_text_is_a_case_error(tmp_path):
    case = _fb_case(tmp_path)
    case["_source"] = 42
    with pytest.raises(CaseError, match="_source: must be a string"):
        twofluid.run_case(case)


# ---------------------------------------------------------------- 9. no NaN or inf in any file
def test_failed_members_write_no_nan_or_inf(tmp_path):
    from twofluid.ensemble.results import ResultsTable

    t = ResultsTable(tmp_path / "members.csv", ["time.end"], ["x", "y"], set())
    t.write({"member": 0, "hash": "", "status": "failed", "reason": "invalid case", "time.end": float("nan"),
             "x": float("inf"), "y": [1.0, float("nan")]})
    t.close()
    text = (tmp_path / "members.csv").read_text()
    assert "nan" not in text.lower() and "inf" not in text.lower()
    assert text.splitlines()[1].endswith(',,,"[1.0,null]"')


def test_vtu_fields_hold_no_nan():
    import meshio
    import tempfile

    from twofluid.io.fields import FILL_UNDEFINED, FieldWriter
    from twofluid.mesh.quad import rectangle

    d = Path(tempfile.mkdtemp())
    w = FieldWriter(d, rectangle(0, 1, 0, 1, 2, 2))
    us = np.array([[0.1, 0.2], [np.nan, np.nan], [0.0, 0.1], [0.3, 0.0]])
    w.write(0.0, {"V": np.zeros((9, 2))}, {"porosity": np.array([0.5, 1.0, 0.5, 0.5]), "U_s": us})
    m = meshio.read(d / "fields_0000.vtu")
    got = m.cell_data["U_s"][0]
    assert np.isfinite(got).all() and (got[1] == FILL_UNDEFINED).all()
    assert m.cell_data["U_s_defined"][0].tolist() == [1, 0, 1, 1]


def test_fs_of_soil_that_cannot_liquefy_is_an_empty_cell_with_its_reason(tmp_path):
    case = load_case("liquefaction-layered-site")
    case["time"]["end"] = 0.2
    case["ground_motion"]["duration"] = 0.2
    case["output"].update(times=[], plots=False)
    res = twofluid.run_case(case, tmp_path / "o")
    assert res.status == "completed", res.summary["reason"]
    for name in ("elements.csv", "layers.csv"):
        text = (tmp_path / "o" / name).read_text()
        assert "inf" not in text.lower() and "nan" not in text.lower()
        rows = list(csv.DictReader(text.splitlines()))
        fs = [k for k in rows[0] if k.startswith("FS_") and k != "FS_note"]
        empty = [r for r in rows if any(r[k] == "" for k in fs)]
        assert empty, name  # the crust cannot liquefy
        assert all(r["FS_note"] == "NL" for r in empty)
        assert all(r["FS_note"] == "" for r in rows if r not in empty)


# ---------------------------------------------------------------- 10. exits and messages
def _signal_after_output(tmp_path, sig):
    """A run stopped by ``sig`` as it writes its last file: interrupted status, exit 130/143."""
    fb = _fb(tmp_path)
    code = ("import os, signal, sys\n"
            "import twofluid.io.folders as f\n"
            "real = f.OutputFolder._save\n"
            "def save(self, final=False):\n"
            "    real(self, final)\n"
            f"    if final: os.kill(os.getpid(), signal.{sig})\n"
            "f.OutputFolder._save = save\n"
            "from twofluid.cli import main\n"
            f"sys.argv = ['twofluid', 'run', {str(fb)!r}, '--out', 'o']\n"
            "main()\n")
    p = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True, timeout=120)
    return p.returncode, json.loads((tmp_path / "o" / "summary.json").read_text()), p.stderr


@pytest.mark.parametrize("sig, status", [("SIGINT", 130), ("SIGTERM", 143)])
def test_a_signal_as_the_run_ends_is_an_interrupted_run(tmp_path, sig, status):
    rc, s, err = _signal_after_output(tmp_path, sig)
    assert rc == status, err
    assert s["status"] == "interrupted" and "as the run ended" in s["reason"]
    assert "Traceback" not in err


@pytest.mark.parametrize("sig, status", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_a_signal_during_the_imports_is_one_line(tmp_path, sig, status):
    code = ("import os, signal, sys\n"
            "from twofluid.cli import main\n"
            "import twofluid.cli as c\n"
            "real = c.parser\n"
            f"def parser():\n    os.kill(os.getpid(), {int(sig)})\n    return real()\n"
            "c.parser = parser\n"
            "sys.argv = ['twofluid', 'cases']\n"
            "main()\n")
    p = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True, timeout=60)
    said = "twofluid: terminated (SIGTERM)" if sig == signal.SIGTERM else "twofluid: interrupted"
    assert p.returncode == status and _one_line(p.stderr) == said


def test_meshio_says_nothing_of_its_own(tmp_path, capfd):
    from twofluid.mesh.gmsh_io import MeshError, read_quad_mesh

    (tmp_path / "m.msh").write_text("not a mesh\n")
    with pytest.raises(MeshError, match="m.msh: cannot read mesh"):
        read_quad_mesh(tmp_path / "m.msh")
    out, err = capfd.readouterr()
    assert out == "" and err == ""


def _msh(path: Path, x0: float, duplicate: bool) -> Path:
    nodes = [(1, x0, 0.0), (2, 1.0, 0.0), (3, 1.0, 1.0), (4, 0.0, 1.0)]
    elems = [(1, 3, 4, 1, 2, 3, 4)] + ([(2, 3, 4, 1, 2, 3, 4)] if duplicate else [])
    text = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$Nodes", str(len(nodes))]
    text += [f"{i} {x!r} {y!r} 0" for i, x, y in nodes] + ["$EndNodes", "$Elements", str(len(elems))]
    text += [f"{e[0]} {e[1]} 2 {e[2]} {e[2]} {e[3]} {e[4]} {e[5]} {e[6]}" for e in elems] + ["$EndElements"]
    path.write_text("\n".join(text) + "\n")
    return path


def test_a_huge_coordinate_and_a_duplicated_element_are_refused_at_loading(tmp_path):
    from twofluid.mesh.gmsh_io import MeshError, read_quad_mesh

    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no NumPy warning on the way
        with pytest.raises(MeshError, match="coordinate 1e\\+300"):
            read_quad_mesh(_msh(tmp_path / "big.msh", 1e300, False))
        with pytest.raises(MeshError, match="duplicated element"):
            read_quad_mesh(_msh(tmp_path / "dup.msh", 0.0, True))
    assert read_quad_mesh(_msh(tmp_path / "ok.msh", 0.0, False)).n_elements == 1


def test_an_empty_out_and_a_device_are_refused(tmp_path, capsys):
    fb = _fb(tmp_path)
    assert main(["run", str(fb), "--out", ""]) == 2
    assert "is empty" in _one_line(capsys.readouterr().err)
    assert main(["run", "/dev/zero"]) == 2
    assert "is not a case file" in _one_line(capsys.readouterr().err)


def test_a_folder_named_like_an_output_is_found_before_the_run(tmp_path, monkeypatch):
    from twofluid.runners import column_1d

    out = tmp_path / "o"
    twofluid.run_case(_fb_case(tmp_path), out)
    (out / "summary.json").unlink()
    (out / "summary.json").mkdir()
    called = []
    monkeypatch.setattr(column_1d, "build", lambda *a, **k: called.append(1))
    with pytest.raises(CaseError, match="summary.json: output folder: is a folder"):
        twofluid.run_case(_fb_case(tmp_path), out)
    assert not called and (out / "summary.json").is_dir()
