"""The fluidization curve of a 1D bed: steady bed pressure drop, porosity and height against the
superficial velocity (``twofluid fluidization-curve CASE``).

Computed from the model's uniform equilibria, not from runs: at each superficial velocity U
the bed is the uniform bed the case's drag law holds (the same equilibrium a run settles to,
and that ``[initial] state = "fluidized"`` starts from):

- below the minimum fluidization velocity U_mf, packed at n_mf (``[initial] settled_porosity``),
  its pressure drop the drag law's at n_mf: ΔP = H β(n_mf, U/n_mf) U/n_mf² (Ergun for the
  default law);
- above it, fluidized at the porosity n(U) where the drag carries the buoyant weight,
  β(n, U/n) U/n² = (1 − n)(ρ_s − ρ_f) g, with ΔP = H β U/n² computed from the law again.

The height H holds the case's solids volume (its initial bed) at that porosity over the
column's cross-section. This is the defluidization branch (velocity decreasing): the model
has no interlocking of a packed bed, so the overshoot of ΔP above the bed weight that a rising
velocity shows in experiments is not there. The curve runs from U_mf/5 up to the velocity at
which the porosity reaches 0.9 or the bed reaches the column's top, whichever is lower.
Beside it: Richardson & Zaki's porosity and height (U = U_t n^k, k of Khan & Richardson 1989,
U_t of the case's law; packed at n_mf below U_t n_mf^k; with ``--rz-exponent richardson_zaki_1954``
U = U_i n^k, k and U_i of Richardson & Zaki 1954 with their wall term d/D), Ergun's pressure drop of the packed bed at n_mf, and the buoyant
weight of the solids per area, (ρ_s − ρ_f) g cos θ V_s/A.
"""
from __future__ import annotations

import csv
import io
from pathlib import Path

import numpy as np

__all__ = ["COLUMNS", "fluidization_curve", "write_curve"]

#: CSV columns (units in the names)
COLUMNS = ("U_m_s", "state", "porosity", "bed_height_m", "bed_pressure_drop_Pa", "porosity_richardson_zaki",
           "bed_height_richardson_zaki_m", "ergun_pressure_drop_packed_Pa", "buoyant_weight_per_area_Pa")


def _ergun_drop(u, n, h, mat) -> float:
    """Ergun's (1952) pressure drop [Pa] of a packed bed of height ``h`` [m] at porosity ``n`` in ``u`` [m/s]."""
    d = mat.d
    return h * (150.0 * mat.mu_f * u * (1.0 - n) ** 2 / (n ** 3 * d * d) + 1.75 * mat.rho_f * u * u * (1.0 - n)
                / (n ** 3 * d))


def fluidization_curve(case: dict, points: int = 60, n_max: float = 0.9, exponent: str = "khan_richardson") -> dict:
    """The curve of ``case`` (a resolved 1D case, bottom inlet): {"rows": [...], "figures": {...}}.

    ``rows`` follow :data:`COLUMNS`, the velocity decreasing (the defluidization branch, module
    docstring); ``points`` velocities, log-spaced from the top velocity down to U_mf/5, with
    U_mf itself among them. ``figures``: U_mf, U_t, n_mf, the solids volume and the weight per area.
    ``exponent``: the Richardson–Zaki comparison's k, ``"khan_richardson"`` (1989, no wall term, U = U_t n^k)
    or ``"richardson_zaki_1954"`` (their correlation with the wall term d/D and U = U_i n^k,
    :func:`twofluid.casefile.bed.richardson_zaki_1954_exponent`; D of a round column of the cross-section).
    """
    from .casefile.bed import _bed_state, column_diameter, height_of_volume, packed_porosity, richardson_zaki_1954_exponent
    from .casefile.builder import build
    from .casefile.schema import CaseError
    from .closures import drag as drag_laws

    src = case.get("_source", "<case>")
    if case["case"]["model"] not in ("two_fluid_1d", "reduced_1d"):
        raise CaseError(src, "[case] model", "a fluidization curve needs a 1D column (two_fluid_1d or reduced_1d)")
    b = build(case)
    model, mat, clo, mesh = b.model, b.model.mat, b.model.clo, b.model.mesh
    if model.bottom.kind != "inlet" or not mat.rho_s > mat.rho_f:
        raise CaseError(src, "[boundary.bottom] kind", "a fluidization curve needs an inlet at the bottom and "
                        "particles denser than the liquid")
    solids = float(model.solids_volume(b.state))
    area = float(mesh.area[0])
    weight = float((mat.rho_s - mat.rho_f) * -model.g_y * solids / area)
    n_mf = packed_porosity(case)
    u_mf = clo.fluidization_velocity(n_mf, mat)
    u_t = drag_laws.terminal_velocity(clo.drag, mat.d, mat.rho_s, mat.rho_f, mat.mu_f, mat.g, **clo.drag_params)
    k = float(drag_laws.khan_richardson_exponent(drag_laws.archimedes_number(mat.d, mat.rho_s, mat.rho_f,
                                                                               mat.mu_f, mat.g)))
    u_ref, source = u_t, "Khan & Richardson (1989), no wall term"
    if exponent == "richardson_zaki_1954":  # their k and intercept with the wall term (equations 33-41)
        wall = float(mat.d) / column_diameter(area)
        k = float(richardson_zaki_1954_exponent(mat.rho_f * u_t * mat.d / mat.mu_f, wall))
        u_ref, source = u_t * 10.0 ** -wall, f"Richardson & Zaki (1954) with the wall term d/D = {wall:.4g}"
    elif exponent != "khan_richardson":
        raise CaseError(src, "fluidization-curve --rz-exponent", f"{exponent!r}: valid are khan_richardson, "
                        "richardson_zaki_1954")
    total = float(mesh.volumes.sum())
    n_top = min(n_max, 1.0 - solids / total)  # the bed fills the column at 1 − V_s/V_column
    if not n_top > n_mf:
        raise CaseError(src, "[initial]", f"the bed fills the column already when packed (n_mf = {n_mf:g}); "
                        "no fluidized branch fits in it")
    u_top = clo.fluidization_velocity(n_top, mat)
    us = np.unique(np.concatenate([np.geomspace(u_top, 0.2 * u_mf, points), [u_mf]]))[::-1]
    rows = []
    for u in us:
        n = _bed_state(clo, mat, float(u), n_mf)
        h = height_of_volume(mesh, solids / (1.0 - n))
        s = u / n
        beta = float(clo.saturated_drag(np.array([n]), np.array([s]), mat.d, mat.rho_f, mat.mu_f,
                                        **clo.drag_params)[0])
        n_rz = min(max((u / u_ref) ** (1.0 / k), n_mf), 1.0)  # packed until U_t n_mf^k
        h_rz = height_of_volume(mesh, solids / (1.0 - n_rz)) if n_rz < 1.0 else float("nan")
        h_mf = height_of_volume(mesh, solids / (1.0 - n_mf))
        rows.append({"U_m_s": float(u), "state": "packed" if u <= u_mf else "fluidized", "porosity": n,
                     "bed_height_m": h, "bed_pressure_drop_Pa": h * beta * s / n,
                     "porosity_richardson_zaki": n_rz, "bed_height_richardson_zaki_m": h_rz,
                     "ergun_pressure_drop_packed_Pa": _ergun_drop(float(u), n_mf, h_mf, mat),
                     "buoyant_weight_per_area_Pa": weight})
    figures = {"U_mf_m_s": u_mf, "U_t_m_s": u_t, "packed_porosity_n_mf": n_mf, "solids_volume_m3": solids,
               "buoyant_weight_per_area_Pa": weight, "richardson_zaki_exponent": k,
               "richardson_zaki_exponent_source": source, "richardson_zaki_velocity_m_s": u_ref,
               "method": "uniform equilibria of the case's drag law (no runs); defluidization branch"}
    return {"rows": rows, "figures": figures, "case": case["case"]["name"]}


def write_curve(curve: dict, out_dir: Path, plot: bool = True) -> list[Path]:
    """Write ``fluidization_curve.csv`` (and ``fluidization_curve.png``) into ``out_dir``."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    path = out_dir / "fluidization_curve.csv"
    f = io.StringIO()  # written whole, never through a symbolic link (io.folders)
    w = csv.writer(f)
    w.writerow(COLUMNS)
    for r in curve["rows"]:
        w.writerow([r[c] if isinstance(r[c], str) else f"{r[c]:.10g}" for c in COLUMNS])
    from .io.folders import write_atomic

    write_atomic(path, f.getvalue())
    paths = [path]
    if plot:
        from .plots.fluidization import fluidization_plot

        paths.append(fluidization_plot(curve, out_dir / "fluidization_curve.png"))
    return paths
