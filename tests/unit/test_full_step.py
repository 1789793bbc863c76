"""The full 1D model's time step in one compiled call (models/full_step_kernel.py, models/full_step.py).

It must make the steps the stepper's Python path makes (timestepping.backward_euler._step with the
model's one-call iterates, the Newton acceptance test, the extrapolated first iterate), bit for bit:
the same iterates, acceptance, step sizes and extrapolation table; where it cannot make a step at the
first try it hands the step, the table and the Newton test's samples back to the stepper, and the two
paths take turns. Its plain Python (what ``TWOFLUID_DISABLE_JIT=1`` runs) and its compiled form agree
to round-off.
"""
from __future__ import annotations

import copy
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from kernel_paths import model_of

from twofluid.models import full_step, full_step_kernel
from twofluid.timestepping.backward_euler import integrate
from twofluid.timestepping import newton as _newton

PEERS = Path(__file__).resolve().parents[2] / "benchmarks" / "peers"
requires_kernel = pytest.mark.skipif(full_step_kernel.compiled() is None, reason="no numba and nothing built")


def _run(name: str, t_end: float, fast: bool, monkeypatch, newton_test: bool = True, fail_every: int = 0):
    """Every step of ``t_end`` [s] of case ``name`` with the full model: (t, Δt, iterations, rejected,
    V, W, P, n, n̄), and how many steps the compiled call made and handed back. ``fail_every``: the call
    declines every so many steps (the stepper makes those)."""
    b = model_of(name, "two_fluid_1d")
    m = b.model
    settings = replace(b.settings, newton_test=newton_test)
    counts = [0, 0]

    def counted(model, old, dt, s):
        if not fast or (fail_every and (counts[0] + counts[1]) % fail_every == fail_every - 1):
            counts[1] += 1
            _newton.release_kernel_samples(model)
            return None
        out = real(model, old, dt, s)
        counts[out is None] += 1
        return out

    real = full_step.step
    monkeypatch.setattr(full_step, "step", counted)
    steps = [(st.t, st.dt, st.iterations, st.rejected, st.state.V, st.state.W, st.state.P, st.state.n,
              st.state.n_bar) for st in integrate(m, b.state, t_end, b.dt, stops=(0.5 * t_end,), settings=settings)]
    monkeypatch.setattr(full_step, "step", real)
    return steps, counts


def _same(ref, got):
    assert len(ref) == len(got)
    for r, g in zip(ref, got):
        assert r[:4] == g[:4]
        for a, c in zip(r[4:], g[4:]):
            np.testing.assert_array_equal(a, c)


CASES = [("fluidized-bed-step", 4.0), ("settling-illite", 40.0), ("slis-step-change", 5.0)]


@requires_kernel
@pytest.mark.parametrize("name,t_end", CASES)
@pytest.mark.parametrize("newton_test", [True, False])
def test_the_compiled_step_makes_the_steppers_steps_bit_for_bit(name, t_end, newton_test, monkeypatch):
    """With the Newton test (accepting on a predicted change) and with the plain test alone; the
    Slis bed rejects steps (Δt halved), which the stepper makes."""
    ref, off = _run(name, t_end, False, monkeypatch, newton_test)
    got, on = _run(name, t_end, True, monkeypatch, newton_test)
    assert off[0] == 0 and on[0] > 0.8 * len(got) > 10  # (else the paths compared would be one)
    _same(ref, got)


@requires_kernel
def test_a_step_the_call_declines_goes_to_the_stepper_and_back(monkeypatch):
    """Every third step made by the stepper: its extrapolation table and the Newton test's samples
    pass between the two paths, and the steps stay the stepper's own."""
    ref, _ = _run("fluidized-bed-step", 3.0, False, monkeypatch)
    got, (made, declined) = _run("fluidized-bed-step", 3.0, True, monkeypatch, fail_every=3)
    assert made > 40 and declined > 20
    _same(ref, got)


def test_a_replaced_method_or_another_law_takes_the_stepper():
    """An instance replacing what the call does, the general assembly, the reduced model and the Wen–Yu
    law (whose two powers the Python path takes from NumPy's array routine) get None."""
    b = model_of("fluidized-bed-step", "two_fluid_1d")
    m, s = b.model, b.state
    m.check = lambda st: None
    assert full_step.step(m, s, b.dt, b.settings) is None
    del m.check
    m.compiled = False
    assert full_step.step(m, s, b.dt, b.settings) is None
    r = model_of("fluidized-bed-step", "reduced_1d")
    assert full_step.step(r.model, r.state, r.dt, r.settings) is None
    w = model_of(str(PEERS / "openfoam-fluidized-bed.toml"), "two_fluid_1d")  # Wen–Yu: NumPy's powers
    assert w.model.clo.drag.__name__ == "wen_yu" and full_step.step(w.model, w.state, w.dt, w.settings) is None


@requires_kernel
def test_plain_and_compiled_steps_agree(monkeypatch):
    """Each compiled call of a short run repeated by the plain Python function on copies of its
    arguments: the same return code and outputs to 1e-12 (relative to each output's largest entry)."""
    ker = full_step_kernel.compiled()
    if ker is full_step_kernel.full_step:
        pytest.skip("the JIT is disabled: the plain function is the kernel")
    real = full_step._static
    checked = [0]

    def both(*args):
        mine = copy.deepcopy(args)
        code = ker(*args)
        with np.errstate(all="ignore"):
            assert full_step_kernel.full_step(*mine) == code
        if code == full_step_kernel.OK:
            rows = args[-1][2]
            for a, b in zip(args[-9:], mine[-9:]):  # the samples, the state, the table, the upwind side, info
                if a.dtype == float and a.ndim == 2:  # the table: the rows it wrote
                    a, b = a[:rows], b[:rows]
                scale = max(float(np.abs(a).max()), 1e-300) if a.dtype == float else 0
                assert np.all(np.abs(a - b) <= 1e-12 * scale) if scale else np.array_equal(a, b)
            checked[0] += 1
        return code

    monkeypatch.setattr(full_step, "_static", lambda model: (lambda st: st and (both, *st[1:]))(real(model)))
    b = model_of("fluidized-bed-step", "two_fluid_1d")
    for _ in integrate(b.model, b.state, 30 * b.dt, b.dt, settings=b.settings):
        pass
    assert checked[0] >= 30
