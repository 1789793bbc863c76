"""CPU time of one Newton iterate and of one time step of the 1D models, in process, best of rounds.

For each case (the two OpenFOAM peers' twofluid cases and the bundled 1D cases) and model
(``two_fluid_1d`` on its kernels and on its general weak-form assembly, ``reduced_1d`` on its
kernels, the one path it has), the case is run for ``--warm`` seconds of simulated time, then:

- *iterate*: ``assemble`` + ``solve`` of the first iterate of the next step (the captured
  iterate, assembled again and again; the step's constants are cached as in a run);
- *step*: one whole ``picard_step`` from the reached state (its iterates, the step's constants
  and the bed-force shift computed anew, the pressure recovery), also repeated;
- *steps*: the mean per step of ``--span`` seconds of simulated time through ``integrate``
  (what a run spends per step in the model and the stepper, without outputs).

CPU time (``time.process_time``), best of ``--rounds`` rounds: the machine may be shared,
and the minimum is the least disturbed. Run with ``PYTHONPATH`` pointing at an export of an
older commit for a before/after table (the ``compiled`` switch is then ignored where that
version has no compiled path, and both rows of the model time the same code).

    python benchmarks/bench_iterate.py
    python benchmarks/bench_iterate.py --cases openfoam-fluidized-bed --rounds 9
"""
from __future__ import annotations

import argparse
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
CASES = {"openfoam-fluidized-bed": HERE / "peers" / "openfoam-fluidized-bed.toml",
         "openfoam-sedimentation": HERE / "peers" / "openfoam-sedimentation.toml",
         "fluidized-bed-step": "fluidized-bed-step", "settling-illite": "settling-illite",
         "slis-step-change": "slis-step-change"}
CONFIGS = (("two_fluid_1d", False), ("two_fluid_1d", None), ("reduced_1d", None))


def _best(f, number: int, rounds: int) -> float:
    """Least CPU seconds per call of ``f`` over ``rounds`` rounds of ``number`` calls."""
    out = []
    for _ in range(rounds):
        t0 = time.process_time()
        for _ in range(number):
            f()
        out.append((time.process_time() - t0) / number)
    return min(out)


def measure(case_ref, model: str, compiled, warm: float, span: float, rounds: int) -> dict:
    from twofluid.casefile.builder import build
    from twofluid.casefile.loader import load_case
    from twofluid.timestepping.backward_euler import integrate, picard_step

    case = load_case(str(case_ref))
    case["case"]["model"] = model
    b = build(case)
    m = b.model
    m.compiled = compiled  # two_fluid_1d: False = the general weak-form assembly, None = the kernels
    s = b.state
    for step in integrate(m, s, warm, b.dt, settings=b.settings):
        s = step.state
    seen = []
    assemble = m.assemble

    def spy(k, old, dt, t):
        if not seen:
            seen.append((k.copy(), old, dt, t))
        return assemble(k, old, dt, t)

    m.assemble = spy
    _, its = picard_step(m, s, b.dt, b.settings)
    del m.assemble
    k, old, dt, t = seen[0]

    def iterate():
        m.solve(m.assemble(k, old, dt, t), t)

    per_iterate = _best(iterate, 100, rounds)
    def step():
        m._step = m._step_full = m._shift_cache = m._fk_step = None  # the step's constants and bed-force shift anew
        picard_step(m, s, b.dt, b.settings)

    per_step = _best(step, 30, rounds)
    best_span, n_steps, n_its = float("inf"), 0, 0
    for _ in range(max(1, rounds // 3)):
        n_steps = n_its = 0
        t0 = time.process_time()
        for step in integrate(m, s, s.t + span, b.dt, settings=b.settings):
            n_steps, n_its = n_steps + 1, n_its + step.iterations
        best_span = min(best_span, (time.process_time() - t0) / max(n_steps, 1))
    label = f"{model} ({'weak-form assembly' if compiled is False else 'kernels'})"
    return {"case": Path(str(case_ref)).stem if str(case_ref).endswith(".toml") else str(case_ref),
            "model": label, "elements": m.mesh.n_elements, "iterate_us": 1e6 * per_iterate,
            "step_us": 1e6 * per_step, "step_its": its, "steps_us": 1e6 * best_span,
            "its_per_step": n_its / max(n_steps, 1)}


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--cases", nargs="+", default=list(CASES), choices=list(CASES))
    p.add_argument("--rounds", type=int, default=5)
    p.add_argument("--warm", type=float, default=5.0, help="simulated seconds before the measurement")
    p.add_argument("--span", type=float, default=2.0, help="simulated seconds of the per-step mean")
    a = p.parse_args(argv)
    compiled_ok = {}
    for model, module in (("reduced_1d", "reduced_kernel"), ("two_fluid_1d", "full_kernel")):
        try:
            compiled_ok[model] = __import__(f"twofluid.models.{module}", fromlist=["available"]).available()
        except ImportError:  # an older version
            compiled_ok[model] = False
    print("| case | elements | model | iterate [µs] | step [µs] (its) | per step over a span [µs] | its/step |")
    print("|---|---|---|---|---|---|---|")
    for name in a.cases:
        for model, compiled in CONFIGS:
            if compiled is None and not compiled_ok[model]:
                continue
            r = measure(CASES[name], model, compiled, a.warm, a.span, a.rounds)
            print(f"| {name} | {r['elements']} | {r['model']} | {r['iterate_us']:.0f} | {r['step_us']:.0f} "
                  f"({r['step_its']}) | {r['steps_us']:.0f} | {r['its_per_step']:.2f} |", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
