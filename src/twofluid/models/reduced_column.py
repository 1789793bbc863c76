"""The vertical model of the liquefaction column on the reduced (W, n) formulation.

:class:`~twofluid.models.liquefaction_1d.VerticalColumn` is the full 1D two-component model
(V, W, P, n) with the ``1VW/0P/0n`` element, an impervious wall at the base and a drained
top. There continuity makes A V = 0 at every vertex, so V ≡ 0 is known, and the reduced model
(:class:`~twofluid.models.reduced_1d.Reduced1D`, Pringle 2001 sec. 4.6.2) solves the same
discrete equations with W and n as the only unknowns of one banded (pentadiagonal) system per
iterate, the pressure recovered from the liquid rows after the step. Its iterates are Newton
iterates (μ_s and 1/n linearised as well) starting from an extrapolation of the last
converged steps, so a step converges in about one iterate where the full model's Picard loop
takes two to three; at convergence both satisfy the same residuals, so the column's results
agree to the Picard tolerance (``tests/unit/test_liquefaction_fast.py``).

What the column adds to the reduced model is the velocity floor of the Picard test (see
:class:`~twofluid.models.liquefaction_1d.VerticalColumn`) and the carrying of the
extrapolation table across the column's split steps, whose vertical state is a fresh copy
with the new reference porosity, and :meth:`ReducedVerticalColumn.fast_step`: the column's vertical
step in one compiled call (:mod:`~twofluid.models.column_step_kernel`), the same numbers as the
stepper's Python path, which takes any step the call cannot make at its first try.
"""
from __future__ import annotations

from contextlib import nullcontext

import numpy as np

from ..closures import kernels as closure_kernels
from ..timestepping import newton as _newton
from . import column_step_kernel
from .reduced_1d import Reduced1D
from .two_fluid_1d import State

_QUIET = nullcontext()  # (reusable: the compiled step's call needs no context)


def run_vertical(ker, args: tuple, more: tuple) -> int:
    """``ker(*args, *more)``, the compiled vertical step (:func:`~twofluid.models.column_step_kernel.vertical_step`
    or its plain Python) with the arguments of :meth:`ReducedVerticalColumn.fast_call` and those after
    ``info``: its code, or -1 where an iterate diverged (ZeroDivisionError) or an array is not as the
    compiled call takes it (TypeError, not C-contiguous float64): the stepper's Python path then meets
    it and says so. Compiled code sets no NumPy error state; only the plain Python of the un-jitted
    run needs it quiet."""
    try:
        with np.errstate(all="ignore") if ker is column_step_kernel.vertical_step else _QUIET:
            return ker(*args, *more)
    except (ZeroDivisionError, TypeError):
        return -1

__all__ = ["ReducedVerticalColumn"]


class ReducedVerticalColumn(Reduced1D):
    """Reduced (W, n) vertical model of the liquefaction column (module docstring).

    Parameters are those of :class:`~twofluid.models.liquefaction_1d.VerticalColumn`:
    ``surcharge`` [Pa] on the skeleton at the drained top, ``velocity_floor`` [m/s] of the
    Picard test; the solids flux defaults to the Galerkin form.
    """

    # the iterates are Newton's: the stepper may accept one on its predicted error (timestepping.newton)
    newton_iterates = True
    #: the column's vertical steps in one compiled call where it covers them (:meth:`fast_step`); False:
    #: always the stepper's Python path (the same numbers; the tests of the stepper itself use it)
    fast_steps = True

    def __init__(self, mesh, materials, closures, *args, surcharge: float = 0.0,
                 velocity_floor: float = 1e-2, **kw):
        kw.setdefault("solids_flux", "galerkin")
        super().__init__(mesh, materials, closures, *args, surcharge=surcharge, **kw)
        self.velocity_floor = float(velocity_floor)

    @property
    def _V_wall(self) -> np.ndarray:
        """The nodal V of a column with a wall at its base (no inlet: c = A V = 0 at every time), one
        array, what :meth:`_mixture_velocity` gives at any time."""
        V = self.__dict__.get("_V_zero")
        if V is None:
            V = self._V_zero = self._mixture_velocity(0.0)
        return V

    def continue_from(self, previous: State, start: State) -> None:
        """``start`` (a copy of the converged ``previous`` with a new n̄) continues its steps: the
        extrapolated first iterate keeps the history of the steps before."""
        ex = self._extrap
        if ex.state is previous:
            ex.state = start

    # --------------------------------------------- the vertical step in one compiled call
    _FAST_METHODS = ("begin_iteration", "check", "end_step", "iterate", "assemble", "solve", "unpack",
                     "iterate_change", "_first_iterate", "bed_force_shift", "_force_shift_at", "_prepare_step",
                     "velocity_scale", "solids_pressure", "compiled_laws", "_remember")

    def _fast_static(self, old: State):
        """The fixed arguments of :func:`~twofluid.models.column_step_kernel.vertical_step` for this
        model, or None where the call does not cover it (an upwind solids flux, a Wen–Yu drag law,
        a method replaced, no compiled kernels): the stepper's Python path then."""
        hit = self.__dict__.get("_fast")
        laws = self.compiled_laws()
        if hit is not None and hit[0] is laws and hit[1] is self.clo:
            return hit[2]
        static = None
        ker = column_step_kernel.compiled()
        args = self._whole_args(old) if ker is not None and laws is not None else None
        cls = type(self)
        if (args is not None and self.solids_flux != "upwind" and getattr(self, "linearisation", "newton") == "newton"
                and self._whole_iterate_ok() and not set(self._FAST_METHODS) & self.__dict__.keys()
                and all(getattr(cls, m) is getattr(ReducedVerticalColumn, m) for m in self._FAST_METHODS)
                and self.BN is not None):
            (_, _, _, _, _), (law, dpar, d, A, p_ref, modulus, fluidized, vpar), consts, _ = args
            if law != closure_kernels.WEN_YU:
                mat, top = self.mat, self.top.kind == "outlet"
                rho = np.array([mat.rho_s + mat.rho_f, mat.rho_s - mat.rho_f, mat.rho_f, mat.mu_f,
                                (mat.rho_s - mat.rho_f) * self.g_y], dtype=float)
                g3 = np.array([mat.rho_s - mat.rho_f, self.g_y, mat.g], dtype=float)
                c = np.ascontiguousarray
                static = (ker, rho, self._mc, c(self._inv2vol, dtype=float), c(self._srcT, dtype=float),
                          c(self._mR0, dtype=float), c(self.vert_area, dtype=float), c(self._tb, dtype=float),
                          self._w0, self._w1, law, dpar, d, A, p_ref, modulus, fluidized, vpar,
                          c(self.volumes, dtype=float), c(self._h, dtype=float), g3, bool(self.clo.viscous),
                          self.bed_forces != "galerkin", *consts, float(self.velocity_floor),
                          c(self._liq_src, dtype=float), top,
                          float(self.top.pressure if top else self.bottom.pressure))
        self._fast = (laws, self.clo, static, None if static is None else static[1:])
        return static

    def fast_step(self, old: State, dt: float, settings) -> tuple | None:
        """One step of ``dt`` [s] from ``old`` as the stepper's first try at it makes it
        (:func:`~twofluid.timestepping.backward_euler.integrate` to ``old.t + dt``), in one compiled call
        (:mod:`~twofluid.models.column_step_kernel`): (the new state, its iterations), or None where the
        call cannot make it (the caller then takes the stepper, which starts the step again)."""
        made = self.compiled_step(old, dt, settings)
        return None if made is None else made[:2]

    def compiled_step(self, old: State, dt: float, settings) -> tuple | None:
        """The stepper's try at a step of ``dt`` [s] from ``old`` in one compiled call (the hook
        :func:`~twofluid.timestepping.backward_euler.integrate` asks first): (the new state, its
        iterations, whether a prediction accepted it: what the stepper's ``_step`` gives the step-size
        control), bit for bit the stepper's; or None where the call cannot make it (nothing changed:
        the stepper then makes the try, or fails it, itself)."""
        call = self.fast_call(old, dt, settings, column_step_kernel.ALONE)  # (the vertical step alone)
        if call is None:
            return None
        ker, args, ctx = call
        made = self.fast_done(ctx, run_vertical(ker, args, ()))
        return None if made is None else (made[0], made[1], int(ctx[4][1]))

    def fast_call(self, old: State, dt: float, settings, more: tuple = (), n_bar=None) -> tuple | None:
        """What :meth:`fast_step` calls: (the compiled :func:`~twofluid.models.column_step_kernel.vertical_step`,
        its arguments up to ``info`` and then ``more`` (those after it: :data:`~.column_step_kernel.ALONE` for
        the vertical step alone), what :meth:`fast_done` takes after the call), or None where the call does
        not cover the step (the stepper's then). ``n_bar``: where given, the step starts from ``old`` with this
        reference porosity, as from the copy of ``old`` with it that :meth:`continue_from` would carry on from
        (not made), and the new state takes ``n_bar`` itself (an array nobody else holds), not a copy."""
        static = self._fast_static(old) if type(old) is State and self.fast_steps else None
        onb = old.n_bar if n_bar is None else n_bar
        if static is None or not (onb.flags.c_contiguous and old.n.flags.c_contiguous):
            _newton.release_kernel_samples(self)
            return None
        ex = self._extrap
        on, oV = old.n, old.V
        ne, nv = on.size, oV.size
        if ex.D is None:
            DW = Dn = np.zeros((1, 1))
            order, ex_t, ex_h = 0, 0.0, -1.0
        else:
            (DW, Dn), order, ex_t, ex_h = ex.D, ex.order, ex.t, (-1.0 if ex.h is None else ex.h)
            if not (DW.flags.c_contiguous and Dn.flags.c_contiguous):
                _newton.release_kernel_samples(self)
                return None
        idx, c, meta, last, _ = _newton.kernel_samples(self)
        d = self.__dict__
        given = d.get("_fast_settings")  # (the settings' values as the call takes them, and one info array a
        if given is None or given[0] is not settings:  # model: read as soon as the call returns)
            given = self._fast_settings = (settings, float(settings.tol), int(settings.max_iter),
                                           bool(settings.newton_test), np.zeros(3, dtype=np.int64))
        _, tol, max_iter, newton, info = given
        newton = newton and bool(self.newton_iterates)  # (the stepper's NewtonTest or none)
        a, P = np.empty(3 * nv - 1), np.empty(ne)
        DWo, Dno = np.empty((6, nv)), np.empty((6, ne))
        t_old = old.t
        t_new = t_old + dt
        if self.bottom.kind == "wall":
            V = d.get("_V_zero")  # (:attr:`_V_wall`, inline)
            if V is None:
                V = self._V_wall
        else:
            V = self._mixture_velocity(t_new)
        cont = ex.state is old and ex.t == t_old
        lt = old if last is None else last
        hit = self._fast
        args = (float(t_old), oV, old.W, on, onb, float(dt), V, *(hit[3] if hit[2] is static else static[1:]), DW,
                Dn, order, float(ex_t or 0.0), float(ex_h), cont, tol, max_iter, newton, lt.V, lt.W, lt.n,
                float(lt.t), last is not None, idx, c, meta, a, P, DWo, Dno, info, *more)
        return static[0], args, (old, t_new, a, P, info, DWo, Dno, cont, newton, n_bar)

    def fast_done(self, ctx: tuple, code: int) -> tuple | None:
        """After the call of :meth:`fast_call`'s arguments returned ``code``: (the new state, its iterations)
        where it made the step, else None (the Newton test's samples handed back to the stepper)."""
        if code != column_step_kernel.OK:
            _newton.release_kernel_samples(self)
            return None
        old, t_new, a, P, info, DWo, Dno, cont, newton, n_bar = ctx
        ex = self._extrap
        nv = old.V.size
        new = State(t_new, a[:nv], a[nv:2 * nv], P, a[2 * nv:], old.n_bar.copy() if n_bar is None else n_bar)
        its, _, rows = info.tolist()
        if rows == 2:
            ex.D, ex.order, ex.h = [DWo[:2], Dno[:2]], 2, t_new - (ex.t if cont else old.t)
        else:
            ex.D, ex.order = [DWo[:rows], Dno[:rows]], rows
        ex.t, ex.state = t_new, new
        if newton:
            self._kernel_samples[3] = new
        return new, its
