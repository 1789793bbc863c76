"""Liquefaction triggering by the simplified procedure (Idriss & Boulanger 2008, 2014).

The cyclic stress ratio of the earthquake (Seed & Idriss 1971),

    CSR = 0.65 (σ_v / σ′_v) (a_max / g) r_d,

is compared with the cyclic resistance ratio of the sand, CRR, which is correlated
with the clean-sand SPT blow count (N1)60cs for magnitude 7.5 and σ′_v = 1 atm and
scaled to the event and the depth by the magnitude scaling factor MSF and the
overburden factor K_σ:

    FS = CRR_{M=7.5, σ′v=1 atm} · MSF · K_σ / CSR.

Every function is pure and vectorised (NumPy broadcasting). Stresses are in Pa and
divided by the atmospheric pressure ``PA`` = 101.325 kPa where the correlations are
stated in atmospheres; depths are in m from the ground surface; accelerations in g.
The sands are taken as clean (fines content below 5 %), so (N1)60cs = (N1)60.

References
----------
Idriss, I. M. (1999). An update to the Seed-Idriss simplified procedure for evaluating
liquefaction potential. Proc. TRB Workshop on New Approaches to Liquefaction, FHWA-RD-99-165.
Idriss, I. M. & Boulanger, R. W. (2008). Soil Liquefaction During Earthquakes.
Monograph MNO-12, Earthquake Engineering Research Institute, Oakland CA.
Boulanger, R. W. & Idriss, I. M. (2014). CPT and SPT based liquefaction triggering
procedures. Report UCD/CGM-14/01, Center for Geotechnical Modeling, UC Davis.
Seed, H. B. & Idriss, I. M. (1971). Simplified procedure for evaluating soil liquefaction
potential. J. Soil Mech. Found. Div. ASCE 97(SM9), 1249–1273.
"""
from __future__ import annotations

import numpy as np

__all__ = ["PA", "C_D", "relative_density_from_n160", "n160_from_relative_density",
           "stress_reduction", "msf_ib2008", "msf_ib2014", "k_sigma", "crr_75",
           "cyclic_stress_ratio", "factor_of_safety", "N160CS_MAX"]

PA = 101.325e3  # atmospheric pressure [Pa]
C_D = 46.0  # Dr = sqrt((N1)60 / C_d), Idriss & Boulanger (2008)
N160CS_MAX = 37.5  # the CRR curve ends here (CRR = 2.0); denser sand is treated as this dense


def relative_density_from_n160(n1_60):
    """Relative density Dr [-] from the corrected SPT blow count (N1)60 [blows/0.3 m].

    Dr = √((N1)60 / C_d) with C_d = 46 (Idriss & Boulanger 2008). Valid for
    clean sands, 0 ≤ (N1)60 ≤ 46 (Dr up to 1).

    >>> round(float(relative_density_from_n160(11.5)), 3)   # sqrt(11.5/46) = sqrt(0.25)
    0.5
    """
    return np.sqrt(np.asarray(n1_60, dtype=float) / C_D)


def n160_from_relative_density(dr):
    """Corrected SPT blow count (N1)60 [blows/0.3 m] from relative density Dr [-].

    (N1)60 = C_d Dr² with C_d = 46, the inverse of :func:`relative_density_from_n160`;
    valid for 0 ≤ Dr ≤ 1.

    >>> float(n160_from_relative_density(0.5))   # 46 * 0.25
    11.5
    """
    dr = np.asarray(dr, dtype=float)
    return C_D * dr * dr


def stress_reduction(z_m, magnitude):
    """Shear stress reduction coefficient r_d [-] (Idriss 1999, in Idriss & Boulanger 2008).

    ln r_d = α(z) + β(z) M with
    α = −1.012 − 1.126 sin(z/11.73 + 5.133), β = 0.106 + 0.118 sin(z/11.28 + 5.142)
    (z in m, arguments in radians) for z ≤ 34 m; r_d = 0.12 exp(0.22 M) below 34 m.
    Units: z [m] from the ground surface, M moment magnitude [-]. The authors state the
    fit for z ≤ 34 m; below about 20 m r_d is uncertain and a site response analysis
    is preferred (Idriss & Boulanger 2008).

    Hand value, z = 5 m, M = 7.5: α = −1.012 − 1.126 sin(5.5593) = −0.2662,
    β = 0.106 + 0.118 sin(5.5853) = 0.0302, r_d = exp(−0.2662 + 7.5·0.0302) = 0.961:

    >>> round(float(stress_reduction(5.0, 7.5)), 3)
    0.961
    >>> round(float(stress_reduction(0.0, 7.5)), 3)   # about 1 at the surface
    1.006
    """
    z = np.asarray(z_m, dtype=float)
    m = np.asarray(magnitude, dtype=float)
    alpha = -1.012 - 1.126 * np.sin(z / 11.73 + 5.133)
    beta = 0.106 + 0.118 * np.sin(z / 11.28 + 5.142)
    return np.where(z <= 34.0, np.exp(alpha + beta * m), 0.12 * np.exp(0.22 * m))


def msf_ib2008(magnitude):
    """Magnitude scaling factor for sand, Idriss & Boulanger (2008) [-].

    MSF = 6.9 exp(−M/4) − 0.058 ≤ 1.8, M the moment magnitude. Derived for
    M ≈ 5.25–8.5 (the cap 1.8 applies below M 5.25). Equal to 1 at M = 7.5.

    >>> round(float(msf_ib2008(7.5)), 3)      # 6.9 exp(-1.875) - 0.058
    1.0
    >>> round(float(msf_ib2008(6.95)), 3)     # Imperial Valley 1940: 6.9 * 0.17596 - 0.058
    1.156
    >>> float(msf_ib2008(5.0))
    1.8
    """
    m = np.asarray(magnitude, dtype=float)
    return np.minimum(6.9 * np.exp(-m / 4.0) - 0.058, 1.8)


def msf_ib2014(magnitude, n1_60cs):
    """Magnitude scaling factor for sand, Boulanger & Idriss (2014) [-].

    MSF = 1 + (MSF_max − 1)(8.64 exp(−M/4) − 1.325), with
    MSF_max = 1.09 + ((N1)60cs / 31.5)² ≤ 2.2 (denser sand: more magnitude dependence).
    M moment magnitude (the case histories span 5.5–9.0), (N1)60cs [blows/0.3 m].
    Equal to 1 at M = 7.5 for any density.

    Hand value, M = 6.95, (N1)60cs = 11.5: MSF_max = 1.09 + 0.1333 = 1.2233,
    MSF = 1 + 0.2233 (8.64 · 0.17594 − 1.325) = 1.0436:

    >>> round(float(msf_ib2014(6.95, 11.5)), 4)
    1.0436
    >>> round(float(msf_ib2014(7.5, 30.0)), 3)
    1.0
    """
    m = np.asarray(magnitude, dtype=float)
    n = np.asarray(n1_60cs, dtype=float)
    msf_max = np.minimum(1.09 + (n / 31.5) ** 2, 2.2)
    return 1.0 + (msf_max - 1.0) * (8.64 * np.exp(-m / 4.0) - 1.325)


def k_sigma(sigma_v_eff_Pa, n1_60cs):
    """Overburden correction factor K_σ [-] (Idriss & Boulanger 2008).

    K_σ = 1 − C_σ ln(σ′_v / P_a) ≤ 1.1 with C_σ = 1 / (18.9 − 2.55 √(N1)60cs) ≤ 0.3.
    σ′_v [Pa] the vertical effective stress, P_a = 101.325 kPa, (N1)60cs ≤ 37
    (where C_σ reaches 0.3). The authors use it up to σ′_v ≈ 10 atm.

    Hand value, σ′_v = 2 atm, (N1)60cs = 11.5: C_σ = 1/(18.9 − 2.55·3.3912) = 0.09754,
    K_σ = 1 − 0.09754 ln 2 = 0.9324:

    >>> round(float(k_sigma(2 * PA, 11.5)), 4)
    0.9324
    >>> float(k_sigma(0.1 * PA, 11.5))        # shallow: capped at 1.1
    1.1
    """
    s = np.asarray(sigma_v_eff_Pa, dtype=float)
    n = np.asarray(n1_60cs, dtype=float)
    c_sigma = np.minimum(1.0 / (18.9 - 2.55 * np.sqrt(np.minimum(n, 37.0))), 0.3)
    return np.minimum(1.0 - c_sigma * np.log(s / PA), 1.1)


def crr_75(n1_60cs):
    """Cyclic resistance ratio CRR_{M=7.5, σ′v=1 atm} of clean sand from (N1)60cs [-].

    CRR = exp((N/14.1) + (N/126)² − (N/23.6)³ + (N/25.4)⁴ − 2.8), N = (N1)60cs
    [blows/0.3 m]: the deterministic SPT curve of Idriss & Boulanger (2008),
    kept by Boulanger & Idriss (2014) (their probabilistic curve with the 16 %-probability constant
    −2.67 − 0.13 = −2.80). The case histories reach (N1)60cs ≈ 37.5, where CRR = 2.0;
    larger N is evaluated at N160CS_MAX = 37.5 (the curve rises without bound beyond).

    Hand value, N = 11.5: exp(0.81560 + 0.00833 − 0.11571 + 0.04202 − 2.8) = 0.1288;
    N = 0 gives exp(−2.8) = 0.0608:

    >>> round(float(crr_75(11.5)), 4)
    0.1288
    >>> round(float(crr_75(0.0)), 4)
    0.0608
    >>> round(float(crr_75(37.5)), 2)
    1.99
    """
    n = np.minimum(np.asarray(n1_60cs, dtype=float), N160CS_MAX)
    return np.exp(n / 14.1 + (n / 126.0) ** 2 - (n / 23.6) ** 3 + (n / 25.4) ** 4 - 2.8)


def cyclic_stress_ratio(sigma_v_Pa, sigma_v_eff_Pa, a_max_g, r_d):
    """Earthquake cyclic stress ratio CSR = 0.65 (σ_v/σ′_v) (a_max/g) r_d [-].

    σ_v, σ′_v [Pa] total and effective vertical stress at the depth, a_max [g] the peak
    horizontal acceleration at the ground surface, r_d from :func:`stress_reduction`
    (Seed & Idriss 1971). Level ground, no static shear.

    Hand value, σ_v = 100 kPa, σ′_v = 60 kPa, a_max = 0.3 g, r_d = 0.961:
    0.65 · (100/60) · 0.3 · 0.961 = 0.3123:

    >>> round(float(cyclic_stress_ratio(100e3, 60e3, 0.3, 0.961)), 4)
    0.3123
    """
    return 0.65 * (np.asarray(sigma_v_Pa, dtype=float) / np.asarray(sigma_v_eff_Pa, dtype=float)) \
        * np.asarray(a_max_g, dtype=float) * np.asarray(r_d, dtype=float)


def factor_of_safety(crr75, msf, k_sig, csr):
    """Factor of safety against liquefaction triggering FS = CRR_7.5 · MSF · K_σ / CSR [-].

    All arguments dimensionless (see :func:`crr_75`, :func:`msf_ib2014`, :func:`k_sigma`,
    :func:`cyclic_stress_ratio`). FS < 1: triggering expected. A zero CSR (no shaking)
    gives FS = inf, never NaN.

    >>> round(float(factor_of_safety(0.1288, 1.0436, 1.1, 0.3123)), 3)
    0.473
    >>> float(factor_of_safety(0.1288, 1.0, 1.0, 0.0))
    inf
    """
    crr75, msf, k_sig, csr = (np.asarray(a, dtype=float) for a in (crr75, msf, k_sig, csr))
    cap = crr75 * msf * k_sig
    with np.errstate(divide="ignore"):
        return np.where(csr > 0.0, cap / np.where(csr > 0.0, csr, 1.0), np.inf)
