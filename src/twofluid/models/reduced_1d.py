"""The reduced-variable 1D model (Pringle 2001 sec. 4.6.2): W and n are the only unknowns of the linear solves.

It solves the same discrete equations as :class:`~twofluid.models.two_fluid_1d.TwoFluid1D`
with the ``1VW/0P/0n`` element, reorganised so that each Newton–Picard iterate is one
pentadiagonal (banded) system in the vertex W and element n, interleaved
(W_0, n_0, W_1, n_1, …, W_ne):

- continuity: A V = c(t) at every vertex, c fixed by the inlet or wall end, so V
  is known;
- porosity (the same upwinded vertex solids flux):
  n_e = n_eᵗ + Δt [A r (V − W)]_{e}^{e+1} / (2 Vol_e), with the upwind ratio
  r = (1 − n_up)/(1 − n_f) Newton-linearised about the iterate as in the full
  model — each n-row couples W_e, W_{e+1}, n_{e−1}, n_e, n_{e+1};
- momentum: at every vertex i with a free W the mixture row carries A_i [[P]]_i, and
  so does the liquid row, which the full model writes per unit liquid volume
  (tested with δW/n), so mixture − liquid is free of P (the thesis's reduced model:
  solid − (1 − n)/n liquid); it couples W_{i−1}, W_i, W_{i+1}, n_{i−1}, n_i.

The buoyant weight and the drag carry the full model's upwind test functions
ψ = N ∓ αB of the step (:meth:`TwoFluid1D.force_shift`, taken at the old state).

In the interleaved ordering both row kinds reach two unknowns either side of the
diagonal: a band of half-width 2, solved as the block-tridiagonal system of the (W_v, n_v) pairs
it also is, with the band LU where the block solve's backward error is not at round-off
(:func:`twofluid.fem.banded._bt22`). The system is
written for the increment from iterate k (right-hand side = minus the residual).

The linearisation about iterate k is Newton's method on the full model's residuals:
drag Newton-linearised in W (exact) and n (finite difference), P_s Taylor-expanded
in n, the upwind ratio Newton-linearised — as in the full model — and, beyond it,
the 1/n of the liquid inertia and viscous terms and μ_s(n) (finite difference) too,
which the full model freezes at the iterate: that makes the convergence quadratic
(a frozen μ_s left a linear rate of ~5e-3 on 1000 elements). The linearisation only
steers the iterates: at convergence both models satisfy the same residuals, so they
agree to the Picard tolerance. P is recovered after each step from the liquid rows
(linearised about the last iterate, with the full model's frozen 1/n), marching
from the outlet: [[P]]_i = −L_i/A_i.

Speed (the reason for the model): what does not change inside the Newton loop (the mixture
velocity and its element products, the old state's terms, Δt factors) is computed once per step;
an iterate is one pass of compiled loops that finds the closure points, one call of each closure
law (the drag law at the iterate and its two finite-difference neighbours, μ_s at n and n + δn,
P_s; compiled where :mod:`~twofluid.closures.kernels` has the law, the registry's function
otherwise), one pass that writes the band system and one band solve. These loops — the iterate,
the step's constants, the bed-force shift, the extrapolated first iterate and the pressure
recovery — are written once, in :mod:`~twofluid.models.reduced_kernel`, and compiled by
:mod:`twofluid.compiled` (with ``TWOFLUID_DISABLE_JIT=1`` they run as plain Python, for
debugging). The first iterate of a
step starts from the extrapolation of the last converged steps, of order up to 4
chosen entry by entry (W and n; V is known exactly; :class:`~twofluid.models.extrapolation.Extrapolator`): on the
settling column nearly every step then converges at the first iterate, on the
fluidized bed (100 elements) three in four.

Checked by: the banded matrix against the finite-difference Jacobian of the residual, the
converged steps against the full model's (:class:`~twofluid.models.two_fluid_1d.TwoFluid1D`,
whose general weak-form assembly is the independent second path), the exact solutions
(Kynch, Terzaghi) and the golden outputs of the bundled cases (``tests/golden``).

``surcharge`` [Pa] is a solids pressure applied on the top face (a load carried by
the skeleton only, drained liquid), used by the Terzaghi check.
"""
from __future__ import annotations

import numpy as np

from ..closures.viscosity import solid_viscosity
from ..closures import kernels as closure_kernels
from . import reduced_kernel
from .two_fluid_1d import _CLEAR, State, TwoFluid1D

__all__ = ["Reduced1D"]

_KL = 2  # half-width of the band of the interleaved (W, n) system
_DIAG = 2 * _KL  # row of the main diagonal in LAPACK band storage (KL fill-in rows first)
_UNDECIDED = object()  # a step's way of iterating not yet decided (Reduced1D.iterate)


class _LastRows:
    """The last iterate assembled by the kernels, for the pressure of the step: its W and n, the
    per-element rows of ``reduced_kernel.LAST_ROWS``, whether μ_s acted, the step's constants."""

    __slots__ = ("W", "n", "rows", "viscous", "st")

    def __init__(self, W, n, rows, viscous, st):
        self.W, self.n, self.rows, self.viscous, self.st = W, n, rows, viscous, st


class Reduced1D(TwoFluid1D):
    """Reduced-variable 1D model: W and n are the only unknowns of the linear solves.

    Parameters are those of :class:`TwoFluid1D`; ``element`` must be ``"1VW/0P/0n"``,
    one end must be an inlet or a wall (it fixes c = A V), and ``surcharge`` [Pa]
    is an optional solids load on the top face.

    Densities, the liquid viscosity and gravity must be scalars (ValueError otherwise).
    """

    # the iterates are Newton's: the stepper may accept one on its predicted error (timestepping.newton)
    newton_iterates = True

    def __init__(self, mesh, materials, closures, bottom, top, element="1VW/0P/0n",
                 solids_flux="upwind", surcharge: float = 0.0):
        if element != "1VW/0P/0n":
            raise ValueError(f"the reduced_1d model supports only the '1VW/0P/0n' element, got {element!r}; "
                             "use model = 'two_fluid_1d' for the quadratic element")
        if "outlet" == bottom.kind == top.kind:
            raise ValueError("the reduced_1d model needs an inlet or a wall at one end (it fixes A V)")
        super().__init__(mesh, materials, closures, bottom, top, element, solids_flux)
        self.surcharge = float(surcharge)
        ne, nv, mat, area = mesh.n_elements, self.nv, materials, self.vert_area
        self._fixed = [v for b, v in ((bottom, 0), (top, ne)) if b.kind != "outlet"]  # W = V there
        # element arrays with the element index last: (2, ne) local vectors, (2, 2, ne) local matrices
        self._Mt = np.ascontiguousarray(np.moveaxis(self.M, 0, -1))
        self._M0, self._M1 = self._Mt[:, 0].copy(), self._Mt[:, 1].copy()  # M x = M0 x_bottom + M1 x_top
        Kt = np.ascontiguousarray(np.moveaxis(self.Kvis, 0, -1))
        # linear element: Kv_e = κ_e [[1, −1], [−1, 1]] (constant shape-function gradients)
        self._kap = Kt[0, 0].copy()
        self._Kt = Kt
        if not np.allclose(Kt, self._kap * np.array([[1.0, -1.0], [-1.0, 1.0]])[:, :, None], rtol=1e-12, atol=0.0):
            raise ValueError("reduced_1d: unexpected viscous element matrix for the linear element")
        self._wt = np.ascontiguousarray(self.avg_weights)  # (2, ne) element-mean weights
        self._w0, self._w1 = self._wt[0].copy(), self._wt[1].copy()
        # constant pieces of the mixture-minus-liquid rows: −B0ᵀ P_s (the buoyant weight, tested
        # with the upwind ψ of the step like the drag, is per step: ``_prepare_step``)
        self._psA = np.stack([area[:-1], -area[1:]])
        self._srcT = np.ascontiguousarray(self.src.T)
        self._liq_src = np.ascontiguousarray((-mat.rho_f * self.g_y * self.src).T)
        self._BNt = np.ascontiguousarray(self.BN.T)  # ∫ B N_j dΩ, (2, ne): the ψ − N part of the tests
        self._sig = np.array([[-1.0], [1.0]])
        # minus the residual terms that do not depend on the iterate (but for the weight): surcharge
        R0 = np.zeros(nv)
        if top.kind == "outlet":
            R0[-1] -= self.surcharge * area[-1]
        self._mR0 = R0
        self._inv2vol = 0.5 / self.volumes
        wb, wa = self.w_below, self.w_above
        self._tb = wb / (wb + wa)  # weight of the element below in the vertex porosity n_f
        self._ext = np.ones(ne + 2)  # porosity with clear liquid outside the ends (scratch)
        # band storage of the rows of prescribed W (identity rows)
        N = 2 * nv - 1
        self._dir = [(_DIAG - d, 2 * v + d, 1.0 if d == 0 else 0.0)
                     for v in self._fixed for d in range(-_KL, _KL + 1) if 0 <= 2 * v + d < N]
        self._V_of_t = (None, None, None)  # (t, c, nodal V) cache
        self._step = None  # cache of what is fixed per step
        self._belf = self._belf_of = None  # upwind side as 0/1 floats, and the boolean array it came from
        self._last_iterate = None  # pieces of the last assembled iterate, for the pressure of the step
        # the kernel takes scalar densities and liquid viscosity (per-element particle sizes are the closures')
        if not all(np.ndim(getattr(mat, f)) == 0 for f in ("rho_f", "rho_s", "mu_f", "g")):
            raise ValueError("the reduced_1d model takes scalar densities, liquid viscosity and gravity "
                             "(per-element particle sizes are the closures')")
        self._h = mesh.lengths
        # the model's element constants of the compiled kernel (reduced_kernel._band_system's ``mc``)
        self._mc = np.ascontiguousarray(np.vstack([self._M0, self._M1, self._wt, self._BNt, self._psA,
                                                   self._Mt.reshape(4, ne), self._Kt.reshape(4, ne), self._kap]))

    # ----------------------------------------------------------- pieces
    def mixture_flux(self, t: float) -> float:
        """c = A V [m³/s] fixed by the inlet (or wall) end at time t."""
        if self.bottom.kind != "outlet":
            return self.vert_area[0] * self.inlet_value(self.bottom, t, 1.0)
        return self.vert_area[-1] * self.inlet_value(self.top, t, -1.0)

    def _assemble_nodal(self, E: np.ndarray) -> np.ndarray:
        """Sum element contributions (2, ne) (local row first) at the vertices."""
        out = np.empty(self.nv)
        out[:-1] = E[0]
        out[-1] = 0.0
        out[1:] += E[1]
        return out

    def _mixture_velocity(self, t: float) -> np.ndarray:
        """Nodal V [m/s] = c(t)/A (the same array while c does not change)."""
        t0, c0, V = self._V_of_t
        if t0 != t:
            c = self.mixture_flux(t)
            if c != c0:
                V = np.full(self.nv, c) / self.vert_area
            self._V_of_t = (t, c, V)
        return V

    def _prepare_step(self, old: State, dt: float, t_new: float) -> dict:
        """What does not change inside the Picard loop of a step (cached on ``old``, Δt, t_new)."""
        st = self._step
        if st is not None and st["old"] is old and st["dt"] == dt and st["t"] == t_new:
            return st
        ker = self._kernels()
        mat, area = self.mat, self.vert_area
        # the step's constants by the kernel, packed as band_system takes them
        ne = old.n.size
        V = self._mixture_velocity(t_new)
        sc, vc = np.empty((16, ne)), np.empty((4, ne + 1))
        alpha = np.ascontiguousarray(self.bed_force_shift(old), dtype=float)
        ker[6](V, old.V, old.W, old.n, alpha, float(dt), self._inv2vol, 0.5 * (mat.rho_s + mat.rho_f) / dt,
               -0.5 * (mat.rho_s - mat.rho_f) / dt, float((mat.rho_s - mat.rho_f) * self.g_y), self._mc,
               self._srcT, self._mR0, area, self._tb, sc, vc)
        st = self._step = {"old": old, "dt": dt, "t": t_new, "V": V, "sc": sc, "vc": vc, "mR": vc[3],
                           "Vbar": sc[0], "dn": sc[12], "hc": 0.5 * mat.rho_f / dt,
                           "cw0": -0.5 * (mat.rho_s - mat.rho_f) / dt}
        return st

    def _force_shift_at(self, s: State) -> np.ndarray:
        """:meth:`TwoFluid1D._force_shift_at` by the kernels (the drag law at n and n + δn, P_s' at n)."""
        ker = self._kernels()
        if self.bed_forces == "galerkin":
            return super()._force_shift_at(s)
        n = s.n
        ne = n.size
        x, s_abs = np.empty(2 * ne), np.empty(2 * ne)
        mat = self.mat
        args = self._whole_args(s)
        if args is not None:  # in two compiled calls around Wen–Yu's powers (the same operations)
            (_, _, points, shift, _), (law, dpar, d, *laws), _, compiled = args
            wen_yu = law == closure_kernels.WEN_YU
            re = np.empty(2 * ne if wen_yu else 0)
            points(n, s.V, s.W, self._w0, self._w1, dpar[3], d, float(mat.rho_f), float(mat.mu_f), wen_yu, x, s_abs,
                   re)
            n_pow, re_pow = compiled.wen_yu_powers(x, re) if wen_yu else (re, re)
            alpha = np.empty(ne)
            shift(n, s.n_bar, s.V, s.W, x, s_abs, re, re_pow, n_pow, law, dpar, d, *laws[:4], float(mat.mu_f),
                  self._mc, self.volumes, self._h, float(mat.rho_s - mat.rho_f), float(self.g_y), float(mat.g), alpha)
            return alpha
        ker[4](n, s.V, s.W, self._w0, self._w1, x, s_abs)
        laws = self.compiled_laws()
        K = laws.beta_per_solids(x, s_abs) if laws is not None else \
            np.ascontiguousarray(self.clo.beta_per_solids(x, s_abs, self._materials_times(2)), dtype=float)
        _, dps = self.solids_pressure(n, s.n_bar, derivative=True)
        alpha = np.empty(ne)
        ker[5](n, s.V, s.W, x, K, np.ascontiguousarray(dps, dtype=float), self._mc, self.volumes, self._h,
               float(mat.rho_s - mat.rho_f), float(self.g_y), float(mat.g), alpha)
        return alpha

    def _kernels(self):
        """The model's kernels (:func:`~twofluid.models.reduced_kernel.kernels`)."""
        ker = self.__dict__.get("_ker")
        if ker is None:
            ker = self._ker = reduced_kernel.kernels()
        return ker

    # ---------------------------------------------------- stepper interface
    def _first_iterate(self, k: State) -> None:
        """At the first iteration of a step from the last converged state, W and n start
        from their extrapolation from the last converged steps (:class:`~twofluid.models.extrapolation.Extrapolator`),
        n kept in (0, 1], and V from c(t)/A.
        """
        ex = self._extrap
        if ex.order >= 3 and k.t > ex.t and abs((k.t - ex.t) - ex.h) <= 1e-9 * ex.h:
            args = self._whole_args(k)  # the same tests and prediction in one compiled call
            if args is not None:
                if args[0][4](*ex.D, ex.order, k.W, k.n):
                    k.V[:] = self._mixture_velocity(k.t)
                return
        if ex.order >= 2 and k.t > ex.t:
            DW, Dn = ex.D
            if (k.n == Dn[0]).all() and (k.W == DW[0]).all():  # k is the last converged state
                W, n = ex.predict(k.t)
                k.V[:] = self._mixture_velocity(k.t)
                k.W[:] = W
                np.minimum(n, 1.0, out=k.n)
                np.maximum(k.n, _CLEAR, out=k.n)

    def assemble(self, k: State, old: State, dt: float, t_new: float) -> tuple:
        """Banded Newton system for the increment of (W, n) of one iterate (module docstring):
        (band storage, minus the residual, the iterate, the step's constants)."""
        return self._assemble_compiled(k, self._prepare_step(old, dt, t_new))

    def _upwind_side(self):
        """(whether the solids flux is upwinded, the upwind side fixed for the step or None, that side as
        0/1 floats for the compiled kernels — any array where there is none: not read)."""
        upwind = self.solids_flux == "upwind"
        below = getattr(self, "_below", None) if upwind else None
        if below is None:
            return upwind, None, self._tb
        if self._belf_of is not below:
            self._belf, self._belf_of = below.astype(float), below
        return upwind, below, self._belf

    def _assemble_compiled(self, k: State, st: dict) -> tuple:
        """:meth:`assemble` by the kernels: the closure points, the laws (compiled, else the registry's),
        the band system."""
        points, band = self._kernels()[:2]
        mat, clo = self.mat, self.clo
        n, W = k.n, k.W
        ne = n.size
        n3, s3, aux = np.empty((3, ne)), np.empty((3, ne)), np.empty((3, ne))
        points(n, W, self._w0, self._w1, st["Vbar"], st["dn"], st["sc"][14], n3, s3, aux)
        laws = self.compiled_laws()
        ps, dps = self.solids_pressure(n, k.n_bar, derivative=True)
        if laws is not None:  # the same laws compiled (closures.kernels)
            kraw = laws.beta_per_solids(n3.ravel(), s3.ravel())
            mu2 = laws.solid_viscosity(n3[:2].ravel()) if clo.viscous else kraw
        else:
            kraw = np.ascontiguousarray(clo.beta_per_solids(n3.ravel(), s3.ravel(), self._materials_times(3)),
                                        dtype=float)
            if clo.viscous:  # μ_s at n and n + δn: the first two rows of n3
                mu2 = np.ascontiguousarray(solid_viscosity(n3[:2].ravel(), mat.mu_f, **clo.viscosity_params),
                                           dtype=float)
            else:
                mu2 = kraw
        upwind, below, belf = self._upwind_side()
        N = 2 * self.nv - 1
        ab = np.empty((N, 3 * _KL + 1)).T
        rhs = np.empty(N)
        last = np.empty((len(reduced_kernel.LAST_ROWS), ne))
        if laws is None:
            ps, dps = np.ascontiguousarray(ps, dtype=float), np.ascontiguousarray(dps, dtype=float)
        band(n, W, kraw, n3, aux, ps, dps, mu2, bool(clo.viscous), float(mat.mu_f), st["hc"], st["cw0"], upwind,
             belf, below is not None, self._mc, st["sc"], st["vc"], ab, rhs, last)
        self._last_rows = last
        self._last_iterate = _LastRows(W, n, last, clo.viscous, st)
        for row, col, val in self._dir:
            ab[row, col] = val
        V = st["V"]
        for v in self._fixed:
            rhs[2 * v] = V[v] - W[v]
        return ab, rhs, k, st

    def iterate(self, k: State, old: State, dt: float, t_new: float):
        """One whole Newton iterate where the compiled kernels assemble it: :meth:`assemble`,
        :meth:`solve`, :meth:`unpack` and :meth:`~TwoFluid1D.iterate_change` in one call (the same
        calls, without the stepper's dispatch between them); returns (the new iterate, whether the
        solve's output is finite, max |Δn|, the velocity change), or None where a subclass or the
        instance replaces one of those methods (the stepper calls them then)."""
        st = self._prepare_step(old, dt, t_new)
        way = st.get("way", _UNDECIDED)
        if way is _UNDECIDED:  # how this step's iterates go, decided once: False for the stepper's four calls
            way = st["way"] = (self._whole_call(k, st) if self._whole_iterate_ok() else False)
        if way is False:
            return None
        if way is not None:  # all of it in two compiled calls around Wen–Yu's powers (the same operations)
            points, whole, powers, n3, re, pts, mid, static, tail = way
            W, n = k.W, k.n
            points(n, W, *pts)
            n_pow, re_pow = powers(n3.ravel(), re) if powers is not None else (re, re)
            _, below, belf = self._upwind_side()
            last, a, change = np.empty((len(reduced_kernel.LAST_ROWS), n.size)), np.empty(3 * self.nv - 1), \
                np.empty(3)
            whole(n, W, k.n_bar, k.V, *mid, re_pow, n_pow, *static, belf, below is not None, *tail, last, a, change)
            self._last_rows = last
            self._last_iterate = _LastRows(W, n, last, self.clo.viscous, st)
            new = self.unpack(a, k, t_new)
            return new, change[0] != 0.0, float(change[1]), float(change[2])
        a = self.solve(self._assemble_compiled(k, st), t_new)
        new = self.unpack(a, k, t_new)
        return (new, *self.iterate_change(a, new, k))

    def _whole_call(self, k: State, st: dict):
        """The compiled calls of this step's whole iterates and their arguments (:meth:`iterate`), or None
        where the kernels are called one by one (:meth:`_whole_args`)."""
        args = self._whole_args(k)
        if args is None:
            return None
        (points, whole, _, _, _), (law, dpar, d, *laws), consts, compiled = args
        ne, mat, mc, sc = k.n.size, self.mat, self._mc, st["sc"]
        wen_yu = law == closure_kernels.WEN_YU
        scratch = self.__dict__.get("_whole_scratch")  # the closure points: rewritten by every iterate
        if scratch is None or scratch[0].shape != (3, ne) or (scratch[3].size != 0) != wen_yu:
            scratch = self._whole_scratch = (np.empty((3, ne)), np.empty((3, ne)), np.empty((3, ne)),
                                             np.empty(3 * ne if wen_yu else 0))
        n3, s3, aux, re = scratch
        rho_f, mu_f = float(mat.rho_f), float(mat.mu_f)
        return (points, whole, compiled.wen_yu_powers if wen_yu else None, n3, re,
                (mc, sc, dpar[3], d, rho_f, mu_f, wen_yu, n3, s3, aux, re),
                (st["V"], sc, st["vc"], mc, n3, s3, aux, re),
                (law, dpar, d, *laws, bool(self.clo.viscous), mu_f, st["hc"], st["cw0"], self.solids_flux == "upwind"),
                (*consts, float(self.velocity_floor)))

    def _whole_args(self, k: State):
        """(the compiled whole iterate, the laws' arguments, the prescribed rows' arrays, the compiled
        laws) where one compiled call can do the iterate — compiled laws, P_s, the velocity scale and
        the assembly not replaced, n̄ an element array — else None (the kernels are then called one
        by one)."""
        laws = self.compiled_laws()
        nb = k.n_bar
        if laws is None or type(nb) is not np.ndarray or nb.shape != k.n.shape or nb.dtype != float \
                or not nb.flags.c_contiguous:
            return None
        cls = type(self)
        if cls.solids_pressure is not TwoFluid1D.solids_pressure or cls.velocity_scale is not TwoFluid1D.velocity_scale \
                or cls._assemble_compiled is not Reduced1D._assemble_compiled \
                or cls.compiled_laws is not TwoFluid1D.compiled_laws:
            return None
        hit = self.__dict__.get("_whole")
        if hit is None or hit[0] is not laws:
            ker = reduced_kernel.whole_iterate()
            if ker is None:
                hit = (laws, None)
            else:
                d = np.array(self._dir, dtype=float).reshape(-1, 3)
                consts = (d[:, 0].astype(np.int64), d[:, 1].astype(np.int64), np.ascontiguousarray(d[:, 2]),
                          np.array(self._fixed, dtype=np.int64))
                hit = (laws, (ker, laws.kernel_args(), consts, laws))
            self._whole = hit
        return hit[1]

    def _whole_iterate_ok(self) -> bool:
        """Whether :meth:`iterate` may stand for the four methods it calls (none replaced)."""
        cls = type(self)
        return (cls.assemble is Reduced1D.assemble and cls.solve is Reduced1D.solve and cls.unpack is Reduced1D.unpack
                and cls.iterate_change is TwoFluid1D.iterate_change
                and not {"assemble", "solve", "unpack", "iterate_change"} & self.__dict__.keys())

    def solve(self, S: tuple, t: float) -> np.ndarray:
        """Increment of (W, n) from the banded solve; returns [V, W, n]."""
        ab, rhs, k, st = S
        info, x = self._kernels()[2](ab, rhs), rhs  # block tridiagonal, else the band LU
        nv = self.nv
        out = np.empty(3 * nv - 1)
        if info != 0:  # singular: the stepper rejects the non-finite result and shrinks the step
            out.fill(np.nan)
            return out
        V = st["V"]
        out[:nv] = V
        np.add(k.W, x[0::2], out=out[nv:2 * nv])
        np.add(k.n, x[1::2], out=out[2 * nv:])
        for v in self._fixed:
            out[nv + v] = V[v]
        return out

    def pack(self, s: State) -> np.ndarray:
        return np.concatenate([s.V, s.W, s.n])

    def unpack(self, a: np.ndarray, like: State, t: float) -> State:
        nv = self.nv
        if type(like) is State:  # the cheap path: V, W, n are fresh slices of the solve's output; P and
            # n̄ are the iterate's own (the stepper's copy of the old state; end_step replaces P)
            return State(t, a[:nv], a[nv:2 * nv], like.P, a[2 * nv:], like.n_bar)
        return like.copy(t=t, V=a[:nv], W=a[nv:2 * nv], n=a[2 * nv:])

    def end_step(self, old: State, new: State, dt: float) -> State:
        """Recover P [Pa] per element from the liquid rows linearised about the last iterate.

        That is the liquid equation the full model's P satisfies in its last solve:
        h M(ΔV + ΔW) − ρ_f g_y ∫N + D + m_l Kv (V + W) + A [[P]] = 0, with h, m_l frozen and
        D linearised about the iterate.
        """
        last = self._last_iterate  # the same recovery as the kernels' last iterate
        nk, m_l, st = last.n, last.viscous, last.st
        P = np.empty(nk.size)
        top = self.top.kind == "outlet"
        self._kernels()[3](new.W, new.n, nk, self._last_rows, self._mc, st["sc"], self._liq_src, m_l,
                           self.vert_area, top, float(self.top.pressure if top else self.bottom.pressure), P)
        new.P = P
        self._remember(old, new, lambda s: [s.W, s.n])
        return new

    def recover_pressure(self, s: State, old: State, dt: float) -> np.ndarray:
        """Element pressures [Pa] of state ``s`` (after a step of ``dt`` from ``old``)."""
        mat, M0, M1 = self.mat, self._M0, self._M1
        V, W, n = s.V, s.W, s.n
        q = (1.0 - 2.0 * n) * np.stack([V[:-1], V[1:]]) + np.stack([W[:-1], W[1:]])
        s_abs = np.abs((q * self._wt).sum(axis=0)) / (2.0 * n * np.maximum(1.0 - n, _CLEAR))
        K = self.clo.beta_per_solids(n, s_abs, mat)
        h = (0.5 * mat.rho_f / dt) / n
        dVW = V - old.V + W - old.W
        Mq = M0 * q[0] + M1 * q[1] + (self._sig * self.bed_force_shift(old)) * (self._BNt[0] * q[0] + self._BNt[1] * q[1])
        L = h * (M0 * dVW[:-1] + M1 * dVW[1:]) + (K / (2.0 * n * n)) * Mq + self._liq_src
        if self.clo.viscous:
            VW = V + W
            L = L + (0.5 * mat.mu_f / n) * (self._kap * (VW[:-1] - VW[1:])) * np.array([[1.0], [-1.0]])
        return self._pressure_from(self._assemble_nodal(L))

    def _pressure_from(self, L: np.ndarray) -> np.ndarray:
        """Element pressures [Pa] from [[P]]_i = −L_i/A_i and the outlet pressure."""
        jump = -L / self.vert_area  # P above − P below at vertex i
        if self.top.kind == "outlet":
            return self.top.pressure - np.cumsum(jump[1:][::-1])[::-1]
        return self.bottom.pressure + np.cumsum(jump[:-1])
