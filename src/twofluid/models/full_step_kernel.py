"""The full 1D model's time step in one compiled call: one backward-Euler step of
:class:`~twofluid.models.two_fluid_1d.TwoFluid1D` (element ``1VW/0P/0n``, Newton linearisation) with
its Newton iterates, their acceptance test and the extrapolation table, written once in
numba-compatible Python (:mod:`twofluid.compiled`).

:func:`twofluid.models.full_step.step` calls :func:`full_step` for each step of the stepper
(:func:`~twofluid.timestepping.backward_euler.integrate`). It makes the same calls, with the same
arithmetic in the same order, as the stepper's Python path (:func:`~twofluid.timestepping.backward_euler._step`
with :meth:`TwoFluid1D.iterate <twofluid.models.two_fluid_1d.TwoFluid1D.iterate>`), so the two give the
same numbers bit for bit (``tests/unit/test_full_step.py``):

- the bed-force shift at the old state (:func:`~twofluid.models.reduced_kernel._shift_points`, the drag
  law, P_s', :func:`~twofluid.models.reduced_kernel._shift`: ``full_kernel.force_shift``);
- the first iterate extrapolated from the table (:meth:`TwoFluid1D._first_iterate`);
- the upwind side of the solids flux from each of the first three iterates (:meth:`TwoFluid1D.begin_iteration`);
- the whole Newton iterates (:func:`~twofluid.models.full_kernel._closure_points`, the laws,
  :func:`~twofluid.models.full_kernel._band_system`, :func:`~twofluid.models.full_kernel._residual`,
  :func:`twofluid.fem.banded._gbsv55`, :func:`~twofluid.models.full_kernel._unpack`,
  :func:`~twofluid.models.reduced_kernel._iterate_change`), accepted by the plain test or on the
  predicted change of the next iterate (:class:`twofluid.timestepping.newton.NewtonTest`, its carried
  constants in ``s_idx``, ``s_c``, ``meta``; :mod:`twofluid.timestepping.newton_kernel`);
- the admissibility test (:func:`~twofluid.models.reduced_kernel._state_check`) and the new rows of the
  extrapolation table (:func:`twofluid.models.extrapolation._push_entries`).

A step it cannot make as the Python path would at its first try (a non-finite iterate, a state
outside (0, 1], no convergence) returns a code and changes nothing the caller keeps; the caller then
takes the Python path for that step (which halves the step, says why, and so on).
"""
from __future__ import annotations

import numpy as np

from ..closures import kernels as laws
from ..fem import banded
from ..timestepping import newton_kernel as _nk
from . import extrapolation as _ex
from . import full_kernel as _fk
from . import reduced_kernel as _rk

__all__ = ["full_step", "compiled", "SIGNATURE", "OK", "NOT_CONVERGED", "NOT_FINITE", "NOT_ADMISSIBLE"]

OK, NOT_CONVERGED, NOT_FINITE, NOT_ADMISSIBLE = 0, 1, 2, 3
_CLEAR = 1e-6  # the models' floor of 1 − n (two_fluid_1d._CLEAR)


def _drag(law, dpar, d, mu_f, x, s, out):
    """CompiledLaws.beta_per_solids (not Wen–Yu): ``dpar`` = (stokes, second, blend width, slip_max, ρ_f)."""
    laws._beta_per_solids(law, dpar[0] != 0.0, dpar[1], dpar[2], dpar[3], x, s, d, dpar[4], mu_f, out)


def _table_rows(x, xo, D, cont, pushed, rows, Do):
    """The new rows ``Do[:rows]`` of one field of the extrapolation table (Extrapolator.push): pushed
    onto the table at its step, else two rows from the table's last one (``cont``) or the old state."""
    if pushed:
        _ex._push_entries(x, D, Do[:rows])
    else:
        for i in range(x.size):
            Do[0, i] = x[i]
            Do[1, i] = x[i] - (D[0, i] if cont else xo[i])


def full_step(t_old, oV, oW, oP, on, onb, dt, mc, vc, shift_mc, lengths, mat, law, dpar, d, A, p_ref, modulus,
              fluidized, vpar, viscous, upwind, shifted, bot_out, p_bot, top_out, p_top, fixed, vals, floor,
              DV, DW, Dn, order, ex_t, ex_h, ex_cont, tol, max_iter, newton, lV, lW, ln, last_t, has_last,
              s_idx, s_c, meta, a_out, DVo, DWo, Dno, bel_out, info):
    """One backward-Euler step of ``dt`` [s] from the old state (``t_old``, V ``oV``, W ``oW``, P ``oP``,
    n ``on``, n̄ ``onb``) (module docstring). ``mat`` = (ρ_f, ρ_s, μ_f, g_y, g, ρ_s − ρ_f); ``mc``, ``vc`` the
    model's element and vertex constants (``full_kernel.constants``), ``shift_mc`` those of the shift;
    the laws as ``CompiledLaws.kernel_args`` gives them; ``fixed``, ``vals`` the prescribed rows (band
    order) and values at the new time. The table: ``DV``, ``DW``, ``Dn`` of ``order`` rows at ``ex_t``,
    step ``ex_h`` (≤ 0: none), ``ex_cont`` whether the old state is its last row. The Newton test's run:
    the last accepted state, its samples (``s_idx``, ``s_c``, ``meta`` = (count, steps)). Written on
    success: ``a_out`` (V, W, P, n), the new table rows, the samples, the upwind side of the last
    iterates ``bel_out`` and ``info`` = (iterations, accepted on a prediction, rows, pushed onto the
    table at its step); returns :data:`OK`
    or why not (nothing the caller keeps written)."""
    ne = on.size
    nv = ne + 1
    N = 2 * nv + 2 * ne
    t_new = t_old + dt
    rho_f, rho_s, mu_f, g_y, g = mat[0], mat[1], mat[2], mat[3], mat[4]  # mat[5]: ρ_s − ρ_f
    # the bed-force shift at the old state (full_kernel.force_shift)
    alpha = np.zeros(ne)
    if shifted:
        x = np.empty(2 * ne)
        s_abs = np.empty(2 * ne)
        _rk._shift_points(on, oV, oW, mc[14], mc[15], x, s_abs)
        K = np.empty(2 * ne)
        _drag(law, dpar, d, mu_f, x, s_abs, K)
        ps = np.empty(ne)
        dps = np.empty(ne)
        laws._solids_pressure(on, onb, A, p_ref, modulus, fluidized, ps, dps)
        _rk._shift(on, oV, oW, x, K, dps, shift_mc, mc[16], lengths, mat[5], g_y, g, alpha)
    # the iterate k: a copy of the old state, from the extrapolation (TwoFluid1D._first_iterate)
    kV = oV.copy()
    kW = oW.copy()
    kP = oP.copy()
    kn = on.copy()
    if order >= 2 and t_new > ex_t:
        if _nk.same(kn, Dn[0]) and _nk.same(kW, DW[0]) and _nk.same(kV, DV[0]):
            if order >= 3 and abs((t_new - ex_t) - ex_h) <= 1e-9 * ex_h:
                _ex._predict_entries(DV, order, kV)
                _ex._predict_entries(DW, order, kW)
                _ex._predict_entries(Dn, order, kn)
            else:
                f = (t_new - ex_t) / ex_h
                if 2.0 < f:
                    f = 2.0
                for i in range(nv):
                    kV[i] = DV[0, i] + f * DV[1, i]
                    kW[i] = DW[0, i] + f * DW[1, i]
                for i in range(ne):
                    kn[i] = Dn[0, i] + f * Dn[1, i]
            for i in range(ne):  # np.clip(n, _CLEAR, 1.0)
                y = kn[i]
                if y < _CLEAR:
                    y = _CLEAR
                if y > 1.0:
                    y = 1.0
                kn[i] = y
    # the Newton test's run: carried on where the old state is the last one it accepted
    steps, count, C, fresh, e_prev, step_C, have_step_C = _nk.start(has_last, last_t, t_old, lV, lW, ln, oV, oW,
                                                                    on, s_idx, s_c, meta)
    # work arrays of the iterates
    x3 = np.empty(3 * ne)
    s3 = np.empty(3 * ne)
    K3 = np.empty(3 * ne)
    mu2 = np.empty(2 * ne)
    ps = np.empty(ne)
    dps = np.empty(ne)
    ab = np.empty((N, _fk.LDAB)).T
    abo = np.empty((N, _fk.LDAB)).T
    fv = np.empty(N)
    Aa = np.empty(N)
    b = np.empty(N)
    change = np.empty(3)
    bel = np.empty(nv)
    prevV, prevW, prevn = kV, kW, kn  # the iterate before the last (NewtonTest.before)
    done = False
    plain = False
    it = 0
    out = np.empty(N)
    for it in range(1, max_iter + 1):
        if it <= 3:  # TwoFluid1D.begin_iteration: the upwind side from this iterate
            for i in range(nv):
                bel[i] = 1.0 if kV[i] - kW[i] >= 0.0 else 0.0
        _fk._closure_points(kn, kV, kW, mc[14], mc[15], x3, s3)
        laws._solids_pressure(kn, onb, A, p_ref, modulus, fluidized, ps, dps)
        _drag(law, dpar, d, mu_f, x3, s3, K3)
        if viscous:
            laws._viscosity(x3[ne:], mu_f, vpar[0], vpar[1], vpar[2], vpar[3], vpar[4], vpar[5], True, mu2)
        _fk._band_system(kn, kV, kW, kP, oV, oW, on, alpha, K3, mu2 if viscous else K3, ps, dps, mc, vc, bel,
                         True, viscous, upwind, rho_f, rho_s, mu_f, g_y, dt, bot_out, p_bot, top_out, p_top,
                         ab, fv, Aa)
        if _fk._residual(ab, fv, Aa, kV, kW, kn, fixed, vals, abo, b) != 0 \
                or banded._gbsv55(abo, b) != 0:
            return NOT_FINITE
        out = np.empty(N)
        _fk._unpack(kV, kW, kP, kn, b, fixed, vals, out)
        nV = out[:nv]
        nW = out[nv:2 * nv]
        nP = out[2 * nv:2 * nv + ne]
        nn = out[2 * nv + ne:]
        _rk._iterate_change(out, nV, nW, nn, kV, kW, kn, floor, change)
        if change[0] == 0.0:
            return NOT_FINITE
        # the plain test, or NewtonTest.converged
        r, plain, e_prev, step_C, have_step_C = _nk.quadratic(change[1], change[2], tol, newton, e_prev, step_C,
                                                              have_step_C, C, count)
        done = r > 0 or (r < 0 and _nk.predicted(nV, nW, nn, kV, kW, kn, prevV, prevW, prevn, floor, tol, it, fresh))
        prevV, prevW, prevn = kV, kW, kn
        kV, kW, kP, kn = nV, nW, nP, nn
        if done:
            if _rk._state_check(nn, nV) != 0:
                if not plain:  # accepted on a prediction but not admissible: iterate on
                    done = False
                    continue
                return NOT_ADMISSIBLE
            break
    if not done:
        return NOT_CONVERGED
    # the new rows of the extrapolation table (TwoFluid1D._remember, Extrapolator.push)
    rows = 2
    pushed = ex_cont and ex_h > 0.0 and abs((t_new - ex_t) - ex_h) <= 1e-9 * ex_h  # the table's step again
    if pushed:
        rows = order + 1 if order + 1 < 6 else 6
    _table_rows(kV, oV, DV, ex_cont, pushed, rows, DVo)
    _table_rows(kW, oW, DW, ex_cont, pushed, rows, DWo)
    _table_rows(kn, on, Dn, ex_cont, pushed, rows, Dno)
    for i in range(N):
        a_out[i] = out[i]
    for i in range(nv):
        bel_out[i] = bel[i]
    # NewtonTest.close: this step's constant joins the samples, the accepted step counts
    if newton:
        _nk.close(step_C, have_step_C, steps, count, s_idx, s_c, meta)
    info[0] = it
    info[1] = 0 if plain else 1
    info[2] = rows
    info[3] = 1 if pushed else 0
    return OK


C1, C2, I1 = "f8[::1]", "f8[:,::1]", "i8[::1]"
SIGNATURE = ("i8(" + ",".join(
    ["f8", C1, C1, C1, C1, C1, "f8", C2, C2, C2, C1, C1, "i8", C1, C1, C1, C1, C1,
     "b1", C1, "b1", "b1", "b1", "b1", "f8", "b1", "f8", I1, C1, "f8",
     C2, C2, C2, "i8", "f8", "f8", "b1", "f8", "i8", "b1", C1, C1, C1, "f8", "b1",
     I1, C1, I1, C1, C2, C2, C2, C1, I1]) + ")")

_HELPERS = (_drag, _table_rows, _fk._fmax, _fk._put, _fk._closure_points, _fk._band_system,
            _fk._residual, _fk._unpack, _rk._fmax, _rk._iterate_change, _rk._shift_points, _rk._shift,
            _rk._state_check, banded._u, banded._gbsv55, _ex._predict_entries, _ex._push_entries, *_nk.HELPERS,
            laws._beta_per_solids, laws._drag, laws._ergun, laws._wen_yu, laws._saturated, laws._next,
            laws._solids_pressure, laws._viscosity, laws._mooney)

_GROUP = None
_TRIED = False


def group_kernels() -> dict | None:
    """The group ``full_1d`` (:mod:`twofluid.compiled`): :func:`full_step` and the stepper's kernels
    (``full_kernel.ENTRIES``), which call the same helpers with the same argument types, so that a
    build compiles each once; the plain functions where the JIT is disabled, or None where it cannot
    be (no numba and nothing built)."""
    global _GROUP, _TRIED
    if not _TRIED:
        _TRIED = True
        from ..compiled import group

        try:
            _GROUP = group("full_1d", {"full_step": (full_step, SIGNATURE), **_fk.ENTRIES}, helpers=_HELPERS)
        except ImportError:
            _GROUP = None
    return _GROUP


def compiled():
    """:func:`full_step` compiled (:func:`group_kernels`), or None."""
    out = group_kernels()
    return None if out is None else out["full_step"]
