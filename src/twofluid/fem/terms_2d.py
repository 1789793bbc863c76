"""Weak-form terms for bilinear (Q1) velocity and element-constant (P0) fields.

Each term is a small function of a :class:`~twofluid.fem.quad.QuadBasis` (or
:class:`~twofluid.fem.quad.FaceBasis`) returning element matrices (n, k, k) or
element vectors (n, k); assembly is separate (:class:`~twofluid.fem.quad.SparsityPattern`).
The integration weights ``basis.dx`` already hold 2πr in axisymmetry, so the
only axisymmetric statements here are the hoop strain u_r/r and the swirl
strains (thesis eq. 4.50).

Vector fields have ``n_comp`` components: 2 (u_x, u_y) or (u_r, u_z), or 3 with the
out-of-plane component (u_θ in axisymmetry, u_w planar) last. Local dofs are
component-major: ``[c0 n0..n3, c1 n0..n3, ...]``.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from twofluid.fem.quad import FaceBasis, QuadBasis

__all__ = ["mass", "strain_operator", "viscous", "divergence", "body_force",
           "pressure_jump", "pressure_jump_load", "checkerboard_penalty",
           "pressure_face_gradient"]


def _per_point(coef: ArrayLike, shape: tuple[int, int]) -> NDArray[np.float64]:
    """Broadcast a scalar, per-element (n_el,) or per-point (n_el, n_q) coefficient."""
    c = np.asarray(coef, dtype=float)
    if c.ndim == 1:
        c = c[:, None]
    return np.broadcast_to(c, shape)


def mass(basis: QuadBasis, coef: ArrayLike = 1.0) -> NDArray[np.float64]:
    """Scalar mass matrices ∫ c N_a N_b dΩ, shape (n_el, 4, 4).

    Examples
    --------
    >>> from twofluid.mesh.quad import rectangle
    >>> M = mass(QuadBasis(rectangle(0, 2, 0, 1, 1, 1)))
    >>> round(float(M.sum()), 12)
    2.0
    """
    c = _per_point(coef, basis.dx.shape) * basis.dx
    return np.einsum("eq,qa,qb->eab", c, basis.N, basis.N)


def strain_operator(basis: QuadBasis, n_comp: int = 2) -> NDArray[np.float64]:
    """Engineering strain-rate operator B, shape (n_el, n_q, n_s, 4 n_comp) [1/m].

    Rows (n_s of them):

    - planar: ε_xx, ε_yy, γ_xy (+ ∂w/∂x, ∂w/∂y with an out-of-plane component w);
    - axisymmetric: ε_rr, ε_zz, ε_θθ = u_r/r, γ_rz (+ ∂u_θ/∂r − u_θ/r, ∂u_θ/∂z with swirl).
    """
    dN, axi = basis.dN, basis.mesh.axisymmetric
    n_el, nq = basis.dx.shape
    n_norm = 3 if axi else 2
    n_s = n_norm + 1 + (2 if n_comp == 3 else 0)
    B = np.zeros((n_el, nq, n_s, 4 * n_comp))
    B[:, :, 0, 0:4] = dN[..., 0]
    B[:, :, 1, 4:8] = dN[..., 1]
    if axi:
        B[:, :, 2, 0:4] = basis.N / basis.radius[..., None]
    B[:, :, n_norm, 0:4] = dN[..., 1]
    B[:, :, n_norm, 4:8] = dN[..., 0]
    if n_comp == 3:
        B[:, :, n_norm + 1, 8:12] = dN[..., 0]
        if axi:
            B[:, :, n_norm + 1, 8:12] -= basis.N / basis.radius[..., None]
        B[:, :, n_norm + 2, 8:12] = dN[..., 1]
    elif n_comp != 2:
        raise ValueError("n_comp must be 2 or 3")
    return B


def _viscous_moduli(n_norm: int, n_s: int) -> NDArray[np.float64]:
    """D with τ = D ε per unit viscosity: normal block 2I − (2/3)11ᵀ, shear 1."""
    D = np.eye(n_s)
    D[:n_norm, :n_norm] = 2.0 * np.eye(n_norm) - 2.0 / 3.0
    return D


def viscous(basis: QuadBasis, mu: ArrayLike, n_comp: int = 2) -> NDArray[np.float64]:
    """Viscous matrices ∫ τ(u) : ∇δu dΩ, τ = μ(∇u + ∇uᵀ − (2/3)(∇·u) I), (n_el, 4nc, 4nc).

    ``mu`` [Pa·s] is a scalar, per element (n_el,) or per quadrature point (n_el, n_q).
    In plane strain the out-of-plane normal stress −(2/3)μ∇·u does no work, so the
    planar normal block is 2×2.

    Examples
    --------
    >>> from twofluid.mesh.quad import rectangle
    >>> b = QuadBasis(rectangle(0, 1, 0, 1, 2, 2))
    >>> K = viscous(b, 1.0)
    >>> rigid = np.r_[np.ones(4), np.zeros(4)]  # translation does no viscous work
    >>> float(np.abs(K @ rigid).max()) < 1e-14
    True
    """
    B = strain_operator(basis, n_comp)
    n_norm = 3 if basis.mesh.axisymmetric else 2
    D = _viscous_moduli(n_norm, B.shape[2])
    w = _per_point(mu, basis.dx.shape) * basis.dx
    return np.einsum("eq,eqsi,st,eqtj->eij", w, B, D, B, optimize=True)


def divergence(basis: QuadBasis, n_comp: int = 2) -> NDArray[np.float64]:
    """∫_e ∇·δu dΩ per element (P0 test function 1), shape (n_el, 4 n_comp).

    Includes u_r/r in axisymmetry; the swirl component has no divergence.
    The P0-pressure block of a Stokes system is ``B = −divergence``.
    """
    n_el = basis.dx.shape[0]
    D = np.zeros((n_el, 4 * n_comp))
    D[:, 0:4] = np.einsum("eq,eqa->ea", basis.dx, basis.dN[..., 0])
    D[:, 4:8] = np.einsum("eq,eqa->ea", basis.dx, basis.dN[..., 1])
    if basis.mesh.axisymmetric:
        D[:, 0:4] += np.einsum("eq,qa->ea", basis.dx / basis.radius, basis.N)
    return D


def body_force(
    basis: QuadBasis,
    f: ArrayLike | Callable[[NDArray[np.float64]], NDArray[np.float64]],
    n_comp: int = 2,
) -> NDArray[np.float64]:
    """Load vectors ∫ f · δu dΩ, shape (n_el, 4 n_comp).

    ``f`` [N/m³] is a constant vector (n_comp,), an array (n_el, n_q, n_comp), or a
    callable of quadrature-point coordinates (n_el, n_q, 2) returning (n_el, n_q, n_comp).
    """
    fv = f(basis.x) if callable(f) else np.asarray(f, dtype=float)
    fv = np.broadcast_to(fv, basis.dx.shape + (n_comp,))
    F = np.einsum("eq,qa,eqc->eca", basis.dx, basis.N, fv)
    return F.reshape(F.shape[0], 4 * n_comp)


def pressure_jump(
    face: FaceBasis, delta: float, mu: ArrayLike, local: bool = False
) -> NDArray[np.float64]:
    """Pressure-jump stabilisation for P0 pressure, (n_f, 2, 2).

    C(p, q) = Σ_F (δ h_F / μ) ∫_F [[p]] [[q]] dΓ (h_F the edge length, dΓ with the
    measure weight), entered as −C in the continuity block (Silvester & Kechkar
    1990; Elman, Silvester & Wathen 2014, §3.3.2). δ [-] is dimensionless; 1/4 is
    the value those authors recommend.

    - ``local=False`` (global): F runs over all interior edges. A smooth pressure
      gradient then leaves a mass source in the first and last element of each row
      (one-sided jumps), which spoils velocity near inflow/outflow boundaries.
    - ``local=True`` (Kechkar–Silvester): F runs only over the edges inside each
      macroelement (``mesh.patches``, e.g. 2×2 blocks); C sums to zero over each
      macroelement, so mass is conserved per macroelement and a linear pressure
      only redistributes flow locally.

    Rows and columns are the two elements of ``face.elements`` (a face outside the
    chosen set gets a zero matrix). ``mu`` [Pa·s] is a scalar or per face (n_f,).

    Examples
    --------
    >>> from twofluid.mesh.quad import rectangle
    >>> C = pressure_jump(FaceBasis(rectangle(0, 2, 0, 1, 2, 1)), 0.25, 1.0)
    >>> C[0].tolist()
    [[0.25, -0.25], [-0.25, 0.25]]
    """
    c = delta * face.length / np.asarray(mu, dtype=float) * face.ds.sum(axis=1)
    if local:
        patches = face.mesh.patches
        if patches is None:
            raise ValueError("local pressure-jump stabilisation needs mesh.patches")
        c = c * (patches[face.elements[:, 0]] == patches[face.elements[:, 1]])
    return c[:, None, None] * np.array([[1.0, -1.0], [-1.0, 1.0]])


def pressure_face_gradient(
    face: FaceBasis, coef: ArrayLike = 1.0
) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Face form of ∫ c ∇p · δu dΩ for element-constant p and c, interior part.

    With p constant per element, ∇p is a surface measure on the edges:
    ∫ c ∇p · δu = Σ_F ∫_F c_F [[p]] ν · δu dΓ, [[p]] = p₊ − p₋, ν outward from the
    minus element. ``coef`` c_F per face (n_f,) (e.g. the average porosity of the
    two elements, for the n∇P term of docs/model.md) or scalar. Boundary edges (prescribed pressure) are the
    model's business.

    Returns
    -------
    G : numpy.ndarray
        (n_f, 4, 2): rows = in-plane components of the two edge nodes,
        component-major ``[c0 a, c0 b, c1 a, c1 b]`` (a swirl component gets no
        pressure force), columns = (p₋, p₊).
    nodes : numpy.ndarray
        (n_f, 2) edge nodes, to build row dofs with ``nodal_dofs(nodes, n_nodes, 2)``.
    """
    c = np.broadcast_to(np.asarray(coef, dtype=float), face.length.shape)
    w = np.einsum("f,fq,qa->fa", c, face.ds, face.phi)           # ∫ c φ_a dΓ
    rows = np.einsum("fa,fk->fka", w, face.normal).reshape(-1, 4)  # (n_f, 2 comps × 2 nodes)
    G = np.stack([-rows, rows], axis=-1)
    return G, face.edges


def pressure_jump_load(
    face: FaceBasis, delta: float, mu: ArrayLike, f: ArrayLike, local: bool = False
) -> NDArray[np.float64]:
    """Right-hand side making :func:`pressure_jump` exact for a pressure balancing ``f``.

    A body force f [N/m³] balanced by pressure (hydrostatics, p = f·x + const) has
    element pressures jumping by f·(x₊ − x₋) between centroids; penalising
    [[p]] − f·Δx instead of [[p]] keeps a fluid at rest at rest (hydrostatic consistency, docs/model.md).
    Returns (n_f, 2) loads for the continuity rows of (element₋, element₊) of a
    system whose pressure block is ``−C``: with p_f the jumps f·Δx the rows read
    −C p = −C p_f, i.e. loads ``c_F f·Δx · [+1, −1]``.
    """
    C = pressure_jump(face, delta, mu, local)[:, 0, 0]
    xc = face.mesh.points[face.mesh.cells].mean(axis=1)
    dp = (xc[face.elements[:, 1]] - xc[face.elements[:, 0]]) @ np.asarray(f, dtype=float)
    return (C * dp)[:, None] * np.array([1.0, -1.0])


def checkerboard_penalty(
    basis: QuadBasis, delta: float, mu: ArrayLike
) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Macroelement checkerboard stabilisation for P0 pressure on 2×2 patches.

    On a 2×2 macroelement M the only pressure mode that Q1 velocities inside M cannot
    see, apart from constants, is the local checkerboard c_M(p) = ¼ Σ_e s_e p_e
    (s_e = ±1, :meth:`~twofluid.mesh.quad.QuadMesh.patch_elements`). Penalising just
    that mode, C_M(p, q) = (4δ/μ) |M| c_M(p) c_M(q) (|M| with the measure weight),
    restores stability by Stenberg's macroelement argument, with the same strength
    as the local jump term on the checkerboard (uniform meshes), while c_M vanishes
    for any pressure linear in x on a parallelogram patch: hydrostatic and
    Poiseuille pressures are not disturbed (unlike the jump terms).

    Returns
    -------
    C : (n_patch, 4, 4) matrices, entered as −C in the continuity block;
    elements : (n_patch, 4) element ids (rows/columns).

    Examples
    --------
    >>> from twofluid.mesh.quad import rectangle
    >>> C, el = checkerboard_penalty(QuadBasis(rectangle(0, 2, 0, 2, 2, 2)), 0.25, 1.0)
    >>> p_lin = np.array([0.5, 1.5, 0.5, 1.5]) + 3 * np.array([0.5, 0.5, 1.5, 1.5])
    >>> float(abs(C[0] @ p_lin[el[0]]).max())
    0.0
    """
    elements, signs = basis.mesh.patch_elements()
    vol = basis.dx.sum(axis=1)[elements].sum(axis=1)
    c = delta / (4.0 * np.asarray(mu, dtype=float)) * vol
    return c[:, None, None] * np.einsum("pa,pb->pab", signs, signs), elements
