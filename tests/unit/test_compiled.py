"""Compiled kernels (twofluid.compiled): built once ahead of time, then imported without numba; the
JIT where no module can be built; None without numba (the callers keep their NumPy paths)."""
from __future__ import annotations

import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

from twofluid import compiled

KERNEL = textwrap.dedent('''
    def scaled_sum(x, c):
        s = 0.0
        for i in range(x.size):
            s += c * x[i]
        return s
''')
SIGNATURE = "f8(f8[::1], f8)"


@pytest.fixture
def kernel_module(tmp_path, monkeypatch):
    (tmp_path / "kmod.py").write_text(KERNEL)
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.setenv("TWOFLUID_CACHE_DIR", str(tmp_path / "cache"))
    import importlib

    import kmod

    importlib.reload(kmod)
    yield kmod
    compiled._LOADED.clear()


def test_a_kernel_is_built_once_and_then_imported_without_numba(kernel_module, tmp_path):
    pytest.importorskip("numba")
    f = compiled.kernel("scaled_sum_test", kernel_module.scaled_sum, SIGNATURE)
    x = np.linspace(0.0, 1.0, 11)
    assert f(x, 2.0) == pytest.approx(kernel_module.scaled_sum(x, 2.0), rel=1e-15)
    built = list((tmp_path / "cache").glob("_twofluid_scaled_sum_test_*"))
    if not built:
        pytest.skip("no ahead-of-time build here (numba.pycc or a C toolchain missing): the JIT is used")
    code = textwrap.dedent(f'''
        import sys
        sys.path.insert(0, {str(tmp_path)!r})
        import numpy as np
        import kmod
        from twofluid import compiled
        f = compiled.kernel("scaled_sum_test", kmod.scaled_sum, {SIGNATURE!r}, build=False, jit=False)
        print(f(np.linspace(0.0, 1.0, 11), 2.0), "numba" in sys.modules)
    ''')
    env = {"TWOFLUID_CACHE_DIR": str(tmp_path / "cache"), "PATH": "/usr/bin:/bin",
           **{k: v for k, v in os.environ.items() if k == "PYTHONPATH"}}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, env=env).stdout
    value, numba_loaded = out.split()
    assert float(value) == pytest.approx(11.0, rel=1e-15) and numba_loaded == "False"


def test_an_edited_kernel_gets_a_module_of_its_own(kernel_module, tmp_path):
    name = compiled._module_name("k", kernel_module.scaled_sum, SIGNATURE)
    (tmp_path / "kmod.py").write_text(KERNEL.replace("c * x[i]", "x[i] * c"))
    import importlib

    importlib.reload(kernel_module)
    assert compiled._module_name("k", kernel_module.scaled_sum, SIGNATURE) != name
    assert compiled._module_name("k", kernel_module.scaled_sum, "f8(f8[:], f8)") != \
        compiled._module_name("k", kernel_module.scaled_sum, SIGNATURE)


def test_where_no_module_can_be_built_the_jit_is_used(kernel_module, monkeypatch):
    numba = pytest.importorskip("numba")
    monkeypatch.setattr(compiled, "_build", lambda *a: None)
    f = compiled.kernel("scaled_sum_jit", kernel_module.scaled_sum, SIGNATURE)
    assert isinstance(f, numba.core.registry.CPUDispatcher)
    assert compiled.kernel("scaled_sum_nojit", kernel_module.scaled_sum, SIGNATURE, jit=False) is None


def test_without_numba_a_kernel_not_built_is_an_import_error(kernel_module, monkeypatch):
    """numba is a core dependency: without it (and no module built) the kernel cannot be had; the
    message names the package and the debugging switch."""
    monkeypatch.setitem(sys.modules, "numba", None)  # import numba now raises ImportError
    monkeypatch.setitem(sys.modules, "numba.pycc", None)
    with pytest.raises(ImportError, match="needs numba"):
        compiled.kernel("scaled_sum_none", kernel_module.scaled_sum, SIGNATURE)
    assert compiled.kernel("scaled_sum_none2", kernel_module.scaled_sum, SIGNATURE, jit=False) is None


def test_with_the_jit_disabled_a_kernel_is_its_plain_python_function(kernel_module, monkeypatch):
    for var in ("TWOFLUID_DISABLE_JIT", "NUMBA_DISABLE_JIT"):
        with monkeypatch.context() as m:
            m.setenv(var, "1")
            assert compiled.jit_disabled()
            assert compiled.kernel(f"scaled_sum_{var}", kernel_module.scaled_sum, SIGNATURE) \
                is kernel_module.scaled_sum
    monkeypatch.setenv("TWOFLUID_DISABLE_JIT", "0")
    monkeypatch.delenv("NUMBA_DISABLE_JIT", raising=False)
    assert not compiled.jit_disabled()


def test_a_build_is_announced_in_one_line_on_stderr(kernel_module, tmp_path):
    """The one-off build says so (one line, naming the cache folder and the command that does it
    ahead); a second process that finds the module says nothing."""
    pytest.importorskip("numba")
    code = textwrap.dedent(f'''
        import sys
        sys.path.insert(0, {str(tmp_path)!r})
        import kmod
        from twofluid import compiled
        compiled.kernel("scaled_sum_announce", kmod.scaled_sum, {SIGNATURE!r})
        compiled.kernel("scaled_sum_announce2", kmod.scaled_sum, {SIGNATURE!r})
    ''')
    env = {"TWOFLUID_CACHE_DIR": str(tmp_path / "cache"), "PATH": "/usr/bin:/bin",
           **{k: v for k, v in os.environ.items() if k == "PYTHONPATH"}}
    first = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, env=env)
    if not list((tmp_path / "cache").glob("_twofluid_scaled_sum_announce_*")):
        pytest.skip("no ahead-of-time build here (numba.pycc or a C toolchain missing): the JIT is used")
    lines = first.stderr.splitlines()
    assert len(lines) == 1 and "compiling the numerical kernels this run needs, once: scaled_sum_announce" \
        in lines[0] and "build-kernels" in lines[0]
    again = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, env=env)
    assert again.stderr == ""


def test_every_group_is_listed_for_build_kernels():
    """``twofluid build-kernels`` builds :data:`compiled.GROUPS`: each getter exists and names its group."""
    import importlib

    names = [name for name, _ in compiled.GROUPS]
    assert len(set(names)) == len(names)
    for name, spec in compiled.GROUPS:
        module, getter = spec.split(":")
        assert callable(getattr(importlib.import_module(module), getter)), spec
        assert f'"{name}"' in open(importlib.import_module(module).__file__).read(), name


def test_every_kernel_of_the_project_is_built_ahead_of_time(tmp_path, monkeypatch):
    """A kernel whose signature numba cannot compile ahead of time falls back to the JIT, which
    works but costs every process ~0.7 s of CPU to import numba: where a toy kernel builds, so must
    each of the project's groups (each getter asked afresh; the run's own cache folder, so the
    modules the other tests built are reused)."""
    numba = pytest.importorskip("numba")
    (tmp_path / "kmod_aot.py").write_text(KERNEL)
    with monkeypatch.context() as m:
        m.syspath_prepend(str(tmp_path))
        m.setenv("TWOFLUID_CACHE_DIR", str(tmp_path / "cache"))
        import kmod_aot

        compiled.kernel("scaled_sum_aot", kmod_aot.scaled_sum, SIGNATURE, jit=False)
        compiled._LOADED.clear()
    if not list((tmp_path / "cache").glob("_twofluid_scaled_sum_aot_*")):
        pytest.skip("no ahead-of-time build here (numba.pycc or a C toolchain missing): the JIT is used")
    from twofluid.closures import kernels as closure_kernels
    from twofluid.fem import banded
    from twofluid.geotech import spectra
    from twofluid.models import column_step_kernel, extrapolation, full_kernel, reduced_kernel, shear_kernel
    from twofluid.timestepping import newton

    getters = {
        "band_lu": (banded, lambda: [banded.band_lu(), banded.band_lu_22(), banded.block_solve_22()]),
        "common_1d": (reduced_kernel, lambda: list(reduced_kernel.common_kernels().values())),
        "closures_1d": (closure_kernels, lambda: list(closure_kernels._compiled().values())),
        "extrapolation": (extrapolation, lambda: list(extrapolation._kernels())),
        "full_1d": (full_kernel, lambda: list(full_kernel.kernels().values())),
        "reduced_1d": (reduced_kernel, lambda: [*reduced_kernel.kernels(), *reduced_kernel.whole_iterate()]),
        "shear_substeps": (shear_kernel, lambda: [shear_kernel.compiled()]),
        "newton_accept": (newton, lambda: [newton._kernels()]),
        "spectra_peaks": (spectra, lambda: [spectra._compiled_peaks()]),
        "column_step": (column_step_kernel, lambda: [column_step_kernel.compiled()]),
    }
    saved = {m: {k: v for k, v in vars(m).items() if k in ("_KERNELS", "_KERNEL", "_TRIED", "_COMPILED",
                                                             "_LU", "_LU22", "_BT22", "_WHOLE", "_COMMON")} for m, _ in getters.values()}
    try:
        for m, _ in getters.values():  # asked afresh
            for k in saved[m]:
                setattr(m, k, False if k == "_TRIED" else None)
        compiled._LOADED.clear()
        jitted = [name for name, (_, get) in getters.items()
                  if any(isinstance(f, numba.core.registry.CPUDispatcher) or f is None for f in get())]
    finally:
        for m, values in saved.items():
            for k, v in values.items():
                setattr(m, k, v)
        compiled._LOADED.clear()
    assert not jitted, f"not built ahead of time: {jitted}"


def test_build_kernels_builds_every_group_ahead_of_time(tmp_path, monkeypatch, capsys):
    """``twofluid build-kernels`` (:func:`compiled.build_all`) leaves no group to the JIT where a toy
    kernel builds ahead of time; run again it finds them all (the suite's own cache folder: the
    groups the other tests need are built once either way)."""
    pytest.importorskip("numba")
    (tmp_path / "kmod_bk.py").write_text(KERNEL)
    with monkeypatch.context() as m:
        m.syspath_prepend(str(tmp_path))
        m.setenv("TWOFLUID_CACHE_DIR", str(tmp_path / "cache"))
        import kmod_bk

        compiled.kernel("scaled_sum_bk", kmod_bk.scaled_sum, SIGNATURE, jit=False)
        compiled._LOADED.clear()
    if not list((tmp_path / "cache").glob("_twofluid_scaled_sum_bk_*")):
        pytest.skip("no ahead-of-time build here (numba.pycc or a C toolchain missing): the JIT is used")
    from twofluid.cli import main

    assert main(["build-kernels"]) == 0
    out = capsys.readouterr()
    assert "kernels in" in out.out and "not built ahead of time" not in out.err
    assert compiled.build_all() == []
