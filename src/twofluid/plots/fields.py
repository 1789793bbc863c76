"""Figures of 2D runs: porosity field, velocity fields, horizontal (radial) profiles."""
from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402

__all__ = ["field_plot", "velocity_plot", "profile_plot"]


def _labels(axi: bool) -> tuple[str, str]:
    return ("r [m]", "z [m]") if axi else ("x [m]", "y [m]")


def _cells(ax, mesh, values, cmap, vmin=None, vmax=None):
    pc = PolyCollection(mesh.points[mesh.cells], array=values, cmap=cmap, edgecolors="none")
    if vmin is not None or vmax is not None:
        pc.set_clim(vmin, vmax)
    ax.add_collection(pc)
    ax.set_xlim(mesh.points[:, 0].min(), mesh.points[:, 0].max())
    ax.set_ylim(mesh.points[:, 1].min(), mesh.points[:, 1].max())
    ax.set_aspect("equal")
    return pc


def field_plot(mesh, values, path: Path, title: str, label: str, cmap="viridis_r",
               vmin=None, vmax=None) -> Path:
    """Element field (e.g. porosity) coloured on the mesh; saved as PNG."""
    h = np.ptp(mesh.points[:, 1]) / max(np.ptp(mesh.points[:, 0]), 1e-12)
    fig, ax = plt.subplots(figsize=(min(3.0 + 6.0 / max(h, 0.5), 9.0), 7.0))
    pc = _cells(ax, mesh, values, cmap, vmin, vmax)
    fig.colorbar(pc, ax=ax, label=label)
    xl, yl = _labels(mesh.axisymmetric)
    ax.set_xlabel(xl)
    ax.set_ylabel(yl)
    ax.set_title(title)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path


def _quiver(ax, xc, vec, n_arrows=22):
    """Arrows at a subsample of element centres (about n_arrows per direction)."""
    span = np.ptp(xc, axis=0)
    cell = np.maximum(span / n_arrows, 1e-12)
    key = np.floor((xc - xc.min(axis=0)) / cell).astype(int)
    _, pick = np.unique(key, axis=0, return_index=True)
    ok = pick[np.all(np.isfinite(vec[pick, :2]), axis=1)]
    return ax.quiver(xc[ok, 0], xc[ok, 1], vec[ok, 0], vec[ok, 1], color="k", width=0.004)


def velocity_plot(mesh, fields: dict, path: Path, title: str) -> Path:
    """Liquid and solid velocity: |U| coloured per element with in-plane arrows (two panels)."""
    xc = np.column_stack([fields["x_m"], fields["y_m"]])
    fig, axes = plt.subplots(1, 2, figsize=(10, 7))
    for ax, key, name in zip(axes, ("Uf_m_s", "Us_m_s"), ("liquid U_f", "solid U_s")):
        u = fields[key]
        mag = np.sqrt(np.nansum(u[:, :2] ** 2, axis=1))
        mag = np.where(np.isfinite(u[:, 0]), mag, np.nan)
        pc = _cells(ax, mesh, np.ma.masked_invalid(mag), "magma_r")
        _quiver(ax, xc, u)
        fig.colorbar(pc, ax=ax, label=f"|{name}| in plane [m/s]", shrink=0.8)
        xl, yl = _labels(mesh.axisymmetric)
        ax.set_xlabel(xl)
        ax.set_ylabel(yl)
        ax.set_title(f"{name} (blank: clear liquid)" if key == "Us_m_s" else name)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path


def profile_plot(profiles: dict, path: Path, title: str, axi: bool, extra: dict | None = None) -> Path:
    """Porosity and velocity against x (r) at each height of ``profiles``.

    ``profiles``: {height: {"x_m", "porosity", "Uf_y", "Us_y", optionally "Uf_theta"}};
    ``extra``: {label: (x, u)} reference curves drawn on the velocity panel.
    """
    swirl = any("Uf_theta" in p for p in profiles.values())
    fig, axes = plt.subplots(1, 3 if swirl else 2, figsize=(13 if swirl else 9, 4.5))
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
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path
