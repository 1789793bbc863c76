"""2DQ1 two-component model: hydrostatics, gauge invariance, solids balance, 1D agreement."""
import numpy as np
import pytest

from twofluid.closures import drag as drag_laws
from twofluid.closures.solids_pressure import reference_porosity_for
from twofluid.casefile.builder import Schedule
from twofluid.mesh.line import uniform_line
from twofluid.mesh.quad import rectangle
from twofluid.models.two_fluid_1d import Boundary, Closures, Materials, State, TwoFluid1D
from twofluid.models.two_fluid_2d import Boundary2D, TwoFluid2D
from twofluid.timestepping.backward_euler import integrate

SAND = Materials(rho_f=1000.0, mu_f=1e-3, rho_s=2650.0, d_p=0.5e-3)
CLO = Closures(drag_params={"blend_width": 0.02}, A=0.015)


def _settled(axisymmetric):
    """A layered deposit (porosity 0.42 at the bottom to 0.48 at its top) under clear liquid."""
    mesh = rectangle(0.0, 0.1, 0.0, 0.4, 4, 8, axisymmetric=axisymmetric)
    side = "axis" if axisymmetric else "slip"
    if axisymmetric:
        mesh.boundaries["axis"] = mesh.boundaries["left"]
    bcs = [Boundary2D("bottom", "wall"), Boundary2D("right", "slip"), Boundary2D("top", "outlet"),
           Boundary2D("axis" if axisymmetric else "left", side)]
    m = TwoFluid2D(mesh, SAND, CLO, bcs, solver="direct")
    yc = mesh.points[mesh.cells].mean(axis=1)[:, 1]
    n = np.where(yc < 0.25, 0.42 + 0.06 * yc / 0.25, 1.0)
    ps = m.settled_solids_pressure(n)
    nbar = np.full(m.ne, 0.4)
    nbar[ps > 0] = reference_porosity_for(n[ps > 0], ps[ps > 0], CLO.A)
    s = State(0.0, np.zeros(m.nv), np.zeros(m.nv), np.zeros(m.ne), n, nbar)
    return m, s, yc


@pytest.mark.parametrize("axisymmetric", [False, True])
def test_settled_bed_stays_at_rest_with_hydrostatic_pressure(axisymmetric):
    m, s, yc = _settled(axisymmetric)
    k = s.copy(t=10.0)
    for it in range(1, 4):  # Newton iterates of a 10 s step (the solution is zero velocity)
        m.begin_iteration(it, k)
        new = m.unpack(m.solve(m.assemble(k, s, 10.0, 10.0), 10.0), k, 10.0)
        k = new
    p_hydro = SAND.rho_f * SAND.g * (0.4 - yc)
    assert np.abs(new.V).max() < 1e-8 and np.abs(new.W).max() < 1e-8  # [m/s], round-off level
    assert np.abs(new.n - s.n).max() < 1e-10
    assert np.abs(new.P - p_hydro).max() < 1e-9 * p_hydro.max()


def _riser(pressure, n_el=(6, 10)):
    mesh = rectangle(0.0, 0.03, 0.0, 0.1, *n_el, axisymmetric=True)
    mesh.boundaries["axis"] = mesh.boundaries["left"]
    bcs = [Boundary2D("bottom", "inlet", velocity=Schedule((0.0,), (0.02,)), solids_velocity=0.004),
           Boundary2D("axis", "axis"), Boundary2D("outer", "wall"),
           Boundary2D("top", "outlet", pressure=pressure)]
    m = TwoFluid2D(mesh, SAND, CLO, bcs, solver="direct")
    yc = mesh.points[mesh.cells].mean(axis=1)[:, 1]
    n = np.where(yc < 0.06, 0.7, 1.0)
    V, W = np.zeros(m.nv), np.zeros(m.nv)
    return m, State(0.0, V, W, np.zeros(m.ne), n, np.full(m.ne, 0.4))


def _run(m, s, t_end=0.05, dt=0.01):
    steps = list(integrate(m, s, t_end, dt))
    return steps


def test_gauge_invariance():
    runs = []
    for p in (0.0, 1.0e5):
        m, s = _riser(p)
        s = s.copy(P=np.full(m.ne, p))
        runs.append(_run(m, s)[-1].state)
    a, b = runs
    # equal to the Picard tolerance (1e-7, relative): both runs stop their iterations there
    assert np.abs(a.V - b.V).max() < 1e-7 * np.abs(a.V).max()
    assert np.abs(a.W - b.W).max() < 1e-7 * np.abs(a.W).max()
    assert np.abs(a.n - b.n).max() < 1e-10
    assert np.abs((b.P - a.P) - 1e5).max() < 1e-6 * 1e5


def test_solids_balance_with_inflow_and_outflow():
    m, s = _riser(0.0)
    v0, out = m.solids_volume(s), 0.0
    for step in _run(m, s):
        out += step.dt * m.solids_outflow(step.state)
    v1 = m.solids_volume(step.state)
    assert abs(out) > 1e-3 * v0  # solids really enter (inflow 0.004 m/s over 0.05 s)
    assert abs(v1 - v0 + out) < 1e-9 * v0
    assert m.check(step.state) is None  # 0 < n <= 1 (+1e-9, the model's admissibility bound)


@pytest.mark.parametrize("nx", [1, 4])
def test_column_reproduces_1d_step_change(nx):
    """Planar nx × 50 column with free-slip walls vs TwoFluid1D on the same vertical mesh.

    Bed step change 0.65 → 0.716 (0.3 mm, 2600 kg/m³ in water, thesis 4.6.1), 3 s.
    Measured: max |n_2D − n_1D| = 9.5e-13 (nx = 1) and 1.1e-10 (nx = 4); asserted
    within 1 % of the porosity. With one element across the discrete equations are
    those of the 1D model; with four, a laterally uniform state must stay uniform
    (round-off must not grow: it did at ≈ 10 1/s with the checkerboard penalty scaled
    by μ_f alone, docs/verification_2d.md section 7).
    """
    mat = Materials(rho_f=998.2, mu_f=1.002e-3, rho_s=2600.0, d_p=0.3e-3)
    L, ny, n0, n1 = 0.5, 50, 0.65, 0.716
    u = [drag_laws.steady_fluidization_velocity(CLO.drag, n, mat.d, mat.rho_s, mat.rho_f, mat.mu_f,
                                                mat.g, **CLO.drag_params) for n in (n0, n1)]
    inflow = Schedule((0.0, 0.0), tuple(u))
    # the 2D model tests its bed forces with the Q1 functions, as the 1D model does with bed_forces =
    # "galerkin" (its default upwind tests, TwoFluid1D.force_shift, have no 2D counterpart yet)
    m1 = TwoFluid1D(uniform_line(L, ny), mat, CLO, Boundary("inlet", velocity=inflow), Boundary("outlet"),
                    bed_forces="galerkin")
    yc1 = m1.mesh.centres
    n_init = np.where(yc1 < 0.35, n0, 1.0)
    s1 = State(0.0, np.full(m1.nv, u[0]), np.full(m1.nv, u[0]), np.zeros(m1.np), n_init, np.full(ny, 0.4))
    mesh = rectangle(0.0, 0.02 * nx, 0.0, L, nx, ny)
    m2 = TwoFluid2D(mesh, mat, CLO, [Boundary2D("bottom", "inlet", velocity=inflow),
                                     Boundary2D("left", "slip"), Boundary2D("right", "slip"),
                                     Boundary2D("top", "outlet")], solver="direct")
    yc2 = mesh.points[mesh.cells].mean(axis=1)[:, 1]
    V = np.zeros(m2.nv)
    V[m2.nn:] = u[0]
    s2 = State(0.0, V, V.copy(), np.zeros(m2.ne), np.where(yc2 < 0.35, n0, 1.0), np.full(m2.ne, 0.4))
    for _ in integrate(m1, s1, 3.0, 0.05):
        pass
    for step in integrate(m2, s2, 3.0, 0.05):
        pass
    n1d, n2d = _.state.n, step.state.n
    row = np.searchsorted(yc1, yc2 - 1e-9)  # the 1D element at each 2D element's height
    diff = np.abs(n2d - n1d[row]).max()
    print(f"max |n_2D - n_1D| = {diff:.3e}")
    assert diff < 0.01 * n0, diff
    assert n2d[yc2 < 0.04].min() > n0 + 0.05  # the expansion front has passed the bottom 4 cm (1D: 0.716)


def test_lagged_solver_reuses_factorisation_and_matches_direct():
    """Modified Newton: the LU of one matrix preconditions GMRES for a changed one (no new LU)."""
    from twofluid.models.two_fluid_2d import LaggedSolver

    m, s = _riser(0.0)
    s = s.copy(V=np.where(np.arange(m.nv) >= m.nn, 0.024, 0.0), W=np.where(np.arange(m.nv) >= m.nn, 0.016, 0.0))
    idx, val = m.dirichlet(0.01)
    lag = LaggedSolver(m.size, m._fixed, kind="lagged", rtol=1e-10, budget=50)
    direct = LaggedSolver(m.size, m._fixed, kind="direct")
    k = s.copy(t=0.01)
    for it, factor in ((1, 1.0), (2, 1.002), (3, 0.999)):  # iterates of one step: the matrix changes
        k = k.copy(V=k.V * factor, n=np.where(k.n < 1.0, k.n * (2.0 - factor), 1.0))
        m.begin_iteration(it, k)
        A, b = m.assemble(k, s, 0.01, 0.01)
        x_lag = lag.solve(A, b, val, m.pack(k))
        x_dir = direct.solve(A, b, val, m.pack(k))
        assert np.abs(x_lag - x_dir).max() < 1e-7 * np.abs(x_dir).max()
    assert lag.stats["factorisations"] == 1 and lag.stats["gmres_iterations"] > 0
    assert direct.stats["factorisations"] == 3


def _fluidized_cylinder(tangential_slip):
    """A vessel full of a bed fluidized at n = 0.6 by a uniform inflow; the outer wall no-slip or free-slip."""
    mesh = rectangle(0.0, 0.05, 0.0, 0.1, 5, 10, axisymmetric=True)
    mesh.boundaries["axis"] = mesh.boundaries["left"]
    u = drag_laws.steady_fluidization_velocity(CLO.drag, 0.6, SAND.d, SAND.rho_s, SAND.rho_f, SAND.mu_f,
                                               SAND.g, **CLO.drag_params)
    bcs = [Boundary2D("bottom", "inlet", velocity=Schedule((0.0,), (u,))), Boundary2D("axis", "axis"),
           Boundary2D("right", "wall", free_slip=tangential_slip), Boundary2D("top", "outlet")]
    m = TwoFluid2D(mesh, SAND, CLO, bcs, solver="direct")
    V = np.zeros(m.nv)
    V[m.nn:2 * m.nn] = u  # axial component
    return m, State(0.0, V, V.copy(), np.zeros(m.ne), np.full(m.ne, 0.6), np.full(m.ne, 0.4)), u


def test_free_slip_wall_keeps_a_uniform_fluidized_bed_at_rest():
    """With the wall's tangential velocity free the uniform bed is an exact steady state; with no slip
    the wall elements lose drag (the liquid's boundary layer, ~0.05 mm, is not resolved) and the
    mixture circulates — the reason the option exists."""
    m, s, u = _fluidized_cylinder(True)
    end = _run(m, s, t_end=1.0, dt=0.2)[-1].state
    us = end.V - end.W  # 2(1 − n) U_s
    assert np.abs(us).max() < 1e-9 * u and np.abs(end.n - 0.6).max() < 1e-10
    m, s, u = _fluidized_cylinder(False)
    end = _run(m, s, t_end=1.0, dt=0.2)[-1].state
    assert np.abs(end.V - end.W).max() > 1e-2 * u


def test_free_slip_on_an_l_shaped_group_holds_each_nodes_normal_components():
    from twofluid.mesh.quad import remove_block

    mesh = remove_block(rectangle(0.0, 0.05, 0.0, 0.1, 5, 10, axisymmetric=True), 0.0, 0.02, 0.04, 0.1)
    mesh.boundaries["axis"] = mesh.boundaries["left"]
    bcs = [Boundary2D("bottom", "inlet", velocity=Schedule((0.0,), (0.001,))), Boundary2D("axis", "axis"),
           Boundary2D("right", "wall"), Boundary2D("top", "outlet"),
           Boundary2D("cut", "rotating_wall", omega=3.0, free_slip=True)]
    m = TwoFluid2D(mesh, SAND, CLO, bcs, swirl=True, solver="direct")
    idx, val = m.dirichlet(0.0)
    nn, x = m.nn, mesh.points
    fixed = {(int(i) // nn, int(i) % nn): v for i, v in zip(idx[: idx.size // 2], val[: idx.size // 2])}
    cut = mesh.boundary_nodes("cut")
    side = cut[np.isclose(x[cut, 0], 0.02) & (x[cut, 1] > 0.04 + 1e-9)]
    tip = cut[np.isclose(x[cut, 1], 0.04) & (x[cut, 0] < 0.02 - 1e-9) & (x[cut, 0] > 1e-9)]
    assert side.size and tip.size
    assert all((0, i) in fixed and (1, i) not in fixed for i in side)  # radial held, axial free
    assert all((1, i) in fixed and (0, i) not in fixed for i in tip)  # axial held, radial free
    assert all(np.isclose(fixed[(2, i)], 3.0 * x[i, 0]) for i in np.concatenate([side, tip]))  # swirl ωr
