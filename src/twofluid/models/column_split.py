"""The hysteretic liquefaction column's split step after its shear sub-steps in one compiled call.

:meth:`LiquefactionColumn.step <twofluid.models.liquefaction_1d.LiquefactionColumn.step>` runs the
shear sub-steps (:mod:`~twofluid.models.hysteretic_kernel`), then :func:`split_step` here: one call of
:func:`~twofluid.models.column_step_kernel.vertical_step` with the vertical step's arguments
(:meth:`ReducedVerticalColumn.fast_call <twofluid.models.reduced_column.ReducedVerticalColumn.fast_call>`)
and those from ``check`` on makes the finite test of the shear's results, the shear column's strains, the vertical
step, the solids outflow, dn/dt (the next sub-steps' interpolation of n, and its product with the next step's likely
span), the next shear step's mixture density and viscosity, σ′_v of the new state and the copy of the shear law's
state the next sub-steps start from. The numbers are those of the
Python path bit for bit (``tests/unit/test_column_split_step.py``); a step the call cannot make
changes nothing, and the column takes the stepper's path for it whole
(:func:`~twofluid.timestepping.backward_euler.integrate`, whose tries the vertical model's
``compiled_step`` makes where it can, bit for bit the stepper's: ``tests/unit/test_column_stepper_steps.py``).
"""
from __future__ import annotations

import numpy as np

from . import column_step_kernel as _kernel
from .reduced_column import run_vertical

_E, _E2 = np.zeros(0), np.zeros((0, 0))  # (no strains to write, no law state to copy)

__all__ = ["split_args", "split_step"]

def split_args(col):
    """The fixed arguments of :func:`~twofluid.models.column_step_kernel.vertical_step` from ``check`` on
    (besides the vertical step's: (the compiled call, the ends' nodes, its outputs and the next shear step's wave
    properties, its work array, whether it is compiled, the shear column's element lengths, the array of dn/dt and
    the next step's n change and its two halves)), or None where it
    does not cover the column ``col`` (a vertical model without the compiled step, an upwind solids flux); kept
    while the closures are the same objects."""
    v = col.v
    hit = col.__dict__.get("_split")
    if hit is not None and hit[0] is v.clo:
        return hit[1]
    ker = _kernel.compiled() if hasattr(v, "fast_call") and v.solids_flux != "upwind" else None
    out = None
    if ker is not None:
        ns = col.n_sat
        laws = v.compiled_laws()
        # the wave properties as LiquefactionColumn._wave_properties sets them with a Newtonian η_s
        props = col._eta_s is not None and laws is not None and not v.clo.viscosity_params
        node = v.vert_node
        out = (ker, int(node[0]), int(node[-1]), np.zeros(2), props,
               np.array([v.mat.rho_f, v.mat.rho_s], dtype=float), np.empty(ns), np.empty(ns),
               np.ascontiguousarray(col._eta_s if props else np.zeros(ns), dtype=float),
               np.empty(ns),  # the call's work array (dP_s/dn̄, not kept)
               ker is not _kernel.vertical_step,  # compiled: called without run_vertical's NumPy error state
               np.ascontiguousarray(col.wave.h, dtype=float))
        ndot = np.empty(2 * ns)  # dn/dt and the next step's n change: read before the next call writes them
        out += (ndot, ndot[:ns], ndot[ns:])
    col._split = (v.clo, out)
    return out


def split_step(col, vert, h: float, dt: float, u: np.ndarray, check: bool, fixed=None, n_bar=None, gamma=None,
               shear=None):
    """The vertical step of ``h`` [s] from ``vert`` (the state with the shear's new n̄) of the column
    ``col``'s split step of ``dt`` [s], and what follows it, in one compiled call (module docstring;
    ``u``: the shear's displacements; ``check``: the call tests that n̄ and ``u`` are finite): (the new
    state, its iterations, the solids outflow [m³/s]), with ``col._ndot`` (an array the next call writes again) and
    the next shear step's wave properties (``col._props``) and σ′_v of the new state (``col._ps``, what
    ``LiquefactionColumn.granular_pressure`` gives for it) set; None where the call does not cover it or cannot make the step
    (nothing changed). ``fixed``: ``col._split_args()``, where the caller has it. ``n_bar``: where given,
    ``vert`` is the column's state before the step and ``n_bar`` the shear's new n̄, an array nobody else
    holds, which the new state takes (:meth:`ReducedVerticalColumn.fast_call
    <twofluid.models.reduced_column.ReducedVerticalColumn.fast_call>`): the step is the one from the copy of
    ``vert`` with ``n_bar`` that carries on its extrapolation history, without that copy made. ``gamma``: where
    given, the call writes the shear column's strains from ``u`` there (whether it makes the step or not, unless
    the check finds ``u`` or n̄ not finite). Where the call makes the step it also leaves the n change of a next
    step of ``dt`` for its shear sub-steps (``col._dn``: (``col._ndot``, that step's span, the change)), and where
    ``shear`` (the hysteretic law's state the shear sub-steps made) is given, a copy of it for the next sub-steps to
    start from (``col._shear_next``: (``shear``, the copy)), the copy :meth:`LiquefactionColumn._shear_hysteretic
    <twofluid.models.liquefaction_1d.LiquefactionColumn._shear_hysteretic>` would make."""
    if fixed is None:
        fixed = col._split_args()
        if fixed is None:
            return None
    ker, node0, node1, out_s, props, mix, wrho, weta, eta_s, work, direct, hw, ndot, rate, dn = fixed
    ne = vert.n.size
    ps = np.empty(ne)
    v = col.v
    nxt = _E2 if shear is None else np.empty(shear.shape)
    call = v.fast_call(vert, h, col.settings, (check, u, float(dt), node0, node1, out_s, ndot, props, mix, wrho, weta,
                                               eta_s, ps, work, hw, _E if gamma is None else gamma,
                                               _E2 if shear is None else shear, nxt), n_bar)
    if call is None:
        return None
    args, ctx = call[1], call[2]
    if direct:  # the compiled call: no NumPy error state to set (:func:`run_vertical`)
        try:
            code = ker(*args)
        except (ZeroDivisionError, TypeError):
            code = -1
    else:
        code = run_vertical(ker, args, ())
    made = v.fast_done(ctx, code)
    if made is None:
        return None
    new = made[0]
    outflow, span = out_s.tolist()
    col._ndot = rate
    col._dn = (rate, span, dn)
    col._props = (new.n, wrho, weta) if props else None
    col._ps = (new, ps)
    col._shear_next = None if shear is None else (shear, nxt)
    return new, made[1], outflow
