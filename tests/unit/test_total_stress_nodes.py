"""The Newmark block's input on a slope: every node's absolute acceleration of the total-stress
companion (``runners.liquefaction_slope.total_stress_node_motion``), sampled every record interval,
from one call of the hysteretic sub-steps over the whole shear wave instead of the column stepped
one record interval at a time.

Both take the same sub-steps (steps of 0.01 s, each 2 sub-steps of 0.005 s, on the bundled sloping
site) with the same law; only the sub-steps' times are summed differently (from the start of the
wave instead of from each step's) and the one call stops Newton's iterations by their rate of
contraction as well (``one_call``'s ``quick``), so they agree to far below Newton's tolerance:
asserted 1e-9 s on the times and 1e-9 of the peak on the accelerations of a 3 s wave (measured
1.3e-12 s and 2.3e-9 of the peak on the bundled sloping site's whole 30.4 s wave, 1.3e-10 without
the quick iterations). Sampling a neighbouring node or one sub-step early differs by orders of
magnitude more, which the tests check too, so that they can fail.
"""
from __future__ import annotations

import numpy as np
import pytest

from twofluid.models import hysteretic_kernel as hk
from twofluid.runners import liquefaction as rl
from twofluid.runners import liquefaction_slope as lsr
from twofluid.runners import liquefaction_total_stress as ts
from slope_cases import sloping_case


def _short(duration=2.0):
    c = sloping_case(ground_motion__duration=duration)
    c["shear_wave"]["free_vibration"] = 1.0
    return c


def _close(t1, a1, t0, a0):
    return t1.shape == t0.shape and np.max(np.abs(t1 - t0)) <= 1e-9 and \
        np.max(np.abs(a1 - a0)) <= 1e-9 * np.max(np.abs(a0))


def test_one_call_repeats_the_column_stepped_record_interval_by_interval():
    c = _short()
    t1, a1 = lsr.total_stress_node_motion(c, 1)
    t0, a0 = lsr.total_stress_node_motion(c, 1, one_call=False)
    assert t0.size > 300 and a0.shape == (t0.size, 33)  # 0.01 s samples over 3 s; 32 elements
    assert np.abs(a0).max() > 0.5  # it shakes [m/s²]
    assert _close(t1, a1, t0, a0)
    # what a wrong sampling gives, far outside the tolerance: a neighbouring node, one sub-step early
    assert not _close(t1, a1[:, [1] + list(range(a1.shape[1] - 1))], t0, a0)
    b = rl.total_stress_column(c, 1)
    total, _ = ts.plan(b.column, b.state, 0.01)
    times, nodes = ts.one_call(b.column, b.state, total, True)
    assert total == 2 * (t0.size - 1)
    early = np.concatenate([np.zeros((1, nodes.shape[1])), nodes[0::2]])
    assert not _close(t1, early, t0, a0)
    assert np.max(np.abs(early - a0)) > 1e3 * 1e-9 * np.max(np.abs(a0))


def test_the_runs_companion_call_serves_its_own_polarity_bit_for_bit():
    """The run's companion (steps of 0.02 s in 4 sub-steps) is the same call as the node motion's
    (0.01 s in 2) for the case's polarity: its every-node output serves it, and its surface column
    is, bit for bit, what the kernel writes when asked for the surface only."""
    c = _short()
    surf = rl.total_stress_surface(c)
    whole = surf.whole
    assert whole is not None and whole.polarity == 1
    np.testing.assert_array_equal(surf[1], whole.nodes[:, -1])
    b = rl.total_stress_column(c)
    total, _ = ts.plan(b.column, b.state, b.dt)
    times, only = ts.one_call(b.column, b.state, total, False)
    np.testing.assert_array_equal(times, surf[0])
    np.testing.assert_array_equal(only, surf[1])
    own = lsr.total_stress_node_motion(c, 1)
    served = lsr.total_stress_node_motion(c, 1, companion=whole)
    for x, y in zip(own, served):
        np.testing.assert_array_equal(x, y)


def test_a_companion_of_another_polarity_or_other_substeps_is_not_used():
    c = _short()
    own = lsr.total_stress_node_motion(c, -1)
    n = 2 * (own[0].size - 1)
    junk = np.full((n, own[1].shape[1]), 1e3)
    for fake in (ts.WholeWave(np.arange(1.0, n + 1.0), junk, 1),  # the other polarity
                 ts.WholeWave(np.arange(1.0, n + 3.0), np.full((n + 2, junk.shape[1]), 1e3), -1)):
        got = lsr.total_stress_node_motion(c, -1, companion=fake)
        np.testing.assert_array_equal(got[1], own[1])
    got = lsr.total_stress_node_motion(c, -1, companion=ts.WholeWave(np.arange(1.0, n + 1.0), junk, -1))
    assert np.all(got[1][1:] == 1e3)  # (and one that matches is used)


def test_a_wave_that_is_not_whole_record_intervals_runs_step_by_step():
    """A free vibration of 1.005 s after the shaking with record intervals of 0.01 s: the wave's
    last step is cut short (other sub-steps), so the node motion is stepped, as before."""
    c = _short()
    c["shear_wave"]["free_vibration"] = 1.005
    b = rl.total_stress_column(c, 1)
    assert ts.plan(b.column, b.state, 0.01) is None
    t1, a1 = lsr.total_stress_node_motion(c, 1)
    t0, a0 = lsr.total_stress_node_motion(c, 1, one_call=False)
    np.testing.assert_array_equal(t1, t0)
    np.testing.assert_array_equal(a1, a0)


def test_every_node_compiled_and_plain_alike():
    """The every-node call compiled and as plain Python (``TWOFLUID_DISABLE_JIT``): 1e-12."""
    if hk.compiled() is None:
        pytest.skip("numba not available: only the plain path runs")
    c = _short(0.5)
    b = rl.total_stress_column(c, 1)
    total, _ = ts.plan(b.column, b.state, 0.01)
    t, a = ts.one_call(b.column, b.state, total, True)
    b = rl.total_stress_column(c, 1)
    tp, ap = ts.one_call(b.column, b.state, total, True, kernel=hk._substeps)
    assert a.shape == (total, 33) and np.abs(a).max() > 0.1
    np.testing.assert_allclose(tp, t, rtol=0, atol=1e-12)
    np.testing.assert_allclose(ap, a, rtol=0, atol=1e-12 * np.max(np.abs(a)))
