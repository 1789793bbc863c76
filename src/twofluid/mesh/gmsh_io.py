"""Read quadrilateral meshes (Gmsh .msh v2/v4 or any meshio format) into a QuadMesh.

Gmsh physical groups become named boundary groups: physical curves (line
elements) give edge groups, physical points (vertex elements) give node groups.
Files without Gmsh tags may name groups through meshio ``cell_sets``. The domain
must consist of 4-node quadrilaterals; coordinates are taken as (x, y), or (r, z)
with ``axisymmetric=True``. Nodes not used by any quadrilateral (geometry points
Gmsh often keeps) are dropped, and clockwise cells are reordered.
"""

from __future__ import annotations

import contextlib
import io
import warnings
from collections.abc import Iterable
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from twofluid.casefile.schema import WORKING_MAX
from twofluid.mesh.quad import QuadMesh

__all__ = ["MeshError", "read_quad_mesh"]

_DOMAIN = {"quad"}
_BOUNDARY = {"line": 1, "vertex": 0}


class MeshError(ValueError):
    """A mesh file cannot be used: unreadable, wrong cell types or missing groups."""


def _group_names(mesh, path: Path) -> dict[tuple[int, int], str]:
    """(dimension, physical tag) -> name from Gmsh field data."""
    names = {}
    for name, data in (mesh.field_data or {}).items():
        data = np.atleast_1d(data)
        if data.size >= 2:
            names[(int(data[1]), int(data[0]))] = name
    return names


def _collect_groups(mesh, path: Path) -> dict[str, list[NDArray[np.int64]]]:
    groups: dict[str, list[NDArray[np.int64]]] = {}
    tags = mesh.cell_data.get("gmsh:physical")
    names = _group_names(mesh, path)
    for k, block in enumerate(mesh.cells):
        if block.type not in _BOUNDARY:
            continue
        dim = _BOUNDARY[block.type]
        conn = np.asarray(block.data, dtype=np.int64)
        if tags is not None:
            t = np.asarray(tags[k], dtype=np.int64)
            for tag in np.unique(t):
                name = names.get((dim, int(tag)), str(int(tag)))
                groups.setdefault(name, []).append(conn[t == tag])
        if tags is not None:
            continue  # Gmsh v4 repeats physical groups as cell_sets
        for name, per_block in (mesh.cell_sets or {}).items():
            if name.startswith("gmsh:") or k >= len(per_block) or per_block[k] is None:
                continue
            idx = np.asarray(per_block[k], dtype=np.int64)
            if idx.size:
                groups.setdefault(name, []).append(conn[idx])
    return groups


def read_quad_mesh(
    path, *, axisymmetric: bool = False, require: Iterable[str] = ()
) -> QuadMesh:
    """Read a quadrilateral mesh with named boundary groups.

    Parameters
    ----------
    path : str, Path or meshio.Mesh
        Mesh file readable by meshio (Gmsh .msh v2 or v4, ...) [coordinates in m], or
        a mesh already in memory (e.g. with ``cell_sets`` naming line cells).
    axisymmetric : bool
        Interpret (x, y) as (r, z).
    require : iterable of str
        Boundary group names that must be present.

    Returns
    -------
    QuadMesh

    Raises
    ------
    MeshError
        If the file cannot be read, contains domain cells other than 4-node
        quadrilaterals, no quadrilaterals, or lacks a required group. The message
        names the file.
    """
    import meshio

    if isinstance(path, meshio.Mesh):
        mesh, path = path, Path("<meshio.Mesh>")
    else:
        path = Path(path)
        said = io.StringIO()  # meshio prints its own errors ("Error: Couldn't read file …"): kept for ours
        try:
            with contextlib.redirect_stdout(said), contextlib.redirect_stderr(said), warnings.catch_warnings():
                warnings.simplefilter("ignore")
                mesh = meshio.read(path)
        except (Exception, SystemExit) as exc:  # meshio raises many types, and calls sys.exit(1) on a
            # file it cannot identify: report them uniformly (a SystemExit would end the caller)
            text = " ".join(said.getvalue().split()) or str(exc) or type(exc).__name__
            raise MeshError(f"{path}: cannot read mesh (meshio: {text[:300]})") from None
    other = sorted({b.type for b in mesh.cells} - _DOMAIN - set(_BOUNDARY))
    if other:
        raise MeshError(f"{path}: unsupported cell types {other}; only 4-node 'quad' "
                        "domain cells (with 'line'/'vertex' boundary groups) are supported")
    quads = [np.asarray(b.data, dtype=np.int64) for b in mesh.cells if b.type == "quad"]
    if not quads:
        raise MeshError(f"{path}: no quadrilateral cells")
    cells = np.concatenate(quads)
    pts = np.asarray(mesh.points, dtype=float)
    if pts.ndim != 2 or pts.shape[1] < 2 or not pts.size:
        raise MeshError(f"{path}: no node coordinates")
    bad = ~np.isfinite(pts) | (np.abs(pts) > WORKING_MAX)
    if bad.any():
        i = int(np.flatnonzero(bad.any(axis=1))[0])
        raise MeshError(f"{path}: node {i} has the coordinate {float(pts[i][bad[i]][0])!r}; valid: finite, at most "
                        f"{WORKING_MAX:g} m in magnitude")
    if cells.min() < 0 or cells.max() >= pts.shape[0]:
        raise MeshError(f"{path}: a quadrilateral names a node that does not exist")
    same = np.unique(np.sort(cells, axis=1), axis=0, return_index=True, return_counts=True)
    if (same[2] > 1).any():
        row = same[0][np.flatnonzero(same[2] > 1)[0]]
        first = np.flatnonzero((np.sort(cells, axis=1) == row).all(axis=1))
        raise MeshError(f"{path}: quadrilaterals {int(first[0])} and {int(first[1])} have the same four nodes "
                        "(a duplicated element); each element must appear once")
    if pts.shape[1] > 2 and np.any(np.abs(pts[:, 2]) > 1e-12 * max(np.ptp(pts[:, :2]), 1.0)):
        raise MeshError(f"{path}: mesh is not in the z = 0 plane")

    used = np.unique(cells)
    new = np.full(pts.shape[0], -1, dtype=np.int64)
    new[used] = np.arange(used.size)
    cells = new[cells]
    xy = pts[used, :2]
    x = xy[cells]
    area2 = ((x[:, 2, 0] - x[:, 0, 0]) * (x[:, 3, 1] - x[:, 1, 1])
             - (x[:, 3, 0] - x[:, 1, 0]) * (x[:, 2, 1] - x[:, 0, 1]))
    cells[area2 < 0] = cells[area2 < 0][:, ::-1]

    boundaries = {}
    for name, parts in _collect_groups(mesh, path).items():
        conn = np.unique(new[np.concatenate(parts)], axis=0)
        if np.any(conn < 0):
            raise MeshError(f"{path}: boundary group {name!r} has nodes outside the quadrilaterals")
        boundaries[name] = conn if conn.shape[1] == 2 else conn.ravel()
    missing = [g for g in require if g not in boundaries]
    if missing:
        raise MeshError(f"{path}: missing boundary groups {missing}; "
                        f"file has {sorted(boundaries)}")
    try:
        return QuadMesh(xy, cells, boundaries, axisymmetric)
    except ValueError as exc:
        raise MeshError(f"{path}: {exc}") from exc
