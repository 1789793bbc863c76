"""1D elements along a LineMesh, vectorised over elements.

Velocity-like fields (V, W) use Lagrange bases of order 1 or 2 on each element;
porosity is constant per element; pressure is constant per element (order 0)
or linear and continuous (order 1). Local coordinate ξ ∈ [0, 1].

Global numbering of a continuous field of order p: vertex i has number p·i, the
midside node of element e (p = 2) has number 2e + 1, so that the system stays
banded.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..mesh.line import LineMesh

__all__ = ["Lagrange1D", "LINE1", "LINE2", "ElementValues", "element_values"]


@dataclass(frozen=True)
class Lagrange1D:
    """Lagrange basis of ``order`` on ξ ∈ [0, 1] with equally spaced nodes.

    >>> LINE2.shape(np.array([0.5])).round(12).tolist()
    [[0.0, 1.0, 0.0]]
    >>> float(LINE1.dshape(np.array([0.3])).sum())
    0.0
    """

    order: int

    @property
    def n_local(self) -> int:
        return self.order + 1

    def shape(self, xi: np.ndarray) -> np.ndarray:
        """(len(ξ), n_local) shape function values."""
        if self.order == 1:
            return np.stack([1.0 - xi, xi], axis=1)
        return np.stack([(1 - xi) * (1 - 2 * xi), 4 * xi * (1 - xi), xi * (2 * xi - 1)], axis=1)

    def dshape(self, xi: np.ndarray) -> np.ndarray:
        """(len(ξ), n_local) derivatives d/dξ."""
        if self.order == 1:
            return np.stack([-np.ones_like(xi), np.ones_like(xi)], axis=1)
        return np.stack([4 * xi - 3, 4 - 8 * xi, 4 * xi - 1], axis=1)

    def dofs(self, n_elements: int) -> np.ndarray:
        """(n_el, n_local) global node numbers."""
        e = np.arange(n_elements)[:, None]
        return self.order * e + np.arange(self.n_local)[None, :]

    def n_nodes(self, n_elements: int) -> int:
        return self.order * n_elements + 1


LINE1 = Lagrange1D(1)
LINE2 = Lagrange1D(2)


@dataclass(frozen=True)
class ElementValues:
    """Basis values at quadrature points of all elements.

    N : (nq, nl) shape values; dN : (n_el, nq, nl) d/dy; div : (n_el, nq, nl)
    the divergence of a basis function in the duct, (1/A) d(A N)/dy;
    JxW : (n_el, nq) quadrature weight × length × A(y) — the measure.
    """

    N: np.ndarray
    dN: np.ndarray
    div: np.ndarray
    JxW: np.ndarray


def element_values(mesh: LineMesh, basis: Lagrange1D, n_quad: int = 4) -> ElementValues:
    """Quadrature data for ``basis`` on every element of ``mesh`` (Gauss–Legendre).

    >>> from twofluid.mesh.line import uniform_line
    >>> ev = element_values(uniform_line(1.0, 5, area=(1.0, 2.0)), LINE1)
    >>> round(float(ev.JxW.sum()), 12)   # ∫ A dy
    1.5
    """
    x, w = np.polynomial.legendre.leggauss(n_quad)
    xi, w = 0.5 * (x + 1.0), 0.5 * w
    h = mesh.lengths[:, None]
    e = np.arange(mesh.n_elements)
    area_q = mesh.area_at(e, xi)
    N = basis.shape(xi)
    dN = basis.dshape(xi)[None, :, :] / h[:, :, None]
    div = dN + N[None, :, :] * (mesh.area_slope[:, None, None] / area_q[:, :, None])
    return ElementValues(N, dN, div, w[None, :] * h * area_q)
