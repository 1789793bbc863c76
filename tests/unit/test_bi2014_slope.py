"""The CSR–N slope b from Boulanger & Idriss's (2014) curve b(MSF_max), its inverse for a layer's own
``csr_n_slope``, and the simplified table, checked against the public liquepy library where it is
installed (the ``bench`` extra) and against hand values where it is not.

Tolerances: liquepy interpolates the same digitised points linearly, and its CRR, K_σ and MSF are
the same closed forms, so the two agree to round-off (1e-12 relative); its K_σ takes P_a in kPa,
given here as 101.325 (the project's atmosphere). Above q_c1Ncs ≈ 211 liquepy leaves C_σ uncapped
where B&I cap it at 0.3 (0.3004 against 0.3): the K_σ rows are compared below it.
"""
import warnings

import numpy as np
import pytest

from twofluid.geotech import correlations as co
from twofluid.geotech import simplified as sp
from twofluid.geotech.profile import simplified_procedure
from twofluid.models.hysteretic_sand import derive

N160 = np.linspace(0.0, 40.0, 81)
QC1N = np.linspace(30.0, 230.0, 81)


def test_b_at_n160cs_10_is_about_0_19_and_spans_the_curve():
    assert float(co.csr_slope_b(co.msf_max_spt(10.0))) == pytest.approx(0.1933, abs=5e-4)
    b = co.csr_slope_b(co.msf_max_spt(N160))
    assert np.all(np.diff(b) >= 0.0)
    assert b.min() == pytest.approx(0.150, abs=1e-3) and b.max() == pytest.approx(0.397, abs=1e-3)


def test_the_inverse_returns_msf_max_and_clamps_it():
    m = np.linspace(1.09, 2.2, 23)
    assert np.allclose(co.msf_max_from_slope(co.csr_slope_b(m)), m, rtol=1e-12)
    assert float(co.msf_max_from_slope(0.05)) == 1.09 and float(co.msf_max_from_slope(0.6)) == 2.2


def test_the_element_and_the_table_take_one_msf_max():
    """derive()'s b is B&I's b at the MSF_max the simplified table scales with (SPT and CPT)."""
    for n in (5.0, 10.0, 20.0, 30.0):
        assert derive(n160cs=n, sigma_v0=100e3)["b"] == pytest.approx(float(co.csr_slope_b(co.msf_max_spt(n))),
                                                                      rel=1e-12)
        m = 5.25  # at M 5.25 B&I's MSF reaches MSF_max (to 3e-4)
        assert float(sp.msf_ib2014(m, n)) == pytest.approx(float(co.msf_max_spt(n)), abs=1e-3)
    for q in (60.0, 120.0, 180.0):
        assert derive(qc1ncs=q, sigma_v0=100e3)["b"] == pytest.approx(float(co.csr_slope_b(co.msf_max_cpt(q))),
                                                                      rel=1e-12)


def test_a_slope_off_the_curve_warns_in_one_line_and_one_on_it_does_not():
    z = np.array([2.0])
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        r = simplified_procedure(z, z + 1.0, [50e3], [40e3], 47.0, True, 0.2, 5.25, csr_n_slope=0.1)
    lines = [str(x.message) for x in w]
    assert len(lines) == 1 and "\n" not in lines[0] and "csr_n_slope 0.1" in lines[0] and "0.15-0.4" in lines[0]
    assert r.MSF[0] == pytest.approx(1.09, abs=1e-3)  # clamped MSF_max, at M 5.25
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        r = simplified_procedure(z, z + 1.0, [50e3], [40e3], 47.0, True, 0.2, 5.25, csr_n_slope=0.25)
    assert not w
    assert r.MSF[0] == pytest.approx(1.373, abs=1e-3)


def test_the_correction_left_out_is_small_above_n160cs_10():
    """(N_M7.5(b)/15)^b, the factor B&I's CRR at 15 cycles would carry: 1.05 at (N1)60cs 5,
    within 2 % from 10 up (docs/liquefaction.md gives the table)."""
    n = np.array([5.0, 10.0, 20.0, 30.0])
    b = co.csr_slope_b(co.msf_max_spt(n))
    corr = (co.n_cycles_m75_ib2014(b) / 15.0) ** b
    assert np.all(np.abs(corr[1:] - 1.0) < 0.02) and 1.03 < corr[0] < 1.07


def test_against_liquepy():
    bi = pytest.importorskip("liquepy.trigger.boulanger_and_idriss_2014")
    m = np.linspace(1.0, 2.3, 131)
    assert np.allclose(co.csr_slope_b(m), bi.calc_b_from_msf_max_bi2014(m), rtol=1e-12, atol=0)
    b = np.linspace(0.06, 0.40, 69)
    assert np.allclose(co.n_cycles_m75_ib2014(b), bi.calc_n_cycles_at_m7p5_bi2014(b), rtol=1e-12, atol=0)
    assert np.allclose(co.csr_slope_b(co.msf_max_cpt(QC1N)), bi.calc_b_from_q_c1ncs(QC1N), rtol=1e-12)
    # the CRR at 15 uniform cycles that liquepy derives with the (N_M7.5/15)^b factor, over ours
    n = np.array([5.0, 10.0, 20.0, 30.0])
    ratio = bi.calc_crr_n15_from_n1_60cs(n) / sp.crr_75(n)
    b = co.csr_slope_b(co.msf_max_spt(n))
    assert np.allclose(ratio, (co.n_cycles_m75_ib2014(b) / 15.0) ** b, rtol=1e-12)
    # the simplified table, SPT and CPT rows, against liquepy's CRR, K_sigma and MSF
    z = np.linspace(2.0, 14.0, N160.size)
    s_eff = 20e3 + 8e3 * z
    for mag in (5.5, 6.5, 7.0, 8.5):  # liquepy returns exactly 1 at M 7.5, the relation 1 - 1.6e-5
        r = simplified_procedure(z, z + 0.2, s_eff + 10e3 * z, s_eff, 50.0, True, 0.3, mag, n160cs=N160 + 1.0)
        n = N160 + 1.0
        msf = 1.0 + (np.minimum(1.09 + (n / 31.5) ** 2, 2.2) - 1.0) * (8.64 * np.exp(-mag / 4.0) - 1.325)
        assert np.allclose(r.CRR_75, bi.calc_crr_m7p5_from_n1_60cs(np.minimum(n, 37.5)), rtol=1e-12)
        assert np.allclose(r.K_sigma, bi.calc_k_sigma_w_n1_60cs(s_eff / 1e3, np.minimum(n, 37.0), pa=101.325),
                           rtol=1e-12)
        assert np.allclose(r.MSF, msf, rtol=1e-12)
        r = simplified_procedure(z, z + 0.2, s_eff + 10e3 * z, s_eff, 50.0, True, 0.3, mag, qc1ncs=QC1N)
        assert np.allclose(r.CRR_75, bi.calc_crr_m7p5_from_qc1ncs(QC1N), rtol=1e-12)
        # B&I cap C_σ at 0.3, which their relation reaches at q_c1Ncs ≈ 211; liquepy leaves it uncapped
        low = QC1N < 210.0
        assert np.allclose(r.K_sigma[low], bi.calc_k_sigma(s_eff[low] / 1e3, QC1N[low], pa=101.325), rtol=1e-12)
        assert np.allclose(r.MSF, bi.calc_msf(mag, QC1N), rtol=1e-12)
