"""The simplified procedure over a layered profile: triggering, then settlement.

:func:`simplified_procedure` takes one row per layer (or per element) with its depth
range, the vertical stresses at its mid-depth and its relative density, evaluates
r_d, CSR, CRR_7.5, MSF, K_σ and FS (Idriss & Boulanger 2008, 2014; see
:mod:`twofluid.geotech.simplified`) and the post-liquefaction volumetric strain
(Ishihara & Yoshimine 1992 as fitted by Idriss & Boulanger 2008; see
:mod:`twofluid.geotech.settlement`), and sums ε_v × thickness into the settlement.

Rows that cannot liquefy — marked not liquefiable, or unsaturated (σ′_v ≥ σ_v, above
the water table) — get FS = inf and ε_v = 0 (never NaN); their r_d and CSR are still
reported, their CRR, MSF and K_σ too (for the row's density), so the table is full.
"""
from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from ..casefile.schema import CaseError
from . import correlations as co, settlement, simplified as sp

__all__ = ["SimplifiedResult", "simplified_procedure", "check_relative_density", "MAGNITUDE_RANGE",
           "A_MAX_RANGE_G"]

MAGNITUDE_RANGE = (5.0, 9.0)  # the case histories behind r_d, MSF and CRR span M 5.5-9.0
A_MAX_RANGE_G = (0.0, 3.0)
SIGMA_EFF_MAX_PA = 20.0 * sp.PA
SOURCE = "simplified_procedure"


@dataclass(frozen=True)
class SimplifiedResult:
    """Per-row arrays (depths from the ground surface) and the total settlement.

    ``FS`` is inf where ``can_liquefy`` is False (not liquefiable or unsaturated) or
    CSR = 0; ``eps_v`` and ``settlement_m`` are 0 there.
    """

    z_top_m: np.ndarray
    z_bottom_m: np.ndarray
    depth_mid_m: np.ndarray
    thickness_m: np.ndarray
    sigma_v_Pa: np.ndarray
    sigma_v_eff_Pa: np.ndarray
    relative_density: np.ndarray
    N1_60cs: np.ndarray
    can_liquefy: np.ndarray
    r_d: np.ndarray
    CSR: np.ndarray
    CRR_75: np.ndarray
    MSF: np.ndarray
    K_sigma: np.ndarray
    FS: np.ndarray
    eps_v: np.ndarray
    settlement_m: np.ndarray
    total_settlement_m: float
    a_max_g: float
    magnitude: float
    msf_form: str

    COLUMNS = (("depth_mid_m", "z_mid [m]", "{:.2f}"), ("thickness_m", "h [m]", "{:.2f}"),
               ("sigma_v_Pa", "sigma_v [kPa]", None), ("sigma_v_eff_Pa", "sigma'_v [kPa]", None),
               ("relative_density", "Dr [%]", "{:.0f}"), ("N1_60cs", "(N1)60cs [-]", "{:.1f}"),
               ("r_d", "r_d [-]", "{:.3f}"), ("CSR", "CSR [-]", "{:.3f}"),
               ("CRR_75", "CRR_7.5 [-]", "{:.3f}"), ("MSF", "MSF [-]", "{:.3f}"),
               ("K_sigma", "K_sigma [-]", "{:.3f}"), ("FS", "FS [-]", "{:.2f}"),
               ("eps_v", "eps_v [%]", None), ("settlement_m", "settlement [mm]", None))

    def to_rows(self) -> list[dict[str, float]]:
        """One dict per row, keyed by the column labels with units (SI; stresses in kPa,
        ε_v in %, settlement in mm as labelled); FS = inf for rows that cannot liquefy."""
        scale = {"sigma_v_Pa": 1e-3, "sigma_v_eff_Pa": 1e-3, "eps_v": 100.0, "settlement_m": 1e3}
        return [{label: float(getattr(self, name)[i]) * scale.get(name, 1.0)
                 for name, label, _ in self.COLUMNS} for i in range(self.depth_mid_m.size)]

    def table(self) -> str:
        """The rows as an aligned text table with a header and the total settlement."""
        rows = self.to_rows()
        labels = [label for _, label, _ in self.COLUMNS]
        fmts = [f or "{:.1f}" for _, _, f in self.COLUMNS]
        fmts[labels.index("eps_v [%]")] = "{:.2f}"
        cells = [[("-" if np.isinf(r[lab]) else fmt.format(r[lab])) for lab, fmt in zip(labels, fmts)]
                 for r in rows]
        width = [max(len(lab), *(len(c[j]) for c in cells)) if cells else len(lab)
                 for j, lab in enumerate(labels)]
        lines = ["  ".join(lab.rjust(w) for lab, w in zip(labels, width))]
        lines += ["  ".join(c.rjust(w) for c, w in zip(row, width)) for row in cells]
        lines.append(f"a_max = {self.a_max_g:.3f} g, M = {self.magnitude:.2f}, MSF {self.msf_form}; "
                     f"FS '-' = cannot liquefy (not liquefiable or above the water table); "
                     f"total settlement {self.total_settlement_m * 1e3:.1f} mm")
        return "\n".join(lines)

    def as_dict(self) -> dict:
        """Plain dict of every field (arrays stay arrays)."""
        return {f.name: getattr(self, f.name) for f in fields(self)}


def _warn_off_curve(slope) -> None:
    """One line for csr_n_slope values beyond B&I's b(MSF_max) curve (their MSF_max is clamped)."""
    lo, hi = co.CSR_N_SLOPE_CURVE_RANGE
    off = slope[(slope < lo) | (slope > hi)]
    if off.size:
        import warnings

        from ..casefile.schema import CaseWarning
        warnings.warn(CaseWarning(f"{SOURCE}: csr_n_slope {off[0]:g} is outside {lo:g}-{hi:g}, the range of "
                                  "Boulanger & Idriss's (2014) b(MSF_max): the simplified table's MSF_max is "
                                  "clamped to 1.09-2.2"), stacklevel=3)


def _fail(key: str, message: str):
    raise CaseError(SOURCE, key, message)


def _rows(name, value, n, dtype=float):
    a = np.asarray(value, dtype=dtype)
    if a.ndim == 0:
        a = np.full(n, a)
    if a.shape != (n,):
        _fail(name, f"must be a scalar or a 1-D array of {n} rows like z_top_m, got shape {a.shape}")
    if dtype is float and not np.all(np.isfinite(a)):
        _fail(name, "must be finite (no NaN or inf)")
    return a


def _scalar(name, value, lo, hi):
    try:
        v = float(value)
    except (TypeError, ValueError):
        _fail(name, f"must be one number in [{lo:g}, {hi:g}], got {value!r}")
    if not lo <= v <= hi:
        _fail(name, f"must be in [{lo:g}, {hi:g}], got {v:g}")
    return v


def check_relative_density(dr_percent, source: str, key: str) -> None:
    """Dr in per cent, in (1, 100]; a value ≤ 1 (a fraction given for per cent) is refused with the
    value it probably meant.

    >>> check_relative_density([45.0], "c.toml", "relative_density")
    >>> check_relative_density([0.45], "c.toml", "relative_density")
    Traceback (most recent call last):
    ...
    twofluid.casefile.schema.CaseError: c.toml: relative_density: 0.45 is <= 1: Dr is in per cent, valid (1, 100] %; did you mean 45 (×100)?
    """
    dr = np.asarray(dr_percent, dtype=float).ravel()
    low = dr[dr <= 1.0]
    if low.size:
        raise CaseError(source, key, f"{low[0]:g} is <= 1: Dr is in per cent, valid (1, 100] %; did you mean "
                        f"{low[0] * 100.0:g} (×100)?")
    if np.any(dr > 100.0):
        raise CaseError(source, key, f"{dr.max():g} is outside the valid range (1, 100] %")


def simplified_procedure(z_top_m, z_bottom_m, sigma_v_Pa, sigma_v_eff_Pa, relative_density,
                         liquefiable, a_max_g, magnitude, *, msf_form: str = "ib2014", n160cs=None,
                         qc1ncs=None, csr_n_slope=None) -> SimplifiedResult:
    """Factor of safety and post-liquefaction settlement of each row of a profile.

    Parameters
    ----------
    z_top_m, z_bottom_m : array (n,)
        Depth range of each row [m] from the ground surface, 0 ≤ top < bottom.
    sigma_v_Pa, sigma_v_eff_Pa : array (n,)
        Total and effective vertical stress at the row's mid-depth [Pa], > 0;
        σ′_v ≤ 20 atm (K_σ is calibrated to about 10 atm).
        σ′_v ≥ σ_v marks an unsaturated row (above the water table): it cannot liquefy.
    relative_density : array (n,) or scalar
        Dr [%] in (1, 100] (per cent, as in a case file; a value ≤ 1, a fraction given for per
        cent, is refused); (N1)60cs = 46 (Dr/100)² (clean sand).
    liquefiable : array (n,) of bool or scalar
        False for rows that cannot liquefy (crust, clay, rock).
    a_max_g : float
        Peak horizontal ground-surface acceleration [g], in [0, 3].
    magnitude : float
        Moment magnitude M_w, in [5, 9].
    n160cs, qc1ncs : array (n,) or scalar, optional
        A row's clean-sand (N1)60cs or q_c1Ncs where known (0 or NaN: not given). A row with
        q_c1Ncs takes Boulanger & Idriss's (2014) CPT route (CRR, C_σ, MSF_max from q_c1Ncs) and
        Dr = 0.478 q^0.264 − 1.063; one with (N1)60cs takes it and Dr = √(N/46); the others
        (N1)60cs = 46 Dr² from ``relative_density``. The liquefaction column's hysteretic model is
        calibrated to the same relations (:mod:`twofluid.models.hysteretic_sand`).
    csr_n_slope : array (n,) or scalar, optional
        A row's slope b of CSR ∝ N^−b from its own cyclic tests, in [0.05, 0.6] (0: from its
        density): with ``msf_form = "ib2014"`` the row's MSF_max is then the one Boulanger &
        Idriss's (2014) b(MSF_max) curve gives for that b, clamped to 1.09–2.2
        (:func:`twofluid.geotech.correlations.msf_max_from_slope`), as in the liquefaction
        column's law; a b outside 0.15–0.40, beyond the curve's range, is clamped with a one-line
        :class:`~twofluid.casefile.schema.CaseWarning`.
    msf_form : {"ib2014", "ib2008"}
        Magnitude scaling factor: Boulanger & Idriss (2014), density-dependent
        (default), or Idriss & Boulanger (2008).

    Returns
    -------
    SimplifiedResult

    Raises
    ------
    CaseError
        One line naming the argument and its valid range.

    Examples
    --------
    A dry crust over one saturated loose row (the crust cannot liquefy: FS = inf):

    >>> r = simplified_procedure([0.0, 2.0], [2.0, 4.0], [19e3, 56e3], [19e3, 46.19e3],
    ...                          [50.0, 50.0], [False, True], 0.3, 7.5)
    >>> float(r.FS[0]), round(float(r.FS[1]), 3), round(r.total_settlement_m, 4)
    (inf, 0.597, 0.0688)
    """
    z_top = np.atleast_1d(np.asarray(z_top_m, dtype=float))
    if z_top.ndim != 1 or z_top.size == 0:
        _fail("z_top_m", f"must be a non-empty 1-D array of depths [m], got shape {z_top.shape}")
    n = z_top.size
    z_top = _rows("z_top_m", z_top, n)
    z_bot = _rows("z_bottom_m", z_bottom_m, n)
    if np.any(z_top < 0.0):
        _fail("z_top_m", "must be >= 0 m (depth from the ground surface)")
    if np.any(z_bot <= z_top):
        i = int(np.argmax(z_bot <= z_top))
        _fail("z_bottom_m", f"must exceed z_top_m in every row (row {i}: {z_bot[i]:g} <= {z_top[i]:g} m)")
    s_v = _rows("sigma_v_Pa", sigma_v_Pa, n)
    s_e = _rows("sigma_v_eff_Pa", sigma_v_eff_Pa, n)
    for name, s in (("sigma_v_Pa", s_v), ("sigma_v_eff_Pa", s_e)):
        if np.any(s <= 0.0):
            _fail(name, "must be > 0 Pa in every row (stress at the row's mid-depth)")
    if np.any(s_e > SIGMA_EFF_MAX_PA):
        # K_sigma is calibrated to ~10 atm and turns negative near 28 atm (C_sigma = 0.3)
        _fail("sigma_v_eff_Pa", f"must be <= {SIGMA_EFF_MAX_PA:g} Pa (20 atm) for the K_sigma correlation, "
              f"got {s_e.max():g} Pa")
    dr_percent = _rows("relative_density", relative_density, n)
    check_relative_density(dr_percent, SOURCE, "relative_density")
    dr = dr_percent / 100.0  # the correlations take the fraction
    liq = np.asarray(liquefiable)
    if liq.dtype != bool:
        _fail("liquefiable", f"must be bool (one per row or one for all), got dtype {liq.dtype}")
    liq = _rows("liquefiable", liq, n, dtype=bool)
    a_max = _scalar("a_max_g", a_max_g, *A_MAX_RANGE_G)
    mag = _scalar("magnitude", magnitude, *MAGNITUDE_RANGE)
    if msf_form not in ("ib2014", "ib2008"):
        _fail("msf_form", f"must be 'ib2014' or 'ib2008', got {msf_form!r}")

    z_mid = 0.5 * (z_top + z_bot)
    h = z_bot - z_top

    def given(name, value):
        x = np.zeros(n) if value is None else np.nan_to_num(_rows(name, value, n), nan=0.0)
        if np.any(x < 0.0):
            _fail(name, "must be >= 0 in every row (0: not given)")
        return x
    nspt, qcpt = given("n160cs", n160cs), given("qc1ncs", qc1ncs)
    slope = given("csr_n_slope", csr_n_slope)
    lo, hi = co.CSR_N_SLOPE_RANGE
    if np.any((slope > 0.0) & ((slope < lo) | (slope > hi))):
        _fail("csr_n_slope", f"must be 0 (not given) or in [{lo:g}, {hi:g}] in every row")
    cpt, spt = qcpt > 0.0, (nspt > 0.0) & ~(qcpt > 0.0)
    dr = np.where(cpt, np.clip(co.dr_from_qc1ncs(np.maximum(qcpt, 1.0)), 5.0, 100.0) / 100.0,
                  np.where(spt, np.minimum(np.sqrt(nspt / 46.0), 1.0), dr))
    dr_percent = 100.0 * dr
    n160 = np.where(spt, nspt, sp.n160_from_relative_density(dr))
    rd = sp.stress_reduction(z_mid, mag)
    csr = sp.cyclic_stress_ratio(s_v, s_e, a_max, rd)
    crr = np.where(cpt, co.crr_75_cpt(qcpt), sp.crr_75(n160))
    if msf_form == "ib2014":
        msf_max = np.where(cpt, co.msf_max_cpt(qcpt), co.msf_max_spt(n160))
        msf_max = np.where(slope > 0.0, co.msf_max_from_slope(slope), msf_max)
        _warn_off_curve(slope[slope > 0.0])
        msf = 1.0 + (msf_max - 1.0) * (8.64 * np.exp(-mag / 4.0) - 1.325)
    else:
        msf = sp.msf_ib2008(mag) * np.ones(n)
    ks = np.where(cpt, co.k_sigma_cpt(s_e, np.maximum(qcpt, 1.0)), sp.k_sigma(s_e, n160))
    can = liq & (s_e < s_v)
    fs = np.where(can, sp.factor_of_safety(crr, msf, ks, csr), np.inf)
    eps = np.where(can, settlement.volumetric_strain(fs, dr), 0.0)
    dz = eps * h
    return SimplifiedResult(z_top, z_bot, z_mid, h, s_v, s_e, dr_percent, n160, can, rd, csr, crr, msf, ks,
                            fs, eps, dz, float(dz.sum()), a_max, mag, msf_form)
