"""The compiled iterate of the full 1D model (models/full_kernel.py) against its NumPy path.

Both paths evaluate the same element terms in the same order (the closures are the same calls)
and sum A aᵏ term by term, so one iterate's band matrix and right-hand side agree to round-off:
the bound is 1e-12 of the largest entry (of the matrix; of the right-hand side), well above a
few ulps of reassociation by a compiler and far below any change of the discrete equations (a
wrong coefficient is O(1) of its entry; the last check of the first test shows that one
changed by 1e-9 of the matrix's size is seen). The solutions of an iterate then agree to the
backward error of the LU, κ(A)·ε relative (as the band and the sparse solves in
``test_full_model_solver.py``), and whole short runs to 1e-8 relative: the iterates differ by
round-off amplified by the conditioning of the Newton solves, and the Picard test (1e-7) ends
every step on the same iterate unless a change sits within round-off of the tolerance (V and W
relative to the velocity scale: behind a closed bottom V is round-off itself).

Without numba the compiled comparisons skip and the NumPy path is the only one; the last tests
check that the full model runs on it, and that the paths the kernels do not cover keep it.
"""
from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from kernel_paths import advance as _advance, assert_same_state, model_of

from twofluid.fem.assembly import BlockSystem
from twofluid.models import full_kernel
from twofluid.models.two_fluid_1d import Boundary, TwoFluid1D
from twofluid.timestepping.backward_euler import picard_step

PEERS = Path(__file__).resolve().parents[2] / "benchmarks" / "peers"
CASES = ("fluidized-bed-step", "settling-illite", "slis-step-change",
         str(PEERS / "openfoam-fluidized-bed.toml"), str(PEERS / "openfoam-sedimentation.toml"))
EPS = np.finfo(float).eps
requires_numba = pytest.mark.skipif(not full_kernel.available(), reason="numba not installed")


def _model(name, element=None):
    return model_of(name, "two_fluid_1d", element)


def _iterates(b, t_end):
    """The iterates (k, old, dt, t) of the step after ``t_end`` of simulated time (NumPy path)."""
    s = _advance(b, t_end, False)
    seen = []
    assemble = b.model.assemble

    def spy(k, old, dt, t):
        seen.append((k.copy(), old, dt, t, getattr(b.model, "_below", None)))
        return assemble(k, old, dt, t)

    b.model.assemble = spy
    picard_step(b.model, s, b.dt, b.settings)
    del b.model.assemble
    return seen


def _free(m, A, t):
    idx, _ = m.dirichlet(t)
    return np.setdiff1d(np.arange(A.shape[0]), idx)


@requires_numba
@pytest.mark.parametrize("name", CASES, ids=lambda c: Path(c).stem)
def test_compiled_band_system_matches_the_numpy_path(name):
    b = _model(name)
    m = b.model
    m.compiled_closures = False  # the kernels around the same closure values (compiled laws: test_closure_kernels)
    seen = _iterates(b, 10 * b.dt)
    assert seen
    for k, old, dt, t, below in seen:
        out = {}
        for compiled in (False, None):
            m.compiled, m._below = compiled, below
            m._shift_cache = m._step_full = m._fk_step = None  # the step's terms and shift anew
            S = m.assemble(k.copy(), old, dt, t)
            assert isinstance(S, BlockSystem if compiled is False else full_kernel.BandIterate)
            out[compiled] = (S.matrix().toarray(), S.rhs.copy(), m.solve(S, t))
        (A1, r1, x1), (A2, r2, x2) = out[False], out[None]
        assert np.abs(A1 - A2).max() <= 1e-12 * np.abs(A1).max()
        assert np.abs(r1 - r2).max() <= 1e-12 * np.abs(r1).max()
        free = _free(m, A1, t)
        kappa = np.linalg.cond(A1[free][:, free])
        assert np.abs(x1 - x2).max() <= 10.0 * kappa * EPS * np.abs(x1).max()
        # and a wrong coefficient would be seen: one entry changed by 1e-9 of the matrix's size
        A3 = A2.copy()
        A3[m.nv + 3, 2] += 1e-9 * np.abs(A1).max()
        assert np.abs(A1 - A3).max() > 1e-12 * np.abs(A1).max()


def _variant(kind):
    """fluidized-bed-step with one option of the model changed (the kernels' other branches)."""
    b = _model("fluidized-bed-step")
    m = b.model
    args = dict(mesh=m.mesh, materials=m.mat, closures=m.clo, bottom=m.bottom, top=m.top)
    kw = {}
    if kind == "galerkin flux":
        kw["solids_flux"] = "galerkin"
    elif kind == "galerkin forces":
        kw["bed_forces"] = "galerkin"
    elif kind == "no viscosity":
        args["closures"] = replace(m.clo, viscous=False)
    elif kind == "outlet below":  # a wall on top, the outlet (at 2 kPa) below: the column drains
        args["bottom"], args["top"] = Boundary("outlet", pressure=2e3), Boundary("wall")
    b.model = TwoFluid1D(**args, **kw)
    return b


@requires_numba
@pytest.mark.parametrize("kind", ["galerkin flux", "galerkin forces", "no viscosity", "outlet below"])
def test_compiled_band_system_of_the_other_options(kind):
    b = _variant(kind)
    m = b.model
    m.compiled_closures = False  # the kernels around the same closure values (compiled laws: test_closure_kernels)
    # (the galerkin flux cannot follow the bed's free surface: the iterates of the first step)
    seen = _iterates(b, 0.0 if kind == "galerkin flux" else 3 * b.dt)
    assert seen
    for k, old, dt, t, below in seen:
        out = {}
        for compiled in (False, None):
            m.compiled, m._below = compiled, below
            m._shift_cache = m._step_full = m._fk_step = None
            S = m.assemble(k.copy(), old, dt, t)
            out[compiled] = (S.matrix().toarray(), S.rhs.copy())
        (A1, r1), (A2, r2) = out[False], out[None]
        assert np.abs(A1 - A2).max() <= 1e-12 * np.abs(A1).max()
        assert np.abs(r1 - r2).max() <= 1e-12 * np.abs(r1).max()


@requires_numba
def test_compiled_bed_force_shift_is_the_numpy_shift():
    b = _model("fluidized-bed-step")
    s = _advance(b, 1.0, False)
    m = b.model
    m.compiled_closures = False  # the kernels around the same closure values (compiled laws: test_closure_kernels)
    ref = m._force_shift_at(s)
    m.compiled = None
    fast = m._force_shift_at(s)
    assert np.abs(ref).max() > 0.1  # the bed's elements are upwinded: the check sees the shares
    assert np.abs(fast - ref).max() <= 1e-12 * 0.5  # |α| < ½


@requires_numba
@pytest.mark.parametrize("name, seconds", [(CASES[0], 2.0), (CASES[1], 5.0), (CASES[2], 2.0),
                                           (CASES[3], 2.0), (CASES[4], 2.0)], ids=lambda c: Path(str(c)).stem)
def test_compiled_runs_give_the_numpy_paths_results(name, seconds):
    runs = {c: _advance(_model(name), seconds, c) for c in (False, None)}
    ref, fast = runs[False], runs[None]
    assert_same_state(ref, fast)


@requires_numba
def test_a_system_that_cannot_be_solved_gives_nan():
    b = _model("fluidized-bed-step")
    m = b.model
    m.compiled = None
    k = b.state.copy(t=b.dt)
    k.n[3] = np.nan
    S = m.assemble(k, b.state, b.dt, k.t)
    assert isinstance(S, full_kernel.BandIterate)
    assert np.isnan(m.solve(S, k.t)).all()


def test_paths_the_kernels_do_not_cover_keep_the_numpy_path():
    """The quadratic element, the Picard linearisation, ``compiled = False`` and a subclass that adds
    a term to the assembled system all assemble a BlockSystem."""

    class Loaded(TwoFluid1D):
        def assemble(self, k, old, dt, t_new):
            S = super().assemble(k, old, dt, t_new)
            S.add_rhs("V", np.array([self.vert_node[-1]]), np.array([-1.0]))
            return S

    b = _model("fluidized-bed-step", "2VW/1P/0n")
    m = b.model
    assert isinstance(m.assemble(b.state.copy(t=b.dt), b.state, b.dt, b.dt), BlockSystem)
    m = _model("fluidized-bed-step").model
    args = (m.mesh, m.mat, m.clo, m.bottom, m.top)
    for model in (TwoFluid1D(*args, linearisation="picard"), Loaded(*args)):
        assert model._full_kernels() is None
    m.compiled = False
    assert m._full_kernels() is None


def test_the_numpy_path_runs():
    b = _model("fluidized-bed-step")
    s = _advance(b, 5 * b.dt, False)
    assert s.t == pytest.approx(5 * b.dt)
    assert b.model._fk is None  # nothing of the compiled path was prepared
    assert np.all((s.n > 0.0) & (s.n <= 1.0))
