"""Vectorised scatter of element arrays into one sparse block system.

The system is split in named blocks of unknowns (e.g. V, W, P, n), each with an
offset. Terms add element matrices with their row and column dof maps; no loop
over elements. Triplets are summed by ``scipy.sparse`` on conversion.
"""
from __future__ import annotations

import numpy as np
import scipy.sparse as sp

__all__ = ["BlockSystem"]


class BlockSystem:
    """Collects COO triplets and a right-hand side for blocks of unknowns.

    >>> s = BlockSystem({"u": 2, "p": 1})
    >>> s.add("u", "u", np.array([[0, 1]]), np.array([[0, 1]]), np.eye(2)[None])
    >>> s.add("p", "u", np.array([[0]]), np.array([[0, 1]]), np.array([[[1.0, -1.0]]]))
    >>> s.matrix().toarray().tolist()
    [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, -1.0, 0.0]]
    """

    def __init__(self, sizes: dict[str, int]):
        self.offset: dict[str, int] = {}
        total = 0
        for name, size in sizes.items():
            self.offset[name] = total
            total += size
        self.size = total
        self.rhs = np.zeros(total)
        self._rows: list[np.ndarray] = []
        self._cols: list[np.ndarray] = []
        self._vals: list[np.ndarray] = []

    def slice(self, name: str, size: int) -> slice:
        return slice(self.offset[name], self.offset[name] + size)

    def add(self, row: str, col: str, rdofs: np.ndarray, cdofs: np.ndarray,
            local: np.ndarray) -> None:
        """Add element matrices ``local`` (n_el, a, b) at (rdofs (n_el, a), cdofs (n_el, b))."""
        r = np.broadcast_to((rdofs + self.offset[row])[:, :, None], local.shape)
        c = np.broadcast_to((cdofs + self.offset[col])[:, None, :], local.shape)
        self._rows.append(r.ravel())
        self._cols.append(c.ravel())
        self._vals.append(local.ravel())

    def add_entries(self, row: str, col: str, r: np.ndarray, c: np.ndarray, v: np.ndarray) -> None:
        """Add single entries (vectors of equal length)."""
        self._rows.append(np.asarray(r) + self.offset[row])
        self._cols.append(np.asarray(c) + self.offset[col])
        self._vals.append(np.asarray(v, dtype=float))

    def add_rhs(self, row: str, rdofs: np.ndarray, local: np.ndarray) -> None:
        """Add element vectors ``local`` (n_el, a) (or plain vectors) at ``rdofs``."""
        np.add.at(self.rhs, np.asarray(rdofs) + self.offset[row], local)

    def triplets(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(rows, cols, values) of all entries added (duplicates not yet summed)."""
        return np.concatenate(self._rows), np.concatenate(self._cols), np.concatenate(self._vals)

    def matrix(self) -> sp.csr_matrix:
        rows, cols, vals = self.triplets()
        return sp.csr_matrix((vals, (rows, cols)), shape=(self.size, self.size))
