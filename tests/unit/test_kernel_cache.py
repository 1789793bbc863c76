"""The kernel cache (twofluid.compiled) under the ways a real installation meets it: an edited
callee in another file, two processes building at once, a build killed half-way, a cache nobody
can write, and the groups a run or an ensemble builds before it starts.

A toy kernel in two files stands for the project's: ``kmod_a.total`` calls ``kmod_b.helper`` (a
listed helper) and reads ``kmod_b.OFFSET`` (a constant numba freezes into the caller)."""
from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest

import twofluid
from twofluid import compiled

KMOD_A = textwrap.dedent('''
    import kmod_b

    def total(x):
        s = 0.0
        for i in range(x.size):
            s += kmod_b.helper(x[i])
        return s + kmod_b.OFFSET
''')
KMOD_B = "SCALE = 2.0\nOFFSET = 0.5\n\n\ndef helper(v):\n    return SCALE * v\n"
SIGNATURE = "f8(f8[::1])"
X = np.linspace(0.0, 1.0, 11)


def expected(scale: float = 2.0, offset: float = 0.5) -> float:
    """The toy's value, summed in the kernel's order."""
    s = 0.0
    for v in X:
        s += scale * v
    return s + offset


# the child: builds or loads the group, prints its value, how it was had and whether numba was loaded
CHILD = textwrap.dedent('''
    import sys
    sys.path.insert(0, sys.argv[1])
    if sys.argv[2] == "jit":
        sys.modules["numba.pycc"] = None  # no ahead-of-time build: numba's JIT and its cache
    import numpy as np
    import kmod_a, kmod_b
    from twofluid import compiled
    out = compiled.group("toy_total", {"total": (kmod_a.total, %r)}, helpers=(kmod_b.helper,))
    f = out["total"]
    how = "aot" if type(f).__name__ == "builtin_function_or_method" else "jit"
    print(repr(f(np.linspace(0.0, 1.0, 11))), how, "numba" in sys.modules)
''' % SIGNATURE)


def _env(cache: Path, **extra) -> dict:
    env = {k: v for k, v in os.environ.items() if k not in ("TWOFLUID_DISABLE_JIT", "NUMBA_DISABLE_JIT")}
    env.update(TWOFLUID_CACHE_DIR=str(cache), **extra)
    return env


def _edit(path: Path, text: str) -> None:
    """Write ``text`` to ``path`` as a later edit: CPython takes a module's cached bytecode
    (``__pycache__``) as current where the source has the size and the modification time, in whole
    seconds, it was compiled from, so an edit of the same size in the same second as the last import
    would be read as the old module whatever the kernels' cache does. The edit's time is put 2 s
    after the file's last one, as an edit by hand comes."""
    before = path.stat().st_mtime_ns
    path.write_text(text)
    later = max(path.stat().st_mtime_ns, before + 2_000_000_000)
    os.utime(path, ns=(later, later))


def _child(src: Path, cache: Path, mode: str = "aot", prefix: list[str] | None = None, **env):
    r = subprocess.run([*(prefix or []), sys.executable, "-c", CHILD, str(src), mode], capture_output=True,
                       text=True, env=_env(cache, **env), timeout=600)
    assert r.returncode == 0, r.stderr[-3000:]
    value, how, numba_loaded = r.stdout.split()
    return float(value), how, numba_loaded == "True", r.stderr


@pytest.fixture
def toy(tmp_path):
    pytest.importorskip("numba")
    src = tmp_path / "src"
    src.mkdir()
    (src / "kmod_a.py").write_text(KMOD_A)
    (src / "kmod_b.py").write_text(KMOD_B)
    return src, tmp_path / "cache"


def _aot_or_skip(how: str) -> None:
    if how != "aot":
        pytest.skip("no ahead-of-time build here (numba.pycc or a C toolchain missing): the JIT is used")


@pytest.mark.parametrize("mode", ["aot", "jit"])
def test_editing_a_callee_in_another_file_recompiles(toy, mode):
    """numba's own cache keys a function on its own file only; the group's module (and the JIT's
    cache folder) is keyed on every file it takes code or constants from, so an edited helper or
    constant in another file gives the new result, not the stale one."""
    src, cache = toy
    value, how, _, _ = _child(src, cache, mode)
    if mode == "aot":
        _aot_or_skip(how)
    assert how == mode and value == expected()
    assert _child(src, cache, mode)[0] == value  # found again (same key)
    _edit(src / "kmod_b.py", KMOD_B.replace("SCALE = 2.0", "SCALE = 3.0"))
    assert _child(src, cache, mode)[0] == expected(3.0)
    _edit(src / "kmod_b.py", KMOD_B.replace("SCALE = 2.0", "SCALE = 3.0").replace("OFFSET = 0.5",
                                                                                        "OFFSET = 1.5"))
    assert _child(src, cache, mode)[0] == expected(3.0, 1.5)


def test_the_package_version_keys_the_cache(toy, monkeypatch):
    src, _ = toy
    monkeypatch.syspath_prepend(str(src))
    import kmod_a
    import kmod_b

    exports = {"total": (kmod_a.total, SIGNATURE)}
    name = compiled._group_name("toy_total", exports, (kmod_b.helper,))
    monkeypatch.setattr(twofluid, "__version__", twofluid.__version__ + ".dev1")
    assert compiled._group_name("toy_total", exports, (kmod_b.helper,)) != name
    assert str(src / "kmod_b.py") in compiled._sources([kmod_a.total])


def test_two_processes_building_at_once_both_get_working_kernels(toy):
    """Started together on an empty cache: one builds, the other waits for it and loads its module;
    both answer, and the cache holds one module and no half-written file."""
    src, cache = toy
    procs = [subprocess.Popen([sys.executable, "-c", CHILD, str(src), "aot"], stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, text=True, env=_env(cache)) for _ in range(2)]
    outs = [p.communicate(timeout=600) for p in procs]
    assert all(p.returncode == 0 for p in procs), [o[1][-2000:] for o in outs]
    results = [o[0].split() for o in outs]
    _aot_or_skip(results[0][1])
    assert [float(r[0]) for r in results] == [expected()] * 2 and {r[1] for r in results} == {"aot"}
    suffix = compiled.importlib.machinery.EXTENSION_SUFFIXES[0]
    assert len(list(cache.glob(f"_twofluid_toy_total_*{suffix}"))) == 1
    assert not list(cache.glob("*.tmp"))
    assert sum("compiling the numerical kernels" in o[1] for o in outs) == 1  # one built, one waited


def test_a_build_killed_half_way_then_rerun_ends_with_working_kernels(toy, monkeypatch):
    """A build killed while it compiles (its lock held) and a half-copied module left beside it:
    the next run builds the module, loads it and removes the leftover."""
    src, cache = toy
    proc = subprocess.Popen([sys.executable, "-c", CHILD, str(src), "aot"], stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL, env=_env(cache))
    deadline = time.monotonic() + 300
    while not list(cache.glob(".*.lock")) and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.02)
    time.sleep(0.3)  # into the compilation
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    monkeypatch.syspath_prepend(str(src))
    import kmod_a
    import kmod_b

    module = compiled._group_name("toy_total", {"total": (kmod_a.total, SIGNATURE)}, (kmod_b.helper,))
    cache.mkdir(exist_ok=True)
    (cache / f".{module}.12345.tmp").write_bytes(b"\x7fELF half a module")
    value, how, _, _ = _child(src, cache)
    _aot_or_skip(how)
    assert value == expected()
    assert not list(cache.glob("*.tmp"))


def _readonly_prefix(paths: list[Path]) -> list[str]:
    """A command prefix that runs its command with ``paths`` read-only: a private mount namespace
    with read-only bind mounts where this runs as root (root writes through file modes); else
    None (the caller then takes the write permission away instead)."""
    if os.geteuid() != 0:
        return None
    script = " && ".join(f'mount --bind -o ro "${i + 1}" "${i + 1}"' for i in range(len(paths))) + \
        f' && shift {len(paths)} && exec "$@"'
    prefix = ["unshare", "-m", "sh", "-c", script, "sh", *map(str, paths)]
    if shutil.which("unshare") is None or subprocess.run([*prefix, "true"], capture_output=True).returncode:
        pytest.skip("cannot make a folder read-only for root here (no mount namespace)")
    return prefix


@pytest.fixture
def readonly(tmp_path):
    """run(paths, cmd) -> the command's CompletedProcess with ``paths`` read-only."""
    changed = []

    def run(paths, cmd, env):
        prefix = _readonly_prefix(paths)
        if prefix is None:
            for p in paths:
                changed.append((p, p.stat().st_mode))
                p.chmod(0o555)
        return subprocess.run([*(prefix or []), *cmd], capture_output=True, text=True, env=env, timeout=900)

    yield run
    for p, mode in changed:
        p.chmod(mode)


def _package_home_cache(tmp_path, cache):
    home = tmp_path / "home"
    home.mkdir()
    return [Path(twofluid.__file__).parent, home, cache], home


def test_a_readonly_cache_with_the_module_built_loads_it(toy, tmp_path, readonly):
    """The package folder, HOME and the cache folder read-only, the module built in the cache: it
    is loaded (no numba, nothing printed)."""
    src, cache = toy
    _aot_or_skip(_child(src, cache)[1])
    paths, home = _package_home_cache(tmp_path, cache)
    r = readonly(paths, [sys.executable, "-c", CHILD, str(src), "aot"], _env(cache, HOME=str(home)))
    assert r.returncode == 0, r.stderr[-3000:]
    value, how, numba_loaded = r.stdout.split()
    assert (float(value), how, numba_loaded, r.stderr) == (expected(), "aot", "False", "")


def test_a_readonly_empty_cache_compiles_in_memory_and_says_why(toy, tmp_path, readonly):
    """Nothing built and nowhere to build: the kernel is compiled for the process alone (right
    answer, slower), with one line naming the folders and the way out."""
    src, cache = toy
    cache.mkdir()
    paths, home = _package_home_cache(tmp_path, cache)
    r = readonly(paths, [sys.executable, "-c", CHILD, str(src), "aot"], _env(cache, HOME=str(home)))
    assert r.returncode == 0, r.stderr[-3000:]
    value, how, _ = r.stdout.split()
    assert float(value) == expected() and how == "jit"
    lines = r.stderr.splitlines()
    assert len(lines) == 1 and "no writable kernel cache folder" in lines[0] and "TWOFLUID_CACHE_DIR" in lines[0]
    assert not list(cache.iterdir())


SHORT_BED = textwrap.dedent('''
    import json, sys
    import twofluid
    c = twofluid.load_case("fluidized-bed-step")
    c["time"]["end"], c["output"]["times"] = 0.2, [0.2]
    r = twofluid.run_case(c, None)
    p = r.tables["profiles.csv"]
    print(json.dumps({"status": r.summary["status"], **{k: [float(v) for v in p[k]] for k in p}}))
''')


def _short_bed(env, prefix=None):
    r = subprocess.run([*(prefix or []), sys.executable, "-c", SHORT_BED], capture_output=True, text=True,
                       env=env, timeout=900)
    assert r.returncode == 0, r.stderr[-3000:]
    import json

    return json.loads(r.stdout.splitlines()[-1]), r.stderr


def test_a_run_with_its_kernels_in_a_readonly_cache(tmp_path, readonly):
    """A bed run whose kernels are built, with the package folder, HOME and the cache read-only,
    completes as with a writable cache, and prints nothing about kernels."""
    pytest.importorskip("numba")
    cache = compiled.cache_dir()
    if cache is None:
        pytest.skip("no writable kernel cache to build the run's kernels in")
    env = _env(cache)
    ref, _ = _short_bed(env)  # builds what is missing
    paths, home = _package_home_cache(tmp_path, cache)
    r = readonly(paths, [sys.executable, "-c", SHORT_BED], dict(env, HOME=str(home)))
    assert r.returncode == 0, r.stderr[-3000:]
    import json

    got = json.loads(r.stdout.splitlines()[-1])
    assert got == ref and ref["status"] == "completed"
    assert "kernel" not in r.stderr


SHORT_SITE = textwrap.dedent('''
    import json
    import numpy as np
    import twofluid
    c = twofluid.load_case("liquefaction-layered-site")
    c["time"]["end"], c["output"]["times"], c["ground_motion"]["duration"] = 0.06, [0.06], 0.06
    r = twofluid.run_case(c, None)
    out = {"status": r.summary["status"]}
    for name, table in r.tables.items():
        for k, v in table.items():
            if np.asarray(v).dtype.kind == "f":
                out[f"{name}:{k}"] = [float(x) for x in v]
    print(json.dumps(out))
''')


def _short_run(script, env):
    r = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, env=env, timeout=900)
    assert r.returncode == 0, r.stderr[-3000:]
    import json

    return json.loads(r.stdout.splitlines()[-1])


@pytest.mark.parametrize("script", [SHORT_BED, SHORT_SITE], ids=["fluidized-bed-step", "layered-site"])
def test_the_unjitted_path_equals_the_compiled_one(script):
    """The same source run as plain Python (TWOFLUID_DISABLE_JIT=1) and compiled: a short run's
    tables (the bed's ten steps; the layered site's first three steps of shaking, the hysteretic
    law) agree to 1e-12 of each column's largest magnitude."""
    pytest.importorskip("numba")
    cache = compiled.cache_dir()
    if cache is None:
        pytest.skip("no writable kernel cache")
    fast = _short_run(script, _env(cache))
    slow = _short_run(script, _env(cache, TWOFLUID_DISABLE_JIT="1"))
    assert fast["status"] == slow["status"] == "completed" and fast.keys() == slow.keys()
    for k in fast:
        if k == "status":
            continue
        a, b = np.array(fast[k]), np.array(slow[k])
        assert np.array_equal(np.isnan(a), np.isnan(b)), k  # (a field undefined where there are no solids)
        a, b = a[~np.isnan(a)], b[~np.isnan(b)]
        scale = max(np.abs(a).max(initial=0.0), 1e-300)
        assert np.abs(a - b).max(initial=0.0) <= 1e-12 * scale, k


RECORD = textwrap.dedent('''
    import sys
    import twofluid
    from twofluid import compiled
    seen, real = set(), compiled.group
    compiled.group = lambda name, *a, **k: (seen.add(name), real(name, *a, **k))[1]
    compiled.prepare = lambda names: None  # what the run itself loads
    case = twofluid.load_case(sys.argv[1])
    end = float(sys.argv[2])
    case["time"]["end"], case["output"]["times"] = end, [end]
    if "ground_motion" in case:
        case["ground_motion"]["duration"] = end
    twofluid.run_case(case, None)
    print(" ".join(sorted(seen)))
    print(" ".join(compiled.groups_for(case)))
''')


@pytest.mark.parametrize("name", ["fluidized-bed-step", "slis-step-change", "liquefaction-elcentro",
                                  "liquefaction-layered-site"])
def test_groups_for_names_every_group_a_short_run_loads(name):
    """:func:`compiled.groups_for` is what :func:`compiled.prepare` builds before a run: a group a
    short run of each 1D model (and both shear laws) loads beyond it would be built mid-run."""
    pytest.importorskip("numba")
    if compiled.cache_dir() is None:
        pytest.skip("no writable kernel cache")
    r = subprocess.run([sys.executable, "-c", RECORD, name, "0.1"], capture_output=True, text=True,
                       env=_env(compiled.cache_dir()), timeout=900)
    assert r.returncode == 0, r.stderr[-3000:]
    seen, planned = (set(line.split()) for line in r.stdout.splitlines()[-2:])
    assert seen and seen <= planned, seen - planned


def test_the_full_model_builds_none_of_the_reduced_models_groups():
    """The default case (the full model) makes its steps in one compiled call (group ``full_1d``, which
    compiles the few functions of ``reduced_kernel`` it calls itself): its run neither plans nor loads
    the reduced model's iterate or its band solvers."""
    pytest.importorskip("numba")
    if compiled.cache_dir() is None:
        pytest.skip("no writable kernel cache")
    r = subprocess.run([sys.executable, "-c", RECORD, "fluidized-bed-step", "0.1"], capture_output=True,
                       text=True, env=_env(compiled.cache_dir()), timeout=900)
    assert r.returncode == 0, r.stderr[-3000:]
    seen, planned = (set(line.split()) for line in r.stdout.splitlines()[-2:])
    assert "full_1d" in seen and not {"reduced_1d", "band_22"} & (seen | planned)


def test_a_helper_called_with_a_constant_compiles_once():
    """A helper's dispatcher is typed on plain argument types: called with a constant by one caller
    and a variable by another it is compiled once (numba alone compiles a literal-typed copy too)."""
    numba = pytest.importorskip("numba")

    def helper(x, i):
        return x[i] * 2.0

    d = compiled._unliteral(numba.njit(helper))

    def by_constant(x):
        return d(x, 0)

    def by_index(x, i):
        return d(x, i)

    x = np.arange(3.0)
    assert numba.njit(by_constant)(x) == 0.0 and numba.njit(by_index)(x, 2) == 4.0
    assert len(d.signatures) == 1, d.signatures


def test_prepare_announces_the_groups_it_builds_in_one_line(toy, tmp_path, monkeypatch, capsys):
    monkeypatch.setenv("TWOFLUID_CACHE_DIR", str(tmp_path / "empty"))
    monkeypatch.delenv("TWOFLUID_BUILDING_KERNELS", raising=False)
    monkeypatch.setattr(compiled, "_ANNOUNCED", False)
    built = []
    monkeypatch.setattr(compiled, "_build_group", lambda spec: (built.append(spec),
                                                                compiled._announce(tmp_path, spec.split(":")[0])))
    monkeypatch.setattr(compiled, "GROUPS", (("g1", "g1:x"), ("g2", "g2:x")))
    compiled.prepare(["g1", "g2", "unknown"])
    err = capsys.readouterr().err.splitlines()
    assert built == ["g1:x", "g2:x"]
    assert len(err) == 1 and err[0].startswith("twofluid: compiling the numerical kernels this run needs, once: g1, g2")


def test_an_ensemble_builds_its_kernels_in_the_parent_before_any_worker(monkeypatch, tmp_path):
    """run_members builds the groups of its members' models before it opens the cluster."""
    from twofluid.ensemble import engine
    from twofluid.ensemble.members import Member

    calls = []
    monkeypatch.setattr(compiled, "prepare", lambda names: calls.append(("prepare", sorted(set(names)))))

    class Stop(Exception):
        pass

    def no_cluster(*a, **k):
        calls.append(("cluster",))
        raise Stop

    monkeypatch.setattr(engine, "cluster_client", no_cluster)
    case = twofluid.load_case("slis-step-change")
    with pytest.raises(Stop):
        engine.run_members([Member(0, {}, case, "h0"), Member(1, {}, case, "h1")], [], tmp_path / "out")
    assert calls == [("prepare", sorted(compiled.groups_for(case))), ("cluster",)]


def _toy_build(toy, monkeypatch):
    """The toy modules (kmod_a, kmod_b) imported for a build of their own: the toy's cache folder, a
    build as ``build-kernels`` makes it, the JIT not disabled."""
    src, cache = toy
    monkeypatch.syspath_prepend(str(src))
    monkeypatch.setenv("TWOFLUID_CACHE_DIR", str(cache))
    monkeypatch.setenv("TWOFLUID_BUILDING_KERNELS", "1")
    monkeypatch.delenv("TWOFLUID_DISABLE_JIT", raising=False)
    monkeypatch.delenv("NUMBA_DISABLE_JIT", raising=False)
    import kmod_a
    import kmod_b

    return kmod_a, kmod_b


def test_the_garbage_collector_collects_only_new_objects_while_a_build_compiles_and_is_restored(toy, monkeypatch):
    """numba's compile of a module runs with the build's collector thresholds (the older generations
    of the millions of objects a build keeps are not scanned again and again); the process's own
    thresholds come back after, and a collector switched off stays off."""
    import gc

    pycc = pytest.importorskip("numba.pycc")
    kmod_a, kmod_b = _toy_build(toy, monkeypatch)

    seen = []
    compile_module = pycc.CC.compile
    monkeypatch.setattr(pycc.CC, "compile", lambda self: (seen.append(gc.get_threshold()), compile_module(self))[1])
    before = gc.get_threshold()
    assert before != compiled._BUILD_GC_THRESHOLDS
    out = compiled.group("toy_gc", {"total": (kmod_a.total, SIGNATURE)}, helpers=(kmod_b.helper,))
    monkeypatch.delitem(compiled._LOADED, "toy_gc")
    if type(out["total"]).__name__ != "builtin_function_or_method":
        pytest.skip("no ahead-of-time build here (numba.pycc or a C toolchain missing): the JIT is used")
    assert out["total"](X) == expected()
    assert seen == [compiled._BUILD_GC_THRESHOLDS] and gc.get_threshold() == before
    gc.disable()
    try:
        with compiled._young_gc_only():
            assert not gc.isenabled()
        assert not gc.isenabled() and gc.get_threshold() == before
    finally:
        gc.enable()


def test_a_helpers_ir_is_optimised_once_in_the_module_that_links_it(toy, monkeypatch):
    """While a module builds, numba's LLVM passes run on the module's library alone (its exports and
    the helpers linked into it), not first on each helper's library: the kernel computes the same,
    and the helper libraries' optimisation is numba's own again after the build."""
    pytest.importorskip("numba.pycc")
    from numba.core import codegen

    kmod_a, kmod_b = _toy_build(toy, monkeypatch)

    optimised = []
    final, functions = codegen.CPUCodeLibrary._optimize_final_module, codegen.CPUCodeLibrary._optimize_functions
    monkeypatch.setattr(codegen.CPUCodeLibrary, "_optimize_final_module",
                        lambda self: (optimised.append(("module", type(self).__name__)), final(self))[1])
    monkeypatch.setattr(codegen.CPUCodeLibrary, "_optimize_functions",
                        lambda self, m: (optimised.append(("functions", type(self).__name__)), functions(self, m))[1])
    out = compiled.group("toy_opt", {"total": (kmod_a.total, SIGNATURE)}, helpers=(kmod_b.helper,))
    monkeypatch.delitem(compiled._LOADED, "toy_opt")
    if type(out["total"]).__name__ != "builtin_function_or_method":
        pytest.skip("no ahead-of-time build here (numba.pycc or a C toolchain missing): the JIT is used")
    assert out["total"](X) == expected()
    assert ("module", "AOTCodeLibrary") in optimised and ("functions", "AOTCodeLibrary") in optimised
    assert not [o for o in optimised if o[1] == "JITCodeLibrary"], optimised
    assert "_optimize_final_module" not in vars(codegen.JITCodeLibrary)
    assert "_optimize_functions" not in vars(codegen.JITCodeLibrary)


def test_numbas_typing_messages_are_plain_text_while_a_module_builds_and_restored_after():
    errors = pytest.importorskip("numba.core.errors")
    scheme = errors.termcolor()
    before = scheme.errmsg("No implementation")
    with compiled._plain_typing_messages():
        assert errors.termcolor().errmsg("No implementation") == "No implementation"
        assert errors.TypingError("No implementation").msg == "No implementation"
    assert scheme.errmsg("No implementation") == before and "_markup" not in vars(scheme)


def test_a_global_functions_call_is_typed_once_per_argument_types_while_a_module_builds():
    """Inside a build the typing context answers a repeated call of a global function (here
    ``math.sqrt`` of a float64, twice) from its first answer: the same signature, typed once; calls
    with other argument types are typed on their own; numba's own method is back after."""
    pytest.importorskip("numba")
    import math

    from numba.core import types, typing
    from numba.core.registry import cpu_target

    ctx = cpu_target.typing_context
    ctx.refresh()
    fnty = ctx.resolve_value_type(math.sqrt)
    resolve = typing.context.BaseContext.resolve_function_type
    typed = []
    calls = fnty.get_call_type

    def counted(context, args, kws):
        typed.append(tuple(args))
        return calls(context, args, kws)

    fnty.get_call_type = counted
    try:
        with compiled._typing_memo():
            a = ctx.resolve_function_type(fnty, (types.float64,), {})
            b = ctx.resolve_function_type(fnty, (types.float64,), {})
            c = ctx.resolve_function_type(fnty, (types.int64,), {})
    finally:
        del fnty.get_call_type
    assert a is b and a.return_type == types.float64 and c is not None
    assert typed == [(types.float64,), (types.int64,)]
    assert typing.context.BaseContext.resolve_function_type is resolve


def test_an_export_that_is_also_a_helper_is_compiled_once_for_the_module_and_its_callers(toy, monkeypatch):
    """An export listed among its group's helpers is exported through a stub calling the helper
    (``compiled._stub``): numba compiles it once, as the helper, and a kernel of another group built
    after it in the process that calls it with the same argument types gets that compile, not a second."""
    pytest.importorskip("numba.pycc")
    from numba.core import compiler

    kmod_a, kmod_b = _toy_build(toy, monkeypatch)
    compiles = []
    compile_extra = compiler.compile_extra

    def counted(typingctx, targetctx, func, *args, **kw):
        compiles.append(func.__qualname__)
        return compile_extra(typingctx, targetctx, func, *args, **kw)

    monkeypatch.setattr(compiler, "compile_extra", counted)
    monkeypatch.setattr("numba.pycc.compiler.compile_extra", counted)
    monkeypatch.setattr(compiled, "_HELPER_DISPATCHERS", {})
    first = compiled.group("toy_stub", {"total": (kmod_a.total, SIGNATURE)}, helpers=(kmod_a.total, kmod_b.helper))
    monkeypatch.delitem(compiled._LOADED, "toy_stub")
    if type(first["total"]).__name__ != "builtin_function_or_method":
        pytest.skip("no ahead-of-time build here (numba.pycc or a C toolchain missing): the JIT is used")
    assert first["total"](X) == expected()
    assert compiles.count("total") == 1 and "total_export" in compiles, compiles

    def twice(x):
        return 2.0 * kmod_a.total(x)

    compiles.clear()
    second = compiled.group("toy_stub_caller", {"twice": (twice, SIGNATURE)}, helpers=(kmod_a.total, kmod_b.helper))
    monkeypatch.delitem(compiled._LOADED, "toy_stub_caller")
    assert second["twice"](X) == 2.0 * expected()
    assert [c.rsplit(".", 1)[-1] for c in compiles] == ["twice"], compiles  # the first group's helper reused


def test_the_typed_containers_c_code_is_linked_only_into_a_module_that_calls_it(tmp_path):
    """numba's C sources of its typed dict, list and set (and their ``utils.c``) are compiled and linked
    only where a kernel's object file names one of their functions; numba's other sources always."""
    cext = [f"/numba/cext/{name}" for name in ("dictobject.c", "listobject.c", "setobject.c", "utils.c")]
    sources = ["/numba/pycc/modulemixin.c", *cext, "/numba/core/runtime/nrt.cpp", "/numba/cext/future.c"]
    plain, with_dict = tmp_path / "plain.o", tmp_path / "dict.o"
    plain.write_bytes(b"\x7fELF ... NRT_decref ... numba_gil_ensure")
    with_dict.write_bytes(b"\x7fELF ... numba_dict_new_sized ...")
    keep = ["/numba/pycc/modulemixin.c", "/numba/core/runtime/nrt.cpp"]
    assert compiled._containers_called(sources[:-1], [plain]) == keep
    assert compiled._containers_called(sources[:-1], [plain, with_dict]) == \
        ["/numba/pycc/modulemixin.c", cext[0], cext[3], "/numba/core/runtime/nrt.cpp"]
    assert compiled._containers_called(sources, [plain]) == sources[:1] + [cext[3]] + sources[-2:]  # (unknown: kept)
    assert compiled._containers_called(sources, [tmp_path / "missing.o"]) == sources
    assert compiled._containers_called(sources, None) == sources


def test_no_llvm_lock_event_is_broadcast_while_a_module_builds_and_the_callbacks_are_back_after():
    pytest.importorskip("numba")
    from llvmlite.binding import ffi

    before = list(ffi.lib._lock._cblist)
    assert before  # numba's, registered when it is imported
    with compiled._no_llvm_lock_events():
        assert ffi.lib._lock._cblist == []
    assert ffi.lib._lock._cblist == before


def test_build_kernels_forks_its_builders_from_a_process_that_set_numba_up_once(toy, monkeypatch):
    """Where no kernel module is imported yet (``twofluid build-kernels``), numba is set up once and the
    builders are forked from the process; they build as a fresh process would, and report each group.
    A process that imported a kernel module starts them afresh instead."""
    pytest.importorskip("numba.pycc")
    if not sys.platform.startswith("linux"):
        pytest.skip("builders are forked on Linux alone")
    src, cache = toy
    code = textwrap.dedent(f'''
        import sys
        sys.path.insert(0, {str(src)!r})
        from twofluid import compiled
        ready = compiled._fork_ready()
        import kmod_a, kmod_b
        def build():
            return compiled.group("toy_fork", {{"total": (kmod_a.total, {SIGNATURE!r})}}, helpers=(kmod_b.helper,))
        kmod_a.build = build
        builder = compiled._Forked([("kmod_a:build", "toy_fork")], dict(__import__("os").environ))
        while builder.poll() is None:
            pass
        print(ready, builder.returncode, builder.communicate()[0].strip().replace(" ", ":"), "toy_fork" in compiled._LOADED)
        import twofluid.models.reduced_kernel
        print(compiled._fork_ready())
    ''')
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=_env(cache), timeout=600)
    assert r.returncode == 0, r.stderr[-3000:]
    first, second = r.stdout.split("\n")[:2]
    ready, status, report, loaded_here = first.split()
    assert ready == "True" and status == "0" and loaded_here == "False"
    _aot_or_skip(report.split(":")[1])
    assert report == "toy_fork:aot" and list(cache.glob("_twofluid_toy_fork_*"))
    assert second == "False"


def test_a_functions_lowering_is_looked_up_once_per_signature_while_a_module_builds():
    """Inside a build numba's target context answers a repeated lookup of a function's implementation
    for a signature from its first answer (the same implementation); a failing lookup raises each
    time, and one of ``__array__`` (make_array's probe) without looking again; numba's own method is
    back after."""
    pytest.importorskip("numba")
    import operator

    from numba.core import base, types
    from numba.core.registry import cpu_target
    from numba.core.typing import signature

    ctx = cpu_target.target_context
    ctx.refresh()
    looked = []
    get_function = base.BaseContext.get_function

    def counted(self, fn, sig, _firstcall=True):
        looked.append((fn, _firstcall))
        return get_function(self, fn, sig, _firstcall)

    add = signature(types.float64, types.float64, types.float64)
    array = types.float64[::1]
    with pytest.MonkeyPatch.context() as m:
        m.setattr(base.BaseContext, "get_function", counted)
        with compiled._lowering_memo():
            a = ctx.get_function(operator.add, add)
            b = ctx.get_function(operator.add, add)
            c = ctx.get_function(operator.mul, add)
            for _ in range(2):
                with pytest.raises(NotImplementedError):
                    ctx.get_function("__array__", signature(array, array))
                with pytest.raises(NotImplementedError):
                    ctx.get_function("no_such_function", add)
        assert base.BaseContext.get_function is counted
    assert a is b and a is not c
    assert [fn for fn, first in looked if first] == [operator.add, operator.mul, "__array__", "no_such_function",
                                                     "no_such_function"]


def test_a_function_types_own_typing_is_answered_once_per_argument_types_while_a_module_builds():
    """Inside a build a ``types.Function``'s typing (which the lowering asks again at each operator with
    a constant operand and each array access) and the typing context's resolution of an operator named
    by its Python function (``operator.getitem``) are answered from their first answer; the
    implementation key the first typing stored is given back with each later answer; numba's own
    methods are back after."""
    pytest.importorskip("numba")
    import operator

    from numba.core import types, typing
    from numba.core.registry import cpu_target
    from numba.core.types import functions

    ctx = cpu_target.typing_context
    ctx.refresh()
    fnty = ctx.resolve_value_type(operator.add)
    typed = []
    get_call_type = functions.BaseFunction.get_call_type

    def counted(self, context, args, kws):
        typed.append((self, tuple(args)))
        return get_call_type(self, context, args, kws)

    ff = (types.float64, types.float64)
    with pytest.MonkeyPatch.context() as m:
        m.setattr(functions.BaseFunction, "get_call_type", counted)
        with compiled._typing_memo():
            a = fnty.get_call_type(ctx, ff, {})
            key = fnty._impl_keys[a.args]
            fnty._impl_keys[a.args] = "another template's"  # (a later typing with other arguments)
            b = fnty.get_call_type(ctx, ff, {})
            assert fnty._impl_keys[a.args] == key
            c = fnty.get_call_type(ctx, (types.int64, types.int64), {})
            array = types.float64[::1]
            d = ctx.resolve_function_type(operator.getitem, (array, types.intp), {})
            e = ctx.resolve_function_type(operator.getitem, (array, types.intp), {})
        assert "get_call_type" not in vars(types.Function) and functions.BaseFunction.get_call_type is counted
    assert a is b and a.return_type == types.float64 and c.return_type == types.int64
    assert d is e and d.return_type == types.float64
    assert [args for f, args in typed if f is fnty] == [ff, (types.int64, types.int64)]
    assert len([args for f, args in typed if f is not fnty]) == 1  # getitem: typed once
    assert typing.context.BaseContext.resolve_function_type.__qualname__ == "BaseContext.resolve_function_type"


def test_an_export_makes_no_c_callable_wrapper_while_its_module_builds(toy, monkeypatch):
    """numba.pycc's exports are built without numba's C-callable (cfunc) wrapper, which nothing of the
    module calls: the kernel computes the same, and numba.pycc's flags are its own again after."""
    pycc = pytest.importorskip("numba.pycc")
    from numba.core import cpu
    from numba.pycc import compiler

    kmod_a, kmod_b = _toy_build(toy, monkeypatch)
    made = []
    create = cpu.CPUContext.create_cfunc_wrapper
    monkeypatch.setattr(cpu.CPUContext, "create_cfunc_wrapper",
                        lambda self, *a, **k: (made.append(a), create(self, *a, **k))[1])
    flags = compiler.Flags
    out = compiled.group("toy_no_cfunc", {"total": (kmod_a.total, SIGNATURE)}, helpers=(kmod_b.helper,))
    monkeypatch.delitem(compiled._LOADED, "toy_no_cfunc")
    _aot_or_skip("aot" if type(out["total"]).__name__ == "builtin_function_or_method" else "jit")
    assert out["total"](X) == expected()
    assert made == [] and compiler.Flags is flags and pycc is not None


# the child of the layout test: a toy group whose exports take a C-contiguous vector and a Fortran-ordered
# matrix, called with arrays of the right and of other layouts; prints one line per call
LAYOUT_CHILD = textwrap.dedent('''
    import sys
    sys.path.insert(0, sys.argv[1])
    import numpy as np
    import kmod_a, kmod_b, kmod_c
    from twofluid import compiled
    out = compiled.group("toy_layout", {"total": (kmod_a.total, "f8(f8[::1])"),
                                        "corner": (kmod_c.corner, "f8(f8[::1, :])")}, helpers=(kmod_b.helper,),
                        check_layouts=sys.argv[2] == "checked")
    total, corner = out["total"], out["corner"]
    print("aot" if type(total).__name__ == "builtin_function_or_method" else "jit")
    x = np.linspace(0.0, 1.0, 22)
    m = np.arange(12.0).reshape(3, 4)
    calls = [("contiguous", total, x[:11]), ("strided", total, x[::2]), ("float32", total, x[::2].astype(np.float32)),
             ("list", total, [0.0, 1.0]), ("fortran", corner, np.asfortranarray(m)), ("C order", corner, m),
             ("one column", corner, m[:, 1:2]), ("empty", total, x[:0])]
    for name, f, a in calls:
        before = sys.getrefcount(a)
        try:
            print(name, "value", repr(f(a)), sys.getrefcount(a) - before)
        except Exception as e:
            print(name, type(e).__name__, sys.getrefcount(a) - before, str(e).replace(" ", "_"))
''')


def test_an_export_given_an_array_of_another_layout_raises_a_value_error_not_a_wrong_answer(toy):
    """An ahead-of-time export whose array argument is declared C-contiguous (or Fortran-ordered) reads
    it by its shape alone: in a group built with ``check_layouts`` its wrapper checks the layout and
    raises ValueError for a strided view (a wrong answer otherwise), NumPy's way (a dimension of length
    1 or an empty array passes); an array of another item size or no array raises numba's TypeError
    (it crashed the process: its exception class was CPython's variable's address); the layout's error
    keeps no reference to the array."""
    src, cache = toy
    (src / "kmod_c.py").write_text("def corner(a):\n    return a[0, 1] + 10.0 * a.shape[0] + 100.0 * a.shape[1]\n")
    def calls(mode):
        r = subprocess.run([sys.executable, "-c", LAYOUT_CHILD, str(src), mode], capture_output=True, text=True,
                           env=_env(cache), timeout=600)
        assert r.returncode == 0, r.stderr[-3000:]
        how, *lines = r.stdout.splitlines()
        _aot_or_skip(how)
        return {line.split()[0] if not line.startswith(("C order", "one column")) else " ".join(line.split()[:2]):
                line.split()[-3:] for line in lines}

    got = calls("checked")
    s = 0.0
    for v in np.linspace(0.0, 1.0, 22)[:11]:
        s += 2.0 * float(v)
    assert got["contiguous"] == ["value", repr(s + 0.5), "0"]
    assert got["strided"][:2] == ["ValueError", "0"] and "C-contiguous" in got["strided"][2]
    assert got["float32"][0] == "TypeError" and got["list"][:2] == ["TypeError", "0"]  # (numba's error keeps a
    # reference to an array of another item size, as it always did)
    assert got["fortran"] == ["value", repr(1.0 + 30.0 + 400.0), "0"]
    assert got["C order"][:2] == ["ValueError", "0"] and "Fortran-contiguous" in got["C order"][2]
    assert got["one column"][:2] == ["ValueError", "0"]  # (3, 1) with a row stride of 4: not contiguous
    assert got["empty"] == ["value", "0.5", "0"]
    unchecked = calls("unchecked")  # a group without check_layouts: another module, its errors raised alike
    assert unchecked["contiguous"] == got["contiguous"] and unchecked["strided"][0] == "value"
    assert unchecked["float32"][0] == "TypeError" and unchecked["list"][:2] == ["TypeError", "0"]


def test_the_models_kernels_given_a_strided_view_give_the_right_answer_or_a_value_error():
    """The 1D models' kernels typed C-contiguous (the common group's state check, a closure law, the
    extrapolation) called with a strided view: the ahead-of-time module raises ValueError; the JIT
    (where no module could be built) or the plain function computes on the view; never the answer of
    the wrong entries."""
    from twofluid.closures import kernels as law_kernels
    from twofluid.models import extrapolation, reduced_kernel

    common = reduced_kernel.common_kernels()
    if common is None:
        pytest.skip("no compiled kernels here")
    n = np.tile([0.5, 2.0], 6)  # the view n[::2] is admissible; the array's first half is not
    V = np.zeros(12)
    try:
        assert common["state_check"](n[::2], V[::2]) == 0
    except ValueError as e:
        assert "C-contiguous" in str(e)
    assert common["state_check"](np.ascontiguousarray(n[::2]), V[:6]) == 0
    laws = law_kernels._compiled()
    out = np.empty(6)
    try:
        laws["viscosity"](n[::2], 1e-3, 1.0, 1.0, 0.2, 0.5, 0.0, 0.0, False, out)
        ref = np.empty(6)
        laws["viscosity"](np.full(6, 0.5), 1e-3, 1.0, 1.0, 0.2, 0.5, 0.0, 0.0, False, ref)
        assert np.array_equal(out, ref)
    except ValueError as e:
        assert "C-contiguous" in str(e)
    predict = extrapolation._kernels()[0]
    D = np.arange(12.0).reshape(3, 4)
    pred = np.empty(4)
    predict(D, 3, pred)
    strided = np.empty(8)
    try:
        predict(D, 3, strided[::2])
        assert np.array_equal(strided[::2], pred)
    except ValueError as e:
        assert "C-contiguous" in str(e)


def test_an_ir_statements_variables_are_listed_as_numba_lists_them_while_a_module_builds():
    """Inside a build numba's IR lists a statement's variables by one walk (``compiled._ir_vars_listed_once``):
    the same variables in the same order for every statement of a kernel; numba's own method is back
    after. A numba whose method has another source keeps its own."""
    pytest.importorskip("numba")
    import hashlib
    import inspect

    from numba.core import compiler, ir

    from twofluid.models import reduced_kernel

    func_ir = compiler.run_frontend(reduced_kernel._band_system)
    stmts = [s for block in func_ir.blocks.values() for s in block.body]
    own = ir.Inst._rec_list_vars
    known = hashlib.sha256(inspect.cleandoc(inspect.getsource(own)).encode()).hexdigest()[:16] \
        == compiled._REC_LIST_VARS_SOURCE
    expected = [s.list_vars() for s in stmts]
    with compiled._ir_vars_listed_once():
        assert (ir.Inst._rec_list_vars is not own) == known
        got = [s.list_vars() for s in stmts]
        nested = ir.Inst._rec_list_vars(stmts[0], {"a": [(stmts[0],), {"b": func_ir.arg_names}]})
    assert got == expected and any(got)
    assert nested == own(stmts[0], {"a": [(stmts[0],), {"b": func_ir.arg_names}]})
    assert ir.Inst._rec_list_vars is own


def test_numbas_own_variable_listing_is_kept_where_its_source_is_another(monkeypatch):
    """``compiled._ir_vars_listed_once`` repeats one source of numba's ``Inst._rec_list_vars``: with
    another (a later numba's), the build keeps numba's own method."""
    pytest.importorskip("numba")
    from numba.core import ir

    own = ir.Inst._rec_list_vars
    monkeypatch.setattr(compiled, "_REC_LIST_VARS_SOURCE", "0" * 16)
    with compiled._ir_vars_listed_once():
        assert ir.Inst._rec_list_vars is own
    assert ir.Inst._rec_list_vars is own
