"""The full 1D model's whole iterate in one call (models/full_iterate.py) against the stepper's
calls one by one (assemble, solve, unpack, iterate_change through full_kernel).

Both make the same kernel and closure calls with the same arguments, so every step is the same bit
for bit: the states are compared with ``array_equal``, not a tolerance. A short run of each bundled
case of the full model and of the 1D peers (fluidized bed, settling, the Slis bed built with the
full model), and the run is checked to have gone through the one-call path (else the comparison
would compare the stepper's path with itself).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from kernel_paths import model_of

from twofluid.models import full_kernel
from twofluid.models.two_fluid_1d import TwoFluid1D
from twofluid.timestepping.backward_euler import integrate

PEERS = Path(__file__).resolve().parents[2] / "benchmarks" / "peers"
CASES = ("fluidized-bed-step", "settling-illite", "slis-step-change", str(PEERS / "openfoam-fluidized-bed.toml"))
requires_numba = pytest.mark.skipif(not full_kernel.available(), reason="numba not installed")


def _run(name, t_end, one_call):
    """The steps of ``t_end`` [s] of case ``name`` with the full model, through the one-call iterate
    (``one_call``) or the stepper's calls one by one; and how many iterates took the one call."""
    b = model_of(name, "two_fluid_1d")
    m = b.model
    calls = [0]
    whole = m.iterate

    def counted(*a):
        out = whole(*a)
        calls[0] += out is not None
        return out

    m.iterate = counted if one_call else (lambda *a: None)
    states = [step.state for step in integrate(m, b.state, t_end, b.dt, stops=(0.5 * t_end,), settings=b.settings)]
    return states, calls[0]


@requires_numba
@pytest.mark.parametrize("name", CASES)
def test_one_call_iterate_is_the_stepper_calls_bit_for_bit(name):
    t_end = 40 * model_of(name, "two_fluid_1d").dt
    ref, none = _run(name, t_end, False)
    fast, used = _run(name, t_end, True)
    assert none == 0 and used >= len(fast) > 10
    assert len(ref) == len(fast)
    for a, b in zip(ref, fast):
        assert a.t == b.t
        for f in ("V", "W", "P", "n", "n_bar"):
            assert np.array_equal(getattr(a, f), getattr(b, f)), (a.t, f)


def test_one_call_iterate_declines_where_the_calls_are_replaced():
    """A subclass or an instance that replaces one of the calls gets them one by one (None)."""
    b = model_of("fluidized-bed-step", "two_fluid_1d")
    m, s = b.model, b.state
    k = s.copy(t=s.t + b.dt)
    m.solve = lambda S, t: TwoFluid1D.solve(m, S, t)
    assert m.iterate(k, s, b.dt, k.t) is None
    del m.solve
    m.compiled = False
    assert m.iterate(k, s, b.dt, k.t) is None

    class Scaled(TwoFluid1D):
        def velocity_scale(self, st):
            return 2.0 * super().velocity_scale(st)

    m2 = Scaled(m.mesh, m.mat, m.clo, m.bottom, m.top)
    assert m2.iterate(k, s, b.dt, k.t) is None


@requires_numba
@pytest.mark.parametrize("name", (CASES[0], CASES[2], CASES[3]))
def test_the_one_call_shift_is_the_models_bit_for_bit(name):
    """The bed-force shift the one call makes at the start of a step is the model's own
    (``bed_force_shift`` through ``full_kernel.force_shift``), on a state with moving V, W and n."""
    from twofluid.models import full_iterate

    b = model_of(name, "two_fluid_1d")
    m = b.model
    states = [step.state for step in integrate(m, b.state, 10 * b.dt, b.dt, settings=b.settings)]
    s = states[-1]
    ne = s.n.size
    m._full_kernels()  # (the run's steps were made in one compiled call: the iterate's kernels not loaded)
    mine = full_iterate._shift(m, s, m.compiled_laws(), (np.empty(2 * ne), np.empty(2 * ne)))
    ref = m._force_shift_at(s)
    assert np.abs(ref).max() > 0.0  # (a shift that is not zero everywhere: a real comparison)
    assert np.array_equal(mine, ref)


def test_the_first_iterate_is_the_extrapolators_prediction():
    """TwoFluid1D._first_iterate writes Extrapolator.predict's fields (n clipped to (0, 1]) straight into
    the iterate: the same numbers as the prediction, at the table's step and after a shorter one."""
    b = model_of("fluidized-bed-step", "two_fluid_1d")
    m = b.model
    s = [step.state for step in integrate(m, b.state, 12 * b.dt, b.dt, settings=b.settings)][-1]
    assert m._extrap.order >= 3
    for h in (b.dt, 0.3 * b.dt):
        k = s.copy(t=s.t + h)
        m._first_iterate(k)
        V, W, n = m._extrap.predict(k.t)
        assert not np.array_equal(k.n, s.n)
        assert np.array_equal(k.V, V) and np.array_equal(k.W, W)
        assert np.array_equal(k.n, np.clip(n, 1e-6, 1.0))
