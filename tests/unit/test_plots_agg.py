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
    """Pixel for pixel what savefig writes at the figure's dpi; RGB only when every pixel is opaque."""
    fig = _figure(face_alpha)
    ours = write_png(fig, tmp_path / "ours.png")
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
