"""Post-liquefaction volumetric strain of clean sand (Ishihara & Yoshimine 1992).

Ishihara & Yoshimine (1992) measured, in cyclic simple shear, the volumetric strain
ε_v of clean sand reconsolidated after cyclic loading, as a function of relative
density Dr and of the factor of safety against liquefaction FS (through the maximum
shear strain γ_max reached while cycling). Zhang, Robertson & Brachman (2002) turned
their charts into curves of ε_v against the CPT q_c1N and FS and summed ε_v over the
profile to estimate settlement of level ground. For a profile given by Dr (or SPT
(N1)60cs) this module uses the fit of the same laboratory data by Idriss & Boulanger
(2008), with γ_max after Yoshimine, Nishizaki, Amano & Hosono (2006):

    γ_lim = 1.859 (1.1 − Dr)³ ≥ 0                  limiting shear strain [-]
    F_α   = 0.032 + 4.7 Dr − 6.0 Dr²                 FS below which γ_max = γ_lim
    γ_max = 0                                        FS ≥ 2
          = min(γ_lim, 0.035 (1 − F_α)(2 − FS)/(FS − F_α))   F_α < FS < 2
          = γ_lim                                    FS ≤ F_α
    ε_v   = 1.5 exp(−2.5 Dr) min(0.08, γ_max)        [-]

Strains are fractions (not per cent). The F_α fit is stated for Dr ≥ 0.4
((N1)60cs ≥ 7); looser sand uses F_α(0.4) = 0.952, a stated extrapolation that keeps
ε_v continuous in Dr (the laboratory data cover Dr ≈ 0.3–0.9).

References
----------
Ishihara, K. & Yoshimine, M. (1992). Evaluation of settlements in sand deposits following
liquefaction during earthquakes. Soils and Foundations 32(1), 173–188.
Zhang, G., Robertson, P. K. & Brachman, R. W. I. (2002). Estimating liquefaction-induced
ground settlements from CPT for level ground. Can. Geotech. J. 39(5), 1168–1180.
Yoshimine, M., Nishizaki, H., Amano, K. & Hosono, Y. (2006). Flow deformation of liquefied
sand under constant shear load and its application to analysis of flow slide of infinite
slope. Soil Dyn. Earthq. Eng. 26(2–4), 253–264.
Idriss, I. M. & Boulanger, R. W. (2008). Soil Liquefaction During Earthquakes. EERI MNO-12.
"""
from __future__ import annotations

import numpy as np

__all__ = ["limiting_shear_strain", "max_shear_strain", "volumetric_strain", "DR_MIN_FIT"]

DR_MIN_FIT = 0.4  # lower end of the F_alpha fit (Idriss & Boulanger 2008: (N1)60cs >= 7)


def limiting_shear_strain(relative_density):
    """Limiting shear strain γ_lim = 1.859 (1.1 − Dr)³ ≥ 0 [-] (Yoshimine et al. 2006).

    Dr [-] relative density, 0 ≤ Dr ≤ 1.

    >>> round(float(limiting_shear_strain(0.5)), 5)   # 1.859 * 0.6**3
    0.40154
    """
    dr = np.asarray(relative_density, dtype=float)
    return 1.859 * np.maximum(1.1 - dr, 0.0) ** 3


def max_shear_strain(fs, relative_density):
    """Maximum cyclic shear strain γ_max [-] from FS and Dr (Idriss & Boulanger 2008).

    See the module docstring for the three branches (FS ≥ 2, F_α < FS < 2, FS ≤ F_α).
    FS [-] ≥ 0 (inf allowed: γ_max = 0); Dr [-] in [0, 1], the F_α fit below
    Dr = 0.4 evaluated at 0.4.

    Hand value, Dr = 0.5, FS = 1: F_α = 0.032 + 2.35 − 1.5 = 0.882,
    γ = 0.035 · 0.118 · 1 / 0.118 = 0.035 (< γ_lim = 0.4015):

    >>> round(float(max_shear_strain(1.0, 0.5)), 6)
    0.035
    >>> float(max_shear_strain(2.5, 0.5)), round(float(max_shear_strain(0.5, 0.5)), 5)
    (0.0, 0.40154)
    """
    fs = np.asarray(fs, dtype=float)
    dr = np.asarray(relative_density, dtype=float)
    d = np.maximum(dr, DR_MIN_FIT)
    f_alpha = 0.032 + 4.7 * d - 6.0 * d * d
    g_lim = limiting_shear_strain(dr)
    mid = (fs > f_alpha) & (fs < 2.0)
    # the middle branch only where it applies, so FS = F_alpha or inf never divides
    safe = np.where(mid, fs - f_alpha, 1.0)
    g_mid = 0.035 * (1.0 - f_alpha) * (2.0 - np.where(mid, fs, 0.0)) / safe
    return np.where(fs >= 2.0, 0.0, np.where(mid, np.minimum(g_lim, g_mid), g_lim))


def volumetric_strain(fs, relative_density):
    """Post-liquefaction volumetric strain ε_v = 1.5 exp(−2.5 Dr) min(0.08, γ_max) [-].

    FS [-] factor of safety against triggering (inf: no strain), Dr [-] in [0, 1].
    Idriss & Boulanger (2008) fit of Ishihara & Yoshimine (1992); the quantity that
    Zhang et al. (2002) sum over the profile as settlement.

    Hand values, Dr = 0.5: FS = 1 gives 1.5 · exp(−1.25) · 0.035 = 0.015042; FS = 0.5
    (γ_max = γ_lim, capped at 0.08) gives 1.5 · 0.286505 · 0.08 = 0.034381:

    >>> [round(float(e), 6) for e in volumetric_strain([1.0, 0.5, float("inf")], 0.5)]
    [0.015042, 0.034381, 0.0]
    """
    dr = np.asarray(relative_density, dtype=float)
    return 1.5 * np.exp(-2.5 * dr) * np.minimum(0.08, max_shear_strain(fs, dr))
