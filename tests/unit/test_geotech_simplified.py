"""Simplified-procedure functions (Idriss & Boulanger 2008, 2014) against hand values.

Hand row: z = 3 m, M_w = 6.95, a_max = 0.25 g, Dr = 0.45, σ_v = 55.0 kPa,
σ′_v = 55.0 − 9.81 = 45.19 kPa (water table at 2 m, crust 18 kN/m³, sand 19 kN/m³):

- (N1)60cs = 46 · 0.45² = 9.315
- r_d: z/11.73 + 5.133 = 5.38875, sin = −0.77985, α = −1.012 + 1.126 · 0.77985 = −0.13389;
  z/11.28 + 5.142 = 5.40796, sin = −0.76769, β = 0.106 − 0.118 · 0.76769 = 0.015413;
  ln r_d = −0.13389 + 6.95 · 0.015413 = −0.026768, r_d = 0.97359
- CSR = 0.65 · (55.0/45.19) · 0.25 · 0.97359 = 0.65 · 1.21708 · 0.25 · 0.97359 = 0.19255
- CRR_7.5: 9.315/14.1 = 0.66064, (9.315/126)² = 0.0054654, (9.315/23.6)³ = 0.061491,
  (9.315/25.4)⁴ = 0.018088; exp(0.66064 + 0.0054654 − 0.061491 + 0.018088 − 2.8)
  = exp(−2.17730) = 0.11335
- MSF (2014): MSF_max = 1.09 + (9.315/31.5)² = 1.17745; exp(−6.95/4) = 0.17596;
  8.64 · 0.17596 − 1.325 = 0.19529; MSF = 1 + 0.17745 · 0.19529 = 1.03465
- K_σ: √9.315 = 3.05205, C_σ = 1/(18.9 − 2.55 · 3.05205) = 0.089950;
  ln(45.19/101.325) = −0.80746; K_σ = 1 + 0.089950 · 0.80746 = 1.07263
- FS = 0.11335 · 1.03465 · 1.07263 / 0.19255 = 0.65330

The hand values carry 5 significant figures, so they are compared at rel 1e-4.
"""
import numpy as np
import pytest

from twofluid.geotech import simplified as sp

HAND = 1e-4  # 5 significant figures in the hand values


def test_hand_row():
    n = sp.n160_from_relative_density(0.45)
    assert n == pytest.approx(9.315, rel=1e-12)
    rd = sp.stress_reduction(3.0, 6.95)
    assert rd == pytest.approx(0.97359, rel=HAND)
    csr = sp.cyclic_stress_ratio(55.0e3, 45.19e3, 0.25, rd)
    assert csr == pytest.approx(0.19255, rel=HAND)
    crr = sp.crr_75(n)
    assert crr == pytest.approx(0.11335, rel=HAND)
    msf = sp.msf_ib2014(6.95, n)
    assert msf == pytest.approx(1.03465, rel=HAND)
    ks = sp.k_sigma(45.19e3, n)
    assert ks == pytest.approx(1.07263, rel=HAND)
    assert sp.factor_of_safety(crr, msf, ks, csr) == pytest.approx(0.65330, rel=HAND)


def test_relative_density_round_trip():
    dr = np.linspace(0.0, 1.0, 11)
    np.testing.assert_allclose(sp.relative_density_from_n160(sp.n160_from_relative_density(dr)), dr,
                               rtol=1e-14, atol=1e-15)


def test_msf_reference_magnitude_and_trend():
    """Both forms are 1 at M = 7.5 (to the 4 digits of their constants) and fall with M."""
    m = np.linspace(5.5, 9.0, 36)
    assert sp.msf_ib2008(7.5) == pytest.approx(1.0, abs=5e-4)
    for n in (0.0, 10.0, 20.0, 30.0):
        assert sp.msf_ib2014(7.5, n) == pytest.approx(1.0, abs=5e-4)
        assert np.all(np.diff(sp.msf_ib2014(m, n)) < 0.0)
    assert np.all(np.diff(sp.msf_ib2008(m)) < 0.0)
    assert sp.msf_ib2008(5.0) == 1.8
    # denser sand: stronger magnitude dependence, MSF_max capped at 2.2
    assert sp.msf_ib2014(5.5, 30.0) > sp.msf_ib2014(5.5, 10.0)
    assert sp.msf_ib2014(5.5, 40.0) == pytest.approx(sp.msf_ib2014(5.5, 50.0), rel=1e-15)


def test_rd_branches_meet_at_34_m():
    """The two r_d branches of Idriss (1999) are fitted to meet at 34 m: there
    α = −2.1200 against ln 0.12 = −2.1203 and β = 0.2187 against 0.22, so ln r_d jumps
    by about 0.0013 M, at most 1.2 % for M ≤ 8.5 (a typo in a constant would show)."""
    for m in (5.5, 6.5, 7.5, 8.5):
        below, above = sp.stress_reduction([34.0, 34.0 + 1e-9], m)
        assert above == pytest.approx(0.12 * np.exp(0.22 * m), rel=1e-12)
        assert below == pytest.approx(above, rel=0.0013 * m + 1e-3)
    z = np.linspace(0.0, 30.0, 61)
    assert np.all(np.diff(sp.stress_reduction(z, 7.5)) < 0.0)


def test_k_sigma_caps():
    assert sp.k_sigma(sp.PA, 15.0) == pytest.approx(1.0, rel=1e-15)
    assert float(sp.k_sigma(0.05 * sp.PA, 15.0)) == 1.1
    # C_sigma reaches its cap 0.3 at (N1)60cs = 37 (1/(18.9 - 2.55 sqrt 37) = 0.295)
    assert sp.k_sigma(np.e * sp.PA, 60.0) == pytest.approx(1.0 - 1.0 / (18.9 - 2.55 * np.sqrt(37.0)))


def test_crr_curve_end():
    """CRR reaches 2.0 at the end of the case-history range (N1)60cs = 37.5, and is held."""
    assert sp.crr_75(37.5) == pytest.approx(2.0, rel=0.01)
    assert sp.crr_75(46.0) == sp.crr_75(37.5)
    n = np.linspace(0.0, 37.5, 76)
    assert np.all(np.diff(sp.crr_75(n)) > 0.0)


def test_fs_falls_with_a_max_and_rises_with_density():
    """Monotonicity over a grid of depths 1–20 m (σ′_v 0.2–2 atm): FS ∝ 1/a_max exactly,
    and FS increases with Dr up to the end of the CRR curve (Dr = √(37.5/46) = 0.903)."""
    z = np.linspace(1.0, 20.0, 20)[:, None]
    s_v = 19e3 * z
    s_e = s_v - 9.81e3 * z
    dr = np.linspace(0.05, 0.9, 35)[None, :]
    n = sp.n160_from_relative_density(dr)
    rd = sp.stress_reduction(z, 6.95)

    def fs(a_max):
        csr = sp.cyclic_stress_ratio(s_v, s_e, a_max, rd)
        return sp.factor_of_safety(sp.crr_75(n), sp.msf_ib2014(6.95, n), sp.k_sigma(s_e, n), csr)

    f1, f2 = fs(0.1), fs(0.3)
    np.testing.assert_allclose(f1, 3.0 * f2, rtol=1e-13)
    assert np.all(np.diff(f2, axis=1) > 0.0)
