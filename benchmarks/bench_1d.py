"""Time the bundled 1D cases with the full and reduced models and both 1D elements.

Each configuration runs in its own process (so the peak resident memory is its
own): the bundled case with ``[case] model`` and ``[mesh] element`` replaced, run
through the stepper for ``--seconds`` of simulated time (no output files). Reported:
wall time per simulated second and per step, steps, Picard iterations per step,
peak traced Python/NumPy memory (tracemalloc, over 20 separate steps) and peak resident set size (ru_maxrss).

    python benchmarks/bench_1d.py                 # all configurations, table to stdout
    python benchmarks/bench_1d.py --write FILE    # the table with the machine description

(docs/benchmarks.md keeps its 2026-11-26 output as history; the newer tables there come from
bench_peers.py, bench_convergence.py, bench_scaling.py and bench_startup.py.)
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time

CONFIGS = [(case, model, element, 0)
           for case in ("fluidized-bed-step", "settling-illite")
           for model, element in (("two_fluid_1d", "1VW/0P/0n"), ("two_fluid_1d", "2VW/1P/0n"),
                                  ("reduced_1d", "1VW/0P/0n"))]
# mesh scaling: the fluidized bed on 1000 elements (0 = the case's own mesh)
CONFIGS += [("fluidized-bed-step", m, "1VW/0P/0n", 1000) for m in ("two_fluid_1d", "reduced_1d")]
SECONDS = {"fluidized-bed-step": 20.0, "settling-illite": 100.0}


def one(case_name: str, model: str, element: str, seconds: float, elements: int = 0) -> dict:
    import resource
    import tracemalloc

    from twofluid.casefile.builder import build
    from twofluid.casefile.loader import load_case
    from twofluid.timestepping.backward_euler import integrate

    case = load_case(case_name)
    case["case"]["model"], case["mesh"]["element"] = model, element
    case["time"]["end"] = seconds
    if elements:
        case["mesh"]["elements"] = elements
    b = build(case)
    t0 = time.perf_counter()
    steps = iters = 0
    for st in integrate(b.model, b.state, b.t_end, b.dt, settings=b.settings):
        steps, iters = st.n_steps, iters + st.iterations
    wall = time.perf_counter() - t0
    # memory does not grow with simulated time (no history is kept): trace 20 steps
    # separately, since tracemalloc slows every allocation
    b = build(case)
    tracemalloc.start()
    for st in integrate(b.model, b.state, 20 * b.dt, b.dt, settings=b.settings):
        pass
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    return {"case": case_name, "model": model, "element": element, "elements": b.model.mesh.n_elements,
            "simulated_s": seconds, "wall_s": wall,
            "steps": steps, "iterations": iters, "wall_per_sim_s": wall / seconds, "wall_per_step_ms": 1e3 * wall / steps,
            "iters_per_step": iters / steps, "traced_peak_MiB": peak / 2**20,
            "maxrss_MiB": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}


def table(results: list[dict]) -> str:
    lines = ["| case | model | element | elements | simulated [s] | steps | Picard its/step | wall [s] | wall per simulated s [s] "
             "| wall per step [ms] | speed-up vs full (same element) | traced peak [MiB] | peak RSS [MiB] |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in results:
        full = next(x for x in results if x["case"] == r["case"] and x["model"] == "two_fluid_1d"
                    and x["element"] == r["element"] and x["elements"] == r["elements"])
        sp = full["wall_per_sim_s"] / r["wall_per_sim_s"]
        lines.append(f"| {r['case']} | {r['model']} | {r['element']} | {r['elements']} | {r['simulated_s']:g} | {r['steps']} | "
                     f"{r['iters_per_step']:.2f} | {r['wall_s']:.2f} | {r['wall_per_sim_s']:.3f} | "
                     f"{r['wall_per_step_ms']:.2f} | {sp:.2f}× | {r['traced_peak_MiB']:.1f} | {r['maxrss_MiB']:.0f} |")
    return "\n".join(lines)


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--one", nargs=5, metavar=("CASE", "MODEL", "ELEMENT", "SECONDS", "ELEMENTS"))
    p.add_argument("--write", help="write the markdown table with the machine description to this file")
    p.add_argument("--repeat", type=int, default=1, help="runs per configuration (the fastest is kept)")
    a = p.parse_args(argv)
    if a.one:
        print(json.dumps(one(a.one[0], a.one[1], a.one[2], float(a.one[3]), int(a.one[4]))))
        return 0
    load_before = os.getloadavg()
    results = []
    for case, model, element, elements in CONFIGS:
        runs = []
        seconds = SECONDS[case] / 10 if elements else SECONDS[case]
        for _ in range(a.repeat):
            out = subprocess.run([sys.executable, __file__, "--one", case, model, element, str(seconds),
                                  str(elements)],
                                 capture_output=True, text=True, check=True)
            runs.append(json.loads(out.stdout.strip().splitlines()[-1]))
        best = min(runs, key=lambda r: r["wall_s"])
        results.append(best)
        print(f"{case} {model} {element} {best['elements']}: {best['wall_per_sim_s']:.3f} s per simulated s",
              file=sys.stderr)
    text = table(results)
    load = f"{load_before[0]:.2f} before, {os.getloadavg()[0]:.2f} after the runs"
    print(text)
    print(f"load average (1 min): {load}", file=sys.stderr)
    if a.write:
        from twofluid.verification.suite import machine

        import datetime
        with open(a.write, "w", encoding="utf-8") as fh:
            fh.write(HEADER.format(date=f"{datetime.datetime.now():%Y-%m-%d %H:%M}", machine=machine(),
                                   repeat=a.repeat, load=load) + text + "\n" + NOTES)
    return 0


HEADER = """# Benchmarks

Generated by `python benchmarks/bench_1d.py --repeat {repeat} --write docs/benchmarks.md` on {date}.

Machine: {machine}. Load average (1 min, all processes on the machine): {load}.

Each configuration runs the bundled case in its own process through the backward-Euler
stepper (no output files), for 20 s (fluidized-bed-step) or 100 s (settling-illite) of
simulated time at the case's step (2 s for the 1000-element mesh-scaling rows); the fastest of {repeat} run(s) is kept. The reduced
model supports only the `1VW/0P/0n` element; its speed-up is against the full model
with the same element.

"""
NOTES = """
Notes. Wall times are sensitive to other load on the machine (see the load average
above: with 2 logical CPUs, a load above 1 means the runs shared them with other jobs,
and the speed-up ratios then move by ±30 %); the per-step figures are the more stable
ones. "traced peak" is
the peak of Python/NumPy allocations over 20 steps (tracemalloc, run separately
from the timed run because it slows every allocation), "peak RSS" the
whole process's maximum resident set size (including the interpreter and imports).
"""

if __name__ == "__main__":
    sys.exit(main())
