"""The lean import of matplotlib in the ``twofluid`` command's process (twofluid.plots): the same
pixels as a normal import, matplotlib's own state put back, and only where it was asked for."""
import subprocess
import sys

import pytest

# draws a figure with what the run figures use (log axes and their mathtext labels, a colour bar,
# a legend, text, a pcolormesh, tight_layout) and writes it through twofluid.plots.agg
FIGURE = r"""
import sys
import numpy as np
import twofluid.plots as plots
if sys.argv[2] == "lean":
    plots.command_process()
from twofluid.plots.agg import new_figure, write_png
import matplotlib.artist, matplotlib.projections
fig = new_figure((5, 4), 80)
a1, a2 = fig.subplots(2, 1)
x = np.logspace(-2, 1, 50)
a1.loglog(x, x ** 1.5, label="Sa = x^1.5")
a1.legend()
a1.set_title("σ′_v/σ′_v0 and r_u")
pc = a2.pcolormesh(np.arange(6), np.arange(4), np.arange(15.0).reshape(3, 5), shading="flat")
fig.colorbar(pc, ax=a2, label="r_u [-]")
a2.annotate("water table", xy=(1, 1))
fig.tight_layout()
write_png(fig, sys.argv[1])
from matplotlib.patches import Rectangle  # a generated set() of a subclass of a subclass still sets
r = Rectangle((0, 0), 1, 1)
r.set(alpha=0.5, lw=3)
assert (r.get_alpha(), r.get_linewidth()) == (0.5, 3)
print("3d" in matplotlib.projections.get_projection_names(), len(matplotlib.artist.kwdoc(matplotlib.artist.Artist)) > 0)
import mpl_toolkits.mplot3d  # importable again after the lean import
import importlib.util  # fontTools.agl: left unexecuted by the lean import (an import statement executes it)
agl = sys.modules.get("fontTools.agl")
print(isinstance(agl, importlib.util._LazyModule), agl.toUnicode("Aacute") == "\u00c1")
"""


def _draw(path, mode):
    out = subprocess.run([sys.executable, "-c", FIGURE, str(path), mode], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert out.stderr == ""  # no warning about Axes3D escapes
    return out.stdout.split()


def test_lean_import_draws_the_same_pixels(tmp_path):
    lean = _draw(tmp_path / "lean.png", "lean")
    normal = _draw(tmp_path / "normal.png", "normal")
    assert (tmp_path / "lean.png").read_bytes() == (tmp_path / "normal.png").read_bytes()
    assert normal == ["True", "True", "False", "True"]  # a Python session: matplotlib as it is
    # the command's process: no 3D projection; kwdoc put back; fontTools.agl executed when read
    assert lean == ["False", "True", "True", "True"]


def test_command_process_only_when_marked():
    import twofluid.plots as plots

    assert not plots.is_command_process()  # importing twofluid (the test session) marks nothing


@pytest.mark.parametrize("argv", [["cases"]])
def test_cli_main_from_python_leaves_matplotlib_alone(argv, capsys):
    """``twofluid.cli.main(argv)`` called from Python is not the command's own process."""
    import twofluid.plots as plots
    from twofluid.cli import main

    assert main(argv) == 0
    assert not plots.is_command_process()
