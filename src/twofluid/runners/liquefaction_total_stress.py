"""The whole shear wave of a total-stress companion column in one call of the hysteretic sub-steps
(:func:`twofluid.runners.liquefaction.total_stress_surface`, and the Newmark block's input,
:func:`twofluid.runners.liquefaction_slope.total_stress_node_motion`).

Nothing moves vertically in a total-stress column (``LiquefactionColumn.shear_only``), so a run's
steps only cut the shear wave into pieces: steps of Δt to the end of the shaking and on to the end
of the shear wave, each cut into m = ⌈Δt/shear_step⌉ sub-steps of Δt/m. Where both stretches are
whole numbers of steps, those are N·m equal sub-steps (:func:`plan`), which one call over the whole
wave takes as well: the same sub-steps, their times summed from the start instead of from each
step's, and Newton's iterations stopped by their rate of contraction as well (:func:`one_call`'s
``quick``: about a quarter fewer evaluations of the law where they take three updates, the last
only confirming the second), so the same accelerations to far below Newton's tolerance. Two step sizes whose plans give the same count are
the same call (the sloping site: steps of 0.02 s in 4 sub-steps and of 0.01 s in 2).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["plan", "WholeWave", "one_call"]


def plan(col, s0, dt: float) -> tuple[int, float] | None:
    """(N·m, Δt/m): the sub-steps a run of ``col`` from the state ``s0`` in steps of ``dt`` [s] takes
    over its whole shear wave, and their size [s]; None where the steps do not cut the shaking and
    the rest of the wave into whole numbers of steps, or one step of the whole wave at Δt/m would not
    take N·m sub-steps (``LiquefactionColumn``'s own count, ⌈span/sub-step⌉)."""
    if not (dt > 0.0 and s0.t == 0.0 and col.shear_end > 0.0):
        return None
    for stretch in (col.shaking_end, col.shear_end - col.shaking_end):
        k = round(stretch / dt)
        if abs(k * dt - stretch) > 1e-9 * max(stretch, dt):
            return None
    per_step = max(1, math.ceil(dt / col.shear_step - 1e-9))
    sub = dt / per_step
    total = round(col.shear_end / dt) * per_step
    if max(1, math.ceil(col.shear_end / sub - 1e-9)) != total:
        return None
    return total, sub


@dataclass(frozen=True)
class WholeWave:
    """Every node's absolute acceleration [m/s²] (record while it shakes plus the node's relative
    acceleration; bottom first) after each of the equal sub-steps of one call, at ``times`` [s]."""

    times: np.ndarray  # (sub-steps,)
    nodes: np.ndarray  # (sub-steps, nodes)
    polarity: int  # the record's sign the column ran with

    def rows(self, steps: int) -> tuple[np.ndarray, np.ndarray]:
        """(t, a): sampled after each of ``steps`` equal steps (each a whole number of the
        sub-steps), from t = 0 (at rest: zeros)."""
        every = self.times.size // steps
        if every * steps != self.times.size:
            raise ValueError(f"{steps} steps do not cut {self.times.size} sub-steps evenly")
        a = self.nodes[every - 1::every]
        return (np.concatenate([[0.0], self.times[every - 1::every]]),
                np.concatenate([np.zeros((1, a.shape[1])), a]))


def one_call(col, s0, total: int, nodes: bool, kernel=None, quick: bool = True):
    """(times [s], absolute acceleration [m/s²]) after each of ``total`` equal sub-steps of the whole
    shear wave of the hysteretic total-stress column ``col`` from ``s0`` (t = 0): of the surface
    node (``nodes`` False: shape (total,)) or of every node, bottom first (shape (total, nodes)); None
    where a sub-step would be halved (Newton did not converge) or a value is not finite.

    The arguments :meth:`LiquefactionColumn.step` gives the sub-steps for one step over the whole
    wave; ``kernel``: :func:`twofluid.models.hysteretic_kernel.runner`'s by default. With ``quick`` (the
    default) Newton's iterations of each sub-step stop as well by their rate of contraction (the
    kernel's ``quick``: the same solution to far below Newton's tolerance, about a quarter fewer
    evaluations of the law); then the accelerations agree with the column's own steps to that
    tolerance, not to round-off."""
    from ..models import hysteretic_kernel as hk

    span = col.shear_end - s0.t
    h = span / total
    col._wave_properties(s0)
    w, wave = s0.wave, col.wave
    ne = wave.h.size
    A, p_ref = col._skeleton_arrays()
    times = s0.t + np.arange(1.0, total + 1.0) * h
    u, vel, acc = w.u.copy(), w.v.copy(), w.a.copy()
    st = np.array(s0.shear, dtype=float)
    nb = np.array(s0.vertical.n_bar, dtype=float)
    out, tau = np.empty(total * (ne + 1) if nodes else total), np.empty(ne)
    run = hk.runner() if kernel is None else kernel
    mid, tail = col.hysteretic_arguments()
    code = int(run(u, vel, acc, st, col.hysteretic, nb, np.ascontiguousarray(s0.vertical.n, dtype=float),
                   np.ascontiguousarray(col._ndot * span), A, p_ref, *mid, s0.t, h,
                   col._record_at(times), col.shaking_end, out, tau, *tail[:-1], 1 if quick else 0))
    if code != 0:
        return None
    return times, (out.reshape(total, ne + 1) if nodes else out)
