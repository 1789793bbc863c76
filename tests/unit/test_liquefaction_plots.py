"""The figures of a liquefaction run (twofluid.plots.liquefaction): what they say about the settlement,
a time axis that shows the shaking, legends that hide no data, and no work hidden in the plotting."""
import json
import warnings

import numpy as np
import pytest

from twofluid.casefile.loader import load_case
from twofluid.plots.liquefaction import settlement_state
from twofluid.runners.common import run_case


def _case(end=120.0, dissipated_r_u=0.01, plots=True):
    """The thesis's fine sand, 20 elements, 3 s of shaking: run to ``end`` or dissipation."""
    c = load_case("liquefaction-fine")
    c["layers"][0]["elements"] = 20
    c["ground_motion"]["duration"] = 3.0
    c["time"]["end"] = end
    c["reconsolidation"]["dissipated_r_u"] = dissipated_r_u
    c["output"]["times"] = [t for t in c["output"]["times"] if t < end]
    c["output"]["plots"] = plots
    return c


def _run(case, out):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return run_case(case, out)


@pytest.fixture(scope="module")
def drawn(tmp_path_factory):
    """{png name: its matplotlib Figure, drawn} of one run stopped before dissipation, and its summary."""
    import twofluid.plots.liquefaction as plots

    figures = {}
    write = plots.write_png

    def keep(fig, path):
        figures[path.name] = fig
        return write(fig, path)

    plots.write_png = keep
    try:
        res = _run(_case(end=60.0), tmp_path_factory.mktemp("partial"))
    finally:
        plots.write_png = write
    assert res.status == "completed"
    return figures, res.summary


def test_settlement_state_says_final_or_the_fraction_reached():
    partial = {"settlement_end_m": 0.0737, "dissipation": {"dissipated": False, "final_settlement_m": 0.175,
                                                           "fraction_of_final_settlement": 0.0737 / 0.175}}
    s = settlement_state(partial)
    assert not s["final"] and s["final_m"] == 0.175
    assert "not final" in s["words"] and "42 %" in s["words"] and "17.5 cm" in s["words"]
    partial["dissipation"]["dissipated"] = True
    assert settlement_state(partial)["words"].startswith("7.37 cm, final")
    assert "no final settlement" in settlement_state({"settlement_end_m": 0.01})["words"]
    nothing = settlement_state({"settlement_end_m": 0.0, "dissipation": {"final_settlement_m": 0.0}})
    assert nothing["final"] and nothing["fraction"] == 1.0


def test_every_figure_with_a_settlement_says_whether_it_is_final_beside_the_predicted_final(drawn):
    figures, summary = drawn
    d = summary["dissipation"]
    assert not d["dissipated"] and 0.0 < d["fraction_of_final_settlement"] < 0.999  # stopped early
    final_cm = f"{100.0 * d['final_settlement_m']:.3g} cm"
    reached = f"{100.0 * d['fraction_of_final_settlement']:.0f} % of the predicted final {final_cm}"
    title = figures["settlement.png"].axes[0].get_title()
    assert "not final" in title and reached in title
    # the predicted final settlement drawn as a level in the settlement panel
    levels = [ln.get_ydata()[0] for ln in figures["settlement.png"].axes[0].lines if ln.get_linestyle() == "--"]
    assert levels == pytest.approx([100.0 * d["final_settlement_m"]])
    suptitle = figures["profile.png"]._suptitle.get_text()
    assert "not final" in suptitle and reached in suptitle and "simplified procedure" in suptitle


def test_a_dissipated_run_is_called_final(tmp_path):
    res = _run(_case(end=3600.0, plots=False), tmp_path / "done")
    assert res.summary["dissipation"]["dissipated"]
    assert ", final (pore pressure dissipated" in settlement_state(res.summary)["words"]


@pytest.mark.parametrize("name", ["ru_histories.png", "settlement.png", "ru_map.png"])
def test_the_time_axis_shows_the_shaking(drawn, name):
    """A run 20 times longer than its shear wave: the shaking takes at least a fifth of the time axis."""
    figures, summary = drawn
    shaking = summary["shaking"]["end_s"]
    ax = figures[name].axes[-1] if name != "ru_map.png" else figures[name].axes[0]
    assert ax.get_xscale() == "symlog"
    x0 = ax.transData.transform([(0.0, 0.0)])[0, 0]
    xs = ax.transData.transform([(shaking, 0.0)])[0, 0]
    box = ax.get_window_extent()
    assert (xs - x0) / box.width > 0.2


def _data_points(fig):
    """Display coordinates of every data point of every line of ``fig`` (not a legend's own handles)."""
    pts = []
    for ax in fig.axes:
        for ln in ax.lines:
            xy = np.column_stack([ln.get_xdata(), ln.get_ydata()]).astype(float)
            xy = xy[np.isfinite(xy).all(axis=1)]
            if xy.size:
                pts.append(ln.get_transform().transform(xy))
    return np.concatenate(pts) if pts else np.empty((0, 2))


def test_no_legend_hides_a_data_point(drawn):
    figures, _ = drawn
    legends = 0
    for name, fig in figures.items():
        renderer = fig.canvas.get_renderer()
        pts = _data_points(fig)
        for ax in fig.axes:
            leg = ax.get_legend()
            if leg is None:
                continue
            legends += 1
            box = leg.get_window_extent(renderer)
            inside = (pts[:, 0] > box.x0) & (pts[:, 0] < box.x1) & (pts[:, 1] > box.y0) & (pts[:, 1] < box.y1)
            assert not inside.any(), f"{name}: the legend hides {int(inside.sum())} data points"
    assert legends >= 3  # r_u histories, profile, spectra


def _comparable(folder, name):
    """A file of a run's folder as compared with and without figures: its bytes, except in what says
    which run it was: summary.json's wall time, the folder's record of its files (their sizes, and
    times of writing, which no two runs share) and the resolved case's ``plots`` key (the input)."""
    text = (folder / name).read_bytes()
    if name == "summary.json":
        summary = json.loads(text)
        summary.pop("wall_time_s")
        return summary
    if name == ".twofluid-run.json":
        return sorted(k for k in json.loads(text)["files"] if not k.endswith(".png"))
    if name == "case.resolved.toml":
        return [ln for ln in text.splitlines() if not ln.startswith(b"plots = ")]
    return text


def test_outputs_other_than_the_figures_are_the_same_without_them(tmp_path):
    """No work hides in the plotting: every file but the PNGs byte for byte the same with and without
    figures (apart from what names the run: :func:`_comparable`)."""
    a, b = tmp_path / "plots", tmp_path / "none"
    _run(_case(end=30.0), a)
    _run(_case(end=30.0, plots=False), b)
    with_plots = {p.name for p in a.iterdir()}
    without = {p.name for p in b.iterdir()}
    assert {n for n in with_plots if n.endswith(".png")} and not {n for n in without if n.endswith(".png")}
    assert {n for n in with_plots if not n.endswith(".png")} == without
    for name in sorted(without):
        assert _comparable(a, name) == _comparable(b, name), name


def test_the_figures_call_a_settlement_final_by_the_summarys_rule():
    """A figure's "final" is the summary's: its settlement_final where given, else the same fraction."""
    from twofluid.plots.liquefaction import FINAL_FRACTION, settlement_state
    from twofluid.runners import liquefaction_report as report

    assert FINAL_FRACTION == report.FINAL_FRACTION
    s = {"settlement_end_m": 0.0993, "settlement_final": False,
         "dissipation": {"dissipated": False, "final_settlement_m": 0.1, "fraction_of_final_settlement": 0.993}}
    assert settlement_state(s)["final"] is False
