""":class:`~twofluid.timestepping.newton.NewtonTest` as the compiled steps make it, written once in
numba-compatible Python (:mod:`twofluid.compiled`) for the kernels that make a step's first try in
one call (:mod:`~twofluid.models.full_step_kernel`, :mod:`~twofluid.models.column_step_kernel`),
which compile these helpers with theirs. The test's carried samples travel as the arrays ``s_idx``
(the steps that measured a constant), ``s_c`` (the constants) and ``meta`` = (count, accepted steps)
(:func:`~twofluid.timestepping.newton.kernel_samples`); this step's state as scalars, returned.
Each makes the Python test's decisions with the same arithmetic in the same order, so a compiled
step gives the stepper's numbers bit for bit.

>>> quadratic(0.25, 0.125, 1e-6, True, 0.5, 0.0, False, 0.0, 0)  # C = 0.25/0.5² = 1: 1000 C e² ≫ tol
(0, False, 0.25, 1.0, True)
"""
from __future__ import annotations

from . import newton as _nt  # (read as _nt.name: a build replaces the helper _accept in its module)

__all__ = ["same", "start", "quadratic", "predicted", "close", "HELPERS"]


def same(a, b):
    """np.array_equal of two arrays of the same size (newton._same)."""
    for i in range(a.size):
        if a[i] != b[i]:
            return False
    return True


def start(has_last, last_t, t_old, lV, lW, ln, oV, oW, on, s_idx, s_c, meta):
    """NewtonTest.__init__ for a step from (``t_old``, ``oV``, ``oW``, ``on``): the run carries on where
    that is the last state it accepted (``has_last``, ``last_t``, ``lV``, ``lW``, ``ln``), else starts
    afresh. Returns (accepted steps, samples, carried C (0 without samples), fresh) and this step's state
    of the test as :func:`quadratic` takes it: (the last iterate's change (0: none), the step's
    constant, whether it has one)."""
    steps = meta[1]
    count = meta[0]
    if not (has_last and last_t == t_old and same(ln, on) and same(lW, oW) and same(lV, oV)):
        steps = 0
        count = 0
    C = 0.0
    for j in range(count):
        if j == 0 or s_c[j] > C:
            C = s_c[j]
    fresh = count > 0 and s_idx[count - 1] >= steps - _nt.FRESH
    return steps, count, C, fresh, 0.0, 0.0, False


def quadratic(dn, dv, tol, newton, e_prev, step_C, have_step_C, C, count):
    """The stepper's test of an iterate that changed n by ``dn`` and V, W by ``dv``: the plain test, and
    with ``newton`` NewtonTest.converged up to its entry and switch tests, after an iterate of change
    ``e_prev`` (0 for the first), with this step's constant ``step_C`` (where ``have_step_C``) and the
    carried ``C`` of ``count`` samples. Returns (1: accepted, 0: not, -1: to :func:`predicted`; whether
    the plain test passed, the change, this step's constant, whether it has one)."""
    plain = dv < tol and dn < tol
    e = dn
    if dv > e:
        e = dv
    if not newton:
        return 1 if plain else 0, plain, e, step_C, have_step_C
    if e_prev != 0.0:
        c = e / (e_prev * e_prev)
        if not have_step_C:
            step_C = c
            have_step_C = True
        elif c > step_C:
            step_C = c
    if e < tol:
        return 1, plain, e, step_C, have_step_C
    have = False
    Cm = 0.0
    if count > 0:
        Cm = C
        have = True
    if have_step_C and (not have or step_C > Cm):
        Cm = step_C
        have = True
    if not have or _nt.SAFETY * Cm * e * e > tol:
        return 0, plain, e, step_C, have_step_C
    return -1, plain, e, step_C, have_step_C


def _scale(V, W, floor):
    """TwoFluid1D.velocity_scale: max(max |V|, max |W|, floor), as Python's max of the three."""
    a = 0.0
    for x in V:
        y = abs(x)
        if y > a or y != y:
            a = y
    b = 0.0
    for x in W:
        y = abs(x)
        if y > b or y != y:
            b = y
    out = a
    if b > out:
        out = b
    if floor > out:
        out = floor
    return out


def predicted(nV, nW, nn, kV, kW, kn, bV, bW, bn, floor, tol, it, fresh):
    """NewtonTest.converged's entry and switch tests (:func:`~twofluid.timestepping.newton._accept`) of
    iterate ``it`` (``nV``, ``nW``, ``nn``) from ``kV``, ``kW``, ``kn``, which came from ``bV``, ``bW``,
    ``bn`` (not read for the first), ``floor`` the velocity scale's floor."""
    if it == 1:
        bV, bW, bn = kV, kW, kn
    return _nt._accept(nV, nW, nn, kV, kW, kn, bV, bW, bn, _scale(nV, nW, floor), _scale(kV, kW, floor), tol,
                   _nt._SIDE_NOISE, _nt._ENTRY_FLOOR, it == 1, fresh) != 0


def close(step_C, have_step_C, steps, count, s_idx, s_c, meta):
    """NewtonTest.close of an accepted step: its constant joins the samples, the step counts, the
    samples older than the window go (``meta`` = (count, steps) written)."""
    if have_step_C:
        s_idx[count] = steps
        s_c[count] = step_C
        count += 1
    steps += 1
    first = steps - _nt.WINDOW
    drop = 0
    while drop < count and s_idx[drop] < first:
        drop += 1
    for j in range(count - drop):
        s_idx[j] = s_idx[j + drop]
        s_c[j] = s_c[j + drop]
    meta[0] = count - drop
    meta[1] = steps


#: the helpers a kernel calling these compiles with them
HELPERS = (same, start, quadratic, _scale, predicted, close, _nt._accept)
