"""The 2D / axisymmetric two-component model 2DQ1: V, W bilinear; P, n constant per element.

The 1D model's discrete formulation (:mod:`twofluid.models.two_fluid_1d`) carried to
quadrilaterals, planar (x, y) or axisymmetric (r, z) with an optional swirl
component; gravity along −y (−z). Rows, each of one Picard/Newton iterate of
backward Euler (docs/model.md, "Governing equations" and "Time integration"):

- mixture (δV): ∂t(ρ̂V − ΔρW) − ∇·τ_m + ∇(P + P_s) = ρ̄ g, pressures integrated by
  parts, −∫∇·δV (P + P_s) plus the traction of the prescribed pressure on outlets;
- liquid, per unit liquid volume (tested with δW/n, n constant per element, as 1D):
  (ρ_f/2n)∂t(V + W) − (1/n)∇·(n τ_f) + ∇P − ρ_f g + β s/n = 0. With P constant per
  element the pressure gradient is the plain face jump Σ_F [[P]] ∫_F φ ν·δW, plus
  (P_Γ − P_e) ∫ φ ν·δW on prescribed-pressure edges: gauge invariant (only jumps
  of P), a settled bed with a porosity gradient and a uniform fluidized bed with
  a free surface are exact discrete equilibria (each element contributes its own
  ρ_f g − βs/n to the jump), and on a column one element wide with free-slip
  walls the discrete equations are those of ``TwoFluid1D`` on the vertical mesh;
- continuity (δP): −∫δP ∇·V − C(P, δP) = 0, C the macroelement checkerboard
  penalty (:func:`~twofluid.fem.terms_2d.checkerboard_penalty`), which leaves
  pressures linear on a 2×2 patch alone, scaled δ/μ_eff with the Brinkman viscosity
  μ_eff = μ_f + βh²/n² (:meth:`TwoFluid2D._penalty_scale`; δ/μ_f in clear liquid);
- porosity (δn): 2|e|(n − nᵗ)/Δt − 2 Σ_F r_F Φ_F = 0, Φ_F = ∫_F (V − W)/2 · ν the
  outward Galerkin solids flux of each face and r_F = (1 − n_up)/(1 − n̄_F) its
  upwind ratio (as the 1D vertex flux: solids balance exact per element, an element
  cannot give away solids it does not hold; r = 1 on inlets, clear liquid outside
  outlets).

β s/n (s the slip, β from the element-mean slip magnitude) is Newton-linearised in
V, W and n; P_s Taylor-linearised in n; r_F and ρ̄ are implicit in n; μ_s and the
1/n weights of the liquid rows are frozen at the iterate (as 1D).
τ_m = (μ_f/2 + μ_s/2)τ(V) + (μ_f/2 − μ_s/2)τ(W), n τ_f = (μ_f/2)τ(V + W), μ_s frozen
at the iterate. Every block is filled into one :class:`SparsityPattern` built
once; :meth:`TwoFluid2D.solve` reuses an LU factorisation across iterations and
steps as a GMRES preconditioner (modified Newton) and refactorises only when GMRES
would cost more than a new factorisation (:class:`LaggedSolver`).
"""
from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Callable

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..closures.viscosity import solid_viscosity
from ..fem.quad import FaceBasis, QuadBasis, SparsityPattern, element_dofs, nodal_dofs
from ..fem.terms_2d import (body_force, checkerboard_penalty, divergence, mass,
                            pressure_face_gradient, viscous)
from ..mesh.quad import QuadMesh
from .two_fluid_1d import Closures, Materials, State

__all__ = ["Boundary2D", "TwoFluid2D", "LaggedSolver", "KINDS", "State"]

_CLEAR = 1e-6
#: boundary kinds, in the order their Dirichlet values are applied (later wins at shared nodes)
KINDS = ("outlet", "inlet", "slip", "axis", "wall", "rotating_wall")


@dataclass(frozen=True)
class Boundary2D:
    """Condition on the mesh boundary group ``group``.

    kind: ``inlet`` (porous distributor: V = W = superficial inflow along the inward
    normal, tangential 0; ``solids_velocity`` > 0 feeds solids: V = j_f + j_s,
    W = j_f − j_s), ``wall`` (no slip), ``slip`` (normal components 0),
    ``axis`` (r = 0: radial and swirl 0), ``rotating_wall`` (no slip for both
    phases, swirl U_f = U_s = ω r [rad/s]: V_θ = ωr, W_θ = (2n − 1)ωr) or
    ``outlet`` (liquid pressure ``pressure`` [Pa]; solids may leave). With
    ``free_slip`` a wall or rotating wall holds only the normal velocity and the
    swirl; the tangential velocity in the (r, z) plane is free. Slip conditions
    need boundaries made of edges along x or y (an L-shaped cut is fine: each
    node holds the normal components of its edges).
    """

    group: str
    kind: str
    velocity: Callable[[float], float] | None = None  # superficial liquid inflow [m/s]
    solids_velocity: float = 0.0  # superficial solids inflow [m/s]
    pressure: float = 0.0  # [Pa]
    omega: float = 0.0  # [rad/s]
    free_slip: bool = False  # wall, rotating_wall: meridional tangential velocity free (swirl still set)


class LaggedSolver:
    """Sparse solves of A x = b with prescribed entries, on a fixed sparsity pattern.

    The reduction to free unknowns is indexed once (the pattern never changes).
    ``kind="lagged"`` (modified Newton): the LU factors of an earlier matrix
    precondition GMRES (right preconditioning, so the tolerance is on the true
    residual) for the current one, across Newton iterates and steps. The iteration
    budget of a solve is what a new factorisation costs: the measured time of the last
    factorisation over the mean time of one GMRES iteration (≈ 70 for the pipe-flow
    matrix: 2.4 s vs 0.035 s idle), within [``min_iter``, ``max_iter``]. A new
    factorisation is made when GMRES does not reach ``rtol`` within the budget, and
    before the next solve when a solve needed more than ``refactor_fraction`` of it
    (GMRES is slowing down: the matrix has drifted from the factored one). Rows are
    equilibrated by their largest entry in the matrix of the last factorisation (so
    the tolerance means the same for momentum, continuity and porosity rows whatever
    Δt). ``kind="direct"``: a fresh SuperLU factorisation every solve.

    ``rtol`` applies to the Newton correction (see :meth:`solve`): an inexact
    Newton step whose error is ``rtol`` times the correction, far below the
    Picard/Newton tolerance once the iterates converge.
    """

    def __init__(self, size: int, fixed: np.ndarray, kind: str = "lagged", rtol: float = 1e-6,
                 min_iter: int = 10, max_iter: int = 150, refactor_fraction: float = 0.5,
                 budget: int | None = None):
        if kind not in ("lagged", "direct"):
            raise ValueError("solver must be 'lagged' or 'direct'")
        self.size, self.kind, self.rtol = size, kind, rtol
        self.min_iter, self.max_iter, self.refactor_fraction = min_iter, max_iter, refactor_fraction
        self._t_fact, self._t_it, self.fixed_budget = None, None, budget
        self.fixed = np.asarray(fixed)
        self.free = np.ones(size, dtype=bool)
        self.free[self.fixed] = False
        self.map = np.full(size, -1, dtype=np.int64)
        self.map[self.free] = np.arange(int(self.free.sum()))
        self._keep = None
        self.lu = None
        self._stale = False  # refactorise before the next solve
        self.stats = {"factorisations": 0, "solves": 0, "gmres_iterations": 0,
                      "factorisation_s": 0.0, "gmres_s": 0.0}

    def _reduce(self, A):
        """Values of the free × free block, in the CSR order of the reduced pattern (unscaled)."""
        nf = int(self.free.sum())
        if self._keep is None:
            rows = np.repeat(np.arange(self.size), np.diff(A.indptr))
            keep = self.free[rows] & self.free[A.indices]
            self._keep, self._ind = keep, self.map[A.indices[keep]].astype(np.int32)
            cnt = np.bincount(self.map[rows[keep]], minlength=nf)
            self._ptr = np.concatenate([[0], np.cumsum(cnt)]).astype(np.int32)
            self._row = np.repeat(np.arange(nf), cnt)
            self._nf = nf
        return A.data[self._keep]

    def _matrix(self, data):
        return sp.csr_matrix((data * self.scale[self._row], self._ind, self._ptr), shape=(self._nf, self._nf))

    def _factor(self, data):
        big = np.zeros(self._nf)
        np.maximum.at(big, self._row, np.abs(data))
        self.scale = 1.0 / np.where(big > 0.0, big, 1.0)
        t0 = time.perf_counter()
        Aff = self._matrix(data)
        self.lu = spla.splu(Aff.tocsc(), permc_spec="COLAMD")
        self._t_fact = time.perf_counter() - t0
        self.stats["factorisations"] += 1
        self.stats["factorisation_s"] += self._t_fact
        self._stale = False
        return Aff

    def budget(self) -> int:
        """GMRES iterations worth one factorisation (measured), within [min_iter, max_iter]."""
        if self.fixed_budget:
            return self.fixed_budget
        if not self._t_fact or not self._t_it:
            return self.max_iter // 2
        return int(min(self.max_iter, max(self.min_iter, self._t_fact / self._t_it)))

    def solve(self, A, b: np.ndarray, values: np.ndarray, guess: np.ndarray | None = None) -> np.ndarray:
        """Solution with x[fixed] = values.

        Solved as a correction to ``guess`` (the current iterate): A δ = b − A x_guess,
        so GMRES's relative tolerance applies to the Newton residual, not to the whole
        right-hand side (which M/Δt aᵗ dominates at small Δt: a 1e-10 relative solve
        of it left velocity noise above the Picard tolerance and stalled steps).
        """
        x = np.zeros(self.size) if guess is None else np.array(guess, dtype=float)
        x[self.fixed] = values
        data = self._reduce(A)
        res = (b - A @ x)[self.free]
        self.stats["solves"] += 1
        if self.kind == "direct" or self.lu is None or self._stale:
            self._factor(data)
            x[self.free] += self.lu.solve(res * self.scale)
            return x
        r = res * self.scale
        if not np.any(r):
            return x
        Aff = self._matrix(data)
        lu = self.lu
        op = spla.LinearOperator(Aff.shape, matvec=lambda v: Aff @ lu.solve(v))
        count = [0]

        def cb(_):
            count[0] += 1

        budget = self.budget()
        t0 = time.perf_counter()
        z, info = spla.gmres(op, r, rtol=self.rtol, atol=0.0, restart=budget, maxiter=1, callback=cb,
                             callback_type="pr_norm")
        dt = time.perf_counter() - t0
        self.stats["gmres_iterations"] += count[0]
        self.stats["gmres_s"] += dt
        if count[0]:
            it = dt / count[0]
            self._t_it = it if self._t_it is None else 0.8 * self._t_it + 0.2 * it
        if info != 0:
            self._factor(data)
            x[self.free] += self.lu.solve(res * self.scale)
            return x
        self._stale = count[0] > self.refactor_fraction * budget
        x[self.free] += self.lu.solve(z)
        return x


def _edge_geometry(mesh: QuadMesh, edges: np.ndarray, order: int = 2):
    """Owner element, ccw edge nodes, outward normal and ∫φ_a ν_k dΓ rows (m, 4) of boundary edges."""
    local = np.array([[0, 1], [1, 2], [2, 3], [3, 0]])
    all_e = mesh.cells[:, local].reshape(-1, 2)
    key_all = np.sort(all_e, axis=1) @ np.array([mesh.n_nodes, 1])
    key = np.sort(edges, axis=1) @ np.array([mesh.n_nodes, 1])
    order_ = np.argsort(key_all)
    pos = order_[np.searchsorted(key_all[order_], key)]
    if not np.all(key_all[pos] == key):
        raise ValueError("boundary edge not found among element edges")
    owner, ccw = pos // 4, all_e[pos]
    g, w = np.polynomial.legendre.leggauss(order)
    phi = np.column_stack([(1 - g) / 2, (1 + g) / 2])
    xa, xb = mesh.points[ccw[:, 0]], mesh.points[ccw[:, 1]]
    d = xb - xa
    length = np.hypot(d[:, 0], d[:, 1])
    normal = np.column_stack([d[:, 1], -d[:, 0]]) / length[:, None]
    x = np.einsum("qa,mad->mqd", phi, np.stack([xa, xb], axis=1))
    ds = 0.5 * w * length[:, None] * mesh.measure_weight(x)
    wphi = np.einsum("mq,qa->ma", ds, phi)
    rows = np.einsum("ma,mk->mka", wphi, normal).reshape(-1, 4)
    return owner, ccw, normal, rows


class TwoFluid2D:
    """Assembles and solves the 2DQ1 two-component equations on a :class:`QuadMesh`.

    Parameters
    ----------
    mesh : QuadMesh
        Planar or axisymmetric mesh [m]; y (z) is up.
    materials, closures : as for :class:`~twofluid.models.two_fluid_1d.TwoFluid1D`
    boundaries : list of Boundary2D
        Conditions on named boundary groups (one at least an outlet: pressure datum).
    swirl : bool
        Third (θ / out-of-plane) velocity component for V and W.
    delta : float
        Checkerboard-penalty parameter [-] (needs ``mesh.patches``; 0 disables it).
    solver : {"lagged", "direct"}
        Linear solver (see :class:`LaggedSolver`).
    """

    element = "2DQ1"
    #: keep n fixed (porosity rows n = nᵗ): a steady solve of V, W, P for a given porosity
    freeze_porosity = False
    #: which porosity dependences are Newton-linearised (the rest are Picard, frozen at the iterate)
    newton_n = ("drag", "upwind")
    #: scale the checkerboard penalty by μ_f/μ_eff (Brinkman); False: by μ_f alone
    brinkman_penalty = True

    def __init__(self, mesh: QuadMesh, materials: Materials, closures: Closures,
                 boundaries: list[Boundary2D], swirl: bool = False, delta: float = 0.25,
                 solids_flux: str = "upwind", solver: str = "lagged"):
        if not any(b.kind == "outlet" for b in boundaries):
            raise ValueError("at least one boundary must be an outlet (it fixes the pressure datum)")
        for b in boundaries:
            if b.kind not in KINDS:
                raise ValueError(f"boundary kind {b.kind!r} not one of {KINDS}")
            mesh.boundary_nodes(b.group)  # KeyError naming the groups if missing
        self.mesh, self.mat, self.clo = mesh, materials, closures
        self.boundaries = sorted(boundaries, key=lambda b: KINDS.index(b.kind))
        self.swirl, self.delta, self.solids_flux = swirl, delta, solids_flux
        self.nc = 3 if swirl else 2
        self.nn, self.ne = mesh.n_nodes, mesh.n_elements
        self.nv = self.nc * self.nn
        self.sizes = {"V": self.nv, "W": self.nv, "P": self.ne, "n": self.ne}
        self.size = 2 * self.nv + 2 * self.ne
        self._precompute()
        self._build_pattern()
        self.linear = LaggedSolver(self.size, self._fixed, kind=solver)

    # ------------------------------------------------------------------ setup
    def _precompute(self):
        mesh, nc, ne = self.mesh, self.nc, self.ne
        b = self.basis = QuadBasis(mesh)
        self.vol = b.dx.sum(axis=1)
        self.wavg = np.einsum("eq,qa->ea", b.dx, b.N) / self.vol[:, None]  # ∫N/|e|
        M = mass(b)
        self.Mv = np.zeros((ne, 4 * nc, 4 * nc))
        for c in range(nc):
            self.Mv[:, 4 * c:4 * c + 4, 4 * c:4 * c + 4] = M
        self.K1 = viscous(b, 1.0, nc)
        self.D = divergence(b, nc)
        g = np.zeros(nc)
        g[1] = -self.mat.g
        self.Ng = body_force(b, g, nc)  # ∫ N g [m/s² · m³]
        self.vd = nodal_dofs(mesh.cells, self.nn, nc)
        self.wd = self.vd + self.nv
        self.pd = element_dofs(ne, 2 * self.nv)
        self.nd = element_dofs(ne, 2 * self.nv + ne)
        f = self.face = FaceBasis(mesh)
        G1, _ = pressure_face_gradient(f, 1.0)
        self.fR = G1[:, :, 1]  # (nf, 4) ∫φ_a ν_k dΓ
        fv = nodal_dofs(f.edges, self.nn, 2)
        self.fvd, self.fwd = fv, fv + self.nv
        self.fe = f.elements
        v = self.vol[self.fe]
        self.fth = v / v.sum(axis=1, keepdims=True)  # weights of n̄_F
        self._h2 = mesh.element_size() ** 2
        self.patch = None
        if self.delta > 0.0 and mesh.patches is not None:
            C, el = checkerboard_penalty(b, self.delta, self.mat.mu_f)
            self.patch = (-C, el)
        # boundary edges carrying a pressure or a solids flux
        rows, own, kinds, pr = [], [], [], []
        for bc in self.boundaries:
            if bc.kind not in ("outlet", "inlet") or mesh.boundaries[bc.group].ndim != 2:
                continue
            o, ccw, _, R = _edge_geometry(mesh, mesh.boundary_edges(bc.group))
            rows.append((R, ccw))
            own.append(o)
            kinds.append(np.full(o.size, bc.kind == "outlet"))
            pr.append(np.full(o.size, bc.pressure))
        if rows:
            self.bR = np.concatenate([r for r, _ in rows])
            bnodes = np.concatenate([c for _, c in rows])
            self.bown = np.concatenate(own)
            self.bout = np.concatenate(kinds)
            self.bP = np.concatenate(pr)
        else:
            self.bR, bnodes = np.zeros((0, 4)), np.zeros((0, 2), int)
            self.bown, self.bout, self.bP = np.zeros(0, int), np.zeros(0, bool), np.zeros(0)
        self.bvd = nodal_dofs(bnodes, self.nn, 2)
        self.bwd = self.bvd + self.nv
        self._fixed, self._dir = self._dirichlet_setup()
        self._node_porosity = np.ones(self.nn)  # until the first assembly (clear liquid)

    def _dirichlet_setup(self):
        """Fixed dofs (V and W) and, per boundary, (dofs, velocity-component factor) of its values."""
        mesh, nn = self.mesh, self.nn
        fixed = np.full(self.nv, -1, dtype=np.int64)  # index into the rule list
        rules = []
        for bc in self.boundaries:
            nodes = mesh.boundary_nodes(bc.group)
            if bc.kind == "outlet":
                continue
            normal = None
            if bc.kind == "slip" or (bc.free_slip and bc.kind in ("wall", "rotating_wall")):
                for c, on in enumerate(self._normal_nodes(bc)):  # per node: the normals of its edges
                    rules.append((bc, c, None))
                    fixed[c * nn + on] = len(rules) - 1
                if self.swirl and bc.kind != "slip":
                    rules.append((bc, 2, None))
                    fixed[2 * nn + nodes] = len(rules) - 1
                continue
            if bc.kind in ("inlet", "axis") and mesh.boundaries[bc.group].ndim == 2:
                _, _, nrm, _ = _edge_geometry(mesh, mesh.boundary_edges(bc.group))
                normal = nrm.mean(axis=0)
                if np.abs(np.abs(normal).max() - 1.0) > 1e-9:
                    raise ValueError(f"boundary group {bc.group!r} ({bc.kind}) must be a straight "
                                     "boundary along x or y")
            elif bc.kind == "axis":
                normal = np.array([-1.0, 0.0])
            comps = list(range(self.nc))
            if bc.kind == "axis":
                comps = [0] + ([2] if self.swirl else [])
            for c in comps:
                rules.append((bc, c, normal))
                fixed[c * nn + nodes] = len(rules) - 1
        idx = np.nonzero(fixed >= 0)[0]
        self._rule_of = fixed[idx]
        self._rules = rules
        return np.concatenate([idx, idx + self.nv]), None

    def _normal_nodes(self, bc: Boundary2D) -> tuple[np.ndarray, np.ndarray]:
        """Nodes of ``bc``'s group on edges with normal along r (or x), and along z (or y)."""
        mesh = self.mesh
        if mesh.boundaries[bc.group].ndim != 2:
            raise ValueError(f"boundary group {bc.group!r} ({bc.kind}, slip) needs its edges")
        _, ccw, nrm, _ = _edge_geometry(mesh, mesh.boundary_edges(bc.group))
        axis = np.argmax(np.abs(nrm), axis=1)
        if np.any(np.abs(np.abs(nrm[np.arange(axis.size), axis]) - 1.0) > 1e-9):
            raise ValueError(f"boundary group {bc.group!r} ({bc.kind}, slip) must be made of edges "
                             "along x or y")
        return tuple(np.unique(ccw[axis == c]) for c in (0, 1))

    def dirichlet(self, t: float) -> tuple[np.ndarray, np.ndarray]:
        """Global indices and values of prescribed V and W [m/s]."""
        nn = self.nn
        idx = self._fixed[: self._fixed.size // 2]
        node = idx % nn
        v = np.zeros(idx.size)
        w = np.zeros(idx.size)
        for r, (bc, c, normal) in enumerate(self._rules):
            sel = self._rule_of == r
            if bc.kind == "inlet" and c < 2:
                inward = -normal[c]
                jf = bc.velocity(t) if bc.velocity else 0.0
                v[sel] = inward * (jf + bc.solids_velocity)
                w[sel] = inward * (jf - bc.solids_velocity)
            elif bc.kind == "rotating_wall" and c == 2:
                # both phases turn with the wall: U_f = U_s = ωr, so V = ωr and
                # W = (2n − 1) ωr with n the wall node's porosity at the iterate
                u = bc.omega * self.mesh.points[node[sel], 0]
                v[sel] = u
                w[sel] = (2.0 * self._node_porosity[node[sel]] - 1.0) * u
        return self._fixed, np.concatenate([v, w])

    def _build_pattern(self):
        blocks = [(self.vd, self.vd), (self.vd, self.wd), (self.wd, self.vd), (self.wd, self.wd),
                  (self.vd, self.pd), (self.vd, self.nd), (self.wd, self.nd), (self.pd, self.vd),
                  (self.nd, self.nd)]
        fp, fn = self.pd[self.fe, 0], self.nd[self.fe, 0]
        blocks += [(self.fwd, fp), (fn, self.fvd), (fn, self.fwd), (fn, fn)]
        bp, bn = self.pd[self.bown], self.nd[self.bown]
        blocks += [(self.bwd, bp), (bn, self.bvd), (bn, self.bwd), (bn, bn)]
        self._n_couplings = (10, 11, 12, 14, 15, 16)  # face and edge rows of n (frozen porosity)
        if self.patch is not None:
            pe = self.pd[self.patch[1], 0]
            blocks.append((pe, pe))
        self.pattern = SparsityPattern(blocks, (self.size, self.size))

    # --------------------------------------------------------------- helpers
    def element_mean(self, nodal: np.ndarray) -> np.ndarray:
        """Element means of a nodal vector field (nc·n_nodes,) -> (n_el, nc)."""
        x = nodal[self.vd].reshape(self.ne, self.nc, 4)
        return np.einsum("eca,ea->ec", x, self.wavg)

    def nodal_porosity(self, n: np.ndarray) -> np.ndarray:
        """Volume-weighted average of the porosity of the elements around each node."""
        num = np.bincount(self.mesh.cells.ravel(), weights=np.repeat(n * self.vol, 4), minlength=self.nn)
        den = np.bincount(self.mesh.cells.ravel(), weights=np.repeat(self.vol, 4), minlength=self.nn)
        return num / den

    def solids_pressure(self, n, n_bar, derivative=False):
        return self.clo.solids_pressure(n, n_bar, self.mat, derivative=derivative)

    def face_porosity(self, n):
        return (self.fth * n[self.fe]).sum(axis=1)

    # -------------------------------------------------------------- assembly
    def assemble(self, k: State, old: State, dt: float, t_new: float):
        """Matrix (CSR on the fixed pattern) and right-hand side of one iterate."""
        mat, clo, ne = self.mat, self.clo, self.ne
        Mv, K1 = self.Mv, self.K1
        if k.n.min() <= 0.0 or k.n.max() > 1.0:  # an iterate outside (0, 1]: coefficients at the bound
            k = k.copy(n=np.clip(k.n, 1e-3, 1.0))
        n = k.n
        self._iterate = self.pack(k)  # the linear solve corrects it (LaggedSolver.solve)
        self._node_porosity = self.nodal_porosity(n)  # for the rotating-wall values of W
        rho_hat, d_rho = 0.5 * (mat.rho_s + mat.rho_f), 0.5 * (mat.rho_s - mat.rho_f)
        rhs = np.zeros(self.size)
        vd, wd = self.vd, self.wd

        def scatter(d, vals):
            np.add.at(rhs, d, vals)

        mu_s = solid_viscosity(n, mat.mu_f, **clo.viscosity_params)[:, None, None] if clo.viscous \
            else np.zeros((ne, 1, 1))
        mu_f = mat.mu_f if clo.viscous else 0.0
        JV, Jq, Jn, drhs = self._drag(k)
        inv_n = (1.0 / n)[:, None, None]  # liquid rows per unit liquid volume (δW/n)
        VV = rho_hat / dt * Mv + 0.5 * (mu_f + mu_s) * K1
        VW = -d_rho / dt * Mv + 0.5 * (mu_f - mu_s) * K1
        WL = inv_n * (0.5 * mat.rho_f / dt * Mv + 0.5 * mu_f * K1)
        WV = WL + JV
        WW = WL + Jq
        scatter(vd, np.einsum("eij,ej->ei", Mv, rho_hat * old.V[vd] - d_rho * old.W[vd]) / dt)
        scatter(wd, np.einsum("eij,ej->ei", inv_n * Mv, 0.5 * mat.rho_f * (old.V[vd] + old.W[vd])) / dt)
        ps, dps = self.solids_pressure(n, k.n_bar, derivative=True)
        VP = -self.D[:, :, None]
        VN = (-self.D * dps[:, None] + (mat.rho_s - mat.rho_f) * self.Ng)[:, :, None]
        scatter(vd, self.D * (ps - dps * n)[:, None] + mat.rho_s * self.Ng)
        WN = Jn[:, :, None]
        scatter(wd, drhs + mat.rho_f * self.Ng)
        PV = -self.D[:, None, :]
        NN = (2.0 * self.vol / dt)[:, None, None]
        scatter(self.nd[:, 0], 2.0 * self.vol / dt * old.n)
        vals = [VV, VW, WV, WW, VP, VN, WN, PV, NN]
        vals += self._faces(k, rhs)
        vals += self._boundary_edges(k, rhs)
        if self.freeze_porosity:  # n = nᵗ: rows of n become 2|e|/Δt n = 2|e|/Δt nᵗ
            rhs[self.nd[:, 0]] = 2.0 * self.vol / dt * old.n
            for i in self._n_couplings:
                vals[i] = np.zeros_like(vals[i])
        if self.patch is not None:
            vals.append(self.patch[0] * self._penalty_scale(n)[:, None, None])
        return self.pattern.assemble(vals), rhs

    def _penalty_scale(self, n: np.ndarray) -> np.ndarray:
        """μ_f/μ_eff per macroelement: the checkerboard penalty δ|M|/μ_eff of a Brinkman medium.

        μ_eff = μ_f + mean over the patch of β h²/n² (β = K(1 − n) the drag
        coefficient at the iterate, per unit liquid volume as the liquid rows, h the
        element size): the pressure–velocity scale h²/(μ + βh²) of drag-dominated
        flow (Brinkman/Darcy stabilisation). In clear liquid β = 0 and the penalty is
        the single-fluid one; in a bed it is weaker by the factor μ_f/(βh²) (~1e-5).
        The plain μ_f scaling made the penalty the dominant pressure–velocity
        coupling inside a bed and grew a porosity checkerboard at ≈ 10 1/s
        (docs/verification_2d.md, section 7).
        """
        el = self.patch[1]
        if not self.brinkman_penalty:
            return np.ones(el.shape[0])
        beta = self._K_iter * (1.0 - n)
        mu_eff = self.mat.mu_f + (beta * self._h2 / (n * n))[el].mean(axis=1)
        return self.mat.mu_f / mu_eff

    def _faces(self, k: State, rhs: np.ndarray) -> list:
        """Interior faces: [[P]] in the liquid rows and the upwinded solids flux."""
        fe, R, th = self.fe, self.fR, self.fth
        WP = np.stack([-R, R], axis=-1)
        flux = 0.5 * np.einsum("fi,fi->f", R, k.V[self.fvd] - k.W[self.fvd])  # Φ_F, − to +
        r, dr = self._upwind(k.n, fe, th, flux, getattr(self, "_fwd_dir", None))
        sgn = np.array([-1.0, 1.0])[None, :, None]  # − loses Φ, + gains it
        NV = sgn * (r[:, None] * R)[:, None, :]
        NW = -NV
        g = 2.0 * flux
        NN = sgn * (g[:, None] * dr)[:, None, :] * ("upwind" in self.newton_n)
        np.add.at(rhs, self.nd[fe, 0], np.einsum("fij,fj->fi", NN, k.n[fe]))
        return [WP, NV, NW, NN]

    def _upwind(self, n, fe, th, flux, forward=None):
        """r = (1 − n_up)/(1 − n̄_F) and ∂r/∂(n₋, n₊) (galerkin: r = 1)."""
        m = flux.size
        if self.solids_flux != "upwind":
            return np.ones(m), np.zeros((m, 2))
        fwd = flux >= 0.0 if forward is None else forward
        n2 = n[fe]
        nbar = (th * n2).sum(axis=1)
        n_up = np.where(fwd, n2[:, 0], n2[:, 1])
        one_f = 1.0 - nbar
        ok = one_f > _CLEAR
        inv = np.where(ok, 1.0 / np.where(ok, one_f, 1.0), 0.0)
        r = (1.0 - n_up) * inv
        dr = r[:, None] * inv[:, None] * th
        dr[:, 0] -= np.where(fwd, inv, 0.0)
        dr[:, 1] -= np.where(fwd, 0.0, inv)
        return r, dr

    def begin_iteration(self, it: int, k: State) -> None:
        """Picard hook: fix the upwind side of every face after the first iteration (as 1D)."""
        if it <= 2:
            self._fwd_dir = np.einsum("fi,fi->f", self.fR, k.V[self.fvd] - k.W[self.fvd]) >= 0.0

    def _boundary_edges(self, k: State, rhs: np.ndarray) -> list:
        """Outlets: liquid (P_Γ − P_e), mixture traction, solids outflow; inlets: solids inflow."""
        e, R, out, PG = self.bown, self.bR, self.bout, self.bP
        ne_ = k.n[e]
        o = out.astype(float)
        WP = (-o[:, None] * R)[:, :, None]
        np.add.at(rhs, self.bwd, -(o * PG)[:, None] * R)
        np.add.at(rhs, self.bvd, -(o * PG)[:, None] * R)
        flux = 0.5 * np.einsum("fi,fi->f", R, k.V[self.bvd] - k.W[self.bvd])  # outward
        r = np.ones(e.size)
        dr = np.zeros(e.size)
        if self.solids_flux == "upwind":
            # clear liquid enters through an outlet; a clear element has no solids to give
            r = np.where(out & ((flux < 0.0) | (1.0 - ne_ < _CLEAR)), 0.0, 1.0)
        NV = -(r[:, None] * R)[:, None, :]
        NN = (2.0 * flux * dr)[:, None, None]
        return [WP, NV, -NV, NN]

    def _drag_force(self, n, V, W):
        """Element drag vectors ∫ N β s/n dΩ (n_el, 4nc) = K M q/(2n²), K = β/(1−n), q = (1−2n)V + W."""
        q = (1.0 - 2.0 * n)[:, None] * V[self.vd] + W[self.vd]
        qbar = np.einsum("eca,ea->ec", q.reshape(self.ne, self.nc, 4), self.wavg)
        qn = np.sqrt((qbar ** 2).sum(axis=1))
        # 1 − n floored at _CLEAR as in TwoFluid1D.slip: continuous as an element empties
        s_abs = qn / (2.0 * n * np.maximum(1.0 - n, _CLEAR))
        K = self.clo.beta_per_solids(n, s_abs, self.mat)  # |slip| saturated at clo.slip_max
        Mq = np.einsum("eij,ej->ei", self.Mv, q)
        return (K / (2.0 * n * n))[:, None] * Mq, K, s_abs, q, qbar, qn, Mq

    def _drag(self, k: State):
        """Newton linearisation of β s/n tested with δW about iterate k (as 1D, vector slip)."""
        n = k.n
        D0, K0, s_abs, q, qbar, qn, Mq = self._drag_force(n, k.V, k.W)
        self._K_iter = K0
        ds = 1e-6 * np.maximum(s_abs, 1e-6)
        dK = (self.clo.beta_per_solids(n, s_abs + ds, self.mat) - K0) / ds * s_abs  # K'|s|
        gain = np.where(qn > 0.0, dK / np.where(qn > 0.0, qn ** 2, 1.0), 0.0)
        grow = (qbar[:, :, None] * self.wavg[:, None, :]).reshape(self.ne, -1)  # ∂|q̄|²/2∂q
        Jq = (K0 / (2.0 * n * n))[:, None, None] * self.Mv \
            + (gain / (2.0 * n * n))[:, None, None] * Mq[:, :, None] * grow[:, None, :]
        JV = (1.0 - 2.0 * n)[:, None, None] * Jq
        dn = 1e-8 * np.where(n < 0.5, 1.0, -1.0)
        Dn = self._drag_force(n + dn, k.V, k.W)[0]
        Jn = (Dn - D0) / dn[:, None] if "drag" in self.newton_n else np.zeros_like(D0)
        lin = np.einsum("eij,ej->ei", JV, k.V[self.vd]) + np.einsum("eij,ej->ei", Jq, k.W[self.vd])
        return JV, Jq, Jn, lin + Jn * n[:, None] - D0

    def solve(self, system, t: float) -> np.ndarray:
        """Linear solve of one iterate with the Dirichlet values of time t."""
        A, b = system
        idx, val = self.dirichlet(t)
        if not (np.all(np.isfinite(A.data)) and np.all(np.isfinite(b))):
            return np.full(self.size, np.nan)  # the stepper retries with a smaller step
        guess = getattr(self, "_iterate", None)
        try:
            return self.linear.solve(A, b, val, guess)
        except RuntimeError:  # exactly singular factor
            self.linear.lu = None
            return np.full(self.size, np.nan)

    # ------------------------------------------------ interface to the stepper
    def pack(self, s: State) -> np.ndarray:
        return np.concatenate([s.V, s.W, s.P, s.n])

    def unpack(self, a: np.ndarray, like: State, t: float) -> State:
        nv, ne = self.nv, self.ne
        return like.copy(t=t, V=a[:nv], W=a[nv:2 * nv], P=a[2 * nv:2 * nv + ne], n=a[2 * nv + ne:])

    def check(self, s: State) -> str | None:
        """Why a state is not admissible (porosity outside (0, 1]), or None."""
        if not np.all(np.isfinite(s.n)) or not np.all(np.isfinite(s.V)):
            return "non-finite values"
        if s.n.min() <= 0.0:
            return f"porosity {s.n.min():.6g} <= 0 in element {int(s.n.argmin())}"
        if s.n.max() > 1.0 + 1e-9:
            return f"porosity {s.n.max():.12g} > 1 in element {int(s.n.argmax())}"
        return None

    #: [m/s] below this the Picard velocity test is absolute (tol × floor): 1e-4 keeps it above the
    #: GMRES round-off of a bed at rest (≈ 2e-13 m/s measured in a settled bed, which a 1e-6 floor
    #: with the initial field's tol 1e-8 never passed)
    velocity_floor = 1e-4

    def velocity_scale(self, s: State) -> float:
        return max(float(np.abs(s.V).max()), float(np.abs(s.W).max()), self.velocity_floor)

    def end_step(self, old: State, new: State, dt: float) -> State:
        return new

    # ---------------------------------------------------------- diagnostics
    def solids_volume(self, s: State) -> float:
        """∫ (1 − n) dΩ [m³] (per metre of depth if planar)."""
        return float(((1.0 - s.n) * self.vol).sum())

    def boundary_fluxes(self, s: State) -> dict[str, dict[str, float]]:
        """Outward liquid and solids volume fluxes [m³/s] through each boundary group.

        Liquid: ∫ (V + W)/2 · ν dΓ; solids: ∫ (V − W)/2 · ν dΓ with the upwind ratio of
        the porosity equation (zero where clear liquid enters an outlet or a clear
        element meets it).
        """
        out = {}
        for bc in self.boundaries:
            if self.mesh.boundaries[bc.group].ndim != 2:
                continue
            own, ccw, _, R = _edge_geometry(self.mesh, self.mesh.boundary_edges(bc.group))
            d = nodal_dofs(ccw, self.nn, 2)
            liq = 0.5 * np.einsum("fi,fi->f", R, s.V[d] + s.W[d])
            sol = 0.5 * np.einsum("fi,fi->f", R, s.V[d] - s.W[d])
            if bc.kind == "outlet" and self.solids_flux == "upwind":  # as _boundary_edges
                sol = np.where((sol < 0.0) | (1.0 - s.n[own] < _CLEAR), 0.0, sol)
            out[bc.group] = {"kind": bc.kind, "liquid_m3_s": float(liq.sum()),
                             "solids_m3_s": float(sol.sum())}
        return out

    def solids_outflow(self, s: State) -> float:
        """Net rate [m³/s] at which solids leave the domain."""
        return sum(v["solids_m3_s"] for v in self.boundary_fluxes(s).values())

    def settled_solids_pressure(self, n: np.ndarray) -> np.ndarray:
        """P_s per element [Pa] making layered porosity ``n`` a discrete equilibrium at rest.

        Structured meshes (elements in vertical columns): marches each column down
        from its top (P_s = 0 above): P_s,below − P_s,above = g Δρ [(1 − n)h]_avg, the
        face form of the mixture-minus-liquid balance (h the element heights).
        """
        xc = self.mesh.points[self.mesh.cells].mean(axis=1)
        y = self.mesh.points[self.mesh.cells][:, :, 1]
        h = y.max(axis=1) - y.min(axis=1)
        col = np.unique(np.round(xc[:, 0], 12), return_inverse=True)[1]
        ps = np.zeros(self.ne)
        w = self.mat.g * (self.mat.rho_s - self.mat.rho_f) * (1.0 - n) * h / 2.0
        for c in np.unique(col):  # one pass per column, vectorised along it
            e = np.nonzero(col == c)[0]
            e = e[np.argsort(-xc[e, 1])]
            load = w[e] + np.concatenate([[0.0], w[e][:-1]])
            ps[e] = np.cumsum(load)
        return ps

    def element_fields(self, s: State) -> dict[str, np.ndarray]:
        """Per-element fields at centres (SI): porosity, P, P_s, and mean V, W, U_f, U_s (n_el, nc).

        U_s is NaN in clear liquid (n = 1).
        """
        v, w = self.element_mean(s.V), self.element_mean(s.W)
        one_m = (1.0 - s.n)[:, None]
        with np.errstate(divide="ignore", invalid="ignore"):
            us = np.where(one_m > _CLEAR, (v - w) / (2.0 * one_m), np.nan)
        xc = self.mesh.points[self.mesh.cells].mean(axis=1)
        return {"x_m": xc[:, 0], "y_m": xc[:, 1], "porosity": s.n, "reference_porosity": s.n_bar,
                "P_Pa": s.P, "Ps_Pa": self.solids_pressure(s.n, s.n_bar), "V_m_s": v, "W_m_s": w,
                "Uf_m_s": (v + w) / (2.0 * s.n[:, None]), "Us_m_s": us}
