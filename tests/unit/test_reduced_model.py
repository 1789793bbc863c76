"""The reduced-variable 1D model (Pringle 2001 sec. 4.6.2) against the full model."""
import numpy as np
import pytest
from kernel_paths import band_to_dense

from twofluid.casefile.builder import build
from twofluid.casefile.loader import load_case
from twofluid.models.reduced_1d import Reduced1D
from twofluid.models.two_fluid_1d import Boundary
from twofluid.timestepping.backward_euler import integrate, picard_step


def _case(name, model, t_end=None):
    c = load_case(name)
    c["case"]["model"] = model
    if t_end:
        c["time"]["end"] = t_end
    return c


def _final(case):
    b = build(case)
    s = b.state
    for st in integrate(b.model, s, b.t_end, b.dt, settings=b.settings):
        s = st.state
    return s


def test_case_file_selects_reduced_model():
    assert isinstance(build(_case("fluidized-bed-step", "reduced_1d")).model, Reduced1D)


@pytest.mark.parametrize("name, dt", [("fluidized-bed-step", 0.02), ("settling-illite", 0.1)])
def test_one_step_solves_the_full_models_equations(name, dt):
    """Same initial state, one step: V, W, n and the recovered P agree to the Picard tolerance.

    Both Picard loops stop when an iterate changes by less than ``tol`` (velocities
    relative to the model's velocity scale, porosity absolute), so the two converged
    states may differ by about that much, never by the round-off of one machine's
    solves. The full model's own round-off floor is far below it: on settling-illite
    its iterates stall at a change of about 5e-9 of the scale when asked for more.
    """
    out = {}
    for model in ("two_fluid_1d", "reduced_1d"):
        b = build(_case(name, model))
        new, it = picard_step(b.model, b.state, dt, b.settings)
        assert new is not None, it
        out[model] = (new, b.model.velocity_scale(new))
    (f, scale), (r, _) = out["two_fluid_1d"], out["reduced_1d"]
    tol = b.settings.tol
    assert np.abs(f.n - r.n).max() < tol
    assert np.abs(f.W - r.W).max() < tol * scale
    assert np.abs(f.V - r.V).max() < tol * scale
    assert np.abs(f.P - r.P).max() < 1e-6 * np.abs(f.P).max()


@pytest.mark.parametrize("name, t_end", [("fluidized-bed-step", 6.0), ("settling-illite", 40.0)])
def test_porosity_agrees_with_the_full_model(name, t_end):
    f = _final(_case(name, "two_fluid_1d", t_end))
    r = _final(_case(name, "reduced_1d", t_end))
    assert np.max(np.abs(r.n - f.n) / f.n) < 1e-7  # the same equations, to the Picard tolerance (measured 2e-12)
    assert abs(r.t - f.t) < 1e-9


def test_only_the_linear_element():
    b = build(_case("fluidized-bed-step", "two_fluid_1d"))
    m = b.model
    with pytest.raises(ValueError, match="1VW/0P/0n"):
        Reduced1D(m.mesh, m.mat, m.clo, m.bottom, m.top, element="2VW/1P/0n")


def test_needs_an_end_fixing_the_flux():
    b = build(_case("fluidized-bed-step", "two_fluid_1d"))
    m = b.model
    out = Boundary("outlet")
    with pytest.raises(ValueError, match="inlet or a wall"):
        Reduced1D(m.mesh, m.mat, m.clo, out, out)


def test_pressure_recovery_is_hydrostatic_at_rest():
    """A uniform fluidized bed at steady state: P from the liquid rows balances the mixture weight."""
    b = build(_case("fluidized-bed-step", "reduced_1d"))
    m, s = b.model, b.state
    n0 = float(s.n[0])  # the porosity the inlet velocity at t = 0 holds
    s = s.copy(n=np.full_like(s.n, n0), V=np.full_like(s.V, m.bottom.velocity(-1.0)),
               W=np.full_like(s.W, m.bottom.velocity(-1.0)))
    P = m.recover_pressure(s, s, 1.0)
    rho_bar = n0 * m.mat.rho_f + (1.0 - n0) * m.mat.rho_s
    grad = np.diff(P) / np.diff(m.mesh.centres)
    assert np.allclose(grad, -rho_bar * m.mat.g, rtol=1e-6)


@pytest.mark.parametrize("name, t_end", [("fluidized-bed-step", 3.0), ("settling-illite", 40.0)])
def test_banded_jacobian_is_the_derivative_of_the_residual(name, t_end):
    """Each iterate is a Newton step: the pentadiagonal (W, n) matrix equals the central
    finite-difference Jacobian of the residual (minus the right-hand side), upwind side fixed."""
    b = build(_case(name, "reduced_1d", t_end))
    m = b.model
    prev = s = b.state
    for st in integrate(m, b.state, b.t_end, b.dt, settings=b.settings):
        prev, s = s, st.state
    dt = s.t - prev.t
    k = s.copy(W=s.W * (1.0 + 1e-3 * np.sin(np.arange(s.W.size))))  # off the converged state
    m._below = (k.V - k.W) >= 0.0

    def residual(W, n):
        ab, rhs, _, _ = m.assemble(k.copy(W=W, n=n), prev, dt, s.t)
        return -rhs, ab

    _, ab = residual(k.W, k.n)
    J = band_to_dense(ab.copy(), 2, 2)
    N = J.shape[0]
    J_fd = np.zeros_like(J)
    step_W = 1e-6 * np.abs(k.W).max()
    for j in range(N):
        eps = step_W if j % 2 == 0 else 1e-7  # W_i at 2i, n_e at 2e + 1
        x_p = [k.W.copy(), k.n.copy()]
        x_m = [k.W.copy(), k.n.copy()]
        x_p[j % 2][j // 2] += eps
        x_m[j % 2][j // 2] -= eps
        J_fd[:, j] = (residual(*x_p)[0] - residual(*x_m)[0]) / (2.0 * eps)
    row_scale = np.abs(J_fd).max(axis=1, keepdims=True)
    assert np.max(np.abs(J - J_fd) / row_scale) < 1e-4


def test_reused_model_restarts_its_caches():
    """A model that has run (per-step caches, extrapolation history) gives, for a step from
    another state, the same result as a fresh model."""
    case = _case("settling-illite", "reduced_1d", 5.0)
    b = build(case)
    for _ in integrate(b.model, b.state, b.t_end, b.dt, settings=b.settings):
        pass
    fresh = build(case)
    used, _ = picard_step(b.model, fresh.state, 0.1, fresh.settings)
    new, _ = picard_step(fresh.model, fresh.state, 0.1, fresh.settings)
    assert np.array_equal(used.n, new.n) and np.array_equal(used.W, new.W) and np.array_equal(used.P, new.P)


def test_extrapolated_start_saves_iterations():
    """Newton with the cubic extrapolation of the last steps as first iterate: on the settling
    column nearly every step converges at the first iterate (the full model needs 3)."""
    b = build(_case("settling-illite", "reduced_1d", 20.0))
    its = [st.iterations for st in integrate(b.model, b.state, b.t_end, b.dt, settings=b.settings)]
    assert np.mean(its) < 1.5
