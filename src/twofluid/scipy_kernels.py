"""SciPy's compiled kernels without the import cost of their packages.

``import scipy.linalg`` costs ~0.35 s of CPU and ``import scipy.optimize`` ~0.45 s
(SciPy 1.17 on the 2-core benchmark VM; numpy itself ~0.12 s), more than a short 1D
run spends on its time steps. The 1D models need one LAPACK routine (``dgbsv``) and
the build one scalar root (``brentq``); both live in SciPy extension modules that
import only NumPy. This module loads those extension modules from their files,
without running ``scipy/linalg/__init__.py`` or ``scipy/optimize/__init__.py``,
and registers them under their own names (a later ``import scipy.linalg`` reuses
them). If that is not possible (another SciPy layout, another signature) it falls
back to the public functions, so the results never depend on the path taken.

>>> import numpy as np
>>> ab = np.array([[0.0, 0.0, 0.0], [0.0, 1.0, 1.0], [2.0, 2.0, 2.0], [1.0, 1.0, 0.0]])  # kl = ku = 1
>>> dgbsv(1, 1, ab, np.array([3.0, 4.0, 3.0]))[2].round(12).tolist()  # [[2,1,0],[1,2,1],[0,1,2]] x = b
[1.0, 1.0, 1.0]
>>> round(brentq(lambda x: x * x - 2.0, 0.0, 2.0, xtol=1e-14, rtol=1e-13), 12)
1.414213562373
"""
from __future__ import annotations

import importlib
import importlib.machinery
import importlib.util
import sys
from pathlib import Path

__all__ = ["dgbsv", "brentq"]


def _extension(package: str, name: str):
    """The compiled module ``package.name`` (e.g. ``scipy.linalg._flapack``), loaded from its file
    if ``package`` has not been imported yet."""
    full = f"{package}.{name}"
    if full in sys.modules:
        return sys.modules[full]
    if package not in sys.modules:
        top = importlib.util.find_spec("scipy")  # where SciPy is, without running its __init__ (~10 ms)
        if top is None or not top.submodule_search_locations:
            return importlib.import_module(full)
        folder = Path(top.submodule_search_locations[0]).joinpath(*package.split(".")[1:])
        for suffix in importlib.machinery.EXTENSION_SUFFIXES:
            path = folder / (name + suffix)
            if path.is_file():
                spec = importlib.util.spec_from_file_location(full, path)
                mod = importlib.util.module_from_spec(spec)
                spec.loader.exec_module(mod)
                sys.modules[full] = mod
                return mod
    return importlib.import_module(full)


def _dgbsv():
    try:
        return _extension("scipy.linalg", "_flapack").dgbsv
    except (ImportError, AttributeError, OSError):
        from scipy.linalg.lapack import dgbsv

        return dgbsv


_DGBSV = None


def dgbsv(kl, ku, ab, b, overwrite_ab=0, overwrite_b=0):
    """LAPACK ``dgbsv`` (band LU with partial pivoting and solve), as ``scipy.linalg.lapack.dgbsv``:
    returns (lub, piv, x, info)."""
    global _DGBSV
    if _DGBSV is None:
        _DGBSV = _dgbsv()
    return _DGBSV(kl, ku, ab, b, overwrite_ab=overwrite_ab, overwrite_b=overwrite_b)


def brentq(f, a: float, b: float, xtol: float, rtol: float, maxiter: int = 100) -> float:
    """Root of ``f`` in [a, b] (a sign change) by Brent's method, as ``scipy.optimize.brentq``."""
    try:
        zeros = _extension("scipy.optimize", "_zeros")
        return float(zeros._brentq(f, float(a), float(b), xtol, rtol, maxiter, (), False, True))
    except (ImportError, AttributeError, OSError, TypeError):
        from scipy.optimize import brentq as public

        return float(public(f, a, b, xtol=xtol, rtol=rtol, maxiter=maxiter))
