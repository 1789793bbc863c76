"""The 1D two-component model: unknowns V, W (nodal), P, n (per element).

Equations (docs/model.md, "Governing equations"), y along the line, g_y = −g cos θ the gravity along it:

- mixture, tested with δV:  ∂t(ρ̂V − ΔρW) = −∂y(P + P_s) + ∂y τ + ρ̄ g_y
- liquid, tested with δW/n: (ρ_f/2n) ∂t(V + W) = −∂yP + (1/n) ∂y(n τ_f) + ρ_f g_y − β s/n
- continuity, tested with δP:  ∇·V = 0
- porosity, tested with δn:   2 ∂t n + ∇·W = 0

with the slip s = U_f − U_s = [(1 − 2n)V + W] / (2n(1 − n)). ``assemble`` builds the
backward-Euler system [M/Δt + K(aᵏ)] aᵏ⁺¹ = f + M aᵗ/Δt of one iterate: the drag
(in V, W and n) and the upwind ratio are Newton-linearised about iterate k, P_s is
Taylor-linearised about it (Pringle 2001 eqs. 4.31–4.32), ρ̄ is implicit in n. With
``linearisation = "newton"`` (default) μ_s(n) and the 1/n weights of the liquid
inertia and viscous terms are Newton-linearised too (finite difference in n for
μ_s), so every term is, and the iterates converge quadratically; ``"picard"``
freezes them at k and starts every step from the last state, the thesis's Picard
iteration (and this code's before 2026-12), kept as the reference path: it
converges only linearly. Both have the same fixed point, the discrete equations.
With ``"newton"`` the first iterate of a step is extrapolated from the last
converged steps (:class:`~twofluid.models.extrapolation.Extrapolator`, V, W and n),
and each iterate is one band LU solve for the increment from the iterate
(:mod:`twofluid.fem.banded`; without it, a slowly settling column with 300
elements stalled at the solve's round-off, 2e-7 of the velocity scale, above the
Picard tolerance, and hit the iteration limit again and again). The iterate of the
``1VW/0P/0n`` element with ``"newton"`` — its terms written straight into band storage, the
residual, the band LU — runs as compiled kernels around the same closure calls
(:mod:`~twofluid.models.full_kernel`), a quarter to a half of the CPU time per step of the
general weak-form assembly (:mod:`twofluid.fem.terms_1d` into a
:class:`~twofluid.fem.assembly.BlockSystem`). That assembly is the only one of the quadratic
element and of ``"picard"``; ``compiled = False`` puts the linear element on it too, which is
how the tests check the kernels against an independent derivation of the same equations.

Pressure gradients (P constant per element): the mixture term is integrated by
parts, −∫ ∇·δV (P + P_s), plus the traction of the prescribed pressure on an
outlet. The liquid equation is tested per unit liquid volume (δW/n, n constant
per element), so its pressure term is the plain jump A [[P]] at each vertex and
its other terms carry 1/n. This is the n∇P of docs/model.md with the porosity moved to the
other side: it is gauge invariant (only jumps of P appear), a settled bed with a
porosity gradient is an exact discrete equilibrium (hydrostatic P), and — which
the ``n_f A [[P]]`` form with averaged vertex porosity is not — so is a uniform
fluidized bed with a free surface: each half-element contributes its own
pressure gradient ρ_f g − βs/n to the jump. ``2VW/1P/0n`` has a linear pressure
per element, discontinuous between elements (P1-disc.): its liquid term is
∫ δW ∂yP dΩ inside the elements plus the same vertex jumps, and its quadratic V
is then exactly divergence free (a continuous linear P constrains ∇·V only
weakly, and the spurious mixture-velocity wiggles drive porosity oscillations).

Solids flux (``solids_flux = "upwind"``, default): the porosity equation uses the
vertex solids flux F = (V − W)/2 scaled by (1 − n_up)/(1 − n_f), n_up the porosity
of the element the solids come from (clear liquid outside an outlet), n_f the
volume-weighted vertex average. It equals the Galerkin form where the porosity
is uniform and keeps an element from giving away solids it does not hold
(docs/model.md, "Numerical hygiene"), e.g. at a descending bed surface. ``"galerkin"`` is the thesis's form.

Bed forces (``1VW/0P/0n``): the buoyant weight of the solids and the drag are tested
with upwind functions ψ = N ∓ αB, not the hat functions (``force_shift``): with hat
functions a vertex sees only the mean of its two elements' forces, which lets an
odd–even porosity mode stand in a fluidized bed (docs/model.md).

The model inherits the two-fluid model's instability of uniform fluidization
(Jackson 1963): without granular-pressure elasticity (P_s ≈ 0 in a fluidized
bed) small porosity disturbances grow, fastest at the shortest wavelengths the
mesh carries. The thesis saw it as oscillations behind fronts (its 4.6.1, 5.1.1).
"""
from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..closures import kernels as closure_kernels
from ..closures.viscosity import solid_viscosity
from ..fem import terms_1d as terms
from ..fem.assembly import BlockSystem
from ..fem.banded import BandSolver
from ..fem.line import LINE1, LINE2, element_values
from ..mesh.line import LineMesh
from ..timestepping.backward_euler import relative_change
from . import full_iterate, full_kernel, full_step, reduced_kernel
from .bed_forces_1d import _CLEAR, UpwindBedForces
from .data_1d import Boundary, Closures, Materials, State, _times
from .diagnostics_1d import LineDiagnostics
from .extrapolation import Extrapolator

__all__ = ["Materials", "Closures", "Boundary", "State", "TwoFluid1D", "ELEMENTS"]

ELEMENTS = {"1VW/0P/0n": (LINE1, 0), "2VW/1P/0n": (LINE2, 1)}
# the methods whose equations the compiled iterate (full_kernel) reproduces: a subclass overriding
# one of them takes the general weak-form assembly
_KERNEL_METHODS = ("assemble", "solve", "_step_terms", "_drag", "_liquid_pressure", "_solids_flux",
                   "_upwind_ratio", "_newton_in_n", "psi_mass", "psi_source", "_force_shift_at", "force_shift",
                   "vertex_porosity", "pack", "unpack")


class TwoFluid1D(UpwindBedForces, LineDiagnostics):
    """Assembles and solves the 1D two-component equations on a LineMesh.

    ``compiled`` (class attribute, may be set per instance): None (default) or True assembles
    and solves each iterate of the ``1VW/0P/0n`` element with the Newton linearisation by the
    kernels of :mod:`~twofluid.models.full_kernel`, and the other elements' band systems
    with the compiled band LU of :mod:`twofluid.fem.banded`; False always takes the general
    weak-form assembly and LAPACK's ``dgbsv`` (the tests' independent second path: the same
    band matrix and right-hand side to round-off). A subclass that overrides a method of the
    equations (e.g. to add a load term to the assembled system) takes the general assembly. The
    iterates also call the run's drag, P_s and μ_s laws compiled, and so does
    :meth:`solids_pressure` everywhere (:meth:`compiled_laws`; a few ulp from the registry's
    functions), unless ``compiled`` or ``compiled_closures`` is False.
    """

    compiled: bool | None = None
    compiled_closures: bool = True  # False: the compiled iterates call the registry's closures (tests)
    velocity_floor = 1e-6  # [m/s] the floor of velocity_scale

    # with linearisation "newton" the iterates are Newton's: the stepper may accept one on its predicted error
    newton_iterates = property(lambda self: self.linearisation == "newton")

    def __init__(self, mesh: LineMesh, materials: Materials, closures: Closures,
                 bottom: Boundary, top: Boundary, element: str = "1VW/0P/0n",
                 solids_flux: str = "upwind", linearisation: str = "newton",
                 bed_forces: str = "upwind"):
        if element not in ELEMENTS:
            raise ValueError(f"element must be one of {list(ELEMENTS)}")
        if linearisation not in ("newton", "picard"):
            raise ValueError(f"linearisation must be 'newton' or 'picard', got {linearisation!r}")
        self.linearisation = linearisation
        if "outlet" not in (bottom.kind, top.kind):
            raise ValueError("at least one end must be an outlet (it fixes the pressure datum)")
        self.mesh, self.mat, self.clo = mesh, materials, closures
        self.bottom, self.top = bottom, top
        self.element, self.solids_flux = element, solids_flux
        if bed_forces not in ("upwind", "galerkin"):
            raise ValueError("bed_forces must be 'upwind' or 'galerkin'")
        self.bed_forces = bed_forces  # "galerkin": hat-function tests (the 2D model's form), for comparisons
        self.basis, self.p_order = ELEMENTS[element]
        ne = mesh.n_elements
        self.nv = self.basis.n_nodes(ne)
        self.np = ne if self.p_order == 0 else 2 * ne  # P0, or linear P discontinuous between elements
        self.sizes = {"V": self.nv, "W": self.nv, "P": self.np, "n": ne}
        self.g_y = mesh.gravity_along(materials.g)
        self._precompute()
        self._extrap = Extrapolator()  # V, W, n of the last converged steps, for the first iterate
        # unknowns numbered along the line for the band solve: velocity node i at i/p, element e's P and n at e + ½
        p = self.basis.order
        ecentre = np.arange(ne) + 0.5
        pos_p = ecentre if self.p_order == 0 else np.repeat(ecentre, 2)
        node = np.arange(self.nv) / p
        self._pattern = {}  # global indices of the element blocks, the same at every iterate
        self._step_full = None  # the terms of the current step that do not depend on the iterate
        self._stacked_mat = None  # materials with per-element arrays repeated (per count), for the fused closure calls
        self._M_twice = None  # the mass matrices twice over, for the fused drag call of ``bed_force_shift``
        self._B0T = -np.swapaxes(self.B0, 1, 2)  # (ne, nl, 1): −∫ ∇·N_i dΩ
        e = self._elements = np.arange(ne)
        vn = self.vert_node
        self._flux_maps = (np.concatenate((e, e)), np.concatenate((vn[1:], vn[:-1])),  # n rows: V, W at vertices
                           np.concatenate((e[1:], e, e[:-1])), np.concatenate((e[:-1], e, e[1:])))  # n_{e−1}, n_e, n_{e+1}
        self._band = BandSolver(np.concatenate([node, node, pos_p, ecentre]))
        # the compiled iterate (full_kernel): the element, the Newton linearisation, scalar densities
        # and viscosity, and the equations of this class (a subclass that adds terms takes the general assembly)
        self._fk_ok = (element == "1VW/0P/0n" and linearisation == "newton" and self.BN is not None
                       and all(np.ndim(getattr(materials, f)) == 0 for f in ("rho_f", "rho_s", "mu_f", "g"))
                       and all(getattr(type(self), f) is getattr(TwoFluid1D, f) for f in _KERNEL_METHODS))
        self._fk = self._fk_step = self._fk_below = self._fk_fixed = None

    # ------------------------------------------------------------------ setup
    def _precompute(self):
        mesh, ne = self.mesh, self.mesh.n_elements
        ev = element_values(mesh, self.basis, n_quad=4)
        self.ev = ev
        self.vdofs = self.basis.dofs(ne)
        self.edofs = np.arange(ne)[:, None]
        self.M = terms.mass(ev)
        self.Kvis = terms.diffusion(ev, 4.0 / 3.0)
        self.src = terms.source(ev)  # ∫ N_i dΩ
        ones = np.ones((ev.N.shape[0], 1))
        self.B0 = terms.divergence(ev, ones)  # (ne, 1, nl): ∫ ∇·N_j dΩ
        if self.p_order == 0:
            self.pdofs = self.edofs
            self.Bp = self.B0
        else:
            pb = LINE1
            x, _ = np.polynomial.legendre.leggauss(4)
            xi = 0.5 * (x + 1.0)
            self.pdofs = np.arange(2 * ne).reshape(ne, 2)  # (bottom, top) values of each element
            self.Bp = terms.divergence(ev, pb.shape(xi))
            dq = pb.dshape(xi)[None, :, :] / mesh.lengths[:, None, None]
            self.Gp = terms.weighted_gradient(ev, np.broadcast_to(dq, (ne, len(xi), 2)))
        # vertex bookkeeping: vertex i is velocity node p*i; element below / above
        p = self.basis.order
        self.vert_node = p * np.arange(ne + 1)
        self._vert_at = slice(None) if p == 1 else self.vert_node  # the vertices' entries of a nodal array (a view where all)
        last = self.basis.n_local - 1
        w_below = np.zeros(ne + 1)
        w_above = np.zeros(ne + 1)
        w_below[1:] = self.src[:, last]
        w_above[:-1] = self.src[:, 0]
        self.w_below, self.w_above = w_below, w_above
        self.vert_area = mesh.area
        # pressure dof just below / just above each vertex (element value or end value)
        if self.p_order == 0:
            self.p_below, self.p_above = np.arange(-1, ne), np.arange(0, ne + 1)
        else:
            self.p_below, self.p_above = np.arange(-1, 2 * ne, 2), np.arange(0, 2 * ne + 1, 2)
        self.volumes = mesh.volumes
        if p == 1:
            # upwind test functions ψ = N ∓ α B of the bed forces (``force_shift``): B = 6ξ(1 − ξ)
            # integrates to one over the reference element; BN = ∫ B N_j dΩ (both halves: B q̄ vol)
            xq, _ = np.polynomial.legendre.leggauss(4)
            xq = 0.5 * (xq + 1.0)
            self.BN = terms.source(ev, np.broadcast_to(6.0 * xq * (1.0 - xq), ev.JxW.shape))
        else:
            self.BN = None  # the quadratic element keeps the Galerkin forces
        self.avg_weights = ev.N.T @ (ev.JxW / ev.JxW.sum(axis=1, keepdims=True)).T  # (nl, ne)

    # --------------------------------------------------------------- helpers
    def element_mean(self, nodal: np.ndarray, at: np.ndarray | None = None) -> np.ndarray:
        """Volume average over each element of a nodal field (over the elements ``at`` only, if given)."""
        if at is None:
            return np.einsum("ei,ie->e", nodal[self.vdofs], self.avg_weights)
        hit = self.__dict__.get("_mean_at")
        if hit is None or hit[0] is not at or hit[1] is not self.vdofs or hit[2] is not self.avg_weights:
            if type(at) is not np.ndarray or at.flags.writeable:
                return np.einsum("ei,ie->e", nodal[self.vdofs[at]], self.avg_weights[:, at])
            # a read-only ``at`` (the probes' elements, asked at every row): its dofs and weights kept while it,
            # the dofs and the weights are the same arrays (the same einsum of the same entries)
            hit = self._mean_at = (at, self.vdofs, self.avg_weights, self.vdofs[at], self.avg_weights[:, at])
        return np.einsum("ei,ie->e", nodal[hit[3]], hit[4])

    def slip(self, V, W, n) -> np.ndarray:
        """Element slip U_f − U_s [m/s], with 1 − n floored at ``_CLEAR`` (continuous as n → 1).

        In clear liquid the drag only ties V to W, driving the slip to zero; the
        floor keeps the slip finite and continuous where an element empties.
        """
        v, w = self.element_mean(V), self.element_mean(W)
        return ((1.0 - 2.0 * n) * v + w) / (2.0 * n * np.maximum(1.0 - n, _CLEAR))

    def vertex_porosity(self, n: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(n_below, n_above, n_f) at vertices; outside the domain counts as clear liquid."""
        nb = np.concatenate([[1.0], n])
        na = np.concatenate([n, [1.0]])
        wb, wa = self.w_below, self.w_above
        nf = (wb * nb + wa * na) / (wb + wa)
        return nb, na, nf

    def solids_pressure(self, n, n_bar, derivative=False):
        """P_s(n, n̄) [Pa] (and ∂P_s/∂n) of the run's law: compiled (:meth:`compiled_laws`) for
        element arrays where it is, else the registry's (the general assembly always)."""
        laws = self.compiled_laws()
        if laws is not None and type(n) is np.ndarray and n.ndim == 1 and np.shape(n_bar) == n.shape:
            ps, dps = laws.solids_pressure(n, n_bar)
            return (ps, dps) if derivative else ps
        return self.clo.solids_pressure(n, n_bar, self.mat, derivative=derivative)

    def inlet_value(self, b: Boundary, t: float, sign: float) -> float:
        return sign * b.velocity(t) if b.kind == "inlet" else 0.0

    def dirichlet(self, t: float) -> tuple[np.ndarray, np.ndarray]:
        """Global indices (into the full system) and values of prescribed V and W (kept for the last t;
        the indices one array while the ends are the same objects, which callers read, never write)."""
        last = getattr(self, "_dirichlet_of", None)
        if last is not None and last[0] == t:
            return last[1], last[2]
        held = getattr(self, "_dirichlet_idx", None)
        if held is None or held[0] is not self.bottom or held[1] is not self.top or held[2] != self.nv:
            idx, fixed = [], []
            for b, node, sign in ((self.bottom, 0, 1.0), (self.top, self.nv - 1, -1.0)):
                if b.kind in ("inlet", "wall"):
                    idx += [node, self.nv + node]
                    fixed.append((b, sign))
            held = self._dirichlet_idx = (self.bottom, self.top, self.nv, np.array(idx, dtype=int), tuple(fixed))
        val = []
        for b, sign in held[4]:  # (the ends with prescribed V and W)
            u = self.inlet_value(b, t, sign)
            val += [u, u]
        idx, val = held[3], np.array(val, dtype=float)
        self._dirichlet_of = (t, idx, val)
        return idx, val

    # -------------------------------------------------------------- assembly
    def _full_kernels(self) -> dict | None:
        """The kernels of the iterate (:mod:`~twofluid.models.full_kernel`), or None for the general
        assembly (``compiled`` False, or an element, linearisation or subclass they do not cover)."""
        if self.compiled is False or not self._fk_ok:
            return None
        ker = self._fk
        if ker is None:
            ker = full_kernel.kernels() or {}
            if ker:
                self._fk_constants = full_kernel.constants(self)
            self._fk = ker
        return ker or None

    def assemble(self, k: State, old: State, dt: float, t_new: float):
        """Matrix and right-hand side of one Picard iterate (see module docstring): a
        :class:`~twofluid.fem.assembly.BlockSystem`, or with the compiled kernels a
        :class:`~twofluid.models.full_kernel.BandIterate` (the same ``matrix()`` and ``rhs``)."""
        ker = self._full_kernels()
        if ker is not None:
            return full_kernel.assemble(self, ker, k, old, dt, t_new)
        mat, clo = self.mat, self.clo
        S = self._step_terms(old, dt, t_new).copy()
        S.iterate = self.pack(k)  # the linearisation point (the band solve is for the increment from it)
        vd, ed = self.vdofs, self.edofs
        n = k.n
        M, Kv = self.M, self.Kvis
        newton = self.linearisation == "newton"
        # liquid inertia per unit liquid volume h M(V + W), h = ρ_f/(2nΔt); Newton: ∂/∂n = −h/n M(ΔV + ΔW)
        h = 0.5 * mat.rho_f / dt / n
        hM = h[:, None, None] * M
        S.add("W", "V", vd, vd, hM)
        S.add("W", "W", vd, vd, hM)
        S.add_rhs("W", vd, h[:, None] * self._step_full["M_VWold"])
        if newton:
            dW_dn = (np.einsum("eij,ej->ei", M, k.V[vd] + k.W[vd]) - self._step_full["M_VWold"]) * (-h / n)[:, None]
        if clo.viscous:
            if newton:  # μ_s at n and n + δn in one call (δn away from n = 0 and 1)
                dn = 1e-8 * np.where(n < 0.5, 1.0, -1.0)
                mu2 = solid_viscosity(np.concatenate((n, n + dn)), self._materials_times(2).mu_f,
                                      **_times(clo.viscosity_params, n.size, 2))
                mu_s = mu2[:n.size]
            else:
                mu_s = solid_viscosity(n, mat.mu_f, **clo.viscosity_params)
            S.add("V", "V", vd, vd, 0.5 * (mat.mu_f + mu_s)[:, None, None] * Kv)
            S.add("V", "W", vd, vd, 0.5 * (mat.mu_f - mu_s)[:, None, None] * Kv)
            ml = (0.5 * mat.mu_f / n)[:, None, None] * Kv
            S.add("W", "V", vd, vd, ml)
            S.add("W", "W", vd, vd, ml)
            if newton:  # μ_s(n) by the finite difference; the viscous 1/n exactly
                dmu = (mu2[n.size:] - mu_s) / dn
                Vk, Wk = k.V[vd], k.W[vd]
                self._newton_in_n(S, "V", k, 0.5 * dmu[:, None] * np.einsum("eij,ej->ei", Kv, Vk - Wk))
                dW_dn -= (0.5 * mat.mu_f / (n * n))[:, None] * np.einsum("eij,ej->ei", Kv, Vk + Wk)
        if newton:
            self._newton_in_n(S, "W", k, dW_dn)
        ps, dps = self.solids_pressure(n, k.n_bar, derivative=True)
        B0T = self._B0T  # (ne, nl, 1)
        S.add("V", "n", vd, ed, B0T * dps[:, None, None])
        S.add_rhs("V", vd, -B0T[:, :, 0] * (ps - dps * n)[:, None])
        self._drag(S, k, self._step_full["M_psi"])
        self._liquid_pressure(S, n, k.P)
        self._solids_flux(S, k)
        return S

    def iterate(self, k: State, old: State, dt: float, t_new: float):
        """:meth:`assemble`, :meth:`solve`, :meth:`unpack` and :meth:`iterate_change` in one call where
        the kernels assemble the iterate (:mod:`~twofluid.models.full_iterate`), else None."""
        ker = self._full_kernels()
        return None if ker is None else full_iterate.iterate(self, ker, k, old, dt, t_new)

    def compiled_step(self, old: State, dt: float, settings):
        """The stepper's first try at a step in one compiled call (:mod:`~twofluid.models.full_step`):
        (the new state, its iterations, whether a prediction accepted it), or None."""
        return full_step.step(self, old, dt, settings)

    def _step_terms(self, old: State, dt: float, t_new: float) -> BlockSystem:
        """The terms of a step that do not depend on the iterate (assembled once per step)."""
        st = self._step_full
        if st is not None and st["old"] is old and st["dt"] == dt and st["t"] == t_new:
            return st["S"]
        mat = self.mat
        S = BlockSystem(self.sizes, self._pattern)
        vd, ed, pd = self.vdofs, self.edofs, self.pdofs
        rho_hat = 0.5 * (mat.rho_s + mat.rho_f)
        d_rho = 0.5 * (mat.rho_s - mat.rho_f)
        M, src = self.M, self.src
        Vold, Wold = old.V[vd], old.W[vd]
        # mixture (rows V): inertia, −∫ ∇·δV P, weight ρ̄ g_y with ρ̄ implicit in n
        S.add("V", "V", vd, vd, rho_hat / dt * M)
        S.add("V", "W", vd, vd, -d_rho / dt * M)
        S.add_rhs("V", vd, np.einsum("eij,ej->ei", M, rho_hat * Vold - d_rho * Wold) / dt)
        S.add("V", "P", vd, pd, -np.swapaxes(self.Bp, 1, 2))
        # weight: ρ_f g_y with N (hydrostatic), the buoyant weight (1 − n)(ρ_s − ρ_f) g_y with ψ like
        # the drag; the upwind shares α are those of the step's old state (``bed_force_shift``)
        alpha = self.bed_force_shift(old)
        src_psi = self.psi_source(alpha)
        S.add_rhs("V", vd, mat.rho_f * self.g_y * src)
        S.add("V", "n", vd, ed, ((mat.rho_s - mat.rho_f) * self.g_y * src_psi)[:, :, None])
        S.add_rhs("V", vd, (mat.rho_s - mat.rho_f) * self.g_y * src_psi)
        # liquid (rows W), per unit liquid volume: tested with δW/n (see module docstring)
        S.add_rhs("W", vd, mat.rho_f * self.g_y * src)
        # continuity (rows P) and porosity (rows n)
        S.add("P", "V", pd, vd, self.Bp)
        S.add("n", "n", ed, ed, (2.0 * self.volumes / dt)[:, None, None])
        S.add_rhs("n", ed[:, 0], 2.0 * self.volumes / dt * old.n)
        # prescribed pressure on outlets: traction in the mixture row
        for b, v, sign in ((self.bottom, 0, -1.0), (self.top, self.mesh.n_elements, 1.0)):
            if b.kind == "outlet":
                S.add_rhs("V", np.array([self.vert_node[v]]), np.array([-sign * b.pressure * self.vert_area[v]]))
        S.rhs  # scatter the right-hand side once
        self._step_full = {"old": old, "dt": dt, "t": t_new, "S": S, "M_psi": self.psi_mass(alpha),
                      "M_VWold": np.einsum("eij,ej->ei", M, Vold + Wold)}
        return S

    def compiled_laws(self):
        """The run's drag, P_s and μ_s laws compiled (:func:`twofluid.closures.kernels.for_closures`),
        which the compiled iterates call in place of the registry functions; None where there are
        none (another law), and on the general assembly (``compiled = False``). Kept while
        ``clo`` and ``mat`` are the same objects."""
        if self.compiled is False or not self.compiled_closures:
            return None
        hit = self.__dict__.get("_laws")
        if hit is None or hit[0] is not self.clo or hit[1] is not self.mat:
            hit = self._laws = (self.clo, self.mat, closure_kernels.for_closures(self.clo, self.mat))
        return hit[2]

    def _materials_times(self, reps: int) -> Materials:
        """The materials for a closure call on ``reps`` stacked copies of the element arrays
        (per-element properties, e.g. of a layered site, repeated; kept while ``self.mat`` is)."""
        cache = self._stacked_mat  # {reps: (the materials they came from, the stacked materials)}
        if cache is None:
            cache = self._stacked_mat = {}
        hit = cache.get(reps)
        if hit is None or hit[0] is not self.mat:
            ne = self.mesh.n_elements
            fields = {f: getattr(self.mat, f) for f in ("rho_f", "mu_f", "rho_s", "d_p", "sphericity", "g")}
            hit = cache[reps] = (self.mat, replace(self.mat, **_times(fields, ne, reps)))
        return hit[1]

    def _newton_in_n(self, S: BlockSystem, row: str, k: State, d: np.ndarray) -> None:
        """Add the Newton term d (n − nᵏ) of element vectors d = ∂R/∂n_e (n_el, nl) to rows ``row``."""
        S.add(row, "n", self.vdofs, self.edofs, d[:, :, None])
        S.add_rhs(row, self.vdofs, d * k.n[:, None])

    def _drag(self, S: BlockSystem, k: State, M: np.ndarray):
        """β s tested with δW (upwind ψ: ``M`` = Mψ of the step's shift), Newton-linearised about iterate k.

        D = K(n, |s̄|) Mψ q / (2n²), Mψ = ∫ ψ_i N_j dΩ, K = β/(1−n), q = (1−2n)V + W, s̄ = q̄/(2n(1−n)) the
        element-mean slip. The V, W derivatives are exact (with the element mean
        q̄ = w·q); the n derivative is a finite difference per element. The drag law is
        called once, at (n, |s|), (n, |s| + δs) and (n + δn, |s(n + δn)|).
        """
        vd, ed, n, wts = self.vdofs, self.edofs, k.n, self.avg_weights
        V = k.V[vd]
        dn = 1e-8 * np.where(n < 0.5, 1.0, -1.0)
        qk = (1.0 - 2.0 * n)[:, None] * V + k.W[vd]
        qn = qk - (2.0 * dn)[:, None] * V  # q at n + δn
        qbar = np.einsum("ei,ie->e", qk, wts)
        nn = n + dn
        s_abs = np.abs(qbar) / (2.0 * n * np.maximum(1.0 - n, _CLEAR))
        s_n = np.abs(np.einsum("ei,ie->e", qn, wts)) / (2.0 * nn * np.maximum(1.0 - nn, _CLEAR))
        ds = 1e-6 * np.maximum(s_abs, 1e-6)
        K3 = self.clo.beta_per_solids(np.concatenate((n, n, nn)), np.concatenate((s_abs, s_abs + ds, s_n)),
                                      self._materials_times(3)).reshape(3, -1)
        K0 = K3[0]
        dK = (K3[1] - K0) / ds * s_abs  # K'|s|
        gain = np.where(np.abs(qbar) > 0.0, dK / np.where(qbar != 0.0, qbar, 1.0), 0.0)
        Mq = np.einsum("eij,ej->ei", M, qk)
        c0 = K0 / (2.0 * n * n)
        D0 = c0[:, None] * Mq
        Jn = ((K3[2] / (2.0 * nn * nn))[:, None] * np.einsum("eij,ej->ei", M, qn) - D0) / dn[:, None]
        Jq = c0[:, None, None] * M + (gain / (2.0 * n * n))[:, None, None] * Mq[:, :, None] * wts.T[:, None, :]
        JV = (1.0 - 2.0 * n)[:, None, None] * Jq
        S.add("W", "V", vd, vd, JV)
        S.add("W", "W", vd, vd, Jq)
        S.add("W", "n", vd, ed, Jn[:, :, None])
        S.add_rhs("W", vd, np.einsum("eij,ej->ei", Jq, qk) + Jn * n[:, None] - D0)  # J·xᵏ = Jq qᵏ

    def _liquid_pressure(self, S: BlockSystem, n: np.ndarray, P: np.ndarray):
        """∂P/∂y tested with δW (the liquid equation per unit liquid volume).

        The distributional gradient of the element-wise pressure: ∫ δW ∂yP inside
        the elements (linear P only) plus A [[P]] at the vertices, where an outlet
        jumps to its prescribed pressure.
        """
        if self.p_order == 1:
            S.add("W", "P", self.vdofs, self.pdofs, self.Gp)
        ne = self.mesh.n_elements
        coef = self.vert_area
        node = self.vert_node
        inner = np.arange(1, ne)
        # [[P]] = P_above − P_below at inner vertices
        S.add_entries("W", "P", node[inner], self.p_above[inner], coef[inner])
        S.add_entries("W", "P", node[inner], self.p_below[inner], -coef[inner])
        for b, v, dof, sign in ((self.bottom, 0, self.p_above[0], 1.0),
                                (self.top, ne, self.p_below[ne], -1.0)):
            if b.kind == "outlet":
                # jump to the prescribed pressure outside: element side carries sign
                S.add_entries("W", "P", [node[v]], [dof], [sign * coef[v]])
                S.add_rhs("W", np.array([node[v]]), np.array([sign * coef[v] * b.pressure]))

    def begin_iteration(self, it: int, k: State) -> None:
        """Picard hook: extrapolated first iterate; fix the upwind side after the third iteration.

        Deciding the upwind side from the iterates of iterations 1 to 3 (``it <= 3``) and
        keeping it for the rest of the step stops a flux that is nearly zero from flipping
        the upwind side at every iteration. The third iterate, not the second: at the
        surface of an expanding bed the small solids flux into the dilute element above
        it can still have the wrong sign in the second iterate, and differently so in
        the full model's Picard iterates and the reduced model's Newton iterates.
        """
        if it == 1 and self.linearisation == "newton":
            self._first_iterate(k)
        if it <= 3:
            at = self._vert_at
            self._below = (k.V[at] - k.W[at]) >= 0.0

    def _first_iterate(self, k: State) -> None:
        """Start a step from the last converged state ``k`` at the extrapolation of V, W, n
        (n kept in (0, 1]); any other starting state is left as it is."""
        ex = self._extrap
        if ex.order >= 2 and k.t > ex.t:
            DV, DW, Dn = ex.D
            if (k.n == Dn[0]).all() and (k.W == DW[0]).all() and (k.V == DV[0]).all():
                ex.predict(k.t, out=(k.V, k.W, k.n))  # into k's arrays
                np.clip(k.n, _CLEAR, 1.0, out=k.n)

    def _remember(self, old: State, new: State, fields) -> None:
        """Add the converged step old → new to the extrapolation table (``fields(state)``: its arrays)."""
        ex = self._extrap
        if ex.state is old and ex.t == old.t:  # a continuation of the steps in the table
            ex.push(new.t, fields(new), new)
        else:
            ex.push(new.t, fields(new), new, old.t, fields(old))

    def _upwind_ratio(self, n: np.ndarray, F: np.ndarray, below: np.ndarray | None = None):
        """r = (1 − n_up)/(1 − n_f) at vertices and its derivatives in n_below, n_above."""
        nb, na, nf = self.vertex_porosity(n)
        if below is None:
            below = F >= 0.0
        n_up = np.where(below, nb, na)
        one_f = 1.0 - nf
        ok = one_f > _CLEAR
        inv = np.where(ok, 1.0 / np.where(ok, one_f, 1.0), 0.0)
        r = (1.0 - n_up) * inv
        tb = self.w_below / (self.w_below + self.w_above)
        dr_b = np.where(below, -inv, 0.0) + r * inv * tb
        dr_a = np.where(below, 0.0, -inv) + r * inv * (1.0 - tb)
        dr_b[0] = 0.0  # outside the domain the porosity is fixed
        dr_a[-1] = 0.0
        return r, dr_b, dr_a

    def _solids_flux(self, S: BlockSystem, k: State):
        """∇·W tested with δn, written with the vertex solids flux F = (V − W)/2.

        Element e gains solids through its bottom vertex e and loses them through
        its top vertex e+1: 2 Vol ṅ_e − [2 A r F]_bottom^top = 0 (r = 1: Galerkin).
        The upwind ratio r(n) is Newton-linearised about iterate k.
        """
        ne = self.mesh.n_elements
        node = self.vert_node
        Fk = 0.5 * (k.V[node] - k.W[node])
        if self.solids_flux == "upwind":
            r, dr_b, dr_a = self._upwind_ratio(k.n, Fk, getattr(self, "_below", None))
        else:
            r, dr_b, dr_a = np.ones(ne + 1), np.zeros(ne + 1), np.zeros(ne + 1)
        a = self.vert_area * r
        # element e: + through its bottom vertex e, − through its top vertex e + 1 (static index maps)
        rows2, cols2, rows3, cols3 = self._flux_maps
        S.add_entries("n", "V", rows2, cols2, np.concatenate((-a[1:], a[:-1])))
        S.add_entries("n", "W", rows2, cols2, np.concatenate((a[1:], -a[:-1])))
        # Newton in r: g_v dr/dn of the elements either side of vertex v, g = ±2 A F (bottom +, top −)
        g = 2.0 * self.vert_area * Fk
        below = g[:-1] * dr_b[:-1]  # ∂/∂n_{e−1} (bottom vertex; dr_b[0] = 0 outside)
        diag = g[:-1] * dr_a[:-1] - g[1:] * dr_b[1:]  # ∂/∂n_e
        above = -g[1:] * dr_a[1:]  # ∂/∂n_{e+1} (top vertex; dr_a[ne] = 0 outside)
        S.add_entries("n", "n", rows3, cols3, np.concatenate((below[1:], diag, above[:-1])))
        n = k.n
        rhs = diag * n
        rhs[1:] += below[1:] * n[:-1]
        rhs[:-1] += above[:-1] * n[1:]
        S.add_rhs("n", self._elements, rhs)

    # ------------------------------------------------ interface to the stepper
    def solve(self, S: BlockSystem, t: float) -> np.ndarray:
        """The iterate's solution by band LU for the increment from the iterate (:mod:`twofluid.fem.banded`)."""
        if isinstance(S, full_kernel.BandIterate):
            return full_kernel.solve(self, self._fk, S, t)
        idx, val = self.dirichlet(t)
        return self._band.solve(S, S.iterate, idx, val, compiled=self.compiled is not False)

    def pack(self, s: State) -> np.ndarray:
        return np.concatenate([s.V, s.W, s.P, s.n])

    def unpack(self, a: np.ndarray, like: State, t: float) -> State:
        nv, np_ = self.nv, self.np
        if type(like) is State:  # the cheap path: V, W, P, n are fresh slices of the solve's output, n̄ the
            # iterate's own (the stepper's copy of the old state)
            return State(t, a[:nv], a[nv:2 * nv], a[2 * nv:2 * nv + np_], a[2 * nv + np_:], like.n_bar)
        return like.copy(t=t, V=a[:nv], W=a[nv:2 * nv], P=a[2 * nv:2 * nv + np_],
                         n=a[2 * nv + np_:])

    def check(self, s: State) -> str | None:
        """Why a state is not admissible (porosity outside (0, 1]), or None."""
        ker = reduced_kernel.common_kernels() if self.compiled is not False else None
        if ker is not None and ker["state_check"](s.n, s.V) == 0:  # one compiled pass of the tests below
            return None
        if not np.all(np.isfinite(s.n)) or not np.all(np.isfinite(s.V)):
            return "non-finite values"
        if s.n.min() <= 0.0:
            return f"porosity {s.n.min():.6g} <= 0 in element {int(s.n.argmin())}"
        if s.n.max() > 1.0 + 1e-9:
            hint = " (the galerkin solids flux cannot follow a free surface; use 'upwind')" \
                if self.solids_flux == "galerkin" else ""
            return f"porosity {s.n.max():.12g} > 1 in element {int(s.n.argmax())}{hint}"
        return None

    def velocity_scale(self, s: State) -> float:
        """max(|V|, |W|, ``velocity_floor``) [m/s]: the scale of the Picard test's velocity change."""
        return max(float(np.abs(s.V).max()), float(np.abs(s.W).max()), self.velocity_floor)

    def iterate_change(self, a: np.ndarray, new: State, k: State) -> tuple[bool, float, float]:
        """(whether the solve's output ``a`` is finite, max |Δn|, max(|ΔV|, |ΔW|)/velocity scale) of
        iterate ``new`` after ``k``: the stepper's test of an iterate
        (:func:`~twofluid.timestepping.backward_euler.relative_change`, the same numbers), in one
        compiled pass where the kernels are."""
        ker = reduced_kernel.common_kernels() if self.compiled is not False else None
        if ker is None or type(self).velocity_scale is not TwoFluid1D.velocity_scale:
            if not np.all(np.isfinite(a)):
                return False, np.nan, np.nan
            return (True, *relative_change(self, new, k))
        out = np.empty(3)
        ker["iterate_change"](a, new.V, new.W, new.n, k.V, k.W, k.n, float(self.velocity_floor), out)
        return out[0] != 0.0, float(out[1]), float(out[2])

    def end_step(self, old: State, new: State, dt: float) -> State:
        """Hook after a converged step (state variables such as n̄ update here; the step joins the
        extrapolation table)."""
        self._remember(old, new, lambda s: [s.V, s.W, s.n])
        return new
