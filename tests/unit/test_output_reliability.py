"""Output folders, stops while finishing, full disks and signals: each test fails on the defect it names."""
import errno
import json
import os
import shutil
import signal
import subprocess
import sys
import threading

import pytest

import twofluid
from twofluid.casefile.loader import load_case
from twofluid.casefile.schema import CaseError
from twofluid.io import folders
from twofluid.io.folders import LOCK, MANIFEST, OutputFolder
from twofluid.runners import run_case

EXE = [shutil.which("twofluid")] if shutil.which("twofluid") else [sys.executable, "-m", "twofluid.cli"]


def _short(steps=4, plots=True):
    case = load_case("settling-illite")
    case["time"]["end"] = steps * case["time"]["step"]
    case["output"].update(times=[], probes=[], plots=plots)
    return case


def _outside(tmp_path):
    target = tmp_path / "outside.txt"
    target.write_text("the user's\n")
    return target


# ---------------------------------------------------------------- commands that write into --out
@pytest.mark.parametrize("argv, name", [
    (["fluidization-curve", "fluidized-bed-step", "--no-plots"], "fluidization_curve.csv"),
    (["element-test", "--gamma", "2e-3", "--max-cycles", "1", "--steps-per-cycle", "20"], "element_test.csv"),
])
def test_out_folders_of_the_commands_are_not_written_through_planted_links(tmp_path, argv, name):
    target = _outside(tmp_path)
    out = tmp_path / "out"
    out.mkdir()
    os.symlink(target, out / name)  # into a folder of no earlier run
    p = subprocess.run([*EXE, *argv, "--out", str(out)], capture_output=True, text=True, timeout=300)
    assert p.returncode == 2 and "not empty" in p.stderr, p.stderr
    (out / name).unlink()
    assert subprocess.run([*EXE, *argv, "--out", str(out)], capture_output=True, timeout=300).returncode == 0
    (out / name).unlink()
    os.symlink(target, out / name)  # into the folder of the command's earlier run
    p = subprocess.run([*EXE, *argv, "--out", str(out)], capture_output=True, text=True, timeout=300)
    assert p.returncode == 2 and "symbolic link" in p.stderr, p.stderr
    assert target.read_text() == "the user's\n" and (out / name).is_symlink()


@pytest.mark.parametrize("argv", [["fluidization-curve", "fluidized-bed-step", "--no-plots"],
                                  ["element-test", "--gamma", "2e-3", "--max-cycles", "1", "--steps-per-cycle", "20"]])
def test_out_folders_of_the_commands_keep_another_programs_summary(tmp_path, argv):
    out = tmp_path / "out"
    out.mkdir()
    (out / "summary.json").write_text('{"mine": true}\n')
    p = subprocess.run([*EXE, *argv, "--out", str(out)], capture_output=True, text=True, timeout=300)
    assert p.returncode == 2 and "not empty" in p.stderr, p.stderr
    assert (out / "summary.json").read_text() == '{"mine": true}\n'


def test_a_rerun_of_a_command_replaces_its_own_files_only(tmp_path):
    out = tmp_path / "out"
    argv = [*EXE, "fluidization-curve", "fluidized-bed-step", "--no-plots", "--out", str(out)]
    assert subprocess.run(argv, capture_output=True, timeout=300).returncode == 0
    assert subprocess.run(argv, capture_output=True, timeout=300).returncode == 0  # its own earlier curve
    assert sorted(e.name for e in out.iterdir()) == [MANIFEST, "fluidization_curve.csv"]


def test_the_hysteretic_element_test_refuses_what_it_would_ignore(capsys):
    from twofluid.cli import main

    for extra in (["--drained"], ["--porosity", "0.4"], ["--A", "1e-3"], ["--gamma-ref", "1e-3"],
                  ["--law", "ann"], ["--out", "somewhere"]):
        assert main(["element-test", "--model", "hysteretic", *extra]) == 2, extra
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and extra[0] in err
    assert not os.path.exists("somewhere")


# ---------------------------------------------------------------- links and files that appear during a run
def test_a_link_planted_during_a_run_is_not_followed_by_the_figures(tmp_path, monkeypatch):
    target = _outside(tmp_path)
    real = folders.write_atomic

    def plant_then_write(path, data):
        if str(path).endswith(".png") and not os.path.lexists(path):
            os.symlink(target, path)  # planted while the run goes, just before the figure is written
        return real(path, data)
    monkeypatch.setattr(folders, "write_atomic", plant_then_write)
    res = run_case(_short(), tmp_path / "run")
    assert target.read_text() == "the user's\n"
    assert res.status == "failed" and "symbolic link" in res.summary["reason"]
    links = [e for e in (tmp_path / "run").iterdir() if e.is_symlink()]
    assert links and all(os.readlink(e) == str(target) for e in links)  # the user's links left as they are


def test_a_users_file_with_an_outputs_name_added_during_a_run_is_not_removed_later(tmp_path, monkeypatch):
    real = folders.write_atomic
    mine = tmp_path / "run" / "elements.csv"  # a name twofluid writes (not in this 1D run)

    def add_users_file(path, data):
        if str(path).endswith("summary.json") and not mine.exists():
            mine.write_text("the user's table\n")
        return real(path, data)
    monkeypatch.setattr(folders, "write_atomic", add_users_file)
    assert run_case(_short(plots=False), tmp_path / "run").status == "completed"
    monkeypatch.setattr(folders, "write_atomic", real)
    with pytest.raises(CaseError, match="elements.csv"):  # the next run refuses to overwrite it
        run_case(_short(plots=False), tmp_path / "run")
    assert mine.read_text() == "the user's table\n"


def test_figures_a_stopped_run_had_written_do_not_block_the_next_run(tmp_path, monkeypatch):
    real = folders.write_atomic
    n = {"png": 0}

    def stop_after_first_figure(path, data):
        real(path, data)
        if str(path).endswith(".png"):
            n["png"] += 1
            raise KeyboardInterrupt  # stopped while drawing the figures
    monkeypatch.setattr(folders, "write_atomic", stop_after_first_figure)
    res = run_case(_short(), tmp_path / "run")
    assert res.status == "interrupted" and n["png"] == 1
    monkeypatch.setattr(folders, "write_atomic", real)
    assert run_case(_short(), tmp_path / "run").status == "completed"


# ---------------------------------------------------------------- stops and full disks while finishing
def test_a_stop_before_the_summary_reports_where_the_time_loop_ended(tmp_path, monkeypatch):
    import twofluid.runners.column_1d as c1

    def stop(path, data):
        raise KeyboardInterrupt
    monkeypatch.setattr(c1, "write_json", stop)
    res = run_case(_short(steps=4), tmp_path / "run")
    s = json.loads((tmp_path / "run" / "summary.json").read_text())
    assert s["status"] == "interrupted" and "summary and plots" in s["reason"]
    assert s["stopped_at_s"] == pytest.approx(4 * load_case("settling-illite")["time"]["step"]) and s["steps"] == 4
    assert res.summary == s


def _disk_with(monkeypatch, free: int):
    """A disk with ``free`` bytes left: a write that makes a file longer takes from them (ENOSPC when
    none are left); a write over bytes the file already has takes nothing."""
    real = folders.write_all
    left = {"n": free}

    def write_all(fd, data, path):
        pos, size = os.lseek(fd, 0, os.SEEK_CUR), os.fstat(fd).st_size
        grow = max(pos + len(data) - size, 0)
        if grow > left["n"]:
            raise OSError(errno.ENOSPC, "No space left on device", str(path))
        left["n"] -= grow
        real(fd, data, path)
    monkeypatch.setattr(folders, "write_all", write_all)
    return left


def test_a_disk_that_fills_while_drawing_gives_a_failed_summary_not_completed(tmp_path, monkeypatch):
    real = folders.write_atomic

    def full_from_the_figures(path, data):
        if str(path).endswith(".png") or full_from_the_figures.full:
            full_from_the_figures.full = True
            _disk_with(monkeypatch, 150)  # the lock and the folder record fit, nothing more
        return real(path, data)
    full_from_the_figures.full = False
    monkeypatch.setattr(folders, "write_atomic", full_from_the_figures)
    res = run_case(_short(), tmp_path / "run")
    s = json.loads((tmp_path / "run" / "summary.json").read_text())
    assert res.status == "failed" and s["status"] == "failed" and "No space left" in s["reason"], s


@pytest.mark.parametrize("free_kb", [8, 16, 24, 32, 48, 64, 80, 96, 128, 160, 256])
def test_a_nearly_full_disk_still_gets_a_summary_that_says_what_happened(tmp_path, monkeypatch, free_kb):
    case = _short(steps=40)
    case["output"]["times"] = [case["time"]["step"] * i for i in range(1, 41)]  # CSVs that fill the disk
    (tmp_path / "run").mkdir()
    _disk_with(monkeypatch, free_kb * 1024)
    try:
        res = run_case(case, tmp_path / "run")
    except OSError:
        res = None
    s = json.loads((tmp_path / "run" / "summary.json").read_text())  # always there, whole
    assert res is not None and s["status"] == res.status, (s, res and res.status)
    assert s["status"] == "completed" or "No space left" in s["reason"], s


def test_a_disk_too_full_for_any_summary_is_an_error_naming_it(tmp_path, monkeypatch):
    (tmp_path / "run").mkdir()
    _disk_with(monkeypatch, 150)  # the lock and the folder record fit, nothing more
    with pytest.raises(OSError, match="summary.json"):
        run_case(_short(), tmp_path / "run")


# ---------------------------------------------------------------- the lock
def test_no_empty_lock_file_is_left_by_a_stop_while_locking(tmp_path, monkeypatch):
    real = folders.write_all

    def stop(fd, data, path):
        if LOCK in str(path):
            raise KeyboardInterrupt
        real(fd, data, path)
    monkeypatch.setattr(folders, "write_all", stop)
    with pytest.raises(KeyboardInterrupt):
        with OutputFolder(tmp_path / "run"):
            pass
    assert not [e.name for e in (tmp_path / "run").iterdir() if e.name.startswith(LOCK)]


# ---------------------------------------------------------------- ensembles
def test_a_bad_scheduler_argument_is_a_case_error(tmp_path):
    for bad in (42, "", "   ", ["tcp://x:1"]):
        with pytest.raises(CaseError, match="scheduler"):
            twofluid.run_ensemble("elcentro-pga-sweep", tmp_path / "e", scheduler=bad)
    assert not (tmp_path / "e").exists()


@pytest.mark.parametrize("sig, raised", [(signal.SIGINT, KeyboardInterrupt), ("SIGTERM", "Terminated")])
def test_a_signal_while_the_cluster_starts_interrupts_and_closes_it(monkeypatch, sig, raised):
    """The workers must not see a Ctrl-C meant for the driver, but the driver must: a SIGINT (or
    SIGTERM) that comes while the local cluster starts interrupts once the start returns, and the
    cluster is closed."""
    import distributed

    from twofluid.ensemble.engine import cluster_client
    from twofluid.runners.common import Terminated

    sig = getattr(signal, sig) if isinstance(sig, str) else sig
    raised = Terminated if raised == "Terminated" else raised
    closed = []

    class Starting:
        def __init__(self, *a, **k):
            # the signal in the middle of the start, to the driver's (main) thread: sent to the process,
            # a thread another test left running (dask's) may take it instead and make the test flaky
            signal.pthread_kill(threading.main_thread().ident, sig)

        def __enter__(self):
            return self

        def __exit__(self, *exc):
            closed.append(True)
            return False

    monkeypatch.setattr(distributed, "LocalCluster", Starting)
    monkeypatch.setattr(distributed, "Client", lambda cluster: pytest.fail("no client after the signal"))
    old = signal.getsignal(signal.SIGTERM)
    with pytest.raises(raised):
        with cluster_client(workers=1):
            pytest.fail("the ensemble went on after a signal during the cluster's start")
    assert closed == [True] and signal.getsignal(signal.SIGTERM) == old
    assert signal.SIGINT not in signal.pthread_sigmask(signal.SIG_BLOCK, set())


def test_off_a_terminal_an_ensemble_prints_a_progress_line_at_a_steady_pace():
    import io
    import time

    from twofluid.ensemble.engine import ProgressLines

    out = io.StringIO()
    p = ProgressLines("sweep", 10, every=0.05, stream=out).start(done=3)
    time.sleep(0.4)
    p.done, p.failed = 5, 1
    time.sleep(0.2)
    p.close()
    lines = out.getvalue().splitlines()
    assert len(lines) >= 4  # whether or not a member finished meanwhile
    assert lines[0].startswith("twofluid: ensemble sweep: 3 of 10 members done, ")
    assert "5 of 10 members done (1 failed)" in lines[-1]


@pytest.mark.parametrize("extra, progress", [([], "lines"), (["--quiet"], False)])
def test_the_ensemble_command_asks_for_progress_lines_off_a_terminal(tmp_path, monkeypatch, extra, progress):
    import twofluid.ensemble as ens
    from twofluid.cli import main

    asked = {}

    def run_ensemble(spec, out, **kw):
        asked.update(kw)
        return []
    monkeypatch.setattr(ens, "run_ensemble", run_ensemble)
    monkeypatch.setattr(sys.stderr, "isatty", lambda: False, raising=False)
    assert main(["ensemble", "elcentro-pga-sweep", "--out", str(tmp_path / "e"), *extra]) == 0
    assert asked["progress"] == progress
