"""Compiled kernels without numba's start-up cost: ahead-of-time extension modules, built once.

A numba-compiled function costs every process that uses it about 0.45 s of CPU to import
numba and 0.25 s to set up its typing and target registries and load the cached machine
code (``numba.njit(cache=True)``; numba 0.68 on the 2-core benchmark VM), more than the
liquefaction column's 7 000 shear sub-steps spend in the kernel itself (0.03 s). So a kernel
is compiled ahead of time instead, with ``numba.pycc``, into an ordinary extension module
kept in a cache folder; later processes import that module (about 1 ms) and do not import
numba at all. Kernels used together are built into one module (:func:`group`: one build,
one import). A module is named after a hash of the source files of its functions, their
signatures, the Python ABI and the NumPy version, so an edited kernel module or another
interpreter builds a new one; it is written under a temporary name and renamed, so that
processes building at the same time never load half a file.

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

import contextlib
import hashlib
import importlib.machinery
import importlib.util
import os
import sys
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


def _module_name(name: str, func: Callable, signature: str, helpers: tuple = ()) -> str:
    return _group_name(name, {name: (func, signature)}, helpers)


def _group_name(group: str, exports: dict, helpers: tuple = ()) -> str:
    """The module of a group of kernels: named after a hash of the source files of the kernels and
    the helpers they call, their names and signatures, the Python ABI and the NumPy version."""
    import numpy

    digest = hashlib.sha256()
    funcs = [f for f, _sig in exports.values()] + list(helpers)
    for file in sorted({f.__code__.co_filename for f in funcs}):
        # the whole source file: reading it costs microseconds where inspect.getsource of each
        # function tokenizes the module (~40 ms for the project's kernels); any edit rebuilds
        digest.update(Path(file).read_bytes())
    key = [f"{f.__qualname__}:{sig}" for f, sig in exports.values()] + [f.__qualname__ for f in helpers]
    digest.update("\n".join(key + [sys.implementation.cache_tag, numpy.__version__]).encode())
    return f"_twofluid_{group}_{digest.hexdigest()[:16]}"


def _import(path: Path, module: str):
    spec = importlib.util.spec_from_file_location(module, path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _build(folder: Path, module: str, exports: dict, helpers: tuple = ()) -> Path | None:
    """Compile ``exports`` {name: (func, signature)} into ``folder/<module><ext>``, the ``helpers``
    they call compiled with them; None if it cannot be done here."""
    import shutil  # here, not at the top: only a build needs them
    import tempfile
    import warnings

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
        for name, (func, signature) in exports.items():
            cc.export(name, signature)(func)
        with _compiled_helpers(helpers), warnings.catch_warnings():
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


@contextlib.contextmanager
def _compiled_helpers(helpers: tuple):
    """The ``helpers`` replaced in their modules by their ``numba.njit`` versions while a kernel that
    calls them compiles (a compiled function can call only compiled functions); restored after."""
    if not helpers:
        yield
        return
    import numba

    saved = [(f.__globals__, f.__name__, f) for f in helpers]
    try:
        for g, name, f in saved:
            g[name] = numba.njit(nogil=True)(f)
        yield
    finally:
        for g, name, f in saved:
            g[name] = f


def kernel(name: str, func: Callable, signature: str, build: bool = True, jit: bool = True) -> Callable | None:
    """``func`` compiled for ``signature`` (a numba signature such as ``"i8(f8[::1], f8)"``; its
    arrays must then be passed C-contiguous with exactly these types): the cached ahead-of-time
    module, built now if ``build`` and possible, else (if ``jit``) ``numba.njit(cache=True)`` of
    ``func``, else None (also without numba). The same object for every call in a process."""
    out = group(name, {name: (func, signature)}, build=build, jit=jit)
    return None if out is None else out[name]


def group(group_name: str, exports: dict, helpers: tuple = (), build: bool = True,
          jit: bool = True) -> dict | None:
    """Several kernels in one ahead-of-time module (one build, one import): ``exports`` {name:
    (func, signature)}, ``helpers`` the plain functions they call (compiled with them). Returns
    {name: compiled function} as :func:`kernel` does for one, or None."""
    if group_name in _LOADED:
        return _LOADED[group_name]
    out = None
    folder = cache_dir()
    module = _group_name(group_name, exports, helpers)
    if folder is not None:
        path = folder / f"{module}{importlib.machinery.EXTENSION_SUFFIXES[0]}"
        if not path.is_file() and build:
            path = _build(folder, module, exports, helpers) or path
        if path.is_file():
            try:
                mod = _import(path, module)
                out = {name: getattr(mod, name) for name in exports}
            except (ImportError, AttributeError, OSError):
                out = None
    if out is None and jit:
        try:
            import numba
        except ImportError:
            numba = None
        if numba is not None:
            try:  # numba's first compile or cache load imports all of scipy.linalg (~0.1 s) only to
                # find its cython_blas, which these kernels do not use: that module is loaded alone
                from .scipy_kernels import _extension

                _extension("scipy.linalg", "cython_blas")
            except (ImportError, OSError):
                pass
            njit = numba.njit(cache=True, nogil=True)
            for f in helpers:  # the module's own name for each helper now calls the compiled one
                f.__globals__[f.__name__] = njit(f)
            out = {name: njit(func) for name, (func, _sig) in exports.items()}
    if out is not None or not jit:
        _LOADED[group_name] = out
    return out
