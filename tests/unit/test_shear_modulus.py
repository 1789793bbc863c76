"""Shear modulus closures against hand-computed values (SPEC 4.3)."""
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
