"""Start-up and plotting cost of ``twofluid run`` for the bundled 1D cases.

Each case runs as ``python -m twofluid.cli run CASE --quiet`` in its own process
(``--child``), in which the CPU time of the process (``time.process_time``: the
interpreter's start-up, the imports, loading and building the case, the initial
pressure) is read when the stepper starts its first step, and the CPU time of
making the plots is measured around the runner's plot call. Reported per case:
CPU before the first step, CPU of the whole run, plots' share of it.

    python benchmarks/bench_startup.py                  # the bundled 1D cases, full length
    python benchmarks/bench_startup.py --end 5          # each run cut to 5 s simulated
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time

CASES = ("fluidized-bed-step", "settling-illite", "slis-step-change")


def child(case: str, out: str, end: float) -> dict:
    """Run ``twofluid run`` (the CLI's main) in this process with the two timers; return them."""
    from pathlib import Path

    from twofluid import cli
    from twofluid.runners import column_1d

    marks = {}
    real_integrate, real_plots = column_1d.integrate, column_1d._plots

    def integrate_marked(*a, **kw):
        marks.setdefault("before_first_step_s", time.process_time())
        yield from real_integrate(*a, **kw)

    def plots(*a, **kw):
        t0 = time.process_time()
        real_plots(*a, **kw)
        marks["plots_s"] = time.process_time() - t0

    column_1d.integrate, column_1d._plots = integrate_marked, plots
    if end:  # a shortened copy of the case file
        from twofluid.casefile.loader import load_case
        from twofluid.io.results import write_resolved_case

        c = load_case(case)
        c["time"]["end"] = end
        c["output"]["times"] = [t for t in c["output"]["times"] if t < end]
        case = str(Path(out) / "short.toml")
        write_resolved_case(Path(case), c)
    assert cli.main(["run", case, "--out", str(Path(out) / "run"), "--quiet"]) == 0
    marks["run_s"] = time.process_time()
    marks["steps"] = json.loads((Path(out) / "run" / "summary.json").read_text())["steps"]
    return marks


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--child", nargs=3, metavar=("CASE", "OUT", "END"))
    p.add_argument("--end", type=float, default=0.0, help="cut every run to this simulated time [s]")
    p.add_argument("--repeat", type=int, default=3, help="processes per case (median reported)")
    a = p.parse_args(argv)
    if a.child:
        print(json.dumps(child(a.child[0], a.child[1], float(a.child[2]))))
        return 0
    print("| case | steps | CPU before the first step [s] (median, min–max) | CPU of the run [s] | plots [s] "
          "| plots' share |")
    print("|---|---|---|---|---|---|")
    for case in CASES:
        runs = []
        for _ in range(a.repeat):
            with tempfile.TemporaryDirectory() as td:
                out = subprocess.run([sys.executable, __file__, "--child", case, td, str(a.end)],
                                     capture_output=True, text=True, check=True)
            runs.append(json.loads(out.stdout.strip().splitlines()[-1]))
        runs.sort(key=lambda r: r["before_first_step_s"])
        mid = runs[len(runs) // 2]
        first = [r["before_first_step_s"] for r in runs]
        share = sorted(r["plots_s"] / r["run_s"] for r in runs)
        print(f"| {case} | {mid['steps']} | {mid['before_first_step_s']:.3f} ({min(first):.3f}–{max(first):.3f}) | "
              f"{mid['run_s']:.2f} | {mid['plots_s']:.2f} | {100 * share[len(share) // 2]:.1f} % "
              f"({100 * share[0]:.1f}–{100 * share[-1]:.1f} %) |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
