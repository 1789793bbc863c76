"""OpenSees PM4Sand u-p columns of twofluid's bundled sites (``sloping-site``, ``liquefaction-layered-site``).

An independent effective-stress model of the same site beside twofluid's hysteretic column. PM4Sand
is used only through ``nDMaterial('PM4Sand', ...)`` of openseespy (pinned in pm4sand_element.py).
The column follows the project's OpenSees peer and ``opensees_layered.py`` (SSPquadUP u-p elements
0.5 m wide, periodic sides by equalDOF, gravity elastic then plastic with a large permeability, the
real permeability afterwards, Newmark gamma = 0.6, a failed step redone as half steps (``advance``)
and then by the peer's ``recover``,
compliant base: Lysmer-Kuhlemeyer dashpot with the outcrop velocity as a base force), changed where
the material differs:

* every layer is PM4Sand with the element protocol of ``pm4sand_element.py``: D_R = Dr of the case,
  G_o = 167 sqrt(46 Dr^2 + 2.5), h_po calibrated so that Idriss & Boulanger's CRR15 at 1 atm
  reaches 3 % in 15 uniform cycles (calibrated once per Dr and cached in
  ``pm4sand_column_hpo.json``), the same secondary parameters (nu = 1/3 in the elastic gravity
  stage for K0 = 0.5, 0.3 after); the crust (no Dr in the case) takes Dr = 55 % and is drained
  (pore pressure fixed at 0 at and above the water table);
* mass densities: the crust's unit weight / g, the sands' (1 - n) rho_s + n rho_w;
* a slope S (the case's ``[site] slope`` in %) as an infinite slope: the gravity normal to the
  slope (g cos theta) is the elements' body force; the slope-parallel component is applied after
  the switch to the plastic stage, drained, as nodal forces (the column's weight times sin theta,
  solid and water: slope-parallel seepage), as the element protocol applies its static shear;
  ``--polarity -1`` reverses the record;
* the case (a bundled name or any case file, e.g. an idealised column written by
  ``scripts/idealised_spreads.py --write-cases``) is read and validated by twofluid, and its record
  is the one twofluid's run takes: the project's reader (``twofluid.io.ground_motion``, through
  the schema's ``load_motion``), cut to ``duration``, baseline-corrected (``baseline_order``),
  scaled to ``pga_g`` with the sign ``polarity``, and on a slope its component along the slope
  (cos theta of it); the bedrock's density and V_s are the case's;
* after the shaking, ``--free`` seconds of free vibration (default: the case's ``free_vibration``),
  then on a slope, while twofluid's flow criterion holds (the window-mean surface velocity
  relative to the base over ``flow_window`` at least ``flow_velocity``), at most ``--flow-max``
  seconds more (default 0: the run ends after the free vibration; the summary says which stop).

Outputs (``--out``: summary.json): surface displacement relative to the base against time (every
0.05 s), the residual (end of run) and peak shear-strain profiles, peak r_u per element, the
liquefied range (r_u >= 0.95 during the run), surface 5 %-damped Sa at 0.1-2 s, the settlement.

    python benchmarks/pm4sand_column.py sloping-site [--polarity 1|-1] [--flow-max 16] [--out DIR]
    python benchmarks/pm4sand_column.py liquefaction-layered-site --free 0 [--out DIR]
    python benchmarks/pm4sand_column.py runs/cases/c03-IMPVALL.I-p.toml --flow-max 16 --out DIR
"""
from __future__ import annotations

import argparse
import json
import math
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import pm4sand_element as pe  # noqa: E402

ops = peer = up_mesh = elastic_gravity = dynamic_transient = None  # OpenSees and opensees_layered's set-up


def load():
    """openseespy, the peer column's helpers (recover, run_until, Stats), the u-p mesh, the first
    (elastic) gravity stage and the shaking's transient analysis, as the PDMY02 layered column (``opensees_layered.py``) sets them up;
    nothing else needs OpenSees."""
    global ops, peer, up_mesh, elastic_gravity, dynamic_transient
    if ops is None:
        ops = pe.load_ops()  # (the wheel's BLAS loaded first where the system has none)
        import opensees_layered as layered

        peer, up_mesh, elastic_gravity = layered.peer, layered.up_mesh, layered.elastic_gravity
        dynamic_transient = layered.dynamic_transient
    return ops


G_ACC = 9.80665
RHO_W = 1.0                 # Mg/m3
GAMMA_W = RHO_W * G_ACC     # kN/m3
K_FLUID = 2.2e6             # kPa
WIDTH = 0.5                 # m (opensees_layered.WIDTH: its up_mesh builds the column)
CRUST_DR = 55.0             # %
HPO_CACHE = HERE / "pm4sand_column_hpo.json"
PERIODS = (0.1, 0.2, 0.3, 0.5, 0.75, 1.0, 1.5, 2.0)


def hpo_for(dr):
    """h_po calibrated for Dr [%] (pm4sand_element.calibrate), cached by Dr rounded to 0.1 %."""
    cache = json.loads(HPO_CACHE.read_text()) if HPO_CACHE.exists() else {}
    key = f"{dr:.1f}"
    if key not in cache:
        frozen = HERE / "pm4sand_element_results.json"
        fr = json.loads(frozen.read_text())["h_po"] if frozen.exists() else {}
        if f"{dr:g}" in fr:
            cache[key] = fr[f"{dr:g}"]
        else:
            cache[key] = pe.calibrate(dr, ops=load())[0]
            ops.wipe()
        HPO_CACHE.write_text(json.dumps(cache, indent=1, sort_keys=True) + "\n")
    return cache[key]


def sa(acc, dt, periods, zeta=0.05):
    """5 %-damped pseudo-spectral acceleration [same unit as acc] (Newmark average acceleration)."""
    out = []
    for T in periods:
        w = 2 * math.pi / T
        m, c, k = 1.0, 2 * zeta * w, w * w
        kh = k + 2 * c / dt + 4 * m / dt ** 2
        u = v = 0.0
        a = -acc[0]
        umax = 0.0
        for i in range(1, len(acc)):
            p = -acc[i] + m * (4 * u / dt ** 2 + 4 * v / dt + a) + c * (2 * u / dt + v)
            un = p / kh
            vn = 2 * (un - u) / dt - v
            a = 4 * (un - u) / dt ** 2 - 4 * v / dt - a
            u, v = un, vn
            umax = max(umax, abs(u))
        out.append(w * w * umax)
    return out


def case_and_motion(name, polarity=None, pga=None, duration=None):
    """The validated case (a bundled name or a case file, as ``twofluid run`` takes it) and its base
    record in m/s² as twofluid's run reads it: the project's own reader (``twofluid.io.ground_motion``
    through the case schema's ``load_motion``), cut to ``duration``, baseline-corrected, scaled to
    ``pga_g`` with the sign ``polarity``. ``polarity``, ``pga`` [g] and ``duration`` [s] override the
    case's keys (None: the case's)."""
    from twofluid.casefile.loader import load_case
    from twofluid.casefile.schema_liquefaction import load_motion

    case = load_case(str(name))
    g = case["ground_motion"]
    for key, value in (("polarity", polarity), ("pga_g", pga), ("duration", duration)):
        if value is not None:
            g[key] = value
    return case, load_motion(case, case["_source"])


def layer_materials(case, rho_s):
    """Per layer: mass density [Mg/m³], void ratio, Dr [%], k [m/s]; the crust (unit_weight > 0) takes
    Dr = CRUST_DR and its unit weight / g."""
    out = []
    for L in case["layers"]:
        if L.get("unit_weight", 0.0) > 0.0:
            out.append((L["unit_weight"] / 1000.0 / G_ACC, 0.6, CRUST_DR, 1e-4))
            continue
        n = L["porosity"] if L.get("porosity", 0.0) > 0.0 else L["void_ratio"] / (1.0 + L["void_ratio"])
        out.append(((1 - n) * rho_s + n * RHO_W, n / (1 - n), L["relative_density"], L["hydraulic_conductivity"]))
    return out


def flowing(t, u, window, v_min):
    """twofluid's flow criterion after the free vibration: v = (D(t - T, t) - D(t - 2T, t - T))/T, D the
    time mean of the surface displacement over the window T; True while v >= v_min [m/s] (or while
    fewer than 2T of samples are there)."""
    t, u = np.asarray(t), np.asarray(u)
    if t.size < 2 or t[-1] - t[0] < 2.0 * window - 1e-9:
        return True
    last = u[t > t[-1] - window].mean()
    before = u[(t > t[-1] - 2.0 * window) & (t <= t[-1] - window)].mean()
    return (last - before) / window >= v_min


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("case", nargs="?", help="a bundled case's name or a case file (e.g. one written by "
                   "scripts/idealised_spreads.py --write-cases)")
    p.add_argument("--polarity", type=int, choices=(1, -1), default=None, help="default: the case's")
    p.add_argument("--dt", type=float, default=0.005)
    p.add_argument("--free", type=float, default=None,
                   help="free vibration after the shaking [s] (default: the case's [shear_wave] free_vibration)")
    p.add_argument("--flow-max", type=float, default=0.0,
                   help="on a slope, after the free vibration, run on while twofluid's flow criterion (the case's "
                        "flow_velocity over flow_window) says the surface still moves, at most this long [s]")
    p.add_argument("--duration", type=float, default=None, help="shaking [s] (default: the case's)")
    p.add_argument("--pga", type=float, default=None, help="outcrop PGA [g] (default: the case's)")
    p.add_argument("--out", default=None)
    p.add_argument("--beside", nargs="+", metavar=("TWOFLUID_DIR", "PM4SAND_SUMMARY"),
                   help="print twofluid's run folder beside PM4Sand summary.json files and stop")
    p.add_argument("--compare", nargs="+", metavar="LABEL:POLARITY:TWOFLUID_DIR:PM4SAND_SUMMARY",
                   help="print the comparison tables of these runs and stop")
    a = p.parse_args(argv)
    if a.beside:
        print(beside(a.beside[0], a.beside[1:]))
        return None
    if a.compare:
        print(compare([(lab, int(pol), tf, pm) for lab, pol, tf, pm in (x.split(":") for x in a.compare)]))
        return None
    if a.case is None:
        p.error("a case is needed (a bundled name or a case file)")
    t_start, cpu_start = time.perf_counter(), time.process_time()
    load()
    case, motion = case_and_motion(a.case, a.polarity, a.pga, a.duration)
    gm_case = case["ground_motion"]
    sw = case["shear_wave"]
    if sw["base"] != "compliant":
        sys.exit(f"{a.case}: [shear_wave] base = {sw['base']!r}; this column has a compliant base only")
    polarity = gm_case["polarity"]
    free = sw["free_vibration"] if a.free is None else a.free
    site = case["site"]
    wt = float(site["water_table_depth"])
    slope = float(site["slope"]) / 100.0
    theta = math.atan(slope)
    rho_s = case["materials"]["particle_density"] / 1000.0
    bedrock_rho, bedrock_vs = sw["bedrock_density"] / 1000.0, sw["bedrock_shear_velocity"]
    # ---------------------------------------------------------------- layers
    mats, h, lay = [], [], []
    for i, (L, (rho, e, dr, k)) in enumerate(zip(case["layers"], layer_materials(case, rho_s))):
        mats.append(dict(name=L["name"], rho=rho, e=e, dr=dr, k=k, hpo=hpo_for(dr), G_o=pe.g0(dr)))
        ne = int(round(L["thickness"] / L["element_size"]))
        h += [L["thickness"] / ne] * ne
        lay += [i] * ne
    h, lay = np.array(h[::-1]), np.array(lay[::-1])           # base first
    nele = h.size
    y = np.concatenate([[0.0], np.cumsum(h)])
    depth = y[-1]
    zc = depth - 0.5 * (y[1:] + y[:-1])
    ydepth = depth - y
    sat = zc > wt
    # ---------------------------------------------------------------- motion
    # twofluid's record (case_and_motion); on a slope its component along the slope, cos(theta) of it, as
    # twofluid's column takes it
    dt_gm = float(motion.dt)
    dur = float(motion.duration)
    acc = np.asarray(motion.acceleration) * math.cos(theta)
    vel = np.concatenate([[0.0], np.cumsum(0.5 * (acc[1:] + acc[:-1]) * dt_gm)])
    t_max = dur + free + (a.flow_max if slope > 0.0 else 0.0)
    vel = np.concatenate([vel, np.full(int(math.ceil((t_max - dur) / dt_gm)) + 2, vel[-1])])
    # ---------------------------------------------------------------- model
    c_dash = bedrock_rho * bedrock_vs * WIDTH
    up_mesh(y, ydepth, wt, c_dash)
    sec = list(pe.SECONDARY.values())
    for i, m in enumerate(mats):
        ops.nDMaterial("PM4Sand", i + 1, m["dr"] / 100.0, m["G_o"], m["hpo"], m["rho"], *sec)
    w = np.array([mats[lay[j]]["rho"] * G_ACC * h[j] for j in range(nele)])        # kN/m2 per element
    sv_est = np.array([w[j:].sum() - 0.5 * w[j] - GAMMA_W * max(0.0, zc[j] - wt) for j in range(nele)])
    nu = pe.SECONDARY["nu"]
    for j in range(nele):
        m = mats[lay[j]]
        p_est = max(0.75 * sv_est[j], 1.0)          # the in-plane mean stress at K0 = 0.5
        g_e = m["G_o"] * pe.P_ATM * math.sqrt(p_est / pe.P_ATM)
        b_e = 2 * g_e * (1 + nu) / (3 * (1 - 2 * nu))
        alpha = 0.25 * h[j] ** 2 / (b_e + 4.0 * g_e / 3.0)
        ops.element("SSPquadUP", j + 1, 2 * j + 1, 2 * j + 2, 2 * j + 4, 2 * j + 3, int(lay[j]) + 1, 1.0, K_FLUID,
                    RHO_W, 1.0 / GAMMA_W, 1.0 / GAMMA_W, m["e"], alpha, 0.0, -G_ACC * math.cos(theta))
    # ---------------------------------------------------------------- gravity
    stats = elastic_gravity(len(mats))
    for j in range(nele):
        ops.setParameter("-val", 0, "-ele", j + 1, "FirstCall", str(int(lay[j]) + 1))
        ops.setParameter("-val", pe.NU_PLASTIC, "-ele", j + 1, "poissonRatio", str(int(lay[j]) + 1))
    if slope > 0.0:       # the slope-parallel weight, drained, plastic; the bedrock's static shear at the base
        ops.loadConst("-time", 0.0)
        ops.timeSeries("Linear", 5, "-factor", 1.0 / 5000.0)
        ops.pattern("Plain", 5, 5)
        total = float(sum(mats[lay[j]]["rho"] * h[j] * WIDTH for j in range(nele))) * G_ACC * math.sin(theta)
        for j in range(nele + 1):
            mass = 0.0
            if j > 0:
                mass += 0.5 * mats[lay[j - 1]]["rho"] * h[j - 1] * WIDTH
            if j < nele:
                mass += 0.5 * mats[lay[j]]["rho"] * h[j] * WIDTH
            ops.load(2 * j + 1, mass * G_ACC * math.sin(theta) - (total if j == 0 else 0.0), 0.0, 0.0)
        peer.run_until(5000.0, 50.0, stats)
        ops.loadConst("-time", 5000.0)
    peer.run_until(ops.getTime() + 10 * 500.0, 500.0, stats)
    for j in range(nele):
        m = mats[lay[j]]
        ops.setParameter("-val", m["k"] / GAMMA_W, "-ele", j + 1, "hPerm")
        ops.setParameter("-val", m["k"] / GAMMA_W, "-ele", j + 1, "vPerm")
    nodes_l = [2 * j + 1 for j in range(nele + 1)]
    sig = np.array([ops.eleResponse(e, "stress") for e in range(1, nele + 1)])
    sv0 = -sig[:, 1]
    tau0 = sig[:, 2]
    ux0 = np.array([ops.nodeDisp(nn, 1) for nn in nodes_l])
    uy0 = ops.nodeDisp(nodes_l[-1], 2)
    p_hyd = GAMMA_W * np.maximum(zc - wt, 0.0) * math.cos(theta)
    # ---------------------------------------------------------------- shaking
    ops.setTime(0.0)
    ops.wipeAnalysis()
    ops.timeSeries("Path", 2, "-dt", dt_gm, "-values", *vel.tolist(), "-factor", c_dash)
    ops.pattern("Plain", 2, 2)
    ops.load(1, 1.0, 0.0, 0.0)
    w1, w2 = 2 * math.pi * 1.0, 2 * math.pi * 10.0
    ops.rayleigh(2 * 0.01 * w1 * w2 / (w1 + w2), 2 * 0.01 / (w1 + w2), 0.0, 0.0)
    work = Path(tempfile.mkdtemp(prefix="pm4_col_"))
    f = {k: str(work / k) for k in ("pp", "ux", "acc", "uy")}
    ops.recorder("Node", "-file", f["pp"], "-time", "-dT", 0.01, "-node", *nodes_l, "-dof", 3, "vel")
    ops.recorder("Node", "-file", f["ux"], "-time", "-dT", 0.01, "-node", *nodes_l, "-dof", 1, "disp")
    ops.recorder("Node", "-file", f["uy"], "-time", "-dT", 0.01, "-node", nodes_l[-1], "-dof", 2, "disp")
    ops.recorder("Node", "-file", f["acc"], "-time", "-node", nodes_l[-1], "-dof", 1, "accel")
    dynamic_transient(1e-4)
    ops.record()
    d_stats = peer.Stats()
    t_d0 = time.perf_counter()
    advance(dur + free, a.dt, d_stats)
    t_flow, u_flow = [], []
    still = slope > 0.0 and a.flow_max > 0.0
    top, bottom = nodes_l[-1], nodes_l[0]
    while still and ops.getTime() < t_max - 1e-9:          # on while the slope flows (twofluid's criterion)
        t_next = min(ops.getTime() + 0.05, t_max)
        advance(t_next, a.dt, d_stats)
        t_flow.append(ops.getTime())
        u_flow.append(ops.nodeDisp(top, 1) - ops.nodeDisp(bottom, 1))
        still = flowing(t_flow, u_flow, sw["flow_window"], sw["flow_velocity"])
    t_end = ops.getTime()
    wall = time.perf_counter() - t_d0
    ops.remove("recorders")
    ops.wipe()
    # ---------------------------------------------------------------- post-process
    pp = np.loadtxt(f["pp"], ndmin=2)
    t = pp[:, 0]
    pn = pp[:, 1:]
    p_ele = 0.5 * (pn[:, :-1] + pn[:, 1:])
    ru = np.where(sat[None, :], (p_ele - p_hyd[None, :]) / sv0[None, :], 0.0)
    ux = np.loadtxt(f["ux"], ndmin=2)[:, 1:] - ux0[None, :]
    gam = (ux[:, 1:] - ux[:, :-1]) / h[None, :]
    surf = ux[:, -1] - ux[:, 0]
    uy = np.loadtxt(f["uy"], ndmin=2)
    acc_s = np.loadtxt(f["acc"], ndmin=2)
    for v in f.values():
        os.remove(v)
    os.rmdir(work)
    a_abs = acc_s[:, 1]          # the compliant base: nodal accelerations are absolute
    dt_rec = float(np.median(np.diff(acc_s[:, 0])))
    ru_max = ru.max(axis=0)
    liq = [j for j in range(nele) if sat[j] and ru_max[j] >= 0.95]
    rng = [float(min(zc[j] - 0.5 * h[j] for j in liq)), float(max(zc[j] + 0.5 * h[j] for j in liq))] if liq else None
    every = max(1, int(round(0.05 / float(np.median(np.diff(t))))))
    keep = np.unique(np.append(np.arange(0, t.size, every), t.size - 1))      # every 0.05 s and the last
    summary = dict(
        case=a.case, polarity=polarity, slope=slope, dt_s=a.dt, free_s=free, openseespy=pe.openseespy_version(),
        record=gm_case["file"], pga_g=gm_case["pga_g"], shaking_s=dur, baseline_order=gm_case["baseline_order"],
        end_s=float(t_end), flow_max_s=a.flow_max if slope > 0.0 else None,
        stopped=("flow criterion" if t_flow and t_end < t_max - 1e-9 else
                 "flow_max, still moving" if t_flow else "free vibration"),
        flow_criterion=dict(velocity_m_s=sw["flow_velocity"], window_s=sw["flow_window"]),
        bedrock=dict(rho_Mg_m3=bedrock_rho, vs_m_s=bedrock_vs), rayleigh=dict(ratio=0.01, frequencies_hz=[1.0, 10.0]),
        newmark=dict(gamma=0.6, beta=0.25 * 1.1 ** 2), secondary=pe.SECONDARY, nu_plastic=pe.NU_PLASTIC,
        materials=[{k: v for k, v in m.items()} for m in mats], crust_dr_percent=CRUST_DR,
        surface_displacement_end_m=float(surf[-1]),
        surface_displacement_end_of_shaking_m=float(np.interp(dur, t, surf)),
        surface_displacement_peak_m=float(np.max(np.abs(surf))),
        settlement_m=float(-(uy[-1, 1] - uy0)), liquefied_range_m=rng,
        liquefied_thickness_m=float(sum(h[j] for j in liq)),
        surface_pga_g=float(np.max(np.abs(a_abs)) / G_ACC),
        surface_sa_g={f"{T:g}": v / G_ACC for T, v in zip(PERIODS, sa(a_abs, dt_rec, PERIODS))},
        steps=d_stats.steps, failed_solves=d_stats.failures, halved_steps=d_stats.substeps,
        failed_at_s=[round(x, 4) for x in d_stats.fail_times], wall_dynamic_s=wall,
        wall_total_s=time.perf_counter() - t_start, cpu_total_s=time.process_time() - cpu_start,
        profile=[dict(depth_m=float(zc[j]), layer=mats[lay[j]]["name"], sigma_v0_kPa=float(sv0[j]),
                      tau0_kPa=float(tau0[j]), ru_max=float(ru_max[j]) if sat[j] else None,
                      gamma_residual=float(gam[-1, j]), gamma_peak=float(np.max(np.abs(gam[:, j]))))
                 for j in range(nele - 1, -1, -1)],
        surface_displacement_history=dict(t_s=t[keep].round(4).tolist(), u_m=surf[keep].round(6).tolist()))
    print(f"=== PM4Sand column {a.case}, polarity {polarity:+d}: surface displacement {100 * surf[-1]:.1f} cm "
          f"(end of shaking {100 * summary['surface_displacement_end_of_shaking_m']:.1f} cm), settlement "
          f"{100 * summary['settlement_m']:.1f} cm, liquefied {rng}, PGA {summary['surface_pga_g']:.3f} g, "
          f"{d_stats.steps} steps, {d_stats.failures} failed, {wall:.0f} s")
    if a.out:
        out = Path(a.out)
        out.mkdir(parents=True, exist_ok=True)
        (out / "summary.json").write_text(json.dumps(summary, indent=1) + "\n")
    return summary


def beside(tf_dir, pm_files, depths=(2.5, 3.5, 4.5, 5.5, 6.5, 7.5, 9.0)):
    """Markdown rows: twofluid's run folder (``twofluid run CASE --out DIR``) beside PM4Sand summaries."""
    import csv
    tf = json.loads((Path(tf_dir) / "summary.json").read_text())
    pms = [json.loads(Path(f).read_text()) for f in pm_files]
    with open(Path(tf_dir) / "spectra.csv") as fh:
        rows = list(csv.DictReader(fh))
    per = np.array([float(r["period_s"]) for r in rows])
    sa_tf = np.array([float(r["Sa_surface_g"]) for r in rows])
    with open(Path(tf_dir) / "elements.csv") as fh:
        els = list(csv.DictReader(fh))
    slope = tf.get("slope")
    resid = None
    if (Path(tf_dir) / "lateral_displacement.csv").exists():      # the end-of-run displacement profile
        with open(Path(tf_dir) / "lateral_displacement.csv") as fh:
            rd = list(csv.reader(fh))
        zs = np.array([float(c[2:-1]) for c in rd[0][1:]])
        u_end = np.array([float(v) for v in rd[-1][1:]])
        resid = (zs, u_end)
    lines = ["| | twofluid | " + " | ".join(f"PM4Sand (polarity {p['polarity']:+d})" for p in pms) + " |",
             "|---|---|" + "---|" * len(pms)]
    u_tf = slope["surface_displacement_end_m"] if slope else 0.0
    lines.append(f"| surface displacement, end [m] | {u_tf:.3f} | " + " | ".join(
        f"{p['surface_displacement_end_m']:.3f}" for p in pms) + " |")
    if slope:
        u_s = slope["surface_displacement_end_of_shaking_m"]
        lines.append(f"| surface displacement, end of shaking [m] | {u_s:.3f} | "
                     + " | ".join(f"{p['surface_displacement_end_of_shaking_m']:.3f}" for p in pms) + " |")
    rng = tf["liquefied_depth_range_shaking_m"]
    lines.append(f"| liquefied (r_u >= 0.95) while shaking [m] | {rng} | " + " | ".join(
        str(p["liquefied_range_m"]) for p in pms) + " |")
    lines.append(f"| settlement, end of shaking [m] | {tf['settlement_end_of_shaking_m']:.4f} | " + " | ".join(
        f"{p['settlement_m']:.4f} (t = {p.get('end_s', p['free_s'] + 10):g} s)" for p in pms) + " |")
    lines.append(f"| surface PGA [g] | {tf['shaking']['peak_surface_acceleration_g']:.3f} | " + " | ".join(
        f"{p['surface_pga_g']:.3f}" for p in pms) + " |")
    for T in (0.2, 0.5, 1.0):
        lines.append(f"| surface Sa({T:g} s) [g] | {float(np.interp(T, per, sa_tf)):.3f} | " + " | ".join(
            f"{p['surface_sa_g'][f'{T:g}']:.3f}" for p in pms) + " |")
    for z in depths:
        e = min(els, key=lambda r: abs(float(r["depth_m"]) - z))
        pr = [min(p["profile"], key=lambda r: abs(r["depth_m"] - z)) for p in pms]
        if resid is not None:
            i = int(np.searchsorted(resid[0], z))
            g_res = (resid[1][i - 1] - resid[1][i]) / (resid[0][i] - resid[0][i - 1])
        lines.append(f"| peak / residual shear strain at {z:g} m [%] | {100 * float(e['peak_shear_strain']):.2f} / "
                     + ("-" if resid is None else f"{100 * g_res:.2f}") + " | " + " | ".join(
                         f"{100 * r['gamma_peak']:.2f} / {100 * r['gamma_residual']:.2f}" for r in pr) + " |")
    return "\n".join(lines)


def twofluid_numbers(run_dir):
    """The numbers of a ``twofluid run CASE --out DIR`` folder that the comparison takes."""
    import csv
    d = Path(run_dir)
    tf = json.loads((d / "summary.json").read_text())
    with open(d / "spectra.csv") as fh:
        rows = list(csv.DictReader(fh))
    per = np.array([float(r["period_s"]) for r in rows])
    sa_tf = np.array([float(r["Sa_surface_g"]) for r in rows])
    sl = tf.get("slope") or {}
    rs = tf.get("residual_strain") or {}
    youd = ((sl.get("estimates") or {}).get("youd_2002") or {}).get("median_m")
    hist = None
    if (d / "surface_displacement.csv").exists():
        with open(d / "surface_displacement.csv") as fh:
            rows = list(csv.DictReader(fh))
        hist = (np.array([float(r["time_s"]) for r in rows]), np.array([float(r["surface_displacement_m"]) for r in rows]))
    return dict(history=hist, u_end=sl.get("surface_displacement_end_m", 0.0),
                u_shaking=sl.get("surface_displacement_end_of_shaking_m"),
                liquefied=tf["liquefied_depth_range_shaking_m"], liquefied_m=tf["liquefied_thickness_shaking_m"],
                gamma_res=rs.get("largest_residual_strain"), gamma_res_z=rs.get("largest_residual_strain_depth_m"),
                pga=tf["shaking"]["peak_surface_acceleration_g"],
                sa={T: float(np.interp(T, per, sa_tf)) for T in (0.2, 0.5, 1.0)},
                settle_shaking=tf["settlement_end_of_shaking_m"], settle_end=tf["settlement_end_m"], youd=youd,
                wall=tf.get("wall_time_s"))


def pm4sand_numbers(summary):
    """The same numbers from a PM4Sand summary (a file or its dict)."""
    p = summary if isinstance(summary, dict) else json.loads(Path(summary).read_text())
    sat = [r for r in p["profile"] if r["ru_max"] is not None]
    big = max(sat, key=lambda r: abs(r["gamma_residual"]))
    h = p["surface_displacement_history"]
    return dict(history=(np.array(h["t_s"]), np.array(h["u_m"])),
                u_end=p["surface_displacement_end_m"], u_shaking=p["surface_displacement_end_of_shaking_m"],
                liquefied=p["liquefied_range_m"], liquefied_m=p["liquefied_thickness_m"],
                gamma_res=big["gamma_residual"], gamma_res_z=big["depth_m"], pga=p["surface_pga_g"],
                sa={T: p["surface_sa_g"][f"{T:g}"] for T in (0.2, 0.5, 1.0)}, settle_end=p["settlement_m"],
                end_s=p.get("end_s"), stopped=p.get("stopped"), cpu=p.get("cpu_total_s"), wall=p.get("wall_total_s"))


def compare(items):
    """Markdown tables of twofluid beside PM4Sand for ``items``: (label, polarity, twofluid run folder,
    PM4Sand summary); the displacements per polarity, their means and ratio, then the rest per run."""
    runs = [(lab, pol, twofluid_numbers(t), pm4sand_numbers(p)) for lab, pol, t, p in items]
    out = ["| column | twofluid +1 / −1 [m] | PM4Sand +1 / −1 [m] | twofluid mean [m] | PM4Sand mean [m] | "
           "twofluid/PM4Sand | Youd median [m] |", "|---|---|---|---|---|---|---|"]
    for lab in dict.fromkeys(r[0] for r in runs):
        mine = {pol: (tf, pm) for lb, pol, tf, pm in runs if lb == lab}
        tf_u = [mine[k][0]["u_end"] for k in (1, -1) if k in mine]
        pm_u = [mine[k][1]["u_end"] for k in (1, -1) if k in mine]
        ratio = np.mean(tf_u) / np.mean(pm_u) if np.mean(pm_u) != 0.0 else float("nan")
        youd = next((mine[k][0]["youd"] for k in mine if mine[k][0]["youd"]), None)
        out.append(f"| {lab} | {' / '.join(f'{u:.3f}' for u in tf_u)} | {' / '.join(f'{u:.3f}' for u in pm_u)} | "
                   f"{np.mean(tf_u):.3f} | {np.mean(pm_u):.3f} | {ratio:.2f} | "
                   + ("-" if youd is None else f"{youd:.2f}") + " |")
    out += ["", "| run | model | liquefied while shaking [m] | largest residual strain [%] (depth) | surface PGA [g] | "
            "Sa 0.2 / 0.5 / 1 s [g] | settlement [cm] |", "|---|---|---|---|---|---|---|"]
    for lab, pol, tf, pm in runs:
        for name, r in (("twofluid", tf), ("PM4Sand", pm)):
            rng = "none" if not r["liquefied"] else f"{r['liquefied'][0]:g}–{r['liquefied'][1]:g}"
            g = "-" if r["gamma_res"] is None else f"{100 * r['gamma_res']:.2f} ({r['gamma_res_z']:g} m)"
            st = (f"{100 * r['settle_shaking']:.2f} end of shaking, {100 * r['settle_end']:.2f} reconsolidated"
                  if name == "twofluid" else f"{100 * r['settle_end']:.2f} at {r['end_s']:.1f} s")
            out.append(f"| {lab} {pol:+d} | {name} | {rng} | {g} | {r['pga']:.3f} | "
                       f"{' / '.join(f'{v:.3f}' for v in r['sa'].values())} | {st} |")
    times = (5.0, 10.0, 15.0, 20.0)
    out += ["", "| run | model | surface displacement [m] at " + " / ".join(f"{t:g}" for t in times)
            + " s | end of shaking | end (t [s]) |", "|---|---|---|---|---|"]
    for lab, pol, tf, pm in runs:
        for name, r in (("twofluid", tf), ("PM4Sand", pm)):
            if r["history"] is None:
                continue
            t, u = r["history"]
            at = [f"{np.interp(x, t, u):.3f}" if x <= t[-1] else "-" for x in times]
            out.append(f"| {lab} {pol:+d} | {name} | {' / '.join(at)} | {r['u_shaking']:.3f} | "
                       f"{r['u_end']:.3f} ({t[-1]:.1f}) |")
    return "\n".join(out)


def advance(t_stop, dt, stats, halvings=4):
    """The shaking's time stepping: the peer's ``run_until`` (batches of Newton steps), except that a
    step Newton fails is first redone as two half steps with Newton, down to dt/2^halvings, and only
    then handed to the peer's ``recover`` (other algorithms). A run without a failed step is the same
    as the peer's. Where a step failed in the idealised columns at dt = 5 ms, neither scheme got past
    it in minutes: one trial step then runs inside PM4Sand's own strain-increment sub-stepping (a
    profiler's stack) for minutes; a smaller dt from the start is the remedy used."""
    def step(h, level):
        if ops.analyze(1, h) == 0:
            stats.steps += 1
            return
        stats.failures += 1
        stats.fail_times.append(ops.getTime())
        if level >= halvings:
            peer.recover(h, stats)
            return
        stats.substeps += 1
        stats.smallest_dt = 0.5 * h if stats.smallest_dt is None else min(stats.smallest_dt, 0.5 * h)
        step(0.5 * h, level + 1)
        step(0.5 * h, level + 1)

    while True:
        t0 = ops.getTime()
        remaining = t_stop - t0
        if remaining <= 1e-9:
            return
        n = int(math.floor(remaining / dt + 1e-6))
        h = dt if n > 0 else remaining
        ok = ops.analyze(max(n, 1), h)
        stats.steps += int(round((ops.getTime() - t0) / h))
        if ok != 0:
            stats.failures += 1
            stats.fail_times.append(ops.getTime())
            stats.substeps += 1
            step(0.5 * h, 1)
            step(0.5 * h, 1)


if __name__ == "__main__":
    main()
