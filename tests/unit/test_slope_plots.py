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
