"""Quadrilateral meshes for planar and axisymmetric 2D problems.

A :class:`QuadMesh` holds node coordinates, counter-clockwise 4-node connectivity,
named boundary groups and the geometry flag. In axisymmetry the coordinates are
(r, z) and the measure carries the weight 2πr (conventions, habit 4): quadrature
multiplies its weights by :meth:`QuadMesh.measure_weight`, so the same weak-form
terms integrate over a planar area (per metre of depth) or over the toroid the
element sweeps about the axis.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

__all__ = ["QuadMesh", "rectangle", "annular_sector", "graded_points", "block_patches",
           "remove_block"]


@dataclass
class QuadMesh:
    """Mesh of 4-node quadrilaterals.

    Parameters
    ----------
    points : numpy.ndarray
        Node coordinates, shape (n_nodes, 2) [m]; (x, y) planar, (r, z) axisymmetric.
    cells : numpy.ndarray
        Connectivity, shape (n_el, 4), nodes counter-clockwise.
    boundaries : dict
        Name -> boundary group: either edges, shape (m, 2) node pairs, or nodes,
        shape (m,).
    axisymmetric : bool
        True for (r, z) coordinates with the 2πr measure weight.
    patches : numpy.ndarray, optional
        Macroelement id of each element (n_el,), e.g. 2×2 blocks of a structured
        mesh; used by the local (Kechkar–Silvester) pressure-jump stabilisation.

    Examples
    --------
    >>> m = rectangle(0.0, 2.0, 0.0, 1.0, 2, 1)
    >>> m.n_nodes, m.n_elements, sorted(m.boundaries)
    (6, 2, ['bottom', 'left', 'right', 'top'])
    """

    points: NDArray[np.float64]
    cells: NDArray[np.int64]
    boundaries: dict[str, NDArray[np.int64]] = field(default_factory=dict)
    axisymmetric: bool = False
    patches: NDArray[np.int64] | None = None

    def __post_init__(self) -> None:
        self.points = np.ascontiguousarray(self.points, dtype=float)
        self.cells = np.ascontiguousarray(self.cells, dtype=np.int64)
        if self.points.ndim != 2 or self.points.shape[1] != 2:
            raise ValueError(f"points must have shape (n, 2), got {self.points.shape}")
        if self.cells.ndim != 2 or self.cells.shape[1] != 4:
            raise ValueError(f"cells must have shape (n_el, 4), got {self.cells.shape}")
        if self.axisymmetric and np.any(self.points[:, 0] < -1e-12 * np.ptp(self.points[:, 0])):
            raise ValueError("axisymmetric mesh needs r >= 0 for every node")
        self.boundaries = {k: np.asarray(v, dtype=np.int64) for k, v in self.boundaries.items()}
        if self.patches is not None:
            self.patches = np.asarray(self.patches, dtype=np.int64)
            if self.patches.shape != (self.n_elements,):
                raise ValueError("patches must give one macroelement id per element")

    @property
    def n_nodes(self) -> int:
        """Number of nodes."""
        return self.points.shape[0]

    @property
    def n_elements(self) -> int:
        """Number of elements."""
        return self.cells.shape[0]

    def measure_weight(self, x: NDArray[np.float64]) -> NDArray[np.float64]:
        """Geometry weight of the measure at points ``x`` (..., 2) [m]: 1 planar, 2πr axisymmetric.

        Examples
        --------
        >>> m = rectangle(1.0, 2.0, 0.0, 1.0, 1, 1, axisymmetric=True)
        >>> float(m.measure_weight(np.array([[1.5, 0.3]]))[0] / np.pi)
        3.0
        """
        x = np.asarray(x, dtype=float)
        if self.axisymmetric:
            return 2.0 * np.pi * x[..., 0]
        return np.ones(x.shape[:-1])

    def boundary_nodes(self, name: str) -> NDArray[np.int64]:
        """Sorted unique node indices of boundary group ``name`` (edges or nodes)."""
        if name not in self.boundaries:
            raise KeyError(f"no boundary group {name!r}; groups are {sorted(self.boundaries)}")
        return np.unique(self.boundaries[name])

    def boundary_edges(self, name: str) -> NDArray[np.int64]:
        """Edges (m, 2) of boundary group ``name``; error if it only lists nodes."""
        group = self.boundaries[name]
        if group.ndim != 2:
            raise ValueError(f"boundary group {name!r} lists nodes, not edges")
        return group

    def interior_edges(self) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
        """Edges shared by two elements.

        Returns
        -------
        edges : numpy.ndarray
            (n_f, 2) node pairs, ordered counter-clockwise as seen from the first element.
        elements : numpy.ndarray
            (n_f, 2) the element owning the edge counter-clockwise ("minus" side,
            whose outward normal is the face normal) and its neighbour ("plus" side).
        """
        local = np.array([[0, 1], [1, 2], [2, 3], [3, 0]])
        e = self.cells[:, local].reshape(-1, 2)
        owner = np.repeat(np.arange(self.n_elements), 4)
        key = np.sort(e, axis=1)
        order = np.lexsort((key[:, 1], key[:, 0]))
        ks = key[order]
        same = np.all(ks[1:] == ks[:-1], axis=1)
        first = order[:-1][same]
        second = order[1:][same]
        return e[first], np.stack([owner[first], owner[second]], axis=1)

    def patch_elements(self) -> tuple[NDArray[np.int64], NDArray[np.float64]]:
        """Elements of each 2×2 macroelement and their checkerboard signs.

        Returns
        -------
        elements : numpy.ndarray
            (n_patch, 4) element ids, in increasing element order.
        signs : numpy.ndarray
            (n_patch, 4) ±1: +1 on the first element and its diagonal partner, −1 on
            its two edge neighbours (the 2-colouring of the patch's 4-cycle).

        Raises
        ------
        ValueError
            If the mesh has no patches or a patch is not a cycle of four elements.
        """
        if self.patches is None:
            raise ValueError("mesh has no macroelement patches")
        order = np.argsort(self.patches, kind="stable")
        ids, counts = np.unique(self.patches, return_counts=True)
        if np.any(counts != 4):
            raise ValueError("every macroelement patch must hold exactly four elements")
        elements = order.reshape(-1, 4)
        _, pair = self.interior_edges()
        pair = pair[self.patches[pair[:, 0]] == self.patches[pair[:, 1]]]
        pid = np.searchsorted(ids, self.patches)
        first = elements[:, 0]
        signs_el = np.ones(self.n_elements)
        for a, b in ((0, 1), (1, 0)):
            hit = pair[:, a] == first[pid[pair[:, a]]]
            signs_el[pair[hit, b]] = -1.0
        signs = signs_el[elements]
        if pair.shape[0] != 4 * ids.size or np.any(signs.sum(axis=1) != 0):
            raise ValueError("macroelement patches must be 2×2 blocks (4-cycles of elements)")
        return elements, signs

    def element_size(self) -> NDArray[np.float64]:
        """Element size h_e = sqrt(planar area) [m], shape (n_el,)."""
        x = self.points[self.cells]
        a = 0.5 * np.abs(
            (x[:, 2, 0] - x[:, 0, 0]) * (x[:, 3, 1] - x[:, 1, 1])
            - (x[:, 3, 0] - x[:, 1, 0]) * (x[:, 2, 1] - x[:, 0, 1])
        )
        return np.sqrt(a)


def graded_points(a: float, b: float, n: int, ratio: float | None = None) -> NDArray[np.float64]:
    """n + 1 points from a to b whose last/first interval ratio is ``ratio`` (geometric).

    Examples
    --------
    >>> graded_points(0.0, 3.0, 2, ratio=2.0).tolist()
    [0.0, 1.0, 3.0]
    """
    if n < 1:
        raise ValueError("need at least one interval")
    if ratio is None or ratio == 1.0:
        return np.linspace(a, b, n + 1)
    if ratio <= 0.0:
        raise ValueError("grading ratio must be positive")
    q = ratio ** (1.0 / max(n - 1, 1))
    d = q ** np.arange(n)
    return a + (b - a) * np.concatenate([[0.0], np.cumsum(d) / d.sum()])


def block_patches(nx: int, ny: int) -> NDArray[np.int64] | None:
    """2×2 macroelement ids of a row-by-row structured nx × ny mesh (None if nx or ny is odd).

    Examples
    --------
    >>> block_patches(4, 2).tolist()
    [0, 0, 1, 1, 0, 0, 1, 1]
    """
    if nx % 2 or ny % 2:
        return None
    i, j = np.meshgrid(np.arange(nx) // 2, np.arange(ny) // 2)
    return (j * (nx // 2) + i).ravel()


def _structured(xs: NDArray, ys: NDArray) -> tuple[NDArray, NDArray, dict]:
    nx, ny = xs.shape[0] - 1, ys.shape[0] - 1
    idx = np.arange((nx + 1) * (ny + 1)).reshape(ny + 1, nx + 1)
    cells = np.stack(
        [idx[:-1, :-1], idx[:-1, 1:], idx[1:, 1:], idx[1:, :-1]], axis=-1
    ).reshape(-1, 4)
    bnd = {
        "bottom": np.stack([idx[0, :-1], idx[0, 1:]], axis=1),
        "right": np.stack([idx[:-1, -1], idx[1:, -1]], axis=1),
        "top": np.stack([idx[-1, 1:], idx[-1, :-1]], axis=1),
        "left": np.stack([idx[1:, 0], idx[:-1, 0]], axis=1),
    }
    return idx, cells, bnd


def rectangle(
    x0: float, x1: float, y0: float, y1: float, nx: int, ny: int, *,
    axisymmetric: bool = False, grading: tuple[float | None, float | None] | None = None,
) -> QuadMesh:
    """Structured nx × ny mesh of [x0, x1] × [y0, y1] [m].

    Elements are numbered row by row (x fastest), so element (i, j) is ``j*nx + i``;
    for even nx and ny the 2×2 blocks are recorded as macroelement ``patches``.
    Boundary groups "left", "right", "bottom", "top"; in axisymmetry (x = r, y = z)
    also "inner" (= left) and "outer" (= right).

    Parameters
    ----------
    grading : (ratio_x, ratio_y), optional
        Last/first element-size ratio along each direction (None or 1: uniform).

    Examples
    --------
    >>> m = rectangle(0.01, 0.05, 0.0, 0.1, 4, 8, axisymmetric=True)
    >>> m.boundary_nodes("inner").size, bool(np.all(m.points[m.boundary_nodes("inner"), 0] == 0.01))
    (9, True)
    """
    gx, gy = grading if grading is not None else (None, None)
    xs = graded_points(x0, x1, nx, gx)
    ys = graded_points(y0, y1, ny, gy)
    X, Y = np.meshgrid(xs, ys)
    _, cells, bnd = _structured(xs, ys)
    if axisymmetric:
        bnd["inner"], bnd["outer"] = bnd["left"], bnd["right"]
    return QuadMesh(np.column_stack([X.ravel(), Y.ravel()]), cells, bnd, axisymmetric,
                    block_patches(nx, ny))


def annular_sector(r_i: float, r_o: float, angle_rad: float, nr: int, nt: int) -> QuadMesh:
    """Planar mesh of the ring sector r_i ≤ r ≤ r_o, 0 ≤ θ ≤ angle_rad [m, rad].

    Boundary groups "inner", "outer", "start" (θ = 0) and "end" (θ = angle_rad).
    Nodes lie on the circles, edges are straight chords.

    Examples
    --------
    >>> m = annular_sector(1.0, 2.0, np.pi / 2, 2, 4)
    >>> bool(np.allclose(np.hypot(*m.points[m.boundary_nodes("outer")].T), 2.0))
    True
    """
    rs = np.linspace(r_i, r_o, nr + 1)
    ts = np.linspace(0.0, angle_rad, nt + 1)
    R, T = np.meshgrid(rs, ts)
    _, cells, bnd = _structured(rs, ts)
    names = {"left": "inner", "right": "outer", "bottom": "start", "top": "end"}
    bnd = {names[k]: v for k, v in bnd.items()}
    pts = np.column_stack([(R * np.cos(T)).ravel(), (R * np.sin(T)).ravel()])
    return QuadMesh(pts, cells, bnd, axisymmetric=False, patches=block_patches(nr, nt))


def remove_block(mesh: QuadMesh, x0: float, x1: float, y0: float, y1: float,
                 name: str = "cut") -> QuadMesh:
    """Mesh without the elements whose centroid lies in [x0, x1] × [y0, y1] [m].

    The edges the removed elements shared with kept ones form the new boundary
    group ``name`` (e.g. the wetted surface of a spindle); existing edge groups keep
    only edges of kept elements. Nodes are renumbered; macroelement patches cut by
    the block are dropped (then ``patches`` is None), so cut along even element
    lines of a structured mesh to keep the checkerboard stabilisation.

    Examples
    --------
    >>> m = remove_block(rectangle(0.0, 4.0, 0.0, 4.0, 4, 4), 0.0, 2.0, 2.0, 4.0, "spindle")
    >>> m.n_elements, m.boundary_edges("spindle").shape[0], m.patches is not None
    (12, 4, True)
    """
    xc = mesh.points[mesh.cells].mean(axis=1)
    gone = (xc[:, 0] >= x0) & (xc[:, 0] <= x1) & (xc[:, 1] >= y0) & (xc[:, 1] <= y1)
    local = np.array([[0, 1], [1, 2], [2, 3], [3, 0]])

    def keys(cells):
        e = np.sort(cells[:, local].reshape(-1, 2), axis=1)
        return e[:, 0] * mesh.n_nodes + e[:, 1]

    kept_cells = mesh.cells[~gone]
    kept_keys = keys(kept_cells)
    cut = np.isin(kept_keys, keys(mesh.cells[gone]))
    new_edges = kept_cells[:, local].reshape(-1, 2)[cut]  # ccw as seen from the kept element
    used = np.unique(kept_cells)
    renum = np.full(mesh.n_nodes, -1, dtype=np.int64)
    renum[used] = np.arange(used.size)
    groups = {}
    for gname, g in mesh.boundaries.items():
        if g.ndim == 2:
            g = g[np.isin(np.sort(g, axis=1) @ np.array([mesh.n_nodes, 1]), kept_keys)]
        else:
            g = g[renum[g] >= 0]
        if g.size:
            groups[gname] = renum[g]
    groups[name] = renum[new_edges]
    patches = None
    if mesh.patches is not None:
        p = mesh.patches[~gone]
        if not np.any(np.isin(p, mesh.patches[gone])):
            patches = np.unique(p, return_inverse=True)[1]
    return QuadMesh(mesh.points[used], renum[kept_cells], groups, mesh.axisymmetric, patches)
