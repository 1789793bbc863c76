"""Figures of a sloping liquefaction run (docs/lateral-spreading.md): the lateral-displacement
profile at the output times, and the surface displacement against time with the engineering
estimates (Zhang et al. 2004, Newmark, Youd et al. 2002 where given) beside it.

Drawn as the other liquefaction figures are (:mod:`twofluid.plots.agg`, fixed margins, no
``tight_layout``, linear or log axes with plain labels); nothing here imports more than they do.
"""
from __future__ import annotations

from . import _matplotlib  # noqa: F401, I001  (first: matplotlib imported lean in the command's process)

from pathlib import Path

import numpy as np
from matplotlib import colormaps
from matplotlib.ticker import FuncFormatter, NullFormatter

from .agg import new_figure, write_png

__all__ = ["slope_plots", "estimate_rows"]

DPI = 110


def _margins(fig, left=0.85, right=0.25, bottom=0.62, top=0.42, **space) -> None:
    w, h = fig.get_size_inches()
    fig.subplots_adjust(left=left / w, right=1.0 - right / w, bottom=bottom / h, top=1.0 - top / h, **space)


def estimate_rows(slope: dict) -> list[tuple[str, float | None, tuple | None, str]]:
    """(label, displacement [m] or None, (lower, upper) band or None, note) of the run and each estimate
    of a summary's ``slope`` block, in the order drawn.

    >>> s = {"surface_displacement_end_m": 0.5, "estimates": {"zhang_2004_ib_gamma_max": {"displacement_m": 9.8},
    ...      "newmark": {"displacement_m": None, "flow_failure": True}, "youd_2002": {"median_m": None,
    ...      "note": "not evaluated: the record is scaled"}}}
    >>> [(r[0], r[1], r[3]) for r in estimate_rows(s)]
    [('this run', 0.5, ''), ('Newmark', None, 'flow failure'), ('Zhang 2004 with I&B γ_max', 9.8, ''), ('Youd et al. 2002', None, 'not evaluated')]
    """
    est = slope["estimates"]
    nm, zh, yd = est["newmark"], est["zhang_2004_ib_gamma_max"], est["youd_2002"]
    rows = [("this run", slope["surface_displacement_end_m"], None, "")]
    note = "flow failure" if nm.get("flow_failure") else ("" if nm.get("displacement_m") is not None else "not evaluated")
    rows.append(("Newmark", nm.get("displacement_m"), None, note))
    rows.append(("Zhang 2004 with I&B γ_max", zh.get("displacement_m"), None, ""))
    if yd.get("median_m") is not None:
        rows.append(("Youd et al. 2002", yd["median_m"], (yd["lower_m"], yd["upper_m"]), ""))
    else:
        rows.append(("Youd et al. 2002", None, None, "not evaluated"))
    return rows


def slope_plots(srec, col, out: Path, title: str, slope: dict) -> list[Path]:
    """Write lateral_displacement.png and surface_displacement.png into ``out``; return the paths.

    ``srec``: the run's :class:`twofluid.runners.liquefaction_slope.SlopeRecorder`; ``slope``: the
    ``slope`` block of its summary."""
    out = Path(out)
    return [_profiles(srec, col, out, title, slope), _history(srec, col, out, title, slope)]


def _profiles(srec, col, out: Path, title: str, slope: dict) -> Path:
    fig = new_figure((6.5, 6.5), DPI)
    ax = fig.subplots()
    times = sorted(srec.profiles)
    colors = colormaps["viridis"](np.linspace(0.0, 0.9, max(len(times), 1)))
    z = srec.depths
    for c, t in zip(colors, times):
        ax.plot(100.0 * srec.profiles[t], z, color=c, lw=1.3, label=f"{t:.4g} s")
    loc = slope["localisation"]
    lo, hi = loc["depth_range_half_peak_m"]
    ax.axhspan(lo, hi, color="tab:red", alpha=0.12, lw=0, label="strain localised")
    zw = col.ground_surface - col.v.mesh.y[-1]
    if zw > 0.0:
        ax.axhline(zw, color="c", lw=0.8, ls="--", label="water table")
    ax.set_ylim(col.ground_surface, 0.0)
    ax.set_xlabel("downslope displacement relative to the base [cm]")
    ax.set_ylabel("depth below the ground surface [m]")
    ax.legend(fontsize=7, title="time", title_fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0),
              borderaxespad=0.0)  # right of the axes: it hides no data
    ax.set_title(f"{title}: lateral displacement ({slope['slope_percent']:g} % slope)", y=1.0)
    ax.grid(alpha=0.3)
    _margins(fig, right=1.25)
    return write_png(fig, out / "lateral_displacement.png")


def _history(srec, col, out: Path, title: str, slope: dict) -> Path:
    fig = new_figure((11, 4.8), DPI)
    ax, bx = fig.subplots(1, 2, gridspec_kw={"width_ratios": [2.6, 1.0]})
    t, d = np.asarray(srec.t), np.asarray(srec.d)
    end = col.shear_end
    t_max = max(min(float(t[-1]), 1.5 * end), col.shaking_end) if end > 0.0 else float(t[-1])
    keep = t <= t_max + 1e-9
    ax.plot(t[keep], 100.0 * d[keep], "k", lw=1.2, label="surface, relative to the base")
    if col.shaking_end > 0.0:
        ax.axvspan(0.0, col.shaking_end, color="0.92", zorder=0, label="shaking")
    flow = slope.get("flow_after_shaking")
    if end > col.shaking_end > 0.0:
        stopped = flow is None or flow["flow_stopped"]
        ax.axvline(end, color="tab:blue", ls="--", lw=0.9,
                   label=("shear wave stopped: flow stopped" if flow is not None and stopped else
                          "shear wave stopped: still flowing" if flow is not None else "shear wave stopped"))
    share = slope.get("share_after_shaking")
    text = f"end of the run ({t[-1]:.4g} s): {100.0 * d[-1]:.3g} cm"
    if share is not None:
        text += f"\n{100.0 * share:.1f} % of it after the shaking"
    if flow is not None and flow.get("time_99_percent_s") is not None:
        text += f"\n99 % reached at {flow['time_99_percent_s']:.3g} s"
    ax.annotate(text, xy=(0.98, 0.04), xycoords="axes fraction", ha="right", va="bottom", fontsize=8)
    ax.set_xlim(0.0, t_max)
    ax.set_xlabel("time [s]" + (f" (constant after {end:.4g} s)" if t[-1] > t_max else ""))
    ax.set_ylabel("downslope surface displacement [cm]")
    ax.set_title(f"{title}: surface displacement", y=1.0)
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=4,
              borderaxespad=0.0)  # below the time axis' label: it hides no data
    ax.grid(alpha=0.3)

    rows = estimate_rows(slope)
    y = np.arange(len(rows))[::-1]
    vals = [r[1] for r in rows if r[1] is not None and r[1] > 0.0]
    lo_v = min(vals + [b[0] for _, _, b, _ in rows if b]) if vals else 0.01
    hi_v = max(vals + [b[1] for _, _, b, _ in rows if b]) if vals else 1.0
    bx.set_xscale("log")
    bx.set_xlim(lo_v / 3.0, hi_v * 3.0)
    bx.xaxis.set_major_formatter(FuncFormatter(lambda x, pos: f"{x:.3g}"))  # plain numbers: no mathtext
    bx.xaxis.set_minor_formatter(NullFormatter())
    for yi, (label, v, band, note) in zip(y, rows):
        color = "k" if label == "this run" else "tab:red"
        if band is not None:
            bx.plot(band, [yi, yi], color=color, lw=2.0, alpha=0.5)
        if v is not None and v > 0.0:
            bx.plot([v], [yi], "o", color=color)
            bx.annotate(f"{v:.3g} m" + (f" ({band[0]:.2g}–{band[1]:.2g})" if band is not None else ""), xy=(v, yi), xytext=(0, 6), textcoords="offset points", ha="center",
                        fontsize=7)
        else:
            bx.annotate(note or "—", xy=(0.5, yi), xycoords=("axes fraction", "data"), ha="center",
                        va="center", fontsize=7, color="0.4")
    bx.set_yticks(y)
    bx.set_yticklabels([r[0] for r in rows], fontsize=8)
    bx.set_ylim(-0.6, len(rows) - 0.4)
    bx.set_xlabel("displacement [m]")
    bx.set_title("beside it", y=1.0)
    bx.grid(alpha=0.3, axis="x")
    _margins(fig, right=0.2, bottom=0.95, wspace=0.55)
    return write_png(fig, out / "surface_displacement.png")
