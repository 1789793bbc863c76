"""First iterate of a time step extrapolated from the converged steps before it.

Both 1D models start the Newton–Picard loop of a step from this prediction: on a
smooth flow it is accurate to the Picard tolerance and the step converges at the
first iterate (docs/benchmarks.md). It only steers the iterates, not the fixed point.
"""
from __future__ import annotations

import numpy as np

__all__ = ["Extrapolator"]

_HISTORY = 6  # backward differences kept (orders up to 4)


def _predict_entries(D, order, pred):
    """:meth:`Extrapolator.predict` of one field, entry by entry (a kernel): ``pred`` =
    Σ_{j≤p} ∇ʲx with, per entry, the order p whose next term |∇^{p+1}x| is smallest (a NaN
    next term makes the orders above it lose)."""
    for i in range(D.shape[1]):
        acc = D[0, i] + D[1, i]
        p = acc
        err = abs(D[2, i])
        for j in range(2, order - 1):
            acc = acc + D[j, i]
            e = abs(D[j + 1, i])
            if e < err:
                p = acc
            err = e if (e < err or e != e) else err  # np.minimum: the smaller, NaN if either is
        pred[i] = p


def _push_entries(x, Do, Dn):
    """The backward differences ``Dn`` of the new state ``x`` from the old ones ``Do``."""
    m = Dn.shape[0]
    for i in range(x.size):
        Dn[0, i] = x[i]
        for j in range(1, m):
            Dn[j, i] = Dn[j - 1, i] - Do[j - 1, i]


_KERNELS = None


def _kernels():
    """(predict, push) compiled (:mod:`twofluid.compiled`)."""
    global _KERNELS
    if _KERNELS is None:
        from ..compiled import group

        # C-contiguous arrays (checked on each call: check_layouts, twofluid.compiled._unbox_checked), as
        # the models' compiled steps call these loops (helpers: compiled once with them,
        # twofluid.compiled._stub)
        ker = group("extrapolation", {"predict": (_predict_entries, "void(f8[:,::1], i8, f8[::1])"),
                                      "push": (_push_entries, "void(f8[::1], f8[:,::1], f8[:,::1])")},
                    helpers=(_predict_entries, _push_entries), check_layouts=True)
        _KERNELS = (ker["predict"], ker["push"])
    return _KERNELS


class Extrapolator:
    """First iterate of a step from the converged steps before it, for the fields W and n.

    Keeps the backward differences ∇ʲx (j < ``_HISTORY``) of the last converged states
    at equal steps h. The extrapolation of order p to the next step is Σ_{j≤p} ∇ʲx and
    its error is about the next term ∇^{p+1}x, so each entry takes the order p ≤ 4
    whose next term is smallest (locally adaptive: high order where the field is
    smooth in time, low order where a front crosses an element). After a change of
    step (or a restart) the table starts again from the last two states, extrapolated
    linearly (at most twice their step ahead) until it has three.

    >>> e = Extrapolator()
    >>> for t in range(6):
    ...     e.push(float(t), [np.array([t ** 3 + 1.0])], None)
    >>> float(e.predict(6.0)[0][0]), e.order  # a cubic in time is extrapolated exactly
    (217.0, 6)
    """

    def __init__(self):
        self.t = self.h = None
        self.D = None  # per field: (order, size) backward differences, ∇⁰x = x first
        self.order = 0  # number of rows (states) in the table
        self.state = None  # the state the last row belongs to (identity check)

    def push(self, t: float, fields: list, state, t_old: float | None = None, old_fields: list | None = None):
        """Add the converged ``fields`` at ``t``; ``t_old``/``old_fields`` restart the table from the step before."""
        if old_fields is not None:
            self.D = [np.stack([x, x - xo]) for x, xo in zip(fields, old_fields)]
            self.order, self.h = 2, t - t_old
        elif self.D is None:
            self.D = [x[None, :].copy() for x in fields]
            self.order, self.h = 1, None
        elif self.h is None or not abs((t - self.t) - self.h) <= 1e-9 * self.h:  # a new step size
            self.D = [np.stack([x, x - Do[0]]) for x, Do in zip(fields, self.D)]
            self.order, self.h = 2, t - self.t
        else:
            m = min(self.order + 1, _HISTORY)
            D = []
            push = _kernels()[1]
            for x, Do in zip(fields, self.D):  # ∇ʲx_new = ∇ʲ⁻¹x_new − ∇ʲ⁻¹x_old
                Dn = np.empty((m, x.size))
                push(np.ascontiguousarray(x, dtype=float), Do, Dn)
                D.append(Dn)
            self.D, self.order = D, m
        self.t, self.state = t, state

    def predict(self, t: float, out: tuple | None = None) -> list | None:
        """The extrapolated fields at ``t`` (None without at least two states); ``out``: an array per
        field to write them into (then returned), else new arrays."""
        if self.order < 2 or not t > self.t:
            return None
        h_new = t - self.t
        if out is None:
            out = [np.empty(D.shape[1]) for D in self.D]
        if self.order >= 3 and abs(h_new - self.h) <= 1e-9 * self.h:
            predict = _kernels()[0]
            for D, pred in zip(self.D, out):
                predict(D, self.order, pred)
            return list(out)
        f = min(h_new / self.h, 2.0)
        for D, pred in zip(self.D, out):
            np.add(D[0], f * D[1], out=pred)
        return list(out)
