"""Compiled kernels without numba's start-up cost: ahead-of-time extension modules, built once.

Every hot loop of the 1D models is written once, in numba-compatible Python (no NumPy twin), and
compiled here. A numba-compiled function costs every process that uses it about 0.45 s of CPU to
import numba and 0.25 s to set up its typing and target registries and load the cached machine
code (``numba.njit(cache=True)``; numba 0.68 on the 2-core benchmark VM), more than the
liquefaction column's 7 000 shear sub-steps spend in the kernel itself (0.03 s). So a kernel
is compiled ahead of time instead, with ``numba.pycc``, into an ordinary extension module
kept in a cache folder; later processes import that module (about 1 ms) and do not import
numba at all. Kernels used together are built into one module (:func:`group`: one build,
one import). A module is named after a hash of the package's version, the source files of its
functions and of every file they take code or constants from (:func:`_sources`), their
signatures, the Python ABI and the NumPy version, so an edited kernel, an edited callee in
another file, another release or another interpreter builds a new one (numba's own cache keys a
function on its own file alone, and would keep a caller compiled against an old callee). A build
holds a lock on its module (a second process building the same group at once waits, then loads
it; a killed build's lock dies with it and its leftovers are removed by the next), and writes
under a temporary name that it renames, so that no process ever loads half a file.

A run builds only the groups its model needs (:func:`groups_for`), before it starts
(:func:`prepare`; an ensemble in its parent, before the workers), and says so in one line on
standard error naming them. ``twofluid build-kernels`` (:func:`build_all`) builds every group
of :data:`GROUPS` ahead, in parallel over the CPUs (:data:`FAMILIES`: the groups that share helpers
in one process). The figures of the build are in
``docs/benchmarks.md``.

Where a module cannot be built (``numba.pycc`` missing — it is deprecated in numba — or no C
toolchain to link it) the kernel is ``numba.njit`` cached in ``<cache folder>/jit/<module>``
(the same key). Where no cache folder is writable, modules already built in any of them are
loaded; the others are compiled by ``numba.njit`` for the process alone, and one line says why
(a correct, slower run). With ``TWOFLUID_DISABLE_JIT=1`` (or numba's own
``NUMBA_DISABLE_JIT=1``) every kernel is its plain Python function, un-compiled: the same
source, for a debugger or print statements, some hundred times slower; it is a debugging aid.

Cache folder: ``$TWOFLUID_CACHE_DIR`` if set, else the ``__pycache__`` folder beside this
module if it is writable, else ``~/.cache/twofluid`` (built modules are looked for in both).

>>> folder = cache_dir()
>>> folder is None or folder.is_dir()
True
"""
from __future__ import annotations

import contextlib
import functools
import hashlib
import importlib.machinery
import importlib.util
import os
import sys
from pathlib import Path
from typing import Callable

__all__ = ["kernel", "group", "cache_dir", "jit_disabled", "build_all", "groups_for", "prepare"]

_LOADED: dict[str, Callable | None] = {}
_ANNOUNCED = False

#: every group of the project's kernels: (group name, "module:getter"); the getter builds the group
#: (``twofluid build-kernels`` calls each). A new group is added here.
GROUPS = (
    ("band_lu", "twofluid.fem.banded:band_lu"),
    ("band_22", "twofluid.fem.banded:_band_22"),
    ("common_1d", "twofluid.models.reduced_kernel:common_kernels"),
    ("closures_1d", "twofluid.closures.kernels:_compiled"),
    ("extrapolation", "twofluid.models.extrapolation:_kernels"),
    ("newton_accept", "twofluid.timestepping.newton:_kernels"),
    ("reduced_1d", "twofluid.models.reduced_kernel:kernels"),
    ("full_1d", "twofluid.models.full_step_kernel:group_kernels"),
    ("shear_substeps", "twofluid.models.shear_kernel:compiled"),
    ("hysteretic", "twofluid.models.hysteretic_kernel:compiled"),
    ("spectra_peaks", "twofluid.geotech.spectra:_compiled_peaks"),
    ("column_record", "twofluid.models.record_kernel:compiled"),
    ("column_step", "twofluid.models.column_step_kernel:compiled"),
)


def jit_disabled() -> bool:
    """Whether kernels run as plain Python (``TWOFLUID_DISABLE_JIT`` or ``NUMBA_DISABLE_JIT`` set to
    anything but 0/empty): the debugging mode of the module docstring.

    >>> isinstance(jit_disabled(), bool)
    True
    """
    return any(os.environ.get(v, "0") not in ("", "0") for v in ("TWOFLUID_DISABLE_JIT", "NUMBA_DISABLE_JIT"))


#: the groups a run of each ``[case] model`` needs (the 1D models' steps, the band solver, the
#: closure laws, the extrapolated first iterate, Newton's acceptance test; a liquefaction column's
#: shear wave and its response spectra). :func:`groups_for` adds the shear law's group.
MODEL_GROUPS = {
    "two_fluid_1d": ("full_1d", "closures_1d"),  # (the one-call step; the stepper's other groups built if a step needs them)
    "reduced_1d": ("reduced_1d", "band_22", "common_1d", "closures_1d", "extrapolation", "newton_accept"),
    "liquefaction_1d": ("reduced_1d", "band_22", "common_1d", "closures_1d", "extrapolation", "newton_accept",
                        "spectra_peaks", "column_record", "column_step"),
    "two_fluid_2d": (),
}
_PLANNED: list[str] = []


def groups_for(case: dict) -> list[str]:
    """The kernel groups (:data:`GROUPS`) a run of ``case`` (a validated case dict) needs.

    >>> groups_for({"case": {"model": "two_fluid_2d"}})
    []
    >>> groups_for({"case": {"model": "two_fluid_1d"}, "closures": {"drag": {"law": "wen_yu"}}})[0]
    'full_1d'
    """
    model = case.get("case", {}).get("model")
    out = list(MODEL_GROUPS.get(model, ()))
    if model == "liquefaction_1d":
        hysteretic = case.get("shear_wave", {}).get("model") == "hysteretic"
        out.append("hysteretic" if hysteretic else "shear_substeps")
    if model == "two_fluid_1d" and (case.get("mesh", {}).get("element", "1VW/0P/0n") != "1VW/0P/0n"
                                    or case.get("closures", {}).get("drag", {}).get("law") == "wen_yu"):
        out = list(_STEPPER_1D)  # steps the one-call step (full_step) does not make: the stepper's groups
    return out


_STEPPER_1D = ("full_1d", "band_lu", "common_1d", "closures_1d", "extrapolation", "newton_accept")


def prepare(names) -> None:
    """Load the kernel groups ``names`` (:data:`GROUPS`), building those not built yet, before a run
    starts (one line on standard error names them, :func:`_announce`). A group a run needs but
    ``names`` misses is still built when first needed, and announced then."""
    if jit_disabled() or os.environ.get("TWOFLUID_KERNELS_PROBE") or cache_dir() is None:
        return  # (no writable cache: each process compiles what it needs itself, and says so)
    specs = dict(GROUPS)
    names = [n for n in dict.fromkeys(names) if n in specs]
    _PLANNED[:] = names
    try:
        with _young_gc_only():  # (the whole set: what one group's build leaves is not scanned by the next's)
            for name in names:
                if name not in _LOADED:
                    _build_group(specs[name])
                del _PLANNED[0]
    except Exception:  # (no numba and nothing built, say): the run meets it where it reports it
        pass
    finally:
        _PLANNED.clear()


def _announce(folder: Path, group_name: str) -> None:
    """One line on standard error, once per process, when a build starts: the group being built
    and, under :func:`prepare`, the groups planned after it (some of which may turn out built)."""
    global _ANNOUNCED
    if not _ANNOUNCED and not os.environ.get("TWOFLUID_BUILDING_KERNELS"):
        _ANNOUNCED = True
        names = [group_name] + [n for n in _PLANNED if n != group_name and n not in _LOADED]
        print(f"twofluid: compiling the numerical kernels this run needs, once: {', '.join(names)} "
              f"(kept in {folder}; `twofluid build-kernels` builds them all ahead)", file=sys.stderr, flush=True)


def _folders() -> list[Path]:
    """Where the ahead-of-time modules may be (module docstring), in order."""
    env = os.environ.get("TWOFLUID_CACHE_DIR")
    return [Path(env)] if env else [Path(__file__).parent / "__pycache__", Path.home() / ".cache" / "twofluid"]


def cache_dir() -> Path | None:
    """The folder the ahead-of-time modules are built into (module docstring), or None if none is
    writable (then modules already built in any of the folders are still loaded)."""
    for folder in _folders():
        try:
            folder.mkdir(parents=True, exist_ok=True)
        except OSError:
            continue
        if os.access(folder, os.W_OK):
            return folder
    return None


def _find(module: str) -> Path | None:
    """The built module ``module`` in any of the cache folders (writable or not), or None."""
    suffix = importlib.machinery.EXTENSION_SUFFIXES[0]
    for folder in _folders():
        path = folder / f"{module}{suffix}"
        if path.is_file():
            return path
    return None


_WARNED_UNWRITABLE = False


def _warn_unwritable() -> None:
    """One line on standard error, once per process, where no cache folder can be written."""
    global _WARNED_UNWRITABLE
    if not _WARNED_UNWRITABLE:
        _WARNED_UNWRITABLE = True
        where = ", ".join(str(f) for f in _folders())
        print(f"twofluid: no writable kernel cache folder ({where}): the kernels not built there are "
              "compiled for this process only (slower; set TWOFLUID_CACHE_DIR to a writable folder)",
              file=sys.stderr, flush=True)


def _module_name(name: str, func: Callable, signature: str, helpers: tuple = ()) -> str:
    return _group_name(name, {name: (func, signature)}, helpers)


@functools.lru_cache(maxsize=None)
def _library_paths() -> tuple[str, ...]:
    """The interpreter's standard library and installed libraries' folders (``sysconfig``), found once
    a process: :func:`_sources` asks at each group a run loads, and ``sysconfig.get_paths`` takes about
    0.1 ms a call."""
    import sysconfig

    paths = sysconfig.get_paths()
    return tuple({p for k in ("stdlib", "platstdlib", "purelib", "platlib") if (p := paths.get(k))})


def _sources(funcs) -> list[str]:
    """The source files of ``funcs`` and of every function and module that they name, followed
    through the functions so found, but the standard library's and installed libraries' (the
    package's own files count wherever it is installed): what a compiled kernel may have taken in
    (numba compiles callees and freezes global constants into the caller)."""
    import types

    package = str(Path(__file__).parent)
    libraries = _library_paths()

    def ours(file: str) -> bool:  # the package's, or another project's sources (not a library's)
        return file.startswith(package) or (file.endswith(".py") and not file.startswith(libraries))

    files, seen, todo = set(), set(), list(funcs)
    while todo:
        f = todo.pop()
        code = getattr(f, "__code__", None)
        if code is None or id(f) in seen:
            continue
        seen.add(id(f))
        files.add(code.co_filename)
        names = set(code.co_names)
        for const in code.co_consts:  # nested code objects (comprehensions, inner functions)
            if isinstance(const, types.CodeType):
                names.update(const.co_names)
        g = getattr(f, "__globals__", {})
        for name in names:
            obj = g.get(name)
            obj = getattr(obj, "py_func", obj)  # a helper replaced by its compiled version
            if isinstance(obj, types.ModuleType):
                file = getattr(obj, "__file__", None) or ""
                if ours(file):  # its constants and functions, read as module.name
                    files.add(file)
            elif isinstance(obj, types.FunctionType) and ours(obj.__code__.co_filename):
                todo.append(obj)
    return sorted(files)


def _group_name(group: str, exports: dict, helpers: tuple = (), check_layouts: bool = False) -> str:
    """The module of a group of kernels: named after a hash of the package's version, the source
    files of the kernels, of the helpers they call and of every package function or module they
    name (:func:`_sources`), their names and signatures, whether its arrays' layouts are checked, the
    Python ABI and the NumPy version."""
    import numpy

    from . import __version__

    digest = hashlib.sha256()
    funcs = [f for f, _sig in exports.values()] + list(helpers)
    for file in sorted(set(_sources(funcs)) | {f.__code__.co_filename for f in funcs}):
        # whole source files: reading them costs microseconds where inspect.getsource of each
        # function tokenizes the module (~40 ms for the project's kernels); any edit rebuilds
        digest.update(Path(file).read_bytes())
    key = [f"{f.__qualname__}:{sig}" for f, sig in exports.values()] + [f.__qualname__ for f in helpers]
    key += ["layouts checked"] if check_layouts else []
    digest.update("\n".join(key + [__version__, sys.implementation.cache_tag, numpy.__version__]).encode())
    return f"_twofluid_{group}_{digest.hexdigest()[:16]}"


def _import(path: Path, module: str):
    spec = importlib.util.spec_from_file_location(module, path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _build(folder: Path, module: str, exports: dict, helpers: tuple = (), check_layouts: bool = False) -> Path | None:
    """Compile ``exports`` {name: (func, signature)} into ``folder/<module><ext>``, the ``helpers``
    they call compiled with them, their arrays' layouts checked on each call if ``check_layouts``
    (:func:`_unbox_checked`); None if it cannot be done here."""
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
    _announce(folder, module.split('_twofluid_', 1)[-1].rsplit('_', 1)[0])
    work = Path(tempfile.mkdtemp(prefix="twofluid-aot-"))
    try:
        cc = _cc_class(CC, folder)(module)
        cc.output_dir = str(work)
        cc.verbose = False
        for name, (func, signature) in exports.items():
            cc.export(name, signature)(_stub(func) if func in helpers else func)
        with _compiled_helpers(helpers), _no_jit_machine_code(), _helpers_optimised_in_module(), \
                _plain_typing_messages(), _typing_memo(), _lowering_memo(), _young_gc_only(), \
                _no_llvm_lock_events(), _unbox_checked(check_layouts), _no_cfunc_wrappers(), _ir_vars_listed_once(), \
                warnings.catch_warnings():
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


def _stub(func: Callable) -> Callable:
    """A function calling ``func`` with its arguments, exported in its stead where ``func`` is also a
    helper of its group (:func:`group`): numba then compiles ``func`` once, as the helper (its
    dispatcher, :data:`_HELPER_DISPATCHERS`), for the export and for every kernel of the process that
    calls it with the same argument types (another group's, built after it in the process), where
    ``numba.pycc`` would type and lower the export anew. ``func`` itself where it takes ``*args``,
    ``**kwargs`` or keyword-only arguments, or has no name of its own (a lambda).

    >>> def total(x, y):
    ...     return x + y
    >>> stub = _stub(total)
    >>> stub.__qualname__, stub(1.0, 2.0)
    ('total_export', 3.0)
    >>> f = lambda x: x
    >>> _stub(f) is f
    True
    """
    code = func.__code__
    if code.co_flags & 0x0C or code.co_kwonlyargcount or not func.__name__.isidentifier():  # 0x0C: *args, **kw
        return func
    args = ", ".join(f"a{i}" for i in range(code.co_argcount))
    ns: dict = {}
    # the body names the helper as its module does: while the group compiles, its dispatcher
    exec(f"def stub({args}):\n    return {func.__name__}({args})\n", func.__globals__, ns)
    stub = ns["stub"]
    stub.__qualname__ = stub.__name__ = f"{func.__qualname__}_export"
    return stub


#: C flags of numba's C helper code linked into every module (its boxing of arguments and its
#: runtime's allocator: not the kernels, which LLVM compiles): -O1 without debug information
#: halves its compile time against Python's own -O3 -g.
_MIXIN_CFLAGS = ["-O1", "-g0"]


#: the module name numba's ``modulemixin.c`` is compiled under once (:func:`_cc_class`)
_MIXIN_NAME = "_twofluid_pycc_mixin"


def _mixin_shim(build_dir: str, module: str) -> str:
    """A C file defining ``pycc_init_<module>``, the one symbol of numba's ``modulemixin.c`` that
    the module's own code calls by the module's name, as a call of the shared copy's (compiled
    once under :data:`_MIXIN_NAME`, its symbols hidden in each module): milliseconds to compile,
    where ``modulemixin.c`` (numba's helper library, included whole) takes 0.6 s of CPU."""
    path = Path(build_dir) / f"{module}_mixin_shim.c"
    path.write_text(
        "struct _object;\nstruct PyMethodDef;\n"
        f"int pycc_init_{_MIXIN_NAME}(struct _object *, struct PyMethodDef *, void *, void *);\n"
        f"int pycc_init_{module}(struct _object *m, struct PyMethodDef *d, void *e, void *g)\n"
        f"{{ return pycc_init_{_MIXIN_NAME}(m, d, e, g); }}\n")
    return str(path)


#: numba's C sources of its typed containers (``numba/cext``, which ``numba.pycc`` links into every
#: module) and the prefix of the symbols each defines; ``utils.c`` serves them alone
_CONTAINER_SOURCES = {"dictobject.c": b"numba_dict", "listobject.c": b"numba_list", "setobject.c": b"numba_set"}


def _containers_called(sources: list, kernel_objects) -> list:
    """``sources`` (numba's C helper sources of a module) without the typed containers' (a typed
    dict, list or set: :data:`_CONTAINER_SOURCES`) that the kernels' machine code ``kernel_objects``
    calls none of, nor ``numba/cext/utils.c`` where it calls none: the project's kernels use no typed
    container, and their three sources take 0.6 s of CPU to compile (with ``utils.c``, once per cache
    folder). A name that appears in an object file's symbol table appears in its bytes, so a module that
    calls a container links it. Every source where the objects cannot be read.

    >>> _containers_called(["/n/modulemixin.c", "/n/cext/dictobject.c", "/n/cext/utils.c"], [])
    ['/n/modulemixin.c']
    """
    try:
        blob = b"".join(Path(obj).read_bytes() for obj in kernel_objects)
    except (OSError, TypeError):
        return list(sources)
    cext = [src for src in sources if os.path.basename(os.path.dirname(src)) == "cext"]
    used = set()
    for name in (os.path.basename(src) for src in cext):
        prefix = _CONTAINER_SOURCES.get(name)
        if name != "utils.c" and (prefix is None or prefix in blob):  # (a source numba adds later: kept)
            used.add(name)
    if used:
        used.add("utils.c")
    return [src for src in sources if src not in cext or os.path.basename(src) in used]


def _cc_class(CC, folder: Path):
    """``numba.pycc.CC`` whose C helper code is compiled with :data:`_MIXIN_CFLAGS` once per numba
    version and interpreter into ``folder/.pycc-objects`` and reused by later builds: the sources
    that do not depend on the module's name as they are, ``modulemixin.c`` under a fixed name with
    a shim per module (:func:`_mixin_shim`)."""

    class _CC(CC):
        def _get_extra_cflags(self):
            return list(super()._get_extra_cflags()) + _MIXIN_CFLAGS

        def _compile_object_files(self, build_dir):
            objects, exports = super()._compile_object_files(build_dir)
            self._kernel_objects = list(objects)
            return objects, exports

        def _compile_mixins(self, build_dir):
            import numba

            sources = self._get_mixin_sources()
            macros = self._get_mixin_defines()
            include_dirs = self._toolchain.get_python_include_dirs()
            flags = self._get_extra_cflags()
            named = [src for src in sources if os.path.basename(src) == "modulemixin.c"]
            shared = [src for src in sources if src not in named]
            if named and macros[0][0] == "PYCC_MODULE_NAME":  # the name is in two symbols only: a shim
                objects = self._toolchain.compile_objects([_mixin_shim(build_dir, macros[0][1])], build_dir,
                                                          extra_cflags=flags)
                shared = sources
            else:
                objects = self._toolchain.compile_objects(named, build_dir, include_dirs=include_dirs,
                                                          macros=macros, extra_cflags=flags)
            key = hashlib.sha256("\n".join([numba.__version__, sys.implementation.cache_tag, sys.platform,
                                             repr(macros[1:]), repr(flags), *shared]).encode()).hexdigest()[:16]
            store = folder / ".pycc-objects"
            for src in sources:  # the object of "numba/pycc/../core/x.c" is written through the
                # folder of numba/pycc in build_dir, which only a compile of modulemixin.c made
                os.makedirs(os.path.join(build_dir, os.path.dirname(src).lstrip(os.sep)), exist_ok=True)
            shared = _containers_called(shared, getattr(self, "_kernel_objects", None))
            with _lock(folder, f"pycc-objects-{key}"):  # one process compiles them, another waits for them
                objects += self._shared_objects(shared, named, build_dir, include_dirs, macros, flags, store, key)
            return objects

        def _shared_objects(self, shared, named, build_dir, include_dirs, macros, flags, store, key):
            objects = []
            for src in shared:
                cached = store / f"{key}-{os.path.basename(src)}.o"
                if not cached.is_file():
                    shared_macros, shared_flags = macros, flags
                    if src in named:  # compiled once, under a fixed name, its symbols hidden
                        shared_macros = [("PYCC_MODULE_NAME", _MIXIN_NAME)] + list(macros[1:])
                        shared_flags = flags + ["-fvisibility=hidden"]
                    built = self._toolchain.compile_objects([src], build_dir, include_dirs=include_dirs,
                                                            macros=shared_macros, extra_cflags=shared_flags)[0]
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


#: each helper's ``numba.njit`` dispatcher, kept for the process: a helper that several groups call
#: (the band solver's, the closure laws') is then typed and compiled once per argument types in a
#: process that builds several groups (a run's :func:`prepare`, a worker of :func:`build_all`), and
#: its machine code linked into each module that calls it. Only compiled code calls them: numba
#: makes them no Python or C-callable wrapper
_HELPER_DISPATCHERS: dict = {}


@contextlib.contextmanager
def _no_jit_machine_code():
    """While a module builds, numba's JIT makes no machine code: a helper's dispatcher (the only
    JIT-compiled functions of a build) is compiled to optimised LLVM IR, which is linked into each
    module that calls it, and would also be compiled to machine code for the process, which
    nothing calls (they have no Python wrapper): 1.5 s of CPU over all groups (load 9). Where this
    numba lacks the two methods replaced, nothing is changed."""
    try:
        from numba.core import codegen

        library, jit = codegen.JITCodeLibrary, codegen.JITCPUCodegen
        finalize, set_env = library._finalize_specific, jit.set_env
    except (ImportError, AttributeError):
        yield
        return

    def ir_only(self):  # JITCodeLibrary._finalize_specific without the engine's finalize_object
        self._codegen._scan_and_fix_unresolved_refs(self._final_module)

    library._finalize_specific = ir_only
    jit.set_env = lambda self, env_name, env: None  # (its address lookup would make the machine code)
    try:
        yield
    finally:
        library._finalize_specific, jit.set_env = finalize, set_env


@contextlib.contextmanager
def _helpers_optimised_in_module():
    """While a module builds, a helper's LLVM IR is optimised once, in the module that links it: numba
    runs LLVM's function passes on each helper's IR as it is made, and its whole module pipeline
    (inlining included) on the helper with its own callees linked in, before the helper's IR is
    linked into its caller's library, where the same pipeline runs again over it; a helper three
    calls deep was optimised four times. Here a helper's library (a ``JITCodeLibrary``: the
    dispatchers of :func:`_compiled_helpers`, which nothing runs, :func:`_no_jit_machine_code`)
    keeps its IR as lowered, and the module's library (numba's ``AOTCodeLibrary``) runs the
    pipeline once over everything linked into it. LLVM's optimisations keep floating-point
    semantics (no fast-math), so the kernels compute the same: the bundled cases' outputs are
    byte-identical (``docs/benchmarks.md``, which gives the build's figures). Where this numba
    lacks the methods replaced, nothing is changed."""
    try:
        from numba.core import codegen

        library = codegen.JITCodeLibrary
        names = ("_optimize_functions", "_optimize_final_module")
        saved = {name: library.__dict__.get(name) for name in names}
        if not all(callable(getattr(library, name, None)) for name in names):
            raise AttributeError
    except (ImportError, AttributeError):
        yield
        return

    library._optimize_functions = lambda self, ll_module: None
    library._optimize_final_module = lambda self: None
    try:
        yield
    finally:
        for name, method in saved.items():
            if method is None:
                delattr(library, name)  # the inherited method (CPUCodeLibrary's) again
            else:
                setattr(library, name, method)


@contextlib.contextmanager
def _plain_typing_messages():
    """While a module builds, numba's error messages are plain text. Its type inference tries an
    operation's typing templates in turn and makes an error, message included, for each that does not
    fit (most do not: some 51 000 over the two ``build-kernels`` processes), and its default colour
    scheme, which adds only bold, writes each message through ``colorama``'s terminal wrappers:
    9 µs each, 0.5 s of CPU in all. Nothing prints them unless the build fails, which then says the
    same without bold. Where numba's messages are plain already (``NUMBA_DISABLE_ERROR_MESSAGE_
    HIGHLIGHTING``) or this numba has no such scheme, nothing is changed."""
    try:
        from numba.core import errors

        scheme = errors.termcolor()  # the one instance every numba module holds
    except (ImportError, AttributeError):
        yield
        return
    if not callable(getattr(type(scheme), "_markup", None)) or "_markup" in vars(scheme):
        yield
        return
    scheme._markup = lambda msg, color=None, style=None: msg
    try:
        yield
    finally:
        del scheme._markup


@contextlib.contextmanager
def _typing_memo():
    """While a module builds, numba types a call of a global function (an operator, ``math.sqrt``,
    ``np.empty``, ``min``: a ``types.Function``) once per argument types: its typing context resolves
    every such call anew, trying the function's typing templates in turn, though the answer depends on
    nothing but the function and the argument types (literal values included in them); a kernel
    multiplies two ``float64`` hundreds of times. The first answer is kept for the build and given to
    every later call with the same types: the same signature, so the same lowering and instructions
    (eleven of the thirteen modules identical instruction by instruction with and without it; the
    column step's and the hysteretic law's the same instructions in another order, as numba numbers
    the functions it compiles, and fewer are compiled: ``docs/benchmarks.md``). The same for the
    operators the type inference names by the Python function (``operator.getitem`` of each array
    access: 1 600 resolutions in the bed models' process) or by name (``"static_getitem"``), and for
    the function's own typing (``types.Function.get_call_type``), which the lowering asks again at
    each operator with a constant operand and each array access (2 700 times there, for 44 distinct
    answers); that one also keeps the key of the implementation it picked (``_impl_keys``, which
    the lowering looks up), and gives it back with each later answer. Calls numba fails to type are
    not kept (its own failure cache replays them). Where this numba's typing context lacks the
    methods replaced, nothing is changed."""
    import types as pytypes

    try:
        from numba.core import types
        from numba.core.typing import context

        resolve = context.BaseContext.__dict__["resolve_function_type"]
        get_call_type = types.Function.get_call_type
        own = types.Function.__dict__.get("get_call_type")  # (None: BaseFunction's, inherited)
    except (ImportError, AttributeError, KeyError):
        yield
        return
    memo: dict = {}
    named = (types.Function, str, pytypes.BuiltinFunctionType)  # (the Python operators: builtins)

    def resolve_function_type(self, func, args, kws):
        if not isinstance(func, named):
            return resolve(self, func, args, kws)
        try:
            key = (self, func, tuple(args), tuple(sorted(kws.items())) if kws else ())
            sig = memo.get(key)
        except TypeError:  # an unhashable argument type: typed as numba does
            return resolve(self, func, args, kws)
        if sig is None:
            sig = resolve(self, func, args, kws)
            if sig is not None:
                memo[key] = sig
        return sig

    typed: dict = {}

    def function_call_type(self, context, args, kws):
        if type(self) is not types.Function or not isinstance(getattr(self, "_impl_keys", None), dict):
            return get_call_type(self, context, args, kws)
        try:
            key = (self, context, tuple(args), tuple(sorted(kws.items())) if kws else ())
            hit = typed.get(key)
        except TypeError:
            return get_call_type(self, context, args, kws)
        if hit is None:
            sig = get_call_type(self, context, args, kws)
            if sig is None:
                return sig
            hit = typed[key] = (sig, self._impl_keys.get(sig.args))
        sig, impl_key = hit
        if impl_key is not None:
            self._impl_keys[sig.args] = impl_key  # as numba's own typing leaves it
        return sig

    context.BaseContext.resolve_function_type = resolve_function_type
    types.Function.get_call_type = function_call_type
    try:
        yield
    finally:
        context.BaseContext.resolve_function_type = resolve
        if own is None:
            del types.Function.get_call_type
        else:
            types.Function.get_call_type = own


@contextlib.contextmanager
def _lowering_memo():
    """While a module builds, numba's target context finds the implementation of a function for a
    signature (``get_function``: an operator on two ``float64``, a call of a helper) once: it looks it
    up anew at every call site it lowers (some 7 000 in the bed models' process, for 1 300 distinct
    function and signature pairs), inspecting the implementation's Python signature each time and,
    where the first lookup misses, loading its registries again. The first answer for a context,
    function and signature is kept for the build and given again: the same implementation, so the
    same instructions. Lookups that fail are not kept, but for ``__array__``: numba's ``make_array``
    asks for it at every array it lowers (1 300 times in that process), for an array-like type that
    wraps an array, and each miss reloads the registries before it fails; numba registers none, so a
    type's miss is remembered. Where this numba's context lacks the method replaced, nothing is
    changed."""
    try:
        from numba.core import base

        get_function = base.BaseContext.__dict__["get_function"]
    except (ImportError, KeyError):
        yield
        return
    memo: dict = {}
    missing: set = set()

    def memo_get_function(self, fn, sig, _firstcall=True):
        if not _firstcall:
            return get_function(self, fn, sig, _firstcall)
        try:
            key = (self, fn, sig.as_function())
            impl = memo.get(key)
            if impl is None and key in missing:
                raise NotImplementedError(f"No definition for lowering {fn}{sig}")
        except (TypeError, AttributeError):  # unhashable: looked up as numba does
            return get_function(self, fn, sig, _firstcall)
        if impl is None:
            try:
                impl = memo[key] = get_function(self, fn, sig, _firstcall)
            except NotImplementedError:
                if isinstance(fn, str) and fn == "__array__":
                    missing.add(key)
                raise
        return impl

    base.BaseContext.get_function = memo_get_function
    try:
        yield
    finally:
        base.BaseContext.get_function = get_function


@contextlib.contextmanager
def _no_llvm_lock_events():
    """While a module builds, numba broadcasts no event when it takes llvmlite's lock: numba asks
    llvmlite to call two functions of its own around every call into LLVM (some 110 000 over the two
    ``build-kernels`` processes), which broadcast a ``numba:llvm_lock`` event to numba's listeners
    (its compile-time statistics, which nothing here reads): 4 µs a call, 0.4 s of CPU in all. The
    callbacks are registered again after. Where this llvmlite keeps no such list, nothing is changed."""
    try:
        from llvmlite.binding import ffi

        callbacks = ffi.lib._lock._cblist
        if not isinstance(callbacks, list):
            raise TypeError
    except (ImportError, AttributeError, TypeError):
        yield
        return
    saved = callbacks[:]
    callbacks.clear()
    try:
        yield
    finally:
        callbacks[:] = saved + [c for c in callbacks if c not in saved]


#: the garbage collector's thresholds while kernels build (:func:`_young_gc_only`): the youngest
#: generation collected every 10 000 allocations (Python's default: 700), the older ones in effect never
_BUILD_GC_THRESHOLDS = (10_000, 1_000_000, 1_000_000)


@contextlib.contextmanager
def _young_gc_only():
    """While kernels build, Python's garbage collector collects only new objects, and less often
    (:data:`_BUILD_GC_THRESHOLDS`); its thresholds are restored after. numba's type inference and
    lowering allocate millions of objects, most of them kept to the end of the build, which the
    default thresholds scan again and again in the older generations: 3.7 s of the two
    ``build-kernels`` processes' 30 s of CPU, 0.8 s with these, for 30–110 MB more memory per process
    (``docs/benchmarks.md``). The machine code built is the same. A collector switched off stays off."""
    import gc

    saved = gc.get_threshold()
    if saved[0]:
        gc.set_threshold(*_BUILD_GC_THRESHOLDS)
    try:
        yield
    finally:
        gc.set_threshold(*saved)


#: SHA-256 (first 16 hex digits) of the source of numba's ``Inst._rec_list_vars`` that
#: :func:`_ir_vars_listed_once` repeats (numba 0.68's)
_REC_LIST_VARS_SOURCE = "c083cbdf60a8f3b5"


@contextlib.contextmanager
def _ir_vars_listed_once():
    """While a module builds, numba lists the variables of an IR statement (``Inst._rec_list_vars``:
    its liveness and use-def analyses ask it of every statement after each of its passes, some two
    million times over the bed models' process) into one list, classifying each value it meets by
    its type once (a variable, an instruction, a sequence, a mapping, or none of them), where
    numba's own walk builds a list per value and tests it against each kind in turn: the same
    variables in the same order, in about half the time. Where this numba's IR lacks the method
    replaced, or its source is not the one this walk repeats (:data:`_REC_LIST_VARS_SOURCE`: another
    numba may list other kinds of value), nothing is changed."""
    try:
        import inspect

        from numba.core import ir

        rec_list_vars = ir.Inst.__dict__["_rec_list_vars"]
        source = hashlib.sha256(inspect.cleandoc(inspect.getsource(rec_list_vars)).encode()).hexdigest()[:16]
    except (ImportError, KeyError, OSError, TypeError):
        yield
        return
    if source != _REC_LIST_VARS_SOURCE:
        yield
        return
    var, inst = ir.Var, ir.Inst
    kinds: dict = {}

    def kind_of(t):  # numba's tests, in its order, once per type
        k = kinds[t] = (1 if issubclass(t, var) else 2 if issubclass(t, inst) else
                        3 if issubclass(t, (list, tuple)) else 4 if issubclass(t, dict) else 0)
        return k

    def collect(val, out):
        k = kinds.get(type(val))
        if k is None:
            k = kind_of(type(val))
        if k == 1:
            out.append(val)
        elif k == 2:
            out.extend(val.list_vars())
        elif k == 3:
            for v in val:
                collect(v, out)
        elif k == 4:
            for v in val.values():
                collect(v, out)

    def listed(self, val):
        out: list = []
        collect(val, out)
        return out

    ir.Inst._rec_list_vars = listed
    try:
        yield
    finally:
        ir.Inst._rec_list_vars = rec_list_vars


@contextlib.contextmanager
def _no_cfunc_wrappers():
    """While a module builds, numba makes its exports no C-callable wrapper (a ``cfunc`` wrapper):
    ``numba.pycc`` makes one for each beside the Python wrapper, which alone the module's method table
    names, so that the wrapper, typed, lowered and optimised with the module, was compiled into every
    module and called by nothing (a tenth of the modules' optimised instructions). Where this numba's
    ``numba.pycc`` has no such flags, nothing is changed."""
    try:
        from numba.pycc import compiler

        flags_class = compiler.Flags
        if "no_cfunc_wrapper" not in dir(flags_class):
            raise AttributeError
    except (ImportError, AttributeError):
        yield
        return

    class Flags(flags_class):
        def __init__(self, *args, **kwargs):
            super().__init__(*args, **kwargs)
            self.no_cfunc_wrapper = True

    compiler.Flags = Flags
    try:
        yield
    finally:
        compiler.Flags = flags_class


#: the error of an export given an array not of its declared layout (:func:`_unbox_checked`)
_LAYOUT_ERROR = ("twofluid: a compiled kernel was given an array that is not {} (its ahead-of-time "
                 "module reads it by its shape alone; np.ascontiguousarray makes one)")


def _layout_error(module, pyapi):
    """The function of ``module`` that the wrapper of :func:`_unbox_checked` calls on an array of
    another layout, made on first use: it releases the array's reference that the unboxing took (its
    meminfo, the first argument, where not null; the wrapper releases none of an argument that
    failed) and sets the ValueError of the message, the second argument. One call per array in the
    wrapper, its body once per module (never inlined: it runs only on an error)."""
    from llvmlite import ir
    from numba.core import cgutils

    fn = cgutils.get_or_insert_function(module, ir.FunctionType(ir.VoidType(), [cgutils.voidptr_t] * 2),
                                        "_twofluid_layout_error")
    if not fn.is_declaration:
        return fn
    fn.linkage = "linkonce_odr"
    fn.attributes.add("noinline")
    fn.attributes.add("cold")
    builder = ir.IRBuilder(fn.append_basic_block())
    meminfo, message = fn.args
    with builder.if_then(cgutils.is_not_null(builder, meminfo)):
        decref = cgutils.get_or_insert_function(module, ir.FunctionType(ir.VoidType(), [cgutils.voidptr_t]),
                                                "NRT_decref")
        builder.call(decref, [meminfo])
    gv = module.globals.get("PyExc_ValueError") or \
        cgutils.add_global_variable(module, pyapi.pyobj, "PyExc_ValueError")
    exc = builder.load(builder.bitcast(gv, pyapi.pyobj.as_pointer()))  # the variable's value: the class
    set_string = cgutils.get_or_insert_function(module, ir.FunctionType(ir.VoidType(), [pyapi.pyobj,
                                                                                    cgutils.voidptr_t]),
                                                "PyErr_SetString")
    builder.call(set_string, [exc, message])
    builder.ret_void()
    return fn


@contextlib.contextmanager
def _unbox_checked(layouts: bool = True):
    """While a module builds, if ``layouts`` (a group's ``check_layouts``), the Python wrapper of each
    export checks that each array it is given as C-contiguous (``f8[::1]``, ``f8[:, ::1]``) or
    Fortran-contiguous (``f8[::1, :]``) is so, and raises ValueError (:data:`_LAYOUT_ERROR`) where one
    is not: ``numba.pycc``'s wrapper checks only the item size, and the compiled code addresses such an
    array by its shape alone, so a strided view would be read and written at the wrong places,
    silently. The test is NumPy's (strides of the dimensions of length 1 ignored, an empty array
    contiguous): about seven instructions per array and call (a group whose callers make their arrays
    themselves does without: the full step's 1.8 M instructions in the bed run). Arrays of any layout
    (``f8[:]``) are not checked. And, in every module, the errors of the wrapper's unboxing (this one,
    numba's own TypeError for an argument that is no array or has another item size) are raised with
    CPython's exception classes: numba names each by its C variable (``PyExc_TypeError``),
    whose address its JIT maps to the class, where the linker of a module gives the variable's own
    address, which crashed the process. Where this numba has no such unboxing registry, nothing is
    changed."""
    try:
        from numba.core import boxing, cgutils, pythonapi, types  # (boxing registers the unboxing)

        registry = pythonapi._unboxers.functions
        if registry.get(types.Array) is not boxing.unbox_array:
            raise KeyError
        unbox = registry[types.Array]
    except (ImportError, AttributeError, KeyError):
        yield
        return

    def unbox_checked(typ, obj, c):
        native = unbox(typ, obj, c)
        if typ.layout not in ("C", "F") or not typ.ndim:
            return native
        builder = c.builder
        ary = c.context.make_array(typ)(c.context, builder, value=native.value)
        shape = cgutils.unpack_tuple(builder, ary.shape, typ.ndim)
        strides = cgutils.unpack_tuple(builder, ary.strides, typ.ndim)
        one = shape[0].type(1)
        ok, empty, expected = cgutils.true_bit, cgutils.false_bit, ary.itemsize
        for dim in (reversed(range(typ.ndim)) if typ.layout == "C" else range(typ.ndim)):
            packed = builder.or_(builder.icmp_signed("<=", shape[dim], one),
                                 builder.icmp_signed("==", strides[dim], expected))
            ok = builder.and_(ok, packed)
            empty = builder.or_(empty, builder.icmp_signed("==", shape[dim], shape[dim].type(0)))
            expected = builder.mul(expected, shape[dim])
        bad = builder.and_(builder.not_(native.is_error), builder.not_(builder.or_(ok, empty)))
        with builder.if_then(bad, likely=False):
            which = "C-contiguous" if typ.layout == "C" else "Fortran-contiguous"
            message = c.context.insert_const_string(builder.module, _LAYOUT_ERROR.format(which))
            meminfo = ary.meminfo if c.context.enable_nrt else cgutils.voidptr_t(None)
            builder.call(_layout_error(builder.module, c.pyapi), [meminfo, message])
        return type(native)(native.value, is_error=builder.or_(native.is_error, bad), cleanup=native.cleanup)

    get_c_object = pythonapi.PythonAPI.get_c_object

    def exception_class(self, name):  # CPython's PyExc_* variable's value (its JIT maps the name to the class)
        if not name.startswith("PyExc_"):
            return get_c_object(self, name)
        gv = self.context.get_c_value(self.builder, self.pyobj, name, dllimport=True)
        return self.builder.load(self.builder.bitcast(gv, self.pyobj.as_pointer()))

    if layouts:
        registry[types.Array] = unbox_checked
    pythonapi.PythonAPI.get_c_object = exception_class
    try:
        yield
    finally:
        registry[types.Array] = unbox
        pythonapi.PythonAPI.get_c_object = get_c_object


def _unliteral(dispatcher):
    """``dispatcher`` typed on its arguments' plain types where a caller passes a constant (numba
    would otherwise compile a helper again for each literal it is called with, ``Literal[int](0)``
    besides ``int64``: the same machine code but for folded constants, typed and optimised once more;
    the hysteretic law's helpers, called with the element test's element 0 and the column's element
    index, were each compiled twice)."""
    from numba.core import types

    resolve = dispatcher.get_call_template

    def get_call_template(args, kws):
        return resolve(tuple(types.unliteral(a) for a in args), {k: types.unliteral(v) for k, v in kws.items()})

    dispatcher.get_call_template = get_call_template
    return dispatcher


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
            if f not in _HELPER_DISPATCHERS:
                _HELPER_DISPATCHERS[f] = _unliteral(numba.njit(nogil=True, no_cpython_wrapper=True,
                                                               no_cfunc_wrapper=True)(f))
            g[name] = _HELPER_DISPATCHERS[f]
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
          jit: bool = True, check_layouts: bool = False) -> dict | None:
    """Several kernels in one ahead-of-time module (one build, one import): ``exports`` {name:
    (func, signature)}, ``helpers`` the plain functions they call (compiled with them). Returns
    {name: compiled function} as :func:`kernel` does for one, or None. With ``check_layouts`` the
    module's exports raise ValueError for an array not of the layout their signature declares (where
    callers pass arrays they did not make; :func:`_unbox_checked`), else such an array is read by its
    shape alone (a wrong answer)."""
    if group_name in _LOADED:
        return _LOADED[group_name]
    if jit_disabled():  # the plain Python functions (module docstring): debugging only
        out = _LOADED[group_name] = {name: func for name, (func, _sig) in exports.items()}
        return out
    if os.environ.get("TWOFLUID_KERNELS_PROBE"):  # build_all's probe: what is there, nothing built
        build = jit = False
    out = None
    helpers = tuple(getattr(f, "py_func", f) for f in helpers)  # a helper the JIT path replaced
    exports = {k: (getattr(f, "py_func", f), sig) for k, (f, sig) in exports.items()}
    module = _group_name(group_name, exports, helpers, check_layouts)
    path = _find(module)
    folder = cache_dir()
    if path is None and build and folder is not None:
        with _lock(folder, module):  # one build at a time per module; the others wait, then load it
            path = _find(module) or _build(folder, module, exports, helpers, check_layouts)
    if path is not None:
        try:
            mod = _import(path, module)
            out = {name: getattr(mod, name) for name in exports}
        except (ImportError, AttributeError, OSError):
            out = None
    if out is None and jit:
        out = _jit(module, exports, helpers, folder)
    if out is not None or not jit:
        _LOADED[group_name] = out
    return out


@contextlib.contextmanager
def _lock(folder: Path, module: str):
    """An exclusive lock on ``folder/.<module>.lock`` (released when the process ends, killed or
    not); leftovers of a build killed half-way are removed under it. Without ``fcntl`` (Windows)
    no lock: two builds then both write the module, each atomically."""
    try:
        import fcntl
    except ImportError:
        yield
        return
    try:
        fh = open(folder / f".{module}.lock", "a")
    except OSError:
        yield
        return
    with fh:
        fcntl.flock(fh, fcntl.LOCK_EX)
        for tmp in folder.glob(f".{module}.*.tmp"):  # a build killed between its copy and rename
            with contextlib.suppress(OSError):
                tmp.unlink()
        yield


def _jit(module: str, exports: dict, helpers: tuple, folder: Path | None) -> dict:
    """The group as ``numba.njit`` functions: cached in ``folder/jit/<module>`` (the group's hash
    keys the cache, so that an edited callee in another file is recompiled, which numba's own
    cache does not see), in memory only where no folder is writable (one line says so)."""
    try:
        import numba
    except ImportError:
        raise ImportError("twofluid needs numba for its kernels (pip install numba; README, "
                          "'Dependencies'); TWOFLUID_DISABLE_JIT=1 runs them as plain Python, "
                          "for debugging only") from None
    try:  # numba's first compile or cache load imports all of scipy.linalg (~0.1 s) only to
        # find its cython_blas, which these kernels do not use: that module is loaded alone
        from .scipy_kernels import _extension

        _extension("scipy.linalg", "cython_blas")
    except (ImportError, OSError):
        pass
    cache = None
    if folder is not None:
        cache = folder / "jit" / module
        try:
            cache.mkdir(parents=True, exist_ok=True)
        except OSError:
            cache = None
    if cache is None:
        _warn_unwritable()
    saved = numba.config.CACHE_DIR
    try:  # numba reads its cache folder when a function is decorated
        numba.config.CACHE_DIR = str(cache) if cache is not None else saved
        njit = numba.njit(cache=cache is not None, nogil=True)
        for f in helpers:  # the module's own name for each helper now calls the compiled one
            f = getattr(f, "py_func", f)
            f.__globals__[f.__name__] = njit(f)
        return {name: njit(getattr(func, "py_func", func)) for name, (func, _sig) in exports.items()}
    finally:
        numba.config.CACHE_DIR = saved


def _build_group(spec: str) -> None:
    """Build one group by calling its getter (``"module:getter"`` of :data:`GROUPS`)."""
    import importlib

    module, getter = spec.split(":")
    getattr(importlib.import_module(module), getter)()


def _probe() -> None:
    """Print the groups of :data:`GROUPS` that have no module in the cache folder (in a process of
    its own, ``TWOFLUID_KERNELS_PROBE`` set: nothing is built or compiled)."""
    for name, spec in GROUPS:
        with contextlib.suppress(Exception):  # a getter that fails on a group not built: not built
            _build_group(spec)
        if not _LOADED.get(name):
            print(name)


#: groups built in one process by :func:`build_all`, in this order: each set shares helpers (the band
#: solver's and the closure laws' in the first, the shear laws' in the second), which that process
#: then compiles once (:data:`_HELPER_DISPATCHERS`); a group not listed is a set of its own
FAMILIES = (
    ("reduced_1d", "band_22", "common_1d", "band_lu", "full_1d", "closures_1d", "extrapolation", "newton_accept",
     "column_step"),
    ("hysteretic", "shear_substeps", "spectra_peaks", "column_record"),
)


def build_all(workers: int | None = None) -> list[str]:
    """Build every group of :data:`GROUPS` not yet in the cache folder, a set of :data:`FAMILIES` per
    process, ``workers`` processes at a time (default: the CPU count); returns the groups that could
    not be built ahead of time (empty where all were). With nothing to build it costs one process's
    imports. The builders are forked from this process once it has set numba up (:func:`_fork_ready`),
    else started afresh.

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
    code = ("import sys; from twofluid import compiled\n"
            "compiled._build_and_report(zip(sys.argv[1::2], sys.argv[2::2]), sys.stdout)")
    specs = dict(GROUPS)
    listed = [n for family in FAMILIES for n in family]
    sets = [[n for n in family if n in missing] for family in FAMILIES]
    sets += [[n] for n, _ in GROUPS if n in missing and n not in listed]
    pending = [s for s in sets if s]
    fork = bool(pending) and _fork_ready()
    running, failed = [], []
    while pending or running:
        while pending and len(running) < workers:
            names = pending.pop(0)
            pairs = [(specs[n], n) for n in names]
            running.append((names, _Forked(pairs, env) if fork else subprocess.Popen(
                [sys.executable, "-c", code, *[a for pair in pairs for a in pair]], env=env,
                stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)))
        time.sleep(0.05)
        for r in [r for r in running if r[1].poll() is not None]:
            running.remove(r)
            report = dict(line.split()[:2] for line in r[1].communicate()[0].splitlines() if len(line.split()) >= 2)
            failed += [n for n in r[0] if report.get(n) != "aot"]
    return [n for n, _ in GROUPS if n in failed]


def _build_and_report(pairs, out) -> None:
    """Build the groups ``pairs`` ((getter spec, group name) of :data:`GROUPS`) in this process, as
    :func:`build_all`'s builders do, writing a line per group to ``out``: its name and ``aot`` (built
    ahead of time) or ``jit``."""
    with _young_gc_only():
        for spec, name in pairs:
            _build_group(spec)
            got = _LOADED.get(name) or {None: None}
            how = "aot" if all(type(f).__name__ == "builtin_function_or_method" for f in got.values()) else "jit"
            print(name, how, file=out, flush=True)


def _fork_ready() -> bool:
    """Whether :func:`build_all` may fork its builders from this process, and if so numba set up in it
    first (imported, ``numba.pycc`` too, and its typing and target contexts' registries loaded: 0.9 s
    of CPU that each builder started afresh pays, once for all of them): on Linux, in a process with
    one thread, numba's JIT not disabled by its environment variable (read when numba is imported),
    and no kernel module imported or group loaded (a forked builder starts as a fresh one would:
    ``twofluid build-kernels``). False elsewhere (the builders are then started afresh)."""
    import threading
    import warnings

    if not sys.platform.startswith("linux") or not hasattr(os, "fork") or threading.active_count() > 1 or \
            _LOADED or os.environ.get("NUMBA_DISABLE_JIT", "0") not in ("", "0") or \
            any(spec.split(":")[0] in sys.modules for _, spec in GROUPS):
        return False
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # numba.pycc's pending deprecation
            from numba.core.registry import cpu_target
            from numba.pycc import CC  # noqa: F401

            cpu_target.typing_context.refresh()
            cpu_target.target_context.refresh()
    except Exception:  # no numba, or one that cannot: the builders find out for themselves
        return False
    return True


class _Forked:
    """A builder of :func:`build_all` forked from this process (:func:`_fork_ready`), building
    ``pairs`` (:func:`_build_and_report`) with the environment ``env``; ``poll()`` and
    ``communicate()`` as a ``subprocess.Popen`` whose standard output is a pipe (its standard error,
    and its own standard output, go nowhere)."""

    def __init__(self, pairs, env: dict):
        read, write = os.pipe()
        sys.stdout.flush()
        sys.stderr.flush()
        pid = os.fork()
        if pid == 0:  # the builder: it leaves by os._exit alone (nothing of this process's exit runs twice)
            status = 1
            try:
                os.close(read)
                null = os.open(os.devnull, os.O_WRONLY)
                os.dup2(null, 1)
                os.dup2(null, 2)
                os.environ.clear()
                os.environ.update(env)
                with os.fdopen(write, "w") as out:
                    _build_and_report(pairs, out)
                status = 0
            finally:
                os._exit(status)
        os.close(write)
        self.pid, self.returncode, self._out = pid, None, os.fdopen(read)

    def poll(self):
        if self.returncode is None:
            pid, status = os.waitpid(self.pid, os.WNOHANG)
            if pid:
                self.returncode = os.waitstatus_to_exitcode(status)
        return self.returncode

    def communicate(self):
        with self._out:
            return self._out.read(), None
