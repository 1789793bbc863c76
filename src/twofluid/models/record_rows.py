"""The base (or outcrop) record at the hysteretic column's shear sub-steps, read for many vertical
steps in one call.

Each vertical step of ``h`` [s] from ``t0`` runs ``m`` shear sub-steps of ``Δt`` and reads the record
at t0 + [1, ..., m] Δt (:meth:`LiquefactionColumn._shear_hysteretic
<twofluid.models.liquefaction_1d.LiquefactionColumn._shear_hysteretic>`). While the base shakes, the
steps follow each other with the same h, m and Δt, so :class:`RecordRows` reads the record for the
next :data:`RecordRows.ROWS` steps at once: the steps' starts as the run sums them (t0, t0 + h,
(t0 + h) + h, ...), each row their sub-steps' times as t0 + [1, ..., m] Δt, and the record at all of
them in one call of the column's ``base_acceleration_at`` (a function of each time alone, as
``np.interp`` of the record is). A step takes its row only where its start, m and Δt are the row's,
so its times and record values are those of the step's own call, bit for bit; any other step (a
mark, a halved sub-step, the flow phase's growing steps) reads a new block from its own start.

>>> import numpy as np
>>> rows = RecordRows(lambda t: 2.0 * t)
>>> t, a = rows.rows(0.0, 2, 0.005, 0.01)
>>> t.tolist(), a.tolist()
([0.005, 0.01], [0.01, 0.02])
>>> t, a = rows.rows(0.01, 2, 0.005, 0.01)  # (the next step: its row of the block)
>>> bool(np.all(t == 0.01 + np.arange(1.0, 3.0) * 0.005))
True
"""
from __future__ import annotations

import numpy as np

__all__ = ["RecordRows"]


class RecordRows:
    """The sub-steps' times and record values of the column's steps, :data:`ROWS` steps a block
    (module docstring); ``at``: times [s] -> the record there [m/s²], element by element."""

    ROWS = 64  # steps a block

    def __init__(self, at):
        self.at = at
        self._m, self._dt, self._k = 0, 0.0, 0
        self._starts, self._times, self._values = [], None, None
        self._lists = self._ends = None
        #: the times of the rows last returned as a list of floats, and the record at the last of them
        self.times, self.end = [], 0.0

    def rows(self, t0: float, m: int, dt: float, h: float) -> tuple[np.ndarray, np.ndarray]:
        """(t0 + [1, ..., m] ``dt``, the record there) of the step from ``t0`` [s] (``m`` sub-steps of
        ``dt`` [s]; ``h`` [s]: the step, which the next steps will likely take too): C-contiguous
        float64 rows, not to be written; :attr:`times` and :attr:`end` set to the times as a list and
        the last value as a float."""
        k = self._k
        if m == self._m and dt == self._dt and k < len(self._starts) and self._starts[k] == t0:
            self._k = k + 1
            self.times, self.end = self._lists[k], self._ends[k]
            return self._times[k], self._values[k]
        starts, t = [t0], t0
        for _ in range(self.ROWS - 1):  # (the run's sum of its steps)
            t = t + h
            starts.append(t)
        times = np.add.outer(np.array(starts), np.arange(1.0, m + 1.0) * dt)  # (t0 + [1, ..., m] dt per row)
        values = np.ascontiguousarray(self.at(times.ravel()), dtype=float).reshape(times.shape)
        self._m, self._dt, self._k = m, dt, 1
        self._starts, self._times, self._values = starts, times, values
        self._lists, self._ends = times.tolist(), values[:, -1].tolist()
        self.times, self.end = self._lists[0], self._ends[0]
        return times[0], values[0]
