"""Bilinear quadrilateral element, its quadrature and vectorised COO assembly.

The pieces, in the order a model uses them:

- :class:`Q1` — reference shape functions of the 4-node quadrilateral and a
  tensor Gauss rule;
- :class:`QuadBasis` — shape values, physical gradients and integration weights at
  every quadrature point of every element at once, arrays of shape (n_el, n_q, ...).
  The weights ``dx`` already contain det J and the mesh's measure weight (2πr in
  axisymmetry), so a term is the same sum in planar and axisymmetric meshes;
- :class:`FaceBasis` — the same on interior edges, for jump and face terms;
- :class:`SparsityPattern` — row/column index arrays of all blocks, built once;
  each assembly only fills values (``np.bincount`` onto the CSR slots).

Degrees of freedom: velocity component c at node i is ``c * n_nodes + i``
(component blocks); element-wise (P0) fields are numbered by element after an
offset. Local element vectors order dofs component-major: ``[c0 n0..n3, c1 n0..n3, ...]``.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from twofluid.mesh.quad import QuadMesh

__all__ = ["Q1", "QuadBasis", "FaceBasis", "SparsityPattern", "gauss_legendre",
           "nodal_dofs", "element_dofs", "assemble_vector"]


def gauss_legendre(n: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """n-point Gauss–Legendre points and weights on [-1, 1] (exact to degree 2n − 1)."""
    return np.polynomial.legendre.leggauss(n)


class Q1:
    """Bilinear 4-node quadrilateral on the reference square [-1, 1]².

    Nodes counter-clockwise: (-1,-1), (1,-1), (1,1), (-1,1). ``order`` is the number
    of Gauss points per direction (2 integrates the Q1 mass matrix exactly on
    parallelograms).

    Examples
    --------
    >>> el = Q1()
    >>> el.points.shape, round(float(el.weights.sum()), 12)
    ((4, 2), 4.0)
    >>> bool(np.allclose(el.shape(el.points).sum(axis=1), 1.0))
    True
    """

    n_nodes = 4
    nodes = np.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]])

    def __init__(self, order: int = 2) -> None:
        g, w = gauss_legendre(order)
        xi, eta = np.meshgrid(g, g, indexing="xy")
        self.points = np.column_stack([xi.ravel(), eta.ravel()])
        self.weights = np.outer(w, w).ravel()

    def shape(self, xi: NDArray[np.float64]) -> NDArray[np.float64]:
        """Shape functions N_a(ξ), shape (n_points, 4)."""
        xi = np.atleast_2d(xi)
        return 0.25 * (1 + xi[:, None, 0] * self.nodes[:, 0]) * (1 + xi[:, None, 1] * self.nodes[:, 1])

    def shape_grad(self, xi: NDArray[np.float64]) -> NDArray[np.float64]:
        """Reference gradients ∂N_a/∂ξ_k, shape (n_points, 4, 2)."""
        xi = np.atleast_2d(xi)
        s, t = self.nodes[:, 0], self.nodes[:, 1]
        d0 = 0.25 * s * (1 + xi[:, None, 1] * t)
        d1 = 0.25 * t * (1 + xi[:, None, 0] * s)
        return np.stack([d0, d1], axis=-1)


class QuadBasis:
    """Element values of a :class:`Q1` field at the quadrature points of a mesh.

    Attributes
    ----------
    x : (n_el, n_q, 2) quadrature-point coordinates [m]
    N : (n_q, 4) shape values (same on every element)
    dN : (n_el, n_q, 4, 2) physical gradients [1/m]
    detJ : (n_el, n_q) Jacobian determinant [m²]
    dx : (n_el, n_q) integration weights w_q · det J · measure weight [m² or m³]

    Examples
    --------
    >>> from twofluid.mesh.quad import rectangle
    >>> b = QuadBasis(rectangle(1.0, 2.0, 0.0, 3.0, 2, 3, axisymmetric=True))
    >>> round(float(b.dx.sum() / np.pi), 10)  # π (r_o² − r_i²) h
    9.0
    """

    def __init__(self, mesh: QuadMesh, element: Q1 | None = None, order: int = 2) -> None:
        self.mesh = mesh
        self.element = element if element is not None else Q1(order)
        el = self.element
        xe = mesh.points[mesh.cells]                       # (n_el, 4, 2)
        self.N = el.shape(el.points)                       # (nq, 4)
        dref = el.shape_grad(el.points)                    # (nq, 4, 2)
        self.x = np.einsum("qa,ead->eqd", self.N, xe)
        J = np.einsum("qak,ead->eqdk", dref, xe)           # J[d, k] = ∂x_d/∂ξ_k
        self.detJ = J[..., 0, 0] * J[..., 1, 1] - J[..., 0, 1] * J[..., 1, 0]
        if np.any(self.detJ <= 0.0):
            bad = np.unique(np.nonzero(self.detJ <= 0.0)[0])
            raise ValueError(f"non-positive Jacobian in elements {bad[:10].tolist()} "
                             "(clockwise or degenerate cells)")
        Jinv = np.empty_like(J)
        Jinv[..., 0, 0], Jinv[..., 1, 1] = J[..., 1, 1], J[..., 0, 0]
        Jinv[..., 0, 1], Jinv[..., 1, 0] = -J[..., 0, 1], -J[..., 1, 0]
        Jinv /= self.detJ[..., None, None]
        self.dN = np.einsum("qak,eqkd->eqad", dref, Jinv)
        self.dx = el.weights * self.detJ * mesh.measure_weight(self.x)

    @property
    def radius(self) -> NDArray[np.float64]:
        """First coordinate (r in axisymmetry) at quadrature points, (n_el, n_q) [m]."""
        return self.x[..., 0]

    def interpolate(self, nodal: NDArray[np.float64]) -> NDArray[np.float64]:
        """Values of a nodal field (n_nodes, ...) at quadrature points, (n_el, n_q, ...)."""
        return np.einsum("qa,ea...->eq...", self.N, nodal[self.mesh.cells])

    def integrate(self, values: NDArray[np.float64]) -> float:
        """∫ f dΩ for quadrature-point values (n_el, n_q) (2πr included in axisymmetry)."""
        return float(np.sum(values * self.dx))


class FaceBasis:
    """Gauss points on the interior edges of a mesh, for jump and face terms.

    Attributes
    ----------
    edges, elements : as returned by :meth:`QuadMesh.interior_edges`
    x : (n_f, n_q, 2) points [m];  ds : (n_f, n_q) weights with measure weight [m or m²]
    normal : (n_f, 2) unit normal, outward from ``elements[:, 0]``
    length : (n_f,) edge length [m]
    phi : (n_q, 2) values of the two edge-node hat functions along the edge

    Examples
    --------
    >>> from twofluid.mesh.quad import rectangle
    >>> f = FaceBasis(rectangle(0.0, 2.0, 0.0, 1.0, 2, 1))
    >>> f.edges.shape, (f.normal + 0.0).tolist(), round(float(f.ds.sum()), 12)
    ((1, 2), [[1.0, 0.0]], 1.0)
    """

    def __init__(self, mesh: QuadMesh, order: int = 2) -> None:
        self.mesh = mesh
        self.edges, self.elements = mesh.interior_edges()
        g, w = gauss_legendre(order)
        self.phi = np.column_stack([(1 - g) / 2, (1 + g) / 2])
        xa, xb = mesh.points[self.edges[:, 0]], mesh.points[self.edges[:, 1]]
        d = xb - xa
        self.length = np.hypot(d[:, 0], d[:, 1])
        self.normal = np.column_stack([d[:, 1], -d[:, 0]]) / self.length[:, None] + 0.0
        self.x = np.einsum("qa,fad->fqd", self.phi, np.stack([xa, xb], axis=1))
        self.ds = 0.5 * w * self.length[:, None] * mesh.measure_weight(self.x)


def nodal_dofs(cells: NDArray[np.int64], n_nodes: int, n_comp: int) -> NDArray[np.int64]:
    """Global dofs of an element's nodal vector field, (n_el, 4 n_comp), component-major.

    Examples
    --------
    >>> nodal_dofs(np.array([[0, 1, 3, 2]]), 4, 2).tolist()
    [[0, 1, 3, 2, 4, 5, 7, 6]]
    """
    return np.concatenate([cells + c * n_nodes for c in range(n_comp)], axis=1)


def element_dofs(n_el: int, offset: int = 0) -> NDArray[np.int64]:
    """Global dofs of a P0 field, (n_el, 1): ``offset + e``."""
    return (offset + np.arange(n_el))[:, None]


class SparsityPattern:
    """Fixed CSR pattern of a sum of element blocks; fill values per assembly.

    Parameters
    ----------
    blocks : list of (row_dofs, col_dofs)
        ``row_dofs`` (n_b, kr), ``col_dofs`` (n_b, kc): block b adds an
        (n_b, kr, kc) array of element matrices at rows × columns.
    shape : (int, int)
        Global matrix shape.

    Examples
    --------
    >>> pat = SparsityPattern([(np.array([[0, 1]]), np.array([[0, 1]])),
    ...                        (np.array([[1, 2]]), np.array([[1, 2]]))], (3, 3))
    >>> A = pat.assemble([np.ones((1, 2, 2)), np.ones((1, 2, 2))])
    >>> A.toarray().tolist()
    [[1.0, 1.0, 0.0], [1.0, 2.0, 1.0], [0.0, 1.0, 1.0]]
    """

    def __init__(self, blocks: list[tuple[NDArray, NDArray]], shape: tuple[int, int]) -> None:
        rows, cols, self.sizes = [], [], []
        for r, c in blocks:
            rows.append(np.broadcast_to(r[:, :, None], (r.shape[0], r.shape[1], c.shape[1])).ravel())
            cols.append(np.broadcast_to(c[:, None, :], (c.shape[0], r.shape[1], c.shape[1])).ravel())
            self.sizes.append(rows[-1].size)
        rows_all, cols_all = np.concatenate(rows), np.concatenate(cols)
        self.shape = shape
        key = rows_all.astype(np.int64) * shape[1] + cols_all
        uniq, self.slot = np.unique(key, return_inverse=True)
        self.indices = (uniq % shape[1]).astype(np.int32)
        counts = np.bincount(uniq // shape[1], minlength=shape[0])
        self.indptr = np.concatenate([[0], np.cumsum(counts)]).astype(np.int32)
        self.nnz = uniq.size

    def assemble(self, values: list[NDArray[np.float64]]) -> sp.csr_matrix:
        """CSR matrix from element blocks given in the order of the constructor."""
        data = np.concatenate([np.asarray(v, dtype=float).ravel() for v in values])
        if data.size != self.slot.size:
            raise ValueError(f"expected {self.slot.size} values, got {data.size}")
        summed = np.bincount(self.slot, weights=data, minlength=self.nnz)
        return sp.csr_matrix((summed, self.indices, self.indptr), shape=self.shape)


def assemble_vector(dofs: NDArray[np.int64], values: NDArray[np.float64], size: int) -> NDArray:
    """Scatter-add element vectors ``values`` (n_el, k) at ``dofs`` (n_el, k) into a vector."""
    return np.bincount(dofs.ravel(), weights=np.asarray(values, float).ravel(), minlength=size)
