"""The liquefaction column's vertical step in one compiled call (models.column_step_kernel).

It must make the steps the stepper's Python path makes (timestepping.backward_euler with the
reduced model's whole iterates and the Newton acceptance test), bit for bit: the same iterates,
the same acceptance, the same pressure and extrapolation table; where it cannot make a step at
the first try it hands the step, and the Newton test's carried samples, back to the stepper. Its
plain Python (what ``TWOFLUID_DISABLE_JIT=1`` runs: the same function object) and its compiled
form agree to round-off.
"""
from __future__ import annotations

import copy
from dataclasses import replace

import numpy as np
import pytest

from twofluid.casefile.loader import load_case
from twofluid.models import column_step_kernel
from twofluid.models.reduced_column import ReducedVerticalColumn
from twofluid.runners.liquefaction import build_column


_FAST_DONE = ReducedVerticalColumn.fast_done


def _column(name: str, duration: float = 1.5):
    c = load_case(f"liquefaction-{name}")
    c["output"]["plots"], c["ground_motion"]["duration"] = False, duration
    return build_column(c)


def _run(name: str, fast: bool, t_end: float = 6.0, monkeypatch=None, newton_test: bool = True):
    """Every step of a short run (shaking, ring-down, reconsolidation with growing steps):
    (t, iterations, V, W, n, P, n̄, surface settlement) per step, and how many steps the compiled
    call made and handed back."""
    b = _column(name)
    col = b.column
    col.v.fast_steps = fast
    col.settings = replace(col.settings, newton_test=newton_test)
    made = {"fast": 0, "back": 0}
    real = _FAST_DONE

    def counted(self, *a):  # (after the compiled call, alone or in the split step: made or handed back)
        out = real(self, *a)
        made["fast" if out is not None else "back"] += 1
        return out

    monkeypatch.setattr(ReducedVerticalColumn, "fast_done", counted)
    rows = []
    for step in col.run(b.state, t_end, b.dt, b.dt_after):
        v = step.state.vertical
        rows.append((v.t, step.iterations, v.V, v.W, v.n, v.P, v.n_bar, col.settlement(step.state)))
    return rows, made


@pytest.mark.parametrize("name, newton_test", [("elcentro", True), ("gravel", True), ("layered-site", True),
                                               ("elcentro", False)])
def test_the_compiled_step_makes_the_steppers_steps_bit_for_bit(name, newton_test, monkeypatch):
    """With the Newton test (accepting on a predicted change) and with the plain test alone."""
    if column_step_kernel.compiled() is None:
        pytest.skip("no compiled kernels here")
    ref, off = _run(name, False, monkeypatch=monkeypatch, newton_test=newton_test)
    got, on = _run(name, True, monkeypatch=monkeypatch, newton_test=newton_test)
    assert off["fast"] == 0
    assert on["fast"] > 0.9 * len(got)  # (the rest handed back: steps the stepper halves, say)
    assert len(got) == len(ref) > 100
    for r, g in zip(ref, got):
        assert r[:2] == g[:2]
        for a, b in zip(r[2:7], g[2:7]):
            np.testing.assert_array_equal(a, b)
        assert r[7] == g[7]


def test_a_step_the_call_cannot_make_goes_back_to_the_stepper(monkeypatch):
    """A compiled call that fails (here: told it did not converge on every tenth step) leaves the
    step, the extrapolation table and the Newton test's samples to the stepper, which makes the
    same run."""
    if column_step_kernel.compiled() is None:
        pytest.skip("no compiled kernels here")
    ref, _ = _run("elcentro", False, t_end=3.0, monkeypatch=monkeypatch)
    real = ReducedVerticalColumn._fast_static
    calls = [0]

    def sometimes_failing(self, old):
        static = real(self, old)
        ker = static[0]

        def ker_or_fail(*a):
            calls[0] += 1
            return column_step_kernel.NOT_CONVERGED if calls[0] % 10 == 0 else ker(*a)
        return (ker_or_fail, *static[1:])

    monkeypatch.setattr(ReducedVerticalColumn, "_fast_static", sometimes_failing)
    got, made = _run("elcentro", True, t_end=3.0, monkeypatch=monkeypatch)
    assert made["back"] >= len(got) // 10 > 5
    assert len(got) == len(ref)
    for r, g in zip(ref, got):
        assert r[:2] == g[:2]
        for a, b in zip(r[2:7], g[2:7]):
            np.testing.assert_array_equal(a, b)


def test_plain_and_compiled_steps_agree(monkeypatch):
    """Each compiled call of a short run repeated by the plain Python function on copies of its
    arguments: the same return code and outputs to 1e-12 (relative to each output's largest entry)."""
    ker = column_step_kernel.compiled()
    if ker is None or ker is column_step_kernel.vertical_step:
        pytest.skip("no compiled kernel here (or the JIT is disabled: the plain function is the kernel)")
    real = ReducedVerticalColumn._fast_static
    checked = [0]

    def both(*args):
        mine = copy.deepcopy(args)
        code = ker(*args)
        assert column_step_kernel.vertical_step(*mine) == code
        if code == column_step_kernel.OK:
            k = len(args) - len(column_step_kernel.ALONE)  # (the arguments after info: nothing besides the step)
            for a, b in zip(args[k - 8:k], mine[k - 8:k]):  # the samples, [V, W, n], P, the table, info
                scale = max(float(np.abs(a).max()), 1e-300) if a.dtype == float else 0
                if a.dtype == float and a.ndim == 2:  # the table: the rows it wrote
                    a, b = a[:args[k - 1][2]], b[:args[k - 1][2]]
                    scale = max(float(np.abs(a).max()), 1e-300)
                assert np.all(np.abs(a - b) <= 1e-12 * scale) if scale else np.array_equal(a, b)
            checked[0] += 1
        return code

    monkeypatch.setattr(ReducedVerticalColumn, "_fast_static", lambda self, old: (both, *real(self, old)[1:]))
    b = _column("elcentro", duration=0.3)
    for _ in b.column.run(b.state, 0.6, b.dt, b.dt_after):
        pass
    assert checked[0] > 20
