"""twofluid against its peers (OpenFOAM, OpenSees) as whole processes, alternated, CPU time.

Each round runs the peer, then every twofluid configuration of that work, one after
another (A B A B …), each as its own process; the CPU time of a process is its user +
system time including its children (``resource.getrusage(RUSAGE_CHILDREN)`` around
it). The speed ratio of a round is peer CPU / twofluid CPU; the table gives the median
and min–max over the rounds. The machine may be shared: only ratios of runs
alternated in one benchmark are quoted, never absolute times from separate runs.

Works (what is and is not the same work is said in each twofluid case file):

- ``openfoam-fluidized-bed``, ``openfoam-sedimentation``: ``bash run.sh`` of a copy of
  ``../shared/peers/openfoam/<case>`` (twoPhaseEulerFoam, mesh generation included)
  against ``twofluid run benchmarks/peers/openfoam-*.toml`` (no plots) with the full
  and the reduced 1D model, at the case files' step (0.02 s) and at the coarser step
  of ``COARSE_STEP``. Skipped, and said so, if ``twoPhaseEulerFoam`` is not on
  the PATH (Debian: ``apt-get install -y openfoam``).
- ``opensees-column``: ``python column.py --perm 1e-4 --quiet`` of a copy of
  ``../shared/peers/opensees/column.py`` (openseespy from the ``bench`` extra) against
  ``twofluid run`` of the bundled liquefaction-elcentro with 20 elements, 30 s of
  shaking and run to 180 s as the peer (no dissipation stop, no plots). Skipped if openseespy is not installed.

twofluid's bytecode is written before the runs (``compile_bytecode``), as an installed package
has it. Plots are switched off in the twofluid case files (``[output] plots = false``, what
``twofluid run --no-plots`` does), so that ``--src`` can also time older versions.

``--as-installed`` adds the column as a user runs it: this environment's ``twofluid`` console
script (``pip install .``, kernels built), with its default plots and with ``--no-plots``.
``--parts`` times the parts of that process instead (no peer): the CPU of the process when the
column's run starts, of the run, of the total-stress companion run, of the summary and tables and
of the figures (matplotlib's import included), each process the console script's own ``main``
with timers around the runner's calls.

    python benchmarks/bench_peers.py                       # all works, 3 rounds
    python benchmarks/bench_peers.py --only openfoam-sedimentation --rounds 5
    python benchmarks/bench_peers.py --only opensees-column --as-installed --rounds 5
    python benchmarks/bench_peers.py --parts --rounds 7
    python benchmarks/bench_peers.py --only opensees-column --as-installed --no-plots --pin 1 --rounds 5

``--pin CPU`` runs every timed process (peer and twofluid alike) on that one core (``taskset -c``),
so that a shared machine's other jobs move both alike; ``--no-plots`` times only the twofluid
configurations without figures. The peer script's SHA-256 is printed with the table and checked
against ``PEER_SHA256``: a changed peer script is a new baseline, and the table says so.
"""
from __future__ import annotations

import argparse
import datetime
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import tomllib
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
# the peers sit beside the project (../shared/peers), or beside the folder of worktrees
PEERS = Path(os.environ.get("TWOFLUID_PEERS", "")) if os.environ.get("TWOFLUID_PEERS") else next(
    (d for d in (ROOT.parent / "shared" / "peers", ROOT.parent.parent / "shared" / "peers") if d.is_dir()),
    ROOT.parent / "shared" / "peers")
# the largest backward-Euler step whose interface heights stay within half an element of those at
# Δt = 0.005 s (step study in docs/benchmarks.md); the case files' own step is 0.02 s
COARSE_STEP = {"openfoam-fluidized-bed": 0.05, "openfoam-sedimentation": 0.1}
#: SHA-256 of ``../shared/peers/opensees/column.py`` that the quoted ratios to OpenSees were measured
#: with; a peer script with another hash is a new baseline (printed with the table)
PEER_SHA256 = {"opensees-column": "3d8b76440102a896e870110e86eb386e4b90439fdf012542dcb273cbee5e5b40"}
MOTION = PEERS.parent / "data" / "ground-motions" / "RSN6_IMPVALL.I_I-ELC180-hor1.AT2"


def compile_bytecode(src: str | Path | None = None) -> None:
    """Write the bytecode of the twofluid that is timed (``src``, or the installed package), as
    ``pip install`` does at install time and the interpreter at a first import. Where the
    environment sets ``PYTHONDONTWRITEBYTECODE=1`` (as on the benchmark VM) no run writes it, and
    every timed process would compile twofluid's modules from source (~40 ms of CPU)."""
    if src is None:
        import twofluid

        src = Path(twofluid.__file__).parent
    subprocess.run([sys.executable, "-m", "compileall", "-q", str(src)], check=True, stdout=subprocess.DEVNULL)


def cpu_of(cmd: list[str], cwd: Path, env: dict | None = None) -> float:
    """User + system CPU seconds of ``cmd`` run to completion (with all its children)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run(cmd, cwd=cwd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def peer_hash(name: str) -> str:
    """A line with the SHA-256 of the peer script of work ``name`` and whether it is the frozen one
    (``PEER_SHA256``)."""
    import hashlib

    path = PEERS / "opensees" / "column.py"
    digest = hashlib.sha256(path.read_bytes()).hexdigest()
    same = "the frozen baseline" if digest == PEER_SHA256.get(name) else \
        f"NOT the frozen {PEER_SHA256.get(name, '?')[:12]}…: a new baseline, ratios not comparable with earlier ones"
    return f"- {name}: peer script {path.name} SHA-256 {digest[:12]}… ({same})"


def _with_wheel_blas(cmd: list[str]) -> list[str]:
    """``cmd`` with openseespy's bundled BLAS/LAPACK folder on the library path, where the system has
    no ``libblas.so.3`` (openseespy's Linux wheel links it but does not ship it on the path: its import
    fails with "Failed to import openseespy on Linux"); ``cmd`` unchanged otherwise."""
    import ctypes.util
    import importlib.util

    spec = importlib.util.find_spec("openseespylinux")
    if ctypes.util.find_library("blas") or spec is None or spec.origin is None:
        return cmd
    lib = Path(spec.origin).parent / "lib"
    if not (lib / "libblas.so.3").exists():
        return cmd
    path = os.pathsep.join(p for p in (str(lib), os.environ.get("LD_LIBRARY_PATH", "")) if p)
    return ["env", f"LD_LIBRARY_PATH={path}", *cmd]


def _case_file(text: str, path: Path, edits: dict) -> Path:
    """Write the TOML ``text`` with ``edits`` {(section, key): value} applied (sections may be dotted)."""
    import tomli_w

    case = tomllib.loads(text)
    for (section, key), value in edits.items():
        d = case
        for part in section.split("."):
            d = d.setdefault(part, {})
        d[key] = value
    path.write_text(tomli_w.dumps(case))
    return path


def column_case(path: Path, elements: int, shaking: float, end: float, plots: bool = False) -> Path:
    """The bundled liquefaction-elcentro (one layer) with ``elements``, ``shaking`` seconds of the
    record and run to ``end`` [s] whatever the pore pressures (no dissipation stop), no plots
    unless ``plots``, with the hysteretic model (the column's default; the bundled case is a
    thesis case)."""
    import tomli_w
    from twofluid.casefile.loader import case_text

    case = tomllib.loads(case_text("liquefaction-elcentro"))
    if "layers" in case:
        case["layers"][0]["elements"] = elements
    else:  # before layered sites
        case["deposit"]["elements"] = elements
    case["ground_motion"]["duration"] = shaking
    if "shear_wave" in case and "model" in case["shear_wave"]:
        # the column's default, hysteretic model (the bundled case keeps the thesis's model)
        case["shear_wave"]["model"] = "hysteretic"
        case["shear_wave"]["damping_ratio"] = 0.01
    case["time"]["end"] = end
    if "dissipated_r_u" in case.get("reconsolidation", {}):
        case["reconsolidation"]["dissipated_r_u"] = 0.0
    case["output"]["times"] = [t for t in case["output"].get("times", []) if t < end]
    case["output"]["plots"] = plots
    path.write_text(tomli_w.dumps(case))
    return path


def installed_cmd(case_path: Path, out: Path) -> list[str]:
    """``twofluid run`` as a user types it: the console script of this environment (``pip install .``)."""
    return [str(Path(sys.executable).parent / "twofluid"), "run", str(case_path), "--out", str(out), "--quiet"]


def twofluid_cmd(case_path: Path, out: Path) -> list[str]:
    return [sys.executable, "-m", "twofluid.cli", "run", str(case_path), "--out", str(out), "--quiet"]


def works(tmp: Path, coarse: bool = True, as_installed: bool = False) -> dict:
    """{work: (peer description, peer command, peer cwd, {config: twofluid command}) or a reason to skip}."""
    out = {}
    foam = shutil.which("twoPhaseEulerFoam")
    for name, folder in (("openfoam-fluidized-bed", "fluidizedBed"), ("openfoam-sedimentation", "sedimentation")):
        if foam is None:
            out[name] = "skipped: twoPhaseEulerFoam not on the PATH (Debian: apt-get install -y openfoam)"
            continue
        peer_dir = tmp / name / folder
        shutil.copytree(PEERS / "openfoam" / folder, peer_dir)
        text = (HERE / "peers" / f"{name}.toml").read_text()
        cfg = {}
        for dt in (None, COARSE_STEP[name]) if coarse else (None,):
            for model in ("two_fluid_1d", "reduced_1d"):
                edits = {("case", "model"): model, ("output", "plots"): False}  # as --no-plots
                label = f"twofluid {model}"
                if dt:
                    edits[("time", "step")] = dt
                    label += f", Δt = {dt:g} s"
                path = _case_file(text, tmp / name / f"{model}-{dt}.toml", edits)
                cfg[label] = twofluid_cmd(path, tmp / name / f"out-{model}-{dt}")
        out[name] = ("OpenFOAM v1912 twoPhaseEulerFoam (`bash run.sh`)", ["bash", "run.sh"], peer_dir, cfg)
    try:
        import openseespy  # noqa: F401
        has_ops = True
    except ImportError:
        has_ops = False
    name = "opensees-column"
    if not has_ops:
        out[name] = "skipped: openseespy not installed (pip install -e '.[bench]')"
    else:
        peer_dir = tmp / name
        peer_dir.mkdir()
        shutil.copy(PEERS / "opensees" / "column.py", peer_dir / "column.py")
        path = column_case(peer_dir / "column-20.toml", elements=20, shaking=30.0, end=180.0)
        peer = [sys.executable, "column.py", "--perm", "1e-4", "--quiet", "--out", "out", "--motion", str(MOTION)]
        peer = _with_wheel_blas(peer)
        label = "twofluid liquefaction_1d, 20 elements, 30 s shaking, to 180 s"
        cfg = {label: twofluid_cmd(path, peer_dir / "out-tf")}
        if as_installed:  # the console script with the default plots, as a user runs it, and without them
            plotted = column_case(peer_dir / "column-20-plots.toml", elements=20, shaking=30.0, end=180.0,
                                  plots=True)
            cfg[label + ", as installed (`twofluid run`, default plots)"] = installed_cmd(plotted,
                                                                                       peer_dir / "out-inst")
            cfg[label + ", as installed, `--no-plots`"] = installed_cmd(plotted, peer_dir / "out-inst-np") \
                + ["--no-plots"]
        out[name] = ("OpenSeesPy PDMY02 u-p column (`column.py --perm 1e-4`)", peer, peer_dir, cfg)
    return out


PARTS = ("process start and imports", "the case, the record, the column's build", "the column's run",
         "the total-stress companion run", "the summary, spectra and tables",
         "the figures (matplotlib's import included)")


def parts_child(case_path: str, out: str) -> dict:
    """In this process, ``twofluid run CASE --out OUT --quiet`` as the console script runs it (its
    ``main``, the command's process), with the CPU time (``time.process_time``) read around the
    runner's calls; returns {part: CPU [s]} (``PARTS``) and the whole."""
    import time

    clock = time.process_time
    from twofluid import cli

    cli.one_blas_thread()
    from twofluid.plots import command_process

    command_process()
    import twofluid.runners.liquefaction as rl
    from twofluid.models import liquefaction_1d

    marks = {}
    run, companion, tables = liquefaction_1d.LiquefactionColumn.run, rl.total_stress_surface, rl.report.write_tables

    def timed_run(self, *a, **kw):
        marks.setdefault("run", clock())
        yield from run(self, *a, **kw)

    def timed_companion(*a, **kw):
        marks["companion"] = clock()
        out = companion(*a, **kw)
        marks["summary"] = clock()
        return out

    def timed_tables(*a, **kw):
        out = tables(*a, **kw)
        marks["figures"] = clock()
        return out

    marks["build"] = clock()  # (the imports: what the command imports before it reads the case)
    liquefaction_1d.LiquefactionColumn.run = timed_run
    rl.total_stress_surface, rl.report.write_tables = timed_companion, timed_tables
    assert cli._main(["run", case_path, "--out", out, "--quiet"]) == 0
    end = clock()
    order = ["build", "run", "companion", "summary", "figures"]
    values = [marks["build"]] + [marks[b] - marks[a] for a, b in zip(order, order[1:])] + [end - marks["figures"]]
    return {**dict(zip(PARTS, values)), "whole": end}


def parts(rounds: int) -> int:
    """The median CPU of each part of the peer column as installed (``parts_child``), ``rounds``
    processes."""
    import json

    from twofluid.verification.suite import machine

    compile_bytecode()
    load0 = os.getloadavg()[0]
    started = datetime.datetime.now(datetime.timezone.utc)
    runs = []
    with tempfile.TemporaryDirectory(prefix="twofluid-parts-") as td:
        case = column_case(Path(td) / "column-20-plots.toml", elements=20, shaking=30.0, end=180.0, plots=True)
        for r in range(rounds):
            out = subprocess.run([sys.executable, __file__, "--parts-child", str(case), str(Path(td) / f"out{r}")],
                                 check=True, capture_output=True, text=True).stdout
            runs.append(json.loads(out.strip().splitlines()[-1]))
    print(f"{started:%Y-%m-%d %H:%M} UTC; {machine()}; load average (1 min) {load0:.2f} before, "
          f"{os.getloadavg()[0]:.2f} after; {rounds} processes, medians")
    print("\n| part | CPU [s] (median, min–max) |\n|---|---|")
    for key in (*PARTS, "whole"):
        v = sorted(r[key] for r in runs)
        print(f"| {key} | {statistics.median(v):.3f} ({v[0]:.3f}–{v[-1]:.3f}) |")
    return 0


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--rounds", type=int, default=3, help="alternated rounds per work (default 3)")
    p.add_argument("--only", nargs="+", help="run only these works")
    p.add_argument("--src", help="run twofluid from this source folder (e.g. an export of an older "
                   "commit, for a before/after table) instead of the installed package; only the case "
                   "files' own step then")
    p.add_argument("--as-installed", action="store_true", help="also time the column as a user runs it: "
                   "this environment's `twofluid` console script with the default plots (install with "
                   "`pip install .` and run `twofluid build-kernels` first)")
    p.add_argument("--parts", action="store_true", help="the CPU of the parts of the column's process as installed "
                   "(no peer; --rounds processes)")
    p.add_argument("--no-plots", action="store_true", help="with --as-installed, time only the "
                   "configurations without figures")
    p.add_argument("--pin", type=int, metavar="CPU", help="run every timed process on this one core "
                   "(taskset -c CPU): peer and twofluid alike")
    p.add_argument("--parts-child", nargs=2, metavar=("CASE", "OUT"), help=argparse.SUPPRESS)
    a = p.parse_args(argv)
    if a.pin is not None and (not shutil.which("taskset") or a.pin not in os.sched_getaffinity(0)):
        p.error(f"--pin {a.pin}: not a core this process may run on "
                f"({sorted(os.sched_getaffinity(0))}), or no taskset on the PATH")
    if a.parts_child:
        import json

        print(json.dumps(parts_child(*a.parts_child)))
        return 0
    if a.parts:
        return parts(a.rounds)
    env = None
    if a.src:
        env = dict(os.environ, PYTHONPATH=str(Path(a.src).resolve()))
    from twofluid.verification.suite import machine

    compile_bytecode(a.src)
    load0 = os.getloadavg()[0]
    started = datetime.datetime.now(datetime.timezone.utc)
    lines = ["| work | peer | twofluid | peer CPU [s] (median) | twofluid CPU [s] (median) "
             "| speed-up: peer / twofluid, median (min–max) | rounds |", "|---|---|---|---|---|---|---|"]
    notes = []
    with tempfile.TemporaryDirectory(prefix="twofluid-peers-") as td:
        for name, w in works(Path(td), coarse=not a.src, as_installed=a.as_installed).items():
            if a.only and name not in a.only:
                continue
            if isinstance(w, str):
                notes.append(f"- {name}: {w}")
                print(f"{name}: {w}", file=sys.stderr)
                continue
            desc, peer_cmd, peer_cwd, cfg = w
            if a.no_plots:
                cfg = {c: cmd for c, cmd in cfg.items() if "default plots" not in c}
            if a.pin is not None:
                pin = ["taskset", "-c", str(a.pin)]
                peer_cmd, cfg = pin + peer_cmd, {c: pin + cmd for c, cmd in cfg.items()}
            if name in PEER_SHA256:
                notes.append(peer_hash(name))
            peer_cpu, tf_cpu = [], {c: [] for c in cfg}
            for r in range(a.rounds):
                peer_cpu.append(cpu_of(peer_cmd, peer_cwd))
                for c, cmd in cfg.items():
                    tf_cpu[c].append(cpu_of(cmd, ROOT, env))
                print(f"{name} round {r + 1}: peer {peer_cpu[-1]:.2f} s, "
                      + ", ".join(f"{c} {v[-1]:.2f} s" for c, v in tf_cpu.items()), file=sys.stderr)
            for c, v in tf_cpu.items():
                ratios = [pc / tc for pc, tc in zip(peer_cpu, v)]
                lines.append(f"| {name} | {desc} | {c} | {statistics.median(peer_cpu):.2f} | "
                             f"{statistics.median(v):.2f} | **{statistics.median(ratios):.2f}×** "
                             f"({min(ratios):.2f}–{max(ratios):.2f}) | {len(ratios)} |")
    load1 = os.getloadavg()[0]
    src = f"; twofluid from {a.src}" if a.src else ""
    src += f"; every process pinned to core {a.pin}" if a.pin is not None else ""
    print(f"{started:%Y-%m-%d %H:%M} UTC{src}; {machine()}; load average (1 min) {load0:.2f} before, "
          f"{load1:.2f} after (the machine is shared)")
    print("\n".join(lines + notes))
    return 0


if __name__ == "__main__":
    sys.exit(main())
