"""Figures of a liquefaction run: r_u histories, depth–time map of r_u, settlement."""
from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

__all__ = ["liquefaction_plots"]


def _shade(ax, col):
    if col.shaking_end > 0.0:
        ax.axvspan(0.0, col.shaking_end, color="0.92", zorder=0, label="shaking")


def liquefaction_plots(rec, col, out: Path, title: str, ru_liq: float = 0.95) -> list[Path]:
    """Write ru_histories.png, ru_map.png and settlement.png into ``out``; return the paths."""
    out = Path(out)
    t = np.array(rec.t)
    ru = np.array(rec.ru)
    paths = []

    fig, axes = plt.subplots(2, 1, figsize=(8, 7), sharex=True)
    colors = plt.cm.viridis(np.linspace(0.0, 0.9, max(len(rec.depths), 1)))
    for j, z in enumerate(rec.depths):
        axes[0].plot(t, ru[:, j], lw=1.0, color=colors[j], label=f"{z:g} m")
    axes[0].axhline(ru_liq, color="k", ls=":", lw=0.8)
    axes[0].set_ylabel("r_u = (P − P_hyd)/σ′_v0 [-]")
    axes[0].legend(fontsize=7, ncol=3, title="depth")
    _shade(axes[0], col)
    sig = np.array(rec.sig)  # σ′_v/σ′_v0 = P_s/σ′_v0 (thesis fig. 5.12)
    for j, z in enumerate(rec.depths):
        axes[1].plot(t, sig[:, j], lw=1.0, color=colors[j])
    axes[1].set_ylabel("σ′_v/σ′_v0 [-]")
    axes[1].set_xlabel("time [s]")
    _shade(axes[1], col)
    axes[0].set_title(f"{title}: excess pore-pressure ratio")
    fig.tight_layout()
    paths.append(out / "ru_histories.png")
    fig.savefig(paths[-1], dpi=110)
    plt.close(fig)

    if len(rec.field_t) > 1:
        ft, field = np.array(rec.field_t), np.array(rec.field)
        fig, ax = plt.subplots(figsize=(8, 4.5))
        depth = col.depth
        pc = ax.pcolormesh(ft, depth, field.T, shading="nearest", cmap="viridis",
                           vmin=0.0, vmax=max(1.0, float(np.nanmax(field))))
        if np.nanmax(field) > ru_liq:
            ax.contour(ft, depth, field.T, levels=[ru_liq], colors="r", linewidths=1.0)
        ax.invert_yaxis()
        ax.set_xlabel("time [s]")
        ax.set_ylabel("depth [m]")
        ax.set_title(f"{title}: r_u (red: r_u = {ru_liq:g})")
        if col.shaking_end > 0.0:
            ax.axvline(col.shaking_end, color="w", ls="--", lw=0.8)
        fig.colorbar(pc, ax=ax, label="r_u [-]")
        fig.tight_layout()
        paths.append(out / "ru_map.png")
        fig.savefig(paths[-1], dpi=110)
        plt.close(fig)

    fig, axes = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
    axes[0].plot(t, 100.0 * np.array(rec.settle), "k", lw=1.2)
    axes[0].set_ylabel("surface settlement [cm]")
    axes[0].invert_yaxis()
    _shade(axes[0], col)
    axes[0].set_title(f"{title}: settlement and base pore pressure")
    axes[1].plot(t, np.array(rec.pbase) / 1e3, "b", lw=1.0)
    axes[1].set_ylabel("base excess pore pressure [kPa]")
    axes[1].set_xlabel("time [s]")
    _shade(axes[1], col)
    fig.tight_layout()
    paths.append(out / "settlement.png")
    fig.savefig(paths[-1], dpi=110)
    plt.close(fig)
    return paths
