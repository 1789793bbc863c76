"""The Python per vertical step of the liquefaction column's run: the CPU of the run's loop that is not
inside a compiled call, in process.

    python benchmarks/bench_step_python.py [CASE] [--rounds N] [--cprofile]

CASE defaults to the peer column of ``benchmarks/bench_peers.py`` (liquefaction-elcentro with the
hysteretic model, 20 elements, 30 s of El Centro at 0.1 g, run to 180 s: 1831 vertical steps, every
one a probe row). What is counted:

- *the run's loop*: the CPU (``time.process_time``) from the first step of
  ``LiquefactionColumn.run`` to the start of the total-stress companion run (as ``bench_peers.py
  --parts`` times "the column's run"): the column's steps and the runner's loop around them;
- *compiled*: the CPU inside the calls of the compiled kernels (the hysteretic sub-steps, the
  vertical step, the record), timed around each call;
- *output rows*: the CPU of formatting and writing the CSV rows and profiles (the probe row and its
  values, the r_u field row, the profiles, the blocks' writes), timed around those calls;
- *Python per step*: the loop less the two (the timers' own cost, about 0.5 µs a call, included).

Each round is a process of its own (the kernels built and loaded first, as a run's ``prepare`` does);
prints each round and the medians. ``--cprofile`` prints cProfile's table of the loop of one more
process instead (its own overhead makes every Python call about twice as dear).
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent


def child(case_path: str, cprofile: bool) -> dict:
    import time

    clock = time.process_time
    from twofluid import cli, compiled
    from twofluid.casefile.loader import load_case
    from twofluid.io import results
    from twofluid.models import column_step_kernel, hysteretic_kernel, liquefaction_1d, record_kernel
    import twofluid.runners.liquefaction as rl

    cli.one_blas_thread()
    active, kernel, rows, depth = [False], [0.0], [0.0], [0]

    def timed(f, into):
        def call(*a, **kw):
            if not active[0] or depth[0]:
                return f(*a, **kw)
            depth[0] += 1
            t0 = clock()
            try:
                return f(*a, **kw)
            finally:
                into[0] += clock() - t0
                depth[0] -= 1
        return call

    case = load_case(case_path)
    compiled.prepare(compiled.groups_for(case))
    runner = hysteretic_kernel.runner
    hysteretic_kernel.runner = lambda: timed(runner(), kernel)
    column_step_kernel.compiled()
    column_step_kernel._COMPILED = timed(column_step_kernel._COMPILED, kernel)
    record = record_kernel.compiled
    record_kernel.compiled = lambda: timed(record(), kernel)
    for owner, name in ((results.ResultWriter, "probe_row"), (rl._Recorder, "probe_row"), (results.CsvStream, "table"),
                        (rl, "check_finite"), (results.ResultWriter, "profile"), (results.CsvStream, "flush"),
                        (rl, "_profile")):
        setattr(owner, name, timed(getattr(owner, name), rows))
    marks, prof = {}, None
    if cprofile:
        import cProfile

        prof = cProfile.Profile()
    run, companion = liquefaction_1d.LiquefactionColumn.run, rl.total_stress_surface

    def timed_run(self, *a, **kw):
        marks["run"] = clock()
        active[0] = True
        if prof:
            prof.enable()
        yield from run(self, *a, **kw)

    def timed_companion(*a, **kw):
        if prof:
            prof.disable()
        active[0] = False
        marks["end"] = clock()
        return companion(*a, **kw)

    liquefaction_1d.LiquefactionColumn.run, rl.total_stress_surface = timed_run, timed_companion
    with tempfile.TemporaryDirectory() as td:
        rl.run_validated(case, td)
    loop = marks["end"] - marks["run"]
    if prof:
        import pstats

        pstats.Stats(prof).sort_stats("tottime").print_stats(30)
    return {"loop": loop, "compiled": kernel[0], "output rows": rows[0], "python per step": loop - kernel[0] - rows[0]}


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("case", nargs="?", help="a liquefaction_1d case (default: the peer column of bench_peers.py)")
    p.add_argument("--rounds", type=int, default=3)
    p.add_argument("--cprofile", action="store_true")
    p.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    a = p.parse_args(argv)
    if a.child:
        print(json.dumps(child(a.case, a.cprofile)))
        return 0
    with tempfile.TemporaryDirectory(prefix="twofluid-step-python-") as td:
        case = a.case
        if case is None:
            sys.path.insert(0, str(HERE))
            from bench_peers import column_case

            case = str(column_case(Path(td) / "column-20.toml", elements=20, shaking=30.0, end=180.0))
        cmd = [sys.executable, __file__, case, "--child"] + (["--cprofile"] if a.cprofile else [])
        runs = []
        load0 = os.getloadavg()[0]
        for _ in range(1 if a.cprofile else a.rounds):
            out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
            if a.cprofile:
                print(out)
            runs.append(json.loads(out.strip().splitlines()[-1]))
    print(f"load average {load0:.2f} before, {os.getloadavg()[0]:.2f} after; CPU [s] per run's loop")
    for key in runs[0]:
        v = sorted(r[key] for r in runs)
        print(f"{key:16s} {statistics.median(v):.4f} ({v[0]:.4f}-{v[-1]:.4f})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
