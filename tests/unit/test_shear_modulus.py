"""Shear modulus closures against hand-computed values (Seed & Idriss 1970; Hardin & Drnevich 1972)."""
from __future__ import annotations

import numpy as np
import pytest

from twofluid.closures import registry
from twofluid.closures import shear_modulus as sm


def test_seed_idriss_hand_values():
    # 218.8 * 30 * sqrt(100) kPa = 65 640 kPa; 218.8 * 70 * sqrt(25) kPa = 76 580 kPa
    assert sm.seed_idriss_gmax(100e3, 30.0) == pytest.approx(65.64e6, rel=1e-12)
    assert sm.seed_idriss_gmax(25e3, 70.0) == pytest.approx(76.58e6, rel=1e-12)
    g = sm.seed_idriss_gmax(np.array([0.0, 1e3, 4e3]), 50.0)
    assert np.allclose(g, [0.0, 10.94e6, 21.88e6])


def test_gmax_vanishes_without_pressure():
    assert sm.seed_idriss_gmax(np.array([0.0, -10.0]), 30.0).tolist() == [0.0, 0.0]


def test_hyperbolic_hand_values_and_symmetry():
    gam = np.array([0.0, 5e-4, -5e-4, 2e-3])
    assert np.allclose(sm.hyperbolic(gam, gamma_ref=5e-4), [1.0, 0.5, 0.5, 0.2])
    with pytest.raises(ValueError):
        sm.hyperbolic(1e-3, gamma_ref=0.0)


def test_tabulated_log_interpolation():
    strains = [1e-6, 1e-4, 1e-2]
    ratios = [1.0, 0.8, 0.2]
    # halfway in log10 between 1e-4 and 1e-2 is 1e-3: (0.8 + 0.2) / 2
    got = sm.tabulated(np.array([1e-7, 1e-5, 1e-3, -1e-3, 1.0]), strains, ratios)
    assert np.allclose(got, [1.0, 0.9, 0.5, 0.5, 0.2])


@pytest.mark.parametrize("strains, ratios", [
    ([1e-4, 1e-5], [1.0, 0.5]),
    ([1e-5, 1e-4], [0.5, 1.0]),
    ([0.0, 1e-4], [1.0, 0.5]),
    ([1e-5], [1.0]),
])
def test_tabulated_rejects_bad_tables(strains, ratios):
    with pytest.raises(ValueError, match="tabulated"):
        sm.tabulated(1e-4, strains, ratios)


def test_secant_modulus_and_strain_inversion():
    # G = 65.64 MPa * 1/(1 + 2) at gamma = 2 gamma_ref
    assert sm.shear_modulus(2e-3, 100e3, 30.0) == pytest.approx(65.64e6 / 3.0)
    red = lambda g: sm.hyperbolic(g, 1e-3)  # noqa: E731
    tau = np.array([-2e4, 0.0, 1e4, 5e4])
    gam = sm.strain_from_stress(tau, 65.64e6, red)
    exact = tau / (65.64e6 - np.abs(tau) / 1e-3)  # closed form of the hyperbola
    assert np.allclose(gam, exact, rtol=1e-9, atol=0.0)
    assert np.isinf(sm.strain_from_stress(7e4, 65.64e6, red))


def test_registered():
    assert registry.get("shear_modulus", "seed_idriss").func is sm.seed_idriss_gmax
    assert {"hyperbolic", "tabulated"} <= set(registry.names("modulus_reduction"))
    assert registry.get("modulus_reduction", "hyperbolic").params["gamma_ref"] == 1e-3


def test_tabulated_curve_is_checked_once_and_matches_tabulated():
    strains, ratios = [1e-6, 1e-4, 1e-2], [1.0, 0.8, 0.2]
    curve = sm.tabulated_curve(strains, ratios)
    g = np.array([1e-7, 1e-5, 1e-3, -1e-3, 1.0])
    assert np.array_equal(curve(g), sm.tabulated(g, strains, ratios))
    assert np.allclose(curve(g), [1.0, 0.9, 0.5, 0.5, 0.2])  # end values held outside the table
    with pytest.raises(ValueError, match="tabulated: ratios"):
        sm.tabulated_curve([1e-5, 1e-4], [0.5, 0.6])


@pytest.mark.parametrize("strains, ratios, what, words", [
    ([1e-5], [1.0], "table", "at least 2"),
    ([1e-5, 1e-4], [1.0], "table", "2 strain(s) but 1"),
    ([-1e-5, 1e-4], [1.0, 0.5], "strains", "-1e-05 (point 1) is outside the valid range (0, inf)"),
    ([1e-4, 1e-5], [1.0, 0.5], "strains", "strains must strictly increase: 0.0001 (point 1) then 1e-05 (point 2)"),
    ([1e-5, np.nan], [1.0, 0.5], "strains", "nan (point 2)"),
    ([1e-5, 1e-4], [1.0, 0.0], "ratios", "G/G_max = 0 at strain 0.0001 (point 2) is outside the valid range (0, 1]"),
    ([1e-5, 1e-4], [1.1, 0.5], "ratios", "1.1"),
    ([1e-5, 1e-4, 1e-3], [1.0, 0.5, 0.6], "ratios", "G/G_max must not increase with strain: 0.5 at 0.0001 then 0.6"),
])
def test_table_problems_name_the_point_and_the_valid_range(strains, ratios, what, words):
    problem = sm.table_problem(strains, ratios)
    assert problem is not None and problem[0] == what and words in problem[1], problem


def test_backbone_dips_where_log_interpolation_softens():
    # between two points the stress r(γ) γ has slope r − (r_i − r_{i+1})/ln(γ_{i+1}/γ_i) at the right end
    g = np.array([1e-4, 1e-3, 3e-3, 1e-2])
    r = np.array([0.9, 0.5, 0.3, 0.12])
    assert sm.backbone_dips(g, r) == [2]  # 0.12 ln(10/3) = 0.144 < 0.18: falls by 2.2 %
    assert sm.backbone_dips(g, r, tolerance=0.03) == []
    x = np.linspace(3e-3, 1e-2, 2001)
    tau = sm.tabulated(x, g, r) * x
    assert (tau.max() - tau[-1]) / tau.max() == pytest.approx(0.0222, abs=2e-4)  # it does dip ...
    x = np.linspace(1e-4, 3e-3, 2001)
    assert np.min(np.diff(sm.tabulated(x, g, r) * x)) > 0.0  # ... and not before
    # a hyperbola sampled once per decade dips well above γ_ref; 20 times per decade by 0.1 % only
    coarse, fine = np.logspace(-7, -1, 7), np.logspace(-7, -1, 121)
    assert sm.backbone_dips(coarse, sm.hyperbolic(coarse, 1e-3)) == [4, 5]
    assert sm.backbone_dips(fine, sm.hyperbolic(fine, 1e-3)) == []


def test_shear_column_with_a_table_of_the_hyperbola_follows_the_hyperbola():
    """The column driven through a tabulated curve sampled from the hyperbola (20 points per decade)
    moves like the column with the hyperbolic backbone; a stiffer table moves it less.

    Log interpolation of the hyperbola at that spacing is off by < 2e-4 in G/G_max; the surface
    displacements (strains up to 0.4 % = 4 γ_ref) differ by 4.5e-4 of their peak (asserted 2e-3);
    the curve with γ_ref = 0.3 % gives a response 85 % of the peak away."""
    from twofluid.models.shear_column import ShearColumn

    strains = np.logspace(-7, -1, 121)
    table = sm.tabulated_curve(strains, sm.hyperbolic(strains, 1e-3))
    stiff = sm.tabulated_curve(strains, sm.hyperbolic(strains, 3e-3))
    y, rho, gmax = np.linspace(0.0, 10.0, 21), np.full(20, 1900.0), np.linspace(60e6, 10e6, 20)
    runs = {}
    for name, red in (("hyperbolic", None), ("table", table), ("stiff", stiff)):
        col = ShearColumn(y, rho, gamma_ref=1e-3, reduction=red, damping_ratio=0.05)
        s, top, peak = col.rest(), [], 0.0
        for k in range(1, 201):
            s = col.step(s, 0.005, 1.0 * np.sin(2 * np.pi * 2.0 * k * 0.005), gmax)
            top.append(s.u[-1])
            peak = max(peak, float(np.max(np.abs(s.gamma))))
        runs[name] = np.array(top)
        assert peak > (5e-4 if name == "stiff" else 3e-3)  # well into the non-linear range
    scale = np.max(np.abs(runs["hyperbolic"]))
    assert np.max(np.abs(runs["table"] - runs["hyperbolic"])) < 2e-3 * scale
    assert np.max(np.abs(runs["stiff"] - runs["hyperbolic"])) > 0.05 * scale
