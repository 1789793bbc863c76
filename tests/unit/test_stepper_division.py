"""The stepper halves the step after an iterate that divides by zero (timestepping.backward_euler).

Compiled kernels, and scalar Python run un-jitted, raise ZeroDivisionError where NumPy arrays
give non-finite values; a diverging Newton iterate must cost a halved step, not the run.
"""
from __future__ import annotations

from dataclasses import dataclass, replace

import pytest

from twofluid.timestepping.backward_euler import PicardSettings, StepFailure, integrate


@dataclass
class _State:
    t: float
    y: float

    def copy(self, t):
        return replace(self, t=t)


class _Decay:
    """y' = −y by backward Euler in one iterate, dividing by zero on steps longer than ``h_max``."""

    def __init__(self, h_max):
        self.h_max = h_max

    def iterate(self, k, old, dt, t_new):
        if dt > self.h_max:
            1.0 / 0.0  # what a diverging compiled iterate does
        new = _State(t_new, old.y / (1.0 + dt))
        return new, True, 0.0, 0.0

    def check(self, new):
        return None

    def end_step(self, old, new, dt):
        return new


def test_division_by_zero_halves_the_step():
    steps = list(integrate(_Decay(h_max=0.3), _State(0.0, 1.0), t_end=1.0, dt=1.0))
    assert steps[-1].t == pytest.approx(1.0)
    assert max(s.dt for s in steps) <= 0.3
    assert sum(s.rejected for s in steps) >= 2  # 1.0 -> 0.5 -> 0.25
    y = 1.0
    for s in steps:  # every accepted step is the exact backward Euler step of its length
        y /= 1.0 + s.dt
    assert steps[-1].state.y == pytest.approx(y, rel=1e-14)


def test_division_by_zero_at_every_step_is_a_step_failure():
    with pytest.raises(StepFailure, match="divided by zero"):
        list(integrate(_Decay(h_max=0.0), _State(0.0, 1.0), t_end=1.0, dt=0.5,
                       settings=PicardSettings(dt_min=1e-3)))
