"""The full 1D model's whole Newton iterate in one Python call around the compiled kernels.

:meth:`TwoFluid1D.iterate <twofluid.models.two_fluid_1d.TwoFluid1D.iterate>` (the stepper's hook for
an iterate in one call) comes here where the kernels of :mod:`~twofluid.models.full_kernel` assemble
the iterate. It makes the calls of :func:`full_kernel.assemble <twofluid.models.full_kernel.assemble>`,
:func:`full_kernel.solve <twofluid.models.full_kernel.solve>`, :meth:`TwoFluid1D.unpack` and
:meth:`TwoFluid1D.iterate_change` with the same arguments in the same order, so the iterates are
the same bit for bit (``tests/unit/test_full_iterate.py``), without what the stepper's four calls
spend between the kernels: the :class:`~twofluid.models.full_kernel.BandIterate`, the work arrays
allocated afresh, the laws and the materials looked up per iterate. The work arrays and the
run's constants are kept per model (:func:`_run_args`, replaced, never changed in place, so a
shallow copy of the model keeps its own).
"""
from __future__ import annotations

import numpy as np

from . import full_kernel, reduced_kernel
from .data_1d import State

__all__ = ["iterate"]

# the methods whose calls ``iterate`` makes at once: a subclass or an instance replacing one gets them one by one
_ONE_CALL_METHODS = frozenset(("assemble", "solve", "unpack", "iterate_change", "velocity_scale"))
_ONE_CALL: dict = {}  # class -> whether it keeps them all


def _run_args(model, ne: int):
    """(the model's materials and closures it was made for, the work arrays, the scalar arguments of
    ``band_system``), kept on the model while its ``mat``, ``clo``, ``bottom`` and ``top`` are the same."""
    mat, clo, bot, top = model.mat, model.clo, model.bottom, model.top
    hit = model.__dict__.get("_fi_run")
    mesh = model.mesh
    if hit is not None and hit[0] is mat and hit[1] is clo and hit[2] is bot and hit[3] is top and hit[4] is mesh \
            and hit[5] is mesh.y:
        return hit
    N = 2 * model.nv + 2 * ne
    work = (np.empty(3 * ne), np.empty(3 * ne), np.empty((N, full_kernel.LDAB)).T, np.empty(N), np.empty(N),
            np.empty((N, full_kernel.LDAB)).T, np.empty(N), np.empty(3), np.empty(2 * ne), np.empty(2 * ne),
            np.empty(ne), np.empty(ne), np.empty(2 * ne), np.empty(3 * ne))  # (the laws' outputs: P_s, ∂P_s/∂n, μ_s, drag)
    scalars = (bool(clo.viscous), model.solids_flux == "upwind", float(mat.rho_f), float(mat.rho_s),
               float(mat.mu_f), float(model.g_y))
    ends = (bot.kind == "outlet", float(bot.pressure), top.kind == "outlet", float(top.pressure))
    # the shift made here where the model's is UpwindBedForces' through full_kernel.force_shift
    from .two_fluid_1d import TwoFluid1D  # (the module that imports this one)

    cls = type(model)
    shift_own = (model.BN is not None and model.bed_forces != "galerkin"
                 and all(getattr(cls, m) is getattr(TwoFluid1D, m) for m in _SHIFT_METHODS)
                 and not set(_SHIFT_METHODS) & model.__dict__.keys())
    hit = model._fi_run = (mat, clo, bot, top, mesh, mesh.y, N, work, scalars, ends, shift_own)
    return hit


#: the methods the bed-force shift of a step goes through (:meth:`UpwindBedForces.bed_force_shift`)
_SHIFT_METHODS = ("bed_force_shift", "_force_shift_at", "force_shift", "solids_pressure", "compiled_laws",
                  "_full_kernels")


def _shift(model, s: State, laws, xs) -> np.ndarray | None:
    """:meth:`UpwindBedForces.bed_force_shift` at ``s`` as :func:`full_kernel.force_shift
    <twofluid.models.full_kernel.force_shift>` makes it, with the compiled ``laws`` and the work
    arrays ``xs`` given, without the cache of the state's copies that the model keeps for a step tried
    again (the shift is a function of ``s``); None where n̄ is not an array like n."""
    n, nb = s.n, s.n_bar
    if type(nb) is not np.ndarray or nb.ndim != 1 or nb.shape != n.shape:
        return None
    return full_kernel.force_shift(model, s, laws, xs)


def iterate(model, ker: dict, k: State, old: State, dt: float, t_new: float):
    """One whole iterate (:meth:`TwoFluid1D.iterate`): (the new iterate, whether the solve's output is
    finite, max |Δn|, the velocity change), or None where the compiled laws or the common kernels
    are not there (the stepper then makes the calls one by one)."""
    cls = type(model)
    if _ONE_CALL.get(cls) is False or not model.__dict__.keys().isdisjoint(_ONE_CALL_METHODS):  # (5 lookups)
        return None
    if cls not in _ONE_CALL:
        from .two_fluid_1d import TwoFluid1D  # (the module that imports this one)

        ok = _ONE_CALL[cls] = all(getattr(cls, f) is getattr(TwoFluid1D, f) for f in _ONE_CALL_METHODS)
        if not ok:
            return None
    laws = model.compiled_laws()
    common = reduced_kernel.common_kernels()
    n, V, W = k.n, k.V, k.W
    nb = k.n_bar
    ne = n.size
    if laws is None or common is None or type(nb) is not np.ndarray or nb.ndim != 1 or nb.shape != n.shape:
        return None
    N, work, scalars, ends, shift_own = _run_args(model, ne)[6:]
    x3, s3, ab, f, Aa, abo, b, change = work[:8]
    viscous, upwind, rho_f, rho_s, mu_f, g_y = scalars
    mc, vc = model._fk_constants
    st = model.__dict__.get("_fi_step")  # the step's: the shift α at the old state, the prescribed rows
    if st is None or st[0] is not old or st[1] != dt or st[2] != t_new:
        alpha = _shift(model, old, laws, work[8:10]) if shift_own else None
        if alpha is None:
            alpha = full_kernel._vector(model.bed_force_shift(old), ne)
        idx, val = model.dirichlet(t_new)  # (full_kernel.solve's conversion, once a step)
        st = model._fi_step = (old, dt, t_new, alpha, np.ascontiguousarray(model._band.pos[idx], dtype=np.int64),
                               np.ascontiguousarray(val, dtype=float))
    # ---- full_kernel.assemble (the laws into arrays kept for the run: band_system reads them, nothing
    # keeps them)
    ker["closure_points"](n, V, W, mc[14], mc[15], x3, s3)
    ps, dps, mu2, K3 = work[10:14]
    laws.solids_pressure(n, nb, out=(ps, dps))
    laws.beta_per_solids(x3, s3, out=K3)
    if viscous:
        laws.solid_viscosity(x3[ne:], out=mu2)
    else:
        mu2 = K3
    below, belf = full_kernel._below_mask(model, vc[0])
    ker["band_system"](n, V, W, k.P, old.V, old.W, old.n, st[3], K3, mu2, ps, dps, mc, vc, belf, below is not None,
                       viscous, upwind, rho_f, rho_s, mu_f, g_y, float(dt), *ends, ab, f, Aa)
    # ---- full_kernel.solve
    fixed, vals = st[4], st[5]
    out = np.empty(N)
    if ker["residual"](ab, f, Aa, V, W, n, fixed, vals, abo, b) != 0 or ker["band_lu"](abo, b) != 0:
        out.fill(np.nan)
    else:
        ker["unpack"](V, W, k.P, n, b, fixed, vals, out)
    # ---- TwoFluid1D.unpack and iterate_change
    nv, np_ = model.nv, model.np
    if type(k) is State:
        new = State(t_new, out[:nv], out[nv:2 * nv], out[2 * nv:2 * nv + np_], out[2 * nv + np_:], nb)
    else:
        new = k.copy(t=t_new, V=out[:nv], W=out[nv:2 * nv], P=out[2 * nv:2 * nv + np_], n=out[2 * nv + np_:])
    common["iterate_change"](out, new.V, new.W, new.n, V, W, n, float(model.velocity_floor), change)
    return new, change[0] != 0.0, float(change[1]), float(change[2])
