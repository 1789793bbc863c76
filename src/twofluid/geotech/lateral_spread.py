"""Engineering estimates of liquefaction-induced lateral spreading on gently sloping ground.

Three estimates a geotechnical engineer would set beside the two-fluid column on a slope:

1. **Strain potential** (Zhang, Robertson & Brachman 2004). The lateral displacement index is
   the maximum cyclic shear strain integrated over depth,

       LDI = ∫₀^{z_max} γ_max(FS, Dr) dz        [m],  γ_max a fraction [-], z_max ≤ 23 m,

   and the displacement of the ground surface is

       LD = (S + 0.2) · LDI          ground slope S [%], 0.2 ≤ S ≤ 3.5
       LD = 6 (L/H)^−0.8 · LDI       free face of height H at distance L, 4 ≤ L/H ≤ 40.

   Zhang et al. plot γ_max in per cent and z in m; the product is then a length in cm, which is
   the same as γ_max as a fraction times z in m. Here γ_max is a fraction, z in m, so LDI and
   LD are in m. γ_max(FS, Dr) is the relation the project already uses for the reconsolidation
   floor (Idriss & Boulanger 2008's fit of Yoshimine et al. 2006, :func:`.settlement.max_shear_strain`),
   not Zhang et al.'s own curves read from Ishihara & Yoshimine's (1992) charts: the two differ by
   tens of per cent at a given FS (the limiting strain at Dr = 40 % is 51 % in Zhang et al., 64 %
   in the fit).

2. **Empirical regression** (Youd, Hansen & Bartlett 2002), ground-slope form::

       log D_H = −16.213 + 1.532 M − 1.406 log R* − 0.012 R + 0.338 log S
                 + 0.540 log T15 + 3.413 log(100 − F15) − 0.795 log(D50_15 + 0.1 mm)
       R* = R + 10^(0.89 M − 5.64)

   (log base 10), D_H [m], M moment magnitude, R [km] horizontal distance to the nearest bound
   of the seismic energy source, S [%] ground slope, T15 [m] cumulative thickness of saturated
   granular layers with (N1)60 < 15, F15 [%] and D50_15 [mm] their average fines content and mean
   grain size. Reported as a median with a ×/÷ 2.5 band (σ_log10 D_H = 0.197, so ×/÷ 2.5 is
   about ±2σ). Verified by the case histories for M 6–8, S 0.1–6 %, T15 1–15 m.

3. **Newmark rigid sliding block** on the liquefied layer's residual strength S_r, one-way
   (downslope only), on an infinite slope of angle α (tan α = S/100). Per unit area of a
   slope-parallel plane at vertical depth z, the mass above weighs σ_v cos α per unit plane area
   (σ_v the vertical stress of that mass); the static shear and the yield coefficient are

       τ_static = σ_d sin α cos α,     FS_post = S_r / τ_static,
       k_y = (S_r − τ_static) / (σ_v cos²α) = (S_r/σ_v)/cos²α − (σ_d/σ_v) tan α,

   from S_r (plane area) = driving weight component + k σ_v cos α · cos α: the undrained residual
   strength does not depend on the normal stress, so the normal component of the inertia force
   drops out. σ_d is the vertical stress whose weight drives: the total σ_v for dry ground or
   slope-parallel seepage (the seepage force carries the water's share), the effective
   (buoyant) σ′_v for a submerged slope under still open water (σ_v then counts the soil below
   the mudline only; the free water above carries no shear). k_y ≤ 0 ⟺ FS_post ≤ 1: a flow
   failure, whose displacement is unbounded and is reported as such, not as a number. While the
   block slides its velocity relative to the ground obeys v̇ = cos α (a(t) − k_y g), a(t) the
   horizontal acceleration that pushes it downslope, and v never becomes negative.
   **Two-way block** (a diagnostic): upslope the weight helps the strength, so the block also
   slides upslope, v̇ = cos α (a(t) + k_y,up g) while v < 0, once a(t) < −k_y,up g, with
   k_y,up = (S_r + τ_static)/(σ_v cos²α). On gentle slopes with FS_post ≫ 1, k_y,up ≈ k_y and
   the two directions nearly cancel.

Units: Dr in per cent at the public API, stresses in Pa, depths in m from the ground surface,
displacements in m, accelerations in m/s² (k_y in g).

References
----------
Zhang, G., Robertson, P. K. & Brachman, R. W. I. (2004). Estimating liquefaction-induced lateral
displacements using the standard penetration test or cone penetration test. J. Geotech.
Geoenviron. Eng. 130(8), 861–871.
Youd, T. L., Hansen, C. M. & Bartlett, S. F. (2002). Revised multilinear regression equations
for prediction of lateral spread displacement. J. Geotech. Geoenviron. Eng. 128(12), 1007–1017.
Newmark, N. M. (1965). Effects of earthquakes on dams and embankments. Géotechnique 15(2),
139–160.
Idriss, I. M. & Boulanger, R. W. (2008). Soil Liquefaction During Earthquakes. EERI MNO-12.
"""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np

from ..casefile.schema import CaseError, CaseWarning
from . import correlations

__all__ = ["lateral_displacement_index", "zhang2004_ground_slope", "zhang2004_free_face",
           "zhang2004", "ZhangResult", "youd2002_site_terms", "youd2002_ground_slope",
           "YoudResult", "slope_angle_rad", "static_shear_stress", "post_liquefaction_fs",
           "yield_coefficient", "newmark_sliding", "newmark_sliding_two_way", "newmark_infinite_slope", "SlidingResult",
           "G", "ZHANG_Z_MAX_M", "ZHANG_SLOPE_RANGE_PCT", "ZHANG_L_OVER_H_RANGE",
           "YOUD_COEFFS_SLOPE", "YOUD_SIGMA_LOG10", "YOUD_BAND_FACTOR", "YOUD_RANGES"]

SOURCE = "lateral_spread"
G = 9.80665  # standard gravity [m/s²]

ZHANG_Z_MAX_M = 23.0                 # deepest liquefiable depth in Zhang et al.'s case histories
ZHANG_SLOPE_RANGE_PCT = (0.2, 3.5)   # ground slope of the LD = (S + 0.2) LDI fit
ZHANG_L_OVER_H_RANGE = (4.0, 40.0)   # free-face ratio of the LD = 6 (L/H)^-0.8 LDI fit

# Youd, Hansen & Bartlett (2002), ground-slope model: b0, b_M, b_logR*, b_R, b_logS, b_logT15,
# b_log(100-F15), b_log(D50+0.1). Checked against two independent implementations:
# gem/oq-engine openquake/hazardlib/gsim/youd_etal_2002.py (COEFFS_SLOPE) and LiquPy
# calc_ls_bartlett (mode 's'); sigma_log10 = 0.197 as in OpenSRA (bzheng10/OpenSRA_dev).
YOUD_COEFFS_SLOPE = (-16.213, 1.532, -1.406, -0.012, 0.338, 0.540, 3.413, -0.795)
YOUD_SIGMA_LOG10 = 0.197
YOUD_BAND_FACTOR = 2.5
# Ranges over which Youd et al. (2002) verified their predictions. M, S and T15 are the
# paper's limits; F15 and D50_15 must lie in the band of their Fig. 7 (a region, not a box):
# the box here is the Bartlett & Youd (1995) data range, a warning only.
YOUD_RANGES = {"magnitude": (6.0, 8.0), "slope_percent": (0.1, 6.0), "t15_m": (1.0, 15.0),
               "f15_percent": (0.0, 50.0), "d50_15_mm": (0.1, 1.0)}


def _fail(key: str, message: str):
    raise CaseError(SOURCE, key, message)


def _scalar(name, value, lo=-math.inf, hi=math.inf, lo_open=False):
    try:
        v = float(value)
    except (TypeError, ValueError):
        _fail(name, f"must be one finite number, got {value!r}")
    if not math.isfinite(v):
        _fail(name, f"must be finite, got {v!r}")
    if v < lo or v > hi or (lo_open and v == lo):
        left = "(" if lo_open else "["
        _fail(name, f"must be in {left}{lo:g}, {hi:g}], got {v:g}")
    return v


def _rows(name, value, n):
    a = np.asarray(value, dtype=float)
    if a.ndim == 0:
        a = np.full(n, float(a))
    if a.shape != (n,):
        _fail(name, f"must be a scalar or a 1-D array of {n} rows like z_top_m, got shape {a.shape}")
    return a


def _depths(z_top_m, z_bottom_m):
    z_top = np.atleast_1d(np.asarray(z_top_m, dtype=float))
    if z_top.ndim != 1 or z_top.size == 0:
        _fail("z_top_m", f"must be a non-empty 1-D array of depths [m], got shape {z_top.shape}")
    n = z_top.size
    z_bot = _rows("z_bottom_m", z_bottom_m, n)
    for name, z in (("z_top_m", z_top), ("z_bottom_m", z_bot)):
        if not np.all(np.isfinite(z)):
            _fail(name, "must be finite (no NaN or inf)")
    if np.any(z_top < 0.0):
        _fail("z_top_m", "must be >= 0 m (depth from the ground surface)")
    if np.any(z_bot <= z_top):
        i = int(np.argmax(z_bot <= z_top))
        _fail("z_bottom_m", f"must exceed z_top_m in every row (row {i}: {z_bot[i]:g} <= {z_top[i]:g} m)")
    order = np.argsort(z_top)
    if np.any(z_top[order][1:] < z_bot[order][:-1]):
        _fail("z_top_m", "rows must not overlap (each depth in at most one row)")
    return z_top, z_bot


def _out_of_range(name: str, value: float, rng: tuple, label: str) -> str | None:
    lo, hi = rng
    if lo <= value <= hi:
        return None
    return f"{name} = {value:g} outside {lo:g}–{hi:g} of {label}"


def _report(notes: list[str], strict: bool, key: str):
    if not notes:
        return
    if strict:
        _fail(key, "; ".join(notes) + " (strict=True)")
    for note in notes:
        warnings.warn(f"{SOURCE}: {note}", CaseWarning, stacklevel=3)


# --------------------------------------------------------------------------- Zhang et al. (2004)

def lateral_displacement_index(z_top_m, z_bottom_m, fs, dr_percent, *, z_max_m=ZHANG_Z_MAX_M):
    """Lateral displacement index LDI = ∫₀^{z_max} γ_max(FS, Dr) dz [m] (Zhang et al. 2004).

    Parameters
    ----------
    z_top_m, z_bottom_m : array (n,)
        Depth range of each row [m] from the ground surface (rows must not overlap; gaps count 0).
    fs : array (n,) or scalar
        Factor of safety against triggering [-], ≥ 0; inf for rows that cannot liquefy
        (γ_max = 0 for FS ≥ 2).
    dr_percent : array (n,) or scalar
        Relative density Dr [%], 0–100.
    z_max_m : float
        Depth [m] below which nothing is integrated, in (0, 23] (Zhang et al.'s deepest
        liquefiable layer); rows reaching below it count to z_max only.

    Returns
    -------
    (ldi_m, gamma_max) : (float, ndarray (n,))
        LDI [m] and γ_max of each row [-] (a fraction), from :func:`.correlations.max_shear_strain_pct`.

    Examples
    --------
    Dr = 50 %, FS = 1: γ_max = 0.035 (hand value of :func:`.settlement.max_shear_strain`); a 4 m
    row between 2 and 6 m gives 0.14 m; with a crust (FS = inf) above nothing changes:

    >>> ldi, g = lateral_displacement_index([0.0, 2.0], [2.0, 6.0], [float("inf"), 1.0], 50.0)
    >>> round(ldi, 6), [round(float(x), 6) for x in g]
    (0.14, [0.0, 0.035])
    """
    z_top, z_bot = _depths(z_top_m, z_bottom_m)
    n = z_top.size
    fs = _rows("fs", fs, n)
    if np.any(np.isnan(fs)) or np.any(fs < 0.0):
        _fail("fs", "must be >= 0 in every row (inf for rows that cannot liquefy), no NaN")
    dr = _rows("dr_percent", dr_percent, n)
    if not np.all(np.isfinite(dr)) or np.any((dr < 0.0) | (dr > 100.0)):
        _fail("dr_percent", f"must be a relative density in per cent in [0, 100], got {dr.min():g}..{dr.max():g}")
    z_max = _scalar("z_max_m", z_max_m, 0.0, ZHANG_Z_MAX_M, lo_open=True)
    gamma = np.asarray(correlations.max_shear_strain_pct(fs, dr), dtype=float)
    h = np.clip(z_bot, None, z_max) - np.clip(z_top, None, z_max)
    return float(np.sum(gamma * h)), gamma


def zhang2004_ground_slope(ldi_m, slope_percent, *, strict=False):
    """Lateral displacement of gently sloping ground LD = (S + 0.2) · LDI [m] (Zhang et al. 2004).

    LDI [m] ≥ 0; S [%] ground slope (100 tan α) > 0, fitted for 0.2 ≤ S ≤ 3.5: outside, a
    :class:`CaseWarning` (or a CaseError with ``strict=True``).

    >>> round(zhang2004_ground_slope(0.14, 2.0), 6)     # 2.2 * 0.14
    0.308
    """
    ldi = _scalar("ldi_m", ldi_m, 0.0)
    s = _scalar("slope_percent", slope_percent, 0.0, lo_open=True)
    note = _out_of_range("S", s, ZHANG_SLOPE_RANGE_PCT, "Zhang et al. (2004) ground-slope fit [%]")
    _report([note] if note else [], strict, "slope_percent")
    return (s + 0.2) * ldi


def zhang2004_free_face(ldi_m, l_over_h, *, strict=False):
    """Lateral displacement near a free face LD = 6 (L/H)^−0.8 · LDI [m] (Zhang et al. 2004).

    L [m] horizontal distance from the toe of the free face, H [m] its height; fitted for
    4 ≤ L/H ≤ 40 (outside: a warning, or a CaseError with ``strict=True``).

    >>> round(zhang2004_free_face(1.0, 10.0), 6)        # 6 * 10**-0.8 = 6 / 6.30957
    0.950936
    """
    ldi = _scalar("ldi_m", ldi_m, 0.0)
    r = _scalar("l_over_h", l_over_h, 0.0, lo_open=True)
    note = _out_of_range("L/H", r, ZHANG_L_OVER_H_RANGE, "Zhang et al. (2004) free-face fit")
    _report([note] if note else [], strict, "l_over_h")
    return 6.0 * r ** -0.8 * ldi


@dataclass(frozen=True)
class ZhangResult:
    """Zhang et al. (2004) estimate: LDI [m], γ_max per row [-], LD [m], the form used
    (``"ground_slope"`` or ``"free_face"``), its geometry parameter (S [%] or L/H [-]) and whether
    it lies in the fitted range."""

    ldi_m: float
    gamma_max: np.ndarray
    displacement_m: float
    form: str
    parameter: float
    in_range: bool


def zhang2004(z_top_m, z_bottom_m, fs, dr_percent, *, slope_percent=None, l_over_h=None,
              z_max_m=ZHANG_Z_MAX_M, strict=False) -> ZhangResult:
    """Zhang et al. (2004) lateral displacement of a profile: LDI, then LD by the slope or free face.

    Give exactly one of ``slope_percent`` (ground slope S [%]) and ``l_over_h`` (free face).
    Other parameters as :func:`lateral_displacement_index`; out of the fitted range: a warning,
    or a CaseError with ``strict=True``.

    >>> r = zhang2004([0.0, 2.0], [2.0, 6.0], [float("inf"), 1.0], 50.0, slope_percent=2.0)
    >>> round(r.ldi_m, 6), round(r.displacement_m, 6), r.form, r.in_range
    (0.14, 0.308, 'ground_slope', True)
    """
    if (slope_percent is None) == (l_over_h is None):
        _fail("slope_percent", "give exactly one of slope_percent (ground slope) and l_over_h (free face)")
    ldi, gamma = lateral_displacement_index(z_top_m, z_bottom_m, fs, dr_percent, z_max_m=z_max_m)
    if slope_percent is not None:
        p = _scalar("slope_percent", slope_percent, 0.0, lo_open=True)
        ld = zhang2004_ground_slope(ldi, p, strict=strict)
        lo, hi = ZHANG_SLOPE_RANGE_PCT
        return ZhangResult(ldi, gamma, ld, "ground_slope", p, lo <= p <= hi)
    p = _scalar("l_over_h", l_over_h, 0.0, lo_open=True)
    ld = zhang2004_free_face(ldi, p, strict=strict)
    lo, hi = ZHANG_L_OVER_H_RANGE
    return ZhangResult(ldi, gamma, ld, "free_face", p, lo <= p <= hi)


# -------------------------------------------------------------- Youd, Hansen & Bartlett (2002)

def youd2002_site_terms(z_top_m, z_bottom_m, n1_60, saturated, fines_percent, d50_mm, *,
                        z_max_m=20.0):
    """T15 [m], F15 [%] and D50_15 [mm] of a profile for :func:`youd2002_ground_slope`.

    T15 is the cumulative thickness of the saturated granular rows with (N1)60 < 15 above
    ``z_max_m`` (20 m: the depth range of the case-history borings); F15 and D50_15 are the
    thickness-weighted means of the fines content and the mean grain size over those rows.
    (N1)60 here is the blow count corrected for energy and overburden only, not the clean-sand
    (N1)60cs. Rows that are not granular (clay, rock) should be passed with ``saturated=False``.
    Returns (0.0, nan, nan) when no row qualifies.

    >>> youd2002_site_terms([0, 2, 5], [2, 5, 9], [20, 8, 12], [False, True, True], 10.0, 0.2)
    (7.0, 10.0, 0.2)
    """
    z_top, z_bot = _depths(z_top_m, z_bottom_m)
    n = z_top.size
    n160 = _rows("n1_60", n1_60, n)
    if not np.all(np.isfinite(n160)) or np.any(n160 < 0.0):
        _fail("n1_60", "must be finite and >= 0 blows/0.3 m in every row")
    sat = np.asarray(saturated)
    if sat.dtype != bool:
        _fail("saturated", f"must be bool (one per row or one for all), got dtype {sat.dtype}")
    sat = np.broadcast_to(sat, (n,)) if sat.ndim == 0 else sat
    if sat.shape != (n,):
        _fail("saturated", f"must be a scalar or a 1-D array of {n} rows, got shape {sat.shape}")
    f = _rows("fines_percent", fines_percent, n)
    if not np.all(np.isfinite(f)) or np.any((f < 0.0) | (f >= 100.0)):
        _fail("fines_percent", "must be in [0, 100) per cent in every row")
    d = _rows("d50_mm", d50_mm, n)
    if not np.all(np.isfinite(d)) or np.any(d <= 0.0):
        _fail("d50_mm", "must be a mean grain size > 0 mm in every row")
    z_max = _scalar("z_max_m", z_max_m, 0.0, lo_open=True)
    h = np.clip(z_bot, None, z_max) - np.clip(z_top, None, z_max)
    w = np.where(sat & (n160 < 15.0), h, 0.0)
    t15 = float(w.sum())
    if t15 == 0.0:
        return 0.0, math.nan, math.nan
    return t15, float(np.sum(w * f) / t15), float(np.sum(w * d) / t15)


@dataclass(frozen=True)
class YoudResult:
    """Youd et al. (2002) ground-slope estimate: median D_H [m] with the ×/÷ ``band_factor``
    band (``lower_m``, ``upper_m``), R* [km], and the verified-range notes (empty: in range)."""

    median_m: float
    lower_m: float
    upper_m: float
    band_factor: float
    r_star_km: float
    notes: tuple[str, ...]

    @property
    def in_range(self) -> bool:
        return not self.notes


def youd2002_ground_slope(magnitude, distance_km, slope_percent, t15_m, f15_percent, d50_15_mm,
                          *, band_factor=YOUD_BAND_FACTOR, strict=False) -> YoudResult:
    """Lateral spread displacement of sloping ground, Youd, Hansen & Bartlett (2002) MLR [m].

    Parameters
    ----------
    magnitude : float
        Moment magnitude M_w, in (0, 10); verified range 6–8.
    distance_km : float
        R [km] ≥ 0, horizontal distance to the nearest bound of the seismic energy source.
    slope_percent : float
        Ground slope S = 100 tan α [%], > 0; verified 0.1–6.
    t15_m : float
        T15 [m] > 0 (see :func:`youd2002_site_terms`); verified 1–15.
    f15_percent : float
        F15 [%] in [0, 100); d50_15_mm : D50_15 [mm] > 0 (warning outside the data box
        :data:`YOUD_RANGES`).
    band_factor : float
        The band is median ×/÷ band_factor (default 2.5 ≈ 10^(2 · 0.197), about ±2σ).
    strict : bool
        Out of the verified ranges: a CaseError instead of a :class:`CaseWarning` per breach.

    Returns
    -------
    YoudResult

    Examples
    --------
    M = 7.5, R = 10 km, S = 1 %, T15 = 5 m, F15 = 10 %, D50_15 = 0.3 mm: R* = 10 + 10^1.035 =
    20.8393 km; log D_H = −16.213 + 11.49 − 1.85435 − 0.12 + 0 + 0.37744 + 6.66983 + 0.31636
    = 0.66629, D_H = 4.6375 m:

    >>> r = youd2002_ground_slope(7.5, 10.0, 1.0, 5.0, 10.0, 0.3)
    >>> round(r.r_star_km, 4), round(r.median_m, 3), round(r.lower_m, 3), round(r.upper_m, 2)
    (20.8393, 4.638, 1.855, 11.59)
    """
    m = _scalar("magnitude", magnitude, 0.0, 10.0, lo_open=True)
    r = _scalar("distance_km", distance_km, 0.0)
    s = _scalar("slope_percent", slope_percent, 0.0, lo_open=True)
    t15 = _scalar("t15_m", t15_m, 0.0, lo_open=True)
    f15 = _scalar("f15_percent", f15_percent, 0.0, 100.0)
    if f15 == 100.0:
        _fail("f15_percent", "must be < 100 % (log(100 − F15))")
    d50 = _scalar("d50_15_mm", d50_15_mm, 0.0, lo_open=True)
    band = _scalar("band_factor", band_factor, 1.0)
    label = "Youd et al. (2002) verified range"
    notes = [n for n in (
        _out_of_range("M", m, YOUD_RANGES["magnitude"], label),
        _out_of_range("S [%]", s, YOUD_RANGES["slope_percent"], label),
        _out_of_range("T15 [m]", t15, YOUD_RANGES["t15_m"], label),
        _out_of_range("F15 [%]", f15, YOUD_RANGES["f15_percent"], "the case-history data box"),
        _out_of_range("D50_15 [mm]", d50, YOUD_RANGES["d50_15_mm"], "the case-history data box"),
    ) if n]
    _report(notes, strict, "youd2002")
    b0, bm, br_star, br, bs, bt, bf, bd = YOUD_COEFFS_SLOPE
    r_star = r + 10.0 ** (0.89 * m - 5.64)
    log_d = (b0 + bm * m + br_star * math.log10(r_star) + br * r + bs * math.log10(s)
             + bt * math.log10(t15) + bf * math.log10(100.0 - f15) + bd * math.log10(d50 + 0.1))
    d = 10.0 ** log_d
    return YoudResult(d, d / band, d * band, band, r_star, tuple(notes))


# ------------------------------------------------------------------ Newmark sliding block

def slope_angle_rad(slope_percent):
    """Slope angle α = atan(S/100) [rad] of a ground slope S [%].

    >>> bool(abs(slope_angle_rad(100.0) - math.pi / 4) < 1e-15)
    True
    """
    return np.arctan(np.asarray(slope_percent, dtype=float) / 100.0)


def static_shear_stress(sigma_drive_Pa, slope_percent):
    """Static shear stress on a slope-parallel plane, τ_static = σ_d sin α cos α [Pa].

    σ_d [Pa]: the vertical stress whose weight drives (module docstring: the total σ_v for dry
    ground or slope-parallel seepage, σ′_v for a submerged slope); S [%] the ground slope.
    sin α cos α = S/100 / (1 + (S/100)²).

    >>> round(float(static_shear_stress(100e3, 2.0)), 3)     # 100e3 * 0.02 / 1.0004
    1999.2
    """
    t = np.asarray(slope_percent, dtype=float) / 100.0
    return np.asarray(sigma_drive_Pa, dtype=float) * t / (1.0 + t * t)


def post_liquefaction_fs(residual_strength_Pa, tau_static_Pa):
    """Post-liquefaction factor of safety FS_post = S_r/τ_static [-]; inf where τ_static = 0.

    Below 1 the liquefied layer cannot carry the static shear: a flow slide.

    >>> float(post_liquefaction_fs(3000.0, 2000.0)), float(post_liquefaction_fs(1.0, 0.0))
    (1.5, inf)
    """
    s_r = np.asarray(residual_strength_Pa, dtype=float)
    tau = np.asarray(tau_static_Pa, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(tau > 0.0, s_r / np.where(tau > 0.0, tau, 1.0), np.inf)


def yield_coefficient(residual_strength_Pa, sigma_v_Pa, slope_percent, sigma_drive_Pa=None):
    """Yield coefficient k_y = (S_r − τ_static)/(σ_v cos²α) [-] of an infinite slope (in g).

    S_r [Pa] residual strength on the sliding plane; σ_v [Pa] vertical stress of the sliding
    mass (its inertia); σ_d [Pa] (default σ_v) the vertical stress whose weight drives, as in
    :func:`static_shear_stress`. k_y ≤ 0: flow failure (FS_post ≤ 1).

    Hand value: S_r = 3 kPa, σ_v = 100 kPa, S = 2 %: τ = 1999.2 Pa, cos²α = 1/1.0004,
    k_y = 1000.8 · 1.0004 / 100e3 = 0.0100120:

    >>> round(float(yield_coefficient(3000.0, 100e3, 2.0)), 7)
    0.010012
    """
    t = np.asarray(slope_percent, dtype=float) / 100.0
    sigma_v = np.asarray(sigma_v_Pa, dtype=float)
    drive = sigma_v if sigma_drive_Pa is None else np.asarray(sigma_drive_Pa, dtype=float)
    tau = static_shear_stress(drive, slope_percent)
    return (np.asarray(residual_strength_Pa, dtype=float) - tau) * (1.0 + t * t) / sigma_v


def newmark_sliding(a_drive, dt, a_yield, d_out, v_out):
    """One-way rigid sliding block, exact for the linearly interpolated record (numba-compatible).

    Integrates v̇ = a(t) − a_y while the block slides (v > 0, or v = 0 and a > a_y) and holds
    v = 0 otherwise, with a(t) linear between the samples ``a_drive[k]`` at t = k dt: within a
    step the velocity is a quadratic and the displacement a cubic in time, the instants where
    sliding starts (a crosses a_y upwards) and stops (v reaches 0) are found in closed form, so
    the only error is that of the linear interpolation of the record (second order in dt for a
    smooth record, first order at a jump). Writes the displacement and velocity at the samples
    into ``d_out`` and ``v_out`` (length of ``a_drive``) and returns the final displacement.

    a_drive [m/s²] the acceleration that pushes the block downslope, a_yield [m/s²] > 0, dt [s].
    The two-way block (:func:`newmark_sliding_two_way`) whose upslope yield is never reached
    (:data:`NO_UPSLOPE_YIELD`): one integrator for both. Plain loops over floats: the same source
    compiles with ``numba.njit`` (with the two-way function compiled as its callee).

    Hand value: a = 2, 2, 2, 0, 0, ... m/s² every 0.5 s, a_y = 1 m/s². For 1 s, a − a_y = 1:
    v = 1 m/s, d = 0.5 m. Over the ramp from 2 to 0 (0.5 s), a − a_y = 1 − 4τ:
    v = 1 + τ − 2τ² = 1 at its end, d += 0.5 + 0.125 − 1/12. Then a − a_y = −1: the block stops
    1 s later, d += 0.5. Total 37/24 = 1.5416667 m:

    >>> import numpy as np
    >>> a = np.array([2.0, 2.0, 2.0, 0.0, 0.0, 0.0, 0.0])
    >>> d, v = np.zeros(7), np.zeros(7)
    >>> bool(abs(newmark_sliding(a, 0.5, 1.0, d, v) - 37 / 24) < 1e-14)
    True
    >>> [float(x) for x in v]
    [0.0, 0.5, 1.0, 1.0, 0.5, 0.0, 0.0]
    """
    return newmark_sliding_two_way(a_drive, dt, a_yield, NO_UPSLOPE_YIELD, d_out, v_out)


#: the upslope yield acceleration [m/s²] of a block that never slides upslope: so large that the
#: upslope excess −a − a_yu is −a_yu to the last bit for any record (and its slope within a step 0)
NO_UPSLOPE_YIELD = 1e300


def newmark_sliding_two_way(a_drive, dt, a_yield_down, a_yield_up, d_out, v_out):
    """Two-way rigid sliding block, exact for the linearly interpolated record (numba-compatible).

    The block's velocity v relative to the ground (positive downslope) obeys

        v̇ = a(t) − a_yd    while v > 0, or v = 0 and a > a_yd      (sliding downslope)
        v̇ = a(t) + a_yu    while v < 0, or v = 0 and a < −a_yu     (sliding upslope)
        v = 0              otherwise (the block rides with the ground),

    with a(t) linear between the samples ``a_drive[k]`` at t = k dt. Downslope the resistance
    left to accelerate the block is S_r − τ_s (a_yd = k_y,down g), upslope gravity helps the
    strength, S_r + τ_s (a_yu = k_y,up g). Within a step v is a quadratic and d a cubic in
    time; the instants where sliding starts (a crosses a_yd upwards or −a_yu downwards) and
    stops (v reaches 0) are found in closed form, several within one step if need be, so the
    only error is that of the linear interpolation of the record. Upslope sliding is integrated
    as the mirror image w = −v ≥ 0 under −a and a_yu. Writes the displacement (positive
    downslope) and velocity at the samples into ``d_out`` and ``v_out`` and returns the final
    displacement. With a_yu larger than −min(a) it is :func:`newmark_sliding`.

    a_drive [m/s²] the acceleration that pushes the block downslope; a_yield_down, a_yield_up
    [m/s²] > 0; dt [s]. Plain loops over floats: the same source compiles with ``numba.njit``.

    Hand value: a = 2, 2, 2, 0, 0, 0, 0, −2, −2, −2, 0, 0, 0, 0, 0 m/s² every 0.5 s and
    a_yd = a_yu = 1 m/s². Downslope 37/24 m as in :func:`newmark_sliding` (at rest from 2.5 s).
    Upslope u = −a rises 0 → 2 over 3.0–3.5 s and crosses 1 at 3.25 s: w = 2τ², +1/96 m; then
    u − 1 = 1 for 1 s: w = 1.125 m/s, +5/8 m; the ramp down over 0.5 s: w stays 1.125, +9/16 + 1/8
    − 1/12 m; then −1: stops after 1.125 s, +81/128 m. Upslope 719/384 m, net −127/384 m:

    >>> import numpy as np
    >>> a = np.array([2.0, 2.0, 2.0, 0.0, 0.0, 0.0, 0.0, -2.0, -2.0, -2.0, 0.0, 0.0, 0.0, 0.0, 0.0])
    >>> d, v = np.zeros(15), np.zeros(15)
    >>> bool(abs(newmark_sliding_two_way(a, 0.5, 1.0, 1.0, d, v) + 127 / 384) < 1e-14)
    True
    >>> [float(x) for x in v[6:]]
    [0.0, -0.125, -0.625, -1.125, -1.125, -0.625, -0.125, 0.0, 0.0]
    """
    n = a_drive.shape[0]
    d = 0.0
    v = 0.0
    if n > 0:
        d_out[0] = 0.0
        v_out[0] = 0.0
    for k in range(n - 1):
        rd0 = a_drive[k] - a_yield_down          # downslope excess, linear in the step
        rd1 = a_drive[k + 1] - a_yield_down
        cd = (rd1 - rd0) / dt
        ru0 = -a_drive[k] - a_yield_up           # upslope excess (mirrored), linear in the step
        ru1 = -a_drive[k + 1] - a_yield_up
        cu = (ru1 - ru0) / dt
        s = 0.0                                  # time into the step [s]
        while s < dt:
            if v == 0.0:
                rd = rd0 + cd * s
                ru = ru0 + cu * s
                if rd > 0.0 or (rd == 0.0 and cd > 0.0):
                    sgn = 1.0                    # slides downslope from s on
                elif ru > 0.0 or (ru == 0.0 and cu > 0.0):
                    sgn = -1.0                   # slides upslope from s on
                elif cd > 0.0:
                    s = max(s, -rd0 / cd)        # a crosses a_yd upwards within or after the step
                    if s >= dt:
                        break
                    sgn = 1.0
                elif cu > 0.0:
                    s = max(s, -ru0 / cu)        # a crosses −a_yu downwards within or after the step
                    if s >= dt:
                        break
                    sgn = -1.0
                else:
                    break                        # at rest until the end of the step
            else:
                sgn = 1.0 if v > 0.0 else -1.0
            if sgn > 0.0:
                rs = rd0 + cd * s
                c = cd
            else:
                rs = ru0 + cu * s
                c = cu
            if v == 0.0 and rs < 0.0:
                rs = 0.0                         # a start at a closed-form crossing: r = 0 there
            w = sgn * v                          # speed along the sliding direction, >= 0
            # sliding from s: w(τ) = w + rs τ + c τ²/2, its first root in (0, dt − s]
            span = dt - s
            qa = 0.5 * c
            qb = rs
            qc = w
            tau = span + 1.0                     # > span: no stop within the step
            if qa == 0.0:
                if qb < 0.0:
                    tau = -qc / qb
            else:
                disc = qb * qb - 4.0 * qa * qc
                if disc >= 0.0:
                    sq = math.sqrt(disc)
                    q = -0.5 * (qb + sq) if qb >= 0.0 else -0.5 * (qb - sq)
                    t1 = q / qa
                    t2 = qc / q if q != 0.0 else -1.0
                    if t1 > 0.0 and t1 < tau:
                        tau = t1
                    if t2 > 0.0 and t2 < tau:
                        tau = t2
            if tau <= span:
                d += sgn * (w * tau + 0.5 * rs * tau * tau + c * tau * tau * tau / 6.0)
                v = 0.0
                s += tau
            else:
                d += sgn * (w * span + 0.5 * rs * span * span + c * span * span * span / 6.0)
                w = w + rs * span + 0.5 * c * span * span
                v = sgn * w if w > 0.0 else 0.0
                s = dt
        d_out[k + 1] = d
        v_out[k + 1] = v
    return d


@dataclass(frozen=True)
class SlidingResult:
    """Newmark sliding block on an infinite slope.

    ``flow_failure`` is True when FS_post ≤ 1 (k_y ≤ 0): the displacement is unbounded and
    ``displacement_m``, ``t_s``, ``displacement_history_m`` are None. Otherwise the displacement
    along the slope [m] at the end of the record and its history at the record's samples from
    ``t_start_s`` on (0 before). ``message`` says it in one line. ``k_y_up``: the upslope yield
    coefficient (S_r + τ_static)/(σ_v cos²α) of a two-way block, None for the one-way block.
    """

    flow_failure: bool
    fs_post: float
    k_y: float
    tau_static_Pa: float
    slope_percent: float
    displacement_m: float | None
    t_s: np.ndarray | None
    displacement_history_m: np.ndarray | None
    message: str
    k_y_up: float | None = None

    @property
    def horizontal_displacement_m(self) -> float | None:
        """The displacement's horizontal component [m] (along the slope × cos α)."""
        if self.displacement_m is None:
            return None
        return self.displacement_m * math.cos(math.atan(self.slope_percent / 100.0))


def newmark_infinite_slope(ground_accel_m_s2, dt_s, residual_strength_Pa, sigma_v_Pa,
                           slope_percent, *, sigma_drive_Pa=None, t_start_s=0.0,
                           two_way=False) -> SlidingResult:
    """Newmark displacement of a liquefied layer on an infinite slope, one way (downslope) or two.

    Parameters
    ----------
    ground_accel_m_s2 : array (n,)
        Horizontal acceleration [m/s²] of the ground below the sliding plane, sampled every
        ``dt_s``, positive **downslope**. The block slides downslope when the ground accelerates
        upslope: the driving acceleration is a(t) = −ground_accel (run a record with both
        polarities by negating it).
    dt_s : float
        Sample interval [s] > 0.
    residual_strength_Pa : float
        S_r [Pa] ≥ 0 of the liquefied layer on the sliding plane.
    sigma_v_Pa : float
        Vertical stress of the sliding mass [Pa] > 0 at the plane (its inertia; for a submerged
        slope the soil below the mudline only).
    slope_percent : float
        Ground slope S = 100 tan α [%], > 0.
    sigma_drive_Pa : float, optional
        Vertical stress whose weight drives (default σ_v: dry ground or slope-parallel seepage;
        σ′_v for a submerged slope), in (0, σ_v].
    t_start_s : float
        Triggering time [s] ≥ 0: the block is fixed to the ground before the first sample at or
        after it.
    two_way : bool
        False (default): the one-way block (:func:`newmark_sliding`, upslope sliding forbidden).
        True: the block also slides upslope once the driving acceleration falls below
        −k_y,up g, k_y,up = (S_r + τ_static)/(σ_v cos²α) (:func:`newmark_sliding_two_way`); the
        displacement is then signed, positive downslope.

    Returns
    -------
    SlidingResult

    Examples
    --------
    >>> import numpy as np
    >>> a = -np.array([0.0, 2.0, 2.0, 2.0, 0.0, 0.0, 0.0])   # the ground accelerates upslope
    >>> r = newmark_infinite_slope(a, 0.5, 3000.0, 100e3, 2.0)
    >>> r.flow_failure, round(r.k_y, 6), round(r.fs_post, 4)
    (False, 0.010012, 1.5006)
    >>> newmark_infinite_slope(a, 0.5, 1500.0, 100e3, 2.0).message[:42]
    'flow failure: FS_post = 0.750 <= 1 (k_y = '
    """
    acc = np.asarray(ground_accel_m_s2, dtype=float)
    if acc.ndim != 1 or acc.size < 2:
        _fail("ground_accel_m_s2", f"must be a 1-D record of at least 2 samples, got shape {acc.shape}")
    if not np.all(np.isfinite(acc)):
        _fail("ground_accel_m_s2", "must be finite (no NaN or inf)")
    dt = _scalar("dt_s", dt_s, 0.0, lo_open=True)
    s_r = _scalar("residual_strength_Pa", residual_strength_Pa, 0.0)
    sigma_v = _scalar("sigma_v_Pa", sigma_v_Pa, 0.0, lo_open=True)
    slope = _scalar("slope_percent", slope_percent, 0.0, lo_open=True)
    drive = sigma_v if sigma_drive_Pa is None else _scalar("sigma_drive_Pa", sigma_drive_Pa, 0.0, sigma_v,
                                                           lo_open=True)
    t0 = _scalar("t_start_s", t_start_s, 0.0)
    tau = float(static_shear_stress(drive, slope))
    fs = float(post_liquefaction_fs(s_r, tau))
    k_y = float(yield_coefficient(s_r, sigma_v, slope, drive))
    if k_y <= 0.0:
        msg = (f"flow failure: FS_post = {fs:.3f} <= 1 (k_y = {k_y:.4f} g): the liquefied layer cannot "
               f"carry the static shear {tau:.0f} Pa, the displacement is unbounded")
        return SlidingResult(True, fs, k_y, tau, slope, None, None, None, msg)
    n = acc.size
    k0 = min(int(math.ceil(t0 / dt - 1e-9)), n - 1)
    a_drive = np.ascontiguousarray(-acc[k0:])
    d_hist = np.zeros(n)
    v_hist = np.zeros(n - k0)
    d_part = np.zeros(n - k0)
    k_up = None
    if two_way:
        k_up = (s_r + tau) * (1.0 + (slope / 100.0) ** 2) / sigma_v   # (S_r + τ_s)/(σ_v cos²α)
        newmark_sliding_two_way(a_drive, dt, k_y * G, k_up * G, d_part, v_hist)
    else:
        newmark_sliding(a_drive, dt, k_y * G, d_part, v_hist)
    cos_a = math.cos(math.atan(slope / 100.0))
    d_hist[k0:] = cos_a * d_part       # v̇ = cos α (a ∓ a_y): the same sliding intervals, scaled
    disp = float(d_hist[-1])
    if two_way:
        msg = (f"two-way Newmark sliding block: FS_post = {fs:.3f}, k_y = {k_y:.4f} g downslope, {k_up:.4f} g "
               f"upslope, displacement {disp:.3f} m along the slope (positive downslope)")
    else:
        msg = (f"Newmark sliding block: FS_post = {fs:.3f}, k_y = {k_y:.4f} g, "
               f"displacement {disp:.3f} m along the slope")
    return SlidingResult(False, fs, k_y, tau, slope, disp, dt * np.arange(n), d_hist, msg, k_up)
