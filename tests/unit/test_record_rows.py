"""What the liquefaction run reads once for many steps must be what each step would read alone:
the record at the hysteretic sub-steps' times (models.record_rows.RecordRows) and the output marks'
test (runners.liquefaction._Marks against _at_mark)."""
from __future__ import annotations

import numpy as np

from twofluid.io import ground_motion as gm
from twofluid.models.record_rows import RecordRows
from twofluid.runners.liquefaction import _at_mark, _Marks


def _record():
    rng = np.random.default_rng(7)
    t = np.cumsum(rng.uniform(0.004, 0.006, 800))  # an uneven record
    return gm.GroundMotion(t, rng.normal(0.0, 1.0, t.size))


def test_the_rows_are_each_steps_own_times_and_record_values():
    """Steps of 0.02 s with 4 sub-steps, a mark's short step, a halved sub-step and steps past the
    record's end: every step's times and values equal t0 + [1, ..., m] dt and np.interp of them, bit
    for bit, and the block is read again only where a step leaves it."""
    motion = _record()
    at = gm.interpolator(motion)
    rows = RecordRows(at)
    reads = [0]

    def counted(x):
        reads[0] += 1
        return at(x)

    rows.at = counted
    t, h, taken = 0.0, 0.02, 0
    for k in range(300):
        step = 0.013 if k == 100 else h  # (a step that lands on a mark)
        m = 8 if k == 200 else 4  # (a step whose sub-steps were halved)
        t_new = t + step
        dt = (t_new - t) / m
        times, values = rows.rows(t, m, dt, h)
        want = t + np.arange(1.0, m + 1.0) * dt
        assert times.tolist() == want.tolist()
        assert values.tolist() == gm.value_at(motion, want).tolist()
        assert times.flags.c_contiguous and values.flags.c_contiguous
        assert rows.times == times.tolist() and rows.end == float(values[-1])  # (the row as lists too)
        taken += 1
        t = t_new
    assert t > motion.duration  # (past the record's end: 0)
    assert reads[0] < taken // 10


def test_the_marks_test_is_at_mark_on_growing_times():
    rng = np.random.default_rng(3)
    marks = sorted({0.5, 1.0, 1.0 + 5e-10, 2.0, 30.0, 30.0 + 2e-8, 100.0})
    t, times = 0.0, []
    for _ in range(4000):
        t += float(rng.choice([0.02, 1e-10, 3e-9, 0.5]))
        times.append(t)
    times += [m + d for m in marks for d in (-1.5e-9, -9e-10, 0.0, 9e-10, 1.5e-9)]
    times.sort()
    near = _Marks(marks)
    hits = 0
    for t in times:
        got = t > near.low and near.at(t)
        assert got == _at_mark(marks, t), t
        hits += got
    assert hits > 10
