"""The immersed avalanche layer (models/avalanche_1d.py) and its rheology: the exact checks.

Steady uniform flow against the closed form with its observed order, a layer started at φ_eq
that shears with no excess pressure, a dense layer below its friction that does not move, a
loose one that stops once compacted, an undrained dilation, the submerged slope at rest, and the
skeleton modulus that sets no time scale of its own.
"""
import math

import numpy as np
import pytest

from twofluid.closures import registry
from twofluid.closures.granular_rheology import RHEOLOGY_DEFAULTS, boyer_pailha, mu_iv, phi_eq, viscous_number
from twofluid.models.avalanche_1d import AvalancheLayer

RHO_S, RHO_F, D, H = 2500.0, 1041.0, 160e-6, 4.9e-3
ETA = RHO_F * 9.22e-5
RH = dict(RHEOLOGY_DEFAULTS)


def layer(n, phi0, slope, **kw):
    return AvalancheLayer(H, n, phi0, slope, RHO_S, RHO_F, ETA, D, rheology=RH, **kw)


def displacement(lay, t_end):
    """Surface displacement [m] over [0, t_end], trapezoidal over the BDF steps, and the last state."""
    ts, vs, last = [], [], None
    for t, y, _ in lay.steps(t_end):
        last = lay.state(t, y)
        ts.append(t)
        vs.append(last.surface_velocity)
    return float(np.trapezoid(vs, ts)), last


def test_viscous_number_inverts_the_friction_to_round_off_and_is_zero_below_yield():
    rng = np.random.default_rng(1)
    phi = rng.uniform(0.55, 0.6, 200)
    ratio = rng.uniform(0.3, 3.0, 200)
    iv = viscous_number(ratio, phi, **RH)
    moving = ratio > RH["mu_s"] + RH["k_dil"] * (phi - RH["phi_c"])
    assert np.all(iv[~moving] == 0.0) and np.all(iv[moving] > 0.0)
    mu, _ = boyer_pailha(iv[moving], phi[moving], **RH)
    np.testing.assert_allclose(mu, ratio[moving], rtol=0, atol=1e-13)


def test_registry_holds_the_rheology_and_the_permeability():
    assert registry.get("granular_rheology", "boyer_pailha").params["phi_c"] == 0.585
    assert registry.get("permeability", "carman_kozeny").params["constant"] == 180.0


def _steady(slope):
    i_star = float(viscous_number(math.tan(math.radians(slope)), 0.0, **{**RH, "k_dil": 0.0}))
    return i_star, float(phi_eq(i_star, RH["phi_c"]))


@pytest.mark.parametrize("n", [10, 20, 40])
def test_started_at_phi_eq_the_layer_shears_with_no_excess_pressure(n):
    i_star, phi_s = _steady(25.0)
    lay = layer(n, phi_s, 25.0)
    s = lay.run([0.0, 5.0, 50.0])[-1]
    assert np.abs(s.p).max() <= 1e-6  # Pa: M × round-off of φ (4e7 × ~1e-16 × a few)
    # P_s = M (φ − φ̄) keeps ~ ε φ M / P_s of its digits (3e-9 at the top element of 10); through the
    # flat μ(I_v) (dμ/d ln I_v ≈ 0.04) that is ~1e-9 of tan ψ
    assert np.abs(s.tan_psi).max() <= 1e-8 and s.surface_velocity > 1e-4
    # φ moves only by that round-off times the shear strain, φ γ̇ t |tan ψ|
    assert np.abs(s.phi - phi_s).max() <= phi_s * s.shear_rate.max() * 50.0 * 1e-8


def test_steady_uniform_flow_matches_the_closed_form_with_second_order():
    """u(z) = I* Δρ g cos θ φ* (h z − z²/2)/η_f with μ(I*) = tan θ, φ* = φ_eq(I*): the piecewise-linear
    field's relative L2 error (5-point Gauss per element) falls as Δz² and is ≤ 1e-3 at 40 elements."""
    i_star, phi_s = _steady(25.0)
    assert mu_iv(i_star, RH["mu_s"], RH["mu_2"], RH["i_0"], RH["phi_c"]) == pytest.approx(math.tan(math.radians(25.0)))
    c = i_star * (RHO_S - RHO_F) * 9.81 * math.cos(math.radians(25.0)) * phi_s / ETA
    xg, wg = np.polynomial.legendre.leggauss(5)
    errs, phis = [], []
    for n in (10, 20, 40):
        s = layer(n, phi_s, 25.0).run([0.0, 20.0])[-1]
        h = s.z[-1]
        assert h == pytest.approx(H, rel=1e-12)
        e2 = r2 = 0.0
        for a, b, ua, ub in zip(s.z[:-1], s.z[1:], s.u[:-1], s.u[1:]):
            z = 0.5 * (a + b) + 0.5 * (b - a) * xg
            uh = ua + (ub - ua) * (z - a) / (b - a)
            ue = c * (h * z - 0.5 * z * z)
            e2 += 0.5 * (b - a) * np.sum(wg * (uh - ue) ** 2)
            r2 += 0.5 * (b - a) * np.sum(wg * ue**2)
        errs.append(math.sqrt(e2 / r2))
        phis.append(np.abs(s.phi - phi_s).max())
    order = np.polyfit(np.log([10, 20, 40]), np.log(errs), 1)[0]
    assert errs[-1] <= 1e-3
    assert -2.1 <= order <= -1.9
    assert max(phis) <= 1e-9  # uniform φ* is exact: only tan ψ's round-off times the strain (above)


@pytest.mark.parametrize("n", [10, 20])
def test_a_graded_layer_keeps_the_solids_and_the_steady_flows_nodal_velocities(n):
    """Elements refined towards the base (top 30 times the base): the solids sum to φ* h, the
    thicknesses are a geometric progression of ratio 30^(1/(N−1)), and the nodal velocities of the
    steady flow are still the closed form's (γ̇ is linear in z and taken at element centres)."""
    i_star, phi_s = _steady(25.0)
    lay = layer(n, phi_s, 25.0, grading=30.0)
    assert lay.m.sum() == pytest.approx(phi_s * H, rel=1e-14)
    np.testing.assert_allclose(lay.m[1:] / lay.m[:-1], 30.0 ** (1.0 / (n - 1)), rtol=1e-13)
    assert lay.m[-1] / lay.m[0] == pytest.approx(30.0, rel=1e-13)
    s = lay.run([0.0, 20.0])[-1]
    c = i_star * (RHO_S - RHO_F) * 9.81 * math.cos(math.radians(25.0)) * phi_s / ETA
    h = s.z[-1]
    np.testing.assert_allclose(s.u, c * (h * s.z - 0.5 * s.z**2), rtol=1e-8, atol=1e-12 * s.u[-1])
    assert np.abs(s.p).max() <= 1e-6


def test_submerged_slope_at_rest_carries_the_buoyant_weight_with_tau_over_ps_tan_theta():
    lay = layer(40, 0.59, 20.0)
    s = lay.state(0.0, lay.y0)
    # P_s = M (φ − φ̄) holds ~ε φ M / P_s of relative round-off (φ − φ̄ is P_s/M ≪ φ)
    digits = 8 * np.finfo(float).eps * s.phi * lay.modulus / s.p_s
    assert np.all(np.abs(lay.tau / s.p_s / math.tan(math.radians(20.0)) - 1.0) <= digits)
    base = (RHO_S - RHO_F) * 9.81 * math.cos(math.radians(20.0)) * 0.59 * H * (1 - 0.5 / 40)
    assert s.p_s[0] == pytest.approx(base, rel=digits[0])
    assert np.abs(s.p).max() <= 1e-6


def test_dense_layer_below_its_friction_does_not_move():
    """φ0 ≥ φ_c and tan θ < μ_s: less than 1e-9 m in 100 s."""
    for phi0 in (RH["phi_c"], 0.592):
        d, last = displacement(layer(20, phi0, 20.0), 100.0)
        assert abs(d) < 1e-9 and np.abs(last.p).max() <= 1e-6


def test_loose_layer_below_mu_s_flows_compacts_and_stops():
    """φ0 < φ_c with tan θ < μ_s but above μ_s + K (φ0 − φ_c): it contracts (p > 0) and flows, and
    every element that has compacted to the yield fraction φ_stop = φ_c − (μ_s − tan θ)/K stops.
    Near yield γ̇ ∝ (excess friction)², so the last of the motion dies algebraically: the
    displacement converges (its last 700 of 1000 s add < 1 % of it)."""
    slope, phi0 = 22.0, 0.56
    tan_t = math.tan(math.radians(slope))
    assert RH["mu_s"] + RH["k_dil"] * (phi0 - RH["phi_c"]) < tan_t < RH["mu_s"]
    phi_stop = RH["phi_c"] - (RH["mu_s"] - tan_t) / RH["k_dil"]
    lay = layer(10, phi0, slope)
    ts, vs, last, peak_p = [], [], None, 0.0
    for t, y, _ in lay.steps(1000.0):
        last = lay.state(t, y)
        ts.append(t)
        vs.append(last.surface_velocity)
        peak_p = max(peak_p, last.p.max())
    ts, vs = np.array(ts), np.array(vs)
    d = np.concatenate([[0.0], np.cumsum(0.5 * (vs[1:] + vs[:-1]) * np.diff(ts))])
    assert peak_p > 1.0 and vs[0] > 0.0
    assert vs[-1] < 1e-3 * vs.max()
    assert d[-1] - d[np.searchsorted(ts, 300.0)] < 0.01 * d[-1] and d[-1] < 1.0
    compacted = last.phi >= phi_stop + 1e-4
    assert compacted.any() and np.all(last.shear_rate[compacted] == 0.0)
    assert np.all(last.phi > phi0 + 0.5 * (phi_stop - phi0))  # every element has compacted


def test_undrained_dilation_pressure_follows_phi_and_mass_is_conserved():
    """Both ends closed: a dense layer dilates its skeleton (φ̄ falls) but no liquid can enter, so
    the layer's thickness, its liquid and solids stay to round-off, and the pressure drop in each
    element is the modulus times the change of φ − φ̄."""
    lay = layer(20, 0.59, 25.0, top="closed")
    s0 = lay.state(0.0, lay.y0)
    states = lay.run([0.0, 1.0, 10.0, 100.0])
    for s in states[1:]:
        liquid = np.sum(np.diff(s.z)) - lay.m.sum()
        assert abs(liquid - (np.sum(np.diff(s0.z)) - lay.m.sum())) <= 1e-15 * H * 20
        dp = s.p - s0.p
        np.testing.assert_allclose(dp, -lay.modulus * ((s.phi - s0.phi) - (s.phi_bar - s0.phi_bar)), rtol=0,
                                   atol=1e-8)
    last = states[-1]
    assert last.p.min() < -0.1  # the dilation sucked: the pressure fell
    assert np.all(last.phi_bar <= s0.phi_bar + 1e-15)


def test_skeleton_modulus_sets_no_time_scale():
    """M of 4e6 and 4e7 Pa (consolidation times η_f h²/(k M) of ~20 and ~2 ms): the base pressure and
    surface velocity of a dilating layer agree to 1 %."""
    out = []
    for m in (4e6, 4e7):
        s = layer(20, 0.578, 25.0, modulus=m).run([0.0, 5.0, 30.0])
        out.append([(x.base_pressure, x.surface_velocity) for x in s[1:]])
    out = np.array(out)
    np.testing.assert_allclose(out[0], out[1], rtol=1e-2)
