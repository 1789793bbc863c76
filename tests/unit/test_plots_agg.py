"""The figures' PNG writer (twofluid.plots.agg) against matplotlib's own ``savefig``."""
import numpy as np
import pytest
from PIL import Image

from twofluid.plots.agg import new_figure, write_png


def _figure(face_alpha=1.0):
    fig = new_figure((3.0, 2.0), dpi=80)
    ax = fig.subplots()
    x = np.linspace(0.0, 1.0, 50)
    ax.plot(x, np.sin(6 * x), label="a line")
    ax.stairs(np.cos(3 * x[:-1]), x, baseline=None)
    ax.set_xlabel("x [m]")
    ax.legend()
    fig.colorbar(ax.pcolormesh(np.outer(x[:5], x[:4])), ax=ax)
    fig.patch.set_alpha(face_alpha)
    fig.tight_layout()
    return fig


@pytest.mark.parametrize("face_alpha, mode", [(1.0, "RGB"), (0.0, "RGBA")])
def test_same_pixels_as_savefig(tmp_path, face_alpha, mode):
    """Pixel for pixel what savefig writes at the figure's dpi with the figures' settings (text
    unhinted); RGB only when every pixel is opaque."""
    import matplotlib

    from twofluid.plots.agg import DRAW_RC

    fig = _figure(face_alpha)
    ours = write_png(fig, tmp_path / "ours.png")
    with matplotlib.rc_context(DRAW_RC):
        fig.savefig(tmp_path / "savefig.png", dpi=fig.dpi)
    with Image.open(ours) as a, Image.open(tmp_path / "savefig.png") as b:
        assert a.mode == mode and b.mode == "RGBA"
        assert a.size == b.size == (240, 160)
        assert a.info["dpi"] == pytest.approx(b.info["dpi"])
        assert a.info["Software"] == b.info["Software"]
        np.testing.assert_array_equal(np.asarray(a.convert("RGBA")), np.asarray(b))
        assert (np.asarray(b)[..., 3] == 255).all() == (mode == "RGB")


def test_a_second_write_draws_again(tmp_path):
    """A figure changed after it was written is drawn anew, not taken from the last picture."""
    fig = _figure()
    with Image.open(write_png(fig, tmp_path / "a.png")) as im:
        first = np.asarray(im)
    fig.axes[0].set_title("a title")
    with Image.open(write_png(fig, tmp_path / "b.png")) as im:
        assert (np.asarray(im) != first).any()


def test_plot_modules_do_not_import_pyplot():
    """The figures of runs need neither pyplot nor its backend machinery (their import is the floor)."""
    import subprocess
    import sys

    code = ("import sys, twofluid.plots.profiles, twofluid.plots.liquefaction, twofluid.plots.fields; "
            "print('matplotlib.pyplot' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def test_1d_figures_keep_their_size_and_resolution(tmp_path):
    """porosity.png and pressure.png at 120 dpi: 6.2 × 6 in and 10 × 5.5 in, as before the Agg canvas."""
    from twofluid.plots.profiles import history_plot, profile_plots

    y = np.linspace(0.005, 0.995, 100)
    profiles = {t: {"y_m": y, "porosity": 0.5 + 0.1 * t * y, "P_Pa": 9.81e3 * (1 - y), "Ps_Pa": 50 * t * (1 - y)}
                for t in (0.0, 1.0, 2.0)}
    paths = profile_plots(profiles, tmp_path, "a title")
    t = np.linspace(0.0, 2.0, 30)
    paths.append(history_plot(t, {"bed surface": 0.5 + 0.1 * t}, tmp_path / "heights.png", "a title",
                              marks={"t1": 1.0}, levels={"theory": 0.7}))
    sizes = {}
    for p in paths:
        with Image.open(p) as im:
            sizes[p.name] = (im.size, im.mode, tuple(round(d) for d in im.info["dpi"]))
    assert sizes == {"porosity.png": ((744, 720), "RGB", (120, 120)),
                     "pressure.png": ((1200, 660), "RGB", (120, 120)),
                     "heights.png": ((780, 540), "RGB", (120, 120))}


@pytest.mark.parametrize("xs, ys, invert", [((0.0, 80.0), (0.65, 0.71), False),
                                            ((-2.5e6, 3.0e6), (10.0, 0.0), True),
                                            ((1e-5, 4e-5), (-0.002, 0.001), False)])
def test_drawn_ticks_are_labelled_inside_the_axes_span_and_clear_of_the_axis_labels(xs, ys, invert):
    """drawn_ticks: every label at a tick inside the limits, the axis labels beyond the tick labels
    (not on them), whatever the magnitudes or the direction of the axis; no matplotlib ticks."""
    import matplotlib

    from twofluid.plots.agg import DRAW_RC, drawn_ticks

    fig = new_figure((5.0, 3.5), dpi=80)
    ax = fig.subplots()
    ax.plot(xs, ys)
    if invert:
        ax.invert_yaxis()
    ax.set_xlabel("an x label [unit]")
    ax.set_ylabel("a y label [unit]")
    fig.subplots_adjust(left=0.22, right=0.95, bottom=0.2, top=0.95)
    drawn_ticks(ax)
    with matplotlib.rc_context(DRAW_RC):
        fig.canvas.draw()
    r = fig.canvas.get_renderer()
    labels = [t for t in ax.texts]
    assert len(ax.get_xticks()) == 0 and len(ax.get_yticks()) == 0 and 6 <= len(labels) <= 14
    box = ax.get_window_extent(r)
    xl, yl = ax.xaxis.label.get_window_extent(r), ax.yaxis.label.get_window_extent(r)
    below = [t.get_window_extent(r) for t in labels if t.get_va() == "top"]
    left = [t.get_window_extent(r) for t in labels if t.get_ha() == "right"]
    assert below and left
    assert all(b.x1 >= box.x0 - 1 and b.x0 <= box.x1 + 1 and b.y1 < box.y0 for b in below)
    assert all(b.y1 >= box.y0 - 1 and b.y0 <= box.y1 + 1 and b.x1 < box.x0 for b in left)
    assert xl.y1 < min(b.y0 for b in below) and yl.x1 < min(b.x0 for b in left)
    assert all(t.get_text() and "e" not in t.get_text() for t in labels)  # plain numbers, no offset


def test_drawn_ticks_of_a_colour_bar_on_its_right_clear_of_its_label():
    import matplotlib
    from matplotlib import colormaps
    from matplotlib.cm import ScalarMappable
    from matplotlib.colors import Normalize

    from twofluid.plots.agg import DRAW_RC, drawn_ticks

    fig = new_figure((4.0, 3.0), dpi=80)
    bar = fig.colorbar(ScalarMappable(Normalize(0.0, 80.0), colormaps["viridis"]),
                       cax=fig.add_axes((0.7, 0.1, 0.05, 0.8)), label="time t [s]")
    drawn_ticks(bar.ax, x=False, grid=False, yside="right")
    with matplotlib.rc_context(DRAW_RC):
        fig.canvas.draw()
    r = fig.canvas.get_renderer()
    box, label = bar.ax.get_window_extent(r), bar.ax.yaxis.label.get_window_extent(r)
    texts = sorted(bar.ax.texts, key=lambda t: t.get_position()[1])
    assert [t.get_text() for t in texts] == ["0", "20", "40", "60", "80"]
    assert all(box.x1 < t.get_window_extent(r).x0 < label.x0 for t in texts)
    assert len(bar.ax.get_yticks()) == 0


def test_lean_axes_draw_the_same_pixels_as_matplotlibs(tmp_path):
    """LeanAxes make no tick until one is drawn; the picture is matplotlib's Axes' own: drawn ticks,
    matplotlib's log ticks, an inverted shared axis, a legend, a title, a grid."""
    from twofluid.plots.agg import drawn_ticks, lean_subplots

    def draw(lean, path):
        fig = new_figure((4.0, 4.0), dpi=60)
        axes = lean_subplots(fig, 3, 1, sharex=True) if lean else fig.subplots(3, 1, sharex=True)
        x = np.linspace(0.0, 10.0, 80)
        axes[0].plot(x, np.sin(x), label="sin")
        axes[0].legend(loc="upper left", bbox_to_anchor=(1.0, 1.0))
        axes[0].set_title("a title", y=1.0)
        axes[1].plot(x, 1.0 + x ** 2)
        axes[1].set_yscale("log")
        axes[1].grid(alpha=0.3)
        axes[2].plot(x, -x)
        axes[2].invert_yaxis()
        axes[2].set_xlabel("x [m]")
        fig.subplots_adjust(left=0.2, right=0.75)
        drawn_ticks(axes[0], xlabels=False)
        drawn_ticks(axes[1], x=False, y=False)
        drawn_ticks(axes[2])
        with Image.open(write_png(fig, path)) as im:
            return np.asarray(im)

    np.testing.assert_array_equal(draw(True, tmp_path / "lean.png"), draw(False, tmp_path / "axes.png"))


def test_log_and_symlog_axes_get_drawn_ticks():
    from twofluid.plots.agg import drawn_ticks

    fig = new_figure((4.0, 3.0), dpi=50)
    ax = fig.subplots()
    ax.plot([0.0, 3600.0], [1e-4, 0.03])
    ax.set_xscale("symlog", linthresh=11.0)
    ax.set_yscale("log")
    ax.set_xlim(0.0, 3600.0)
    drawn_ticks(ax)
    labels = [t.get_text() for t in ax.texts]
    assert labels == ["0", "5", "10", "100", "1000", "0.0001", "0.001", "0.01"]
    assert len(ax.get_xticks()) == 0 and len(ax.get_yticks()) == 0
