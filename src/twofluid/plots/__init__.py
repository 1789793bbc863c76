"""Figures of runs, drawn on matplotlib's Agg canvas (:mod:`twofluid.plots.agg`).

matplotlib's import is the largest single cost of a short run's figures (docs/benchmarks.md,
"Start-up and plots"). In the ``twofluid`` command's own process (:func:`command_process`,
called by ``twofluid.cli``), the first figure module imported (each imports
``twofluid.plots._matplotlib`` first) imports matplotlib's figure and Agg canvas without two
pieces of work that such a process never uses (:func:`import_matplotlib_lean`); a Python
session that imports twofluid gets matplotlib as it always is.
"""
from __future__ import annotations

import sys

__all__ = ["command_process", "import_matplotlib_lean", "is_command_process"]

_command = False  # set by command_process()


def command_process() -> None:
    """Mark this process as the ``twofluid`` command's (before any figure module is imported):
    matplotlib will be imported by :func:`import_matplotlib_lean`.

    Called by ``twofluid.cli``; not for a Python session, whose matplotlib must keep its
    docstrings and its 3D projection.
    """
    global _command
    _command = True


def is_command_process() -> bool:
    """Whether :func:`command_process` marked this process.

    >>> is_command_process()  # a Python session (here: the doctests)
    False
    """
    return _command


def import_matplotlib_lean() -> bool:
    """Import ``matplotlib.figure`` and the Agg canvas without two costs of matplotlib's import
    that the figures here never use; return True if it did, False if matplotlib's figure module
    was imported already (nothing done).

    - The property tables in the docstrings of every Artist subclass's ``set`` method, which
      matplotlib writes as each class is created (``matplotlib.artist.kwdoc``, by inspecting
      every setter of the class): about a quarter of the import's CPU. While the figure module
      is imported, ``kwdoc`` returns an empty string; it is put back after.
    - The 3D projection, whose module (``mpl_toolkits.mplot3d``, with its artists) matplotlib's
      projection registry imports to register it: refused for the length of the import
      (``matplotlib.projections`` then registers no "3d" projection, and says so in a warning,
      which is silenced), and importable again after.

    Nothing that draws reads either, so the pixels are those of a normal import
    (``tests/unit/test_plots_lean_import.py``). The cost is in this process only: the ``set``
    methods of matplotlib's artists have short docstrings, and there is no "3d" projection.

    >>> import subprocess, sys
    >>> code = "from twofluid.plots import import_matplotlib_lean as lean; print(lean(), lean())"
    >>> subprocess.run([sys.executable, "-c", code], capture_output=True, text=True).stdout.split()
    ['True', 'False']
    """
    if "matplotlib.figure" in sys.modules:
        return False
    import warnings

    import matplotlib.artist as artist

    kwdoc = getattr(artist, "kwdoc", None)
    three_d = "mpl_toolkits.mplot3d"
    refuse = three_d not in sys.modules
    try:
        if kwdoc is not None:
            artist.kwdoc = lambda _artist: ""
        if refuse:
            sys.modules[three_d] = None  # an import of it raises ImportError, which matplotlib catches
        with warnings.catch_warnings():
            warnings.filterwarnings("ignore", message="Unable to import Axes3D")
            import matplotlib.backends.backend_agg  # noqa: F401
            import matplotlib.figure  # noqa: F401
    finally:
        if kwdoc is not None:
            artist.kwdoc = kwdoc
        if refuse and three_d in sys.modules and sys.modules[three_d] is None:
            del sys.modules[three_d]
    return True
