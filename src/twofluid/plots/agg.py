"""Figures drawn straight on matplotlib's Agg canvas and written as RGB PNGs.

Why not ``pyplot`` and ``savefig`` (measured in docs/benchmarks.md, "Start-up and plots"):

- A figure is made at the resolution it is written at, with its Agg canvas attached,
  so that a layout pass (``tight_layout``, constrained layout) and the drawing share
  one renderer: the text extents the layout measured are cached for the drawing.
  ``savefig(dpi=...)`` of a figure made at 100 dpi measures all its text twice.
- The PNG is RGB when the picture is opaque (every figure here has a white face):
  the same pixels as matplotlib's RGBA file, a quarter less data to compress, written by
  Pillow at zlib level 3 instead of 6; a figure's encoding takes ~15 ms instead of ~27 ms
  and the files are no larger.
- No pyplot: no figure manager, no global list of open figures to close.
"""
from __future__ import annotations

from . import _matplotlib  # noqa: F401, I001  (first: matplotlib imported lean in the command's process)

import io
import math
from contextlib import contextmanager
from pathlib import Path

import matplotlib
import numpy as np
from matplotlib.artist import Artist
from matplotlib.axes import Axes
from matplotlib.axis import XAxis, YAxis
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.ticker import MaxNLocator
from PIL import Image, PngImagePlugin

from ..io import folders

__all__ = ["LeanAxes", "drawn_ticks", "lean_subplots", "log_ticks", "new_figure", "symlog_ticks", "tick_locator", "write_png"]

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


class _TicksWhenDrawn:
    """The ``majorTicks`` or ``minorTicks`` of a :class:`LeanAxes`' axis: an empty list at first, where
    matplotlib's axis makes one tick at once (``matplotlib.axis._LazyTickList``) as the axes is made
    and cleared, whether any is drawn or not. matplotlib makes the ticks it draws when it draws them
    (``Axis.get_major_ticks``), with the properties set on the axis meanwhile."""

    def __init__(self, name: str):
        self.name = name

    def __get__(self, instance, owner):
        if instance is None:
            return self
        ticks: list = []
        setattr(instance, self.name, ticks)  # the instance's own list from now on, as matplotlib's
        return ticks


def _set(self, **kwargs):
    """matplotlib's ``Artist.set``. A subclass of an artist that defines its own ``set`` is made without
    the signature and docstring matplotlib otherwise builds for it (tens of ms for an Axes)."""
    return Artist.set(self, **kwargs)


def _lean_axis(cls):
    def _get_tick(self, major: bool):
        """matplotlib's new tick, clipped to the axes' patch as the axis clips the ticks it has when
        it is cleared (``Axis.reset_ticks``), which a lean axis does not have yet."""
        tick = cls._get_tick(self, major)
        tick.set_clip_path(self.axes.patch)
        return tick

    return type(f"Lean{cls.__name__}", (cls,), {"majorTicks": _TicksWhenDrawn("majorTicks"),
                                                 "minorTicks": _TicksWhenDrawn("minorTicks"), "set": _set,
                                                 "_get_tick": _get_tick})


class LeanAxes(Axes):
    """matplotlib's Axes whose axes make no tick until one is drawn. Every tick matplotlib makes is five
    artists (two marks, a grid line, two labels): an Axes makes four of them as it is made, which an
    axis whose ticks are drawn by :func:`drawn_ticks` never draws, about 1.5 ms a tick. The first of
    them also places the spines (their transform): :meth:`clear` places them instead. Same pixels.

    >>> fig = new_figure((2.0, 1.0), dpi=50)
    >>> ax = fig.subplots(subplot_kw={"axes_class": LeanAxes})
    >>> len(ax.xaxis.majorTicks), len(ax.xaxis.get_major_ticks(3))
    (0, 3)
    """

    set = _set

    def clear(self):
        super().clear()
        for spine in self.spines.values():  # placed as matplotlib's first tick (which places it) would
            spine.set_position(spine.get_position())

    def _init_axis(self):
        self.xaxis = _LeanXAxis(self, clear=False)
        self.spines.bottom.register_axis(self.xaxis)
        self.spines.top.register_axis(self.xaxis)
        self.yaxis = _LeanYAxis(self, clear=False)
        self.spines.left.register_axis(self.yaxis)
        self.spines.right.register_axis(self.yaxis)


def new_figure(figsize: tuple[float, float], dpi: float, **kwargs) -> Figure:
    """A Figure of ``figsize`` [inch] at ``dpi`` on its own Agg canvas (``kwargs`` go to Figure).

    >>> fig = new_figure((2.0, 1.0), dpi=50)
    >>> fig.canvas.get_width_height()
    (100, 50)
    """
    fig = Figure(figsize=figsize, dpi=dpi, **kwargs)
    FigureCanvasAgg(fig)
    return fig


def lean_subplots(fig: Figure, *args, **kwargs):
    """``fig.subplots(*args, **kwargs)`` of :class:`LeanAxes`.

    >>> axes = lean_subplots(new_figure((2.0, 2.0), dpi=50), 2, 1, sharex=True)
    >>> [type(a).__name__ for a in axes], len(axes[0].yaxis.minorTicks)
    (['LeanAxes', 'LeanAxes'], 0)
    """
    return fig.subplots(*args, subplot_kw={"axes_class": LeanAxes, **kwargs.pop("subplot_kw", {})}, **kwargs)


@contextmanager
def _fonts_found_once():
    """While the settings cannot change (a figure being drawn), each font matplotlib looks for is
    looked up once. ``FontManager.findfont`` reads eleven settings to key its cache at every call,
    and a figure's drawing calls it for every text, twice: about a tenth of the drawing's CPU. The
    same fonts are found (the lookup is matplotlib's, with the settings of the drawing)."""
    from matplotlib import font_manager

    manager = font_manager.fontManager
    find = manager.findfont
    found = {}

    def findfont(prop, fontext="ttf", directory=None, fallback_to_default=True, rebuild_if_missing=True):
        key = (prop, fontext, directory, fallback_to_default, rebuild_if_missing)
        try:
            return found[key]
        except KeyError:
            found[key] = path = find(prop, fontext, directory, fallback_to_default, rebuild_if_missing)
            return path
        except TypeError:  # not hashable
            return find(prop, fontext, directory, fallback_to_default, rebuild_if_missing)

    manager.findfont = findfont
    try:
        yield
    finally:
        del manager.findfont


def write_png(fig: Figure, path: str | Path) -> Path:
    """Draw ``fig`` (made by :func:`new_figure`) at its dpi and write it to ``path`` as PNG.

    The pixels are those ``fig.savefig(path, dpi=fig.dpi)`` writes with :data:`DRAW_RC` (text
    unhinted); the file is RGB when every pixel is opaque (RGBA otherwise) and carries the
    resolution and the matplotlib version as savefig's does. Written whole or not at all, never
    through a symbolic link, and recorded in its run folder's list of outputs
    (:func:`twofluid.io.folders.write_atomic`).

    >>> import tempfile
    >>> from PIL import Image
    >>> fig = new_figure((2.0, 1.0), dpi=50)
    >>> _ = fig.subplots().plot([0, 1], [0, 1])
    >>> with tempfile.TemporaryDirectory() as d:
    ...     with Image.open(write_png(fig, Path(d) / "a.png")) as im:
    ...         print(im.size, im.mode)
    (100, 50) RGB
    """
    path = Path(path)
    with matplotlib.rc_context(DRAW_RC), _fonts_found_once():
        fig.canvas.draw()
    rgba = np.asarray(fig.canvas.buffer_rgba())
    image = Image.frombuffer("RGBA", (rgba.shape[1], rgba.shape[0]), rgba, "raw", "RGBA", 0, 1)
    if (rgba[..., 3] == 255).all():  # opaque: RGB, converted by Pillow (a strided NumPy copy costs 3x more)
        image = image.convert("RGB")
    info = PngImagePlugin.PngInfo()
    info.add_text("Software", f"Matplotlib version{matplotlib.__version__}, https://matplotlib.org/")
    buf = io.BytesIO()  # written whole and never through a symbolic link, recorded in the run's folder
    image.save(buf, format="png", dpi=(fig.dpi, fig.dpi), pnginfo=info, compress_level=PNG_COMPRESS_LEVEL)
    folders.write_atomic(path, buf.getvalue())  # (looked up at the call: tests stand in for it)
    return path


def symlog_ticks(axis, lo: float, hi: float, min_gap: float = 0.06) -> list[float]:
    """Tick locations of a symlog ``axis`` (matplotlib's, of an axes) from ``lo`` ≥ 0 to ``hi``: linear
    ones in the linear part [0, linthresh] (at most 3 intervals), then 1 × 10^k beyond it (and 2 and
    5 × 10^k where the log part spans less than two decades); a location closer than ``min_gap``
    (a fraction of the axis' length) to the one before it is left out.

    >>> fig = new_figure((4.0, 1.0), dpi=50)
    >>> ax = fig.subplots(); ax.set_xscale("symlog", linthresh=11.0); _ = ax.set_xlim(0.0, 3600.0)
    >>> symlog_ticks(ax.xaxis, 0.0, 3600.0)
    [0.0, 5.0, 10.0, 100.0, 1000.0]
    """
    thresh = float(axis.get_transform().linthresh)
    scale = axis.get_transform()
    locs = [float(v) for v in tick_locator(3).tick_values(max(lo, 0.0), min(hi, thresh)) if lo <= v <= thresh]
    if hi > thresh:
        subs = (1.0,) if hi / thresh >= 100.0 else (1.0, 2.0, 5.0)
        k0, k1 = math.floor(math.log10(thresh)), math.ceil(math.log10(hi))
        locs += [m * 10.0 ** k for k in range(k0, k1 + 1) for m in subs if thresh < m * 10.0 ** k <= hi]
    span = float(scale.transform(hi) - scale.transform(lo)) or 1.0
    kept: list[float] = []
    for v in locs:
        if not kept or (scale.transform(v) - scale.transform(kept[-1])) / span >= min_gap:
            kept.append(v)
    return kept


def log_ticks(lo: float, hi: float) -> list[float]:
    """Tick locations of a log axis from ``lo`` to ``hi``: 1 × 10^k, and 2 and 5 × 10^k where it
    spans less than two decades.

    >>> log_ticks(0.05, 2.0), log_ticks(2e-5, 0.04)
    ([0.05, 0.1, 0.2, 0.5, 1.0, 2.0], [0.0001, 0.001, 0.01])
    """
    lo = max(lo, 1e-300)
    subs = (1.0,) if hi / lo >= 100.0 else (1.0, 2.0, 5.0)
    k0, k1 = math.floor(math.log10(lo)), math.ceil(math.log10(hi))
    return [float(f"{m * 10.0 ** k:.12g}") for k in range(k0, k1 + 1) for m in subs
            if lo * (1.0 - 1e-9) <= m * 10.0 ** k <= hi * (1.0 + 1e-9)]


class _PlainFormatter:
    """Labels as plain numbers (up to four significant digits, matplotlib's minus sign)."""

    def format_ticks(self, values):
        return [f"{v:.4g}".replace("-", "\N{MINUS SIGN}") for v in values]


_LeanXAxis, _LeanYAxis = _lean_axis(XAxis), _lean_axis(YAxis)


def _tick_labels(locs, lo: float, hi: float, formatter) -> list[str]:
    """Labels of the ticks at ``locs`` of an axis from ``lo`` to ``hi``: ``formatter`` (a matplotlib
    Formatter), or matplotlib's default one without an offset or a power of ten (0.25, 12000)."""
    from matplotlib.ticker import ScalarFormatter

    if isinstance(formatter, _PlainFormatter):
        return formatter.format_ticks(list(locs))
    if formatter is None:
        formatter = ScalarFormatter(useOffset=False)
        formatter.set_scientific(False)
    formatter.create_dummy_axis()
    formatter.axis.set_view_interval(lo, hi)
    formatter.axis.set_data_interval(lo, hi)
    return formatter.format_ticks(list(locs))


def drawn_ticks(ax, x: bool = True, y: bool = True, xlabels: bool = True, ylabels: bool = True,
                xformatter=None, yformatter=None, grid: bool = True, nbins: int = NBINS,
                yside: str = "left") -> None:
    """Ticks of the linear (or log, symlog: :func:`log_ticks`, :func:`symlog_ticks`, plain labels) x and y axes of ``ax`` as matplotlib draws them — marks 3.5 pt long
    outside, labels 3.5 pt beyond, a light grid (``grid``), the axis label below or beside the tick
    labels — but drawn as three artists per axis (a line collection of the marks, one of the grid
    lines, one text per label) instead of matplotlib's five artists per tick, made and laid out at
    every drawing. Locations by :func:`tick_locator`; labels by the formatters (None: matplotlib's
    default, without an offset). Call it last: after the data, the limits and the margins
    (``subplots_adjust``) are final. ``xlabels``/``ylabels`` False: marks only (an axis shared
    with a labelled one). ``yside="right"``: the y ticks on the right (a colour bar's, once
    ``fig.colorbar`` has made it: it sets its locator when it is made, not when it is drawn).

    On a figure of one axes this halves the CPU of its ticks: about a third of the figure's
    (docs/benchmarks.md, "Start-up and plots").

    >>> fig = new_figure((4.0, 3.0), dpi=50)
    >>> ax = fig.subplots(); _ = ax.plot([0.0, 80.0], [0.65, 0.71]); drawn_ticks(ax)
    >>> sorted(t.get_text() for t in ax.texts)
    ['0', '0.66', '0.68', '0.70', '20', '40', '60', '80']
    >>> len(ax.get_xticks()), len(ax.collections)  # no matplotlib ticks; marks and grid of each axis
    (0, 4)
    """
    import matplotlib as mpl
    from matplotlib.collections import LineCollection
    from matplotlib.ticker import NullLocator
    from matplotlib.transforms import ScaledTranslation

    fig = ax.figure
    rc = mpl.rcParams
    renderer = fig.canvas.get_renderer()
    box = ax.get_position()
    w_in, h_in = fig.get_size_inches()
    for which, on, labelled, formatter in (("x", x, xlabels, xformatter), ("y", y, ylabels, yformatter)):
        axis = ax.xaxis if which == "x" else ax.yaxis
        if not on or axis.get_scale() not in ("linear", "symlog", "log"):
            continue
        lo, hi = sorted(ax.get_xlim() if which == "x" else ax.get_ylim())
        slack = 1e-9 * max(hi - lo, 1e-300)
        if axis.get_scale() == "symlog":
            locs = symlog_ticks(axis, lo, hi)
            formatter = formatter or _PlainFormatter()
        elif axis.get_scale() == "log":
            locs = log_ticks(lo, hi)
            formatter = formatter or _PlainFormatter()
        else:
            locs = [float(v) for v in tick_locator(nbins).tick_values(lo, hi) if lo - slack <= v <= hi + slack]
        axis.set_major_locator(NullLocator())
        axis.set_minor_locator(NullLocator())
        size, width, pad = (rc[f"{which}tick.major.{k}"] for k in ("size", "width", "pad"))
        color = rc[f"{which}tick.color"]
        if which == "x":  # the mark's length as a fraction of the axes' height (points -> inches -> fraction)
            trans, frac = ax.get_xaxis_transform(), size / 72.0 / (box.height * h_in)
            marks = [[(v, 0.0), (v, -frac)] for v in locs]
            lines = [[(v, 0.0), (v, 1.0)] for v in locs]
            shift = ScaledTranslation(0.0, -(size + pad) / 72.0, fig.dpi_scale_trans)
            place = dict(ha="center", va="top")
        else:
            trans, frac = ax.get_yaxis_transform(), size / 72.0 / (box.width * w_in)
            side = 1.0 if yside == "right" else -1.0
            edge = 1.0 if yside == "right" else 0.0
            marks = [[(edge, v), (edge + side * frac, v)] for v in locs]
            lines = [[(0.0, v), (1.0, v)] for v in locs]
            shift = ScaledTranslation(side * (size + pad) / 72.0, 0.0, fig.dpi_scale_trans)
            place = dict(ha="left" if yside == "right" else "right", va="center_baseline")
        ax.add_collection(LineCollection(marks, transform=trans, colors=color, linewidths=width, clip_on=False,
                                         zorder=2.5), autolim=False)
        if grid:
            ax.add_collection(LineCollection(lines, transform=trans, colors=rc["grid.color"],
                                             linewidths=rc["grid.linewidth"], alpha=0.3, zorder=1.5),
                              autolim=False)
        if not labelled:
            continue
        extent = 0.0  # the labels' height (x) or width (y) [points]: where the axis label goes
        for v, text in zip(locs, _tick_labels(locs, lo, hi, formatter)):
            xy = (v, 0.0) if which == "x" else (1.0 if yside == "right" else 0.0, v)
            label = ax.text(*xy, text, transform=trans + shift, fontsize=rc[f"{which}tick.labelsize"],
                            color=rc[f"{which}tick.labelcolor"] if rc[f"{which}tick.labelcolor"] != "inherit"
                            else color, clip_on=False, **place)
            bb = label.get_window_extent(renderer)  # measured once: the drawing reuses the measure
            extent = max(extent, (bb.height if which == "x" else bb.width) * 72.0 / fig.dpi)
        axis.labelpad = rc["axes.labelpad"] + size + pad + extent
