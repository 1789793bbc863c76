"""The liquefaction column's vertical step in one compiled call: one backward-Euler step of the
reduced (W, n) model with its Newton iterates, their acceptance test, the pressure recovery and
the extrapolation table, written once in numba-compatible Python (:mod:`twofluid.compiled`).

:meth:`ReducedVerticalColumn.fast_step <twofluid.models.reduced_column.ReducedVerticalColumn.fast_step>`
calls :func:`vertical_step` for each of the column's vertical steps. It makes the same calls, with
the same arithmetic in the same order, as the stepper's Python path
(:func:`twofluid.timestepping.backward_euler._step` with
:meth:`Reduced1D.iterate <twofluid.models.reduced_1d.Reduced1D.iterate>`), so the two give the same
numbers bit for bit (``tests/unit/test_column_step_kernel.py``):

- the bed-force shift at the old state and the step's constants
  (:func:`~twofluid.models.reduced_kernel._shift_law_points`,
  :func:`~twofluid.models.reduced_kernel._shift_with_laws`,
  :func:`~twofluid.models.reduced_kernel._step_constants`);
- the first iterate extrapolated from the table (:func:`~twofluid.models.reduced_kernel._first_iterate`,
  or linearly after a change of step);
- the whole Newton iterates (:func:`~twofluid.models.reduced_kernel._iterate_points`,
  :func:`~twofluid.models.reduced_kernel._whole_iterate`), accepted by the plain test or on the predicted
  change of the next iterate (:class:`twofluid.timestepping.newton.NewtonTest`: the carried contraction
  constants are the arrays ``s_idx``, ``s_c`` and ``meta``, its compiled helpers
  :mod:`twofluid.timestepping.newton_kernel`);
- the admissibility test (:func:`~twofluid.models.reduced_kernel._state_check`), the pressure
  recovery (:func:`~twofluid.models.reduced_kernel._step_pressure`) and the new rows of the
  extrapolation table (:func:`twofluid.models.extrapolation._push_entries`).

A step it cannot make as the Python path would at its first try (a rejected iterate, a state
outside (0, 1], no convergence) returns a code, changes nothing the caller keeps, and the caller
takes the Python path for that step (which halves the step, says why, and so on).

With the hysteretic law the column's split step calls it once after its shear sub-steps
(:mod:`~twofluid.models.column_split`), with the arguments from ``check`` on, to do in the same call
what the column's Python did around the step, each with NumPy's element-wise arithmetic in the same
order (bit for bit, ``tests/unit/test_column_split_step.py``): the finite test of the shear's results and the
shear column's strains before it; after it the solids outflow, dn/dt (and its product with the next step's likely
span), the next shear step's mixture density and viscosity (:func:`~twofluid.closures.kernels._viscosity`), σ′_v of
the new state, which the run's record reads, and the copy of the shear law's state the next sub-steps start from. One function: as a second export calling the step
as a helper it cost the build 3 s of CPU more (its body optimised twice). The run's record of the
new state stays a call of its own (:mod:`~twofluid.models.record_kernel`): made here too it saved
about 6 µs a step and cost the build 1.5 s of CPU (its pairwise sum compiled a second time); the
shear sub-steps too (:mod:`~twofluid.models.hysteretic_kernel`): compiled into this group as well
they would add their build, about 6 s of CPU.

>>> callable(compiled()) or compiled() is None
True
"""
from __future__ import annotations

import numpy as np

from ..closures import kernels as laws
from ..fem import banded
from ..timestepping import newton_kernel as _nk
from . import extrapolation as _ex
from . import reduced_kernel as _rk

__all__ = ["vertical_step", "compiled", "ALONE", "SIGNATURE", "OK",
           "NOT_CONVERGED", "NOT_FINITE", "NOT_ADMISSIBLE", "NOT_FINITE_SHEAR"]

OK, NOT_CONVERGED, NOT_FINITE, NOT_ADMISSIBLE, NOT_FINITE_SHEAR = 0, 1, 2, 3, 4
_CLEAR = 1e-6  # the models' floor of 1 − n (two_fluid_1d._CLEAR)


def vertical_step(t_old, oV, oW, on, onb, dt, V, rho, mc, inv2vol, srcT, mR0, area, tb, w0, w1, law, dpar, d,
                  A, p_ref, modulus, fluidized, vpar, vol, h, g3, viscous, shifted, dir_row, dir_col, dir_val,
                  fixed, floor, liq_src, top_outlet, p_end, DW, Dn, order, ex_t, ex_h, ex_cont, tol, max_iter,
                  newton, lV, lW, ln, last_t, has_last, s_idx, s_c, meta, a_out, P_out, DWo, Dno, info,
                  check, u, dt_step, node0, node1, out_s, ndot, props, mix, wrho, weta, eta_s, ps, dps, hw, gam, st_src, st_next):
    """One backward-Euler step of ``dt`` [s] from the old state (``t_old``, V ``oV``, W ``oW``, n ``on``,
    n̄ ``onb``) with the nodal mixture velocity ``V`` at the new time (module docstring). ``rho`` =
    (ρ_s + ρ_f, ρ_s − ρ_f, ρ_f, μ_f, (ρ_s − ρ_f) g_y), ``g3`` = (ρ_s − ρ_f, g_y, g); the model's
    arrays as :class:`~twofluid.models.reduced_1d.Reduced1D` keeps them; ``shifted``: the upwind bed
    forces (else Galerkin, α = 0). The table: ``DW``, ``Dn`` of ``order`` rows at ``ex_t``, step
    ``ex_h`` (≤ 0: none), ``ex_cont`` whether the old state is its last row. The Newton test's run:
    the last accepted state (``lV``, ``lW``, ``ln``, ``last_t``, ``has_last``), its samples (``s_idx``,
    ``s_c``, ``meta`` = (count, steps)). Written on success: ``a_out`` = [V, W, n], ``P_out``, the new
    table ``DWo``, ``Dno`` (``info[2]`` rows), the samples, and ``info`` = (iterations, accepted on a
    prediction, rows); returns :data:`OK` or why not (nothing the caller keeps written).

    What the hysteretic column's split step does after its shear sub-steps besides (the arguments from
    ``check`` on; :data:`ALONE` for none of it, :mod:`~twofluid.models.column_split`): with ``check``, first
    the test that the new n̄ ``onb`` and the displacements ``u`` are finite (:data:`NOT_FINITE_SHEAR` if
    not, nothing done); then, unless ``gam`` is empty, the shear column's strains ``gam`` = (u[i + 1] −
    u[i])/``hw``[i] (``hw`` its element lengths; NumPy's ``(u[1:] − u[:-1])/hw``), whatever comes of the step;
    after the step, on success only, the solids outflow through the ends (``out_s[0]``
    [m³/s] unless ``out_s`` is empty; the nodes ``node0``, ``node1``: ``diagnostics_1d.solids_outflow``
    with the Galerkin flux), ``ndot`` = (n − n_old)/``dt_step`` [1/s] unless empty (in ``ndot[:ne]``; where
    ``ndot`` has room for 2 ne, also the n change of a next step of ``dt_step`` from the new time t as the
    next shear sub-steps take it, ``ndot[ne:]`` = ``ndot[:ne]`` × s, with its span s = (t + ``dt_step``) − t
    in ``out_s[1]``), with ``props`` the next
    shear step's mixture density ``wrho`` = n ρ_f + (1 − n) ρ_s (``mix`` = (ρ_f, ρ_s)) and viscosity
    ``weta`` = μ_m(n) + ``eta_s`` [Pa·s] (``LiquefactionColumn._wave_properties``), each with NumPy's
    element-wise arithmetic, and unless ``ps`` is empty σ′_v = P_s(n, n̄) of the new state in ``ps`` (``dps``
    its slope; ``LiquefactionColumn.granular_pressure``, which the run's record reads), and unless ``st_next`` is
    empty a copy of the shear law's state ``st_src`` there (the next shear sub-steps' start, which they write)."""
    ne = on.size
    nv = ne + 1
    if check:
        for i in range(onb.size):
            xi = onb[i]
            if not xi - xi == 0.0:  # NaN or ±inf (np.isfinite)
                return NOT_FINITE_SHEAR
        for i in range(u.size):
            xi = u[i]
            if not xi - xi == 0.0:
                return NOT_FINITE_SHEAR
    for i in range(gam.size):
        gam[i] = (u[i + 1] - u[i]) / hw[i]
    t_new = t_old + dt
    # the bed-force shift at the old state (Reduced1D._force_shift_at) and the step's constants
    alpha = np.zeros(ne)
    empty = np.empty(0)
    if shifted:
        x = np.empty(2 * ne)
        s_abs = np.empty(2 * ne)
        _rk._shift_law_points(on, oV, oW, w0, w1, dpar[3], d, rho[2], rho[3], False, x, s_abs, empty)
        _rk._shift_with_laws(on, onb, oV, oW, x, s_abs, empty, empty, empty, law, dpar, d, A, p_ref, modulus,
                             fluidized, rho[3], mc, vol, h, g3[0], g3[1], g3[2], alpha)
    sc = np.empty((16, ne))
    vc = np.empty((4, nv))
    _rk._step_constants(V, oV, oW, on, alpha, dt, inv2vol, 0.5 * rho[0] / dt, -0.5 * rho[1] / dt, rho[4], mc, srcT,
                        mR0, area, tb, sc, vc)
    hc = 0.5 * rho[2] / dt
    cw0 = -0.5 * rho[1] / dt
    # the iterate k: a copy of the old state, from the extrapolation (Reduced1D._first_iterate)
    kV = oV.copy()
    kW = oW.copy()
    kn = on.copy()
    if order >= 3 and t_new > ex_t and abs((t_new - ex_t) - ex_h) <= 1e-9 * ex_h:
        if _rk._first_iterate(DW, Dn, order, kW, kn):
            for i in range(nv):
                kV[i] = V[i]
    elif order >= 2 and t_new > ex_t:
        if _nk.same(kn, Dn[0]) and _nk.same(kW, DW[0]):
            f = (t_new - ex_t) / ex_h
            if 2.0 < f:
                f = 2.0
            for i in range(nv):
                kV[i] = V[i]
                kW[i] = DW[0, i] + f * DW[1, i]
            for i in range(ne):
                y = Dn[0, i] + f * Dn[1, i]
                y = y if not y > 1.0 else 1.0
                kn[i] = y if not y < _CLEAR else _CLEAR
    # the Newton test's run: carried on where the old state is the last one it accepted
    steps, count, C, fresh, e_prev, step_C, have_step_C = _nk.start(has_last, last_t, t_old, lV, lW, ln, oV, oW,
                                                                    on, s_idx, s_c, meta)
    n3 = np.empty((3, ne))
    s3 = np.empty((3, ne))
    aux = np.empty((3, ne))
    last = np.empty((len(_rk.LAST_ROWS), ne))
    nk = kn
    prevV, prevW, prevn = kV, kW, kn  # the iterate before the last (NewtonTest.before)
    done = False
    plain = False
    it = 0
    a = np.empty(3 * nv - 1)
    for it in range(1, max_iter + 1):
        _rk._iterate_points(kn, kW, mc, sc, dpar[3], d, rho[2], rho[3], False, n3, s3, aux, empty)
        a = np.empty(3 * nv - 1)
        change = np.empty(3)
        _rk._whole_iterate(kn, kW, onb, kV, V, sc, vc, mc, n3, s3, aux, empty, empty, empty, law, dpar, d, A, p_ref,
                           modulus, fluidized, vpar, viscous, rho[3], hc, cw0, False, tb, False, dir_row, dir_col,
                           dir_val, fixed, floor, last, a, change)
        if change[0] == 0.0:
            return NOT_FINITE
        nV = a[:nv]
        nW = a[nv:2 * nv]
        nn = a[2 * nv:]
        # the plain test, or NewtonTest.converged
        r, plain, e_prev, step_C, have_step_C = _nk.quadratic(change[1], change[2], tol, newton, e_prev, step_C,
                                                              have_step_C, C, count)
        done = r > 0 or (r < 0 and _nk.predicted(nV, nW, nn, kV, kW, kn, prevV, prevW, prevn, floor, tol, it, fresh))
        prevV, prevW, prevn = kV, kW, kn
        nk = kn
        kV, kW, kn = nV, nW, nn
        if done:
            if _rk._state_check(nn, nV) != 0:
                if not plain:  # accepted on a prediction but not admissible: iterate on
                    done = False
                    continue
                return NOT_ADMISSIBLE
            break
    if not done:
        return NOT_CONVERGED
    # the step's pressure (Reduced1D.end_step) and the new rows of the extrapolation table
    _rk._step_pressure(kW, kn, nk, last, mc, sc, liq_src, viscous, area, top_outlet, p_end, P_out)
    rows = 2
    if ex_cont and ex_h > 0.0 and abs((t_new - ex_t) - ex_h) <= 1e-9 * ex_h:
        rows = order + 1 if order + 1 < 6 else 6
        _ex._push_entries(kW, DW, DWo[:rows])
        _ex._push_entries(kn, Dn, Dno[:rows])
    else:  # a restart from the old state, or a new step size: two rows
        for i in range(nv):
            DWo[0, i] = kW[i]
            DWo[1, i] = kW[i] - (DW[0, i] if ex_cont else oW[i])
        for i in range(ne):
            Dno[0, i] = kn[i]
            Dno[1, i] = kn[i] - (Dn[0, i] if ex_cont else on[i])
    for i in range(3 * nv - 1):
        a_out[i] = a[i]
    # NewtonTest.close: this step's constant joins the samples, the accepted step counts
    if newton:
        _nk.close(step_C, have_step_C, steps, count, s_idx, s_c, meta)
    info[0] = it
    info[1] = 0 if plain else 1
    info[2] = rows
    if out_s.size > 0:
        f0 = 0.5 * (a_out[node0] - a_out[nv + node0])
        f1 = 0.5 * (a_out[node1] - a_out[nv + node1])
        out_s[0] = f1 * area[nv - 1] - f0 * area[0]
    if ndot.size > 0:
        for i in range(ne):
            ndot[i] = (a_out[2 * nv + i] - on[i]) / dt_step
        if ndot.size >= 2 * ne:
            span = (t_new + dt_step) - t_new
            out_s[1] = span
            for i in range(ne):
                ndot[ne + i] = ndot[i] * span
    if props:
        n_end = a_out[2 * nv:]
        laws._viscosity(n_end, rho[3], vpar[0], vpar[1], vpar[2], vpar[3], vpar[4], vpar[5], False, weta)
        for i in range(ne):
            wrho[i] = n_end[i] * mix[0] + (1.0 - n_end[i]) * mix[1]
            weta[i] = weta[i] + eta_s[i]
    if ps.size > 0:
        laws._solids_pressure(a_out[2 * nv:], onb, A, p_ref, modulus, fluidized, ps, dps)
    if st_next.size > 0:
        src = st_src.reshape(st_src.size)  # (views of the C-contiguous arrays: one loop)
        dst = st_next.reshape(st_next.size)
        for i in range(src.size):
            dst[i] = src[i]
    return OK


C1, C2, I1 = "f8[::1]", "f8[:,::1]", "i8[::1]"
SIGNATURE = ("i8(" + ",".join(
    ["f8", C1, C1, C1, C1, "f8", C1, C1, C2, C1, C2, C1, C1, C1, C1, C1, "i8", C1, C1,
     C1, C1, C1, "b1", C1, C1, C1, C1, "b1", "b1", I1, I1, C1,
     I1, "f8", C2, "b1", "f8", C2, C2, "i8", "f8", "f8", "b1", "f8", "i8",
     "b1", C1, C1, C1, "f8", "b1", I1, C1, I1, C1, C1, C2, C2, I1,
     "b1", C1, "f8", "i8", "i8", C1, C1, "b1", C1, C1, C1, C1, C1, C1, C1, C1, C2, C2]) + ")")

_HELPERS = (_rk._fmax, _rk._sign, _rk._closure_points, _rk._band_system, _rk._iterate_change, _rk._shift_points,
            _rk._shift, _rk._step_constants, _rk._state_check, _rk._step_pressure, _rk._iterate_points,
            _rk._whole_iterate, _rk._shift_law_points, _rk._shift_with_laws, _rk._first_iterate,
            banded._u, banded._gbsv22, banded._bt22, _ex._predict_entries, _ex._push_entries, *_nk.HELPERS,
            laws._beta_per_solids, laws._drag, laws._ergun, laws._wen_yu, laws._saturated, laws._next,
            laws._wen_yu_reynolds, laws._wen_yu_given, laws._solids_pressure, laws._viscosity, laws._mooney)

_E = np.zeros(0)
_E2 = np.zeros((0, 0))
#: the arguments of :func:`vertical_step` from ``check`` on for the vertical step alone (nothing tested,
#: written or recorded besides)
ALONE = (False, _E, 1.0, 0, 0, _E, _E, False, _E, _E, _E, _E, _E, _E, _E, _E, _E2, _E2)

_COMPILED = None
_TRIED = False


def compiled():
    """:func:`vertical_step` compiled (:mod:`twofluid.compiled`, group ``column_step``; the plain function
    where the JIT is disabled), or None where it cannot be (no numba and nothing built)."""
    global _COMPILED, _TRIED
    if not _TRIED:
        _TRIED = True
        from ..compiled import group

        try:
            out = group("column_step", {"vertical_step": (vertical_step, SIGNATURE)}, helpers=_HELPERS)
        except ImportError:
            out = None
        _COMPILED = None if out is None else out["vertical_step"]
    return _COMPILED
