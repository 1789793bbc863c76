"""The stepper's acceptance of Newton iterates on their predicted change (timestepping.newton).

The plain test accepts iterate k once its change is below ``tol``; the Newton test may accept
an earlier iterate of the same sequence, when the next change is predicted to be below
tol/1000. So on every step the state it accepts must differ from the plain test's (computed
here from a copy of the model at the start of the step, the same iterates) by less than
``tol`` in the stepper's own measure, it must never take more iterates, and whole runs must
agree to the accumulated per-step differences.
"""
from __future__ import annotations

import copy
from dataclasses import replace

import numpy as np
import pytest

import twofluid.timestepping.backward_euler as be
from twofluid.casefile.builder import build
from twofluid.casefile.loader import load_case
from twofluid.models.reduced_column import ReducedVerticalColumn
from twofluid.models.two_fluid_1d import TwoFluid1D
from twofluid.runners.liquefaction import build_column
from twofluid.timestepping.newton import NewtonTest


@pytest.fixture
def audit(monkeypatch):
    """Every Newton-tested step is repeated with the plain test on a copy of the model."""
    real = be._step  # what ``integrate`` calls
    rows = []

    def spy(model, old, dt, settings, accept_unconverged=False):
        if not (settings.newton_test and getattr(model, "newton_iterates", False)):
            return real(model, old, dt, settings, accept_unconverged)
        plain_model = copy.deepcopy(model, memo={id(old): old})  # its caches still know ``old``
        plain, plain_its, _ = real(plain_model, old, dt, replace(settings, newton_test=False), accept_unconverged)
        new, its, predicted = real(model, old, dt, settings, accept_unconverged)
        assert (new is None) == (plain is None), (old.t, dt, its, plain_its)
        if new is not None:
            assert its + predicted <= plain_its  # the step-size control sees at most the plain count
            rows.append((max(be.relative_change(model, new, plain)) / settings.tol, its, plain_its))
        return new, its, predicted

    monkeypatch.setattr(be, "_step", spy)
    # the liquefaction column's vertical steps by the stepper, not in one compiled call (which makes the
    # same steps: tests/unit/test_column_step_kernel.py)
    monkeypatch.setattr(ReducedVerticalColumn, "fast_steps", False)
    # and the full model's steps too (the same steps in one compiled call: tests/unit/test_full_step.py)
    monkeypatch.setattr(TwoFluid1D, "compiled_step", lambda self, old, dt, settings: None)
    return rows


def _check(rows):
    change, its, plain_its = np.array(rows).T
    print(f"largest change/tol {change.max():.3g}, iterates {its.sum() / plain_its.sum():.3f} of the plain test's")
    assert change.max() < 1.0  # below the tolerance: measured < 0.016 on these runs
    assert np.all(its <= plain_its)
    return its.sum() / plain_its.sum()


@pytest.mark.parametrize("name, model, t_end", [
    ("fluidized-bed-step", "reduced_1d", 8.0),  # with the hard steps at the bed surface (t = 7.62 s)
    ("fluidized-bed-step", "two_fluid_1d", 3.0),
    ("slis-step-change", "reduced_1d", 6.0),  # rejected steps, up to 12 iterates
    ("settling-illite", "two_fluid_1d", 4.0),
])
def test_beds_accept_within_the_tolerance_of_the_plain_test(audit, name, model, t_end):
    c = load_case(name)
    c["case"]["model"], c["time"]["end"] = model, t_end
    b = build(c)
    assert b.model.newton_iterates
    for _ in be.integrate(b.model, b.state, b.t_end, b.dt, settings=b.settings):
        pass
    assert _check(audit) < 1.0  # fewer iterates (measured 0.80–0.99)


@pytest.mark.parametrize("name", ["elcentro", "gravel"])
def test_column_accepts_within_the_tolerance_of_the_plain_test(audit, name):
    c = load_case(f"liquefaction-{name}")
    c["output"]["plots"], c["ground_motion"]["duration"] = False, 1.5
    b = build_column(c)
    for _ in b.column.run(b.state, 3.0, b.dt, b.dt_after):
        pass
    assert _check(audit) < 0.9  # measured 0.8


def _column_run(name, newton_test):
    c = load_case(f"liquefaction-{name}")
    c["output"]["plots"], c["ground_motion"]["duration"] = False, 1.5
    b = build_column(c)
    col = b.column
    col.settings = replace(col.settings, newton_test=newton_test)
    s, steps = b.state, 0
    for step in col.run(b.state, 6.0, b.dt, b.dt_after):
        s, steps = step.state, steps + 1
    return col, s, steps


@pytest.mark.parametrize("name", ["fine", "gravel"])
def test_whole_column_runs_agree(name):
    """Porosity, W and settlement of a shaken and reconsolidating column: each step's states agree
    to below the tolerance (absolute in n, relative to the velocity floor in W), so after N steps
    the runs differ by at most N tol where the steps do not amplify a difference (measured:
    1e-14 in n after 300 steps)."""
    (col, plain, steps), (_, new, _) = (_column_run(name, False), _column_run(name, True))
    tol, v = col.settings.tol, col.v
    assert new.t == plain.t and steps > 100
    assert np.abs(new.vertical.n - plain.vertical.n).max() < steps * tol
    assert np.abs(new.vertical.W - plain.vertical.W).max() < steps * tol * v.velocity_scale(plain.vertical)
    h = col.settlement(plain)
    assert h > 0.0
    # Σ h_e Δn_e/(1 − n_e) over the column: depth/(1 − n) times the porosity bound
    bound = steps * tol * v.mesh.lengths.sum() / (1.0 - plain.vertical.n.max())
    assert abs(col.settlement(new) - h) < bound


@pytest.mark.parametrize("name, t_end", [("fluidized-bed-step", 8.0), ("slis-step-change", 20.0)])
def test_whole_bed_runs_agree(name, t_end):
    """The same steps (the step-size control counts the iterate a prediction saved, so the
    rejected and regrown steps of slis-step-change are the plain test's) and states that agree
    to the accumulated per-step differences."""
    c = load_case(name)
    c["case"]["model"], c["time"]["end"] = "reduced_1d", t_end
    out = {}
    for newton_test in (False, True):
        b = build(c)
        out[newton_test] = [st for st in be.integrate(b.model, b.state, b.t_end, b.dt,
                                                      settings=replace(b.settings, newton_test=newton_test))]
    assert [st.t for st in out[True]] == [st.t for st in out[False]]
    assert [st.rejected for st in out[True]] == [st.rejected for st in out[False]]
    assert sum(st.rejected for st in out[False]) > 0 or name == "fluidized-bed-step"
    plain, new = out[False][-1], out[True][-1]
    tol = b.settings.tol
    assert np.abs(new.state.n - plain.state.n).max() < plain.n_steps * tol
    assert np.abs(new.state.W - plain.state.W).max() < plain.n_steps * tol * b.model.velocity_scale(plain.state)


def test_picard_models_keep_the_plain_test():
    """No ``newton_iterates`` (2D, single fluid) or the Picard linearisation: the plain test only."""
    c = load_case("fluidized-bed-step")
    c["mesh"]["element"] = "1VW/0P/0n"
    b = build(c)
    assert b.model.newton_iterates
    b.model.linearisation = "picard"
    assert not b.model.newton_iterates
    s = b.state
    its = [st.iterations for st in be.integrate(b.model, s, 0.2, b.dt, settings=b.settings)]
    b2 = build(c)
    b2.model.linearisation = "picard"
    its2 = [st.iterations for st in be.integrate(b2.model, b2.state, 0.2, b2.dt,
                                                 settings=replace(b2.settings, newton_test=False))]
    assert its == its2
    from twofluid.models.two_fluid_2d import TwoFluid2D

    assert not getattr(TwoFluid2D, "newton_iterates", False)


class _Toy:
    """Scalar 'model' for the test itself: states with t, n and V = W = v."""

    newton_iterates = True

    def velocity_scale(self, s):
        return 1.0


def _s(t, n, v=(0.0,), w=None):
    from types import SimpleNamespace
    v = np.array(v, float)
    return SimpleNamespace(t=t, n=np.atleast_1d(np.array(n, float)), V=v, W=v if w is None else np.array(w, float))


def test_first_iterate_needs_a_carried_contraction():
    """Without a measured C (a new run) the first iterate is accepted only by the plain test."""
    m, tol = _Toy(), 1e-7
    t = NewtonTest(m, _s(0.0, 0.5), tol)
    assert not t.converged(1, _s(1.0, 0.5 + 1e-6), _s(1.0, 0.5), 1e-6)


def test_carried_contraction_and_its_age():
    """C measured on one step lets the next steps accept their first iterate; after WINDOW steps
    without a new measurement the second iterate is taken again."""
    from twofluid.timestepping import newton

    m, tol = _Toy(), 1e-7
    old = _s(0.0, 0.5)
    t = NewtonTest(m, old, tol)
    assert not t.converged(1, _s(1.0, 0.51), old, 1e-2)
    assert not t.converged(2, _s(1.0, 0.5101), _s(1.0, 0.51), 1e-4)  # C = 1: 1e3·1·1e-8 > tol
    assert t.converged(3, _s(1.0, 0.5101), _s(1.0, 0.5101), 1e-11)
    state = _s(1.0, 0.5101)
    t.close(state)
    accepted = 0
    for step in range(1, 10):
        t = NewtonTest(m, state, tol)
        ok = t.converged(1, _s(step + 1.0, 0.6), state, 3e-7)  # 1e3·1·9e-14 < tol
        accepted += ok
        if not ok:
            assert step == newton.FRESH + 1  # step 0's samples are no longer fresh
            assert t.converged(2, _s(step + 1.0, 0.6), _s(step + 1.0, 0.6), 1e-14)
        state = _s(step + 1.0, 0.6 + step)
        t.close(state)
    assert accepted == 8
    # a step from a state this run did not accept starts afresh
    assert not NewtonTest(m, _s(0.0, 0.5), tol).converged(1, _s(1.0, 0.6), _s(0.0, 0.5), 3e-7)


def test_entries_must_contract():
    """A small norm-based prediction is not enough when one entry converges slowly."""
    m, tol = _Toy(), 1e-7
    x0, x1 = _s(1.0, [0.5, 0.9]), _s(1.0, [0.51, 0.9 + 1e-5])
    t = NewtonTest(m, _s(0.0, [0.5, 0.9]), tol)
    assert not t.converged(1, x1, x0, 1e-2)
    x2 = _s(1.0, [0.51 + 1e-6, 0.9 + 1e-5 + 5e-7])  # entry 1: θ = 0.05, remaining ≈ 2.6e-8 < tol
    assert t.converged(2, x2, x1, 1e-6) is True
    t = NewtonTest(m, _s(0.0, [0.5, 0.9]), tol)
    t.converged(1, x1, x0, 1e-2)
    x2 = _s(1.0, [0.51 + 1e-6, 0.9 + 1e-5 + 2e-6])  # θ = 0.2: remaining ≈ 5e-7 > tol
    assert not t.converged(2, x2, x1, 2e-6)


def test_upwind_side_change_blocks_a_prediction():
    m, tol = _Toy(), 1e-7
    old = _s(0.0, 0.5, v=[1e-3, 1e-3], w=[0.0, 0.0])
    t = NewtonTest(m, old, tol)
    t.C, t.fresh = 1e-3, True  # as if carried from a recent step
    prev = _s(1.0, 0.5, v=[1e-3, 1e-3], w=[0.0, 1e-3 - 1e-9])
    flip = _s(1.0, 0.5 + 1e-6, v=[1e-3, 1e-3], w=[0.0, 1e-3 + 1e-9])  # V − W changes sign at node 1
    assert not t.converged(1, flip, prev, 1e-6)
    t = NewtonTest(m, old, tol)
    t.C, t.fresh = 1e-3, True
    noise = _s(1.0, 0.5 + 1e-6, v=[1e-3, 1e-3], w=[0.0, 1e-3 + 1e-18])  # round-off: does not count
    assert t.converged(1, noise, _s(1.0, 0.5, v=[1e-3, 1e-3], w=[0.0, 1e-3 - 1e-18]), 1e-6)


@pytest.mark.skipif(__import__("twofluid.timestepping.newton", fromlist=["_kernels"])._kernels() is None,
                    reason="numba not installed")
def test_the_compiled_tests_decide_as_the_numpy_tests(monkeypatch):
    """NewtonTest.converged's side and entry tests in one compiled pass (newton._accept) give the
    NumPy tests' decision on iterates that contract, stall, flip the upwind side or do not move."""
    from types import SimpleNamespace as NS

    import twofluid.timestepping.newton as newton

    class M:
        newton_iterates = True

        def velocity_scale(self, s):
            return max(float(np.abs(s.V).max()), float(np.abs(s.W).max()), 1e-6)

    rng = np.random.default_rng(11)
    tol = 1e-7
    decisions = {True: 0, False: 0}
    for case in range(400):
        ne = 20
        V = rng.uniform(-1e-2, 1e-2, ne + 1)
        W = V + rng.uniform(-1e-3, 1e-3, ne + 1)
        n = rng.uniform(0.4, 0.9, ne)
        step = 10.0 ** rng.uniform(-10, -6)
        rate = rng.choice([0.01, 0.3, 0.6, 1.2])  # contracting fast, slowly, too slowly, not at all
        mk = lambda k: NS(t=1.0, V=V + step * rate ** k * rng.standard_normal(ne + 1) * (case % 7 != 0),
                          W=W + step * rate ** k * rng.standard_normal(ne + 1), n=n + step * rate ** k * rng.standard_normal(ne))
        before, prev, new = mk(0), mk(1), mk(2)
        if case % 11 == 0:  # V − W flips sign at a node, by more than the noise
            new.W = new.W.copy()
            new.W[3] = new.V[3] + np.sign(prev.V[3] - prev.W[3]) * 1e-3
        if case % 13 == 0:  # an entry that did not move before
            before.n = before.n.copy()
            before.n[5] = prev.n[5]
        out = []
        for compiled in (True, False):
            if not compiled:
                monkeypatch.setattr(newton, "_kernels", lambda: None)
            test = NewtonTest(M(), NS(t=0.0, V=V, W=W, n=n), tol)
            test.C, test.fresh = 1e-30, bool(case % 2)
            test.e, test.before = 1e-3, before  # a previous iterate (its change) and the one before it
            it = 1 if case % 17 == 0 else 2
            if it == 1:
                test.e = test.before = None
            e = max(float(np.abs(new.n - prev.n).max()), 2 * tol)  # above tol: not the plain test
            out.append(test.converged(it, new, prev, e))
            monkeypatch.undo()
        assert out[0] == out[1], case
        decisions[out[0]] += 1
    assert decisions[True] > 20 and decisions[False] > 20, decisions
