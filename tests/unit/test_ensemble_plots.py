"""The figures of an ensemble (twofluid.ensemble.plots) from members' rows: a plot and statistics for
a list-valued figure, settlement figures that say whether they are final, legends that hide no data."""
from types import SimpleNamespace

import numpy as np
import pytest

from twofluid.ensemble.plots import ensemble_plots, list_values, settlement_note
from twofluid.ensemble.results import figure_stats

DEPTHS = [float(z) for z in np.linspace(0.5, 9.5, 19)]


def _rows(n=12):
    rng = np.random.default_rng(3)
    rows = []
    for i in range(n):
        pga = 0.1 + 0.02 * i
        rows.append({"member": i, "status": "completed", "ground_motion.pga_g": pga,
                     "settlement_end_m": 0.02 + 0.1 * pga, "dissipation.dissipated": i % 2 == 0,
                     "report_depths.depth_m": list(DEPTHS),
                     "report_depths.peak_r_u": list(np.clip(pga * 5 * rng.uniform(0.5, 1.5, len(DEPTHS)), 0, 1.1)),
                     "record": "a" if i < n // 2 else "b"})
    rows.append({"member": n, "status": "failed", "ground_motion.pga_g": 0.9, "settlement_end_m": None,
                 "report_depths.peak_r_u": None, "report_depths.depth_m": None, "record": "a"})
    return rows


def _spec(collect):
    return SimpleNamespace(name="study", base={"case": {"model": "liquefaction_1d"}}, sample={},
                           collect=collect, varied=lambda: {"ground_motion.pga_g": "grid", "record": "grid"})


@pytest.fixture
def saved(monkeypatch):
    """{file name: Figure} of every figure the ensemble writes."""
    from twofluid.ensemble import plots

    figures = {}
    save = plots._save

    def keep(fig, path, dpi):
        save(fig, path, dpi)
        figures[path.name] = fig

    monkeypatch.setattr(plots, "_save", keep)
    return figures


def test_a_list_valued_figure_gets_a_plot_against_its_depths(tmp_path, saved):
    collect = ["settlement_end_m", "report_depths.depth_m", "report_depths.peak_r_u"]
    names = {p.name for p in ensemble_plots(_rows(), _spec(collect), tmp_path)}
    assert "list_report_depths_peak_r_u.png" in names
    assert "list_report_depths_depth_m.png" not in names  # the depths are the plot's axis
    ax = saved["list_report_depths_peak_r_u.png"].axes[0]
    assert ax.yaxis_inverted() and "depth_m" in ax.get_ylabel()
    mean = next(ln for ln in ax.lines if ln.get_label().startswith("mean of 12"))
    values = np.array([r["report_depths.peak_r_u"] for r in _rows() if r["status"] == "completed"])
    np.testing.assert_allclose(mean.get_xdata(), values.mean(0))
    np.testing.assert_allclose(mean.get_ydata(), DEPTHS)


def test_list_statistics_per_entry():
    rows = _rows()
    stats = figure_stats(rows, ["report_depths.peak_r_u", "settlement_end_m"])["report_depths.peak_r_u"]
    values = np.array([r["report_depths.peak_r_u"] for r in rows if r["status"] == "completed"])
    assert stats["count"] == 12 and stats["entries"] == len(DEPTHS) and stats["unit"] == "-"
    for k, fn in (("min", np.min), ("mean", np.mean), ("std", np.std), ("max", np.max)):
        np.testing.assert_allclose(stats[k], fn(values, 0), err_msg=k)
    ragged = figure_stats([{"status": "completed", "r": [1.0]}, {"status": "completed", "r": [3.0, 4.0]}], ["r"])
    assert ragged["r"]["mean"] == [2.0, 4.0] and ragged["r"]["std"] == [1.0, 0.0]
    assert list_values([{"status": "completed", "r": ["a"]}], "r") is None


def test_settlement_figures_say_how_many_members_are_final(tmp_path, saved):
    ensemble_plots(_rows(), _spec(["settlement_end_m"]), tmp_path)
    title = saved["figure_settlement_end_m.png"]._suptitle.get_text()
    assert "6 of 12 members final" in title
    assert "not collected" in settlement_note("settlement_end_m", [{"settlement_end_m": 0.1}])
    assert settlement_note("peak_r_u_top_element", [{}]) == ""


def test_no_legend_hides_a_data_point(tmp_path, saved):
    collect = ["settlement_end_m", "report_depths.depth_m", "report_depths.peak_r_u"]
    ensemble_plots(_rows(), _spec(collect), tmp_path)
    checked = 0
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    for name, fig in saved.items():
        canvas = FigureCanvasAgg(fig)  # (pyplot took its canvas away when it closed the figure)
        canvas.draw()
        renderer = canvas.get_renderer()
        pts = [ln.get_transform().transform(np.column_stack([ln.get_xdata(), ln.get_ydata()]).astype(float))
               for ax in fig.axes for ln in ax.lines if len(ln.get_xdata())]
        pts = np.concatenate(pts)
        for ax in fig.axes:
            if ax.get_legend() is None:
                continue
            box = ax.get_legend().get_window_extent(renderer)
            inside = (pts[:, 0] > box.x0) & (pts[:, 0] < box.x1) & (pts[:, 1] > box.y0) & (pts[:, 1] < box.y1)
            assert not inside.any(), name
            checked += 1
    assert checked >= 2


def test_a_figure_is_never_written_through_a_link_planted_in_the_folder(tmp_path):
    """A symbolic link planted where an ensemble figure goes is neither followed nor replaced (as
    for every output, io.folders.write_atomic): the write is refused and the link's target,
    outside the folder, is not touched."""
    from matplotlib.figure import Figure

    from twofluid.ensemble.plots import _save

    outside = tmp_path / "outside.png"
    outside.write_bytes(b"the user's file")
    out = tmp_path / "study"
    out.mkdir()
    (out / "figure_x.png").symlink_to(outside)
    fig = Figure(figsize=(1, 1))
    fig.subplots().plot([0, 1])
    with pytest.raises(OSError, match="symbolic link"):
        _save(fig, out / "figure_x.png", 50)
    assert outside.read_bytes() == b"the user's file"
    _save(fig, out / "figure_y.png", 50)
    assert (out / "figure_y.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
