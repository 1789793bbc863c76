"""Compliant base of the shear column (Lysmer–Kuhlemeyer dashpot, outcrop motion; docs/liquefaction.md).

Exact solution: a uniform linear layer (H = 10 m, ρ = 2000 kg/m³, G = 50 MPa, V_s = 158.1 m/s,
f1 = V_s/(4H) = 3.953 Hz) on an elastic half-space with impedance ratio α = ρ V_s/(ρ_r V_r),
shaken harmonically at the outcrop: surface/outcrop amplitude = 1/√(cos²kH + α² sin²kH)
(k = ω/V_s, no damping), or 1/|cos k*H + i α* sin k*H| with a Kelvin–Voigt viscosity
(:func:`~twofluid.models.shear_column.layer_amplification`).

Tolerances:
- amplification within 0.2 % with 40 elements and 100 steps per period. The error is that of
  the discretisation: average acceleration lengthens the period by (ωΔt)²/12 = 3.3e-4 and the
  linear elements shorten it by about (kh)²/24 ≤ 1.2e-4 (kH ≤ 3π/4), which moves the
  amplification by at most a few 1e-4 off resonance (measured: 0.6e-4 at f1, 1.5e-4 at f1/2,
  −2.3e-4 at 1.5 f1 for α = 0.5; halving Δt divides the f1/2 error by 4.4). Measured over 5
  periods after 7 (α = 0.5: radiation damping ξ ≈ 2α/π ≈ 0.3 has removed the start-up
  transient, e^-14; the same numbers to 4e-6 after 25 periods) by a least-squares fit of
  sin ωt, cos ωt;
- α → 0: with α = 1e-4 (10 % Kelvin–Voigt damping at f1, so that a steady state exists;
  18 and 10 periods, 16 periods of f1 before a 2-period fit: the start-up transient is down
  to e^-10) both bases are within 0.1 % of their exact solutions (measured −0.9e-4 at f1,
  2.4e-4 at f1/2), the compliant amplification is within 0.1 % of the rigid-base one, and
  their ratio is the exact ratio (1 − 6.37e-4 at f1, 1 − 2.8e-6 at f1/2) within 1e-5
  (measured 1.8e-7 and 5e-11);
- energy: average acceleration is the trapezoidal rule, so E(t) + (work of the dashpot) = E(0)
  to round-off (asserted 1e-12, measured 5e-15); a downgoing pulse leaves the column through a
  matched base (α = 1) with < 1e-4 of its energy left (measured 1.3e-6) and leaves the reflected
  fraction R² = ((α − 1)/(α + 1))² = 1/9 for α = 0.5 and 2 within 2 % (measured ±0.34 %); a
  rigid base keeps all of it (1e-12).
"""
from __future__ import annotations

import numpy as np
import pytest

from twofluid.models.shear_column import ShearColumn, layer_amplification

H, NE, RHO, G = 10.0, 40, 2000.0, 50e6
VS = np.sqrt(G / RHO)
F1 = VS / (4 * H)


def _impedance(alpha):
    return None if alpha is None else RHO * VS / alpha


def _amplification(f, alpha, eta=0.0, periods=30, steps_per_period=100, fit=5):
    """Steady surface/outcrop acceleration amplitude under a_g = sin ωt (time domain)."""
    col = ShearColumn(np.linspace(0.0, H, NE + 1), np.full(NE, RHO), reduction="linear",
                      viscosity=eta, base_impedance=_impedance(alpha))
    w = 2 * np.pi * f
    dt = 1.0 / (steps_per_period * f)
    s = col.rest()
    t, top = [], []
    for k in range(1, steps_per_period * periods + 1):
        a_g = np.sin(w * k * dt)
        s = col.step(s, dt, a_g, G)
        t.append(s.t)
        top.append(s.a[-1] + a_g)  # absolute = relative to the outcrop + outcrop
    n = steps_per_period * fit
    t, top = np.array(t[-n:]), np.array(top[-n:])
    coef, *_ = np.linalg.lstsq(np.column_stack([np.sin(w * t), np.cos(w * t)]), top, rcond=None)
    return float(np.hypot(*coef))


@pytest.mark.parametrize("ratio", [1.0, 0.5, 1.5])
def test_harmonic_amplification_on_an_elastic_half_space(ratio):
    """At the first resonance (kH = π/2: exactly 1/α = 2) and off it (f1/2, 1.5 f1: 1.2649)."""
    alpha = 0.5
    f = ratio * F1
    exact = float(layer_amplification(f, H, RHO, G, _impedance(alpha)))
    kh = 2 * np.pi * f / VS * H
    assert exact == pytest.approx(1.0 / np.sqrt(np.cos(kh) ** 2 + alpha**2 * np.sin(kh) ** 2), rel=1e-12)
    got = _amplification(f, alpha, periods=12)
    assert abs(got / exact - 1.0) < 2e-3, (ratio, got, exact)
    # and not the rigid-base answer (a dashpot that did nothing would give 1/|cos kH|)
    rigid = 1.0 / abs(np.cos(kh)) if ratio != 1.0 else np.inf
    assert abs(got / rigid - 1.0) > 0.05


@pytest.mark.parametrize("ratio, periods", [(1.0, 18), (0.5, 10)])
def test_small_impedance_ratio_recovers_the_rigid_base(ratio, periods):
    """α = 1e-4 against the rigid base, with 10 % Kelvin–Voigt damping at f1 (a steady state)."""
    eta = 2 * 0.10 * G / (2 * np.pi * F1)
    f = ratio * F1
    rigid = _amplification(f, None, eta, periods, fit=2)
    soft = _amplification(f, 1e-4, eta, periods, fit=2)
    exact_rigid = float(layer_amplification(f, H, RHO, G, None, eta))
    exact_soft = float(layer_amplification(f, H, RHO, G, _impedance(1e-4), eta))
    assert rigid == pytest.approx(exact_rigid, rel=1e-3)
    assert soft == pytest.approx(exact_soft, rel=1e-3)
    assert abs(soft / rigid - 1.0) < 1e-3
    # the small difference itself is the exact one (the discretisation errors cancel)
    assert abs(soft / rigid - exact_soft / exact_rigid) < 1e-5


def _pulse(alpha, ne=200, width=0.5, t_end=0.06):
    """Gaussian pulse at mid-depth moving down (u = f(y + V_s t)); undamped linear column.

    It reaches the base at 0.032 s and has passed it by 0.045 s; what the base reflects
    reaches the surface after t_end.
    """
    y = np.linspace(0.0, H, ne + 1)
    col = ShearColumn(y, np.full(ne, RHO), reduction="linear", base_impedance=_impedance(alpha))
    s = col.rest()
    x = (y - H / 2) / width
    s.u = 1e-3 * np.exp(-x * x)
    s.v = VS * 1e-3 * np.exp(-x * x) * (-2 * x / width)
    s = col.at_equilibrium(s, 0.0, G)
    e0 = col.energy(s, G)
    dt = (H / ne) / VS
    work, drift = 0.0, 0.0
    for _ in range(int(round(t_end / dt))):
        new = col.step(s, dt, 0.0, G)
        work += col.dashpot_work(s, new)
        s = new
        drift = max(drift, abs(col.energy(s, G) + work - e0) / e0)
    return col.energy(s, G) / e0, work / e0, drift


@pytest.mark.parametrize("alpha", [1.0, 0.5, 2.0, None])
def test_dashpot_absorbs_an_outgoing_pulse(alpha):
    left, absorbed, drift = _pulse(alpha)
    assert drift < 1e-12  # discrete energy balance, at every step
    if alpha is None:
        assert abs(left - 1.0) < 1e-12 and absorbed == 0.0
    elif alpha == 1.0:
        assert left < 1e-4  # matched impedance: the pulse leaves
        assert absorbed > 1.0 - 1e-4
    else:
        assert left == pytest.approx(((alpha - 1) / (alpha + 1)) ** 2, rel=0.02)


def test_compliant_base_is_validated():
    with pytest.raises(ValueError, match="base_impedance"):
        ShearColumn(np.linspace(0.0, 1.0, 3), np.full(2, RHO), base_impedance=0.0)
