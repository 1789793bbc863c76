"""Cost per time step against the number of elements: full and reduced 1D models, liquefaction column.

1D models: settling-illite refined to 100 … 10 000 elements, ``--steps`` steps of
the case's Δt after ``--warmup`` steps (in this process, no output files); CPU time
(``time.process_time``) per step and per Picard iterate. Column: the bundled
liquefaction-elcentro with 20, 80 and 320 elements and 2 s of shaking, as whole
``twofluid run --no-plots`` processes (CPU of the whole process, start-up included).

    python benchmarks/bench_scaling.py               # both tables
    python benchmarks/bench_scaling.py --no-column
"""
from __future__ import annotations

import argparse
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ELEMENTS = (100, 300, 1000, 3000, 10000)
COLUMN = (20, 80, 320)


def bed_row(model: str, elements: int, steps: int, warmup: int) -> dict:
    from twofluid.casefile.builder import build
    from twofluid.casefile.loader import load_case
    from twofluid.timestepping.backward_euler import integrate

    case = load_case("settling-illite")
    case["case"]["model"], case["mesh"]["elements"] = model, elements
    case["time"]["end"] = (steps + warmup) * case["time"]["step"]
    b = build(case)
    its = n = 0
    t0 = None
    for st in integrate(b.model, b.state, b.t_end, b.dt, settings=b.settings):
        if st.n_steps == warmup:
            t0 = time.process_time()
        elif st.n_steps > warmup:
            its, n = its + st.iterations, n + 1
    cpu = time.process_time() - t0
    return {"model": model, "elements": elements, "steps": n, "its": its / n, "per_step_ms": 1e3 * cpu / n,
            "per_iterate_ms": 1e3 * cpu / its}


def column_row(elements: int, seconds: float) -> dict:
    from bench_peers import column_case

    with tempfile.TemporaryDirectory() as td:
        path = column_case(Path(td) / "column.toml", elements=elements, shaking=seconds, end=seconds)
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        subprocess.run([sys.executable, "-m", "twofluid.cli", "run", str(path), "--out", str(Path(td) / "out"),
                        "--quiet"], check=True, stdout=subprocess.DEVNULL)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime
    return {"elements": elements, "cpu": cpu}


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--steps", type=int, default=30)
    p.add_argument("--warmup", type=int, default=5)
    p.add_argument("--no-column", action="store_true")
    p.add_argument("--elements", type=int, nargs="+", default=list(ELEMENTS), help="mesh sizes of the 1D models")
    p.add_argument("--models", nargs="+", default=["two_fluid_1d", "reduced_1d"])
    p.add_argument("--shaking", type=float, default=2.0, help="seconds of shaking of the column runs")
    a = p.parse_args(argv)
    print("| model | elements | Picard its/step | CPU per step [ms] | CPU per iterate [ms] | per iterate per 1000 elements [ms] |")
    print("|---|---|---|---|---|---|")
    for model in a.models:
        for ne in a.elements:
            r = bed_row(model, ne, a.steps, a.warmup)
            print(f"| {model} | {ne} | {r['its']:.2f} | {r['per_step_ms']:.2f} | {r['per_iterate_ms']:.3f} | "
                  f"{1e3 * r['per_iterate_ms'] / ne:.3f} |", flush=True)
    if not a.no_column:
        print(f"\n| liquefaction column, {a.shaking:g} s shaking | elements | CPU of the run [s] |")
        print("|---|---|---|")
        for ne in COLUMN:
            r = column_row(ne, a.shaking)
            print(f"| liquefaction-elcentro | {ne} | {r['cpu']:.2f} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
