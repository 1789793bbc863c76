"""The figures of a sloping run (twofluid.plots.slope): written beside the other liquefaction
figures on a slope, not on level ground; sizes as drawn (pixels = inches × dpi)."""
import warnings

from PIL import Image

from twofluid.casefile.loader import load_case
from twofluid.runners.common import run_case


def _run(slope, out):
    c = load_case("sloping-site")
    c["site"]["slope"] = slope
    c["ground_motion"]["duration"] = 3.0
    c["shear_wave"]["free_vibration"] = 4.0
    c["time"]["end"] = 30.0
    c["output"]["times"] = [2.0, 10.0]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return run_case(c, out)


def test_sloping_run_draws_its_displacement_figures(tmp_path):
    r = _run(3.0, tmp_path / "slope")
    assert r.status == "completed"
    sizes = {"lateral_displacement.png": (715, 715), "surface_displacement.png": (1210, 528)}
    for name, size in sizes.items():
        with Image.open(tmp_path / "slope" / name) as im:
            assert im.size == size, name
    assert (tmp_path / "slope" / "profile.png").exists()


def test_level_ground_draws_none_of_them(tmp_path):
    _run(0.0, tmp_path / "level")
    assert not (tmp_path / "level" / "surface_displacement.png").exists()
    assert not (tmp_path / "level" / "lateral_displacement.png").exists()
    assert (tmp_path / "level" / "profile.png").exists()


def test_slope_figures_do_not_import_pyplot():
    import subprocess
    import sys

    code = "import sys, twofluid.plots.slope; print('matplotlib.pyplot' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def test_no_legend_hides_a_data_point(tmp_path, monkeypatch):
    """The legends of the displacement figures lie outside their data: no point of a line inside one."""
    import numpy as np

    import twofluid.plots.slope as slope

    figures = {}
    write = slope.write_png

    def keep(fig, path):
        figures[path.name] = fig
        return write(fig, path)

    monkeypatch.setattr(slope, "write_png", keep)
    _run(3.0, tmp_path / "slope")
    assert set(figures) == {"lateral_displacement.png", "surface_displacement.png"}
    for name, fig in figures.items():
        renderer = fig.canvas.get_renderer()
        pts = np.concatenate([ln.get_transform().transform(np.column_stack([ln.get_xdata(), ln.get_ydata()])
                                                           .astype(float))
                              for ax in fig.axes for ln in ax.lines if len(ln.get_xdata())])
        legends = [ax.get_legend() for ax in fig.axes if ax.get_legend() is not None]
        assert legends, name
        for leg in legends:
            box = leg.get_window_extent(renderer)
            inside = (pts[:, 0] > box.x0) & (pts[:, 0] < box.x1) & (pts[:, 1] > box.y0) & (pts[:, 1] < box.y1)
            assert not inside.any(), name
