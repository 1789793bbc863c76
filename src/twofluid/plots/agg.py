"""Figures drawn straight on matplotlib's Agg canvas and written as RGB PNGs.

Why not ``pyplot`` and ``savefig`` (measured in docs/benchmarks.md, "Start-up and plots"):

- A figure is made at the resolution it is written at, with its Agg canvas attached,
  so that a layout pass (``tight_layout``, constrained layout) and the drawing share
  one renderer: the text extents the layout measured are cached for the drawing.
  ``savefig(dpi=...)`` of a figure made at 100 dpi measures all its text twice.
- The PNG is RGB when the picture is opaque (every figure here has a white face):
  the same pixels as matplotlib's RGBA file, a quarter less data to compress, written
  at zlib level 3 instead of 6; a figure's encoding takes ~15 ms instead of ~27 ms and
  the files are no larger.
- No pyplot: no figure manager, no global list of open figures to close.
"""
from __future__ import annotations

from . import _matplotlib  # noqa: F401, I001  (first: matplotlib imported lean in the command's process)

from pathlib import Path

import matplotlib
import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.ticker import MaxNLocator
from PIL import Image, PngImagePlugin

__all__ = ["few_ticks", "new_figure", "tick_locator", "write_png"]

#: zlib level of the PNGs: level 3 compresses these line figures as well as the default 6, faster
PNG_COMPRESS_LEVEL = 3

#: matplotlib settings of the figures while they are drawn (:func:`write_png`). Text unhinted: since
#: matplotlib 3.11 every glyph of every text is loaded and rendered one by one, and FreeType's
#: hinting of DejaVu Sans (its TrueType instructions) is about a third of a text's CPU (2.4 instead
#: of 3.5 ms for a label of 27 characters at 120 dpi); the figures' CPU drops by about a tenth. At
#: these sizes the glyphs look the same, a pixel wider at most (matplotlib's own tests draw unhinted).
DRAW_RC = {"text.hinting": "no_hinting"}

#: at most this many intervals between the labelled ticks of a linear axis. matplotlib's default
#: fits up to about ten on these figures' axes, and each tick is five artists (two marks, a grid
#: line, two labels) made and a label laid out and drawn: the ticks and their labels are most of
#: a figure's CPU (docs/benchmarks.md, "Start-up and plots")
NBINS = 5


def tick_locator(nbins: int = NBINS) -> MaxNLocator:
    """matplotlib's automatic tick locator (steps of 1, 2, 2.5 or 5 × 10^k) with at most ``nbins``
    intervals.

    >>> tick_locator().tick_values(0.0, 80.0)
    array([ 0., 20., 40., 60., 80.])
    """
    return MaxNLocator(nbins=nbins, steps=[1, 2, 2.5, 5, 10])


def few_ticks(*axes, nbins: int = NBINS) -> None:
    """Give every linear x and y axis of ``axes`` :func:`tick_locator` (log and symlog axes keep
    theirs). Call it after the scales are set: setting a scale resets the locator.

    >>> ax = new_figure((6.0, 4.0), dpi=50).subplots()
    >>> _ = ax.plot([0.0, 0.71], [0.65, 1.0]); few_ticks(ax)
    >>> len(ax.get_xticks()) <= NBINS + 3, len(ax.get_yticks()) <= NBINS + 3
    (True, True)
    """
    for ax in axes:
        for axis in (ax.xaxis, ax.yaxis):
            if axis.get_scale() == "linear":
                axis.set_major_locator(tick_locator(nbins))


def new_figure(figsize: tuple[float, float], dpi: float, **kwargs) -> Figure:
    """A Figure of ``figsize`` [inch] at ``dpi`` on its own Agg canvas (``kwargs`` go to Figure).

    >>> fig = new_figure((2.0, 1.0), dpi=50)
    >>> fig.canvas.get_width_height()
    (100, 50)
    """
    fig = Figure(figsize=figsize, dpi=dpi, **kwargs)
    FigureCanvasAgg(fig)
    return fig


def write_png(fig: Figure, path: str | Path) -> Path:
    """Draw ``fig`` (made by :func:`new_figure`) at its dpi and write it to ``path`` as PNG.

    The pixels are those ``fig.savefig(path, dpi=fig.dpi)`` writes with :data:`DRAW_RC` (text
    unhinted); the file is RGB when every pixel is opaque (RGBA otherwise) and carries the
    resolution and the matplotlib version as savefig's does.

    >>> import tempfile
    >>> fig = new_figure((2.0, 1.0), dpi=50)
    >>> _ = fig.subplots().plot([0, 1], [0, 1])
    >>> with tempfile.TemporaryDirectory() as d:
    ...     with Image.open(write_png(fig, Path(d) / "a.png")) as im:
    ...         print(im.size, im.mode)
    (100, 50) RGB
    """
    path = Path(path)
    with matplotlib.rc_context(DRAW_RC):
        fig.canvas.draw()
    rgba = np.asarray(fig.canvas.buffer_rgba())
    image = Image.frombuffer("RGBA", (rgba.shape[1], rgba.shape[0]), rgba, "raw", "RGBA", 0, 1)
    if (rgba[..., 3] == 255).all():  # opaque: RGB, converted by Pillow (a strided NumPy copy costs 3x more)
        image = image.convert("RGB")
    info = PngImagePlugin.PngInfo()
    info.add_text("Software", f"Matplotlib version{matplotlib.__version__}, https://matplotlib.org/")
    image.save(path, format="png", dpi=(fig.dpi, fig.dpi), pnginfo=info, compress_level=PNG_COMPRESS_LEVEL)
    return path
