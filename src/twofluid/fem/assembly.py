"""Vectorised scatter of element arrays into one sparse block system.

The system is split in named blocks of unknowns (e.g. V, W, P, n), each with an
offset. Terms add element matrices with their row and column dof maps; no loop
over elements. Triplets are summed by ``scipy.sparse`` on conversion (or by the
band solver, :mod:`twofluid.fem.banded`).

Element matrices added with the same dof maps (the same array objects) and shape
are summed element by element before they are scattered, and the global row and
column indices of a dof map are kept in ``pattern`` (a dict the model passes to
every system it assembles): the Python/NumPy cost of one iterate is then a few
array additions per term, not a scatter.
"""
from __future__ import annotations

import numpy as np

__all__ = ["BlockSystem"]


class BlockSystem:
    """Collects element matrices, COO triplets and a right-hand side for blocks of unknowns.

    >>> s = BlockSystem({"u": 2, "p": 1})
    >>> s.add("u", "u", np.array([[0, 1]]), np.array([[0, 1]]), np.eye(2)[None])
    >>> s.add("p", "u", np.array([[0]]), np.array([[0, 1]]), np.array([[[1.0, -1.0]]]))
    >>> s.matrix().toarray().tolist()
    [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, -1.0, 0.0]]
    """

    def __init__(self, sizes: dict[str, int], pattern: dict | None = None):
        self.offset: dict[str, int] = {}
        total = 0
        for name, size in sizes.items():
            self.offset[name] = total
            total += size
        self.size = total
        self._rhs = np.zeros(total)
        self._rhs_blocks: dict = {}  # (row, id(rdofs)) -> [rdofs, summed element vectors]
        self._blocks: dict = {}  # (row, col, id(rdofs), id(cdofs), shape) -> [rdofs, cdofs, summed matrices]
        self._pattern = {} if pattern is None else pattern
        self._rows: list[np.ndarray] = []
        self._cols: list[np.ndarray] = []
        self._vals: list[np.ndarray] = []

    def copy(self) -> "BlockSystem":
        """A system holding the same terms, to add more to (element arrays shared, not copied)."""
        new = BlockSystem.__new__(BlockSystem)
        new.offset, new.size, new._pattern = self.offset, self.size, self._pattern
        new._rhs = self.rhs.copy()
        new._rhs_blocks = {}
        new._blocks = {key: list(blk) for key, blk in self._blocks.items()}
        new._rows, new._cols, new._vals = list(self._rows), list(self._cols), list(self._vals)
        return new

    def slice(self, name: str, size: int) -> slice:
        return slice(self.offset[name], self.offset[name] + size)

    def add(self, row: str, col: str, rdofs: np.ndarray, cdofs: np.ndarray,
            local: np.ndarray) -> None:
        """Add element matrices ``local`` (n_el, a, b) at (rdofs (n_el, a), cdofs (n_el, b))."""
        key = (row, col, id(rdofs), id(cdofs), local.shape)
        blk = self._blocks.get(key)
        if blk is None:
            self._blocks[key] = [rdofs, cdofs, local]
        else:
            blk[2] = blk[2] + local

    def add_entries(self, row: str, col: str, r: np.ndarray, c: np.ndarray, v: np.ndarray) -> None:
        """Add single entries (vectors of equal length)."""
        self._rows.append(np.asarray(r) + self.offset[row])
        self._cols.append(np.asarray(c) + self.offset[col])
        self._vals.append(np.asarray(v, dtype=float))

    def add_rhs(self, row: str, rdofs: np.ndarray, local: np.ndarray) -> None:
        """Add element vectors ``local`` (n_el, a) (or plain vectors) at ``rdofs``."""
        key = (row, id(rdofs))
        blk = self._rhs_blocks.get(key)
        if blk is None:
            self._rhs_blocks[key] = [rdofs, local]
        else:
            blk[1] = blk[1] + local

    @property
    def rhs(self) -> np.ndarray:
        """The right-hand side (the element vectors added so far scattered into it)."""
        for (row, _), (rdofs, local) in self._rhs_blocks.items():
            np.add.at(self._rhs, np.asarray(rdofs) + self.offset[row], local)
        self._rhs_blocks = {}
        return self._rhs

    def _indices(self, key, rdofs, cdofs) -> tuple[np.ndarray, np.ndarray]:
        """Global (rows, cols) of every entry of a block's element matrices (cached in the pattern)."""
        hit = self._pattern.get(key)
        if hit is not None and hit[0] is rdofs and hit[1] is cdofs:
            return hit[2], hit[3]
        if len(self._pattern) > 256:  # dof maps that are not kept from one system to the next
            self._pattern.clear()
        row, col, _, _, shape = key
        r = np.broadcast_to((rdofs + self.offset[row])[:, :, None], shape).ravel()
        c = np.broadcast_to((cdofs + self.offset[col])[:, None, :], shape).ravel()
        self._pattern[key] = (rdofs, cdofs, r, c)
        return r, c

    def triplets(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(rows, cols, values) of all entries added (duplicates not yet summed)."""
        rows, cols, vals = list(self._rows), list(self._cols), list(self._vals)
        for key, (rdofs, cdofs, local) in self._blocks.items():
            r, c = self._indices(key, rdofs, cdofs)
            rows.append(r)
            cols.append(c)
            vals.append(local.ravel())
        return np.concatenate(rows), np.concatenate(cols), np.concatenate(vals)

    def matrix(self):
        """The summed matrix as ``scipy.sparse.csr_matrix`` (SciPy's sparse module imported on use)."""
        import scipy.sparse as sp

        rows, cols, vals = self.triplets()
        return sp.csr_matrix((vals, (rows, cols)), shape=(self.size, self.size))
