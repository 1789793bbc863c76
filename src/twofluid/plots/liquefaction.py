"""Figures of a liquefaction run: r_u histories, depth–time map of r_u, settlement, the profile
(layers, water table, peak r_u, peak strain, simplified-procedure FS) and response spectra.

Drawn for their CPU (docs/benchmarks.md, "Start-up and plots" and "The figures' CPU"): margins
fixed in inches (:func:`_margins`) rather than computed by ``tight_layout``, which lays out every
text of a figure once more; axes that make no tick until one is drawn
(:class:`twofluid.plots.agg.LeanAxes`); the ticks of linear, log and symlog axes drawn as
collections and texts (:func:`twofluid.plots.agg.drawn_ticks`), log axes without minor ticks (the
minor grid one collection, :func:`_minor_log_grid`) and labelled with plain numbers (0.1, 1, 10,
1e−05) rather than matplotlib's 10^x, whose mathtext parser costs about 0.1 s to build; titles
placed at the top of their axes
(``y=1.0``) rather than placed anew at each drawing above whatever might stick out there (none
of these axes has ticks on top).
"""
from __future__ import annotations

from . import _matplotlib  # noqa: F401, I001  (first: matplotlib imported lean in the command's process)

import math
from pathlib import Path

import numpy as np
from matplotlib import colormaps

from .agg import drawn_ticks, lean_subplots, log_ticks, new_figure, write_png

__all__ = ["liquefaction_plots", "settlement_state"]

#: resolution of the PNGs [dots per inch]
DPI = 110


def _margins(fig, left: float = 0.85, right: float = 0.25, bottom: float = 0.62, top: float = 0.42,
             **space) -> None:
    """Fixed margins [inch] around the axes of ``fig`` (``space``: wspace, hspace, as fractions).

    The default fits tick labels of up to six characters and an axis label on the left, a title
    on top, and the x tick labels and axis label at the bottom.

    >>> from twofluid.plots.agg import new_figure
    >>> fig = new_figure((8.0, 4.0), 50)
    >>> _margins(fig)
    >>> print(f"{fig.subplotpars.left * 8.0:.3f} {(1.0 - fig.subplotpars.top) * 4.0:.3f}")
    0.850 0.420
    """
    w, h = fig.get_size_inches()
    fig.subplots_adjust(left=left / w, right=1.0 - right / w, bottom=bottom / h, top=1.0 - top / h, **space)


def _minor_log_grid(ax, which: str = "x") -> None:
    """Grid lines of the log-scaled ``which`` axis ("x" or "y") of ``ax`` at 2 … 9 × 10^k (those not
    labelled by :func:`twofluid.plots.agg.log_ticks`) as one line collection, in the grid's style
    (call it once the axes' limits are final).

    matplotlib makes every minor tick of a log axis five artists (two marks, a grid line, two
    labels), 8 a decade and again for each axis that shares it: on the spectra figure about a
    third of its CPU for what one collection of lines draws the same.

    >>> from twofluid.plots.agg import new_figure
    >>> ax = new_figure((3.0, 2.0), 50).subplots()
    >>> _ = ax.loglog([1e-3, 1.2e-2], [0.01, 10.0]); _minor_log_grid(ax, "y")
    >>> ys = [seg[0][1] for seg in ax.collections[0].get_segments()]  # 2 ... 9 x 10^k inside the limits
    >>> int(sum(0.01 < y < 10.0 for y in ys)), all(ax.get_ylim()[0] <= y <= ax.get_ylim()[1] for y in ys)
    (24, True)
    """
    import matplotlib as mpl
    from matplotlib.collections import LineCollection

    lo, hi = sorted(ax.get_xlim() if which == "x" else ax.get_ylim())
    lo = max(lo, 1e-300)
    labelled = set(log_ticks(lo, hi))
    k0, k1 = math.floor(math.log10(lo)), math.ceil(math.log10(hi))
    at = [float(f"{m * 10.0 ** k:.12g}") for k in range(k0, k1 + 1) for m in range(2, 10)]
    at = [v for v in at if lo <= v <= hi and v not in labelled]
    if which == "x":
        segments, transform = [[(v, 0.0), (v, 1.0)] for v in at], ax.get_xaxis_transform()
    else:
        segments, transform = [[(0.0, v), (1.0, v)] for v in at], ax.get_yaxis_transform()
    rc = mpl.rcParams
    ax.add_collection(LineCollection(segments, transform=transform, zorder=1.5, colors=rc["grid.color"],
                                     linewidths=rc["grid.linewidth"], alpha=0.3), autolim=False)


#: width [inch] of a legend column placed right of its axes (a line and a label of ~8 characters at 7 pt)
LEGEND_COLUMN = 0.75

#: a long run's time axis is symlog (linear through the shaking) beyond this many times the shaking
SYMLOG_AFTER = 4.0


def _outside_legend(ax, **kwargs):
    """The legend of ``ax`` right of it, its top at the axes' top: outside the data, so that it hides
    no data point (its width, :data:`LEGEND_COLUMN` a column, is left in the right margin)."""
    return ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0, **kwargs)


def _time_axis(ax, t, col) -> str:
    """Make the time axis of ``ax`` show the shaking, and return its label. A run much longer than its
    shaking (more than :data:`SYMLOG_AFTER` times the shear wave's end) gets a symlog axis, linear from
    0 to the shear wave's end and logarithmic beyond, so that the shaking takes about a third of the
    axis instead of a sliver; a shorter one keeps its linear axis.

    >>> from types import SimpleNamespace
    >>> from twofluid.plots.agg import new_figure
    >>> ax = new_figure((4.0, 3.0), 50).subplots()
    >>> _time_axis(ax, [0.0, 3600.0], SimpleNamespace(shear_end=11.0)), ax.get_xscale()
    ('time [s] (linear to 11 s, logarithmic after)', 'symlog')
    >>> [float(v) for v in ax.get_xlim()]
    [0.0, 3600.0]
    """
    t_end = float(t[-1]) if len(t) else 0.0
    thresh = max(float(col.shear_end), 1.0)
    if float(col.shear_end) <= 0.0 or t_end <= SYMLOG_AFTER * thresh:
        return "time [s]"
    ax.set_xscale("symlog", linthresh=thresh, linscale=1.0)
    ax.set_xlim(0.0, t_end)
    return f"time [s] (linear to {thresh:g} s, logarithmic after)"


#: a settlement at least this fraction of the predicted final one is called final: the summary's own
#: rule (``settlement_final``, runners.liquefaction_report.FINAL_FRACTION), used here only for a
#: summary written without that field
FINAL_FRACTION = 0.99


def settlement_state(summary: dict) -> dict:
    """How far a run's settlement got, from its ``summary``: ``reached_m``, ``final_m`` (the predicted
    final settlement, None if the summary has none), ``fraction`` (reached / final), ``final`` (the
    pore pressure dissipated, or :data:`FINAL_FRACTION` of the final settlement reached) and
    ``words``, which say it for a title.

    >>> s = {"settlement_end_m": 0.0737, "dissipation": {"dissipated": False, "final_settlement_m": 0.175,
    ...      "fraction_of_final_settlement": 0.421}}
    >>> settlement_state(s)["words"]
    '7.37 cm reached, not final: 42 % of the predicted final 17.5 cm'
    >>> s["dissipation"].update(dissipated=True, fraction_of_final_settlement=0.997)
    >>> settlement_state(s)["words"]
    '7.37 cm, final (pore pressure dissipated; predicted final 17.5 cm)'
    >>> s["dissipation"].update(dissipated=False, final_settlement_m=0.0738, fraction_of_final_settlement=0.9986)
    >>> settlement_state(s)["words"]
    '7.37 cm, final (100 % of the predicted final 7.38 cm)'
    """
    reached = float(summary["settlement_end_m"])
    d = summary.get("dissipation") or {}
    final = d.get("final_settlement_m")
    fraction = d.get("fraction_of_final_settlement")
    if fraction is None and final is not None:
        fraction = reached / final if final > 0.0 else 1.0  # nothing left to settle
    dissipated = bool(d.get("dissipated"))
    done = summary.get("settlement_final")  # the run's own statement, where it made one
    if done is None:
        done = dissipated or (fraction is not None and fraction >= FINAL_FRACTION)
    if final is None:
        words = f"{100.0 * reached:.3g} cm reached (no final settlement predicted)"
    elif dissipated:
        words = f"{100.0 * reached:.3g} cm, final (pore pressure dissipated; predicted final {100.0 * final:.3g} cm)"
    elif done:
        words = f"{100.0 * reached:.3g} cm, final ({100.0 * fraction:.0f} % of the predicted final {100.0 * final:.3g} cm)"
    else:
        words = (f"{100.0 * reached:.3g} cm reached, not final: {100.0 * fraction:.0f} % of the predicted final "
                 f"{100.0 * final:.3g} cm")
    return {"reached_m": reached, "final_m": final, "fraction": fraction, "final": done, "words": words}


def _shade(ax, col):
    if col.shaking_end > 0.0:
        ax.axvspan(0.0, col.shaking_end, color="0.92", zorder=0, label="shaking")


def liquefaction_plots(rec, col, out: Path, title: str, ru_liq: float = 0.95, case=None, summary=None,
                       extra=None) -> list[Path]:
    """Write ru_histories.png, ru_map.png, settlement.png and, given the run's ``case``,
    ``summary`` and ``extra`` tables, profile.png and spectra.png into ``out``; return the paths."""
    out = Path(out)
    t = np.array(rec.t)
    ru = np.array(rec.ru)
    paths = []

    fig = new_figure((8, 7), DPI)
    axes = lean_subplots(fig, 2, 1, sharex=True)
    colors = colormaps["viridis"](np.linspace(0.0, 0.9, max(len(rec.depths), 1)))
    for j, z in enumerate(rec.depths):
        axes[0].plot(t, ru[:, j], lw=1.0, color=colors[j], label=f"{z:g} m")
    axes[0].axhline(ru_liq, color="k", ls=":", lw=0.8)
    axes[0].set_ylabel("r_u = (P − P_hyd)/σ′_v0 [-]")
    ncol = 1 if len(rec.depths) <= 14 else 2
    _outside_legend(axes[0], fontsize=7, ncol=ncol, title="depth")
    _shade(axes[0], col)
    sig = np.array(rec.sig)  # σ′_v/σ′_v0 = P_s/σ′_v0 (thesis fig. 5.12)
    for j, z in enumerate(rec.depths):
        axes[1].plot(t, sig[:, j], lw=1.0, color=colors[j])
    axes[1].set_ylabel("σ′_v/σ′_v0 [-]")
    axes[1].set_xlabel(_time_axis(axes[1], t, col))
    _shade(axes[1], col)
    axes[0].set_title(f"{title}: excess pore-pressure ratio", y=1.0)
    _margins(fig, right=0.3 + LEGEND_COLUMN * ncol, hspace=0.1)
    drawn_ticks(axes[0], xlabels=False, grid=False)  # (the time axis is shared)
    drawn_ticks(axes[1], grid=False)
    paths.append(write_png(fig, out / "ru_histories.png"))

    if len(rec.field_t) > 1:
        ft, field = np.array(rec.field_t), np.array(rec.field)
        fig = new_figure((8, 4.5), DPI)
        ax = lean_subplots(fig)
        depth = col.depth
        pc = ax.pcolormesh(ft, depth, field.T, shading="nearest", cmap="viridis",
                           vmin=0.0, vmax=max(1.0, float(np.nanmax(field))))
        if np.nanmax(field) > ru_liq:
            ax.contour(ft, depth, field.T, levels=[ru_liq], colors="r", linewidths=1.0)
        ax.set_ylim(col.ground_surface, 0.0)
        ax.set_xlabel(_time_axis(ax, ft, col))
        ax.set_ylabel("depth below the ground surface [m]")
        ax.set_title(f"{title}: r_u (red: r_u = {ru_liq:g})", y=1.0)
        if col.shaking_end > 0.0:  # the shaking window: a labelled bar along the top edge
            ax.axvline(col.shaking_end, color="w", ls="--", lw=0.8)
            ax.axvspan(0.0, col.shaking_end, ymin=0.95, ymax=1.0, color="tab:red", alpha=0.8)
            ax.annotate(f"shaking 0–{col.shaking_end:g} s", xy=(col.shaking_end, 0.975),
                        xycoords=("data", "axes fraction"), xytext=(4, 0), textcoords="offset points",
                        ha="left", va="center", color="tab:red", fontsize=8)
        zw = col.ground_surface - col.v.mesh.y[-1]
        if zw > 0.0:
            ax.axhline(zw, color="c", lw=0.8)
            ax.annotate("water table", xy=(ft[-1], zw), ha="right", va="bottom", color="c", fontsize=8)
        _margins(fig, right=0.2)  # before the colour bar, which takes its room from the axes
        bar = fig.colorbar(pc, ax=ax, label="r_u [-]")
        drawn_ticks(ax, grid=False)
        drawn_ticks(bar.ax, x=False, grid=False, yside="right")
        paths.append(write_png(fig, out / "ru_map.png"))

    fig = new_figure((8, 6), DPI)
    axes = lean_subplots(fig, 2, 1, sharex=True)
    axes[0].plot(t, 100.0 * np.array(rec.settle), "k", lw=1.2)
    axes[0].set_ylabel("surface settlement [cm]")
    state = settlement_state(summary) if summary is not None else None
    if state is not None and state["final_m"] is not None:  # the predicted final settlement, dashed
        axes[0].axhline(100.0 * state["final_m"], color="k", ls="--", lw=0.8)
        axes[0].annotate(f"predicted final {100.0 * state['final_m']:.3g} cm", xy=(0.01, 100.0 * state["final_m"]),
                         xycoords=("axes fraction", "data"), xytext=(0, 3), textcoords="offset points",
                         ha="left", va="bottom", fontsize=8)
    axes[0].invert_yaxis()
    _shade(axes[0], col)
    heading = f"{title}: settlement and base pore pressure"
    axes[0].set_title(heading if state is None else f"{heading}\nsettlement {state['words']}", y=1.0,
                      fontsize=None if state is None else 10)
    axes[1].plot(t, np.array(rec.pbase) / 1e3, "b", lw=1.0)
    axes[1].set_ylabel("base excess pore pressure [kPa]")
    axes[1].set_xlabel(_time_axis(axes[1], t, col))
    _shade(axes[1], col)
    _margins(fig, top=0.42 if state is None else 0.6, hspace=0.1)
    drawn_ticks(axes[0], xlabels=False, grid=False)  # (the time axis is shared)
    drawn_ticks(axes[1], grid=False)
    paths.append(write_png(fig, out / "settlement.png"))
    if case is not None and summary is not None and extra is not None:
        paths.append(_profile_plot(rec, col, out, title, ru_liq, summary, extra))
        if extra.get("spectra") is not None:
            paths.append(_spectra_plot(out, title, extra["spectra"]))
    return paths


def _profile_plot(rec, col, out: Path, title: str, ru_liq: float, summary: dict, extra: dict) -> Path:
    """Peak r_u, peak shear strain and FS against depth, layers and water table drawn."""
    ns = col.n_sat
    fig = new_figure((11, 6), DPI)
    axes = lean_subplots(fig, 1, 3, sharey=True)
    z = col.depth_all
    run, inp = extra["simplified_run"], extra["simplified_input"]
    axes[0].plot(np.clip(rec.peak, 0.0, None), z[:ns], "k.-", lw=1.0, ms=3, label="two-fluid peak r_u")
    axes[0].axvline(ru_liq, color="r", ls=":", lw=0.8)
    axes[0].set_xlabel("peak r_u [-]")
    axes[0].set_xlim(0.0, 1.1)
    axes[1].semilogx(np.maximum(rec.peak_strain, 1e-7), z, "b.-", lw=1.0, ms=3)
    axes[1].set_xlabel("peak |shear strain| [-]")
    fs_run = np.where(np.isfinite(run.FS), run.FS, np.nan)
    fs_in = np.where(np.isfinite(inp.FS), inp.FS, np.nan)
    axes[2].plot(fs_run, run.depth_mid_m, "m.-", lw=1.0, ms=3,
                 label=f"a_max = run surface {run.a_max_g:.2f} g")
    axes[2].plot(fs_in, inp.depth_mid_m, "g.--", lw=1.0, ms=3, label=f"a_max = input {inp.a_max_g:.2f} g")
    axes[2].axvline(1.0, color="r", ls=":", lw=0.8)
    axes[2].set_xlim(0.0, 3.0)
    axes[2].set_xlabel("FS, simplified procedure [-]")
    axes[2].legend(fontsize=7, loc="lower center", bbox_to_anchor=(0.5, 1.01), borderaxespad=0.0)  # above: hides nothing
    zw = summary["site"]["water_table_depth_m"]
    for ax in axes:
        for la in summary["layers"]:
            ax.axhline(la["depth_bottom_m"], color="0.6", lw=0.6)
        ax.axhline(zw, color="c", lw=1.0)
        ax.grid(alpha=0.3)
    for la in summary["layers"]:
        axes[0].annotate(la["name"], xy=(1.08, 0.5 * (la["depth_top_m"] + la["depth_bottom_m"])),
                         ha="right", va="center", fontsize=7, color="0.3")
    axes[0].annotate("water table", xy=(0.02, zw), va="bottom", color="c", fontsize=7)
    axes[0].set_ylim(col.ground_surface, 0.0)
    axes[0].set_ylabel("depth below the ground surface [m]")
    fig.suptitle(f"{title}: profile\nsettlement, two-fluid: {settlement_state(summary)['words']}; "
                 f"simplified procedure: {100 * run.total_settlement_m:.3g} cm (final)", fontsize=10)
    _margins(fig, right=0.3, top=0.95, wspace=0.12)
    for ax in axes:  # the depth axis is shared: labelled once
        drawn_ticks(ax, ylabels=ax is axes[0])
    return write_png(fig, out / "profile.png")


def _spectra_plot(out: Path, title: str, spec: dict) -> Path:
    fig = new_figure((8, 7), DPI)
    axes = lean_subplots(fig, 2, 1, sharex=True)
    T = spec["period_s"]
    axes[0].loglog(T, spec["Sa_input_g"], "k", lw=1.2, label="input")
    axes[0].loglog(T, spec["Sa_surface_g"], "r", lw=1.2, label="surface")
    axes[0].set_ylabel(f"S_a, {100 * spec['damping']:g} % damped [g]")
    _outside_legend(axes[0])
    axes[0].set_title(f"{title}: response spectra", y=1.0)
    axes[1].semilogx(T, spec["amplification"], "b", lw=1.2)
    axes[1].axhline(1.0, color="k", lw=0.6)
    axes[1].set_ylabel("amplification S_a,surface / S_a,input [-]")
    axes[1].set_xlabel("period [s]")
    _minor_log_grid(axes[0], "x")
    _minor_log_grid(axes[0], "y")
    _minor_log_grid(axes[1], "x")
    _margins(fig, right=0.3 + 1.1 * LEGEND_COLUMN, hspace=0.1)
    drawn_ticks(axes[0], xlabels=False)  # (the period axis is shared)
    drawn_ticks(axes[1])
    return write_png(fig, out / "spectra.png")
