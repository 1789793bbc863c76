"""The hysteretic sub-steps' kernel alone, on recorded calls: a stable timing of the kernel and a
bit-for-bit check of everything it writes, for work on ``models/hysteretic_kernel.py`` and the law.

``capture`` runs a case (``twofluid run CASE --no-plots``, in this process) and records the
arguments of every call of the kernel, those of the total-stress companion (one call over the
whole wave) and those of the effective-stress run (one call per vertical step), into two pickles.
``replay`` calls the compiled kernel (the source tree's, or an installed one: run it with that
environment's Python) on copies of them, in this process, ``--reps`` times, and prints per file the
CPU of one replay (fastest and median) and a SHA-256 of every array the calls leave (the state,
n̄, the surface and stress series) and of their return codes: the same digest before and after a
change of the kernel is the same output, bit for bit.

    python benchmarks/bench_hysteretic_replay.py capture liquefaction-layered-site /tmp/replay
    python benchmarks/bench_hysteretic_replay.py replay /tmp/replay/*.pkl --reps 7

Instructions rather than seconds on a shared machine: ``valgrind --tool=callgrind
--toggle-collect='*hysteretic_kernel*_substeps*' python benchmarks/bench_hysteretic_replay.py replay
FILE --reps 1`` counts those of the kernel alone.
"""
from __future__ import annotations

import argparse
import hashlib
import pickle
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np


def _copy(args):
    return tuple(x.copy() if isinstance(x, np.ndarray) else x for x in args)


def capture(case: str, folder: Path) -> None:
    """Record the kernel's calls of ``twofluid run CASE`` into ``folder``/CASE-companion.pkl and
    CASE-run.pkl."""
    from twofluid import cli
    from twofluid.models import hysteretic_kernel as hk
    from twofluid.runners import liquefaction as rl

    runner = hk.runner
    real = runner()
    calls = {"companion": [], "run": []}

    def recorder(kind):
        def kernel(*args):
            calls[kind].append(_copy(args))
            return real(*args)
        return kernel

    companion = rl.total_stress_surface
    hk.runner = lambda: recorder("run")
    rl.total_stress_surface = lambda c, *a, **kw: companion(c, *a, **{**kw, "kernel": recorder("companion")})
    try:
        with tempfile.TemporaryDirectory() as td:
            cli.main(["run", case, "--out", str(Path(td) / "out"), "--quiet", "--no-plots"])
    except SystemExit:
        pass
    finally:
        hk.runner, rl.total_stress_surface = runner, companion
    folder.mkdir(parents=True, exist_ok=True)
    name = Path(case).stem if case.endswith(".toml") else case
    for kind, recorded in calls.items():
        if recorded:
            path = folder / f"{name}-{kind}.pkl"
            with open(path, "wb") as fh:
                pickle.dump(recorded, fh)
            print(f"{path}: {len(recorded)} calls, {sum(a[22].size for a in recorded)} sub-steps")


def replay(path: Path, reps: int) -> tuple[float, float, str]:
    """(fastest, median CPU [s] of one replay of the calls in ``path``, SHA-256 of their outputs)."""
    from twofluid.models import hysteretic_kernel as hk

    with open(path, "rb") as fh:
        recorded = pickle.load(fh)
    kernel = hk.runner()
    times, digest = [], ""
    for _ in range(reps):
        calls = [_copy(a) for a in recorded]
        t0 = time.process_time()
        codes = [int(kernel(*a)) for a in calls]
        times.append(time.process_time() - t0)
        h = hashlib.sha256(str(codes).encode())
        for a in calls:
            for x in a:
                if isinstance(x, np.ndarray):
                    h.update(x.tobytes())
        digest = h.hexdigest()
    return min(times), statistics.median(times), digest


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = p.add_subparsers(dest="command", required=True)
    c = sub.add_parser("capture", help="record a case's kernel calls")
    c.add_argument("case")
    c.add_argument("folder", type=Path)
    r = sub.add_parser("replay", help="time recorded calls and digest their outputs")
    r.add_argument("files", nargs="+", type=Path)
    r.add_argument("--reps", type=int, default=5)
    a = p.parse_args(argv)
    if a.command == "capture":
        capture(a.case, a.folder)
        return 0
    for path in a.files:
        fastest, median, digest = replay(path, a.reps)
        print(f"{path.name}: fastest {fastest * 1e3:.1f} ms, median {median * 1e3:.1f} ms ({a.reps} replays); "
              f"outputs sha256 {digest[:16]}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
