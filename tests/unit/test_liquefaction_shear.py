"""Newmark shear column of the liquefaction model (models/shear_column.py).

Tolerances: the first natural frequency of a uniform column on a rigid base,
f1 = √(G/ρ)/(4H), within 0.1 % with 40 elements and 200 steps per period
(expected error: O(h²) ≈ 1e-4 from the mesh plus (ωΔt)²/12 ≈ 8e-5 from the
average-acceleration period elongation); energy of the undamped linear column
constant to 1e-9 (the scheme conserves it exactly up to round-off); the
amplitude decay of the damped first mode within 5 % of the Rayleigh ratio ξ(ω1);
a resonance test against the steady-state response of a single mode.
"""
from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import solve_banded

from twofluid.models.shear_column import NewmarkFailure, ShearColumn, rayleigh_coefficients

H, NE, RHO, G = 10.0, 40, 2000.0, 50e6


def _mode_one(col, amplitude=1e-3):
    """Column displaced in the first mode shape, at rest, with a consistent acceleration."""
    y = col.y
    s = col.rest()
    s.u = amplitude * np.sin(np.pi * y / (2 * H))
    s.gamma = np.diff(s.u) / col.h
    md, mo = col._mass_bands()
    f = col.internal_force(G * s.gamma)
    ab = np.zeros((3, NE))
    ab[0, 1:], ab[1], ab[2, :-1] = mo[1:], md[1:], mo[1:]
    s.a[1:] = solve_banded((1, 1), ab, -f[1:])
    return s


def _crossings(t, u):
    i = np.flatnonzero((u[:-1] > 0) & (u[1:] <= 0))
    return t[i] + (t[i + 1] - t[i]) * u[i] / (u[i] - u[i + 1])


def test_first_natural_frequency_and_no_numerical_damping():
    col = ShearColumn(np.linspace(0, H, NE + 1), np.full(NE, RHO), reduction="linear")
    f1 = np.sqrt(G / RHO) / (4 * H)  # 3.953 Hz
    dt = 1.0 / (200 * f1)
    s = _mode_one(col)
    e0 = col.energy(s, G)
    t, ut, energy = [], [], []
    for _ in range(2000):  # 10 periods
        s = col.step(s, dt, 0.0, G)
        t.append(s.t)
        ut.append(s.u[-1])
        energy.append(col.energy(s, G))
    tc = _crossings(np.array(t), np.array(ut))
    f_num = 1.0 / np.mean(np.diff(tc))
    assert abs(f_num - f1) / f1 < 1e-3
    assert np.max(np.abs(np.array(energy) - e0)) / e0 < 1e-9
    assert np.max(np.abs(ut)) == pytest.approx(1e-3, rel=1e-4)  # amplitude kept


def test_rayleigh_damping_of_the_first_mode():
    xi = 0.05
    col = ShearColumn(np.linspace(0, H, NE + 1), np.full(NE, RHO), reduction="linear",
                      damping_ratio=xi, damping_frequencies=(1.0, 10.0))
    f1 = np.sqrt(G / RHO) / (4 * H)
    a0, a1 = rayleigh_coefficients(xi, 1.0, 10.0)
    w1 = 2 * np.pi * f1
    xi1 = a0 / (2 * w1) + a1 * w1 / 2  # ratio the Rayleigh law gives at f1
    s = _mode_one(col)
    dt = 1.0 / (200 * f1)
    t, ut = [], []
    for _ in range(800):
        s = col.step(s, dt, 0.0, G)
        t.append(s.t)
        ut.append(s.u[-1])
    t, ut = np.array(t), np.array(ut)
    peaks = [i for i in range(1, len(ut) - 1) if ut[i] > ut[i - 1] and ut[i] >= ut[i + 1]]
    delta = np.log(ut[peaks[0]] / ut[peaks[-1]]) / (len(peaks) - 1)
    xi_num = delta / np.sqrt(4 * np.pi**2 + delta**2)
    assert xi_num == pytest.approx(xi1, rel=0.05)


def test_resonant_column_builds_up_like_a_damped_oscillator():
    """Harmonic base shaking at f1: steady surface amplitude of mode 1 = Γ a/(2 ξ ω²)."""
    xi = 0.05
    col = ShearColumn(np.linspace(0, H, NE + 1), np.full(NE, RHO), reduction="linear",
                      damping_ratio=xi, damping_frequencies=(3.0, 5.0))
    f1 = np.sqrt(G / RHO) / (4 * H)
    w = 2 * np.pi * f1
    a0, a1 = rayleigh_coefficients(xi, 3.0, 5.0)
    xi1 = a0 / (2 * w) + a1 * w / 2
    gamma1 = 4.0 / np.pi  # participation factor of sin(πy/2H) (unit surface value)
    amp = 0.1
    dt = 1.0 / (50 * f1)
    s = col.rest()
    top = []
    for k in range(1, 2000):  # 40 periods: the transient decays as exp(−ξωt) ≈ 3e-6
        s = col.step(s, dt, amp * np.sin(w * k * dt), G)
        top.append(s.u[-1])
    steady = np.max(np.abs(top[-150:]))
    expected = gamma1 * amp / (2 * xi1 * w**2)
    # higher modes add ~1 % off resonance
    assert steady == pytest.approx(expected, rel=0.03)


def test_softening_backbone_and_negligible_shear_when_g_is_zero():
    col = ShearColumn(np.linspace(0, H, NE + 1), np.full(NE, RHO), gamma_ref=1e-3)
    s = col.rest()
    for k in range(1, 50):
        s = col.step(s, 0.005, 1.0, np.full(NE, 50e6))
    # hyperbolic stress: τ = G_max γ/(1 + |γ|/γ_ref), below the strength G_max γ_ref
    assert np.all(np.abs(s.tau) <= 50e6 * 1e-3 * 1.001 + 1e3)
    # a column with no stiffness (liquefied) is left behind by the base: u = −a t²/2
    col0 = ShearColumn(np.linspace(0, H, NE + 1), np.full(NE, RHO), reduction="linear")
    s0 = col0.rest()
    s0.a[1:] = -1.0  # consistent start: the base already accelerates at 1 m/s²
    for k in range(1, 11):
        s0 = col0.step(s0, 0.01, 1.0, np.zeros(NE))
    assert s0.u[-1] == pytest.approx(-0.5 * 1.0 * 0.1**2, rel=1e-12)


@pytest.mark.parametrize("what", ["g_max", "a_g", "rho"])
def test_non_finite_input_is_a_newmark_failure_not_a_solver_error(what):
    """A NaN modulus, base acceleration or density ends the step with NewmarkFailure (which the
    column turns into a failed step), not with solve_banded's ValueError."""
    col = ShearColumn(np.linspace(0.0, 10.0, 11), rho=np.full(10, 2000.0))
    g_max, a_g = np.full(10, 50e6), 1.0
    if what == "g_max":
        g_max[3] = np.nan
    elif what == "a_g":
        a_g = np.inf
    else:
        col.rho[0] = np.nan
    with pytest.raises(NewmarkFailure, match="non-finite"):
        col.step(col.rest(), 0.01, a_g, g_max)
