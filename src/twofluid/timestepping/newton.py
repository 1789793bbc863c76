"""Acceptance of a Newton iterate on its predicted remaining change (models with ``newton_iterates``).

The stepper's plain test accepts iterate k when its change δ_k (the measure of
:func:`~twofluid.timestepping.backward_euler.relative_change`: absolute in porosity, relative to
the velocity scale in V and W) is below the tolerance: one more iterate than needed when the
iterates converge quadratically, since |δ_{k+1}| ≈ C |δ_k|² is then far below it already. A
model whose iterates are Newton iterates (class attribute or property ``newton_iterates``
true) may also have iterate k accepted when its *next* change is predicted to be below
``tol / SAFETY``, the prediction being conservative in three ways:

- **Quadratic** (Deuflhard 2004, ch. 2: the Kantorovich quantity ω|δ_k| estimated from the
  iterates): |δ_{k+1}| ≈ C |δ_k|² with C the largest ratio |δ_{j+1}|/|δ_j|² measured over the
  pairs of iterates of this step and of the last ``WINDOW`` (20) accepted steps of the same run
  (a run is recognised by the step starting from the state the model's last step accepted: V,
  W, n and t unchanged, whatever else was replaced). The first iterate is accepted on the
  carried C alone, and only while one of the last ``FRESH`` (5) steps measured it: a run whose
  steps all end at the first iterate takes the second iterate again every sixth step. C varies
  by two orders of magnitude from step to step at a moving bed surface, hence the maximum
  over many steps (with the last 5 only, a first iterate 0.1 tol from the plain test's state
  was accepted). ``SAFETY`` = 1000: in the max norm the measured C can underestimate the
  next change by orders of magnitude where entries converge at very different rates, at the
  surface of a fluidized bed, where 1/(1 − n) makes the curvature of the drag huge: in
  replays of the bundled 1D cases' and columns' iterates the next change reached
  25 × C|δ_1|² after a first iterate and 400 × C|δ_k|² after a later one that passed the
  entry test below (28 000 × before it).
- **Entry by entry** (k ≥ 2): every entry whose change is above 1 % of the tolerance must be
  contracting, θ_i = |δ_{k,i}|/|δ_{k−1,i}| < 1/2, with its remaining change under that linear
  rate, |δ_{k,i}| θ_i/(1 − θ_i) (Deuflhard's error estimate), below the tolerance: the nearly
  clear liquid above a bed converges linearly for a few iterates before Newton's quadratic
  rate sets in, which the max norm of δ hides behind the larger, quadratically converging
  entries of the bed.
- **Switches**: the 1D models decide the upwind side of the solids flux from the sign of
  V − W at the vertices of the iterate (of each of the first three iterates, then frozen);
  an iterate at which V − W changed sign at a node (by more than 1e-3 of the tolerance of the
  velocity scale: round-off in clear liquid, where the side does not matter, is far below) is
  not accepted on a prediction, since the next iterate would be linearised on the other side.
  Other non-smooth points an iterate may cross (the 1e-6 floor of 1 − n in the slip and the
  upwind ratio, the drag law's blend, Ergun's |slip| at zero slip) are not detected one by
  one: across them the convergence is at best linear, which the entry test sees from the
  second iterate on; for a first iterate the carried C and the margin are the guard (the
  audited runs include bed surfaces, where the 1 − n floor sits).

Everything depends only on the iterates of this run, so the same inputs give the same steps.
The accepted state differs from the one the plain test would accept (the next iterate or a
later one) by the predicted change: < tol/1000 by the estimate, < 0.016 tol measured on every
step of short runs of the bundled 1D cases and liquefaction columns
(``tests/unit/test_newton_acceptance.py``). The stepper's step-size control counts the iterate
a prediction saved, so the steps (and rejected attempts) are those of the plain test.
"""
from __future__ import annotations

import weakref
from collections import deque

import numpy as np

__all__ = ["NewtonTest", "SAFETY", "WINDOW", "FRESH"]

SAFETY = 1000.0  # the predicted next change must be below tol / SAFETY
WINDOW = 20  # accepted steps whose measured C enter the carried maximum
FRESH = 5  # the first iterate is accepted on a prediction only if one of these last steps measured C
_ENTRY_FLOOR = 1e-2  # entries changing by less than this fraction of tol are not tested one by one
_SIDE_NOISE = 1e-3  # |V − W| below this fraction of tol × velocity scale: a sign change does not count

class _Runs(weakref.WeakKeyDictionary):
    """model -> :class:`_Run`, counting its changes (``changes``): :func:`kernel_samples` looks a model up
    again only where the table changed since it last did."""

    changes = 0

    def __setitem__(self, key, value):
        self.changes += 1
        super().__setitem__(key, value)

    def __delitem__(self, key):
        self.changes += 1
        super().__delitem__(key)

    def pop(self, key, *args):
        self.changes += 1
        return super().pop(key, *args)

    def popitem(self):
        self.changes += 1
        return super().popitem()

    def setdefault(self, key, default=None):
        self.changes += 1
        return super().setdefault(key, default)

    def update(self, dict=None, /, **kwargs):
        self.changes += 1
        super().update(dict, **kwargs)


_RUNS: "_Runs" = _Runs()  # model -> _Run


class _Run:
    """What the test carries from step to step of one run of one model."""

    def __init__(self):
        self.last = None  # the state the last accepted step returned
        self.steps = 0  # accepted steps
        self.samples = deque()  # (index of the step, largest |δ_{j+1}|/|δ_j|² of its iterates), oldest first

    def continues(self, old) -> bool:
        s = self.last
        return s is not None and (s is old or (s.t == old.t and _same(s.n, old.n) and _same(s.W, old.W)
                                               and _same(s.V, old.V)))


def kernel_samples(model) -> list:
    """The test's samples of ``model``'s run as a compiled step keeps them: [indices (int64), constants,
    [count, accepted steps] (int64), the last accepted state, the record they were taken from] (arrays
    with room for this step's sample at least), taken from the stepper's record where its Python path made the last
    step, kept on the model (``_kernel_samples``) while the compiled calls make the steps."""
    d = model.__dict__
    run = d.get("_kernel_samples")
    seen = _RUNS.changes
    mark = d.get("_kernel_samples_seen")  # (the table's count and this model's id when it was last looked up)
    if run is not None and mark is not None and mark[0] == seen and mark[1] == id(model):  # (the same record)
        rec = run[4]
    else:
        rec = _RUNS.get(model)
        model._kernel_samples_seen = (seen, id(model))  # (a copy of the model looks itself up)
    if run is None or rec is not run[4]:  # (the stepper made steps of this model since)
        samples = list(rec.samples) if rec is not None else []
        cap = len(samples) + WINDOW + 8
        idx, c = np.zeros(cap, dtype=np.int64), np.zeros(cap)
        for j, (i, x) in enumerate(samples):
            idx[j], c[j] = i, x
        meta = np.array([len(samples), rec.steps if rec is not None else 0], dtype=np.int64)
        run = model._kernel_samples = [idx, c, meta, rec.last if rec is not None else None, rec]
    idx, c = run[0], run[1]
    if idx.size < run[2].item(0) + 2:  # room for this step's sample
        idx.resize(idx.size + 64, refcheck=False)
        c.resize(c.size + 64, refcheck=False)
    return run


def release_kernel_samples(model) -> None:
    """Hand :func:`kernel_samples` of ``model`` back to the stepper's record (before its Python path runs)."""
    run = model.__dict__.get("_kernel_samples")
    if run is not None:
        idx, c, meta, last, _ = run
        rec = _Run()
        rec.samples = deque((int(idx[j]), float(c[j])) for j in range(int(meta[0])))
        rec.steps, rec.last = int(meta[1]), last
        _RUNS[model] = rec
        model._kernel_samples = None


def _same(a: np.ndarray, b: np.ndarray) -> bool:
    """np.array_equal of two arrays (a third of its time: this runs three times a step)."""
    return a is b or (a.shape == b.shape and bool((a == b).all()))


def _accept(nV, nW, nn, pV, pW, pn, bV, bW, bn, scale_new, scale_prev, tol, side_noise, entry_floor,
            first, fresh):
    """:meth:`NewtonTest.converged` after its quadratic test, compiled: 0 where V − W changed sign
    at a node by more than the noise (``_side_changed``), else for the first iterate ``fresh``, else
    the entry-by-entry contraction test on the changes new − prev against prev − before."""
    noise = side_noise * tol * scale_new
    for i in range(nV.size):
        a = nV[i] - nW[i]
        b = pV[i] - pW[i]
        if (a >= 0.0) != (b >= 0.0) and abs(a) > noise:
            return 0
    if first:
        return 1 if fresh else 0
    floor = entry_floor * tol
    rest_max = 0.0
    big = False
    m = nn.size
    for j in range(m + 2 * nV.size):  # the entries of _changes: n, then V, then W
        if j < m:
            d = abs(nn[j] - pn[j])
            dp = abs(pn[j] - bn[j])
        elif j < m + nV.size:
            i = j - m
            d = abs(nV[i] - pV[i]) / scale_new
            dp = abs(pV[i] - bV[i]) / scale_prev
        else:
            i = j - m - nV.size
            d = abs(nW[i] - pW[i]) / scale_new
            dp = abs(pW[i] - bW[i]) / scale_prev
        if not d >= floor:  # (NaN too, as NumPy's comparison leaves it out)
            continue
        big = True
        theta = d / dp if dp != 0.0 else np.inf
        if not theta < 0.5:  # (NaN or inf too)
            return 0
        r = d * theta / (1.0 - theta)
        if r > rest_max:
            rest_max = r
    if not big:
        return 1
    return 1 if rest_max <= tol else 0


_KERNEL = None
_TRIED = False


def _kernels():
    """:func:`_accept` compiled (:mod:`twofluid.compiled`)."""
    global _KERNEL, _TRIED
    if not _TRIED:
        _TRIED = True
        from ..compiled import kernel

        A1 = "f8[:]"
        _KERNEL = kernel("newton_accept", _accept,
                         f"i8({','.join([A1] * 9)},f8,f8,f8,f8,f8,b1,b1)")
    return _KERNEL


def _changes(model, new, prev) -> np.ndarray:
    """Per-entry changes in the stepper's measure: |Δn| and |ΔV|, |ΔW| over the velocity scale."""
    scale = model.velocity_scale(new)
    return np.concatenate((np.abs(new.n - prev.n), np.abs(new.V - prev.V) / scale,
                           np.abs(new.W - prev.W) / scale))


class NewtonTest:
    """The acceptance test of one step's Newton iterates (module docstring).

    >>> from types import SimpleNamespace as NS
    >>> class M:  # a model whose iterates are Newton's, V = W = 0
    ...     newton_iterates = True
    ...     def velocity_scale(self, s): return 1.0
    >>> z = np.zeros(1)
    >>> state = lambda t, n: NS(t=t, n=np.array([n]), V=z, W=z)
    >>> m, old = M(), state(0.0, 0.5)
    >>> test = NewtonTest(m, old, tol=1e-7)
    >>> [test.converged(it, state(1.0, n), state(1.0, p), abs(n - p))
    ...  for it, (p, n) in enumerate([(0.5, 0.6), (0.6, 0.601), (0.601, 0.601001)], 1)]
    [False, False, True]
    """

    def __init__(self, model, old, tol: float):
        run = _RUNS.get(model)
        if run is None or not run.continues(old):
            run = _RUNS[model] = _Run()
        self.model, self.tol, self.run = model, tol, run
        samples = run.samples
        self.C = max(c for _, c in samples) if samples else None  # carried C (``close`` keeps WINDOW steps)
        self.fresh = bool(samples) and samples[-1][0] >= run.steps - FRESH
        self.step_C = None  # the largest C of this step's pairs of iterates
        self.e = None  # change of the last iterate
        self.before = None  # the iterate the last call's ``prev`` came from (for its per-entry changes)

    def converged(self, it: int, new, prev, e: float) -> bool:
        """Whether iterate ``it`` (``new``, from ``prev``, change ``e``) is the step: by the plain
        test (e < tol) or on the predicted change of the next iterate."""
        tol, e_prev, before = self.tol, self.e, self.before
        self.e, self.before = e, prev
        if e_prev:  # ≥ tol (or the step would have ended), unless tol = 0 and an iterate did not move
            c = e / (e_prev * e_prev)
            self.step_C = c if self.step_C is None else max(self.step_C, c)
        if e < tol:
            return True
        C = max((c for c in (self.C, self.step_C) if c is not None), default=None)
        if C is None or SAFETY * C * e * e > tol:
            return False
        ker = _kernels() if type(new.V) is np.ndarray and new.V.ndim == 1 else None
        if ker is not None:  # the two tests below in one compiled pass (the same decisions)
            model = self.model
            prev_old = before if before is not None and it > 1 else prev  # (not read for it = 1)
            return bool(ker(new.V, new.W, new.n, prev.V, prev.W, prev.n, prev_old.V, prev_old.W, prev_old.n,
                            float(model.velocity_scale(new)), float(model.velocity_scale(prev)), float(tol),
                            _SIDE_NOISE, _ENTRY_FLOOR, it == 1, self.fresh))
        if self._side_changed(new, prev):
            return False
        if it == 1:
            return self.fresh
        d = _changes(self.model, new, prev)
        big = d >= _ENTRY_FLOOR * tol
        if not big.any():
            return True
        d_prev = _changes(self.model, prev, before)[big]
        d = d[big]
        with np.errstate(divide="ignore", invalid="ignore"):
            theta = d / d_prev  # an entry that did not change before: inf, not accepted
        return bool(theta.max() < 0.5 and (d * theta / (1.0 - theta)).max() <= tol)

    def _side_changed(self, new, prev) -> bool:
        a, b = new.V - new.W, prev.V - prev.W
        flipped = (a >= 0.0) != (b >= 0.0)
        if not flipped.any():
            return False
        noise = _SIDE_NOISE * self.tol * self.model.velocity_scale(new)
        return bool((np.abs(a[flipped]) > noise).any())

    def close(self, accepted) -> None:
        """End of the step: ``accepted`` is the state the step returned, or None (rejected)."""
        run = self.run
        if self.step_C is not None:
            run.samples.append((run.steps, self.step_C))
        if accepted is not None:
            run.steps += 1
            run.last = accepted
        first, samples = run.steps - WINDOW, run.samples
        while samples and samples[0][0] < first:
            samples.popleft()
