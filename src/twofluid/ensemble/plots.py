"""Figures of an ensemble: each scalar figure against the varied parameters, histograms of a
Monte Carlo, each list-valued figure (a value per depth, say) over its members with their
statistics, and the fragility curves of a PGA sweep. Legends sit outside the axes (they hide no
data); a figure of a settlement says in its title how many members reached their final one."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from .fragility import fit_lognormal_fragility, fragility_by_level
from .results import unit_of

__all__ = ["ensemble_plots", "fragility_fits", "list_values", "settlement_note"]

#: a legend right of its axes, top-aligned: outside the data, so that it hides none of it
OUTSIDE = {"loc": "upper left", "bbox_to_anchor": (1.02, 1.0), "borderaxespad": 0.0}


def _save(fig, path: Path, dpi: int) -> None:
    """Write ``fig`` as PNG whole or not at all, never through a symbolic link planted in the folder
    (:func:`twofluid.io.folders.write_atomic`)."""
    import io

    from ..io.folders import write_atomic

    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi)
    write_atomic(path, buf.getvalue())


def _scalar(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def list_values(rows: list[dict], f: str) -> list[np.ndarray] | None:
    """The completed members' values of figure ``f`` as float arrays when every one is a list of
    numbers (None entries as NaN); None when ``f`` is not list-valued.

    >>> [a.tolist() for a in list_values([{"status": "completed", "r": [0.5, None]}], "r")]
    [[0.5, nan]]
    >>> list_values([{"status": "completed", "r": 0.5}], "r") is None
    True
    """
    done = [r.get(f) for r in rows if r["status"] == "completed"]
    if not done or not all(isinstance(v, list) and v and all(_scalar(x) or x is None for x in v) for v in done):
        return None
    return [np.array([np.nan if x is None else x for x in v], float) for v in done]


def settlement_note(f: str, done: list[dict]) -> str:
    """For a settlement figure ``f``: whether the members' settlements are final, from what the
    ensemble collected of their summaries' ``dissipation`` block ("" for another figure).

    >>> rows = [{"dissipation.dissipated": True}, {"dissipation.dissipated": False}]
    >>> settlement_note("settlement_end_m", rows)
    '1 of 2 members final (dissipated)'
    >>> settlement_note("settlement_end_m", [{}])
    'whether final not collected (add dissipation.dissipated to collect)'
    """
    if "settlement" not in f or "final" in f:
        return ""
    flags = [r.get("dissipation.dissipated") for r in done]
    fracs = [r.get("dissipation.fraction_of_final_settlement") for r in done]
    words = []
    if all(isinstance(x, bool) for x in flags):
        words.append(f"{sum(flags)} of {len(flags)} members final (dissipated)")
    if all(_scalar(x) for x in fracs):
        words.append(f"reached {100.0 * min(fracs):.0f}–{100.0 * max(fracs):.0f} % of their predicted final")
    return "; ".join(words) or "whether final not collected (add dissipation.dissipated to collect)"


def _list_plot(values: list[np.ndarray], f: str, title: str, path: Path, depths=None) -> Path:
    """Every member's list ``values`` of figure ``f`` (thin lines) with their mean, minimum and
    maximum per entry, against ``depths`` (name, values; downwards) or the entries' number."""
    import warnings

    import matplotlib.pyplot as plt

    width = min(v.size for v in values)
    vals = np.array([v[:width] for v in values])
    down = depths is not None and len(depths[1]) >= width and all(_scalar(x) for x in depths[1][:width])
    pos = np.asarray(depths[1][:width], float) if down else np.arange(1, width + 1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # an entry no member has: NaN
        lo, mean, hi = np.nanmin(vals, 0), np.nanmean(vals, 0), np.nanmax(vals, 0)
    fig, ax = plt.subplots(figsize=(5.4, 5.4) if down else (6.4, 4.2))

    def draw(y, *args, **kwargs):  # the figure along x, and the entries down y where they are depths
        return ax.plot(y, pos, *args, **kwargs) if down else ax.plot(pos, y, *args, **kwargs)

    for v in vals:
        draw(v, "-", color="0.6", lw=0.6, alpha=0.6)
    draw(mean, "o-", color="k", lw=1.4, ms=3, label=f"mean of {len(vals)} members")
    draw(lo, "--", color="tab:blue", lw=1.0, label="min / max")
    draw(hi, "--", color="tab:blue", lw=1.0)
    ax.plot([], [], "-", color="0.6", lw=0.6, label="each member")
    label = f"{f} [{unit_of(f)}]"
    if down:
        ax.invert_yaxis()
        ax.set_xlabel(label)
        ax.set_ylabel(f"{depths[0]} [m]")
    else:
        ax.set_xlabel("entry")
        ax.set_ylabel(label)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, **OUTSIDE)
    ax.set_title(title, fontsize=9)
    fig.tight_layout()
    _save(fig, path, 100)
    plt.close(fig)
    return path


def _depths_for(f: str, collect: list[str], done: list[dict]):
    """(name, values) of the depths of list figure ``f``'s entries: a collected list figure beside it
    whose name ends in ``depth_m`` (``report_depths.depth_m`` for ``report_depths.peak_r_u``), as
    the first completed member has it; None if there is none.

    >>> _depths_for("a.r_u", ["a.r_u", "a.depth_m"], [{"a.depth_m": [1.0, 2.0]}])
    ('a.depth_m', [1.0, 2.0])
    """
    parent = f.rsplit(".", 1)[0] if "." in f else ""
    for g in collect:
        if g != f and g.endswith("depth_m") and (g.rsplit(".", 1)[0] if "." in g else "") == parent:
            v = done[0].get(g)
            if isinstance(v, list):
                return g, v
    return None


def key_unit(model: str, key: str) -> str:
    """The unit of a case key ``section.key`` from the case schema ("-" if it has none).

    >>> key_unit("liquefaction_1d", "layers.1.relative_density"), key_unit("liquefaction_1d", "ground_motion.pga_g")
    ('%', 'g')
    """
    from ..casefile import schema

    parts = [p for p in key.split(".") if not p.isdigit()]  # layers.2.porosity: the layers' key
    section, name = ".".join(parts[:-1]), parts[-1]
    keys = schema._model_schema(model).get(section) or getattr(schema, "ARRAYS", {}).get(model, {}).get(section, [])
    return next((k.unit for k in keys if k.name == name and k.unit), unit_of(key))


def fragility_fits(rows: list[dict], frag: dict) -> dict:
    """One lognormal fit per entry of the fragility figure (per depth when it is a list)."""
    done = [r for r in rows if r["status"] == "completed" and r.get(frag["figure"]) is not None
            and _scalar(r.get(frag["intensity"]))]
    out = {**frag, "unit": unit_of(frag["intensity"]), "curves": []}  # ground motion in g
    if not done:
        return {**out, "note": "no completed member"}
    values = [np.atleast_1d(np.asarray(r[frag["figure"]], float)) for r in done]
    width = min(len(v) for v in values)
    labels = done[0].get(frag["labels"]) if frag["labels"] else None
    labels = list(np.atleast_1d(labels))[:width] if labels is not None else list(range(width))
    x = np.array([r[frag["intensity"]] for r in done], float)
    for j in range(width):
        hit = np.array([v[j] >= frag["threshold"] for v in values])
        levels, counts, frac = fragility_by_level(x, hit)
        out["curves"].append({"label": labels[j], **fit_lognormal_fragility(x, hit), "levels": levels.tolist(),
                              "members": counts.tolist(), "fraction": frac.tolist()})
    return out


def _fragility_plot(fits: dict, path: Path, title: str) -> Path:
    import matplotlib.pyplot as plt
    from scipy import stats

    curves = fits["curves"]
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4.5))
    colours = plt.cm.viridis(np.linspace(0, 0.9, max(len(curves), 1)))
    xs = np.array(curves[0]["levels"]) if curves else np.array([1.0])
    grid = np.linspace(0.0, 1.1 * xs.max(), 200)[1:]
    for c, col in zip(curves, colours):
        name = f"{c['label']:g} m" if _scalar(c["label"]) else str(c["label"])
        ax.plot(c["levels"], c["fraction"], "o", color=col, ms=4)
        if c["theta"] is not None:
            ax.plot(grid, stats.norm.cdf(np.log(grid / c["theta"]) / c["beta"]), "-", color=col,
                    label=f"{name}: θ = {c['theta']:.3g}, β = {c['beta']:.2f}")
        else:
            ax.plot(c["levels"], c["fraction"], ":", color=col, label=f"{name}: {c['note'].split(':')[0]}")
    ax.set_xlabel(f"{fits['intensity']} [{fits['unit']}]")
    ax.set_ylabel(f"P({fits['figure']} ≥ {fits['threshold']:g})")
    ax.set_ylim(-0.03, 1.03)
    ax.legend(fontsize=6, loc="upper left", bbox_to_anchor=(0.0, -0.16), borderaxespad=0.0)  # below: hides nothing
    ax.set_title("fragility: members (dots), lognormal MLE (lines)", fontsize=9)
    if curves and all(_scalar(c["label"]) for c in curves):
        depth = np.array([c["label"] for c in curves], float)
        prob = np.array([c["fraction"] for c in curves])  # depth × level
        for k, (lev, col) in enumerate(zip(xs, plt.cm.plasma(np.linspace(0, 0.85, xs.size)))):
            bx.plot(prob[:, k], depth, "o-", color=col, ms=3, label=f"{lev:g} {fits['unit']}")
        bx.invert_yaxis()
        bx.set_xlabel("probability over the members")
        bx.set_ylabel(f"{fits['labels'] or 'entry'} (depth from the surface) [m]")
        bx.set_xlim(-0.03, 1.03)
        bx.legend(fontsize=7, title=fits["intensity"], title_fontsize=7, **OUTSIDE)
        bx.set_title("probability by depth at each level", fontsize=9)
    else:
        bx.axis("off")
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    _save(fig, path, 110)
    plt.close(fig)
    return path


def ensemble_plots(rows: list[dict], spec, out: Path, fragility: dict | None = None) -> list[Path]:
    """Write the study's figures into ``out``; return their paths."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    done = [r for r in rows if r["status"] == "completed"]
    model = spec.base["case"]["model"]
    varied = spec.varied()
    numeric = [k for k in varied if done and all(_scalar(r.get(k)) for r in done)]
    groups = [k for k in varied if k not in numeric]  # e.g. the record: one colour each
    scalars = [f for f in spec.collect if done and all(_scalar(r.get(f)) for r in done)]
    paths = []
    for f in scalars:
        if numeric:
            fig, axes = plt.subplots(1, len(numeric), figsize=(4.2 * len(numeric), 3.6), squeeze=False)
            keys = sorted({str(r.get(groups[0])) for r in done}) if groups else [None]
            for ax, k in zip(axes[0], numeric):
                for g in keys:
                    sub = [r for r in done if g is None or str(r.get(groups[0])) == g]
                    sub.sort(key=lambda r: r[k])
                    xs = [r[k] for r in sub]
                    # a line only when it is a curve: one member per value (else other keys vary too)
                    style = "o-" if varied[k] != "sample" and len(set(xs)) == len(xs) else "o"
                    ax.plot(xs, [r[f] for r in sub], style, ms=3, label=g)
                ax.set_xlabel(f"{k} [{key_unit(model, k)}]")
                ax.set_ylabel(f"{f} [{unit_of(f)}]")
                if groups and len(keys) <= 12:
                    ax.legend(fontsize=6, **OUTSIDE)
            note = settlement_note(f, done)
            fig.suptitle(f"{spec.name}: {f}" + (f"\n{note}" if note else ""), fontsize=10)
            fig.tight_layout()
            paths.append(out / f"figure_{f.replace('.', '_')}.png")
            _save(fig, paths[-1], 100)
            plt.close(fig)
        if spec.sample:
            fig, ax = plt.subplots(figsize=(4.5, 3.5))
            ax.hist([r[f] for r in done], bins="auto")
            ax.set_xlabel(f"{f} [{unit_of(f)}]")
            ax.set_ylabel("members")
            note = settlement_note(f, done)
            ax.set_title(f"{spec.name}: {len(done)} members" + (f"\n{note}" if note else ""), fontsize=9)
            fig.tight_layout()
            paths.append(out / f"histogram_{f.replace('.', '_')}.png")
            _save(fig, paths[-1], 100)
            plt.close(fig)
    listed = [f for f in spec.collect if done and list_values(rows, f) is not None]
    axes_of = {d[0] for d in (_depths_for(f, spec.collect, done) for f in listed) if d is not None}
    for f in listed:
        if f in axes_of:  # the depths of another list figure: that plot's axis
            continue
        values = list_values(rows, f)
        note = settlement_note(f, done)
        title = f"{spec.name}: {f}, {len(values)} members" + (f"\n{note}" if note else "")
        paths.append(_list_plot(values, f, title, out / f"list_{f.replace('.', '_')}.png",
                                _depths_for(f, spec.collect, done)))
    if fragility and fragility.get("curves"):
        paths.append(_fragility_plot(fragility, out / "fragility.png", f"{spec.name}: {len(done)} members"))
    return paths
