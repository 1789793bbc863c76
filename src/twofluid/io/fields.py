"""Field time series of 2D runs: one VTU file per output time plus a ParaView .pvd index.

Written with meshio (binary VTU, no HDF5 needed); the ``.pvd`` collection is
rewritten after every time, so an interrupted run leaves a valid series. Point
data: V and W [m/s] (3 components, the third u_θ or 0); cell data: porosity,
reference porosity, P and P_s [Pa], U_f and U_s [m/s] (element means). U_s is undefined in
clear liquid: written there as :data:`FILL_UNDEFINED` (0), with the cell field ``U_s_defined``
(1 where U_s is defined, 0 in clear liquid) to mask it: no file holds NaN. Read back with
``meshio.read``. Any other non-finite value ends the run (:func:`twofluid.io.results.check_finite`).
"""
from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from .folders import create, record, write_atomic

__all__ = ["FieldWriter", "FILL_UNDEFINED"]

#: the value written for U_s where it is undefined (clear liquid, n = 1); the cell field
#: ``U_s_defined`` (1: defined, 0: clear liquid) says where
FILL_UNDEFINED = 0.0


def _vec3(a: np.ndarray) -> np.ndarray:
    """(m, 2 or 3) -> (m, 3), zero third component if missing."""
    out = np.zeros((a.shape[0], 3))
    out[:, : a.shape[1]] = a
    return out


class FieldWriter:
    """Writes ``fields_NNNN.vtu`` and ``fields.pvd`` into ``out_dir``.

    Examples
    --------
    >>> import tempfile, meshio
    >>> from twofluid.mesh.quad import rectangle
    >>> d = Path(tempfile.mkdtemp())
    >>> w = FieldWriter(d, rectangle(0, 1, 0, 1, 2, 2))
    >>> _ = w.write(0.5, {"V": np.zeros((9, 2))}, {"porosity": np.full(4, 0.6)})
    >>> float(meshio.read(d / "fields_0000.vtu").cell_data["porosity"][0][0])
    0.6
    """

    def __init__(self, out_dir: Path, mesh, basename: str = "fields"):
        self.out = Path(out_dir)
        self.out.mkdir(parents=True, exist_ok=True)
        self.mesh, self.base = mesh, basename
        self.entries: list[tuple[float, str]] = []

    def write(self, t: float, point_data: dict, cell_data: dict) -> Path | None:
        """One time [s]: nodal arrays (n_nodes, k) and element arrays (n_el,) or (n_el, k).

        None (nothing written) for a non-finite time after this run's first refusal."""
        import meshio

        from .results import check_finite

        if not (check_finite(f"fields at nodes ({self.base}.pvd)", t, point_data, element_name="node")
                and check_finite(f"fields ({self.base}.pvd)", t, cell_data, undefined=("U_s",))):
            return None

        pts = np.column_stack([self.mesh.points, np.zeros(self.mesh.n_nodes)])
        pdata = {k: (_vec3(v) if v.ndim == 2 else v) for k, v in point_data.items()}
        cell_data = dict(cell_data)
        for k in [k for k in cell_data if k.startswith("U_s")]:  # undefined in clear liquid: a fill and a mask
            v = np.asarray(cell_data[k], dtype=float)
            undefined = np.isnan(v).any(axis=1) if v.ndim == 2 else np.isnan(v)
            cell_data[k] = np.where(np.isnan(v), FILL_UNDEFINED, v)
            cell_data[f"{k}_defined"] = (~undefined).astype(np.uint8)
        cdata = {k: [(_vec3(v) if v.ndim == 2 else v)] for k, v in cell_data.items()}
        name = f"{self.base}_{len(self.entries):04d}.vtu"
        _write_vtu(self.out / name, meshio.Mesh(pts, [("quad", self.mesh.cells)], point_data=pdata,
                                                cell_data=cdata))
        self.entries.append((t, name))
        self._index()
        return self.out / name

    def _index(self) -> None:
        rows = "\n".join(f'    <DataSet timestep="{t:.10g}" part="0" file="{f}"/>' for t, f in self.entries)
        write_atomic(self.out / f"{self.base}.pvd",
                     '<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n  <Collection>\n'
                     f"{rows}\n  </Collection>\n</VTKFile>\n")


def _write_vtu(path: Path, mesh) -> None:
    """meshio's VTU writer into a new temporary file (made here: never a link), renamed over ``path``."""
    import meshio

    tmp = path.with_name(path.name + ".tmp")
    try:
        os.close(create(tmp))
        meshio.write(tmp, mesh, file_format="vtu")
        os.replace(tmp, path)
    except OSError as exc:
        tmp.unlink(missing_ok=True)
        raise OSError(exc.errno, exc.strerror or str(exc), str(path)) from None
    record(path)
