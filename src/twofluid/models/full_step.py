"""The full 1D model's steps in one compiled call each (:mod:`~twofluid.models.full_step_kernel`).

:func:`~twofluid.timestepping.backward_euler.integrate` asks the model's ``compiled_step`` for each
step first (:meth:`TwoFluid1D.compiled_step <twofluid.models.two_fluid_1d.TwoFluid1D.compiled_step>`
→ :func:`step`): the step as the stepper's first try at it makes it, the same numbers bit for bit,
or None, and the stepper's Python path then makes the step (a rejected try, a method replaced by a
subclass or an instance, a law with no compiled form in the call). What the Python path keeps between
steps — the extrapolation table, the Newton test's record of the run, the upwind side — is kept as
it keeps it, so the two paths can take turns.
"""
from __future__ import annotations

import numpy as np

from ..closures import kernels as closure_kernels
from ..timestepping import newton as _newton
from . import full_kernel, full_step_kernel
from .data_1d import State

__all__ = ["step"]

#: the methods whose work the compiled step does: a subclass or an instance replacing one takes the stepper
_FAST_METHODS = ("begin_iteration", "check", "end_step", "iterate", "assemble", "solve", "unpack", "iterate_change",
                 "_first_iterate", "bed_force_shift", "_force_shift_at", "force_shift", "velocity_scale",
                 "solids_pressure", "compiled_laws", "_remember", "_full_kernels", "compiled_step")
_FAST = frozenset(_FAST_METHODS)
_CLASS_OK: dict = {}  # class -> whether it keeps them all


def _static(model):
    """The fixed arguments of :func:`~twofluid.models.full_step_kernel.full_step` for ``model`` (kept while
    its laws, materials, ends and mesh are the same objects), or None where the call does not cover it."""
    d = model.__dict__
    hit = d.get("_fs_static")  # ((what it was made for), the arguments): the same objects, the same flags
    if hit is not None:
        k = hit[0]
        if k[0] is model.clo and k[1] is model.mat and k[2] is model.bottom and k[3] is model.top \
                and k[4] is model.mesh and k[5] is model.compiled and k[6] is model.compiled_closures \
                and type(model) is k[7] and d.keys().isdisjoint(_FAST):  # (looks up the 18 names: not the dict's all)
            return hit[1]
    cls = type(model)
    ok = _CLASS_OK.get(cls)
    if ok is None:
        from .two_fluid_1d import TwoFluid1D  # (the module that imports this one)

        ok = _CLASS_OK[cls] = all(getattr(cls, m) is getattr(TwoFluid1D, m) for m in _FAST_METHODS)
    if not ok or not _FAST.isdisjoint(d) or model.compiled is False or not model._fk_ok:
        return None  # (the conditions of TwoFluid1D._full_kernels, without building its kernels)
    laws = model.compiled_laws()  # (a function of clo, mat and the two flags)
    key = (model.clo, model.mat, model.bottom, model.top, model.mesh, model.compiled, model.compiled_closures, cls)
    static = None
    ker = full_step_kernel.compiled() if laws is not None else None
    if ker is not None:
        law, dpar, d, A, p_ref, modulus, fluidized, vpar = laws.kernel_args()
        if law != closure_kernels.WEN_YU:  # (its powers are NumPy's array routine in the Python path)
            mat, bot, top, c = model.mat, model.bottom, model.top, np.ascontiguousarray
            mc, vc = full_kernel.constants(model)
            shift_mc = model.__dict__.get("_fk_shift_mc")
            if shift_mc is None:  # full_kernel.force_shift's
                shift_mc = model._fk_shift_mc = np.zeros((19, mc.shape[1]))
                shift_mc[10:14] = mc[0:4]
            matv = np.array([float(mat.rho_f), float(mat.rho_s), float(mat.mu_f), float(model.g_y), float(mat.g),
                             float(mat.rho_s - mat.rho_f)])
            static = (ker, mc, vc, shift_mc, c(model.mesh.lengths, dtype=float), matv, law, c(dpar, dtype=float),
                      c(d, dtype=float), c(A, dtype=float), c(p_ref, dtype=float), c(modulus, dtype=float),
                      bool(fluidized), c(vpar, dtype=float), bool(model.clo.viscous), model.solids_flux == "upwind",
                      model.BN is not None and model.bed_forces != "galerkin", bot.kind == "outlet",
                      float(bot.pressure), top.kind == "outlet", float(top.pressure))
    model._fs_static = (key, static)
    return static


def step(model, old: State, dt: float, settings) -> tuple | None:
    """One step of ``dt`` [s] from ``old`` as the stepper's first try at it makes it, in one compiled
    call: (the new state, its iterations, whether a prediction accepted it), or None where the call
    cannot make it (the stepper then makes the step)."""
    static = _static(model) if type(old) is State else None
    if static is None:
        _newton.release_kernel_samples(model)
        return None
    ker = static[0]
    ex = model._extrap
    ne, nv = old.n.size, old.V.size
    if ex.D is None:
        DV = DW = Dn = np.zeros((1, 1))
        order, ex_t, ex_h = 0, 0.0, -1.0
    else:
        (DV, DW, Dn), order, ex_t, ex_h = ex.D, ex.order, ex.t, (-1.0 if ex.h is None else ex.h)
    idx, c, meta, last, _ = _newton.kernel_samples(model)
    newton = bool(settings.newton_test and model.newton_iterates)  # (the stepper's NewtonTest or none)
    t_new = old.t + dt
    fi, val = model.dirichlet(t_new)
    held = model.__dict__.get("_fs_fixed")  # (the band rows, kept while the indices are the same array)
    if held is None or held[0] is not fi:
        held = model._fs_fixed = (fi, np.ascontiguousarray(model._band.pos[fi], dtype=np.int64))
    fixed = held[1]
    N = 2 * nv + 2 * ne
    a, bel, info = np.empty(N), np.empty(nv), np.zeros(4, dtype=np.int64)
    DVo, DWo, Dno = np.empty((6, nv)), np.empty((6, nv)), np.empty((6, ne))
    cont = ex.state is old and ex.t == old.t
    lt = last if last is not None else old
    args = (float(old.t), old.V, old.W, old.P, old.n, old.n_bar, float(dt), *static[1:],
            fixed, np.ascontiguousarray(val, dtype=float), float(model.velocity_floor), DV, DW, Dn, order,
            float(ex_t or 0.0), float(ex_h), cont, float(settings.tol), int(settings.max_iter), newton,
            lt.V, lt.W, lt.n, float(lt.t), last is not None, idx, c, meta, a, DVo, DWo, Dno, bel, info)
    try:
        # a diverging iterate is the stepper's to report, as in its own path (compiled code sets no NumPy
        # error state: only the plain Python of the un-jitted run needs it quiet)
        if ker is full_step_kernel.full_step:
            with np.errstate(all="ignore"):
                code = ker(*args)
        else:
            code = ker(*args)
    except (ZeroDivisionError, TypeError):  # a diverging iterate; an array not as the call takes it
        code = -1
    if code != full_step_kernel.OK:
        _newton.release_kernel_samples(model)
        return None
    new = State(t_new, a[:nv], a[nv:2 * nv], a[2 * nv:2 * nv + ne], a[2 * nv + ne:], old.n_bar.copy())
    rows = int(info[2])
    ex.D, ex.order = [DVo[:rows], DWo[:rows], Dno[:rows]], rows
    if not info[3]:  # two rows from the table's last one or the old state: a new step
        ex.h = t_new - (ex.t if cont else old.t)
    ex.t, ex.state = t_new, new
    model._below = bel != 0.0
    if newton:
        model._kernel_samples[3] = new
    return new, int(info[0]), bool(info[1])
