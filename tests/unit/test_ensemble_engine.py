"""The ensemble engine on a LocalCluster of 2 worker processes: the same figures as the same
members run one by one, failing members recorded while the rest complete, reruns that skip
completed members, SIGTERM keeping every finished member, the table in memory and on disk."""
from __future__ import annotations

import csv
import json
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

import twofluid
from twofluid.ensemble import load_ensemble
from twofluid.ensemble.engine import cluster_client
from twofluid.ensemble.members import members

GRID = """
[ensemble]
name = "small-grid"
base = "settling-illite"
collect = ["porosity_range", "solids_volume_m3.final", "profile.porosity@end"]
[set]
"time.end" = 2.0
"output.times" = [2.0]
[grid]
"materials.particle_diameter" = [5e-5, 7e-5]
"closures.solids_pressure.compressibility" = [0.1, 0.2, -1.0]
"""
PICARD_TOL = 1e-7  # [numerics] picard_tol of the case: how far two converged runs may differ


@pytest.fixture(scope="module")
def client():
    with cluster_client(workers=2) as c:
        yield c


def read_rows(path):
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def test_a_grid_gives_the_figures_of_its_members_run_one_by_one(tmp_path, client):
    path = tmp_path / "grid.toml"
    path.write_text(GRID)
    rows = twofluid.run_ensemble(str(path), tmp_path / "out", client=client)
    assert [r["member"] for r in rows] == list(range(6))
    done = [r for r in rows if r["status"] == "completed"]
    assert len(done) == 4
    for r, m in zip(rows, members(load_ensemble(path))):
        if m.error:
            continue
        alone = twofluid.run_case(m.case, tmp_path / f"alone-{m.index}")
        assert r["hash"] == m.hash
        assert r["solids_volume_m3.final"] == pytest.approx(alone.summary["solids_volume_m3"]["final"],
                                                           rel=PICARD_TOL)
        n_alone = alone.profiles[max(alone.profiles)]["porosity"]
        np.testing.assert_allclose(r["profile.porosity@end"], n_alone, rtol=0, atol=PICARD_TOL)
        np.testing.assert_allclose(r["porosity_range"], alone.summary["porosity_range"], rtol=0, atol=PICARD_TOL)
    # the table on disk holds the same rows (lists as JSON), and the summary counts them
    disk = {int(d["member"]): d for d in read_rows(tmp_path / "out" / "members.csv")}
    assert set(disk) == set(range(6))
    assert json.loads(disk[0]["profile.porosity@end"]) == rows[0]["profile.porosity@end"]
    summary = json.loads((tmp_path / "out" / "ensemble.json").read_text())
    assert summary["completed"] == 4 and len(summary["failed"]) == 2 and summary["invalid"] == 2
    assert summary["figures"]["solids_volume_m3.final"]["unit"] == "m³"
    assert (tmp_path / "out" / "figure_solids_volume_m3_final.png").is_file()


def test_failing_members_are_recorded_and_the_rest_complete(tmp_path, client):
    """An invalid combination (schema), a record that cannot be read (found on the worker) and
    a run whose time step fails: each is a failed row with its reason; the others complete."""
    from twofluid.casefile.loader import case_text

    base = tmp_path / "liq.toml"
    base.write_text(case_text("liquefaction-elcentro").replace("end = 3600.0", "end = 0.4").replace(
        "times = [6.0, 10.0, 20.0, 30.0, 60.0, 120.0]", "times = [0.4]").replace("duration = 6.0", "duration = 0.4"))
    rec = tmp_path / "records"
    rec.mkdir()
    from importlib import resources

    good = resources.files("twofluid") / "data" / "ground_motions" / "RSN6_IMPVALL.I_I-ELC180-hor1.AT2"
    (rec / "a_good.AT2").write_text(good.read_text())
    (rec / "b_broken.AT2").write_text("this is not a PEER record\n")
    path = tmp_path / "ens.toml"
    path.write_text(f"""
[ensemble]
base = "{base}"
collect = ["settlement_end_m", "peak_r_u_top_element"]
[ground_motions]
files = "records"
pga_g = [0.1, 6.0]
""")
    rows = twofluid.run_ensemble(str(path), tmp_path / "out", client=client, plots=False)
    by = {(r["ground_motion.file"], r["ground_motion.pga_g"]): r for r in rows}
    assert by[("a_good.AT2", 0.1)]["status"] == "completed"
    assert by[("a_good.AT2", 0.1)]["settlement_end_m"] is not None
    broken = by[("b_broken.AT2", 0.1)]
    assert broken["status"] == "failed" and "b_broken.AT2" in broken["reason"]
    for f in ("a_good.AT2", "b_broken.AT2"):  # 6 g is outside [0, 5] g: invalid before running
        r = by[(f, 6.0)]
        assert r["status"] == "failed" and "[ground_motion] pga_g" in r["reason"] and "[0, 5]" in r["reason"]
    assert all("\n" not in r["reason"] for r in rows)


def test_a_rerun_skips_completed_members_and_runs_failed_or_missing_ones(tmp_path, client):
    path = tmp_path / "grid.toml"
    path.write_text(GRID)
    out = tmp_path / "out"
    first = twofluid.run_ensemble(str(path), out, client=client, plots=False)
    table = out / "members.csv"
    rows = read_rows(table)
    missing = next(r for r in rows if r["status"] == "completed")
    with open(table, "w", newline="") as fh:  # lose one completed member, as if it never finished
        w = csv.DictWriter(fh, list(rows[0]))
        w.writeheader()
        w.writerows(r for r in rows if r is not missing)
    again = twofluid.run_ensemble(str(path), out, client=client, plots=False)
    summary = json.loads((out / "ensemble.json").read_text())
    assert summary["kept_from_before"] == 3 and summary["ran"] == 1 and summary["invalid"] == 2
    assert [(r["member"], r["status"], r["hash"]) for r in again] == [(r["member"], r["status"], r["hash"])
                                                                        for r in first]
    kept = [r for r in again if r["status"] == "completed" and r["hash"] != missing["hash"]]
    assert all(r["wall_time_s"] == pytest.approx(f["wall_time_s"]) for r, f in
               zip(kept, [f for f in first if f["status"] == "completed" and f["hash"] != missing["hash"]]))
    # a changed ensemble: its new members run, rows of members no longer in it move aside
    path.write_text(GRID.replace("[5e-5, 7e-5]", "[5e-5, 6e-5]"))
    twofluid.run_ensemble(str(path), out, client=client, plots=False)
    summary = json.loads((out / "ensemble.json").read_text())
    assert summary["kept_from_before"] == 2 and summary["ran"] == 2
    assert len(read_rows(out / "members.previous.csv")) == 2


@pytest.mark.skipif(sys.platform == "win32", reason="SIGTERM")
def test_sigterm_stops_the_ensemble_keeping_every_finished_member(tmp_path, client):
    path = tmp_path / "long.toml"
    # 12 members, more than the driver's window (8 members with 2 worker threads), each of
    # 4000 steps (about 0.5 s of CPU): the signal comes while members are still to be sent
    path.write_text(GRID.replace('"time.end" = 2.0', '"time.end" = 4.0\n"time.step" = 0.001').replace(
        '"output.times" = [2.0]', '"output.times" = [4.0]').replace("[0.1, 0.2, -1.0]",
                                                                   "[0.1, 0.12, 0.14, 0.16, 0.18, 0.2]"))
    out = tmp_path / "out"
    proc = subprocess.Popen([sys.executable, "-m", "twofluid.cli", "ensemble", str(path), "--out", str(out),
                             "--workers", "2", "--quiet"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline:  # wait for two finished members
        if (out / "members.csv").is_file() and len(read_rows(out / "members.csv")) >= 2:
            break
        time.sleep(0.2)
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 143, err  # SIGTERM's documented status (130 is Ctrl-C's)
    assert "terminated (SIGTERM)" in err and "members.csv" in err
    finished = read_rows(out / "members.csv")
    assert 2 <= len(finished) < 12 and all(r["status"] == "completed" for r in finished)
    record = json.loads((out / "ensemble.json").read_text())
    assert record["status"] == "interrupted" and record["reason"] == "terminated (SIGTERM)"
    twofluid.run_ensemble(str(path), out, client=client, plots=False)
    summary = json.loads((out / "ensemble.json").read_text())
    assert summary["kept_from_before"] == len(finished) and summary["completed"] == 12


def test_the_bundled_example_runs_briefly_with_its_fragility(tmp_path, client):
    """The bundled PGA sweep at coarse settings (one PGA × 2 draws, 1 s of shaking): it runs,
    and ensemble.json holds one fragility entry per report depth, fitted or with its note."""
    spec = load_ensemble("elcentro-pga-sweep")
    spec.set.update({"time.end": 1.0, "output.times": [1.0], "ground_motion.duration": 1.0})
    spec.motions["pga_g"] = [0.3]
    spec.sample["count"] = 2
    rows = twofluid.run_ensemble(spec, tmp_path, client=client)
    assert len(rows) == 2 and all(r["status"] == "completed" for r in rows), [r["reason"] for r in rows]
    summary = json.loads((tmp_path / "ensemble.json").read_text())
    curves = summary["fragility"]["curves"]
    assert [c["label"] for c in curves] == rows[0]["report_depths.depth_m"]
    assert all((c["theta"] is None) == (c["note"] != "maximum likelihood") for c in curves)
    assert (tmp_path / "fragility.png").stat().st_size > 10_000
