"""Compiled kernels without numba's start-up cost: ahead-of-time extension modules, built once.

A numba-compiled function costs every process that uses it about 0.45 s of CPU to import
numba and 0.25 s to set up its typing and target registries and load the cached machine
code (``numba.njit(cache=True)``; numba 0.68 on the 2-core benchmark VM), more than the
liquefaction column's 7 000 shear sub-steps spend in the kernel itself (0.03 s). So a kernel
is compiled ahead of time instead, with ``numba.pycc``, into an ordinary extension module
kept in a cache folder; later processes import that module (about 1 ms) and do not import
numba at all. The module is named after a hash of the function's source, its signature, the
Python ABI and the NumPy version, so an edited kernel or another interpreter builds a new
one; it is written under a temporary name and renamed, so that processes building at the
same time never load half a file.

Where a module cannot be built (``numba.pycc`` missing — it is deprecated in numba — no C
toolchain to link it, no writable cache folder) the kernel is ``numba.njit(cache=True)`` as
before; without numba :func:`kernel` returns None and the caller keeps its NumPy path. The
first build costs 1–4 s of CPU per kernel on the benchmark VM (the shear kernel 3.7 s, where the
JIT's first compile took 2.7 s).

Cache folder: ``$TWOFLUID_CACHE_DIR`` if set, else the ``__pycache__`` folder beside this
module if it is writable, else ``~/.cache/twofluid``.

>>> folder = cache_dir()
>>> folder is None or folder.is_dir()
True
"""
from __future__ import annotations

import hashlib
import importlib.machinery
import importlib.util
import inspect
import os
import shutil
import sys
import tempfile
import textwrap
import warnings
from pathlib import Path
from typing import Callable

__all__ = ["kernel", "cache_dir"]

_LOADED: dict[str, Callable | None] = {}


def cache_dir() -> Path | None:
    """The folder of the ahead-of-time modules (module docstring), or None if none is writable."""
    env = os.environ.get("TWOFLUID_CACHE_DIR")
    candidates = [Path(env)] if env else [Path(__file__).parent / "__pycache__",
                                          Path.home() / ".cache" / "twofluid"]
    for folder in candidates:
        try:
            folder.mkdir(parents=True, exist_ok=True)
        except OSError:
            continue
        if os.access(folder, os.W_OK):
            return folder
    return None


def _module_name(name: str, func: Callable, signature: str) -> str:
    import numpy

    source = textwrap.dedent(inspect.getsource(func))
    key = "\n".join([source, signature, sys.implementation.cache_tag, numpy.__version__])
    return f"_twofluid_{name}_{hashlib.sha256(key.encode()).hexdigest()[:16]}"


def _import(path: Path, module: str):
    spec = importlib.util.spec_from_file_location(module, path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _build(folder: Path, module: str, name: str, func: Callable, signature: str) -> Path | None:
    """Compile ``func`` into ``folder/<module><ext>``; None if it cannot be done here."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # numba.pycc's pending deprecation
            from numba.pycc import CC
    except ImportError:
        return None
    suffix = importlib.machinery.EXTENSION_SUFFIXES[0]
    target = folder / f"{module}{suffix}"
    work = Path(tempfile.mkdtemp(prefix="twofluid-aot-"))
    try:
        cc = CC(module)
        cc.output_dir = str(work)
        cc.verbose = False
        cc.export(name, signature)(func)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            cc.compile()
        built = next(work.glob(f"{module}*{suffix}"))
        tmp = folder / f".{module}.{os.getpid()}.tmp"
        shutil.copyfile(built, tmp)
        os.replace(tmp, target)  # atomic: a reader sees the old file, none, or the whole new one
        return target
    except Exception:  # no compiler or linker, a numba that cannot do it: the JIT instead
        return None
    finally:
        shutil.rmtree(work, ignore_errors=True)


def kernel(name: str, func: Callable, signature: str, build: bool = True, jit: bool = True) -> Callable | None:
    """``func`` compiled for ``signature`` (a numba signature such as ``"i8(f8[::1], f8)"``; its
    arrays must then be passed C-contiguous with exactly these types): the cached ahead-of-time
    module, built now if ``build`` and possible, else (if ``jit``) ``numba.njit(cache=True)`` of
    ``func``, else None (also without numba). The same object for every call in a process."""
    if _LOADED.get(name) is not None:
        return _LOADED[name]
    out = None
    folder = cache_dir()
    module = _module_name(name, func, signature)
    if folder is not None:
        path = folder / f"{module}{importlib.machinery.EXTENSION_SUFFIXES[0]}"
        if not path.is_file() and build:
            path = _build(folder, module, name, func, signature) or path
        if path.is_file():
            try:
                out = getattr(_import(path, module), name)
            except (ImportError, AttributeError, OSError):
                out = None
    if out is None and jit:
        try:
            import numba
        except ImportError:
            numba = None
        if numba is not None:
            out = numba.njit(cache=True, nogil=True)(func)
    _LOADED[name] = out
    return out
