"""Picard iterations per step and rejected steps of the full and reduced 1D models.

Runs every bundled 1D case (and settling-illite refined to 300 and 1000 elements)
with ``two_fluid_1d`` and ``reduced_1d`` (element ``1VW/0P/0n``, the one both
support) through the stepper, no output files, and reports steps, Picard
iterations per step, rejected attempts (the step halved: Picard not converged or
porosity out of (0, 1]) and the largest porosity difference between the two
models at the end (they solve the same discrete equations). CPU times are printed
too, but for speed ratios use ``bench_peers.py`` (alternated whole processes).

    python benchmarks/bench_convergence.py            # markdown table to stdout
    python benchmarks/bench_convergence.py --quick    # 1/10 of the simulated time
"""
from __future__ import annotations

import argparse
import sys
import time

import numpy as np

# (case, elements (0: the case's own), simulated seconds (0: the case's end time))
CONFIGS = [("fluidized-bed-step", 0, 0.0), ("settling-illite", 0, 0.0), ("slis-step-change", 0, 0.0),
           ("settling-illite", 300, 60.0), ("settling-illite", 1000, 60.0)]
MODELS = ("two_fluid_1d", "reduced_1d")


def run(case_name: str, model: str, elements: int, seconds: float) -> dict:
    from twofluid.casefile.builder import build
    from twofluid.casefile.loader import load_case
    from twofluid.timestepping.backward_euler import integrate

    case = load_case(case_name)
    case["case"]["model"], case["mesh"]["element"] = model, "1VW/0P/0n"
    if elements:
        case["mesh"]["elements"] = elements
    if seconds:
        case["time"]["end"] = seconds
    b = build(case)
    steps = its = rejected = 0
    s = b.state
    t0 = time.process_time()
    for st in integrate(b.model, b.state, b.t_end, b.dt, settings=b.settings):
        steps, its, rejected, s = st.n_steps, its + st.iterations, rejected + st.rejected, st.state
    cpu = time.process_time() - t0
    return {"case": case_name, "model": model, "elements": b.model.mesh.n_elements, "seconds": b.t_end,
            "steps": steps, "its": its / max(steps, 1), "rejected": rejected, "cpu": cpu, "n": s.n, "t": s.t}


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="a tenth of the simulated time")
    a = p.parse_args(argv)
    print("| case | elements | simulated [s] | model | steps | Picard its/step | rejected | its ratio full/reduced "
          "| max |Δn| full − reduced | CPU [s] |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for case, ne, sec in CONFIGS:
        if a.quick:
            from twofluid.casefile.loader import load_case
            sec = 0.1 * (sec or load_case(case)["time"]["end"])
        r = {m: run(case, m, ne, sec) for m in MODELS}
        f, red = r["two_fluid_1d"], r["reduced_1d"]
        dn = float(np.abs(f["n"] - red["n"]).max()) if abs(f["t"] - red["t"]) < 1e-9 else float("nan")
        for m in MODELS:
            x = r[m]
            ratio = f"{f['its'] / red['its']:.2f}" if m == "two_fluid_1d" else ""
            diff = f"{dn:.1e}" if m == "two_fluid_1d" else ""
            print(f"| {case} | {x['elements']} | {x['seconds']:g} | {m} | {x['steps']} | {x['its']:.2f} | "
                  f"{x['rejected']} | {ratio} | {diff} | {x['cpu']:.2f} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
