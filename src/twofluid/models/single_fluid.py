"""Steady Stokes flow of one incompressible Newtonian fluid on a quadrilateral mesh.

Weak form (planar, or axisymmetric through the 2πr measure), Q1 velocity, P0
pressure p [Pa]::

    ∫ τ(u) : ∇δu dΩ − ∫ p ∇·δu dΩ = ∫ ρ g · δu dΩ        for all δu
    −∫ q ∇·u dΩ − C(p, q)        = 0                      for all q (P0)

τ = μ(∇u + ∇uᵀ − (2/3)(∇·u)I), C the pressure stabilisation
(by default the macroelement checkerboard penalty, parameter δ). The optional third
velocity component is the swirl u_θ (axisymmetric) or the out-of-plane velocity
(planar); with the convective terms dropped (slow flow, as in the thesis) it does not interact with the
in-plane flow, but it shares the matrix so the two-component model can add
couplings.

Boundaries not listed with a Dirichlet value are traction free (σ·ν = 0). If every
boundary node has both in-plane components prescribed (enclosed flow), the
pressure is fixed by ∫ p dΩ = 0 with a Lagrange multiplier.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from numpy.typing import ArrayLike, NDArray

from twofluid.fem.quad import (FaceBasis, QuadBasis, SparsityPattern, assemble_vector,
                               element_dofs, nodal_dofs)
from twofluid.fem.terms_2d import (body_force, checkerboard_penalty, divergence,
                                   pressure_jump, pressure_jump_load, viscous)
from twofluid.mesh.quad import QuadMesh

__all__ = ["StokesResult", "StokesSystem", "assemble_stokes", "solve_stokes", "COMPONENTS"]

#: component names accepted in Dirichlet specifications
COMPONENTS = {"x": 0, "r": 0, "y": 1, "z": 1, "w": 2, "theta": 2}

Value = float | Callable[[NDArray[np.float64]], NDArray[np.float64]]


@dataclass
class StokesResult:
    """Solution of :func:`solve_stokes`.

    Attributes
    ----------
    mesh : QuadMesh
    velocity : (n_nodes, n_comp) nodal velocity [m/s]: (u_x, u_y[, w]) or (u_r, u_z[, u_θ])
    pressure : (n_el,) element pressure [Pa]
    enclosed : whether the mean-zero pressure constraint was used
    info : solver details (dofs, nnz)
    reaction : (n_nodes, n_comp) nodal reactions A u − b of the momentum rows [N]: the force
        the prescribed boundaries exert on the fluid (zero to round-off at free nodes);
        with the 2πr measure in axisymmetry over the full circumference
    """

    mesh: QuadMesh
    velocity: NDArray[np.float64]
    pressure: NDArray[np.float64]
    enclosed: bool
    info: dict = field(default_factory=dict)
    reaction: NDArray[np.float64] | None = None


@dataclass
class StokesSystem:
    """Assembled (unreduced) Q1–P0 Stokes system of :func:`assemble_stokes`.

    Attributes
    ----------
    matrix : scipy.sparse.csr_matrix, rhs : numpy.ndarray
    n_velocity : velocity dofs (n_comp · n_nodes); pressures follow, one per element
    n_elements, n_comp : int
    fixed, values : Dirichlet dofs and their values [m/s]
    enclosed : bool (a Lagrange multiplier row ∫ p dΩ = 0 is last)
    stabilisation : resolved stabilisation kind
    """

    matrix: sp.csr_matrix
    rhs: NDArray[np.float64]
    n_velocity: int
    n_elements: int
    n_comp: int
    fixed: NDArray[np.int64]
    values: NDArray[np.float64]
    enclosed: bool
    stabilisation: str | None


def _dirichlet_values(
    mesh: QuadMesh, dirichlet: Mapping[str, Mapping[str | int, Value]], n_comp: int
) -> tuple[NDArray[np.int64], NDArray[np.float64]]:
    """Fixed dofs and values; groups are applied in order (later ones win at shared nodes)."""
    n = mesh.n_nodes
    fixed = np.full(n_comp * n, np.nan)
    for name, comps in dirichlet.items():
        nodes = mesh.boundary_nodes(name)
        for comp, value in comps.items():
            c = COMPONENTS[comp] if isinstance(comp, str) else int(comp)
            if c >= n_comp:
                raise ValueError(f"component {comp!r} given but the flow has {n_comp} components")
            val = value(mesh.points[nodes]) if callable(value) else value
            fixed[c * n + nodes] = np.broadcast_to(np.asarray(val, dtype=float), nodes.shape)
    dofs = np.nonzero(~np.isnan(fixed))[0]
    return dofs, fixed[dofs]


def _is_enclosed(mesh: QuadMesh, fixed_dofs: NDArray[np.int64]) -> bool:
    local = np.array([[0, 1], [1, 2], [2, 3], [3, 0]])
    edges = np.sort(mesh.cells[:, local].reshape(-1, 2), axis=1)
    uniq, count = np.unique(edges, axis=0, return_counts=True)
    bnodes = np.unique(uniq[count == 1])
    fixed = np.zeros(2 * mesh.n_nodes, dtype=bool)
    fixed[fixed_dofs[fixed_dofs < 2 * mesh.n_nodes]] = True
    return bool(np.all(fixed[bnodes]) and np.all(fixed[mesh.n_nodes + bnodes]))


def assemble_stokes(
    mesh: QuadMesh,
    mu: float,
    dirichlet: Mapping[str, Mapping[str | int, Value]],
    *,
    rho: float = 0.0,
    gravity: ArrayLike = (0.0, 0.0),
    swirl: bool = False,
    stabilisation: str | None = "auto",
    delta: float = 0.25,
    quadrature_order: int = 2,
) -> StokesSystem:
    """Assemble the Q1–P0 Stokes system (arguments as :func:`solve_stokes`).

    Unknowns: velocity component blocks (``c * n_nodes + node``), then one pressure
    per element, then (enclosed flow only) the Lagrange multiplier of ∫ p dΩ = 0.
    The matrix is symmetric: [[K, Bᵀ], [B, −C]] with B = −∫ q ∇·u.
    """
    nc = 3 if swirl else 2
    n, ne = mesh.n_nodes, mesh.n_elements
    nu = nc * n
    basis = QuadBasis(mesh, order=quadrature_order)
    udofs = nodal_dofs(mesh.cells, n, nc)
    pdofs = element_dofs(ne, nu)
    fixed, values = _dirichlet_values(mesh, dirichlet, nc)
    enclosed = _is_enclosed(mesh, fixed)
    size = nu + ne + (1 if enclosed else 0)

    K = viscous(basis, mu, nc)
    B = -divergence(basis, nc)[:, None, :]                       # (ne, 1, 4nc)
    blocks = [(udofs, udofs), (pdofs, udofs), (udofs, pdofs)]
    vals = [K, B, np.transpose(B, (0, 2, 1))]
    g = np.zeros(nc)
    g[:2] = np.asarray(gravity, dtype=float)
    b = np.zeros(size)
    b[:nu] = assemble_vector(udofs, body_force(basis, rho * g, nc), nu)
    kind = stabilisation
    if kind == "auto":
        kind = "checkerboard" if mesh.patches is not None else "global"
    if kind == "checkerboard":
        C, patch_el = checkerboard_penalty(basis, delta, mu)
        blocks.append((nu + patch_el, nu + patch_el))
        vals.append(-C)
    elif kind in ("local", "global"):
        face = FaceBasis(mesh, order=quadrature_order)
        blocks.append((nu + face.elements, nu + face.elements))
        vals.append(-pressure_jump(face, delta, mu, local=kind == "local"))
        load = pressure_jump_load(face, delta, mu, rho * g[:2], local=kind == "local")
        b[nu:nu + ne] += assemble_vector(face.elements, load, ne)
    elif kind is not None:
        raise ValueError(f"unknown stabilisation {stabilisation!r}")
    if enclosed:
        lag = np.full((ne, 1), size - 1)
        vol = basis.dx.sum(axis=1)[:, None, None]
        blocks += [(pdofs, lag), (lag, pdofs)]
        vals += [vol, vol]
    A = SparsityPattern(blocks, (size, size)).assemble(vals)

    return StokesSystem(A, b, nu, ne, nc, fixed, values, enclosed, kind)


def solve_stokes(
    mesh: QuadMesh,
    mu: float,
    dirichlet: Mapping[str, Mapping[str | int, Value]],
    *,
    rho: float = 0.0,
    gravity: ArrayLike = (0.0, 0.0),
    swirl: bool = False,
    stabilisation: str | None = "auto",
    delta: float = 0.25,
    quadrature_order: int = 2,
) -> StokesResult:
    """Solve steady Stokes flow with Q1–P0 elements and a sparse direct solver.

    Parameters
    ----------
    mesh : QuadMesh
        Planar or axisymmetric mesh [m].
    mu : float
        Dynamic viscosity [Pa·s].
    dirichlet : mapping
        ``{group: {component: value}}``; component names ``"x"/"r"``, ``"y"/"z"``,
        ``"w"/"theta"`` (or 0, 1, 2); value [m/s] a number or a callable of node
        coordinates (m, 2) returning (m,).
    rho : float
        Density [kg/m³] for the body force ρ g.
    gravity : (2,) array_like
        Gravity vector in the mesh plane [m/s²].
    swirl : bool
        Solve for the third (θ / out-of-plane) velocity component.
    stabilisation : {"auto", "checkerboard", "local", "global", None}
        Pressure stabilisation of Q1–P0: ``"checkerboard"`` penalises the local
        checkerboard of each 2×2 macroelement
        (:func:`~twofluid.fem.terms_2d.checkerboard_penalty`), ``"local"`` the
        pressure jumps inside macroelements (Kechkar–Silvester), ``"global"`` the
        jumps across all interior edges (:func:`~twofluid.fem.terms_2d.pressure_jump`,
        made exact for the hydrostatic pressure of ρg); None for plain Q1–P0.
        ``"auto"``: checkerboard if the mesh has patches, else global.
    delta : float
        Stabilisation parameter δ [-] (default 1/4).
    quadrature_order : int
        Gauss points per direction.

    Returns
    -------
    StokesResult

    Examples
    --------
    >>> from twofluid.mesh.quad import rectangle
    >>> m = rectangle(0.0, 2.0, 0.0, 1.0, 4, 2)
    >>> prof = lambda x: x[:, 1] * (1.0 - x[:, 1])    # Poiseuille profile [m/s]
    >>> res = solve_stokes(m, 1.0, {"top": {"x": 0, "y": 0}, "bottom": {"x": 0, "y": 0},
    ...                             "left": {"x": prof, "y": 0}, "right": {"y": 0}})
    >>> bool(np.allclose(res.velocity[:, 0], prof(m.points)))
    True
    """
    sys_ = assemble_stokes(mesh, mu, dirichlet, rho=rho, gravity=gravity, swirl=swirl,
                           stabilisation=stabilisation, delta=delta,
                           quadrature_order=quadrature_order)
    A, nu, ne = sys_.matrix, sys_.n_velocity, sys_.n_elements
    x = np.zeros(A.shape[0])
    x[sys_.fixed] = sys_.values
    free = np.ones(A.shape[0], dtype=bool)
    free[sys_.fixed] = False
    rhs = sys_.rhs - A @ x
    A_ff = A[free][:, free].tocsc()
    x[free] = spla.splu(A_ff).solve(rhs[free])
    reaction = (A @ x - sys_.rhs)[:nu]
    return StokesResult(
        mesh=mesh,
        velocity=x[:nu].reshape(sys_.n_comp, mesh.n_nodes).T.copy(),
        pressure=x[nu:nu + ne].copy(),
        enclosed=sys_.enclosed,
        info={"n_dofs": int(free.sum()), "nnz": int(A_ff.nnz),
              "stabilisation": sys_.stabilisation},
        reaction=reaction.reshape(sys_.n_comp, mesh.n_nodes).T.copy(),
    )
