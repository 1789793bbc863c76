"""OpenSees PM4Sand as a run-time peer: undrained cyclic simple shear of one element, beside twofluid.

PM4Sand (Boulanger & Ziotopoulou 2017, report UCD/CGM-17/01, version 3.1) is used only through
``nDMaterial('PM4Sand', ...)`` of openseespy (pinned: ``OPENSEESPY_VERSION``); its source is not
read. The protocol:

* one ``SSPquad`` element 1 m x 1 m, plane strain; base fixed; the two top nodes tied (equalDOF in
  x and y), so the width is constant: simple shear with K0 loading;
* consolidation: sigma'_v = 101.3 kPa applied drained in the elastic stage (stage 0); with
  nu = 1/3 the elastic stage gives K0 = nu / (1 - nu) = 0.5 (checked on every run);
* then the plastic stage (stage 1) and the static shear tau_s = alpha sigma'_v applied DRAINED (the
  vertical load held, the vertical displacement free), in increments of at most 0.5 kPa, as
  PM4Sand's calibration drivers and the column's static start do;
* then undrained: the top's vertical displacement is held (constant volume, the usual equivalent of
  undrained simple shear with incompressible water), r_u = 1 - sigma'_v / sigma'_v0;
* uniform stress-controlled cycles tau = (alpha + CSR sin 2 pi t) sigma'_v0, t in cycles, 400 load
  steps a cycle (failed steps redone in ten substeps);
* liquefaction: a single-amplitude strain |gamma - gamma_s| >= 3 %, counted from the strain gamma_s
  at the end of the static shear; N_3% is the fractional cycle at which it is first reached;
  the strain at the end of each cycle is gamma(k) - gamma_s, k = 1, 2, ...

A step of the plastic stage's very first call that stays inside the yield surface returns NaN in
openseespy 3.7.1.2 (a divide by zero in the material); so the first increment after the stage
switch is at least 0.5 kPa of shear: the static shear's first increment, or on level ground the
first step of the cycles spans the load to 0.5 kPa (about 1 % of a cycle at CSR 0.09), then steps
of 1/400 of a cycle.

Parameters (primary, per relative density Dr): D_R = Dr; G_o = 167 sqrt((N1)60 + 2.5) with
(N1)60 = 46 Dr^2 (the manual's suggested relation for G_o, UCD/CGM-17/01 sec. 4); h_po calibrated
(``calibrate``) so that CSR = CRR_M7.5 of Idriss & Boulanger (2008, 2014), twofluid's
``geotech.simplified.crr_75((N1)60)`` (K_sigma = 1 at 101.3 kPa), reaches 3 % in 15 cycles;
mass density 2.0 Mg/m3 (no inertia in a static analysis). Secondary, all passed (``SECONDARY``):
the manual's defaults, with negative values for the ones the model computes itself (h_o, A_do,
z_max, c_e, C_DR, C_kaf, F_sed,min, p_sed,o), except nu = 1/3 (default 0.3) for K0 = 0.5.

    python benchmarks/pm4sand_element.py --calibrate            # h_po per Dr, then the cases
    python benchmarks/pm4sand_element.py --json benchmarks/pm4sand_element_results.json
    python benchmarks/pm4sand_element.py --case 35,0.0,0.0899 --cycles 25

Needs openseespy (``pip install openseespy==3.7.1.2``); about 1 s of one core per 20 cycles.
"""
from __future__ import annotations

import argparse
import ctypes
import hashlib
import importlib.util
import json
import math
import sys
from pathlib import Path

import numpy as np

OPENSEESPY_VERSION = "3.7.1.2"
SIGMA_V0 = 101.3        # kPa
P_ATM = 101.3           # kPa
RHO = 2.0               # Mg/m3
MAX_DTAU_STATIC = 0.5   # kPa, the largest load increment of the drained static shear
DTAU_FRACTION = 0.02    # a strain step aims at this fraction of the cyclic stress amplitude
DGAMMA_MIN, DGAMMA_MAX = 1e-7, 1e-3   # bounds of a strain step
MAX_STEPS = 400000
NU_PLASTIC = 0.3        # Poisson's ratio of the plastic stage (the manual's default)
GAMMA_LIQ = 0.03        # single-amplitude strain of liquefaction
# Secondary parameters in nDMaterial's order after Den: the manual's defaults; -1: computed by the model.
SECONDARY = dict(P_atm=P_ATM, h_o=-1.0, e_max=0.8, e_min=0.5, n_b=0.5, n_d=0.1, A_do=-1.0, z_max=-1.0,
                 c_z=250.0, c_e=-1.0, phi_cv=33.0, nu=1.0 / 3.0, c_GD=2.0, c_DR=-1.0, c_kaf=-1.0,
                 Q=10.0, R=1.5, m=0.01, F_sed_min=-1.0, p_sed_o=-1.0)
# The cases: Dr [%], alpha = tau_s / sigma'_v0, CSR ("crr": the CRR of the Dr).
CASES = [(35, 0.05, 0.09), (35, 0.10, 0.06), (35, 0.10, 0.09), (55, 0.10, 0.147),
         (35, 0.0, "crr"), (55, 0.0, "crr")]
DRS = (35, 55)
# The small-bias cases: the drift per cycle after N_3% against alpha, at CSR = f CRR15 of the Dr.
DRIFT_ALPHAS = (0.0, 0.01, 0.02, 0.05)
DRIFT_CSR_FACTORS = (1.0, 1.3)
DRIFT_CYCLES = 30
HERE = Path(__file__).resolve().parent


def load_ops():
    """openseespy's module; the wheel's bundled BLAS/LAPACK are loaded first where the system has none."""
    try:
        import openseespy.opensees as ops
        return ops
    except Exception:
        spec = importlib.util.find_spec("openseespylinux")
        if spec is None:
            raise
        lib = Path(spec.origin).parent / "lib"
        for name in ("libquadmath.so.0", "libgfortran.so.4", "libblas.so.3", "liblapack.so.3", "libgomp.so.1"):
            if (lib / name).exists():
                ctypes.CDLL(str(lib / name), mode=ctypes.RTLD_GLOBAL)
        import openseespy.opensees as ops
        return ops


def openseespy_version() -> str:
    from importlib.metadata import version
    return version("openseespy")


def n160(dr: float) -> float:
    """(N1)60 = 46 (Dr/100)^2 (Idriss & Boulanger 2008, C_d = 46)."""
    return 46.0 * (dr / 100.0) ** 2


def g0(dr: float) -> float:
    """PM4Sand's G_o = 167 sqrt((N1)60 + 2.5) (the manual's suggested relation)."""
    return 167.0 * math.sqrt(n160(dr) + 2.5)


def crr15(dr: float) -> float:
    """Idriss & Boulanger's CRR_M7.5 at sigma'_v = 1 atm (twofluid.geotech.simplified.crr_75)."""
    from twofluid.geotech.simplified import crr_75
    return float(crr_75(n160(dr)))


def run(dr, hpo, alpha, csr, n_cycles=30.0, stop_gamma=None, after_n3=None, min_cycles=20, ops=None,
        static="drained"):
    """One undrained cyclic simple-shear test (module docstring).

    Returns dict: n3 (cycles at |gamma - gamma_s| >= 3 %, None if not reached), gamma_s, K0,
    gamma_end [end of each cycle, from gamma_s], gamma_peak [largest |gamma - gamma_s| in each
    cycle], ru_end, ru_max [per cycle], cycles_run, steps. Stops after ``n_cycles`` or once
    |gamma - gamma_s| >= ``stop_gamma`` (None: 3 %), or (``after_n3``) once ``after_n3`` cycles past
    N_3% and at least ``min_cycles`` cycles are recorded. ``static="undrained"`` (a sensitivity, not
    the protocol) holds the volume before the static shear is ramped, r_u then counting from the
    consolidation stress.
    """
    ops = ops or load_ops()
    stop = GAMMA_LIQ if stop_gamma is None else stop_gamma
    sv = SIGMA_V0
    ops.wipe()
    ops.model("basic", "-ndm", 2, "-ndf", 2)
    for tag, x, y in ((1, 0.0, 0.0), (2, 1.0, 0.0), (3, 1.0, 1.0), (4, 0.0, 1.0)):
        ops.node(tag, x, y)
    ops.fix(1, 1, 1)
    ops.fix(2, 1, 1)
    ops.equalDOF(3, 4, 1, 2)
    ops.nDMaterial("PM4Sand", 1, dr / 100.0, g0(dr), hpo, RHO, *SECONDARY.values())
    ops.element("SSPquad", 1, 1, 2, 3, 4, 1, "PlaneStrain", 1.0)
    ops.timeSeries("Linear", 1)
    ops.pattern("Plain", 1, 1)
    ops.load(3, 0.0, -0.5 * sv)
    ops.load(4, 0.0, -0.5 * sv)
    ops.constraints("Transformation")
    ops.numberer("RCM")
    ops.system("FullGeneral")
    ops.test("NormDispIncr", 1e-9, 100, 0)
    ops.algorithm("Newton")
    ops.integrator("LoadControl", 0.05)
    ops.analysis("Static")
    ops.updateMaterialStage("-material", 1, "-stage", 0)
    if ops.analyze(20) != 0:
        raise RuntimeError("consolidation failed")
    s = ops.eleResponse(1, "stress")
    k0, sv_cons = s[0] / s[1], -s[1]
    ops.loadConst("-time", 0.0)
    ops.updateMaterialStage("-material", 1, "-stage", 1)
    ops.setParameter("-val", 0, "-ele", 1, "FirstCall", "1")        # the model initialises on the K0 stress
    ops.setParameter("-val", NU_PLASTIC, "-ele", 1, "poissonRatio", "1")
    if alpha > 0.0 and static == "drained":      # drained static shear, the vertical load held
        n = max(1, int(math.ceil(alpha * sv / MAX_DTAU_STATIC)))
        ops.timeSeries("Linear", 2)
        ops.pattern("Plain", 2, 2)
        ops.load(3, alpha * sv, 0.0)
        ops.integrator("LoadControl", 1.0 / n)
        if ops.analyze(n) != 0:
            raise RuntimeError(f"drained static shear failed (Dr {dr}, alpha {alpha})")
    s = ops.eleResponse(1, "stress")
    sv0, tau_s = -s[1], s[2]
    gam_s = ops.nodeDisp(3, 1)
    ops.loadConst("-time", gam_s)
    ops.timeSeries("Constant", 3)
    ops.pattern("Plain", 3, 3)
    ops.sp(3, 2, ops.nodeDisp(3, 2))             # undrained: constant volume
    ops.timeSeries("Linear", 4)
    ops.pattern("Plain", 4, 4)
    ops.sp(3, 1, 1.0)                            # horizontal displacement = pseudo-time
    if alpha > 0.0 and static == "undrained":    # the sensitivity: tau_s ramped at constant volume
        dg = DGAMMA_MIN
        while ops.eleResponse(1, "stress")[2] < alpha * sv:
            ops.integrator("LoadControl", dg)
            if ops.analyze(1) != 0 or ops.nodeDisp(3, 1) - gam_s > GAMMA_LIQ:
                raise RuntimeError(f"undrained static shear failed (Dr {dr}, alpha {alpha})")
            dg = min(1.5 * dg, 1e-5)
        s = ops.eleResponse(1, "stress")
        sv0, tau_s = sv_cons, s[2]
        gam_s = ops.nodeDisp(3, 1)
    amp = csr * sv
    hi, lo = tau_s + amp, tau_s - amp
    # segments: (target, N at its start, N at its end, direction); the first a quarter cycle
    seg_from, target, n0, n1, sign = tau_s, hi, 0.0, 0.25, 1.0
    dg, k_prev = DGAMMA_MIN, None
    g_end, g_peak, ru_end, ru_max, g_hi, g_lo = [], [], [], [], [], []
    peak = rmax = 0.0
    hi_c, lo_c = -math.inf, math.inf
    n3 = None
    n_now = 0.0
    tau_prev, g_prev = tau_s, 0.0
    steps = 0
    while steps < MAX_STEPS:
        ops.integrator("LoadControl", sign * dg)
        if ops.analyze(1) != 0:
            raise RuntimeError("strain step failed")
        steps += 1
        s = ops.eleResponse(1, "stress")
        tau, ru = s[2], 1.0 + s[1] / sv0
        g = ops.nodeDisp(3, 1) - gam_s
        n_now = n0 + (n1 - n0) * min(1.0, max(0.0, (tau - seg_from) / (target - seg_from)))
        peak, rmax = max(peak, abs(g)), max(rmax, ru)
        hi_c, lo_c = max(hi_c, g), min(lo_c, g)
        if n3 is None and abs(g) >= GAMMA_LIQ:
            n3 = n_now
        # end of a cycle: tau crosses tau_s upward on an up segment past the first quarter
        if sign > 0 and n0 > 0.0 and tau_prev < tau_s <= tau:
            f = (tau_s - tau_prev) / (tau - tau_prev)
            g_end.append(g_prev + f * (g - g_prev))
            g_peak.append(peak)
            g_hi.append(hi_c)
            g_lo.append(lo_c)
            hi_c, lo_c = -math.inf, math.inf
            ru_end.append(ru)
            ru_max.append(rmax)
            peak = rmax = 0.0
            if len(g_end) >= n_cycles:
                break
            if after_n3 is not None and n3 is not None and len(g_end) >= max(min_cycles, n3 + after_n3):
                break
        if abs(g) >= stop:
            break
        # next strain increment: about DTAU_FRACTION of the amplitude from the last tangent
        k = (tau - tau_prev) / (sign * dg)
        want = DTAU_FRACTION * amp / k if k > 0 else DGAMMA_MAX
        dg = min(max(want, DGAMMA_MIN), DGAMMA_MAX, 2.0 * dg)
        tau_prev, g_prev = tau, g
        if sign * (tau - target) >= 0.0:         # target reached: reverse
            seg_from, n0 = tau, n1
            target, n1, sign = (lo, n1 + 0.5, -1.0) if sign > 0 else (hi, n1 + 0.5, 1.0)
            dg = DGAMMA_MIN
    ops.wipe()
    return dict(n3=n3, gamma_s=gam_s, tau_s_kPa=tau_s, K0=k0, sigma_v_start_kPa=sv0, cycles_run=n_now,
                steps=steps, gamma_end=g_end, gamma_peak=g_peak, ru_end=ru_end, ru_max=ru_max,
                gamma_max=g_hi, gamma_min=g_lo)


def cycles_to_3pct(dr, hpo, csr, alpha=0.0, n_max=40.0, ops=None):
    r = run(dr, hpo, alpha, csr, n_cycles=n_max, ops=ops)
    return r["n3"] if r["n3"] is not None else math.inf


def calibrate(dr, target=15.0, lo=0.02, hi=10.0, iters=30, tol=0.05, ops=None):
    """h_po with N_3%(CSR = CRR15) = ``target`` cycles (bisection on log h_po; N grows with h_po)."""
    csr = crr15(dr)
    for _ in range(iters):
        mid = math.sqrt(lo * hi)
        n = cycles_to_3pct(dr, mid, csr, n_max=target + 5.0, ops=ops)
        if abs(n - target) < tol:
            return mid, n
        lo, hi = (mid, hi) if n < target else (lo, mid)
    return mid, n


def csr_for_cycles(dr, hpo, n_target, alpha=0.0, iters=30, tol=0.05, ops=None):
    """CSR with N_3% = ``n_target`` (bisection; N falls as CSR grows)."""
    lo, hi = 0.02, 0.6
    for _ in range(iters):
        mid = 0.5 * (lo + hi)
        n = cycles_to_3pct(dr, hpo, mid, alpha, n_max=n_target + 5.0, ops=ops)
        if abs(n - n_target) < tol:
            return mid, n
        lo, hi = (mid, hi) if n > n_target else (lo, mid)
    return mid, n


def twofluid_case(dr, alpha, csr, n_cycles, steps=200):
    """twofluid's hysteretic element beside it at the same (N1)60cs (= 46 Dr^2, clean sand).

    N_3% from ``twofluid element-test``'s function (it stops at r_u >= 0.98 or 3 %); the strain at
    the end of each cycle from the same kernel run on, with the stops moved out of reach."""
    from twofluid.closures import hysteretic as law
    from twofluid.models import hysteretic_kernel as hk
    from twofluid.models import hysteretic_sand as hs
    from twofluid.models.element_test_hysteretic import element_test
    sig = SIGMA_V0 * 1e3
    first = element_test(csr=csr, sigma_v0=sig, n160cs=n160(dr), alpha=alpha, max_cycles=int(n_cycles),
                         steps_per_cycle=steps)
    par = hs.parameters(sigma_v0=[sig], n160cs=n160(dr), qc1ncs=None, dr=None, k2max=30.0,
                        friction_angle=None, csr_n_slope=None)
    st = law.new_state(1, par)
    if alpha > 0.0:
        par = hs.apply_k_alpha(par, alpha)
        par[0, law.P_TAUS] = alpha * sig
        law.static_state(st, par, 0, alpha * sig, sig)
    size = steps * int(n_cycles) + 1
    g, tau, ru = np.zeros(size), np.zeros(size), np.zeros(size)
    n = hk.element_cycles(st, par, 0, float(csr), steps, int(n_cycles), 10.0, 10.0, g, tau, ru, bias=float(alpha))
    last = size if n < 0 else int(round(n * steps)) + 1
    ends = [float(g[i * steps]) for i in range(1, int(n_cycles) + 1) if i * steps < last]
    g_hi = [float(g[(i - 1) * steps:i * steps + 1].max()) for i in range(1, len(ends) + 1)]
    g_lo = [float(g[(i - 1) * steps:i * steps + 1].min()) for i in range(1, len(ends) + 1)]
    g3 = np.nonzero(np.abs(g[:last]) >= GAMMA_LIQ)[0]
    return dict(n_liq_cli=None if first.cycles != first.cycles else first.cycles,
                n3=float(g3[0]) / steps if g3.size else None, gamma_end=ends, gamma_max=g_hi, gamma_min=g_lo,
                ru_end=[float(ru[i * steps]) for i in range(1, len(ends) + 1)], crr15=first.crr, b=first.b)


def script_hash() -> str:
    return hashlib.sha256(Path(__file__).read_bytes()).hexdigest()[:16]


def element_table(hpo, ops=None, twofluid=True):
    """The six cases (CASES) run to max(20, N_3% + 10) cycles (at most 40) or |gamma| 50 %."""
    rows = []
    for dr, alpha, csr in CASES:
        c = crr15(dr) if csr == "crr" else float(csr)
        r = run(dr, hpo[dr], alpha, c, n_cycles=40.0, stop_gamma=0.5, after_n3=10.0, ops=ops)
        n_keep = max(20, int(math.ceil(r["n3"])) + 10) if r["n3"] is not None else 20
        for key in ("gamma_end", "gamma_peak", "ru_end", "ru_max"):
            r[key] = [float(v) for v in r[key][:n_keep]]
        row = dict(dr_percent=dr, n160=n160(dr), alpha=alpha, csr=c, margin=alpha - c,
                   stress_reversal=alpha - c < 0.0, pm4sand=r)
        if twofluid:
            row["twofluid"] = twofluid_case(dr, alpha, c, n_keep)
        rows.append(row)
    return rows


def drift_per_cycle(gamma_end, n3, first=1, last=5):
    """Mean increment a cycle of the end-of-cycle strain (cycle k at index k - 1) from N_3% + ``first``
    to N_3% + ``last`` cycles, linear between cycle ends; None where N_3% is not reached or the
    cycles ran out before N_3% + ``last``. Given the mean strain of each cycle (gamma_max + gamma_min)/2
    instead, the drift of the cycles' centre, which a loop that only widens does not move."""
    if n3 is None or n3 + last > len(gamma_end):
        return None
    k = np.arange(1, len(gamma_end) + 1)
    a, b = (float(np.interp(n3 + x, k, gamma_end)) for x in (first, last))
    return (b - a) / (last - first)


def drift_table(hpo, drs=DRS, ops=None, twofluid=True, cycles=DRIFT_CYCLES):
    """The small-bias cases (DRIFT_ALPHAS x DRIFT_CSR_FACTORS per Dr), each run for ``cycles`` cycles
    or to |gamma| 50 %: the end-of-cycle strains, N_3%, and over N_3% + 1..5 the drift a cycle of the
    end-of-cycle strain and of the cycles' mean strain (gamma_max + gamma_min)/2."""
    rows = []
    for dr in drs:
        for f in DRIFT_CSR_FACTORS:
            for alpha in DRIFT_ALPHAS:
                c = f * crr15(dr)
                r = run(dr, hpo[dr], alpha, c, n_cycles=float(cycles), stop_gamma=0.5, ops=ops)
                for key in ("gamma_end", "gamma_peak", "ru_end", "ru_max", "gamma_max", "gamma_min"):
                    r[key] = [float(v) for v in r[key]]
                r["drift_per_cycle"] = drift_per_cycle(r["gamma_end"], r["n3"])
                r["mean_drift_per_cycle"] = drift_per_cycle(
                    [0.5 * (a + b) for a, b in zip(r["gamma_max"], r["gamma_min"])], r["n3"])
                row = dict(dr_percent=dr, n160=n160(dr), alpha=alpha, csr_over_crr15=f, csr=c, pm4sand=r)
                if twofluid:
                    tf = twofluid_case(dr, alpha, c, cycles)
                    tf["drift_per_cycle"] = drift_per_cycle(tf["gamma_end"], tf["n3"])
                    tf["mean_drift_per_cycle"] = drift_per_cycle(
                        [0.5 * (a + b) for a, b in zip(tf["gamma_max"], tf["gamma_min"])], tf["n3"])
                    row["twofluid"] = tf
                print(f"Dr {dr} % alpha {alpha:.2f} CSR {c:.4f} ({f} CRR15): PM4Sand N_3% {r['n3']}, drift "
                      f"{r['drift_per_cycle']}, mean {r['mean_drift_per_cycle']}" + ("" if not twofluid else
                      f"; twofluid N_3% {row['twofluid']['n3']}, drift {row['twofluid']['drift_per_cycle']}, "
                      f"mean {row['twofluid']['mean_drift_per_cycle']}"),
                      flush=True)
                rows.append(row)
    return rows


def _pct(v):
    return "-" if v is None else f"{100 * v:.2f}"


def markdown(res) -> str:
    """The frozen results as the tables of docs/benchmarks.md."""
    out = ["| Dr | alpha | CSR | margin | PM4Sand N_3% | twofluid N_3% | PM4Sand gamma end of cycle 15 / 20 [%] | "
           "twofluid [%] | PM4Sand r_u max (cycle 20) |", "|---|---|---|---|---|---|---|---|---|"]
    for r in res["cases"]:
        pm, tf = r["pm4sand"], r.get("twofluid", {})
        ge, te = pm["gamma_end"], tf.get("gamma_end", [])
        at = lambda lst, i: lst[i] if len(lst) > i else None  # noqa: E731
        out.append(f"| {r['dr_percent']} % | {r['alpha']:.2f} | {r['csr']:.4f} | {r['margin']:+.3f} | "
                   f"{'-' if pm['n3'] is None else '%.2f' % pm['n3']} | "
                   f"{'-' if tf.get('n3') is None else '%.2f' % tf['n3']} | {_pct(at(ge, 14))} / {_pct(at(ge, 19))} | "
                   f"{_pct(at(te, 14))} / {_pct(at(te, 19))} | {pm['ru_max'][min(19, len(pm['ru_max']) - 1)]:.3f} |")
    out += ["", "Strain at the end of each cycle, from the static strain [%] (PM4Sand / twofluid), "
            "cycles N_3% - 1 to N_3% + 10:", ""]
    for r in res["cases"]:
        pm, tf = r["pm4sand"], r.get("twofluid", {})
        k0 = max(0, int(pm["n3"]) - 1) if pm["n3"] is not None else 0
        cyc = range(k0, min(len(pm["gamma_end"]), k0 + 12))
        out.append(f"- Dr {r['dr_percent']} %, alpha {r['alpha']:.2f}, CSR {r['csr']:.4f}: " + ", ".join(
            f"{k + 1}: {100 * pm['gamma_end'][k]:.2f}"
            + (f"/{100 * tf['gamma_end'][k]:.2f}" if len(tf.get("gamma_end", [])) > k else "") for k in cyc))
    out += ["", "| Dr | CRR at 5 / 15 / 30 cycles (PM4Sand) | I&B CRR15 | h_po | G_o |", "|---|---|---|---|---|"]
    for dr, c in res["crr_curve"].items():
        pr = res["primary"][dr]
        out.append(f"| {dr} % | {c['5']['csr']:.4f} / {c['15']['csr']:.4f} / {c['30']['csr']:.4f} | "
                   f"{pr['crr15_ib']:.4f} | {pr['h_po']:.4f} | {pr['G_o']:.1f} |")
    return "\n".join(out)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--calibrate", action="store_true", help="calibrate h_po per Dr (else read --json's)")
    p.add_argument("--json", default=None, help="write (or, without --calibrate, read h_po from) this file")
    p.add_argument("--case", default=None, metavar="DR,ALPHA,CSR", help="one test, printed")
    p.add_argument("--hpo", type=float, default=None, help="h_po of --case (default: the JSON's)")
    p.add_argument("--cycles", type=float, default=25.0)
    p.add_argument("--static", choices=("drained", "undrained"), default="drained",
                   help="--case: how the static shear is applied (undrained: a sensitivity)")
    p.add_argument("--no-twofluid", action="store_true")
    p.add_argument("--drift", default=None, metavar="DR[,DR]", help="run the small-bias cases of these Dr and "
                   "add them to --json's small_bias (the other entries kept)")
    p.add_argument("--table", action="store_true", help="print --json's results as markdown tables and stop")
    a = p.parse_args(argv)
    if a.table:
        print(markdown(json.loads(Path(a.json).read_text())))
        return None
    ver = openseespy_version()
    if ver != OPENSEESPY_VERSION:
        print(f"pm4sand_element: openseespy {ver} is installed, the frozen numbers are of {OPENSEESPY_VERSION}",
              file=sys.stderr)
    ops = load_ops()
    old = json.loads(Path(a.json).read_text()) if a.json and Path(a.json).exists() else None
    if a.drift:
        drs = tuple(int(v) for v in a.drift.split(","))
        rows = drift_table({int(k): v for k, v in old["h_po"].items()}, drs=drs, ops=ops,
                           twofluid=not a.no_twofluid, cycles=int(a.cycles))
        keep = [r for r in old.get("small_bias", {}).get("cases", []) if r["dr_percent"] not in drs]
        old["small_bias"] = dict(
            description="drift per cycle after N_3% at small static bias: alpha x CSR = f CRR15, "
                        f"{int(a.cycles)} cycles or |gamma| 50 %; drift_per_cycle over N_3% + 1..5",
            openseespy=ver, script_sha256_16=script_hash(),
            cases=sorted(keep + rows, key=lambda r: (r["dr_percent"], r["csr_over_crr15"], r["alpha"])))
        Path(a.json).write_text(json.dumps(old, indent=1) + "\n")
        print(f"written {a.json}")
        return rows
    if a.case:
        dr, alpha, csr = (float(v) for v in a.case.split(","))
        hpo = a.hpo if a.hpo is not None else old["h_po"][str(int(dr))]
        r = run(dr, hpo, alpha, csr, n_cycles=a.cycles, stop_gamma=0.5, ops=ops, static=a.static)
        print(json.dumps(r, indent=1))
        return r
    if a.calibrate or old is None:
        hpo = {}
        for dr in DRS:
            hpo[dr], n = calibrate(dr, ops=ops)
            print(f"Dr {dr} %: (N1)60 {n160(dr):.3f}, G_o {g0(dr):.1f}, CRR15 {crr15(dr):.4f}, h_po {hpo[dr]:.4f} "
                  f"-> N_3% {n:.2f}", flush=True)
    else:
        hpo = {int(k): v for k, v in old["h_po"].items()}
    curve = {}
    for dr in ([] if old is not None and "crr_curve" in old and not a.calibrate else DRS):
        curve[dr] = {}
        for n_t in (5.0, 15.0, 30.0):
            c, n = csr_for_cycles(dr, hpo[dr], n_t, ops=ops)
            curve[dr][str(int(n_t))] = dict(csr=c, n3=n)
        print(f"Dr {dr} %: CRR at 5/15/30 cycles " + " / ".join(f"{v['csr']:.4f}" for v in curve[dr].values()),
              flush=True)
    if not curve:                                # the CRR curve of an earlier run, its N_3% checked
        curve = {int(k): v for k, v in old["crr_curve"].items()}
        for dr, c in curve.items():
            for n_t, v in c.items():
                if v.get("n3") is None:
                    v["n3"] = cycles_to_3pct(dr, hpo[dr], v["csr"], n_max=float(n_t) + 5.0, ops=ops)
    rows = element_table(hpo, ops=ops, twofluid=not a.no_twofluid)
    for r in rows:
        pm = r["pm4sand"]
        e = pm["gamma_end"]
        print(f"Dr {r['dr_percent']} % alpha {r['alpha']:.2f} CSR {r['csr']:.4f}: N_3% "
              f"{'-' if pm['n3'] is None else '%.2f' % pm['n3']}; gamma end of cycles 15/20 "
              f"{100 * e[14] if len(e) > 14 else float('nan'):.2f} / {100 * e[19] if len(e) > 19 else float('nan'):.2f} %"
              + ("" if a.no_twofluid else f"; twofluid N_3% {r['twofluid']['n3']}"), flush=True)
    out = dict(
        description="OpenSees PM4Sand undrained cyclic DSS element tests (benchmarks/pm4sand_element.py)",
        openseespy=ver, script_sha256_16=script_hash(), sigma_v0_kPa=SIGMA_V0, K0_target=0.5,
        gamma_liq=GAMMA_LIQ, mass_density_Mg_m3=RHO, secondary=SECONDARY,
        primary={str(dr): dict(D_R=dr / 100.0, n160=n160(dr), G_o=g0(dr), h_po=hpo[dr], crr15_ib=crr15(dr))
                 for dr in DRS},
        h_po={str(dr): hpo[dr] for dr in DRS}, crr_curve={str(dr): curve[dr] for dr in DRS}, cases=rows)
    if a.json:
        Path(a.json).write_text(json.dumps(out, indent=1) + "\n")
        print(f"written {a.json}")
    return out


if __name__ == "__main__":
    main()
