"""Modulus-reduction and damping curves of sand: Darendeli (2001) and Menq (2003).

Both are the modified hyperbola

    G/G_max = 1 / (1 + (γ/γ_r)^a),
    D = D_min + b(N) (G/G_max)^0.1 D_Masing(γ; γ_r, a),     b(N) = 0.6329 − 0.0057 ln N,

with D_Masing the Masing damping of the modified hyperbola, written by Darendeli as a cubic in
the Masing damping of the plain hyperbola (a = 1), D_1 = (100/π)[4 (γ − γ_r ln((γ + γ_r)/γ_r))
/ (γ²/(γ + γ_r)) − 2] per cent: D_Masing = c1 D_1 + c2 D_1² + c3 D_1³ with
c1 = −1.1143 a² + 1.8618 a + 0.2523, c2 = 0.0805 a² − 0.0710 a − 0.0095,
c3 = −0.0005 a² + 0.0002 a + 0.0003 (D in per cent inside the cubic).

- **Darendeli (2001)**, all soils, σ′_m in atm (P_a = 101.325 kPa):
  γ_r = (φ1 + φ2 PI OCR^φ3) (σ′_m/P_a)^φ4 [%], a = φ5,
  D_min = (φ6 + φ7 PI OCR^φ8) (σ′_m/P_a)^φ9 (1 + φ10 ln f) [%], b = φ11 + φ12 ln N, with
  φ1…φ12 = 0.0352, 0.0010, 0.3246, 0.3483, 0.9190, 0.8005, 0.0129, −0.1069, −0.2889, 0.2919,
  0.6329, −0.0057 (his Table 8.12, the calibrated mean values). For clean sand PI = 0, OCR = 1:
  γ_r = 0.0352 (σ′_m/P_a)^0.3483 % — 0.0216, 0.0350 and 0.0568 % at 25, 100 and 400 kPa.
- **Menq (2003)**, sands and gravels from the uniformity coefficient C_u and D50 [mm]:
  γ_r = 0.12 C_u^−0.6 (σ′_m/P_a)^(0.5 C_u^−0.15) [%], a = 0.86 + 0.1 log10(σ′_m/P_a),
  D_min = 0.55 C_u^0.1 D50^−0.3 (σ′_m/P_a)^−0.08 [%], b as Darendeli's.

Strains here are fractions (γ_r returned as a fraction), damping ratios fractions, stresses Pa.
The curves are laboratory means at σ′_m = 25 kPa–1.6 MPa (Darendeli: 0.25–16 atm; Menq:
resonant-column tests at 0.25–4 atm), for strains up to about 0.3 % (Menq) or 1 % (Darendeli);
beyond, the modified hyperbola's implied strength is not the soil's: fit a backbone that
reaches τ_max (:mod:`.backbone_fit`).

References
----------
Darendeli, M. B. (2001). Development of a new family of normalized modulus reduction and
material damping curves. PhD thesis, University of Texas at Austin.
Menq, F.-Y. (2003). Dynamic properties of sandy and gravelly soils. PhD thesis, University of
Texas at Austin.
"""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from .registry import register

__all__ = ["P_ATM", "DARENDELI_PHI", "darendeli_parameters", "menq_parameters",
           "modified_hyperbolic_reduction", "modified_hyperbolic_damping", "darendeli", "darendeli_damping",
           "menq", "menq_damping"]

P_ATM = 101.325e3  # [Pa] the atmosphere the curves are normalised by
#: Darendeli (2001) φ1 … φ12, calibrated values for all soils (his Table 8.12)
DARENDELI_PHI = (0.0352, 0.0010, 0.3246, 0.3483, 0.9190, 0.8005, 0.0129, -0.1069, -0.2889, 0.2919,
                 0.6329, -0.0057)


def darendeli_parameters(sigma_m_Pa, pi=0.0, ocr=1.0, frequency_hz=1.0, n_cycles=10.0):
    """(γ_r [-], a [-], D_min [-], b [-]) of Darendeli (2001) for mean effective stress σ′_m [Pa].

    PI [%] plasticity index, OCR [-], loading frequency f [Hz], number of cycles N [-].
    γ_r and D_min are returned as fractions (Darendeli writes them in per cent).

    Hand value, σ′_m = 1 atm, N = 10: γ_r = 0.0352 % = 3.52e-4, D_min = 0.8005 %,
    b = 0.6329 − 0.0057 ln 10 = 0.619775:

    >>> [round(float(v), 6) for v in darendeli_parameters(101.325e3)]
    [0.000352, 0.919, 0.008005, 0.619775]
    """
    f = DARENDELI_PHI
    s = np.asarray(sigma_m_Pa, dtype=float) / P_ATM
    gamma_r = (f[0] + f[1] * pi * ocr ** f[2]) * s ** f[3] / 100.0
    d_min = (f[5] + f[6] * pi * ocr ** f[7]) * s ** f[8] * (1.0 + f[9] * np.log(frequency_hz)) / 100.0
    return gamma_r, f[4], d_min, f[10] + f[11] * np.log(n_cycles)


def menq_parameters(sigma_m_Pa, cu=1.5, d50_mm=0.5, n_cycles=10.0):
    """(γ_r [-], a [-], D_min [-], b [-]) of Menq (2003) for σ′_m [Pa], C_u [-] and D50 [mm].

    Hand value, σ′_m = 1 atm, C_u = 1.5, D50 = 0.5 mm: γ_r = 0.12 · 1.5^−0.6 = 0.12 · 0.78405
    = 0.094086 %, a = 0.86, D_min = 0.55 · 1.04138 · 1.23114 = 0.70515 %:

    >>> [round(float(v), 7) for v in menq_parameters(101.325e3)]
    [0.0009409, 0.86, 0.0070515, 0.6197753]
    """
    s = np.asarray(sigma_m_Pa, dtype=float) / P_ATM
    gamma_r = 0.12 * cu ** -0.6 * s ** (0.5 * cu ** -0.15) / 100.0
    a = 0.86 + 0.1 * np.log10(s)
    d_min = 0.55 * cu ** 0.1 * d50_mm ** -0.3 * s ** -0.08 / 100.0
    return gamma_r, a, d_min, DARENDELI_PHI[10] + DARENDELI_PHI[11] * np.log(n_cycles)


def modified_hyperbolic_reduction(gamma: ArrayLike, gamma_r, a) -> np.ndarray:
    """G/G_max = 1/(1 + (|γ|/γ_r)^a) [-]; γ, γ_r [-] (fractions), a [-].

    >>> float(modified_hyperbolic_reduction(3.52e-4, 3.52e-4, 0.919))
    0.5
    """
    return 1.0 / (1.0 + (np.abs(np.asarray(gamma, dtype=float)) / gamma_r) ** a)


def modified_hyperbolic_damping(gamma: ArrayLike, gamma_r, a, d_min, b) -> np.ndarray:
    """Damping ratio D = D_min + b (G/G_max)^0.1 D_Masing [-] of the modified hyperbola.

    γ, γ_r [-], a [-], D_min [-], b [-] (module docstring; Darendeli's per-cent cubic is applied
    in per cent). At γ → 0 it tends to D_min; at γ = γ_r, a = 1 the Masing part is
    (100/π)(8 (1 − ln 2) − 2) = 14.4775 %; with c1 = 0.9998, c2 = c3 = 0 and (G/G_max)^0.1 =
    0.5^0.1 = 0.93303 the damping is 0.9998 · 14.4775 · 0.93303 = 13.505 %:

    >>> round(float(modified_hyperbolic_damping(1e-3, 1e-3, 1.0, 0.0, 1.0)), 5)
    0.13505
    """
    g = np.maximum(np.abs(np.asarray(gamma, dtype=float)), 1e-300)
    x = g / gamma_r
    # 4 (x − ln(1 + x))(1 + x)/x² − 2 with a series below x = 1e-3, where it loses digits
    big = 4.0 * (x - np.log1p(x)) * (1.0 + x) / np.where(x > 0, x * x, 1.0) - 2.0
    small = x * (2.0 / 3.0 - x * (1.0 / 3.0 - 0.2 * x))   # its series, error O(x⁴)
    d1 = (100.0 / np.pi) * np.where(x > 1e-3, big, small)
    c1 = -1.1143 * a * a + 1.8618 * a + 0.2523
    c2 = 0.0805 * a * a - 0.0710 * a - 0.0095
    c3 = -0.0005 * a * a + 0.0002 * a + 0.0003
    d_masing = (c1 * d1 + c2 * d1 ** 2 + c3 * d1 ** 3) / 100.0
    return d_min + b * modified_hyperbolic_reduction(g, gamma_r, a) ** 0.1 * d_masing


@register("modulus_reduction", "darendeli", params={"sigma_m": 100e3, "pi": 0.0, "ocr": 1.0},
          porosity_range=(0.0, 0.5), reference="Darendeli (2001), PhD thesis, UT Austin")
def darendeli(gamma: ArrayLike, sigma_m: float = 100e3, pi: float = 0.0, ocr: float = 1.0) -> np.ndarray:
    """Darendeli (2001) G/G_max(γ) [-] at mean effective stress σ′_m [Pa], PI [%], OCR [-].

    γ [-] (a fraction). Clean sand: PI = 0, OCR = 1. Valid σ′_m ≈ 25 kPa–1.6 MPa, γ ≤ 1 %.

    Hand values at 1 atm (γ_r = 3.52e-4): γ = 1e-3 gives 1/(1 + 2.8409^0.919) = 1/3.6106:

    >>> [round(float(v), 4) for v in darendeli([1e-6, 3.52e-4, 1e-3], sigma_m=101.325e3)]
    [0.9955, 0.5, 0.277]
    """
    gamma_r, a, _d, _b = darendeli_parameters(sigma_m, pi, ocr)
    return modified_hyperbolic_reduction(gamma, gamma_r, a)


def darendeli_damping(gamma: ArrayLike, sigma_m: float = 100e3, pi: float = 0.0, ocr: float = 1.0,
                      frequency_hz: float = 1.0, n_cycles: float = 10.0) -> np.ndarray:
    """Darendeli (2001) damping ratio D(γ) [-] (a fraction, not %); parameters as :func:`darendeli`.

    At small strain D → D_min = 0.8005 % (plus the Masing part, 0.003 % at 1e-7); at 0.1 %
    strain 13.8 %:

    >>> [round(float(v), 5) for v in darendeli_damping([1e-7, 1e-3], sigma_m=101.325e3)]
    [0.00804, 0.13791]
    """
    gamma_r, a, d_min, b = darendeli_parameters(sigma_m, pi, ocr, frequency_hz, n_cycles)
    return modified_hyperbolic_damping(gamma, gamma_r, a, d_min, b)


@register("modulus_reduction", "menq", params={"sigma_m": 100e3, "cu": 1.5, "d50_mm": 0.5},
          porosity_range=(0.0, 0.5), reference="Menq (2003), PhD thesis, UT Austin")
def menq(gamma: ArrayLike, sigma_m: float = 100e3, cu: float = 1.5, d50_mm: float = 0.5) -> np.ndarray:
    """Menq (2003) G/G_max(γ) [-] of sand and gravel at σ′_m [Pa], C_u [-], D50 [mm].

    γ [-] (a fraction). Clean uniform sand: C_u ≈ 1.2–2, D50 ≈ 0.2–0.6 mm. Valid σ′_m ≈
    25–400 kPa (his tests), γ ≲ 0.3 %.

    >>> round(float(menq(9.4086e-4, sigma_m=101.325e3)), 4)   # at γ_r
    0.5
    """
    gamma_r, a, _d, _b = menq_parameters(sigma_m, cu, d50_mm)
    return modified_hyperbolic_reduction(gamma, gamma_r, a)


def menq_damping(gamma: ArrayLike, sigma_m: float = 100e3, cu: float = 1.5, d50_mm: float = 0.5,
                 n_cycles: float = 10.0) -> np.ndarray:
    """Menq (2003) damping ratio D(γ) [-] (a fraction); parameters as :func:`menq`.

    >>> round(float(menq_damping(1e-7, sigma_m=101.325e3)), 5)    # D_min (0.70515 %) + Masing
    0.00707
    """
    gamma_r, a, d_min, b = menq_parameters(sigma_m, cu, d50_mm, n_cycles)
    return modified_hyperbolic_damping(gamma, gamma_r, a, d_min, b)
