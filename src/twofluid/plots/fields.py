"""Figures of 2D runs: porosity field, velocity fields, horizontal (radial) profiles."""
from __future__ import annotations

from . import _matplotlib  # noqa: F401, I001  (first: matplotlib imported lean in the command's process)

from pathlib import Path

import numpy as np
from matplotlib.collections import PolyCollection

from .agg import new_figure, write_png

__all__ = ["field_plot", "velocity_plot", "profile_plot", "single_fluid_plot", "robust_limits"]

#: percentiles of the element values that set a colour scale (one odd element must not set it)
PERCENTILES = (1.0, 99.0)


#: resolution of the PNGs [dots per inch]
DPI = 130

#: a domain taller (or wider) than this ratio is drawn stretched to it, the axis label says so
MAX_RATIO = 4.0


def _save(fig, path: Path, title: str | None = None) -> Path:
    """Title (if any), layout, write ``path`` at :data:`DPI`."""
    if title is not None:
        fig.suptitle(title)
    fig.tight_layout()
    return write_png(fig, path)


def _labels(axi: bool) -> tuple[str, str]:
    return ("r [m]", "z [m]") if axi else ("x [m]", "y [m]")


def _aspect(mesh) -> float:
    """Display aspect (height of a y unit over width of an x unit): 1, or a stretch to MAX_RATIO."""
    ratio = np.ptp(mesh.points[:, 1]) / max(np.ptp(mesh.points[:, 0]), 1e-12)
    return 1.0 if 1.0 / MAX_RATIO <= ratio <= MAX_RATIO else float(np.clip(ratio, 1 / MAX_RATIO, MAX_RATIO)) / ratio


def _axis_labels(ax, mesh):
    xl, yl = _labels(mesh.axisymmetric)
    a = _aspect(mesh)
    if a != 1.0:  # say that the picture is not to scale
        yl = f"{yl} (drawn at {a:.3g}× the scale of {xl.split()[0]})"
    ax.set_xlabel(xl)
    ax.set_ylabel(yl)


def _cells(ax, mesh, values, cmap, vmin=None, vmax=None):
    pc = PolyCollection(mesh.points[mesh.cells], array=values, cmap=cmap, edgecolors="none")
    if vmin is not None or vmax is not None:
        pc.set_clim(vmin, vmax)
    ax.add_collection(pc)
    ax.set_xlim(mesh.points[:, 0].min(), mesh.points[:, 0].max())
    ax.set_ylim(mesh.points[:, 1].min(), mesh.points[:, 1].max())
    ax.set_aspect(_aspect(mesh))
    return pc


def robust_limits(values, percentiles=PERCENTILES) -> tuple[float, float, str]:
    """Colour limits from percentiles of the finite values, and a note for the colour-bar label.

    The full range is used when the percentiles span most of it (80 %: no outlier to
    leave out); otherwise the note names the percentiles and the full range (values
    outside get the end colours).

    >>> lo, hi, note = robust_limits(np.r_[np.linspace(0.80, 0.81, 200), 0.95])
    >>> bool(hi < 0.811), "percentile" in note
    (True, True)
    >>> robust_limits([0.5, 0.6])[2]
    ''
    """
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    if v.size == 0:
        return 0.0, 1.0, ""
    lo, hi = np.percentile(v, percentiles)
    full = float(v.min()), float(v.max())
    if hi <= lo or hi - lo >= 0.8 * (full[1] - full[0]):
        return full[0], full[1], ""
    return float(lo), float(hi), (f"colour scale: percentiles {percentiles[0]:g}–{percentiles[1]:g} of the "
                                  f"elements; full range {full[0]:.4g}–{full[1]:.4g}")


def field_plot(mesh, values, path: Path, title: str, label: str, cmap="viridis_r",
               vmin=None, vmax=None, robust: bool = True) -> Path:
    """Element field (e.g. porosity) coloured on the mesh; saved as PNG.

    ``robust``: without ``vmin``/``vmax`` the colour scale spans the 1st–99th percentile
    of the element values (:func:`robust_limits`, said in the colour-bar label).
    """
    h = np.ptp(mesh.points[:, 1]) / max(np.ptp(mesh.points[:, 0]), 1e-12) * _aspect(mesh)  # as drawn
    fig = new_figure((min(3.0 + 6.0 / max(h, 0.5), 9.0), 7.0), DPI)
    ax = fig.subplots()
    extend = "neither"
    if robust and vmin is None and vmax is None:
        vmin, vmax, note = robust_limits(values)
        if note:
            label, extend = f"{label}\n({note})", "both"
    pc = _cells(ax, mesh, values, cmap, vmin, vmax)
    fig.colorbar(pc, ax=ax, label=label, extend=extend)
    _axis_labels(ax, mesh)
    ax.set_title(title)
    return _save(fig, path)


#: arrow length ∝ |U|^ARROW_POWER: slow regions (speeds over decades) keep visible arrows
ARROW_POWER = 0.5


def _quiver(ax, xc, vec, n_arrows=22, aspect=1.0):
    """Arrows at a subsample of element centres (about n_arrows per direction).

    White with a black edge (seen on light and dark colours), length ∝ √|U| scaled so
    the longest spans the typical spacing of the arrows on the page (a flow whose speeds
    span decades keeps arrows in its slow parts); the colour gives the speed. Directions
    are those of the data; ``aspect`` is the display stretch of y (:func:`_aspect`).
    """
    span = np.ptp(xc, axis=0)
    cell = np.maximum(span / n_arrows, 1e-12)
    key = np.floor((xc - xc.min(axis=0)) / cell).astype(int)
    _, pick = np.unique(key, axis=0, return_index=True)
    ok = pick[np.all(np.isfinite(vec[pick, :2]), axis=1)]
    u = vec[ok, :2]
    mag = np.hypot(u[:, 0], u[:, 1])
    top = mag.max() if mag.size else 0.0
    if top <= 0.0:
        return None
    # page lengths in x units: a data vector (u, v) shows as √(u² + (aspect v)²)
    spacing = np.sqrt(span[0] * span[1] * aspect / max(ok.size, 1))
    page = np.sqrt(u[:, 0] ** 2 + (aspect * u[:, 1]) ** 2)
    scale = (mag / top) ** ARROW_POWER * 0.9 * min(spacing, span[0] / 3) / np.where(page > 0, page, 1.0)
    return ax.quiver(xc[ok, 0], xc[ok, 1], u[:, 0] * scale, u[:, 1] * scale, angles="xy", scale_units="xy",
                     scale=1.0, color="white", edgecolor="black", linewidth=0.6, width=0.006,
                     headwidth=4.0, headlength=4.5, headaxislength=4.0)


def velocity_plot(mesh, fields: dict, path: Path, title: str) -> Path:
    """Liquid and solid velocity: |U| coloured per element with in-plane arrows (two panels)."""
    xc = np.column_stack([fields["x_m"], fields["y_m"]])
    fig = new_figure((10, 7), DPI)
    axes = fig.subplots(1, 2)
    for ax, key, name in zip(axes, ("Uf_m_s", "Us_m_s"), ("liquid U_f", "solid U_s")):
        u = fields[key]
        mag = np.sqrt(np.nansum(u[:, :2] ** 2, axis=1))
        mag = np.where(np.isfinite(u[:, 0]), mag, np.nan)
        lo, hi, note = robust_limits(mag)
        pc = _cells(ax, mesh, np.ma.masked_invalid(mag), "magma_r", 0.0, hi)
        _quiver(ax, xc, u, aspect=_aspect(mesh))
        label = f"|{name}| in plane [m/s]" + (f"\n(top of the scale: percentile {PERCENTILES[1]:g}; "
                                               f"max {np.nanmax(mag):.3g} m/s)" if note else "")
        fig.colorbar(pc, ax=ax, label=label, shrink=0.8, extend="max" if note else "neither")
        _axis_labels(ax, mesh)
        ax.set_title((f"{name} (blank: clear liquid)" if key == "Us_m_s" else name)
                     + "\narrows: direction, length ∝ √|U|", fontsize=9)
    return _save(fig, path, title)


def profile_plot(profiles: dict, path: Path, title: str, axi: bool, extra: dict | None = None) -> Path:
    """Porosity and velocity against x (r) at each height of ``profiles``.

    ``profiles``: {height: {"x_m", "porosity", "Uf_y", "Us_y", optionally "Uf_theta"}};
    ``extra``: {label: (x, u)} reference curves drawn on the velocity panel.
    """
    swirl = any("Uf_theta" in p for p in profiles.values())
    fig = new_figure((13 if swirl else 9, 4.5), DPI)
    axes = fig.subplots(1, 3 if swirl else 2)
    xl = _labels(axi)[0]
    for h, p in sorted(profiles.items()):
        axes[0].plot(p["x_m"], p["porosity"], drawstyle="steps-mid", label=f"height {h:g} m")
        line, = axes[1].plot(p["x_m"], p["Uf_y"], label=f"U_f, {h:g} m")
        axes[1].plot(p["x_m"], p["Us_y"], "--", color=line.get_color(), label=f"U_s, {h:g} m")
        if swirl:
            axes[2].plot(p["x_m"], p["Uf_theta"], label=f"U_f,θ, {h:g} m")
    for label, (x, u) in (extra or {}).items():
        axes[1].plot(x, u, ":", color="k", label=label)
    axes[0].set_ylabel("porosity n [-]")
    axes[1].set_ylabel("axial (vertical) velocity [m/s]")
    if swirl:
        axes[2].set_ylabel("swirl velocity [m/s]")
    for ax in axes:
        ax.set_xlabel(xl)
        ax.legend(fontsize=7)
        ax.grid(alpha=0.3)
    return _save(fig, path, title)


def single_fluid_plot(r, uz, ut, r_exact, uz_exact, ut_exact, path: Path, title: str) -> Path:
    """Single-fluid check: axial and swirl velocity along r, FEM nodes against the exact annulus."""
    fig = new_figure((10, 4.5), DPI)
    axes = fig.subplots(1, 2)
    for ax, u, ex, name, exact in ((axes[0], uz, uz_exact, "axial velocity u_z [m/s]",
                                    "annular Poiseuille flow, same flow rate [m/s]"),
                                   (axes[1], ut, ut_exact, "swirl velocity u_θ [m/s]",
                                    "circular Couette flow [m/s]")):
        ax.plot(r, u, "o", ms=3, label="finite elements, nodes [m/s]")
        ax.plot(r_exact, ex, "-", color="k", lw=1, label=exact)
        ax.set_xlabel("r [m]")
        ax.set_ylabel(name)
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
    return _save(fig, path, title)
