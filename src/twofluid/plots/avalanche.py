"""Figures of an ``immersed_avalanche`` run (docs/avalanche.md): the surface velocity and base excess
pressure against time for every φ0 with the data of Pailha et al. (2008) on the same axes, and the
solid fraction and velocity profiles at the output times.
"""
from __future__ import annotations

from . import _matplotlib  # noqa: F401, I001  (first: matplotlib imported lean in the command's process)

from pathlib import Path

import numpy as np
from matplotlib import colormaps

from .agg import new_figure, write_png

__all__ = ["avalanche_figures"]

DPI = 110


def avalanche_figures(out: Path, hists: dict, profiles: dict, compare: bool) -> list[Path]:
    """Write avalanche_history.png and avalanche_profiles.png into ``out``; return the paths.

    ``hists``: {φ0: {"t" [s], "v" [m/s], "p" [Pa]}}; ``profiles``: {φ0: {t: {"z", "u", "phi", "p"}}}.
    """
    from ..verification import pailha2008 as data

    out = Path(out)
    cmap = colormaps["viridis"]
    keys = sorted(hists)
    colour = {k: cmap(i / max(len(keys) - 1, 1)) for i, k in enumerate(keys)}
    fig = new_figure((11.0, 4.6), dpi=DPI)
    av, ap = fig.add_subplot(1, 2, 1), fig.add_subplot(1, 2, 2)
    for k in keys:
        h = hists[k]
        mark = " (calibration)" if compare and k in data.CALIBRATED else ""
        keep = h["t"] > 0.0
        av.plot(h["t"][keep], np.maximum(h["v"][keep], data.FLOOR_M_S) * 1e3, color=colour[k],
                label=f"φ0 = {k:.3f}{mark}")
        ap.plot(h["t"], h["p"], color=colour[k])
        if compare:
            d = data.load(k)
            av.plot(np.clip(d["v_t"], 1e-2, None), np.maximum(d["v"], data.FLOOR_M_S) * 1e3, "o", ms=3,
                    color=colour[k], mfc="none")
            ap.plot(d["p_t"], d["p"], "o", ms=3, color=colour[k], mfc="none")
    av.set_yscale("log")
    av.axhline(0.2, color="0.6", lw=0.8, ls=":")
    av.set_xlabel("time [s]")
    av.set_ylabel("surface velocity [mm/s] (floored at 0.02)")
    ap.set_xlabel("time [s]")
    ap.set_ylabel("base excess pore pressure [Pa]")
    av.legend(fontsize=7, loc="lower right")
    if compare:
        av.set_title("lines: model; circles: Pailha et al. (2008)", fontsize=9)
    fig.subplots_adjust(left=0.07, right=0.98, bottom=0.12, top=0.92, wspace=0.25)
    paths = [write_png(fig, out / "avalanche_history.png")]

    fig = new_figure((11.0, 4.6), dpi=DPI)
    ap_, au = fig.add_subplot(1, 2, 1), fig.add_subplot(1, 2, 2)
    for k in keys:
        for j, (t, f) in enumerate(sorted(profiles[k].items())):
            if t == 0.0:
                continue
            ap_.plot(f["phi"], f["z"] * 1e3, color=colour[k], lw=0.8, label=f"φ0 = {k:.3f}" if j == 1 else None)
            au.plot(f["u"] * 1e3, f["z"] * 1e3, color=colour[k], lw=0.8)
    ap_.set_xlabel("solid fraction φ")
    ap_.set_ylabel("height above the base [mm]")
    au.set_xlabel("velocity [mm/s]")
    ap_.legend(fontsize=7)
    ap_.set_title("profiles at the output times", fontsize=9)
    fig.subplots_adjust(left=0.07, right=0.98, bottom=0.12, top=0.92, wspace=0.2)
    paths.append(write_png(fig, out / "avalanche_profiles.png"))
    return paths
