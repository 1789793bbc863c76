"""The kernels of the reduced 1D model (models/reduced_kernel.py) and the band solves they call.

The reduced model's iterate exists once, as the kernels; what checks it is elsewhere: its band
matrix against the finite-difference Jacobian of its residual and its steps against the full
model's (tests/unit/test_reduced_model.py), the exact solutions (Kynch, Terzaghi) and the golden
outputs of the bundled cases (tests/cases/test_golden_1d.py). Here: the same source run as plain
Python (``TWOFLUID_DISABLE_JIT=1``, the debugging mode) gives the compiled kernels' steps, the
whole iterate is the four calls it stands for, and the band solves.

The band LU of the kernel follows LAPACK's dgbtf2/dgbtrs, so its solutions agree with
``dgbsv``'s to the backward error of the LU: κ(A)·ε relative, with κ estimated by the
solutions' own sensitivity (checked on random matrices that need row interchanges).
"""
from __future__ import annotations

import numpy as np
import pytest
from kernel_paths import advance as _advance, assert_same_state, band_to_dense, model_of

from twofluid.casefile.loader import load_case
from twofluid.fem.banded import band_lu
from twofluid.models import reduced_kernel
from twofluid.runners.liquefaction import build_column
from twofluid.scipy_kernels import dgbsv
from twofluid.timestepping.backward_euler import picard_step

CASES = ("fluidized-bed-step", "settling-illite", "slis-step-change")
EPS = np.finfo(float).eps


def _model(name, model="reduced_1d", element=None):
    return model_of(name, model, element)


def _dense(ab, kl=2):
    """The matrix of LAPACK band storage (entry (i, j) at ab[2 kl + i − j, j])."""
    N = ab.shape[1]
    A = np.zeros((N, N))
    for d in range(-kl, kl + 1):
        i = np.arange(max(0, -d), min(N, N - d))
        A[i, i + d] = ab[2 * kl - d, i + d]
    return A


def test_the_kernels_run_as_plain_python_and_give_the_compiled_steps():
    """``TWOFLUID_DISABLE_JIT=1`` runs the same source un-compiled (for a debugger): five steps of
    the fluidized bed give the compiled run's state to 1e-8 of each field's scale — the
    compiled and the interpreted loops differ only by the round-off of the libm calls and of the
    band solve, amplified by the Newton solves' conditioning, far below the stepper's tol 1e-7."""
    import json
    import os
    import subprocess
    import sys

    code = ("import json; from kernel_paths import advance, model_of; "
            "from twofluid import compiled; assert compiled.jit_disabled(); "
            "b = model_of('fluidized-bed-step', 'reduced_1d'); s = advance(b, 5 * b.dt, None); "
            "print(json.dumps({f: list(map(float, getattr(s, f))) for f in 'VWnP'} | {'t': s.t}))")
    env = dict(os.environ, TWOFLUID_DISABLE_JIT="1")
    env["PYTHONPATH"] = os.pathsep.join([os.path.dirname(__file__), env.get("PYTHONPATH", "")])
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, check=True)
    plain = json.loads(out.stdout)
    b = _model("fluidized-bed-step")
    fast = _advance(b, 5 * b.dt, None)
    from twofluid.models.data_1d import State

    ref = State(plain["t"], *(np.asarray(plain[f]) for f in "VWPn"), fast.n_bar)
    assert_same_state(ref, fast, rel=1e-8)


def _iterates(b, t_end):
    """The iterates (k, old, dt, t) of the step after ``t_end`` of simulated time."""
    s = _advance(b, t_end, False)
    seen = []
    assemble = b.model.assemble

    def spy(k, old, dt, t):
        seen.append((k.copy(), old, dt, t))
        return assemble(k, old, dt, t)

    b.model.assemble = spy
    picard_step(b.model, s, b.dt, b.settings)
    del b.model.assemble
    return seen


@pytest.mark.parametrize("name, element, seconds", [("fluidized-bed-step", "1VW/0P/0n", 1.0),
                                                    ("fluidized-bed-step", "2VW/1P/0n", 1.0),
                                                    ("settling-illite", "1VW/0P/0n", 5.0)])
def test_full_model_with_the_compiled_band_lu_gives_dgbsvs_results(name, element, seconds):
    # (with the linear element the whole iterate is compiled: models/full_kernel.py)
    runs = {c: _advance(_model(name, "two_fluid_1d", element), seconds, c) for c in (False, True)}
    ref, fast = runs[False], runs[True]
    assert_same_state(ref, fast)


@pytest.mark.parametrize("N, kl, ku", [(401, 2, 2), (7, 2, 2), (3, 2, 2), (60, 3, 1), (1, 2, 2)])
def test_band_lu_matches_lapack_dgbsv(N, kl, ku):
    rng = np.random.default_rng(N + 10 * kl + ku)
    ab = np.asfortranarray(rng.standard_normal((2 * kl + ku + 1, N)))  # no diagonal dominance: pivoting
    b = rng.standard_normal(N)
    ref = dgbsv(kl, ku, ab.copy(order="F"), b.copy())[2]
    A = band_to_dense(ab, kl, ku)
    x = b.copy()
    assert band_lu()(ab.copy(order="F"), x, kl, ku) == 0
    kappa = np.linalg.cond(A)
    assert np.abs(A @ x - b).max() <= 50 * N * EPS * np.abs(A).max() * np.abs(x).max()
    assert np.abs(x - ref).max() <= 50 * N * kappa * EPS * np.abs(ref).max()
    singular = np.zeros_like(ab)
    assert band_lu()(singular, b.copy(), kl, ku) == 1


@pytest.mark.parametrize("N", [2, 3, 4, 5, 8, 401])
def test_the_band_lu_written_out_for_two_diagonals_is_the_general_one(N):
    """band_lu_22 (kl = ku = 2, the reduced model's band, its loops written out) performs the general
    band LU's operations in its order: the same factors and solution bit for bit, on random
    matrices (row interchanges in most columns) and on one with a zero pivot."""
    from twofluid.fem.banded import band_lu_22

    rng = np.random.default_rng(N)
    for trial in range(20):
        ab = np.asfortranarray(rng.standard_normal((7, N)))
        if trial == 0:
            ab[:, 0] = 0.0  # a zero column: LAPACK's info = 1
        b = rng.standard_normal(N)
        a1, x1, a2, x2 = ab.copy(order="F"), b.copy(), ab.copy(order="F"), b.copy()
        info1, info2 = band_lu_22()(a1, x1), band_lu()(a2, x2, 2, 2)
        assert info1 == info2 == (1 if trial == 0 else 0)
        if info1 == 0:
            assert np.array_equal(a1, a2) and np.array_equal(x1, x2)


@pytest.mark.parametrize("N", [1, 2, 3, 4, 5, 9, 401])
def test_the_block_solve_is_accurate_or_hands_over_to_the_band_lu(N):
    """block_solve_22 (2 × 2 blocks without interchanges between them) solves the reduced model's
    band: on diagonally dominant random matrices its row-wise backward error is below the
    tolerance it checks, and it leaves ``ab`` as it was; where a pivot block is singular, or
    nearly so (growth: the backward error check), or the matrix is singular, or n is even (no
    pairs and a last one), the result is the band LU's, bit for bit, info included."""
    from twofluid.fem.banded import _BT_TOL, band_lu_22, block_solve_22

    rng = np.random.default_rng(N)
    for trial in range(30):
        ab = np.asfortranarray(rng.standard_normal((7, N)))
        ab[:2] = 0.0  # the LU's fill-in rows: not part of A
        ab[4] += 10.0 * np.sign(ab[4])  # diagonally dominant: block LU is stable (Golub & Van Loan, thm 4.5.2)
        kind = trial % 4
        if kind == 1 and N > 1:  # a singular first pivot block in a regular matrix: no block LU
            ab[4, 0] = ab[3, 1] = ab[5, 0] = ab[4, 1] = 0.0
        elif kind == 2 and N > 1:  # a nearly singular one: growth of ~1e14
            ab[4, 0], ab[3, 1], ab[5, 0] = 1.0, 1.0, 1.0
            ab[4, 1] = 1.0 + 1e-14
        elif kind == 3:
            ab[:, N // 2] = 0.0  # a singular matrix
        b = rng.standard_normal(N)
        a1, x1, a2, x2 = ab.copy(order="F"), b.copy(), ab.copy(order="F"), b.copy()
        info1, info2 = block_solve_22()(a1, x1), band_lu_22()(a2, x2)
        if N % 2 == 1 and (kind == 0 or (N == 1 and kind != 3)):  # by blocks (one unknown: its 1 × 1 block)
            assert info1 == 0 and np.array_equal(a1, ab)
            A = _dense(ab)
            r = np.abs(b - A @ x1) / (np.abs(A) @ np.abs(x1) + np.abs(b))
            assert r.max() <= _BT_TOL
        else:  # handed over
            assert info1 == info2 and np.array_equal(a1, a2) and np.array_equal(x1, x2, equal_nan=True)


def test_the_extrapolation_is_exact_for_polynomials_in_time_entry_by_entry():
    """The extrapolated first iterate (models/extrapolation.py, its kernels) against exact values:
    an entry that is a polynomial of degree d ≤ 4 in time has ∇^{d+1}x = 0, so it takes the order
    d and its prediction is the polynomial's value at the next step. Integer coefficients at
    integer times keep every difference exact in floating point, so the comparison is exact; a
    NaN entry stays NaN and leaves the others alone; after a change of step the prediction is the
    linear one (at most twice the step ahead)."""
    from twofluid.models.extrapolation import Extrapolator

    coeffs = np.array([[3, 0, 0, 0, 0], [1, -2, 0, 0, 0], [2, 1, -1, 0, 0], [1, 0, 2, 1, 0], [5, -1, 0, 3, -1]], float)

    def x(t):
        return coeffs @ (float(t) ** np.arange(5))

    e = Extrapolator()
    for t in range(7):
        v = x(t)
        v[0] = np.nan if t == 6 else v[0]
        e.push(float(t), [v, 2.0 * v], None)
    assert e.order == 6
    W, n = e.predict(7.0)
    exact = x(7)
    assert np.isnan(W[0]) and np.isnan(n[0])
    np.testing.assert_array_equal(W[1:], exact[1:])
    np.testing.assert_array_equal(n[1:], 2.0 * exact[1:])
    x6 = x(6)  # as pushed at t = 6, but for its NaN entry
    e.push(7.5, [x(7.5), x(7.5)], None)  # a new step size (1.5): the table restarts from t = 6 and 7.5
    W, _ = e.predict(8.0)
    assert e.order == 2
    np.testing.assert_allclose(W[1:], (x(7.5) + (x(7.5) - x6) / 3.0)[1:], rtol=1e-15)


@pytest.mark.parametrize("model", ["reduced_1d", "two_fluid_1d"])
def test_the_compiled_iterate_test_is_the_steppers(model):
    """TwoFluid1D.iterate_change (one compiled pass) gives relative_change's numbers exactly (max
    and abs are exact), and says when the solve's output is not finite."""
    from twofluid.timestepping.backward_euler import relative_change

    b = _model("fluidized-bed-step", model)
    m = b.model
    old = _advance(b, 1.0, False)
    k = old.copy()
    rng = np.random.default_rng(5)
    new = old.copy(V=old.V + 1e-4 * rng.standard_normal(old.V.size), W=old.W * 1.01,
                   n=old.n + 1e-5 * rng.standard_normal(old.n.size))
    a = m.pack(new)
    m.compiled = None
    finite, dn, dv = m.iterate_change(a, new, k)
    assert finite and (dn, dv) == relative_change(m, new, k) and dn > 0 and dv > 0
    a[a.size // 2] = np.inf
    assert not m.iterate_change(a, new, k)[0]
    a[a.size // 2] = np.nan
    assert not m.iterate_change(a, new, k)[0]
    m.compiled = False  # the NumPy form
    assert not m.iterate_change(a, new, k)[0]
    a[a.size // 2] = 0.0
    assert m.iterate_change(a, new, k) == (True, *relative_change(m, new, k))


def test_the_compiled_state_check_gives_the_numpy_checks_answers():
    m = _model("fluidized-bed-step").model
    s = _model("fluidized-bed-step").state
    cases = {"ok": {}, "nan n": {"n": np.nan}, "inf V": {"V": np.inf}, "n = 0": {"n": 0.0},
             "n > 1": {"n": 1.0 + 1e-8}, "n = 1 + 1e-10": {"n": 1.0 + 1e-10}}
    for label, change in cases.items():
        t = s.copy()
        for f, v in change.items():
            getattr(t, f)[3] = v
        answers = []
        for compiled in (False, None):
            m.compiled = compiled
            answers.append(m.check(t))
        assert answers[0] == answers[1], label
        assert (answers[0] is None) == (label in ("ok", "n = 1 + 1e-10")), label


@pytest.mark.parametrize("name, drag", [("fluidized-bed-step", None), ("slis-step-change", None),
                                        ("fluidized-bed-step", "wen_yu"), ("settling-illite", "ergun")])
def test_the_whole_iterate_is_the_four_calls(name, drag):
    """Reduced1D.iterate (assemble, solve, unpack and the iterate test in two compiled calls around
    Wen–Yu's powers) gives the stepper's own sequence of those calls bit for bit, and so do the
    kernels called one by one (no whole iterate, no fused bed-force shift), for each drag law
    (Gidaspow in the bundled cases); a replaced method turns it off."""
    runs = []
    for way in ("whole", "four calls", "kernel by kernel"):
        b = model_of(name, "reduced_1d", drag=drag)
        if way == "whole":
            assert b.model._whole_args(b.state) is not None  # the compiled whole iterate is taken
        elif way == "four calls":
            b.model.iterate = None  # the stepper then calls the four methods itself
        else:
            b.model._whole_args = lambda s: None
        runs.append(_advance(b, 1.0, None))
    for run in runs[1:]:
        for f in ("V", "W", "P", "n"):
            assert np.array_equal(getattr(runs[0], f), getattr(run, f)), f
    m = _model(name).model
    assert m._whole_iterate_ok()
    m.assemble = m.assemble
    assert not m._whole_iterate_ok()
