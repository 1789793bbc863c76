"""Figure of a cyclic simple-shear element test: pressures, n̄ and τ–γ loops."""
from __future__ import annotations

from . import _matplotlib  # noqa: F401, I001  (first: matplotlib imported lean in the command's process)

from pathlib import Path

import matplotlib
import matplotlib.ticker

from .agg import new_figure, write_png

# The figure does not use pyplot; the backend is set for callers that import pyplot after
# this module (models.element_test closes pyplot's figures), as this module did before.
matplotlib.use("Agg")

__all__ = ["plot_element_test", "plot_csr_n"]

#: resolution of the PNG [dots per inch]
DPI = 120


def plot_element_test(result, path: str | Path | None = None, element: int = 0,
                      title: str | None = None):
    """Plot P_s, r_u and n̄ against cycles and the τ–γ loops of one element.

    Parameters
    ----------
    result : twofluid.models.element_test.ElementTestResult
        Output of :func:`~twofluid.models.element_test.cyclic_simple_shear`.
    path : str or Path, optional
        PNG file to write; the figure is returned either way.
    element : int
        Which element (column of the histories) to plot.
    title : str, optional
        Figure title; by default the loading and cycles to liquefaction.

    Returns
    -------
    matplotlib.figure.Figure
    """
    cyc = result.cycles
    fig = new_figure((14, 4.2), DPI, layout="constrained")
    ax_p, ax_n, ax_t = fig.subplots(1, 3)

    ax_p.plot(cyc, result.p_s[:, element] / 1e3, color="tab:blue", label="$P_s$")
    ax_p.set_xlabel("cycles")
    ax_p.set_ylabel("granular pressure $P_s$ [kPa]", color="tab:blue")
    ax_r = ax_p.twinx()
    ax_r.plot(cyc, result.r_u[:, element], color="tab:red", label="$r_u$")
    ax_r.axhline(result.settings.get("ru_liquefied", 0.95), color="tab:red", ls=":", lw=0.8)
    ax_r.set_ylabel("excess pore-pressure ratio $r_u$ [-]", color="tab:red")
    ax_r.set_ylim(-0.02, 1.02)

    ax_n.plot(cyc, result.n_bar[:, element], color="tab:green", label=r"$\bar n$")
    ax_n.plot(cyc, result.porosity[:, element], color="k", ls="--", label="$n$")
    ax_n.set_xlabel("cycles")
    ax_n.set_ylabel("porosity [-]")
    ax_n.legend(loc="best")

    ax_t.plot(result.gamma[:, element] * 100.0, result.tau[:, element] / 1e3, lw=0.7)
    ax_t.set_xlabel(r"shear strain $\gamma$ [%]")
    ax_t.set_ylabel(r"shear stress $\tau$ [kPa]")

    n_liq = result.cycles_to_liquefaction[element]
    if title is None:
        mode = result.settings.get("mode", "")
        drained = "drained" if result.settings.get("drained") else "undrained"
        told = f"liquefied after {n_liq:.2f} cycles" if n_liq != float("inf") \
            else "no liquefaction"
        title = f"{drained} cyclic simple shear ({mode}-controlled): {told}"
    fig.suptitle(title)
    if path is not None:
        write_png(fig, path)
    return fig


def plot_csr_n(rows, path: str | Path | None = None, title: str | None = None):
    """The model's cycles to liquefaction against the correlation's CSR–N curve.

    ``rows`` as :func:`twofluid.models.element_test_hysteretic.csr_n_curve` returns them; the band
    is ±15 % in CSR around the correlation."""
    import numpy as np

    fig = new_figure((6.0, 4.2), DPI, layout="constrained")
    ax = fig.add_subplot(1, 1, 1)
    csr = np.array([r["csr"] for r in rows])
    n_c = np.array([r["cycles_correlation"] for r in rows])
    n_m = np.array([r["cycles_model"] for r in rows])
    ax.plot(n_c, csr, "k-", label="correlation: CRR (15/N)^b")
    ax.fill_between(n_c, 0.85 * csr, 1.15 * csr, color="0.85", label="±15 % in CSR")
    ax.plot(n_m, csr, "o", color="C0", label="element test (r_u ≥ 0.98 or γ ≥ 3 %)")
    ax.set_xscale("log")
    ax.set_xticks(n_c, [f"{v:g}" for v in n_c])
    ax.xaxis.set_minor_locator(matplotlib.ticker.NullLocator())
    ax.set_xlabel("uniform cycles to liquefaction N")
    ax.set_ylabel("CSR = τ/σ′_v0")
    ax.set_title(title or "Undrained cyclic simple shear, hysteretic model")
    ax.legend(fontsize=8)
    if path is not None:
        write_png(fig, path)
    return fig
