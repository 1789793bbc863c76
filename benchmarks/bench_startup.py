"""Start-up and plotting cost of ``twofluid run`` for the bundled 1D and liquefaction cases.

Each case runs as ``twofluid run CASE --quiet`` (the CLI's ``main``) in its own process
(``--child``), marked as the command's process as ``twofluid`` marks its own (one BLAS thread,
matplotlib imported lean: ``twofluid.plots.command_process``), in which the CPU time of the process (``time.process_time``: the
interpreter's start-up, the imports, loading and building the case, the initial
state) is read when the stepper starts its first step, and the CPU time of making the
plots (importing matplotlib and the plotting module, drawing, writing the PNGs) is
measured around the runner's plot call. Reported per case: CPU before the first step,
CPU of the whole run, the plots' CPU and share of it, the wall time of the process.

``--worker`` makes the plots of the 1D cases in a second process instead, forked when
the run starts so that it imports matplotlib while the run steps, and handed the
runner's data when the run ends (a prototype measured here, not a mode of
``twofluid``): the plots' CPU is then the worker's, counted in the run's CPU, and
the wall time shows what the overlap gains.

``--floor`` times the imports alone in fresh processes with NumPy already imported:
the least matplotlib a figure needs (``matplotlib.figure`` and the Agg canvas), the
plotting modules of twofluid, and ``matplotlib.pyplot`` for comparison.

    python benchmarks/bench_startup.py                  # every case, full length, 3 processes each
    python benchmarks/bench_startup.py --end 5          # the 1D runs cut to 5 s simulated
    python benchmarks/bench_startup.py --worker --cases fluidized-bed-step
    python benchmarks/bench_startup.py --floor --repeat 7
    python benchmarks/bench_startup.py --compare /tmp/old/src --repeat 5   # alternated with another tree
"""
from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time

CASES_1D = ("fluidized-bed-step", "settling-illite", "slis-step-change")
CASES_LIQ = ("liquefaction-fine", "liquefaction-gravel", "liquefaction-layered-site", "liquefaction-elcentro")

#: what --floor imports, each in a fresh process after ``import numpy``
FLOOR = {"matplotlib.figure + Agg canvas (the least a figure needs)":
         "import matplotlib.figure, matplotlib.backends.backend_agg",
         "twofluid.plots.profiles (1D figures)": "import twofluid.plots.profiles",
         "twofluid.plots.liquefaction": "import twofluid.plots.liquefaction",
         "matplotlib.pyplot (for comparison)": "import matplotlib; matplotlib.use('agg'); import matplotlib.pyplot"}


def _worker(conn):
    """The plot process of ``--worker``: import while the run steps, then plot what arrives."""
    t0 = time.process_time()
    from twofluid.runners import column_1d

    import twofluid.plots.profiles  # noqa: F401  (matplotlib, before the data arrive)

    conn.send(time.process_time() - t0)
    args = conn.recv()
    column_1d._plots(*args)
    conn.send(time.process_time())
    conn.close()


def _shortened(case: str, out, end: float) -> str:
    """A copy of ``case`` ending at ``end`` [s] simulated (its output times before it kept)."""
    from pathlib import Path

    from twofluid.casefile.loader import load_case
    from twofluid.io.results import write_resolved_case

    c = load_case(case)
    c["time"]["end"] = end
    c["output"]["times"] = [t for t in c["output"]["times"] if t < end]
    path = Path(out) / "short.toml"
    write_resolved_case(path, c)
    return str(path)


def child(case: str, out: str, end: float, worker: bool) -> dict:
    """Run ``twofluid run`` (the CLI's main) in this process with the timers; return them."""
    from pathlib import Path

    from twofluid import cli

    cli.one_blas_thread()  # as ``twofluid run`` does first, before NumPy is imported
    from twofluid import plots as _plots_pkg

    if hasattr(_plots_pkg, "command_process"):  # as ``twofluid run`` marks its process (matplotlib lean)
        _plots_pkg.command_process()
    from twofluid.runners import column_1d

    marks = {}
    real_integrate, real_plots = column_1d.integrate, column_1d._plots

    def integrate_marked(*a, **kw):
        marks.setdefault("before_first_step_s", time.process_time())
        yield from real_integrate(*a, **kw)

    def run_marked(self, *a, **kw):
        marks.setdefault("before_first_step_s", time.process_time())
        yield from real_run(self, *a, **kw)

    def plots(*a, **kw):
        t0 = time.process_time()
        real_plots(*a, **kw)
        marks["plots_s"] = time.process_time() - t0

    class LiquefactionPlots:
        """Stands for twofluid.plots.liquefaction until the runner imports it: times import and plots."""

        @staticmethod
        def liquefaction_plots(*a, **kw):
            t0 = time.process_time()
            del sys.modules["twofluid.plots.liquefaction"]
            from twofluid.plots.liquefaction import liquefaction_plots

            paths = liquefaction_plots(*a, **kw)
            marks["plots_s"] = time.process_time() - t0
            return paths

    column_1d.integrate = integrate_marked
    if case not in CASES_1D:  # (the liquefaction model is not imported by a 1D run)
        from twofluid.models import liquefaction_1d

        real_run = liquefaction_1d.LiquefactionColumn.run
        liquefaction_1d.LiquefactionColumn.run = run_marked
        sys.modules["twofluid.plots.liquefaction"] = LiquefactionPlots
    pool = None
    if worker:
        import multiprocessing as mp

        ctx = mp.get_context("fork")
        conn, theirs = ctx.Pipe()
        pool = ctx.Process(target=_worker, args=(theirs,))
        pool.start()

        def plots(*a, **kw):  # noqa: F811  (the worker's)
            t0 = time.process_time()
            marks["worker_import_s"] = conn.recv()
            conn.send(a)
            marks["worker_cpu_s"] = conn.recv()
            marks["plots_here_s"] = time.process_time() - t0

    column_1d._plots = plots
    if end and case in CASES_1D:
        case = _shortened(case, out, end)
    assert cli.main(["run", case, "--out", str(Path(out) / "run"), "--quiet"]) == 0
    if pool is not None:
        pool.join()
        marks["plots_s"] = marks["worker_cpu_s"] + marks["plots_here_s"]
    marks["run_s"] = time.process_time() + marks.get("worker_cpu_s", 0.0)
    marks["steps"] = json.loads((Path(out) / "run" / "summary.json").read_text())["steps"]
    return marks


def floor(code: str) -> float:
    """CPU [s] of ``code`` in this process, NumPy already imported."""
    import numpy  # noqa: F401

    t0 = time.process_time()
    exec(code)
    return time.process_time() - t0


def _run(args: list[str], src: str | None = None) -> tuple[dict, float]:
    """Run this script as a child (``src``: a source tree whose twofluid it imports instead)."""
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([src, os.environ.get("PYTHONPATH", "")])} if src else None
    t0 = time.perf_counter()
    out = subprocess.run([sys.executable, __file__, *args], capture_output=True, text=True, check=True, env=env)
    return json.loads(out.stdout.strip().splitlines()[-1]), time.perf_counter() - t0


def machine() -> str:
    cpu = next((line.split(":", 1)[1].strip() for line in open("/proc/cpuinfo") if line.startswith("model name")),
               platform.processor()) if os.path.exists("/proc/cpuinfo") else platform.processor()
    import matplotlib
    import numpy

    return (f"{cpu}, {os.cpu_count()} logical CPUs, {platform.system()} {platform.release()}; Python "
            f"{platform.python_version()}, NumPy {numpy.__version__}, matplotlib {matplotlib.__version__}")


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--child", nargs=4, metavar=("CASE", "OUT", "END", "WORKER"), help=argparse.SUPPRESS)
    p.add_argument("--floor-child", metavar="CODE", help=argparse.SUPPRESS)
    p.add_argument("--cases", default=",".join(CASES_1D + CASES_LIQ), help="comma-separated bundled cases")
    p.add_argument("--end", type=float, default=0.0, help="cut every 1D run to this simulated time [s]")
    p.add_argument("--repeat", type=int, default=3, help="processes per case (median reported)")
    p.add_argument("--worker", action="store_true", help="1D plots in a process forked at the start of the run")
    p.add_argument("--floor", action="store_true", help="time the imports of matplotlib alone")
    p.add_argument("--compare", metavar="SRC", help="alternate every process with one that imports twofluid "
                   "from the source tree SRC (e.g. an export of another commit's src/)")
    a = p.parse_args(argv)
    if a.child:
        print(json.dumps(child(a.child[0], a.child[1], float(a.child[2]), a.child[3] == "1")))
        return 0
    if a.floor_child:
        print(json.dumps(floor(a.floor_child)))
        return 0
    load0 = os.getloadavg()[0]
    print(f"{time.strftime('%Y-%m-%d %H:%M %Z')}; {machine()}; load average (1 min) {load0:.2f} before")
    if a.floor:
        print("\n| import (NumPy already imported) | CPU [s] (median, min–max) |\n|---|---|")
        for label, code in FLOOR.items():
            t = sorted(_run(["--floor-child", code])[0] for _ in range(a.repeat))
            print(f"| {label} | {statistics.median(t):.3f} ({t[0]:.3f}–{t[-1]:.3f}) |", flush=True)
        print(f"\nload average (1 min) {os.getloadavg()[0]:.2f} after")
        return 0
    trees = {"this tree": None, **({a.compare: a.compare} if a.compare else {})}
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from bench_peers import compile_bytecode

    for src in trees.values():  # as an installed package has it (bench_peers.compile_bytecode)
        compile_bytecode(src)
    print(f"\n| case | code | steps | CPU before the first step [s] (median, min–max) | CPU of the run [s] "
          "| plots [s] | plots' share | wall [s] |")
    print("|---|---|---|---|---|---|---|---|")
    for case in a.cases.split(","):
        if a.worker and case not in CASES_1D:
            continue
        runs = {t: [] for t in trees}
        for _ in range(a.repeat):
            for label, src in trees.items():  # alternated: A B A B
                with tempfile.TemporaryDirectory() as td:
                    r, wall = _run(["--child", case, td, str(a.end), "1" if a.worker else "0"], src)
                runs[label].append({**r, "wall_s": wall})
        for label, rs in runs.items():
            first = sorted(r["before_first_step_s"] for r in rs)
            share = sorted(r["plots_s"] / r["run_s"] for r in rs)
            med = lambda k: statistics.median(r[k] for r in rs)  # noqa: E731
            print(f"| {case} | {label} | {rs[0]['steps']} | {med('before_first_step_s'):.3f} "
                  f"({first[0]:.3f}–{first[-1]:.3f}) | {med('run_s'):.2f} | {med('plots_s'):.2f} | "
                  f"{100 * statistics.median(share):.1f} % ({100 * share[0]:.1f}–{100 * share[-1]:.1f} %) | "
                  f"{med('wall_s'):.2f} |", flush=True)
    print(f"\nload average (1 min) {os.getloadavg()[0]:.2f} after")
    return 0


if __name__ == "__main__":
    sys.exit(main())
