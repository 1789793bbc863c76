"""The full 1D model's fast path (Newton, extrapolated first iterate, band LU for the increment)
against its reference path (the thesis's Picard iteration, sparse direct solve of the unknowns)."""
import numpy as np
import pytest

from twofluid.casefile.builder import build
from twofluid.casefile.loader import load_case
from twofluid.models.two_fluid_1d import TwoFluid1D
from twofluid.timestepping.backward_euler import PicardSettings, _solve, integrate

ELEMENTS = ("1VW/0P/0n", "2VW/1P/0n")


def _built(name, element="1VW/0P/0n", elements=None, t_end=None, model="two_fluid_1d", **kw):
    c = load_case(name)
    c["case"]["model"], c["mesh"]["element"] = model, element
    if elements:
        c["mesh"]["elements"] = elements
    if t_end:
        c["time"]["end"] = t_end
    b = build(c)
    if kw:
        m = b.model
        b.model = TwoFluid1D(m.mesh, m.mat, m.clo, m.bottom, m.top, element=m.element,
                             solids_flux=m.solids_flux, **kw)
    return b


class _SparseSolve:
    """The model without its ``solve``: the stepper's sparse direct solve of the unknowns."""

    def __init__(self, model):
        self._model = model

    def __getattr__(self, name):
        if name == "solve":
            raise AttributeError(name)
        return getattr(self._model, name)


def _last_two(b):
    prev = s = b.state
    for st in integrate(b.model, b.state, b.t_end, b.dt, settings=b.settings):
        prev, s = s, st.state
    return prev, s


def _free_system(m, S, t):
    A = S.matrix().tocsr()
    idx, val = m.dirichlet(t)
    free = np.setdiff1d(np.arange(S.size), idx)
    return A, free, idx, val


@pytest.mark.parametrize("element", ELEMENTS)
def test_band_solve_equals_the_sparse_solve(element):
    """The same assembled iterate: band LU (increment) and SuperLU (unknowns) agree to the
    conditioning of the system times the double-precision round-off."""
    b = _built("fluidized-bed-step", element, elements=30, t_end=2.0)
    m = b.model
    prev, s = _last_two(b)
    k = s.copy(t=s.t + b.dt, W=s.W * (1.0 + 1e-2 * np.sin(np.arange(s.W.size))))
    m.begin_iteration(2, k)
    S = m.assemble(k, s, b.dt, k.t)
    band = m.solve(S, k.t)
    sparse = _solve(m, S, k.t)
    A, free, idx, val = _free_system(m, S, k.t)
    kappa = np.linalg.cond(A[free][:, free].toarray())
    assert np.array_equal(band[idx], val)
    assert np.abs(band - sparse).max() <= 10.0 * kappa * np.finfo(float).eps * np.abs(sparse).max()


@pytest.mark.parametrize("name, element, t_end", [("fluidized-bed-step", ELEMENTS[0], 2.0),
                                                   ("fluidized-bed-step", ELEMENTS[1], 2.0),
                                                   ("settling-illite", ELEMENTS[0], 20.0)])
def test_newton_matrix_is_the_jacobian_of_the_residual(name, element, t_end):
    """Every term is Newton-linearised: the assembled matrix equals the central finite-difference
    Jacobian of the residual R(a) = A(a) a − b(a) (the system assembled about a itself), upwind side
    fixed. The tolerance is that of the drag's own finite difference in n (steps 1e-8, 1e-6 |s|)."""
    b = _built(name, element, elements=12, t_end=t_end)
    m = b.model
    prev, s = _last_two(b)
    dt = s.t - prev.t
    k = s.copy(W=s.W * (1.0 + 1e-3 * np.sin(np.arange(s.W.size))))
    m.begin_iteration(2, k)  # fixes the upwind side from k
    a0 = m.pack(k)

    def residual(a):
        S = m.assemble(m.unpack(a, k, s.t), prev, dt, s.t)
        return S.matrix() @ a - S.rhs, S

    _, S = residual(a0)
    A, free, _, _ = _free_system(m, S, s.t)
    J = A.toarray()[free]
    J_fd = np.zeros_like(J)
    nvel = 2 * m.nv
    vscale = np.abs(a0[:nvel]).max()
    for j in range(a0.size):
        if j < nvel:
            eps = 1e-6 * vscale
        elif j < nvel + m.np:
            eps = 1e-6 * max(np.abs(a0[nvel:nvel + m.np]).max(), 1.0)
        else:
            eps = 1e-7
        ap, am = a0.copy(), a0.copy()
        ap[j] += eps
        am[j] -= eps
        J_fd[:, j] = (residual(ap)[0][free] - residual(am)[0][free]) / (2.0 * eps)
    row_scale = np.abs(J_fd).max(axis=1, keepdims=True)
    assert np.max(np.abs(J - J_fd) / row_scale) < 1e-4


@pytest.mark.parametrize("name, element, t_end", [("fluidized-bed-step", ELEMENTS[0], 3.0),
                                                   ("fluidized-bed-step", ELEMENTS[1], 1.5),
                                                   ("settling-illite", ELEMENTS[0], 30.0)])
def test_fast_path_solves_the_same_equations(name, element, t_end):
    """Fast path and reference path (frozen coefficients, each step from the last state) with a
    Picard tolerance of 1e-11 end at the same porosity to 1e-8 relative: the same discrete
    equations (both stop within ~1e-11 of their fixed point). Both solve for the increment: the
    sparse solve of the unknowns stalls at its round-off (1.6e-7 of the velocity scale in the
    first, 1e-7 s long steps after the inlet step of the quadratic element), far above 1e-11.
    The quadratic element's bed surface empties an element (1 − n ~ 3e-7) at t ≈ 1.9 s, where the
    1 − n floor (1e-6) of the slip and of the upwind ratio is a kink of the discrete equations:
    the two paths land 2e-7 apart there, so that run stops before it."""
    settings = PicardSettings(tol=1e-11, max_iter=200)
    out = {}
    for path, kw in (("fast", {}), ("reference", {"linearisation": "picard"})):
        b = _built(name, element, t_end=t_end, **kw)
        s = b.state
        for st in integrate(b.model, b.state, b.t_end, b.dt, settings=settings):
            s = st.state
        out[path] = s
    f, r = out["fast"], out["reference"]
    assert f.t == pytest.approx(r.t, abs=1e-12)
    assert np.max(np.abs(f.n - r.n) / r.n) < 1e-8
    scale = np.abs(r.W).max()
    assert np.abs(f.W - r.W).max() < 1e-8 * scale


@pytest.mark.parametrize("elements", [300, 1000])
def test_refined_settling_column_converges_like_the_reduced_model(elements):
    """settling-illite refined: no rejected step, Picard iterations per step within 1.5× of the
    reduced model's (the reference path hit the 40-iteration limit here repeatedly)."""
    its, rejected = {}, {}
    for model in ("two_fluid_1d", "reduced_1d"):
        b = _built("settling-illite", elements=elements, t_end=3.0, model=model)
        steps = [st for st in integrate(b.model, b.state, b.t_end, b.dt, settings=b.settings)]
        its[model] = np.mean([st.iterations for st in steps])
        rejected[model] = sum(st.rejected for st in steps)
    assert rejected["two_fluid_1d"] <= rejected["reduced_1d"]
    assert its["two_fluid_1d"] <= 1.5 * its["reduced_1d"]


def test_linearisation_is_checked():
    m = _built("settling-illite").model
    with pytest.raises(ValueError, match="linearisation"):
        TwoFluid1D(m.mesh, m.mat, m.clo, m.bottom, m.top, linearisation="secant")
