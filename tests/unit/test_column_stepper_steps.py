"""The liquefaction column's vertical steps that the stepper halves: integrate's steps with each try
made by the vertical model's compiled_step (one compiled call) where it can be, by the stepper's
Python ``_step`` where it cannot. They must be integrate's steps bit for bit: the same step sizes,
iterations, states and failure, where tries fail, halve and grow again."""
from __future__ import annotations

import copy
from dataclasses import replace

import numpy as np
import pytest

from twofluid.casefile.loader import load_case
from twofluid.models import column_step_kernel
from twofluid.runners.liquefaction import build_column
from twofluid.timestepping import backward_euler as be, newton


@pytest.fixture(scope="module")
def shaken():
    """A layered column after 1 s of shaking and 1 s of free vibration (its liquefied state)."""
    c = load_case("liquefaction-layered-site")
    c["output"]["plots"], c["ground_motion"]["duration"] = False, 1.0
    c["shear_wave"]["free_vibration"] = 1.0
    b = build_column(c)
    col, s = b.column, b.state
    for step in col.run(s, 2.5, b.dt, b.dt_after):
        s = step.state
    return col, s


def _steps(col, s, dt, settings, how, monkeypatch):
    """Each step (size, iterations, V, W, P, n, n̄) from ``s`` over ``dt`` [s] of a copy of the column's
    vertical model; and the stepper's tries and failed tries."""
    model = copy.deepcopy(col.v, memo={id(s.vertical): s.vertical})  # (its caches know the state)
    newton.release_kernel_samples(model)  # (the Newton test's record of the run so far, for both: not copied with the model)
    counts = {"python": 0, "failed": 0}
    real = be._step

    def spy(*a, **kw):
        out = real(*a, **kw)
        counts["python"] += 1
        counts["failed"] += out[0] is None
        return out

    monkeypatch.setattr(be, "_step", spy)
    if how == "integrate":
        model.compiled_step = None  # (the stepper's own tries only)
    steps = [(st.dt, st.iterations, st.state) for st in be.integrate(model, s.vertical, s.t + dt, dt, settings=settings)]
    monkeypatch.undo()
    return [(h, its, v.t, v.V, v.W, v.P, v.n, v.n_bar) for h, its, v in steps], counts


@pytest.mark.parametrize("max_iter, dt", [(3, 60.0), (2, 5.0)])
def test_the_steps_are_integrates_where_tries_fail_and_halve(shaken, monkeypatch, max_iter, dt):
    if column_step_kernel.compiled() is None:
        pytest.skip("no compiled kernels here")
    col, s = shaken
    tight = replace(col.settings, max_iter=max_iter)  # (tries that do not converge: the steps halve)
    ref, by_integrate = _steps(col, s, dt, tight, "integrate", monkeypatch)
    got, by_python = _steps(col, s, dt, tight, "compiled_step", monkeypatch)
    assert by_python["failed"] == by_integrate["failed"] > 3  # (every failed try is the stepper's own)
    assert by_python["python"] < by_integrate["python"] - 3  # (tries made by the compiled step)
    assert len(got) == len(ref) > 3
    for r, g in zip(ref, got):
        assert r[:3] == g[:3]
        for a, b in zip(r[3:], g[3:]):
            np.testing.assert_array_equal(a, b)


def test_a_step_that_cannot_be_made_fails_as_integrates(shaken, monkeypatch):
    col, s = shaken
    hopeless = replace(col.settings, max_iter=1, dt_min=1.0)
    with pytest.raises(be.StepFailure) as ref:
        _steps(col, s, 5.0, hopeless, "integrate", monkeypatch)
    with pytest.raises(be.StepFailure) as got:
        _steps(col, s, 5.0, hopeless, "compiled_step", monkeypatch)
    assert str(got.value) == str(ref.value)
    assert (got.value.t, got.value.dt) == (ref.value.t, ref.value.dt)
