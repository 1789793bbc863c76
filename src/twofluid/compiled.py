"""Compiled kernels without numba's start-up cost: ahead-of-time extension modules, built once.

Every hot loop of the 1D models is written once, in numba-compatible Python (no NumPy twin), and
compiled here. A numba-compiled function costs every process that uses it about 0.45 s of CPU to
import numba and 0.25 s to set up its typing and target registries and load the cached machine
code (``numba.njit(cache=True)``; numba 0.68 on the 2-core benchmark VM), more than the
liquefaction column's 7 000 shear sub-steps spend in the kernel itself (0.03 s). So a kernel
is compiled ahead of time instead, with ``numba.pycc``, into an ordinary extension module
kept in a cache folder; later processes import that module (about 1 ms) and do not import
numba at all. Kernels used together are built into one module (:func:`group`: one build,
one import). A module is named after a hash of the source files of its functions, their
signatures, the Python ABI and the NumPy version, so an edited kernel module or another
interpreter builds a new one; it is written under a temporary name and renamed, so that
processes building at the same time never load half a file.

The build is done once per installation and cache folder: ``twofluid build-kernels``
(:func:`build_all`, the README's install command runs it) builds every group, its groups in
parallel over the CPUs; a run that needs a group not built yet builds it and says so in one line
on standard error. The figures of the build are in ``docs/benchmarks.md``.

Where a module cannot be built (``numba.pycc`` missing — it is deprecated in numba — no C
toolchain to link it, no writable cache folder) the kernel is ``numba.njit(cache=True)``.
With ``TWOFLUID_DISABLE_JIT=1`` (or numba's own ``NUMBA_DISABLE_JIT=1``) every kernel is its
plain Python function, un-compiled: the same source, for a debugger or print statements, some
hundred times slower; it is a debugging aid, not a fallback.

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

__all__ = ["kernel", "group", "cache_dir", "jit_disabled", "build_all"]

_LOADED: dict[str, Callable | None] = {}
_ANNOUNCED = False

#: every group of the project's kernels: (group name, "module:getter"); the getter builds the group
#: (``twofluid build-kernels`` calls each). A new group is added here.
GROUPS = (
    ("band_lu", "twofluid.fem.banded:band_lu"),
    ("closures_1d", "twofluid.closures.kernels:_compiled"),
    ("extrapolation", "twofluid.models.extrapolation:_kernels"),
    ("newton_accept", "twofluid.timestepping.newton:_kernels"),
    ("reduced_1d", "twofluid.models.reduced_kernel:kernels"),
    ("full_1d", "twofluid.models.full_kernel:kernels"),
    ("shear_substeps", "twofluid.models.shear_kernel:compiled"),
    ("hysteretic", "twofluid.models.hysteretic_kernel:compiled"),
    ("spectra_peaks", "twofluid.geotech.spectra:_compiled_peaks"),
)


def jit_disabled() -> bool:
    """Whether kernels run as plain Python (``TWOFLUID_DISABLE_JIT`` or ``NUMBA_DISABLE_JIT`` set to
    anything but 0/empty): the debugging mode of the module docstring.

    >>> isinstance(jit_disabled(), bool)
    True
    """
    return any(os.environ.get(v, "0") not in ("", "0") for v in ("TWOFLUID_DISABLE_JIT", "NUMBA_DISABLE_JIT"))


def _announce(folder: Path) -> None:
    """One line on standard error, once per process, when a build starts."""
    global _ANNOUNCED
    if not _ANNOUNCED and not os.environ.get("TWOFLUID_BUILDING_KERNELS"):
        _ANNOUNCED = True
        print(f"twofluid: compiling the numerical kernels once (up to a minute of CPU; kept in {folder}; "
              "`twofluid build-kernels` does it ahead)", file=sys.stderr, flush=True)


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
    _announce(folder)
    work = Path(tempfile.mkdtemp(prefix="twofluid-aot-"))
    try:
        cc = _cc_class(CC, folder)(module)
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


#: C flags of numba's C helper code linked into every module (its boxing of arguments and its
#: runtime's allocator: not the kernels, which LLVM compiles): -O1 without debug information
#: halves its compile time against Python's own -O3 -g.
_MIXIN_CFLAGS = ["-O1", "-g0"]


def _cc_class(CC, folder: Path):
    """``numba.pycc.CC`` whose C helper code is compiled with :data:`_MIXIN_CFLAGS`, and whose
    helper sources that do not depend on the module's name are compiled once per numba version
    and interpreter into ``folder/.pycc-objects`` and reused by later builds."""

    class _CC(CC):
        def _get_extra_cflags(self):
            return list(super()._get_extra_cflags()) + _MIXIN_CFLAGS

        def _compile_mixins(self, build_dir):
            import numba

            sources = self._get_mixin_sources()
            macros = self._get_mixin_defines()
            include_dirs = self._toolchain.get_python_include_dirs()
            flags = self._get_extra_cflags()
            named = [src for src in sources if os.path.basename(src) == "modulemixin.c"]
            shared = [src for src in sources if src not in named]
            objects = self._toolchain.compile_objects(named, build_dir, include_dirs=include_dirs,
                                                      macros=macros, extra_cflags=flags)
            key = hashlib.sha256("\n".join([numba.__version__, sys.implementation.cache_tag, sys.platform,
                                             repr(macros[1:]), repr(flags), *shared]).encode()).hexdigest()[:16]
            store = folder / ".pycc-objects"
            for src in shared:
                cached = store / f"{key}-{os.path.basename(src)}.o"
                if not cached.is_file():
                    built = self._toolchain.compile_objects([src], build_dir, include_dirs=include_dirs,
                                                            macros=macros, extra_cflags=flags)[0]
                    try:
                        store.mkdir(exist_ok=True)
                        tmp = store / f".{cached.name}.{os.getpid()}.tmp"
                        import shutil

                        shutil.copyfile(built, tmp)
                        os.replace(tmp, cached)  # atomic, as the modules
                    except OSError:
                        objects.append(built)
                        continue
                objects.append(str(cached))
            return objects

    return _CC


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
    ``func`` (ImportError without numba), else None; ``func`` itself where the JIT is disabled
    (:func:`jit_disabled`). The same object for every call in a process."""
    out = group(name, {name: (func, signature)}, build=build, jit=jit)
    return None if out is None else out[name]


def group(group_name: str, exports: dict, helpers: tuple = (), build: bool = True,
          jit: bool = True) -> dict | None:
    """Several kernels in one ahead-of-time module (one build, one import): ``exports`` {name:
    (func, signature)}, ``helpers`` the plain functions they call (compiled with them). Returns
    {name: compiled function} as :func:`kernel` does for one, or None."""
    if group_name in _LOADED:
        return _LOADED[group_name]
    if jit_disabled():  # the plain Python functions (module docstring): debugging only
        out = _LOADED[group_name] = {name: func for name, (func, _sig) in exports.items()}
        return out
    if os.environ.get("TWOFLUID_KERNELS_PROBE"):  # build_all's probe: what is there, nothing built
        build = jit = False
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
            raise ImportError("twofluid needs numba for its kernels (pip install numba; README, "
                              "'Dependencies'); TWOFLUID_DISABLE_JIT=1 runs them as plain Python, "
                              "for debugging only") from None
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


def _build_group(spec: str) -> None:
    """Build one group by calling its getter (``"module:getter"`` of :data:`GROUPS`)."""
    import importlib

    module, getter = spec.split(":")
    getattr(importlib.import_module(module), getter)()


def _probe() -> None:
    """Print the groups of :data:`GROUPS` that have no module in the cache folder (in a process of
    its own, ``TWOFLUID_KERNELS_PROBE`` set: nothing is built or compiled)."""
    for name, spec in GROUPS:
        _build_group(spec)
        if not _LOADED.get(name):
            print(name)


#: groups whose getters call another group's (built first, so that it is not built twice at once)
_AFTER = {"reduced_1d": "band_lu", "full_1d": "band_lu"}


def build_all(workers: int | None = None) -> list[str]:
    """Build every group of :data:`GROUPS` not yet in the cache folder, each in a process of its own,
    ``workers`` at a time (default: the CPU count); returns the groups that could not be built ahead
    of time (empty where all were). With nothing to build it costs one process's imports.

    >>> callable(build_all)
    True
    """
    import subprocess
    import time

    if cache_dir() is None:
        return [name for name, _ in GROUPS]
    workers = max(1, workers or os.cpu_count() or 1)
    env = dict(os.environ, TWOFLUID_BUILDING_KERNELS="1")
    env.pop("TWOFLUID_DISABLE_JIT", None)
    env.pop("NUMBA_DISABLE_JIT", None)
    probe = subprocess.run([sys.executable, "-c", "from twofluid import compiled; compiled._probe()"],
                           env=dict(env, TWOFLUID_KERNELS_PROBE="1"), capture_output=True, text=True)
    missing = probe.stdout.split() if probe.returncode == 0 else [name for name, _ in GROUPS]
    code = ("import sys; from twofluid import compiled; compiled._build_group(sys.argv[1]); "
            "out = compiled._LOADED.get(sys.argv[2]) or {None: None}; "
            "print('aot' if all(type(f).__name__ == 'builtin_function_or_method' for f in out.values()) else 'jit')")
    # the longest builds first (so that two workers end together), a group after the one it calls
    pending = sorted(((n, s) for n, s in GROUPS if n in missing), key=lambda g: g[0] not in ("reduced_1d",))
    running, failed, done = [], [], {n for n, _ in GROUPS if n not in missing}
    while pending or running:
        ready = [g for g in pending if _AFTER.get(g[0], g[0]) in done | {g[0]}
                 and _AFTER.get(g[0]) not in {r[0] for r in running}]
        while ready and len(running) < workers:
            g = ready.pop(0)
            pending.remove(g)
            running.append((g[0], subprocess.Popen([sys.executable, "-c", code, g[1], g[0]], env=env,
                                                   stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)))
        if not running:  # a dependency that is neither built nor pending: build the group anyway
            _AFTER.clear()
            continue
        time.sleep(0.05)
        for r in [r for r in running if r[1].poll() is not None]:
            running.remove(r)
            out = r[1].communicate()[0]
            done.add(r[0])
            if r[1].returncode != 0 or out.strip() != "aot":
                failed.append(r[0])
    return failed
