"""geotech.correlations: identities between the published relations, hand values, inverses.

Compared quantities and tolerances:
- the CPT C_σ of Boulanger & Idriss (2014) against 1/(18.9 − 17.3 Dr) of Idriss & Boulanger
  (2008) with Dr from q_c1Ncs: the two are the same relation with coefficients rounded to 3
  significant figures (17.3 · 0.478 = 8.269 printed 8.27), so they agree to 0.5 %;
- the SPT C_σ of :func:`.simplified.k_sigma` against the same Dr form with Dr = √(N/46):
  2.55 = 17.3/√46 to 3 figures, 0.5 %;
- inverses to round-off (1e-12 relative);
- MSF-implied slope: Idriss's clean-sand pair (MSF_max 1.8, b 0.34) reproduced to round-off,
  and the cycles to liquefaction follow CSR ∝ N^−b exactly.
"""
import math

import numpy as np
import pytest

from twofluid.geotech import correlations as co
from twofluid.geotech import settlement, simplified


def test_relative_density_relations_are_inverse_and_per_cent():
    dr = np.linspace(1.0, 100.0, 34)
    np.testing.assert_allclose(co.dr_from_n160cs(co.n160cs_from_dr(dr)), dr, rtol=1e-12)
    np.testing.assert_allclose(co.dr_from_qc1ncs(co.qc1ncs_from_dr(dr)), dr, rtol=1e-12)
    # the per-cent API is the fraction API of simplified.py times 100
    n = np.array([2.0, 11.5, 30.0])
    np.testing.assert_allclose(co.dr_from_n160cs(n), 100 * simplified.relative_density_from_n160(n), rtol=1e-14)
    # Dr = 0 at q_c1Ncs = (1.063/0.478)^(1/0.264) ≈ 20.6 (I&B's lower end of q_c1Ncs ≈ 21)
    assert co.qc1ncs_from_dr(0.0) == pytest.approx(20.6, abs=0.1)


def test_cpt_and_spt_c_sigma_are_the_same_dr_relation():
    q = np.linspace(25.0, 200.0, 30)
    dr = co.dr_from_qc1ncs(q) / 100
    np.testing.assert_allclose(co.c_sigma_cpt(q), 1 / (18.9 - 17.3 * dr), rtol=5e-3)
    n = np.linspace(2.0, 30.0, 15)
    ks_spt = simplified.k_sigma(4 * simplified.PA, n)
    ks_dr = 1 - np.log(4.0) / (18.9 - 17.3 * co.dr_from_n160cs(n) / 100)
    np.testing.assert_allclose(ks_spt, ks_dr, rtol=5e-3)
    assert float(co.c_sigma_cpt(1000.0)) == pytest.approx(0.3, abs=1e-3)   # held at q = 211 (C_σ = 0.3)


def test_cpt_crr_msf_and_k_sigma_hand_values():
    # q = 100: exponent 0.884956 + 0.01 − 0.364431 + 0.283870 − 2.8 = −1.985605
    # (terms to 6 decimals: the hand value is good to 2e-6)
    assert float(co.crr_75_cpt(100.0)) == pytest.approx(math.exp(-1.985605), rel=5e-6)
    assert float(co.crr_75_cpt(0.0)) == pytest.approx(math.exp(-2.8), rel=1e-14)
    assert float(co.msf_max_cpt(100.0)) == pytest.approx(1.09 + (100 / 180) ** 3, rel=1e-14)
    assert float(co.msf_max_cpt(400.0)) == 2.2 and float(co.msf_max_spt(60.0)) == 2.2
    # msf_ib2014 of simplified.py is built on the same MSF_max: at M 5.25 the MSF is MSF_max
    for n in (5.0, 15.0, 25.0):
        assert float(simplified.msf_ib2014(5.25, n)) == pytest.approx(float(co.msf_max_spt(n)), rel=2e-4)
    assert float(co.k_sigma_cpt(0.05 * simplified.PA, 100.0)) == 1.1


def test_slope_b_from_msf_max_and_cycles_to_liquefaction():
    # Boulanger & Idriss (2014) Fig. A.16 at its tabulated points, and between them linearly
    assert float(co.csr_slope_b(1.768)) == 0.333 and float(co.csr_slope_b(1.0)) == 0.08
    assert float(co.csr_slope_b((1.373 + 1.540) / 2)) == pytest.approx((0.250 + 0.290) / 2, rel=1e-12)
    msf = co.msf_max_spt(np.array([5.0, 10.0, 20.0, 30.0]))
    b = co.csr_slope_b(msf)
    assert np.all(np.diff(b) > 0)                     # denser sand: steeper CSR–N curve
    np.testing.assert_allclose(co.msf_max_from_slope(b), msf, rtol=1e-12)
    crr = 0.13
    n = np.array([3.0, 15.0, 50.0])
    csr = co.csr_for_cycles(n, crr, 0.2)
    np.testing.assert_allclose(co.cycles_to_liquefaction(csr, crr, 0.2), n, rtol=1e-12)
    np.testing.assert_allclose(np.log(csr[0] / csr[2]) / np.log(n[2] / n[0]), 0.2, rtol=1e-12)
    # the multidirectional factor: the unidirectional element is 1/0.9 stronger
    assert float(co.csr_for_cycles(15.0, crr, 0.2, c_multidirectional=0.9)) == pytest.approx(crr / 0.9)


def test_residual_strength_published_form():
    n = np.array([0.0, 4.0, 8.0, 12.0, 16.0])
    with_vr = np.exp(n / 16 + ((n - 16) / 21.2) ** 3 - 3)
    np.testing.assert_allclose(co.residual_strength_ratio_ib2008(n, void_redistribution=True), with_vr,
                               rtol=1e-14)
    np.testing.assert_allclose(co.residual_strength_ratio_ib2008(n), with_vr * (1 + np.exp(n / 2.4 - 6.6)),
                               rtol=1e-14)
    # loose sand: about 3 % of σ′_vc (I&B 2008's curves start near 0.03 at N = 0)
    assert float(co.residual_strength_ratio_ib2008(0.0)) == pytest.approx(0.0324, abs=5e-4)
    # without void redistribution the strength is never lower, and both are capped by tan φ′
    m = np.linspace(0, 30, 61)
    assert np.all(co.residual_strength_ratio_ib2008(m) >= co.residual_strength_ratio_ib2008(m, True))
    assert float(co.residual_strength_ratio_ib2008(30.0, friction_angle_deg=33.0)) == pytest.approx(
        math.tan(math.radians(33.0)))
    assert float(co.residual_strength_ib2008(8.0, 50e3)) == pytest.approx(
        50e3 * float(co.residual_strength_ratio_ib2008(8.0)))


def test_k_alpha_hand_value_limits_and_trend():
    # α = 0.1, Dr = 50 %, p′ = 100 kPa (hand value in the docstring, from the published a, b, c)
    xi = 1 / (10 - math.log(100 * 100e3 / simplified.PA)) - 0.5
    a = 1267 + 636 * 0.01 - 634 * math.exp(0.1) - 632 * math.exp(-0.1)
    b = math.exp(-1.11 + 12.3 * 0.01 + 1.31 * math.log(0.1001))
    c = 0.138 + 0.0126 + 2.52e-3
    assert float(co.k_alpha_ib2003(0.1, 50.0, 100e3)) == pytest.approx(a + b * math.exp(-xi / c), rel=1e-12)
    assert a + b * math.exp(-xi / c) == pytest.approx(0.9675, abs=1e-4)
    # no static shear: K_α = 1 (to the 2e-6 of b at α = 0, times exp(0.6/0.138) at most)
    np.testing.assert_allclose(co.k_alpha_ib2003(0.0, [30.0, 60.0, 90.0], 100e3), 1.0, atol=2e-4)
    # static shear weakens loose (contractive) sand and strengthens dense sand (I&B 2008, Fig. 5.?)
    assert float(co.k_alpha_ib2003(0.2, 35.0, 100e3)) < 1.0 < float(co.k_alpha_ib2003(0.2, 90.0, 100e3))


def test_seed_booker_curve():
    r = np.array([0.25, 0.5, 0.75, 1.0])
    ru = co.seed_booker_ru(r)
    np.testing.assert_allclose(ru, 2 / np.pi * np.arcsin(r ** (1 / 1.4)), rtol=1e-14)
    assert np.all(np.diff(ru) > 0) and ru[-1] == 1.0
    np.testing.assert_allclose(co.seed_booker_cycle_ratio(ru), r, rtol=1e-12)
    # α = 0.5 is the straight-line arcsine limit: r_u = (2/π) asin(N/N_L)
    assert float(co.seed_booker_ru(0.5, alpha=0.5)) == pytest.approx(1 / 3, rel=1e-12)


def test_per_cent_wrappers_and_reconsolidation_strain_match_settlement_module():
    dr = np.array([40.0, 60.0, 80.0])
    fs = np.array([0.8, 1.2, 1.6])
    np.testing.assert_allclose(co.limiting_shear_strain_pct(dr), settlement.limiting_shear_strain(dr / 100))
    g = co.max_shear_strain_pct(fs, dr)
    np.testing.assert_allclose(g, settlement.max_shear_strain(fs, dr / 100))
    # ε_v from γ_max directly equals the FS route of settlement.volumetric_strain
    np.testing.assert_allclose(co.reconsolidation_strain(g, dr), settlement.volumetric_strain(fs, dr / 100),
                               rtol=1e-14)
    # three Dr × three γ_max: the published 1.5 exp(−2.5 Dr) min(0.08, γ) (cap at 8 %)
    for d in (40.0, 60.0, 80.0):
        for gm in (0.01, 0.05, 0.2):
            assert float(co.reconsolidation_strain(gm, d)) == pytest.approx(
                1.5 * math.exp(-2.5 * d / 100) * min(0.08, gm), rel=1e-14)
