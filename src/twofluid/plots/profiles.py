"""Figures of 1D runs: porosity and pressure profiles, bed height or interfaces in time.

Margins are fixed (``subplots_adjust``) rather than computed by ``tight_layout``, which lays
out each figure's text once more; the colour bars sit in fixed rectangles beside them; the
curves of a profile figure are one line collection; the ticks are drawn as collections and texts
(:func:`twofluid.plots.agg.drawn_ticks`). Figures are drawn and written by
:mod:`twofluid.plots.agg` (no pyplot). CPU: docs/benchmarks.md, "Start-up and plots".
"""
from __future__ import annotations

from . import _matplotlib  # noqa: F401, I001  (first: matplotlib imported lean in the command's process)

from pathlib import Path

import numpy as np
from matplotlib import colormaps
from matplotlib.cm import ScalarMappable
from matplotlib.colors import Normalize
from matplotlib.ticker import FuncFormatter

from .agg import drawn_ticks, new_figure, write_png

__all__ = ["profile_plots", "history_plot"]

#: resolution of the PNGs [dots per inch]
DPI = 120


def _grouped(x, _pos=None) -> str:
    """A tick label with thin-space thousands groups (12 000), shortest form otherwise.

    >>> _grouped(12000.0), _grouped(0.25), _grouped(-1500.0)
    ('12\u2009000', '0.25', '\u22121\u2009500')
    """
    if x == int(x) and abs(x) >= 1000:
        text = f"{abs(int(x)):,}".replace(",", "\u2009")
    else:
        text = f"{abs(x):g}"
    return ("\u2212" if x < 0 else "") + text


def _by_time(profiles: dict[float, dict]):
    return sorted(profiles.items())


def _edges(y: np.ndarray) -> np.ndarray:
    """Element edges from element centres (midpoints inside, mirrored at the ends)."""
    mid = 0.5 * (y[1:] + y[:-1])
    if y.size == 1:
        return np.array([y[0] - 0.5, y[0] + 0.5])
    return np.concatenate([[2 * y[0] - mid[0]], mid, [2 * y[-1] - mid[-1]]])


def _steps(values: np.ndarray, edges: np.ndarray) -> np.ndarray:
    """The staircase of element values between their edges as a polyline (x, y): what
    ``Axes.stairs(values, edges, orientation="horizontal", baseline=None)`` draws.

    >>> _steps(np.array([0.4, 0.5]), np.array([0.0, 1.0, 2.0])).tolist()
    [[0.4, 0.0], [0.4, 1.0], [0.5, 1.0], [0.5, 2.0]]
    """
    return np.column_stack([np.repeat(values, 2), np.repeat(edges, 2)[1:-1]])


def _curves(ax, curves: list[np.ndarray], colors, linewidth: float) -> None:
    """Draw the polylines ``curves`` ((k, 2) arrays of x, y) in ``colors`` as one line collection and
    scale the axes to them: one artist instead of one per output time (a step patch's limits are
    found segment by segment in Python)."""
    from matplotlib.collections import LineCollection

    ax.add_collection(LineCollection(curves, colors=colors, linewidths=linewidth))
    ax.autoscale_view()


def _time_bar(fig, box: tuple[float, float, float, float], cmap, norm):
    """A colour bar for the output time of the curves [s] in the rectangle ``box`` (left, bottom,
    width, height as fractions of the figure): placed where ``fig.colorbar(..., ax=...)`` puts it
    beside the fixed margins, without the new grid of subplots that call lays out for it."""
    sm = ScalarMappable(cmap=cmap, norm=norm)
    bar = fig.colorbar(sm, cax=fig.add_axes(box), label="time t [s]")
    drawn_ticks(bar.ax, x=False, grid=False, yside="right")


def profile_plots(profiles: dict[float, dict], out_dir: Path, title: str) -> list[Path]:
    """porosity.png (n against height at each output time) and pressure.png (P, P_s)."""
    out = []
    fig = new_figure((6.2, 6), DPI)
    ax = fig.subplots()
    cmap = colormaps["viridis"]
    items = _by_time(profiles)
    times = [t for t, _ in items]
    norm = Normalize(min(times), max(max(times), min(times) + 1e-12))
    colors = [cmap(norm(t)) for t in times]  # one curve per output time, its colour on the time bar
    _curves(ax, [_steps(np.asarray(f["porosity"]), _edges(np.asarray(f["y_m"]))) for _, f in items], colors, 1.0)
    ax.set_xlabel("porosity n [-]")
    ax.set_ylabel("height y [m]")
    ax.set_title(title, y=1.0)  # at the top of the axes: not placed anew at each drawing
    fig.subplots_adjust(left=0.15, right=0.798, bottom=0.09, top=0.94)  # fixed margins: tight_layout is slow
    drawn_ticks(ax)
    _time_bar(fig, (0.8385, 0.09, 0.0411, 0.85), cmap, norm)
    out.append(write_png(fig, Path(out_dir) / "porosity.png"))

    fig = new_figure((10, 5.5), DPI)
    a1, a2 = fig.subplots(1, 2, sharey=True)
    for a, key in ((a1, "P_Pa"), (a2, "Ps_Pa")):
        _curves(a, [np.column_stack([f[key], f["y_m"]]) for _, f in items], colors, 1.5)
    a1.set_xlabel("liquid pressure P [Pa]")
    a2.set_xlabel("granular pressure P_s [Pa]")
    a1.set_ylabel("height y [m]")
    fig.subplots_adjust(left=0.09, right=0.802, bottom=0.1, top=0.92, wspace=0.06)
    for a in (a1, a2):  # grouped digits: "10000120001400" no longer runs together; the height labelled once
        drawn_ticks(a, xformatter=FuncFormatter(_grouped), ylabels=a is a1)
    _time_bar(fig, (0.8465, 0.1, 0.02255, 0.82), cmap, norm)
    fig.suptitle(title)
    out.append(write_png(fig, Path(out_dir) / "pressure.png"))
    return out


def history_plot(t: np.ndarray, series: dict[str, np.ndarray], out_path: Path, title: str,
                 ylabel: str = "height [m]", marks: dict | None = None,
                 levels: dict[str, float] | None = None, scale_after: float | None = None) -> Path:
    """Curves against time (e.g. bed height, interface heights) with optional marks.

    ``marks``: vertical lines, name -> time [s] or (time [s], label); ``levels``:
    horizontal dashed lines, label -> value (e.g. a theoretical final height).
    ``scale_after`` [s]: the vertical scale is set by the samples after this time and the
    levels, and spans at least 4 % of their magnitude (a start-up value off that scale is
    named in the legend instead of setting it).
    """
    fig = new_figure((6.5, 4.5), DPI)
    ax = fig.subplots()
    for name, y in series.items():
        ax.plot(t, y, label=name)
    for label, value in (levels or {}).items():
        if np.isfinite(value):
            ax.axhline(value, ls=":", color="0.3", lw=1.0, label=f"{label}: {value:.4g}")
    for name, tm in (marks or {}).items():
        tm, text = tm if isinstance(tm, tuple) else (tm, f"{name} = {tm:.3g} s")
        if np.isfinite(tm):
            ax.axvline(tm, ls="--", color="k", lw=0.8)
            ax.text(tm, ax.get_ylim()[1], f" {text}", va="top", fontsize=8)
    if scale_after is not None:
        _scale_after(ax, t, series, levels or {}, scale_after)
    ax.set_xlabel("time t [s]")
    ax.set_ylabel(ylabel)
    ax.set_title(title, y=1.0)  # at the top of the axes: not placed anew at each drawing
    ax.legend(fontsize=8)
    fig.subplots_adjust(left=0.12, right=0.97, bottom=0.12, top=0.92)
    drawn_ticks(ax)
    return write_png(fig, out_path)


def _scale_after(ax, t, series, levels, t0) -> None:
    """Vertical limits from the samples after ``t0`` and the levels; samples before it that fall
    outside are listed in the legend (an invisible line carries the label)."""
    t = np.asarray(t)
    later = t > t0
    vals = [np.asarray(y)[later] for y in series.values()] + [np.array([v]) for v in levels.values()]
    vals = np.concatenate([v[np.isfinite(v)] for v in vals]) if vals else np.array([])
    if vals.size == 0:
        return
    lo, hi = float(vals.min()), float(vals.max())
    span = max(hi - lo, 0.04 * max(abs(lo), abs(hi)))  # at least ±2 % of the values: no ripple of 1e-4 blown up
    mid = 0.5 * (lo + hi)
    lo, hi = mid - 0.58 * span, mid + 0.58 * span
    ax.set_ylim(lo, hi)
    for name, y in series.items():
        early = np.asarray(y)[~later]
        off = early[(early < lo) | (early > hi)]
        if off.size:
            peak = off[np.argmax(np.abs(off - 0.5 * (lo + hi)))]
            ax.plot([], [], " ", label=f"{name} up to t = {t0:.3g} s reaches {peak:.4g} (off the scale)")
