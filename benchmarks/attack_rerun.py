"""Replay representative trials of issue 23's attack classes and count the failures of each class.

Classes (every count should be 0):

- outside write: a file created, changed or removed outside the run's folder (the sandbox's other
  files, including a file a planted symbolic link points to);
- lost data: a file of the user's removed or changed, a CSV with a half row, an empty or unreadable
  summary.json / .twofluid-run.json;
- traceback: "Traceback" on stderr, or an exit status outside {0, 1, 2, 130, 143};
- non-CaseError: an API call with bad input that raises anything but CaseError;
- silent non-finite: "nan" or "inf" in a CSV or JSON file written, NaN in a VTU file;
- multi-line: an error (exit 2) or interruption reported in more than one line (warnings excepted).

Groups: case-file mutations of two bundled cases, API calls, folders, signals at random moments,
file-size limits (a full disk). Local and bounded (about 2-4 min on 2 cores):

    python benchmarks/attack_rerun.py [--seed 1] [--mutations 40] [--signals 16]
"""
from __future__ import annotations

import argparse
import json
import os
import random
import resource
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

COUNTS = {k: 0 for k in ("outside write", "lost data", "traceback", "non-CaseError", "silent non-finite",
                         "multi-line")}
TRIALS = {"case-file mutations": 0, "API calls": 0, "folders": 0, "signals": 0, "full disk": 0}
LOG: list[str] = []


def bad(cls: str, what: str) -> None:
    COUNTS[cls] += 1
    LOG.append(f"{cls}: {what}")


def snapshot(root: Path, skip: Path | None = None) -> dict:
    out = {}
    for p in root.rglob("*"):
        if skip is not None and (p == skip or skip in p.parents):
            continue
        try:
            st = p.lstat()
        except OSError:
            continue
        if p.is_dir() and not p.is_symlink():  # a folder's own times change as entries are made in it
            out[str(p.relative_to(root))] = "folder"
            continue
        out[str(p.relative_to(root))] = (st.st_size, st.st_mtime_ns, os.path.islink(p))
    return out


def cli(args, cwd, preexec=None, timeout=300):
    p = subprocess.run([sys.executable, "-m", "twofluid.cli", *map(str, args)], cwd=cwd, capture_output=True,
                       text=True, timeout=timeout, preexec_fn=preexec)
    return p.returncode, p.stderr


def check_exit(rc: int, err: str, what: str) -> None:
    if "Traceback" in err or rc not in (0, 1, 2, 130, 143):
        bad("traceback", f"{what}: rc {rc}: {err.strip()[-200:]}")
    lines = [x for x in err.strip().splitlines() if x.strip() and not x.startswith("twofluid: warning:")]
    if rc in (2, 130, 143) and len(lines) > 1:
        bad("multi-line", f"{what}: {lines}")


def check_outputs(folder: Path, what: str) -> None:
    if not folder.is_dir():
        return
    for f in folder.rglob("*"):
        if f.is_symlink() or not f.is_file():
            continue
        if f.suffix in (".csv", ".json", ".toml", ".pvd"):
            text = f.read_text(errors="replace")
            low = text.lower()
            if f.suffix in (".csv", ".json") and ("nan" in low.replace("nano", "") or "inf" in
                                                  low.replace("info", "").replace("inflow", "").replace("infinite", "")):
                if _has_nonfinite(text, f.suffix):
                    bad("silent non-finite", f"{what}: {f.name}")
            if f.suffix == ".csv" and text:
                import csv
                rows = list(csv.reader(text.splitlines()))
                if not text.endswith("\n") or len({len(r) for r in rows}) > 1:
                    bad("lost data", f"{what}: half row in {f.name}")
            if f.suffix == ".json":
                try:
                    json.loads(text)
                except ValueError:
                    bad("lost data", f"{what}: {f.name} is not whole JSON")
        if f.suffix == ".vtu":
            import meshio
            import numpy as np
            m = meshio.read(f)
            if any(not np.isfinite(np.asarray(v[0], float)).all() for v in m.cell_data.values()):
                bad("silent non-finite", f"{what}: {f.name}")


def _has_nonfinite(text: str, suffix: str) -> bool:
    import csv
    import re
    if suffix == ".json":
        return re.search(r"\b(NaN|Infinity|-Infinity)\b", text) is not None
    for row in csv.reader(text.splitlines()):
        for cell in row:
            try:
                v = float(cell)
            except ValueError:
                continue
            if v != v or v in (float("inf"), float("-inf")):
                return True
    return False


# ---------------------------------------------------------------- the cases
def write_case(case: dict, path: Path) -> None:
    import tomli_w

    from twofluid.casefile.schema import effective
    doc: dict = {}
    for where, table in effective(case).items():
        if where.startswith("_"):
            continue
        node = doc
        *parents, last = where.split(".")
        for p in parents:
            node = node.setdefault(p, {})
        node[last] = table
    path.write_text(tomli_w.dumps(doc))


def short_cases():
    from twofluid.casefile.loader import load_case

    fb = load_case("fluidized-bed-step")
    fb["time"]["end"] = 5.0
    fb["output"].update(times=[5.0], plots=False)
    liq = load_case("liquefaction-elcentro")
    liq["time"]["end"] = 0.5
    liq["ground_motion"]["duration"] = 0.4
    liq["output"].update(times=[], plots=False)
    return {"fb": fb, "liq": liq}


VALUES = [float("nan"), float("inf"), -1.0, 0.0, 1e300, 1e-300, 0.45, "x", [], True, 10 ** 30, -0.5]


def mutations(rng: random.Random, cases: dict, n: int):
    import copy
    out = []
    for i in range(n):
        name = rng.choice(sorted(cases))
        case = copy.deepcopy(cases[name])
        tables = [(w, t) for w, t in case.items() if isinstance(t, dict) and not w.startswith("_")
                  and w not in ("case", "output")]
        if name == "liq":
            tables += [("layers.1", case["layers"][0])]
        where, table = rng.choice(tables)
        key = rng.choice(sorted(k for k in table if k != "name"))
        table[key] = rng.choice(VALUES)
        out.append((name, f"[{where}] {key} = {table[key]!r}", case))
    return out


def run_mutations(sandbox: Path, rng, n: int) -> None:
    for i, (name, what, case) in enumerate(mutations(rng, short_cases(), n)):
        TRIALS["case-file mutations"] += 1
        d = sandbox / f"m{i}"
        d.mkdir()
        try:
            write_case(case, d / "c.toml")
        except Exception:  # noqa: BLE001 - TOML cannot hold it (nan in a list is fine; a None is not)
            continue
        (d / "mine.txt").write_text("mine")
        before = snapshot(sandbox, skip=d / "out")
        rc, err = cli(["run", "c.toml", "--out", "out", "--no-plots"], cwd=d)
        check_exit(rc, err, f"mutation {what}")
        after = snapshot(sandbox, skip=d / "out")
        if before != after:
            bad("outside write", f"mutation {what}: {set(before) ^ set(after)}")
        check_outputs(d / "out", f"mutation {what}")


# ---------------------------------------------------------------- the API
def run_api(sandbox: Path) -> None:
    import twofluid
    from twofluid.casefile.schema import CaseError

    (sandbox / "e.toml").write_text('[ensemble]\nname = "e"\nbase = "settling-illite"\ncollect = ["steps"]\n'
                                    '[grid]\n"materials.particle_diameter" = [6e-5, 7e-5]\n')
    fb = short_cases()["fb"]
    calls = [lambda: twofluid.run_ensemble(None), lambda: twofluid.run_ensemble(42),
             lambda: twofluid.run_ensemble({}), lambda: twofluid.run_ensemble(""),
             lambda: twofluid.run_ensemble(str(sandbox / "e.toml"), out_dir=42),
             lambda: twofluid.run_ensemble(str(sandbox / "e.toml"), out_dir="/dev/null"),
             lambda: twofluid.run_ensemble(str(sandbox / "e.toml"), out_dir=""),
             lambda: twofluid.run_ensemble(str(sandbox / "e.toml"), workers=-1),
             lambda: twofluid.run_ensemble(str(sandbox / "e.toml"), workers=0),
             lambda: twofluid.run_case({**fb, "_source": 42}),
             lambda: twofluid.run_case(42), lambda: twofluid.run_case(None), lambda: twofluid.run_case({}),
             lambda: twofluid.run_case(fb, out_dir=42), lambda: twofluid.run_case(fb, out_dir="/dev/null"),
             lambda: twofluid.run_case(fb, out_dir=""), lambda: twofluid.run_case("/dev/zero"),
             lambda: twofluid.load_case("/dev/zero"), lambda: twofluid.load_case(3.5),
             lambda: twofluid.run_case({**fb, "time": {**fb["time"], "end": float("nan")}}),
             lambda: twofluid.run_case({**fb, "materials": "heavy"})]
    from twofluid.geotech import simplified_procedure
    calls += [lambda: simplified_procedure([0.0], [1.0], [2e4], [1e4], [0.45], [True], 0.2, 7.0),
              lambda: simplified_procedure([0.0], [1.0], [2e4], [1e4], [450.0], [True], 0.2, 7.0)]
    for i, call in enumerate(calls):
        TRIALS["API calls"] += 1
        try:
            call()
            bad("non-CaseError", f"API call {i}: accepted")
        except CaseError as exc:
            if "\n" in str(exc):
                bad("multi-line", f"API call {i}: {exc}")
        except Exception as exc:  # noqa: BLE001 - the class counted
            bad("non-CaseError", f"API call {i}: {type(exc).__name__}: {exc}")


# ---------------------------------------------------------------- folders
def run_folders(sandbox: Path) -> None:
    root = sandbox / "folders"
    root.mkdir()
    fb = short_cases()["fb"]
    write_case(fb, root / "fb.toml")

    def trial(what, prepare, args, expect_rc=None):
        TRIALS["folders"] += 1
        d = root / f"t{TRIALS['folders']}"
        d.mkdir()
        shutil.copy(root / "fb.toml", d / "fb.toml")
        (d / "outside.csv").write_text("mine\n")
        prepare(d)
        before = snapshot(d, skip=d / "run")
        user = {str(p.relative_to(d)): p.read_bytes() for p in (d / "run").glob("*")
                if p.is_file() and not p.is_symlink() and not p.name.startswith(".")} if (d / "run").is_dir() else {}
        rc, err = cli(args, cwd=d)
        check_exit(rc, err, what)
        if expect_rc is not None and rc != expect_rc:
            bad("traceback", f"{what}: rc {rc}, expected {expect_rc}: {err.strip()[-200:]}")
        after = snapshot(d, skip=d / "run")
        outside = {k: v for k, v in after.items() if not k.startswith(("twofluid-out",))}
        if {k: v for k, v in before.items() if not k.startswith("twofluid-out")} != outside:
            bad("outside write", f"{what}: {set(before) ^ set(after)}")
        for name, data in user.items():
            p = d / name
            if not p.is_file() or p.read_bytes() != data:
                bad("lost data", f"{what}: {name}")
        check_outputs(d / "run", what)

    def planted_link(d):
        (d / "run").mkdir()
        (d / "run" / ".twofluid-run.json").write_text('{"files":[]}')
        os.symlink("../outside.csv", d / "run" / "profiles.csv")

    def legacy_with_user_file(d):
        (d / "run").mkdir()
        (d / "run" / "case.resolved.toml").write_text("#\n")
        (d / "run" / "my.csv").write_text("mine\n")

    def summary_folder(d):
        subprocess.run([sys.executable, "-m", "twofluid.cli", "run", "fb.toml", "--out", "run"], cwd=d,
                       capture_output=True)
        (d / "run" / "summary.json").unlink()
        (d / "run" / "summary.json").mkdir()

    def user_members(d):
        (d / "run").mkdir()
        (d / "run" / "members.csv").write_text("a,b\n1,2\n")
        (d / "e.toml").write_text('[ensemble]\nname = "../../../escape"\nbase = "settling-illite"\n'
                                  'collect = ["steps"]\n[grid]\n"materials.particle_diameter" = [6e-5, 7e-5]\n')

    def escape(d):
        (d / "e.toml").write_text('[ensemble]\nname = "../../../escape"\nbase = "settling-illite"\n'
                                  'collect = ["steps"]\n[set]\n"time.end" = 0.2\n"output.times" = [0.2]\n'
                                  '[grid]\n"materials.particle_diameter" = [6e-5, 7e-5]\n')

    nothing = lambda d: None  # noqa: E731
    trial("planted link", planted_link, ["run", "fb.toml", "--out", "run"], 2)
    trial("resolved case + my.csv", legacy_with_user_file, ["run", "fb.toml", "--out", "run"], 2)
    trial("summary.json a folder", summary_folder, ["run", "fb.toml", "--out", "run"], 2)
    trial("user's members.csv", user_members, ["ensemble", "e.toml", "--out", "run", "--workers", "1"], 2)
    trial("--out a file", lambda d: (d / "run").write_text("x"), ["run", "fb.toml", "--out", "run"], 2)
    trial("--out ''", nothing, ["run", "fb.toml", "--out", ""], 2)
    trial("run /dev/zero", nothing, ["run", "/dev/zero"], 2)
    trial("ensemble --out a file", lambda d: (escape(d), (d / "run").write_text("x")),
          ["ensemble", "e.toml", "--out", "run"], 2)
    trial("ensemble name ../../../escape", escape, ["ensemble", "e.toml", "--workers", "1", "--quiet"], 0)


# ---------------------------------------------------------------- signals
#: the signals come after the interpreter's own start (about 40 ms here, before any twofluid code
#: runs: there the operating system's default ends the process, which a shell reports as 130/143)
START_S = 0.08

def run_signals(sandbox: Path, rng, n: int) -> None:
    root = sandbox / "signals"
    root.mkdir()
    write_case(short_cases()["fb"], root / "fb.toml")
    for i in range(n):
        sig = rng.choice([signal.SIGINT, signal.SIGTERM])
        delay = rng.uniform(START_S, 0.6)
        out = root / f"o{i}"
        p = subprocess.Popen([sys.executable, "-m", "twofluid.cli", "run", "fb.toml", "--out", out.name],
                             cwd=root, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        time.sleep(delay)
        if p.poll() is not None:
            p.communicate()
            continue  # it ended first: no trial
        TRIALS["signals"] += 1
        p.send_signal(sig)
        _, err = p.communicate()
        what = f"{signal.Signals(sig).name} after {delay:.3f} s"
        want = 143 if sig == signal.SIGTERM else 130
        check_exit(p.returncode, err, what)
        if p.returncode != want:
            bad("traceback", f"{what}: exit {p.returncode}, expected {want}: {err.strip()[-200:]}")
        s = out / "summary.json"
        if s.is_file():
            status = json.loads(s.read_text())["status"]
            if status == "completed" and "as it ended" not in err:
                bad("lost data", f"{what}: summary says completed, exit {p.returncode}")
        check_outputs(out, what)


# ---------------------------------------------------------------- full disk
def run_full_disk(sandbox: Path) -> None:
    root = sandbox / "disk"
    root.mkdir()
    cases = short_cases()
    write_case(cases["fb"], root / "fb.toml")
    write_case(cases["liq"], root / "liq.toml")
    for name, limit in [("fb", 2048), ("fb", 8192), ("fb", 20000), ("liq", 8192), ("liq", 65536)]:
        TRIALS["full disk"] += 1

        def setlimit(n=limit):
            resource.setrlimit(resource.RLIMIT_FSIZE, (n, n))
        out = root / f"{name}-{limit}"
        rc, err = cli(["run", f"{name}.toml", "--out", out.name, "--no-plots"], cwd=root, preexec=setlimit)
        what = f"{name} with files limited to {limit} bytes"
        check_exit(rc, err, what)
        if rc == 1 and not any(x in err for x in (".csv", ".json", ".toml")):
            bad("lost data", f"{what}: the message names no file: {err.strip()[-200:]}")
        for f in (".twofluid-run.json",):
            p = out / f
            if p.exists() and not p.read_text().strip():
                bad("lost data", f"{what}: {f} empty")
        check_outputs(out, what)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--mutations", type=int, default=40)
    ap.add_argument("--signals", type=int, default=16)
    a = ap.parse_args()
    rng = random.Random(a.seed)
    t0 = time.perf_counter()
    sandbox = Path(tempfile.mkdtemp(prefix="twofluid-attack-"))
    try:
        run_api(sandbox)
        run_folders(sandbox)
        run_mutations(sandbox, rng, a.mutations)
        run_signals(sandbox, rng, a.signals)
        run_full_disk(sandbox)
    finally:
        shutil.rmtree(sandbox, ignore_errors=True)
    print(f"trials: {TRIALS} ({sum(TRIALS.values())} in {time.perf_counter() - t0:.0f} s, seed {a.seed})")
    print("failures by class: " + ", ".join(f"{k}: {v}" for k, v in COUNTS.items()))
    for line in LOG:
        print("  " + line)
    return 1 if any(COUNTS.values()) else 0


if __name__ == "__main__":
    sys.exit(main())
