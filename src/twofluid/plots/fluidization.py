"""The fluidization curve's figure: bed pressure drop, porosity and height against superficial velocity."""
from __future__ import annotations

from . import _matplotlib  # noqa: F401, I001  (first: matplotlib imported lean in the command's process)

from pathlib import Path

import numpy as np
from matplotlib.ticker import FuncFormatter

from .agg import new_figure, write_png

__all__ = ["fluidization_plot"]

DPI = 120


def fluidization_plot(curve: dict, out_path: Path) -> Path:
    """Three panels on a log velocity axis (:func:`twofluid.fluidization_curve.fluidization_curve`):
    ΔP with Ergun's packed bed and the bed weight per area; porosity and height with Richardson–Zaki."""
    rows = curve["rows"]
    col = {k: np.array([r[k] for r in rows]) for k in rows[0] if k != "state"}
    u = col["U_m_s"] * 1e3  # mm/s
    fig = new_figure((7.0, 9.0), DPI)
    a1, a2, a3 = fig.subplots(3, 1, sharex=True)
    a1.plot(u, col["bed_pressure_drop_Pa"], "-", color="C0", lw=2, label="model (uniform equilibria)")
    a1.plot(u, col["ergun_pressure_drop_packed_Pa"], "--", color="C1", label="Ergun, packed bed at n_mf")
    a1.axhline(curve["figures"]["buoyant_weight_per_area_Pa"], ls=":", color="0.3",
               label=f"buoyant weight per area: {curve['figures']['buoyant_weight_per_area_Pa']:.4g} Pa")
    a1.set_ylim(0.0, 1.6 * curve["figures"]["buoyant_weight_per_area_Pa"])
    a1.set_ylabel("bed pressure drop ΔP [Pa]")
    a2.plot(u, col["porosity"], "-", color="C0", lw=2, label="model")
    a2.plot(u, col["porosity_richardson_zaki"], "--", color="C2", label="Richardson–Zaki (Khan–Richardson k)")
    a2.set_ylabel("porosity n [-]")
    a3.plot(u, col["bed_height_m"], "-", color="C0", lw=2, label="model")
    a3.plot(u, col["bed_height_richardson_zaki_m"], "--", color="C2", label="Richardson–Zaki")
    a3.set_ylabel("bed height H [m]")
    a3.set_xlabel("superficial liquid velocity U [mm/s] (decreasing: defluidization branch)")
    u_mf = curve["figures"]["U_mf_m_s"] * 1e3
    for a in (a1, a2, a3):
        a.set_xscale("log")
        a.xaxis.set_major_formatter(FuncFormatter(lambda x, _p: f"{x:g}"))
        a.axvline(u_mf, ls="-.", color="k", lw=0.8)
        a.grid(alpha=0.3, which="both")
        a.legend(fontsize=8, loc="best")  # where it covers the fewest data points
    a1.text(u_mf, a1.get_ylim()[1], f" U_mf = {u_mf:.3g} mm/s", va="top", fontsize=8)
    fig.suptitle(f"{curve['case']}: fluidization curve")
    fig.subplots_adjust(left=0.13, right=0.97, bottom=0.07, top=0.95, hspace=0.08)
    return write_png(fig, out_path)
