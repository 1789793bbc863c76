"""verification.slope_flow: exact flows of a Newtonian and a Bingham layer on an infinite slope.

Compared quantities and tolerances:
- velocity u(z) [m/s]: against hand values and against the governing balance itself — the
  profiles are polynomials of degree ≤ 2, so their derivatives from a degree-2 fit of exact
  samples are exact to round-off (relative 1e-9, the conditioning of the fit);
- flux q [m²/s]: Simpson's rule on the piecewise-quadratic profile, exact when z_p is a node
  (relative 1e-12);
- the limits τ_y → 0 (first order in τ_y, stated coefficient) and τ_y ≥ ρ g h sin α (exactly 0);
- the start-up series: the PDE by centred differences (second order; tolerance from the step),
  the steady state at large t to 1e-12 relative.
Sources: Bird, Stewart & Lightfoot (2002) §2.2 (film), Liu & Mei (1989) (Bingham on a slope).
"""
import math

import numpy as np
import pytest

from twofluid.casefile.schema import CaseError
from twofluid.verification import slope_flow as sf

RHO, MU, H = 1900.0, 50.0, 3.0
ALPHA = math.atan(0.03)                      # a 3 % slope
K = RHO * sf.G * math.sin(ALPHA) / MU        # ρ g sin α / μ [1/(m s)]


def _simpson(f, a, b, n=64):
    z = np.linspace(a, b, n + 1)
    w = np.ones(n + 1)
    w[1:-1:2], w[2:-1:2] = 4.0, 2.0
    return (b - a) / (3 * n) * np.dot(w, f(z))


def test_film_flow_balance_boundary_conditions_and_flux():
    """μ u'' = −ρ g sin α, u(0) = 0 (no slip), u'(h) = 0 (no stress at the free surface)."""
    z = np.linspace(0.0, H, 13)
    u = sf.film_flow_velocity(z, H, RHO, MU, ALPHA)
    c2, c1, c0 = np.polyfit(z, u, 2)
    assert 2 * c2 == pytest.approx(-K, rel=1e-9)          # u'' = −ρ g sin α/μ
    assert abs(c0) < 1e-12 * u.max() and u[0] == 0.0
    assert 2 * c2 * H + c1 == pytest.approx(0.0, abs=1e-9 * K * H)
    # symmetry: the free surface is the axis of the parabola, u(h − s) is the maximum minus K s²/2
    s = np.linspace(0.0, H, 7)
    np.testing.assert_allclose(sf.film_flow_velocity(H - s, H, RHO, MU, ALPHA),
                               sf.film_flow_surface_velocity(H, RHO, MU, ALPHA) - 0.5 * K * s ** 2,
                               rtol=1e-13, atol=1e-15)
    q = sf.film_flow_flux(H, RHO, MU, ALPHA)
    assert q == pytest.approx(_simpson(lambda x: sf.film_flow_velocity(x, H, RHO, MU, ALPHA), 0, H), rel=1e-12)
    assert q / H == pytest.approx(2 / 3 * sf.film_flow_surface_velocity(H, RHO, MU, ALPHA), rel=1e-14)
    # scaling: u_s ∝ h², q ∝ h³
    assert sf.film_flow_flux(2 * H, RHO, MU, ALPHA) == pytest.approx(8 * q, rel=1e-14)


def test_film_flow_hand_value():
    """ρ = 2000 kg/m³, μ = 1000 Pa s, h = 2 m, sin α = 0.02: u_s = 2000 · 9.80665 · 0.02 · 4/2000."""
    a = math.asin(0.02)
    assert sf.film_flow_surface_velocity(2.0, 2000.0, 1000.0, a) == pytest.approx(0.784532, rel=1e-12)
    assert float(sf.film_flow_velocity(0.0, 2.0, 2000.0, 1000.0, a)) == 0.0


def test_bingham_plug_sheared_layer_and_stress():
    """Liu & Mei (1989): τ = τ_y + μ_p u' below z_p = h − τ_y/(ρ g sin α), rigid plug above."""
    tau_y = 0.4 * RHO * sf.G * math.sin(ALPHA) * H      # 40 % of the bed shear stress
    zp = sf.bingham_plug_base(H, RHO, tau_y, ALPHA)
    assert zp == pytest.approx(0.6 * H, rel=1e-14)
    up = sf.bingham_plug_velocity(H, RHO, MU, tau_y, ALPHA)
    assert up == pytest.approx(K * zp ** 2 / 2, rel=1e-14)
    plug = np.linspace(zp, H, 9)
    np.testing.assert_allclose(sf.bingham_slope_velocity(plug, H, RHO, MU, tau_y, ALPHA), up, rtol=1e-15)
    # the sheared layer is the Newtonian film of thickness z_p (the plug exerts no extra stress)
    zs = np.linspace(0.0, zp, 11)
    np.testing.assert_allclose(sf.bingham_slope_velocity(zs, H, RHO, MU, tau_y, ALPHA),
                               sf.film_flow_velocity(zs, zp, RHO, MU, ALPHA), rtol=1e-14, atol=1e-16)
    # stress balance in the sheared layer: τ_y + μ_p u'(z) = ρ g sin α (h − z)
    c2, c1, _ = np.polyfit(zs, sf.bingham_slope_velocity(zs, H, RHO, MU, tau_y, ALPHA), 2)
    for z in (0.0, 0.3 * zp, zp):
        assert tau_y + MU * (2 * c2 * z + c1) == pytest.approx(RHO * sf.G * math.sin(ALPHA) * (H - z),
                                                              rel=1e-9)
    q = sf.bingham_slope_flux(H, RHO, MU, tau_y, ALPHA)
    quad = (_simpson(lambda x: sf.bingham_slope_velocity(x, H, RHO, MU, tau_y, ALPHA), 0, zp)
            + up * (H - zp))
    assert q == pytest.approx(quad, rel=1e-12)


def test_bingham_hand_values():
    a = math.asin(0.02)         # ρ g sin α = 392.266 Pa/m for ρ = 2000
    tau_y = 392.266
    assert sf.bingham_plug_base(2.0, 2000.0, tau_y, a) == pytest.approx(1.0, rel=1e-12)
    assert sf.bingham_plug_velocity(2.0, 2000.0, 1000.0, tau_y, a) == pytest.approx(0.196133, rel=1e-12)
    assert sf.bingham_slope_flux(2.0, 2000.0, 1000.0, tau_y, a) == pytest.approx(0.392266 * 5 / 6, rel=1e-12)


def test_bingham_limits():
    z = np.linspace(0.0, H, 31)
    newton = sf.film_flow_velocity(z, H, RHO, MU, ALPHA)
    np.testing.assert_array_equal(sf.bingham_slope_velocity(z, H, RHO, MU, 0.0, ALPHA), newton)
    assert sf.bingham_slope_flux(H, RHO, MU, 0.0, ALPHA) == pytest.approx(sf.film_flow_flux(H, RHO, MU, ALPHA),
                                                                         rel=1e-14)
    # tau_y -> 0: the surface velocity falls by K h δ to first order, δ = τ_y/(ρ g sin α)
    drive = RHO * sf.G * math.sin(ALPHA)
    for tau_y in (1e-3, 1e-5):
        delta = tau_y / drive
        us = sf.bingham_plug_velocity(H, RHO, MU, tau_y, ALPHA)
        assert sf.film_flow_surface_velocity(H, RHO, MU, ALPHA) - us == pytest.approx(K * H * delta, rel=2 * delta / H)
    # no flow once the yield stress reaches the bed shear stress ρ g h sin α
    tb = drive * H
    for tau_y in (tb, 1.5 * tb):
        assert np.all(sf.bingham_slope_velocity(z, H, RHO, MU, tau_y, ALPHA) == 0.0)
        assert sf.bingham_slope_flux(H, RHO, MU, tau_y, ALPHA) == 0.0
    assert sf.bingham_plug_velocity(H, RHO, MU, 0.999 * tb, ALPHA) > 0.0
    # a level bed does not flow
    assert sf.bingham_plug_velocity(H, RHO, MU, 1.0, 0.0) == 0.0
    assert sf.film_flow_surface_velocity(H, RHO, MU, 0.0) == 0.0


def test_film_startup_series():
    """∂u/∂t = ν ∂²u/∂z² + g sin α from rest; u(0) = 0, ∂u/∂z(h) = 0 (separation of variables)."""
    nu = MU / RHO
    t_visc = H * H / nu
    z = np.array([0.0, 0.4 * H, H])
    np.testing.assert_allclose(sf.film_flow_startup(z, 0.0, H, RHO, MU, ALPHA), 0.0,
                               atol=5e-10 * sf.film_flow_surface_velocity(H, RHO, MU, ALPHA))
    np.testing.assert_allclose(sf.film_flow_startup(z, 20 * t_visc, H, RHO, MU, ALPHA),
                               sf.film_flow_velocity(z, H, RHO, MU, ALPHA), rtol=1e-12, atol=1e-15)
    # the PDE at an interior point, centred differences (errors O(dt²), O(dz²) of ~1e-8 here)
    t, zc = 0.05 * t_visc, 0.5 * H
    dt, dz = 1e-3 * t, 1e-3 * H

    def u(zz, tt):
        return float(sf.film_flow_startup(zz, tt, H, RHO, MU, ALPHA, n_terms=4000))

    ut = (u(zc, t + dt) - u(zc, t - dt)) / (2 * dt)
    uzz = (u(zc + dz, t) - 2 * u(zc, t) + u(zc - dz, t)) / dz ** 2
    assert ut == pytest.approx(nu * uzz + sf.G * math.sin(ALPHA), rel=1e-5)
    # monotone approach to the steady profile from below
    times = t_visc * np.array([0.01, 0.1, 0.5, 1.0, 3.0])
    us = [float(sf.film_flow_startup(H, tt, H, RHO, MU, ALPHA)) for tt in times]
    assert np.all(np.diff(us) > 0) and us[-1] < sf.film_flow_surface_velocity(H, RHO, MU, ALPHA)


@pytest.mark.parametrize("call, key", [
    (lambda: sf.film_flow_velocity([0.0], 0.0, RHO, MU, ALPHA), "h_m"),
    (lambda: sf.film_flow_velocity([0.0], H, RHO, -1.0, ALPHA), "mu"),
    (lambda: sf.film_flow_velocity([0.0], H, float("nan"), MU, ALPHA), "rho"),
    (lambda: sf.film_flow_velocity([H + 0.1], H, RHO, MU, ALPHA), "z_m"),
    (lambda: sf.film_flow_velocity([-0.1], H, RHO, MU, ALPHA), "z_m"),
    (lambda: sf.film_flow_velocity([0.0], H, RHO, MU, 2.0), "alpha_rad"),
    (lambda: sf.bingham_slope_velocity([0.0], H, RHO, MU, -1.0, ALPHA), "tau_y"),
    (lambda: sf.bingham_slope_velocity([0.0], H, RHO, 0.0, 1.0, ALPHA), "mu_p"),
    (lambda: sf.film_flow_startup([0.0], -1.0, H, RHO, MU, ALPHA), "t_s"),
])
def test_bad_inputs_one_line(call, key):
    with pytest.raises(CaseError) as e:
        call()
    msg = str(e.value)
    assert msg.startswith(f"slope_flow: {key}: ") and "\n" not in msg
