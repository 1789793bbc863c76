"""Golden-output regression of the bundled 1D cases: each run (shortened) ends where it ended
when its golden file was written, to a tolerance set by the stepper's convergence test.

The golden files (``tests/golden/<run>.json``: the state V, W [m/s] at the vertices, n [-] and
P [Pa] per element, at the end time) change only through ``python -m pytest
tests/cases/test_golden_1d.py --update-golden``, in a commit that says why the results moved.

Tolerance. A step ends when an iterate changes by less than ``tol`` (PicardSettings.tol:
absolute in n, relative to the velocity scale in V and W). The iterates are Newton iterates
(quadratic contraction), so the accepted state is within a small fraction of ``tol`` of the
discrete solution; another CPU, BLAS or compiler changes only round-off in each solve, which
moves a converged step by far less than ``tol``. Over the run those step errors add up at most
linearly (the runs are short and dissipative), and a different decision of the stepper (one
iterate more or less, a different step size) would move the result by the time-discretisation
error, orders of magnitude above ``tol`` — that is a change of results the test must report.
So the compared quantities are

- n: max |n − n_golden| ≤ 10 tol (absolute),
- V, W: max |x − x_golden| ≤ 10 tol × s, s the golden run's velocity scale (max |V|, |W|),
- P: max |P − P_golden| ≤ 10 tol × max |P_golden|,

and the end time exactly. 10 tol leaves room for the accumulation of per-step differences
without hiding a change of step sequence or of the equations.
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from twofluid.casefile.builder import build
from twofluid.casefile.loader import load_case
from twofluid.timestepping.backward_euler import integrate

GOLDEN = Path(__file__).resolve().parent.parent / "golden"

# (golden file, bundled case, [case] model or None for the case's own, end time [s])
RUNS = [
    ("fluidized-bed-step", "fluidized-bed-step", None, 10.0),
    ("fluidized-bed-step.reduced_1d", "fluidized-bed-step", "reduced_1d", 10.0),
    ("settling-illite", "settling-illite", None, 90.0),
    ("settling-illite.reduced_1d", "settling-illite", "reduced_1d", 90.0),
    ("settling-illite.2VW", "settling-illite", "2VW/1P/0n", 30.0),
    ("slis-step-change", "slis-step-change", None, 10.0),
]


def _run(name: str, model: str | None, end: float):
    case = load_case(name)
    if model == "2VW/1P/0n":
        case["mesh"]["element"] = model
    elif model:
        case["case"]["model"] = model
    case["time"]["end"] = end
    b = build(case)
    s, steps = b.state, 0
    for st in integrate(b.model, b.state, end, b.dt, settings=b.settings):
        s, steps = st.state, steps + 1
    return s, b.settings.tol


@pytest.mark.parametrize("golden, name, model, end", RUNS, ids=[r[0] for r in RUNS])
def test_a_bundled_run_ends_where_its_golden_output_says(golden, name, model, end, request):
    s, tol = _run(name, model, end)
    path = GOLDEN / f"{golden}.json"
    fields = {f: np.asarray(getattr(s, f), dtype=float) for f in ("V", "W", "n", "P")}
    if request.config.getoption("--update-golden"):
        path.write_text(json.dumps({"case": name, "model": model, "end_s": end, "t": s.t,
                                    **{f: [float(x) for x in a] for f, a in fields.items()}}) + "\n")
        pytest.skip(f"{path.name} rewritten")
    ref = json.loads(path.read_text())
    assert s.t == ref["t"]
    gold = {f: np.asarray(ref[f]) for f in ("V", "W", "n", "P")}
    scale = max(np.abs(gold["V"]).max(), np.abs(gold["W"]).max())
    for f, a in fields.items():
        assert a.shape == gold[f].shape, f
        bound = 10 * tol * {"n": 1.0, "V": scale, "W": scale, "P": np.abs(gold["P"]).max()}[f]
        err = np.abs(a - gold[f]).max()
        assert err <= bound, f"{f}: {err:.3g} > {bound:.3g}"
