"""The liquefaction column against OpenSees, its reference path, and its scaling with elements.

Whole processes, alternated A B A B (one round = one run of each configuration, in turn),
CPU time = user + system of the process and its children (``resource.getrusage``). The
machine may be shared: only ratios of runs alternated in one benchmark are quoted.

Works:

- ``peer``: ``python column.py --perm 1e-4 --quiet`` of a copy of the OpenSees peer
  (``../shared/peers/opensees``: 10 m, 20 u-p elements, PDMY02, El Centro 0.1 g for 30 s at
  0.005 s, then to 180 s; openseespy from the ``bench`` extra) against ``twofluid run`` of
  the bundled liquefaction-elcentro with 20 elements and 30 s of shaking (no plots), with
  the fast paths (default) and the reference paths (``run_liquefaction(reference=True)``:
  full vertical model, NumPy shear sub-steps).
- ``bundled``: each bundled liquefaction case as shipped (no plots), fast and reference.
- ``scaling``: cost per vertical step and per shear sub-step of the elcentro column with 20,
  80 and 320 elements over its first ``--scaling-time`` seconds (in-process, after a warm-up
  step; fast paths).

    python benchmarks/bench_column.py                     # everything, 3 rounds
    python benchmarks/bench_column.py --only peer --rounds 5
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
import time
import tomllib
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
PEERS = next((d for d in (ROOT.parent / "shared" / "peers", ROOT.parent.parent / "shared" / "peers")
              if d.is_dir()), ROOT.parent / "shared" / "peers")
MOTION = PEERS.parent / "data" / "ground-motions" / "RSN6_IMPVALL.I_I-ELC180-hor1.AT2"
BUNDLED = ("liquefaction-elcentro", "liquefaction-fine", "liquefaction-gravel", "liquefaction-layered-site")
REFERENCE = ("import sys; from twofluid.runners.liquefaction import run_liquefaction; "
             "run_liquefaction(sys.argv[1], sys.argv[2], reference=True)")


def cpu_of(cmd, cwd) -> float:
    """User + system CPU seconds of ``cmd`` run to completion (with its children)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run(cmd, cwd=cwd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def case_file(name: str, path: Path, elements: int | None = None, duration: float | None = None) -> Path:
    """The bundled case ``name`` without plots (and with ``elements`` per layer, ``duration`` of shaking)."""
    import tomli_w

    from twofluid.casefile.loader import case_text

    case = tomllib.loads(case_text(name))
    case.setdefault("output", {})["plots"] = False
    if elements is not None:
        for la in case["layers"]:
            la["elements"] = elements
    if duration is not None:
        case["ground_motion"]["duration"] = duration
    path.write_text(tomli_w.dumps(case))
    return path


def commands(case: Path, out: Path) -> dict:
    return {"twofluid (fast)": [sys.executable, "-m", "twofluid.cli", "run", str(case), "--out", str(out / "f"),
                                "--quiet"],
            "twofluid (reference)": [sys.executable, "-c", REFERENCE, str(case), str(out / "r")]}


def alternate(label: str, cfg: dict, rounds: int, cwd: Path) -> dict:
    cpu = {c: [] for c in cfg}
    for r in range(rounds):
        for c, (cmd, where) in cfg.items():
            cpu[c].append(cpu_of(cmd, where or cwd))
        print(f"{label} round {r + 1}: " + ", ".join(f"{c} {v[-1]:.2f} s" for c, v in cpu.items()),
              file=sys.stderr, flush=True)
    return cpu


def ratio_row(work, base, cpu, other) -> str:
    ratios = [b / o for b, o in zip(cpu[base], cpu[other])]
    return (f"| {work} | {other} | {statistics.median(cpu[other]):.2f} ({min(cpu[other]):.2f}–"
            f"{max(cpu[other]):.2f}) | {base} {statistics.median(cpu[base]):.2f} | "
            f"**{statistics.median(ratios):.2f}×** ({min(ratios):.2f}–{max(ratios):.2f}) | {len(ratios)} |")


def scaling(elements: int, t_end: float, reference: bool = False) -> tuple[float, float, int, int, float]:
    """(ms per vertical step, µs per shear sub-step, steps, sub-steps, Picard its/step) of the
    column (fast or reference paths), in-process: the vertical model and the shear sub-steps
    (with the per-step Python around them) timed separately (process time)."""
    from twofluid.casefile.loader import load_case
    from twofluid.runners.liquefaction import build_column

    with tempfile.TemporaryDirectory() as td:
        case = load_case(str(case_file("liquefaction-elcentro", Path(td) / "c.toml", elements, 30.0)))
    b = build_column(case, reference=True) if reference else build_column(case)
    col = b.column
    shear_t, total_t, steps, subs, its = 0.0, 0.0, 0, 0, 0
    real = col._shear

    def timed(s, t_new):
        nonlocal shear_t
        t0 = time.process_time()
        out = real(s, t_new)
        shear_t += time.process_time() - t0
        return out

    col._shear = timed
    s = b.state
    first = True
    t0 = time.process_time()
    for step in col.run(s, t_end, b.dt):
        if first:  # warm-up: kernel load, caches
            first, shear_t, t0 = False, 0.0, time.process_time()
            continue
        steps += 1
        subs += step.substeps
        its += step.iterations
    total_t = time.process_time() - t0
    return 1e3 * (total_t - shear_t) / steps, 1e6 * shear_t / subs, steps, subs, its / steps


def machine() -> str:
    """The verification report's machine line, with numba's version (or its absence)."""
    from twofluid.verification.suite import machine as base

    try:
        import numba
        nb = f", numba {numba.__version__}"
    except ImportError:
        nb = ", no numba"
    return base() + nb


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--rounds", type=int, default=3)
    p.add_argument("--only", nargs="+", choices=("peer", "bundled", "scaling"))
    p.add_argument("--scaling-time", type=float, default=2.0, help="simulated seconds per scaling run")
    a = p.parse_args(argv)
    only = set(a.only or ("peer", "bundled", "scaling"))
    started = datetime.datetime.now(datetime.timezone.utc)
    load0 = os.getloadavg()[0]
    lines = ["| work | configuration | CPU [s] median (min–max) | against, median CPU [s] | "
             "speed-up: against / configuration, median (min–max) | rounds |", "|---|---|---|---|---|---|"]
    notes = []
    with tempfile.TemporaryDirectory(prefix="twofluid-column-") as td:
        tmp = Path(td)
        if "peer" in only:
            try:
                import openseespy  # noqa: F401
            except ImportError:
                notes.append("- peer: skipped, openseespy not installed (pip install -e '.[bench]')")
            else:
                peer = tmp / "opensees"
                peer.mkdir()
                shutil.copy(PEERS / "opensees" / "column.py", peer / "column.py")
                case = case_file("liquefaction-elcentro", tmp / "column-20.toml", 20, 30.0)
                cfg = {"OpenSees": ([sys.executable, "column.py", "--perm", "1e-4", "--quiet", "--out", "out",
                                     "--motion", str(MOTION)], peer)}
                cfg.update({k: (v, None) for k, v in commands(case, tmp / "peer").items()})
                cpu = alternate("peer", cfg, a.rounds, ROOT)
                for c in ("twofluid (fast)", "twofluid (reference)"):
                    lines.append(ratio_row("OpenSees peer column, 20 elements, 30 s shaking", "OpenSees", cpu, c))
        if "bundled" in only:
            for name in BUNDLED:
                case = case_file(name, tmp / f"{name}.toml")
                cfg = {k: (v, None) for k, v in commands(case, tmp / name).items()}
                cpu = alternate(name, cfg, a.rounds, ROOT)
                lines.append(ratio_row(f"{name} (as shipped)", "twofluid (reference)", cpu, "twofluid (fast)"))
    print(f"{started:%Y-%m-%d %H:%M} UTC; {machine()}; load average (1 min) {load0:.2f} before, "
          f"{os.getloadavg()[0]:.2f} after (shared machine)")
    print("\n".join(lines + notes))
    if "scaling" in only:
        print(f"\nScaling (liquefaction-elcentro, 30 s record, first {a.scaling_time:g} s):\n")
        print("| paths | elements | vertical steps | shear sub-steps | Picard its/step | vertical [ms/step] | "
              "shear [µs/sub-step] | vertical per element [µs] | shear per element [µs] |")
        print("|---|---|---|---|---|---|---|---|---|")
        for ref, ne in [(r, ne) for r in (False, True) for ne in (20, 80, 320)]:
            v, sh, n, m, its = scaling(ne, a.scaling_time, ref)
            print(f"| {'reference' if ref else 'fast'} | {ne} | {n} | {m} | {its:.2f} | {v:.3f} | {sh:.1f} | "
                  f"{1e3 * v / ne:.2f} | {sh / ne:.3f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
