"""Field correlations for the constitutive model of liquefiable sand (clean sand, per-cent Dr).

The hysteretic effective-stress model of the liquefaction column is calibrated from the same
penetration resistance the simplified procedure uses (:mod:`.simplified`), so that an element
test and the simplified table agree. This module gathers the correlations it needs:

- relative density Dr [%] from (N1)60cs and from q_c1Ncs, and back (Idriss & Boulanger 2008);
- the CPT route of Boulanger & Idriss (2014): CRR_M7.5, C_σ, K_σ and MSF_max from q_c1Ncs,
  and MSF_max from (N1)60cs;
- the slope b of the CSR–N curve against MSF_max of Boulanger & Idriss (2014, Fig. A.16), its
  inverse (the MSF_max a given b implies), their equivalent cycles N_M7.5(b) (Fig. A.15), and the
  number of uniform cycles to liquefaction N_L = 15 (CRR/CSR)^(1/b);
- the residual strength S_r of liquefied sand (Idriss & Boulanger 2008), with and without
  void redistribution;
- the static-shear correction K_α (Idriss & Boulanger 2003, in I&B 2008);
- the Seed–Booker growth of r_u with N/N_L;
- per-cent wrappers of the Ishihara–Yoshimine strains of :mod:`.settlement`, and the
  reconsolidation strain from a maximum shear strain.

Conventions of the new public API: relative density Dr in PER CENT (0–100), stresses in Pa,
strains as fractions (never %). Fractions of Dr are used only internally. The sands are clean:
fines content is not taken into account (the fines adjustments Δ(N1)60 and Δ(N1)60-Sr are
zero; for S_r, Idriss & Boulanger's Δ(N1)60-Sr is 1, 2, 4 and 5 at 10, 25, 50 and 75 % fines —
add it to the blow count before calling :func:`residual_strength_ratio_ib2008`).
All functions are pure and vectorised (NumPy broadcasting).

References
----------
Idriss, I. M. & Boulanger, R. W. (2003). Relating Kα and Kσ to SPT blow count and to CPT tip
resistance for use in evaluating liquefaction potential. Proc. 2003 Dam Safety Conf., ASDSO.
Idriss, I. M. & Boulanger, R. W. (2007). SPT- and CPT-based relationships for the residual
shear strength of liquefied soils. Proc. 4th ICEGE, Thessaloniki, 1–22.
Idriss, I. M. & Boulanger, R. W. (2008). Soil Liquefaction During Earthquakes. EERI MNO-12.
Boulanger, R. W. & Idriss, I. M. (2014). CPT and SPT based liquefaction triggering procedures.
Report UCD/CGM-14/01, UC Davis.
Seed, H. B., Martin, P. P. & Lysmer, J. (1976). Pore-water pressure changes during soil
liquefaction. J. Geotech. Eng. Div. ASCE 102(GT4), 323–346 (the curve of Booker, Rahman &
Seed 1976).
Yoshimine, M., Nishizaki, H., Amano, K. & Hosono, Y. (2006). Soil Dyn. Earthq. Eng. 26, 253–264.
"""
from __future__ import annotations

import math

import numpy as np

from . import settlement
from .simplified import C_D, PA

__all__ = ["dr_from_n160cs", "n160cs_from_dr", "dr_from_qc1ncs", "qc1ncs_from_dr",
           "crr_75_cpt", "c_sigma_cpt", "k_sigma_cpt", "msf_max_cpt", "msf_max_spt",
           "N_CYCLES_M75", "MSF_MAX_RANGE", "CSR_N_SLOPE_RANGE", "CSR_N_SLOPE_CURVE_RANGE", "B_OF_MSF_MAX",
           "N_M75_OF_B", "csr_slope_b", "msf_max_from_slope", "n_cycles_m75_ib2014",
           "cycles_to_liquefaction", "csr_for_cycles", "residual_strength_ratio_ib2008",
           "residual_strength_ib2008", "relative_state_index", "k_alpha_ib2003",
           "seed_booker_ru", "seed_booker_cycle_ratio", "limiting_shear_strain_pct",
           "max_shear_strain_pct", "reconsolidation_strain"]

N_CYCLES_M75 = 15.0  # equivalent uniform cycles of an M 7.5 event (Seed et al. 1975; I&B 2008)
MSF_MAX_RANGE = (1.09, 2.2)  # B&I (2014): MSF_max from (N1)60cs or q_c1Ncs spans 1.09-2.2 [-]
CSR_N_SLOPE_CURVE_RANGE = (0.15, 0.40)  # the b that B&I's b(MSF_max) spans over that range [-]
#: Boulanger & Idriss (2014) Fig. A.16, b against MSF_max (as digitised in liquepy): (MSF_max, b)
B_OF_MSF_MAX = np.array([
    [1.000, 1.019, 1.045, 1.084, 1.130, 1.184, 1.242, 1.373, 1.540, 1.651, 1.768, 1.891, 2.025, 2.215],
    [0.080, 0.101, 0.121, 0.147, 0.170, 0.191, 0.211, 0.250, 0.290, 0.312, 0.333, 0.353, 0.374, 0.399]])
#: Boulanger & Idriss (2014) Fig. A.15, N_M7.5 against b (as digitised in liquepy): (b, N_M7.5)
N_M75_OF_B = np.array([
    [0.060, 0.063, 0.068, 0.072, 0.078, 0.086, 0.095, 0.110, 0.129, 0.148, 0.168, 0.189, 0.213, 0.235,
     0.253, 0.273, 0.310, 0.333, 0.372, 0.400],
    [950.789, 628.731, 405.756, 278.274, 197.931, 121.658, 77.552, 47.081, 30.742, 22.947, 18.878,
     16.503, 15.519, 14.593, 14.235, 14.054, 14.384, 14.374, 14.710, 15.060]])
CSR_N_SLOPE_RANGE = (0.05, 0.6)  # a CSR–N slope b given from a soil's own cyclic tests (csr_n_slope) [-]
QC1NCS_CSIGMA_MAX = 211.0  # B&I (2014): C_sigma evaluated at q_c1Ncs <= 211 (where it reaches 0.3)


def dr_from_n160cs(n1_60cs):
    """Relative density Dr [%] = 100 √((N1)60cs / C_d), C_d = 46 (Idriss & Boulanger 2008).

    (N1)60cs [blows/0.3 m], clean sand, 0–46 (Dr 0–100 %).

    >>> float(dr_from_n160cs(11.5))        # 100 sqrt(0.25)
    50.0
    """
    return 100.0 * np.sqrt(np.asarray(n1_60cs, dtype=float) / C_D)


def n160cs_from_dr(dr_percent):
    """(N1)60cs [blows/0.3 m] = 46 (Dr/100)², the inverse of :func:`dr_from_n160cs`; Dr [%] 0–100.

    >>> float(n160cs_from_dr(50.0))
    11.5
    """
    d = np.asarray(dr_percent, dtype=float) / 100.0
    return C_D * d * d


def dr_from_qc1ncs(qc1ncs):
    """Relative density Dr [%] = 100 (0.478 q_c1Ncs^0.264 − 1.063) (Idriss & Boulanger 2008).

    q_c1Ncs [-] the normalised clean-sand cone resistance; Dr = 0 at q_c1Ncs = 20.6 and 100 %
    at 254 (the authors use it for q_c1Ncs ≥ 21). It is the relation behind B&I's C_σ:
    1/(18.9 − 17.3 Dr) with this Dr is 1/(37.3 − 8.27 q_c1Ncs^0.264).

    Hand value, q_c1Ncs = 100: 100^0.264 = 3.3729, 0.478 · 3.3729 − 1.063 = 0.5492:

    >>> round(float(dr_from_qc1ncs(100.0)), 2)
    54.92
    """
    q = np.asarray(qc1ncs, dtype=float)
    return 100.0 * (0.478 * q ** 0.264 - 1.063)


def qc1ncs_from_dr(dr_percent):
    """q_c1Ncs [-] = ((Dr/100 + 1.063)/0.478)^(1/0.264), the inverse of :func:`dr_from_qc1ncs`.

    >>> round(float(qc1ncs_from_dr(dr_from_qc1ncs(100.0))), 9)
    100.0
    """
    d = np.asarray(dr_percent, dtype=float) / 100.0
    return ((d + 1.063) / 0.478) ** (1.0 / 0.264)


def crr_75_cpt(qc1ncs):
    """CRR_{M=7.5, σ′v=1 atm} of clean sand from the CPT, Boulanger & Idriss (2014) [-].

    CRR = exp(q/113 + (q/1000)² − (q/140)³ + (q/137)⁴ − 2.80), q = q_c1Ncs [-] (the
    deterministic curve, probability 16 %). The case histories span q_c1Ncs ≈ 20–180; the
    curve rises steeply beyond (CRR = 0.93 at 180, 3.7 at 211).

    Hand value, q = 100: 0.88496 + 0.01 − 0.36443 + 0.28387 − 2.8 = −1.98561, CRR = 0.1373:

    >>> round(float(crr_75_cpt(100.0)), 4)
    0.1373
    """
    q = np.asarray(qc1ncs, dtype=float)
    return np.exp(q / 113.0 + (q / 1000.0) ** 2 - (q / 140.0) ** 3 + (q / 137.0) ** 4 - 2.80)


def c_sigma_cpt(qc1ncs):
    """C_σ = 1/(37.3 − 8.27 q_c1Ncs^0.264) ≤ 0.3 of K_σ, Boulanger & Idriss (2014) [-].

    q_c1Ncs [-] evaluated at most at 211, where C_σ reaches 0.3.

    >>> round(float(c_sigma_cpt(100.0)), 5)   # 1/(37.3 - 8.27 * 3.37291)
    0.10631
    """
    q = np.minimum(np.asarray(qc1ncs, dtype=float), QC1NCS_CSIGMA_MAX)
    return np.minimum(1.0 / (37.3 - 8.27 * q ** 0.264), 0.3)


def k_sigma_cpt(sigma_v_eff_Pa, qc1ncs):
    """Overburden factor K_σ = 1 − C_σ ln(σ′_v/P_a) ≤ 1.1 with the CPT C_σ [-] (B&I 2014).

    σ′_v [Pa] vertical effective stress, P_a = 101.325 kPa, C_σ from :func:`c_sigma_cpt`.

    >>> round(float(k_sigma_cpt(2 * PA, 100.0)), 4)   # 1 - 0.10631 ln 2
    0.9263
    """
    s = np.asarray(sigma_v_eff_Pa, dtype=float)
    return np.minimum(1.0 - c_sigma_cpt(qc1ncs) * np.log(s / PA), 1.1)


def msf_max_cpt(qc1ncs):
    """MSF_max = 1.09 + (q_c1Ncs/180)³ ≤ 2.2, Boulanger & Idriss (2014) [-].

    >>> round(float(msf_max_cpt(100.0)), 4)   # 1.09 + 0.171468
    1.2615
    """
    q = np.asarray(qc1ncs, dtype=float)
    return np.minimum(1.09 + (q / 180.0) ** 3, 2.2)


def msf_max_spt(n1_60cs):
    """MSF_max = 1.09 + ((N1)60cs/31.5)² ≤ 2.2, Boulanger & Idriss (2014) [-].

    The value :func:`.simplified.msf_ib2014` uses.

    >>> round(float(msf_max_spt(11.5)), 4)
    1.2233
    """
    n = np.asarray(n1_60cs, dtype=float)
    return np.minimum(1.09 + (n / 31.5) ** 2, 2.2)


def csr_slope_b(msf_max):
    """Slope b of the cyclic strength curve CSR ∝ N^−b for a given MSF_max, Boulanger & Idriss
    (2014, App. A, Fig. A.16) [-].

    B&I relate the cap of their magnitude scaling factor (MSF_max, the MSF at M ≤ 5.25) to b
    through the equivalent uniform cycles of their ground-motion set: a flatter CSR–N curve (small
    b, loose sand) makes the few strong cycles of a small earthquake count for less, and the small
    cycles of a large one for more. The curve is tabulated (:data:`B_OF_MSF_MAX`, their figure
    as digitised in the liquepy library, checked in the tests against liquepy) and interpolated
    linearly; outside 1.000–2.215 it is held at its ends (0.080, 0.399). MSF_max [-] ≥ 1; with
    MSF_max of B&I from (N1)60cs (:func:`msf_max_spt`, 1.09–2.2) b runs from 0.150 to 0.397.

    Hand value, (N1)60cs = 10: MSF_max = 1.09 + (10/31.5)² = 1.19078, between (1.184, 0.191) and
    (1.242, 0.211): b = 0.191 + 0.020 · 0.00678/0.058 = 0.19334:

    >>> round(float(csr_slope_b(msf_max_spt(10.0))), 5)
    0.19334
    >>> float(csr_slope_b(1.373)), float(csr_slope_b(3.0))
    (0.25, 0.399)
    """
    return np.interp(np.asarray(msf_max, dtype=float), B_OF_MSF_MAX[0], B_OF_MSF_MAX[1])


def msf_max_from_slope(b):
    """MSF_max [-] that a CSR–N slope b [-] implies: the inverse of :func:`csr_slope_b` (B&I's
    curve is monotone), clamped to B&I's range of MSF_max, 1.09–2.2 (:data:`MSF_MAX_RANGE`).

    For a soil whose slope is known from its own cyclic tests (``csr_n_slope``): the simplified
    table then scales its CRR with the MSF that b implies. The curve spans b = 0.150–0.397 within
    that range; a b outside 0.15–0.40 (:data:`CSR_N_SLOPE_CURVE_RANGE`) lies beyond what the curve
    can express and is clamped (the caller warns).

    >>> round(float(msf_max_from_slope(0.25)), 6), round(float(msf_max_from_slope(csr_slope_b(1.3))), 6)
    (1.373, 1.3)
    >>> float(msf_max_from_slope(0.05)), float(msf_max_from_slope(0.5))
    (1.09, 2.2)
    """
    m = np.interp(np.asarray(b, dtype=float), B_OF_MSF_MAX[1], B_OF_MSF_MAX[0])
    return np.clip(m, *MSF_MAX_RANGE)


def n_cycles_m75_ib2014(b):
    """Equivalent uniform cycles N_M7.5 of an M 7.5 motion for a soil of CSR–N slope b [-],
    Boulanger & Idriss (2014, App. A, Fig. A.15), interpolated in :data:`N_M75_OF_B` (held at the
    ends beyond b = 0.06–0.40).

    At small b the many small cycles of a record count for more, so N_M7.5 grows from about 15
    (b ≥ 0.2) to 78 at b = 0.095. The hysteretic law is NOT corrected by (N_M7.5(b)/15)^b: its CRR
    is anchored at 15 uniform cycles, as PM4Sand is calibrated (docs/liquefaction.md gives the size
    of the correction that is left out).

    >>> round(float(n_cycles_m75_ib2014(0.189)), 3), round(float(n_cycles_m75_ib2014(0.095)), 3)
    (16.503, 77.552)
    """
    return np.interp(np.asarray(b, dtype=float), N_M75_OF_B[0], N_M75_OF_B[1])


def cycles_to_liquefaction(csr, crr_m75, b, c_multidirectional=1.0):
    """Uniform cycles to liquefaction N_L = 15 (CRR_M7.5 / (c_md CSR))^(1/b) [-].

    Parameters
    ----------
    csr : array_like
        Uniform cyclic stress ratio τ_cyc/σ′_v [-] of the test, > 0.
    crr_m75 : array_like
        Cyclic resistance ratio at 15 cycles (M 7.5) and 1 atm [-], e.g. :func:`.simplified.crr_75`
        or :func:`crr_75_cpt` (times K_σ for another stress).
    b : array_like
        Slope of CSR ∝ N^−b, e.g. :func:`csr_slope_b` [-], > 0.
    c_multidirectional : float
        The field CRR is c_md times the unidirectional (simple shear) strength: Seed (1979)'s
        c_md = 0.9 for two-directional shaking, so a unidirectional element is 1/c_md
        stronger than the field correlation. The default 1.0 does NOT apply it: the element
        then reaches N = 15 at CSR = CRR_M7.5. Pass 0.9 to apply it (N = 15 at CRR/0.9).

    >>> round(float(cycles_to_liquefaction(0.1288, 0.1288, 0.1166)), 6)
    15.0
    >>> round(float(cycles_to_liquefaction(0.1288 / 1.2233, 0.1288, 0.1166)), 2)   # 15 e^1.72856
    84.49
    """
    csr = np.asarray(csr, dtype=float)
    return N_CYCLES_M75 * (np.asarray(crr_m75, dtype=float) / (c_multidirectional * csr)) \
        ** (1.0 / np.asarray(b, dtype=float))


def csr_for_cycles(n_cycles, crr_m75, b, c_multidirectional=1.0):
    """Uniform CSR that liquefies in ``n_cycles`` cycles: CSR = CRR_M7.5 (15/N)^b / c_md [-].

    The inverse of :func:`cycles_to_liquefaction` (same parameters).

    >>> round(float(csr_for_cycles(15.0, 0.1288, 0.1166)), 4)
    0.1288
    """
    n = np.asarray(n_cycles, dtype=float)
    return np.asarray(crr_m75, dtype=float) * (N_CYCLES_M75 / n) ** np.asarray(b, dtype=float) \
        / c_multidirectional


def residual_strength_ratio_ib2008(n1_60cs_sr, void_redistribution=False, friction_angle_deg=30.0):
    """Residual strength ratio S_r/σ′_vc of liquefied sand, Idriss & Boulanger (2007, 2008) [-].

    With N = (N1)60cs-Sr [blows/0.3 m],

        void redistribution significant:  S_r/σ′_vc = exp(N/16 + ((N − 16)/21.2)³ − 3.0)
        void redistribution negligible:   the same × (1 + exp(N/2.4 − 6.6)),

    both capped at tan φ′. ``void_redistribution=False`` (the default) is the second relation,
    the one the liquefaction column ships. N here is the clean-sand value; for silty sand add
    Δ(N1)60-Sr (module docstring). The case histories reach N ≈ 15–20 (the curves rise
    steeply beyond, where the tan φ′ cap takes over).

    Hand values: N = 8: exp(0.5 − 0.05242 − 3) = 0.07779 with void redistribution, × (1 +
    exp(−3.26667)) = 0.08076 without; N = 16: exp(−2) (1 + exp(0.06667)) = 0.28000:

    >>> [round(float(v), 5) for v in residual_strength_ratio_ib2008([8.0, 16.0])]
    [0.08076, 0.28]
    >>> round(float(residual_strength_ratio_ib2008(8.0, void_redistribution=True)), 5)
    0.07779
    >>> round(float(residual_strength_ratio_ib2008(25.0)), 4)    # capped: tan 30°
    0.5774
    """
    n = np.asarray(n1_60cs_sr, dtype=float)
    ratio = np.exp(n / 16.0 + ((n - 16.0) / 21.2) ** 3 - 3.0)
    if not void_redistribution:
        ratio = ratio * (1.0 + np.exp(n / 2.4 - 6.6))
    return np.minimum(ratio, math.tan(math.radians(friction_angle_deg)))


def residual_strength_ib2008(n1_60cs_sr, sigma_v_eff_Pa, void_redistribution=False,
                             friction_angle_deg=30.0):
    """Residual strength S_r [Pa] = σ′_vc · :func:`residual_strength_ratio_ib2008`.

    σ′_vc [Pa] the vertical effective stress before the earthquake (never the current one:
    S_r must not follow the pore pressure).

    >>> round(float(residual_strength_ib2008(8.0, 50e3)))    # 0.080757 * 50 kPa
    4038
    """
    return np.asarray(sigma_v_eff_Pa, dtype=float) * residual_strength_ratio_ib2008(
        n1_60cs_sr, void_redistribution, friction_angle_deg)


def relative_state_index(dr_percent, p_eff_Pa, q=10.0):
    """Relative state parameter index ξ_R = 1/(Q − ln(100 p′/P_a)) − Dr [-] (Boulanger 2003).

    Dr [%] relative density, p′ [Pa] mean effective stress ((1 + 2K_0)/3 σ′_v in level
    ground), Q = 10 for quartz sand. ξ_R < 0: dilative (denser than critical).

    >>> round(float(relative_state_index(50.0, 100e3)), 5)   # 1/(10 - ln 98.692) - 0.5
    -0.31509
    """
    p = np.asarray(p_eff_Pa, dtype=float)
    return 1.0 / (q - np.log(100.0 * p / PA)) - np.asarray(dr_percent, dtype=float) / 100.0


def k_alpha_ib2003(alpha, dr_percent, p_eff_Pa, q=10.0):
    """Static shear correction K_α = a + b exp(−ξ_R/c) (Idriss & Boulanger 2003, 2008) [-].

    a = 1267 + 636 α² − 634 exp(α) − 632 exp(−α),
    b = exp(−1.11 + 12.3 α² + 1.31 ln(α + 0.0001)),
    c = 0.138 + 0.126 α + 2.52 α³,
    α = τ_static/σ′_v [-], ξ_R from :func:`relative_state_index` (Dr [%], p′ [Pa], Q).
    Fitted for α ≤ 0.35 and −0.6 ≤ ξ_R ≤ 0.1; outside, α and ξ_R are held at those limits.
    K_α = 1 at α = 0 (a = 1, b ≈ 2e-6).

    Hand value, α = 0.1, Dr = 50 %, p′ = 100 kPa: ξ_R = −0.31509, a = 0.82439,
    b = 0.018278, c = 0.15312, K_α = 0.82439 + 0.018278 exp(2.05780) = 0.9675:

    >>> round(float(k_alpha_ib2003(0.1, 50.0, 100e3)), 4)
    0.9675
    >>> round(float(k_alpha_ib2003(0.0, 50.0, 100e3)), 4)
    1.0
    """
    a_ = np.clip(np.asarray(alpha, dtype=float), 0.0, 0.35)
    xi = np.clip(relative_state_index(dr_percent, p_eff_Pa, q), -0.6, 0.1)
    a = 1267.0 + 636.0 * a_ * a_ - 634.0 * np.exp(a_) - 632.0 * np.exp(-a_)
    b = np.exp(-1.11 + 12.3 * a_ * a_ + 1.31 * np.log(a_ + 0.0001))
    c = 0.138 + 0.126 * a_ + 2.52 * a_ ** 3
    return a + b * np.exp(-xi / c)


def seed_booker_ru(cycle_ratio, alpha=0.7):
    """Pore pressure ratio r_u = (2/π) arcsin((N/N_L)^(1/(2α))) [-] (Seed, Martin & Lysmer 1976).

    N/N_L [-] the cycle ratio (held in [0, 1]); α [-] the shape constant, 0.7 for the
    average of their undrained cyclic tests.

    >>> round(float(seed_booker_ru(0.5)), 4)    # (2/pi) asin(0.5**(1/1.4))
    0.4173
    >>> float(seed_booker_ru(1.0))
    1.0
    """
    r = np.clip(np.asarray(cycle_ratio, dtype=float), 0.0, 1.0)
    return (2.0 / np.pi) * np.arcsin(r ** (1.0 / (2.0 * alpha)))


def seed_booker_cycle_ratio(r_u, alpha=0.7):
    """Cycle ratio N/N_L = sin(π r_u/2)^(2α) at which r_u is reached, the inverse of
    :func:`seed_booker_ru` [-]; r_u held in [0, 1].

    >>> round(float(seed_booker_cycle_ratio(seed_booker_ru(0.25))), 12)
    0.25
    """
    r = np.clip(np.asarray(r_u, dtype=float), 0.0, 1.0)
    return np.sin(0.5 * np.pi * r) ** (2.0 * alpha)


def limiting_shear_strain_pct(dr_percent):
    """Limiting shear strain γ_lim = 1.859 (1.1 − Dr)³ ≥ 0 [-], Dr in per cent (Yoshimine 2006).

    :func:`.settlement.limiting_shear_strain` with Dr [%]; the form is Idriss & Boulanger's
    (2008) fit of Yoshimine et al. (2006) (Dr as a fraction inside the bracket).

    >>> round(float(limiting_shear_strain_pct(50.0)), 5)
    0.40154
    """
    return settlement.limiting_shear_strain(np.asarray(dr_percent, dtype=float) / 100.0)


def max_shear_strain_pct(fs, dr_percent):
    """Maximum shear strain γ_max [-] from FS and Dr [%] (:func:`.settlement.max_shear_strain`).

    >>> round(float(max_shear_strain_pct(1.0, 50.0)), 6)
    0.035
    """
    return settlement.max_shear_strain(fs, np.asarray(dr_percent, dtype=float) / 100.0)


def reconsolidation_strain(gamma_max, dr_percent):
    """Reconsolidation volumetric strain ε_v = 1.5 exp(−2.5 Dr) min(0.08, γ_max) [-].

    Idriss & Boulanger's (2008) fit of Ishihara & Yoshimine (1992) with γ_max, the maximum
    single-amplitude shear strain [-] the element reached (a fraction), given directly (not
    through FS) and Dr [%]. The floor of the liquefaction column's final volumetric strain.

    Hand value, γ_max = 0.035, Dr = 50 %: 1.5 exp(−1.25) 0.035 = 0.015042:

    >>> round(float(reconsolidation_strain(0.035, 50.0)), 6)
    0.015042
    >>> round(float(reconsolidation_strain(0.5, 50.0)), 6)     # capped at 8 % strain
    0.034381
    """
    g = np.abs(np.asarray(gamma_max, dtype=float))
    return 1.5 * np.exp(-2.5 * np.asarray(dr_percent, dtype=float) / 100.0) * np.minimum(0.08, g)
