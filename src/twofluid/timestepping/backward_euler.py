"""Backward Euler with Picard iterations, as a generator of converged steps.

``integrate`` yields a :class:`Step` after every converged time step; output,
probes, progress bars and plots consume the stream. The step size shrinks
(halves) when the Picard loop does not converge or the model rejects the state
(e.g. porosity leaving (0, 1]), or an iterate is non-finite or divides by zero (a diverging
Newton iterate in scalar code, compiled or plain, raises ZeroDivisionError), and grows back (×1.5) after easy steps; it lands
exactly on the requested ``stops`` (output times). A step that cannot be made
even at ``dt_min`` raises :class:`StepFailure`, which says where and why.

The model must provide ``assemble(k, old, dt, t) -> BlockSystem``,
``dirichlet(t)``, ``pack``, ``unpack``, ``check``, ``velocity_scale`` and
``end_step`` (see :class:`twofluid.models.two_fluid_1d.TwoFluid1D`); optional
hooks: ``begin_iteration(it, k)`` before each Picard iteration and
``solve(system, t)`` to replace the default sparse direct solve; ``compiled_step(old, dt, settings)``,
which :func:`integrate` asks first for each step: (the state, iterations, whether a prediction accepted
it) as :func:`_step` would give them, or None (then :func:`_step` makes it).

Convergence: an iterate is the step when its change (:func:`relative_change`: absolute in
porosity, relative to ``velocity_scale`` in V and W) is below ``PicardSettings.tol``. A model
whose iterates are Newton iterates says so with a true ``newton_iterates`` (class attribute or
property); then an iterate is also the step when the change of the next one is predicted to be
below tol/1000 (:class:`~twofluid.timestepping.newton.NewtonTest`: quadratic contraction
carried from the last steps of the same run, an entry-by-entry contraction test, no change of
the upwind side), which saves the iterate that only confirmed convergence. Other models, and
``PicardSettings(newton_test=False)``, keep the plain test.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Iterable, Iterator

import numpy as np

from .newton import NewtonTest

__all__ = ["Step", "StepFailure", "PicardSettings", "picard_step", "relative_change", "integrate"]


@dataclass(frozen=True)
class PicardSettings:
    tol: float = 1e-7  # relative change of velocities, absolute change of porosity
    max_iter: int = 40
    dt_min: float = 1e-7  # [s]
    grow: float = 1.5
    easy_iters: int = 4  # grow Δt again after a step needing at most this many iterations
    newton_test: bool = True  # models with ``newton_iterates``: accept on the predicted next change too


@dataclass(frozen=True, init=False)
class Step:
    """A converged step (frozen). Its ``__init__`` writes the fields into the instance's dict, as the
    frozen dataclass's generated one does through ``object.__setattr__`` at three times the cost (one a step).

    >>> s = Step(0.5, 0.1, 2, None, 5)
    >>> s, s == Step(0.5, 0.1, 2, None, 5, 0)
    (Step(t=0.5, dt=0.1, iterations=2, state=None, n_steps=5, rejected=0), True)
    """

    t: float
    dt: float
    iterations: int
    state: object
    n_steps: int
    rejected: int = 0  # attempts at this step rejected (Picard not converged, state not admissible)

    def __init__(self, t: float, dt: float, iterations: int, state: object, n_steps: int, rejected: int = 0):
        d = self.__dict__
        d["t"] = t
        d["dt"] = dt
        d["iterations"] = iterations
        d["state"] = state
        d["n_steps"] = n_steps
        d["rejected"] = rejected


class StepFailure(RuntimeError):
    def __init__(self, t: float, dt: float, reason: str, state=None):
        super().__init__(f"step from t = {t:.6g} s failed at dt = {dt:.3g} s: {reason}")
        self.t, self.dt, self.reason, self.state = t, dt, reason, state


def _solve(model, S, t_new):
    import scipy.sparse.linalg as spla  # on use: models with their own ``solve`` never need it

    A = S.matrix().tocsr()
    idx, val = model.dirichlet(t_new)
    a = np.zeros(S.size)
    a[idx] = val
    free = np.setdiff1d(np.arange(S.size), idx)
    rhs = S.rhs[free] - A[free][:, idx] @ val
    Aff = A[free][:, free].tocsc()
    a[free] = spla.spsolve(Aff, rhs)
    return a


def relative_change(model, new, old, floor: float | None = None) -> tuple[float, float]:
    """(max |Δn|, max(|ΔV|, |ΔW|)/velocity scale) between two states: the change the Picard test uses.

    The scale is ``model.velocity_scale(new)`` (its floor is set for the Picard test, above the
    linear solver's round-off); with ``floor`` [m/s] it is max(|V|, |W|, floor) instead — for
    measures of how fast a slow flow still changes (steady-state tests), which a Picard floor
    would understate.
    """
    scale = model.velocity_scale(new) if floor is None else \
        max(float(np.abs(new.V).max()), float(np.abs(new.W).max()), floor)
    dv = max(np.abs(new.V - old.V).max(), np.abs(new.W - old.W).max()) / scale
    return float(np.abs(new.n - old.n).max()), float(dv)


def picard_step(model, old, dt: float, settings: PicardSettings = PicardSettings(),
                accept_unconverged: bool = False):
    """One backward-Euler step from ``old``; returns (state, iterations) or (None, reason).

    ``accept_unconverged``: after ``settings.max_iter`` iterates the last one is the
    step even if it has not met ``settings.tol`` (pseudo-transient continuation, where
    the intermediate states are not wanted); it must still pass ``model.check``.
    """
    whole = getattr(model, "compiled_step", None) if not accept_unconverged else None
    made = whole(old, dt, settings) if whole is not None else None  # (the same step, in one call)
    new, info, _ = made if made is not None else _step(model, old, dt, settings, accept_unconverged)
    return new, info


def _step(model, old, dt, settings, accept_unconverged=False):
    """:func:`picard_step`, and whether the last iterate was accepted on a prediction (the plain
    test would have taken at least one more)."""
    t_new = old.t + dt
    k = old.copy(t=t_new)
    hook = getattr(model, "begin_iteration", None)
    newton = NewtonTest(model, old, settings.tol) \
        if settings.newton_test and getattr(model, "newton_iterates", False) else None
    close = newton.close if newton else (lambda accepted: None)  # tells the test how the step ended
    change = getattr(model, "iterate_change", None)  # the model's own (compiled) form of the test below
    solve = getattr(model, "solve", None)
    whole = getattr(model, "iterate", None)  # all of an iterate in one call (None: not for this one)
    with np.errstate(all="ignore"):  # a trial iterate may leave (0, 1]; checked below (one context a step)
        for it in range(1, settings.max_iter + 1):
            if hook:
                hook(it, k)
            try:
                done = whole(k, old, dt, t_new) if whole is not None else None
                if done is None:
                    S = model.assemble(k, old, dt, t_new)
                    a = solve(S, t_new) if solve is not None else _solve(model, S, t_new)
            except ZeroDivisionError:  # a diverging iterate in scalar (compiled or plain) code
                close(None)
                return None, "an iterate divided by zero", False
            if done is not None:
                new, finite, dn, dv = done
            else:
                new = model.unpack(a, k, t_new)
                if change is not None:
                    finite, dn, dv = change(a, new, k)
                else:
                    finite = np.all(np.isfinite(a))
                    if finite:
                        dn, dv = relative_change(model, new, k)
            if not finite:
                close(None)
                return None, "linear solve gave non-finite values", False
            plain = dv < settings.tol and dn < settings.tol
            done = newton.converged(it, new, k, max(dn, dv)) if newton else plain
            k = new
            last = accept_unconverged and it == settings.max_iter
            if done or last:
                reason = model.check(new)
                if reason and not (plain or last):
                    continue  # accepted on a prediction but not admissible: iterate on as the plain test would
                if reason:
                    close(None)
                    return None, reason, False
                out = model.end_step(old, new, dt)
                close(out)
                return out, it, not plain
        close(None)
        return None, f"Picard did not converge in {settings.max_iter} iterations (dv={dv:.2e}, dn={dn:.2e})", False


def integrate(model, state, t_end: float, dt: float, stops: Iterable[float] = (),
              settings: PicardSettings = PicardSettings()) -> Iterator[Step]:
    """Advance ``state`` to ``t_end`` with target step ``dt`` [s], yielding each step."""
    stops = sorted(t for t in stops if state.t < t <= t_end) + [t_end]
    h = dt
    n_steps = rejected = 0
    eps = 1e-9 * max(dt, 1e-12)
    whole = getattr(model, "compiled_step", None)  # the step in one call (None: not made there)
    for stop in stops:
        while state.t < stop - eps:
            h_try = min(h, stop - state.t)
            if stop - state.t - h_try < 0.01 * dt:  # avoid a sliver before the stop
                h_try = stop - state.t
            made = whole(state, h_try, settings) if whole is not None else None
            new, info, predicted = made if made is not None else _step(model, state, h_try, settings)
            if new is None:
                if h_try / 2 < settings.dt_min:
                    raise StepFailure(state.t, h_try, info, state)
                h = h_try / 2
                rejected += 1
                continue
            n_steps += 1
            state = new
            # easy by the plain test's count (one iterate more where a prediction ended the step),
            # so that the step sizes are those of the plain test
            if info + predicted <= settings.easy_iters and h < dt:
                h = min(dt, h * settings.grow)
            yield Step(state.t, h_try, info, state, n_steps, rejected)
            rejected = 0
