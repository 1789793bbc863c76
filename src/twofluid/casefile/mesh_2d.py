"""The mesh of a ``two_fluid_2d`` case, built and checked when the case is loaded.

The mesh decides what the boundary sections of a case may say: which groups exist,
where the axis lies, whether a ``cut`` removes anything, which rows of elements the
``[profiles] heights`` meet. Building it (a rectangle or one file read) is cheap, so
:func:`check_mesh` does it at load time and each problem is a one-line
:class:`~twofluid.casefile.schema.CaseError` naming the key, instead of a ``KeyError``
or an empty array deep inside a run.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from ..mesh.quad import QuadMesh, rectangle, remove_block
from .schema import CaseError

__all__ = ["build_mesh", "check_mesh", "element_row", "uncovered_edges"]

BOUNDARY_NAMES = ("left", "right", "bottom", "top", "inner", "outer", "axis", "cut")


def _mesh_path(case: dict, src: str) -> Path:
    path = Path(case["mesh"]["file"])
    if not path.is_absolute() and Path(str(src)).is_file():
        path = Path(src).parent / path
    return path


def build_mesh(case: dict, source: str | None = None) -> QuadMesh:
    """The case's mesh with its named boundary groups (plus "axis" when r starts at 0)."""
    m, src = case["mesh"], source or case.get("_source", "<case>")
    if m["kind"] == "gmsh":
        from ..mesh.gmsh_io import MeshError, read_quad_mesh

        path = _mesh_path(case, src)
        if not path.is_file():
            raise CaseError(src, "[mesh] file", f"{path} does not exist")
        try:
            return read_quad_mesh(path, axisymmetric=m["axisymmetric"])
        except MeshError as exc:
            raise CaseError(src, "[mesh] file", str(exc)) from None
    with np.errstate(all="ignore"):
        mesh = rectangle(m["x0"], m["x1"], m["y0"], m["y1"], m["nx"], m["ny"], axisymmetric=m["axisymmetric"],
                         grading=(m["grading_x"], m["grading_y"]))
    if m["axisymmetric"] and m["x0"] == 0.0:
        mesh.boundaries["axis"] = mesh.boundaries["left"]
    if m["cut"]:
        mesh = remove_block(mesh, *m["cut"], name="cut")
    return mesh


def element_row(mesh: QuadMesh, height: float) -> np.ndarray:
    """Elements of the row containing ``height`` [m] (the row below it at the top of the mesh)."""
    y = mesh.points[mesh.cells][:, :, 1]
    lo, hi = y.min(axis=1), y.max(axis=1)
    row = np.nonzero((lo <= height) & (hi > height))[0]
    if row.size == 0:
        row = np.nonzero((lo < height) & (hi >= height))[0]
    return row


def uncovered_edges(mesh: QuadMesh, groups: list[str]) -> int:
    """Number of boundary edges of ``mesh`` in none of ``groups``."""
    local = np.array([[0, 1], [1, 2], [2, 3], [3, 0]])
    e = np.sort(mesh.cells[:, local].reshape(-1, 2), axis=1)
    key, cnt = np.unique(e[:, 0] * mesh.n_nodes + e[:, 1], return_counts=True)
    bnd = key[cnt == 1]
    cov = [np.sort(mesh.boundary_edges(g), axis=1) @ np.array([mesh.n_nodes, 1]) for g in groups
           if g in mesh.boundaries and mesh.boundaries[g].ndim == 2]
    return int((~np.isin(bnd, np.concatenate(cov) if cov else [])).sum())


def _check_geometry(case: dict, mesh: QuadMesh, source: str) -> None:
    m = case["mesh"]
    key = "[mesh] grading_x/grading_y" if m["kind"] == "rectangle" else "[mesh] file"
    x = mesh.points[mesh.cells]
    with np.errstate(all="ignore"):  # twice the area of each quadrilateral (diagonals' cross product)
        area2 = ((x[:, 2, 0] - x[:, 0, 0]) * (x[:, 3, 1] - x[:, 1, 1])
                 - (x[:, 3, 0] - x[:, 1, 0]) * (x[:, 2, 1] - x[:, 0, 1]))
        size = np.ptp(mesh.points, axis=0).max()
    if not (np.all(np.isfinite(mesh.points)) and np.all(np.isfinite(area2))):
        raise CaseError(source, key, "gives node coordinates that are not finite")
    worst = float(area2.min()) / (2.0 * size ** 2) if size > 0 else 0.0
    if not worst > 1e-12:  # an inverted or collapsed element: a singular or meaningless system
        e = int(np.argmin(area2))
        raise CaseError(source, key, f"gives an inverted or collapsed element ({e}, area "
                        f"{area2[e] / 2:.3g} m² in a domain of {size:.3g} m): lower the grading or refine")


def _check_cut(case: dict, source: str) -> None:
    m = case["mesh"]
    if m["kind"] != "rectangle" or not m["cut"]:
        return
    whole = rectangle(m["x0"], m["x1"], m["y0"], m["y1"], m["nx"], m["ny"],
                      grading=(m["grading_x"], m["grading_y"]))
    xc = whole.points[whole.cells].mean(axis=1)
    x0, x1, y0, y1 = m["cut"]
    gone = (xc[:, 0] >= x0) & (xc[:, 0] <= x1) & (xc[:, 1] >= y0) & (xc[:, 1] <= y1)
    if not gone.any():
        raise CaseError(source, "[mesh] cut", f"{m['cut']} removes no element (no element centre lies inside; "
                        f"domain [{m['x0']:g}, {m['x1']:g}] × [{m['y0']:g}, {m['y1']:g}] m)")
    if gone.all():
        raise CaseError(source, "[mesh] cut", f"{m['cut']} removes every element of the domain")


def check_mesh(case: dict, source: str) -> QuadMesh:
    """Build the mesh and check the boundary sections and heights against it (see module doc)."""
    _check_cut(case, source)
    mesh = build_mesh(case, source)
    _check_geometry(case, mesh, source)
    groups = sorted(mesh.boundaries)
    used: dict[str, str] = {}
    for name in BOUNDARY_NAMES:
        b = case["boundary"][name]
        if b["kind"] == "none":
            continue
        where = f"[boundary.{name}]"
        group = b["group"] or name
        if group not in mesh.boundaries or mesh.boundaries[group].ndim != 2:
            key = f"{where} group" if b["group"] else f"{where} kind"
            raise CaseError(source, key, f"the mesh has no boundary group {group!r} (of edges); groups: "
                            f"{', '.join(groups)}")
        if group in used:
            raise CaseError(source, f"{where} group", f"mesh group {group!r} already has a condition "
                            f"({used[group]}): one condition per group")
        used[group] = where
        if b["kind"] == "axis":
            r = mesh.points[np.unique(mesh.boundaries[group]), 0]
            if np.abs(r).max() > 1e-9 * max(np.ptp(mesh.points[:, 0]), 1e-300):
                raise CaseError(source, f"{where} kind", f"axis needs its group at r = 0; group {group!r} "
                                f"lies at r = {r.min():.4g} .. {r.max():.4g} m")
    missing = uncovered_edges(mesh, list(used))
    if missing:
        raise CaseError(source, "[boundary.*]", f"{missing} boundary edges have no condition; mesh groups: "
                        f"{', '.join(groups)}")
    ys = mesh.points[:, 1]
    for h in case["profiles"]["heights"]:
        if element_row(mesh, h).size == 0:
            raise CaseError(source, "[profiles] heights", f"{h:g} lies outside the mesh "
                            f"[{ys.min():g}, {ys.max():g}] m")
    sf = case["single_fluid"]
    if sf["enabled"]:
        if not ys.min() <= sf["height"] <= ys.max():
            raise CaseError(source, "[single_fluid] height", f"{sf['height']:g} lies outside the mesh "
                            f"[{ys.min():g}, {ys.max():g}] m")
        if not sf["r_inner"] < mesh.points[:, 0].max():
            raise CaseError(source, "[single_fluid] r_inner", f"{sf['r_inner']:g} must lie inside the mesh "
                            f"(r < {mesh.points[:, 0].max():g} m)")
    return mesh
