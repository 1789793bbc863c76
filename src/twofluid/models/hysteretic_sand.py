"""Parameters of the hysteretic shear law (:mod:`twofluid.closures.hysteretic`) from the inputs an
engineer has: (N1)60cs (SPT), q_c1Ncs (CPT) or Dr, and σ′_v0.

Triggering is calibrated to the correlations of Idriss & Boulanger (2008) and Boulanger & Idriss
(2014) that :mod:`twofluid.geotech` also uses for the simplified procedure, so the element test
and the simplified table share CRR, K_σ and the slope b:

* CRR = CRR_M7.5(N) · K_σ(σ′_v0, N), N = (N1)60cs (SPT; the CPT route uses its own CRR and C_σ);
  the 0.9 factor for multidirectional shaking is **not** applied: a uniform cycle of the element
  at CSR = CRR_M7.5 (σ′_v0 = 1 atm) liquefies in 15 cycles, and the 1D column, shaken in one
  direction, is given the field resistance as the correlation states it;
* b from Boulanger & Idriss's (2014) curve of b against MSF_max (their Fig. A.16,
  :func:`twofluid.geotech.correlations.csr_slope_b`), MSF_max = 1.09 + ((N1)60cs/31.5)² or
  1.09 + (q_c1Ncs/180)³ ≤ 2.2 as in their MSF, so the simplified table's MSF and the element's
  CSR–N curve come from one MSF_max; CRR stays anchored at 15 uniform cycles, with no
  (N_M7.5(b)/15)^b correction (PM4Sand is calibrated the same way);
* residual strength S_r/σ′_v0 of Idriss & Boulanger (2008), void redistribution negligible,
  ≤ tan φ′ (:func:`twofluid.geotech.correlations.residual_strength_ratio_ib2008`), with
  (N1)60cs-Sr = (N1)60cs (clean sand: no fines adjustment);
* under a static shear stress τ_s (a slope), α = τ_s/σ′_v0 > 0: CRR·K_α(α, ξ_R) of Idriss &
  Boulanger (2008) (:func:`apply_k_alpha`; ξ_R at p′ = σ′_v0 (1 + 2 K0)/3);
* γ_lim = 1.859 (1.1 − Dr)³ (Yoshimine et al. 2006), Dr = √((N1)60cs/46);
* φ′ = 33° + 3 I_R, I_R = Dr (10 − ln p′/kPa) − 1 clipped to [0, 4] (Bolton 1986, triaxial form;
  p′ = σ′_v0 (1 + 2 K0)/3 with K0 = 0.5), unless given.

>>> row = derive(n160cs=10.0, sigma_v0=100e3)
>>> round(float(row["crr"]), 4), round(float(row["b"]), 3)
(0.1182, 0.193)
"""
from __future__ import annotations

import functools
import math

import numpy as np

from ..closures import hysteretic as law
from ..geotech import correlations as co
from ..geotech.correlations import csr_slope_b, residual_strength_ratio_ib2008
from ..geotech.simplified import crr_75, k_sigma

__all__ = ["derive", "parameters", "menq_fit", "bolton_friction_angle", "apply_k_alpha", "DEFAULTS", "K0"]

K0 = 0.5  # at-rest earth pressure coefficient of the element tests and of σ′_m [-]

#: defaults of the parameters that are not correlations (docs/liquefaction.md states each)
DEFAULTS = {
    "gamma_threshold": 5e-5,  # no damage below (|Δγ|/2 ≤ γ_t), full above 2 γ_t [-]
    "gamma_dilation": 0.10,  # dilation restores σ′_v0 tan φ′ over this strain beyond γ_d [-]
    "gamma_d0": 0.005,  # zone without dilation before liquefaction [-]
    "gamma_d_steps": 100.0,  # γ_d widens by γ_lim/100 per crossing of the zone once liquefied [-]
    "alpha": 0.7,  # Seed–Booker shape [-]
    "r_cap": 0.999,  # largest generated ratio [-]
    "k_centre": 1.0,  # once triggered, γ_c moves this share of the way to each half cycle's mean strain [-]
    "gamma_weakening": 0.2,  # γ_dr doubles once γ_c has drifted this far from where it triggered [-]
}


def bolton_friction_angle(dr, p_mean_pa):
    """Peak friction angle φ′ [deg] = 33 + 3 I_R, I_R = Dr (10 − ln p′) − 1 in [0, 4] (Bolton 1986).

    Dr [-] fraction, p′ [Pa].

    >>> round(float(bolton_friction_angle(0.47, 66.7e3)), 2)
    38.18
    """
    ir = np.clip(np.asarray(dr) * (10.0 - np.log(np.asarray(p_mean_pa) / 1e3)) - 1.0, 0.0, 4.0)
    return 33.0 + 3.0 * ir


def derive(*, n160cs=None, qc1ncs=None, dr=None, sigma_v0, friction_angle=None):
    """Correlated parameters of one soil at σ′_v0 [Pa]: a dict of crr, b, tan_phi,
    residual_strength [Pa], gamma_lim, dr (fraction), n160cs. Give one of (N1)60cs, q_c1Ncs or Dr
    [%] (then (N1)60cs = 46 Dr²); friction_angle [deg], None: Bolton's."""
    sig = float(sigma_v0)
    if qc1ncs is not None:
        q = float(qc1ncs)
        dr_f = min(max(float(co.dr_from_qc1ncs(q)) / 100.0, 0.05), 1.0)
        n = 46.0 * dr_f * dr_f
        crr = float(co.crr_75_cpt(q) * co.k_sigma_cpt(sig, q))
        msf_max = float(co.msf_max_cpt(q))
    else:
        if n160cs is not None:
            n = float(n160cs)
            dr_f = min(math.sqrt(n / 46.0), 1.0)
        else:
            dr_f = float(dr) / 100.0
            n = 46.0 * dr_f * dr_f
        crr = float(crr_75(n) * k_sigma(sig, n))
        msf_max = float(co.msf_max_spt(n))
    p_mean = sig * (1.0 + 2.0 * K0) / 3.0
    phi = float(bolton_friction_angle(dr_f, p_mean)) if friction_angle is None else float(friction_angle)
    tan_phi = math.tan(math.radians(phi))
    return {"crr": crr, "b": float(csr_slope_b(msf_max)), "tan_phi": tan_phi,
            "residual_strength": float(residual_strength_ratio_ib2008(n, friction_angle_deg=phi)) * sig,
            "gamma_lim": 1.859 * max(1.1 - dr_f, 0.0) ** 3, "dr": dr_f, "n160cs": n,
            "friction_angle": phi}


def parameters(*, sigma_v0, n160cs=None, qc1ncs=None, dr=None, k2max=30.0, friction_angle=None,
               theta=(0.0, 0.0, 1.0, 1.0, 1.0), mrdf=(1.0, 0.0, 1.0), liquefiable=True,
               g_max_fixed=0.0, csr_n_slope=None, **overrides) -> np.ndarray:
    """The (n, NPARAM) parameter array of :mod:`twofluid.closures.hysteretic` for n elements.

    Every argument is a scalar or an (n,) array (``theta`` (5,) or (n, 5), ``mrdf`` (3,) or (n, 3)).
    ``g_max_fixed`` > 0 marks an element above the water table: fixed G_max [Pa] and effective
    stress σ′_v0, no pore pressure. ``csr_n_slope`` (> 0; None or NaN: derived) replaces the CSR–N
    slope b that :func:`derive` takes from the magnitude scaling factor, the CRR at 15 cycles kept
    (a soil whose slope is known from its own cyclic tests). ``overrides`` replace :data:`DEFAULTS`.

    >>> p = parameters(sigma_v0=[50e3, 100e3], n160cs=10.0)
    >>> p.shape, bool(p[1, law.P_SR] > p[0, law.P_SR])
    ((2, 28), True)
    """
    sig = np.atleast_1d(np.asarray(sigma_v0, dtype=float))
    ne = sig.size
    each = lambda x: np.broadcast_to(np.asarray(x if x is not None else np.nan, dtype=float), (ne,))
    n_a, q_a, d_a = each(n160cs), each(qc1ncs), each(dr)
    phi_a = each(friction_angle)
    b_a = each(csr_n_slope)
    opts = dict(DEFAULTS, **overrides)
    par = np.zeros((ne, law.NPARAM))
    for e in range(ne):
        kw = {}
        if np.isfinite(q_a[e]) and q_a[e] > 0.0:
            kw["qc1ncs"] = q_a[e]
        elif np.isfinite(n_a[e]) and n_a[e] > 0.0:
            kw["n160cs"] = n_a[e]
        else:
            kw["dr"] = d_a[e] if np.isfinite(d_a[e]) else 47.0
        c = derive(sigma_v0=sig[e], friction_angle=None if not np.isfinite(phi_a[e]) else phi_a[e], **kw)
        par[e, law.P_TANPHI] = c["tan_phi"]
        par[e, law.P_SR] = c["residual_strength"]
        par[e, law.P_CRR] = c["crr"]
        par[e, law.P_B] = b_a[e] if np.isfinite(b_a[e]) and b_a[e] > 0.0 else c["b"]
        par[e, law.P_GLIM] = max(c["gamma_lim"], opts["gamma_d0"])
        par[e, law.P_DR] = c["dr"]
        par[e, law.P_DGD] = c["gamma_lim"] / opts["gamma_d_steps"]
    par[:, law.P_K2] = each(k2max)
    th = np.broadcast_to(np.asarray(theta, dtype=float), (ne, 5))
    par[:, law.P_TH1:law.P_TH5 + 1] = th
    par[:, law.P_P1:law.P_P3 + 1] = np.broadcast_to(np.asarray(mrdf, dtype=float), (ne, 3))
    par[:, law.P_GT] = opts["gamma_threshold"]
    par[:, law.P_SIG0] = sig
    gfix = each(g_max_fixed)
    par[:, law.P_GMAXFIX] = gfix
    par[:, law.P_PSFIX] = np.where(gfix > 0.0, sig, 0.0)
    par[:, law.P_LIQ] = np.where(gfix > 0.0, 0.0, np.broadcast_to(np.asarray(liquefiable, dtype=float), (ne,)))
    par[:, law.P_GDR] = opts["gamma_dilation"]
    par[:, law.P_ALPHA] = opts["alpha"]
    par[:, law.P_RCAP] = opts["r_cap"]
    par[:, law.P_GD0] = opts["gamma_d0"]
    par[:, law.P_KC] = opts["k_centre"]
    par[:, law.P_GW] = opts["gamma_weakening"]
    return np.ascontiguousarray(par)


def apply_k_alpha(par: np.ndarray, alpha) -> np.ndarray:
    """The parameter array ``par`` with each element's CRR multiplied by K_α of Idriss & Boulanger
    (2008) at its static shear ratio ``alpha`` = τ_s/σ′_v0 [-] (scalar or per element; elements
    with α = 0 or that generate no pore pressure unchanged) and its relative state parameter
    ξ_R(Dr, p′), p′ = σ′_v0 (1 + 2 K0)/3 (:func:`twofluid.geotech.correlations.k_alpha_ib2003`;
    α held at 0.35 and ξ_R in [−0.6, 0.1] beyond the fit). Returns a new array.

    >>> p = parameters(sigma_v0=[100e3], n160cs=10.0)
    >>> q = apply_k_alpha(p, 0.1)   # ξ_R = 1/(10 − ln 65.79) − 0.4663 = −0.2942: 0.8244 + 0.01828 e^1.9216
    >>> round(float(q[0, law.P_CRR] / p[0, law.P_CRR]), 4)
    0.9493
    """
    out = np.array(par, dtype=float)
    a = np.broadcast_to(np.asarray(alpha, dtype=float), (out.shape[0],))
    use = (a > 0.0) & (out[:, law.P_LIQ] > 0.0)
    if np.any(use):
        p_mean = out[use, law.P_SIG0] * (1.0 + 2.0 * K0) / 3.0
        out[use, law.P_CRR] *= co.k_alpha_ib2003(a[use], 100.0 * out[use, law.P_DR], p_mean)
    return out


@functools.lru_cache(maxsize=256)
def _menq_fit(sigma_v: float, tan_phi: float, g_max: float):
    from ..closures.backbone_fit import fit_gqh
    from ..closures.dynamic_curves import menq, menq_damping

    g = np.logspace(-6.0, -1.5, 30)
    sm = sigma_v * (1.0 + 2.0 * K0) / 3.0
    fit = fit_gqh(g, menq(g, sm), menq_damping(g, sm), tau_max=sigma_v * tan_phi, g_max=g_max)
    return tuple(float(x) for x in fit.theta), tuple(float(x) for x in fit.mrdf), float(fit.d_min)


def menq_fit(sigma_v, tan_phi, g_max):
    """GQ/H θ1…θ5 and MRDF p1…p3 fitted to Menq's (2003) clean-sand curves (C_u = 1.5,
    D50 = 0.5 mm) at σ′_m = σ′_v (1 + 2 K0)/3, with the strength σ′_v tan φ′ and G_max [Pa]
    (:func:`twofluid.closures.backbone_fit.fit_gqh`); returns (theta, mrdf, d_min).

    A fit costs about 1.5 s of CPU, so each is kept in memory and in a small JSON file in the
    compiled kernels' cache folder (:func:`twofluid.compiled.cache_dir`), keyed by its inputs to
    six digits and the fitting module's source; later runs read it back.

    >>> theta, mrdf, d_min = menq_fit(60e3, 0.78, 218.8e3 * 30 * 60 ** 0.5)
    >>> len(theta), len(mrdf), bool(0.0 < d_min < 0.02)
    (5, 3, True)
    """
    key = (float(f"{sigma_v:.6g}"), float(f"{tan_phi:.6g}"), float(f"{g_max:.6g}"))
    return _disk_cached(key)


@functools.lru_cache(maxsize=256)
def _disk_cached(key):
    import hashlib
    import json
    import os
    from pathlib import Path

    from ..compiled import cache_dir

    folder = cache_dir()
    digest = hashlib.sha256(repr(key).encode())
    closures = Path(__file__).resolve().parent.parent / "closures"
    for name in ("backbone_fit.py", "backbones.py", "dynamic_curves.py"):  # not imported: SciPy's
        digest.update((closures / name).read_bytes())  # optimize costs 0.5 s to import
    path = None if folder is None else folder / f"menq_fit_{digest.hexdigest()[:20]}.json"
    if path is not None and path.is_file():
        try:
            d = json.loads(path.read_text())
            return tuple(d["theta"]), tuple(d["mrdf"]), float(d["d_min"])
        except (OSError, ValueError, KeyError, TypeError):
            pass
    out = _menq_fit(*key)
    if path is not None:
        try:
            tmp = path.with_suffix(f".{os.getpid()}.tmp")
            tmp.write_text(json.dumps({"theta": out[0], "mrdf": out[1], "d_min": out[2]}))
            os.replace(tmp, path)
        except OSError:
            pass
    return out
