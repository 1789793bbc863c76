"""The 1D two-component model: equilibrium, gauge invariance, conservation, Richardson–Zaki."""
import numpy as np
import pytest

from twofluid.casefile.builder import build
from twofluid.casefile.loader import load_case
from twofluid.timestepping.backward_euler import integrate

G = 9.81


def settled_case(element="1VW/0P/0n", p_out=0.0):
    c = load_case("settling-illite")
    c["mesh"].update(length=1.0, elements=40, element=element)
    c["materials"].update(particle_diameter=1e-3, sphericity=1.0)
    c["closures"]["solids_pressure"].update(compressibility=0.015)
    c["initial"].update(bed_height=0.6, state="settled", porosity=0.45)
    c["boundary"]["top"]["pressure"] = p_out
    return c


def with_gradient(b):
    """Bed porosity varying linearly 0.40 → 0.50 over the bed; n̄ from the discrete equilibrium."""
    from twofluid.closures.solids_pressure import reference_porosity_for

    m, s = b.model, b.state
    bed = s.n < 1.0
    y = m.mesh.centres
    s.n[bed] = 0.40 + 0.10 * y[bed] / y[bed].max()
    ps = m.settled_solids_pressure(s.n)
    s.n_bar[bed] = reference_porosity_for(s.n[bed], ps[bed], m.clo.A, m.clo.p_ref)
    return s


def run(b, state, t_end, dt):
    last = state
    for step in integrate(b.model, state, t_end, dt, settings=b.settings):
        last = step.state
    return last


def test_settled_bed_with_porosity_gradient_stays_at_rest_with_hydrostatic_pressure():
    b = build(settled_case())
    s0 = with_gradient(b)
    s = run(b, s0, 2.0, 0.1)
    # at rest to round-off: velocities below 1e-9 of the particles' Stokes settling velocity
    mat = b.model.mat
    u_t = (mat.rho_s - mat.rho_f) * G * mat.d ** 2 / (18 * mat.mu_f)
    assert np.abs(s.V).max() < 1e-9 * u_t and np.abs(s.W).max() < 1e-9 * u_t
    assert np.abs(s.n - s0.n).max() < 1e-12
    y = b.model.mesh.centres
    rho_f = b.model.mat.rho_f
    np.testing.assert_allclose(s.P, rho_f * G * (1.0 - y), rtol=1e-10)
    # P_s at the bottom carries the buoyant weight of all the solids above it
    ps = b.model.solids_pressure(s.n, s.n_bar)
    h = b.model.mesh.lengths
    weight = (b.model.mat.rho_s - rho_f) * G * ((1 - s.n) * h).sum()
    assert ps[0] == pytest.approx(weight - (b.model.mat.rho_s - rho_f) * G * (1 - s.n[0]) * h[0] / 2, rel=1e-9)


def test_adding_a_constant_to_the_outlet_pressure_changes_no_velocity_or_porosity():
    """Gauge invariance, to the Picard tolerance.

    The two runs solve the same equations; each step stops its Picard loop at an
    iterate within ``tol`` of the fixed point (velocities relative to the velocity
    scale, porosity absolute), and the two runs may stop one iterate apart, so they
    agree to a few ``tol``, not to one machine's round-off. The thesis's ∇(nP) form
    changes n at the 1e-2 level here.
    """
    res = []
    for p_out in (0.0, 1.0e5):
        c = load_case("fluidized-bed-step")
        c["mesh"].update(elements=50)
        c["boundary"]["top"]["pressure"] = p_out
        b = build(c)
        res.append(run(b, b.state, 2.0, 0.05))
    a, b2 = res
    tol, scale = b.settings.tol, b.model.velocity_scale(a)
    assert np.abs(a.V - b2.V).max() < 10 * tol * scale
    assert np.abs(a.W - b2.W).max() < 10 * tol * scale
    assert np.abs(a.n - b2.n).max() < 10 * tol
    np.testing.assert_allclose(b2.P - a.P, 1.0e5, rtol=0, atol=10 * tol * np.abs(a.P).max())


@pytest.mark.parametrize("name", ["settling-illite", "fluidized-bed-step"])
def test_solids_volume_is_conserved_to_round_off(name):
    c = load_case(name)
    b = build(c)
    m = b.model
    v0 = m.solids_volume(b.state)
    s = run(b, b.state, 20 * c["time"]["step"], c["time"]["step"])
    assert abs(m.solids_volume(s) - v0) / v0 < 1e-12


def rz_case(n_bed, n_flow, elements=40, end=1.0, dt=0.05):
    c = load_case("fluidized-bed-step")
    c["closures"]["drag"].update(law="wen_yu", stokes=True)  # exactly U = U_t n^4.65
    c["closures"]["solids_pressure"]["fluidized"] = "none"  # the drag law's identity alone, P_s negligible
    c["mesh"].update(elements=elements)
    c["initial"].update(state="uniform", porosity=n_bed, bed_height=0.5, settled_height=-1.0)
    c["boundary"]["bottom"].update(times=[0.0], porosities=[], velocities=[_rz_velocity(c, n_flow)])
    c["time"].update(end=end, step=dt)
    return c


def _rz_velocity(c, n):
    ma = c["materials"]
    ut = (ma["particle_density"] - ma["liquid_density"]) * G * ma["particle_diameter"] ** 2 / (18 * ma["liquid_viscosity"])
    return ut * n ** 4.65


@pytest.mark.parametrize("n", [0.5, 0.7, 0.9])
def test_uniform_bed_at_the_richardson_zaki_velocity_stays_at_rest(n):
    """U = U_t n^4.65 (computed from Richardson–Zaki, not from the drag law) holds the bed at n.

    A bed off its equilibrium porosity by δ would move at about k U_t n^(k−1) δ, so a
    solids velocity below 1e-6 U_t shows the model's steady porosity equals the
    Richardson–Zaki one far better than the 0.5 % asked.
    """
    c = rz_case(n, n)
    b = build(c)
    s = run(b, b.state, 2.0, 0.05)
    bed = b.model.mesh.centres < 0.45  # the bed, away from its surface
    assert np.abs(s.n[bed] / n - 1).max() < 1e-6
    us = b.model.element_fields(s)["Us_m_s"][bed]
    u_t = _rz_velocity(c, 1.0)
    assert np.abs(us).max() < 1e-6 * u_t


def test_settled_start_warns_where_the_fluidized_bed_pressure_exceeds_the_weight():
    """With the Foscolo–Gibilaro term (here 30× its coefficient) the top bed element carries less
    weight than P_e alone: it cannot start at rest; its exponential part gets 1e-6 p_ref (the
    closest to rest) and a warning says so. The elements below are at their settled P_s exactly."""
    from twofluid.casefile.schema import CaseWarning

    c = settled_case()
    c["closures"]["solids_pressure"].update(fluidized="foscolo_gibilaro", fluidized_coefficient=100.0)
    with pytest.warns(CaseWarning, match="in 1 of 24 bed elements"):
        b = build(c)
    m, s = b.model, b.state
    bed = np.nonzero(s.n < 1.0)[0]
    top = bed[-1]
    ps = m.solids_pressure(s.n, s.n_bar)
    want = m.settled_solids_pressure(s.n)
    np.testing.assert_allclose(ps[bed[:-1]], want[bed[:-1]], rtol=1e-9)
    mat, clo = m.mat, m.clo
    pe = clo.fluidized_pressure(s.n[top], mat.d, mat.rho_s, mat.rho_f, mat.g, **clo.fluidized_params)
    assert pe > want[top] and ps[top] - pe == pytest.approx(1e-6 * clo.p_ref, rel=1e-6)
