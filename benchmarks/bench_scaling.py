"""Cost per time step against the number of elements: full and reduced 1D models, liquefaction column.

1D models: settling-illite refined to 100 … 10 000 elements, ``--steps`` steps of
the case's Δt after ``--warmup`` steps (in this process, no output files); CPU time
(``time.process_time``) per step and per Picard iterate. Column, per step: the bundled
liquefaction-elcentro (the peer column of ``bench_peers.py``) with 20 … 10 000 elements,
``--column-steps`` vertical steps of 0.02 s while it shakes, after ``--warmup`` steps, in this
process (the model's steps only, no recording): CPU per vertical step, split into its shear
sub-steps (:meth:`LiquefactionColumn._shear`, per sub-step) and the vertical solve (the rest).
Column, whole runs: 20, 80 and 320 elements and 2 s of shaking, as whole
``twofluid run --no-plots`` processes (CPU of the whole process, start-up included).

    python benchmarks/bench_scaling.py               # the three tables
    python benchmarks/bench_scaling.py --no-column --no-column-runs
"""
from __future__ import annotations

import argparse
import resource
import subprocess
import sys
import tempfile
import time
import tomllib
from pathlib import Path

import tomli_w

ELEMENTS = (100, 300, 1000, 3000, 10000)
COLUMN = (20, 80, 320)
COLUMN_STEPS = (20, 80, 320, 1000, 3000, 10000)
LAYER_MAX = 5000  # elements of one layer (the case schema's limit)


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


def column_step_row(elements: int, steps: int, warmup: int) -> dict:
    """CPU per vertical step of the shaking column with ``elements``, its shear sub-steps apart."""
    from bench_peers import column_case
    from twofluid.casefile.loader import load_case
    from twofluid.runners.liquefaction import build_column

    with tempfile.TemporaryDirectory() as td:
        path = column_case(Path(td) / "column.toml", elements=elements, shaking=30.0, end=180.0)
        if elements > LAYER_MAX:  # the same sand as layers of at most LAYER_MAX elements
            case = tomllib.loads(path.read_text())
            layer, k = case["layers"][0], -(-elements // LAYER_MAX)
            case["layers"] = [dict(layer, name=f"{layer['name']} {i + 1}", thickness=layer["thickness"] / k,
                                   elements=elements // k) for i in range(k)]
            path.write_text(tomli_w.dumps(case))
        b = build_column(load_case(str(path)))
    col, s = b.column, b.state
    shear_cpu = [0.0]
    inner = col._shear

    def timed(state, t_new):  # the shear sub-steps of one vertical step
        t0 = time.process_time()
        out = inner(state, t_new)
        shear_cpu[0] += time.process_time() - t0
        return out

    col._shear = timed
    for _ in range(warmup):  # compiles or loads the kernels, fills the extrapolation history
        s = col.step(s, b.dt).state
    shear_cpu[0] = 0.0
    its = subs = 0
    t0 = time.process_time()
    for _ in range(steps):
        st = col.step(s, b.dt)
        s, its, subs = st.state, its + st.iterations, subs + st.substeps
    cpu = time.process_time() - t0
    return {"elements": elements, "its": its / steps, "per_step_ms": 1e3 * cpu / steps,
            "shear_ms": 1e3 * shear_cpu[0] / steps, "per_substep_us": 1e6 * shear_cpu[0] / subs,
            "vertical_ms": 1e3 * (cpu - shear_cpu[0]) / steps}


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
    p.add_argument("--no-column", action="store_true", help="no per-step table of the column")
    p.add_argument("--no-column-runs", action="store_true", help="no whole runs of the column")
    p.add_argument("--no-beds", action="store_true", help="no table of the 1D models")
    p.add_argument("--column-elements", type=int, nargs="+", default=list(COLUMN_STEPS))
    p.add_argument("--column-steps", type=int, default=25, help="timed vertical steps of the column")
    p.add_argument("--elements", type=int, nargs="+", default=list(ELEMENTS), help="mesh sizes of the 1D models")
    p.add_argument("--models", nargs="+", default=["two_fluid_1d", "reduced_1d"])
    p.add_argument("--shaking", type=float, default=2.0, help="seconds of shaking of the column runs")
    a = p.parse_args(argv)
    if not a.no_beds:
        print("| model | elements | Picard its/step | CPU per step [ms] | CPU per iterate [ms] | per iterate per 1000 elements [ms] |")
        print("|---|---|---|---|---|---|")
        for model in a.models:
            for ne in a.elements:
                r = bed_row(model, ne, a.steps, a.warmup)
                print(f"| {model} | {ne} | {r['its']:.2f} | {r['per_step_ms']:.2f} | {r['per_iterate_ms']:.3f} | "
                      f"{1e3 * r['per_iterate_ms'] / ne:.3f} |", flush=True)
    if not a.no_column:
        print(f"\n| liquefaction column, shaking, Δt = 0.02 s | elements | Picard its/step | CPU per vertical step [ms] "
              "| shear sub-steps [ms] | per sub-step [µs] | per sub-step per 1000 elements [µs] | vertical [ms] "
              "| vertical per 1000 elements [ms] |")
        print("|---|---|---|---|---|---|---|---|---|")
        for ne in a.column_elements:
            r = column_step_row(ne, a.column_steps, a.warmup)
            print(f"| liquefaction-elcentro | {ne} | {r['its']:.2f} | {r['per_step_ms']:.3f} | {r['shear_ms']:.3f} | "
                  f"{r['per_substep_us']:.1f} | {1e3 * r['per_substep_us'] / ne:.1f} | {r['vertical_ms']:.3f} | "
                  f"{1e3 * r['vertical_ms'] / ne:.3f} |", flush=True)
    if not a.no_column_runs:
        print(f"\n| liquefaction column, {a.shaking:g} s shaking | elements | CPU of the run [s] |")
        print("|---|---|---|")
        for ne in COLUMN:
            r = column_row(ne, a.shaking)
            print(f"| liquefaction-elcentro | {ne} | {r['cpu']:.2f} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
