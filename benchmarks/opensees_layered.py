"""The bundled layered site (``liquefaction-layered-site``) in OpenSees: PDMY02 u-p column, nearly undrained.

An independent effective-stress model of the same site as twofluid's bundled case, to see whether an
established model liquefies the loose sand from its base up and then isolates the sand above it
(docs/liquefaction.md, "Why the band isolates the sand above it"; docs/benchmarks.md, "The layered
site against OpenSees (PDMY02), nearly undrained").

The model follows the project's OpenSees peer (``../shared/peers/opensees/column.py``: SSPquadUP
u-p elements, PressureDependMultiYield02, a gravity stage elastic then plastic with a large
permeability, the real permeability set afterwards, periodic sides by equalDOF, Newmark
gamma = 0.6, failed steps redone by the peer's ``recover``), changed only where the site differs:

* geometry and elements of the case file: crust 0-2 m (0.5 m elements), loose sand 2-8 m (0.25 m),
  dense sand 8-15 m (0.5 m); the column is 0.5 m wide;
* water table at 2 m: the pore pressure is fixed at 0 at every node at or above it, so the crust is
  drained (no excess pore pressure) and the loose sand drains through its top;
* the crust: PDMY02 with the material documentation's suggested set for Dr = 40 % (its
  G_r = 90 MPa at 101 kPa is the case's K2max = 40: 218.8 * 40 * sqrt(101) kPa = 88 MPa) and the
  case's mass density 18 kN/m3 / g; with p fixed it is a drained, total = effective stress layer;
* the loose sand: the documentation's suggested set nearest Dr = 47 %, Dr = 50 % (``--loose-set
  40`` for the Dr = 40 % set, to bracket); the dense sand: the Dr = 75 % set (the case: 80 %);
  in both the saturated mass density and the void ratio are the case's (n = 0.44 and 0.38,
  particle density 2650 kg/m3: 1.924 and 2.023 Mg/m3, e = 0.786 and 0.613), the rest as documented;
  no parameter is fitted to anything;
* base: impervious (no flux), fixed vertically; ``--base compliant`` (the case's): elastic bedrock,
  2400 kg/m3, V_s 760 m/s, a Lysmer-Kuhlemeyer dashpot c = rho_r V_r A (a zeroLength viscous
  element to a fixed node) and the outcrop record entered as the equivalent force c A v_o(t) at the
  base node (``--input force``, the usual OpenSees practice; v_o by the trapezoidal rule from the
  scaled record) or, equivalently up to the Rayleigh mass term, as a uniform excitation with the
  outcrop acceleration and the dashpot on the relative velocity (``--input relative``, twofluid's
  formulation); ``--base rigid``: base fixed, uniform excitation with the record;
* Rayleigh damping of the case: 1 % at 1 and 10 Hz, stiffness part on the current tangent (the
  peer's choice);
* the case's record (El Centro 1940 N-S, array #9, 180 deg), first 10 s, scaled to ``--pga``;
  the analysis stops with the shaking (t = 10 s).

k is in m/s; the u-p element takes k / gamma_w (gamma_w = rho_w g = 9.80665 kN/m3), as the peer.

Outputs (printed, and ``profile.csv`` / ``summary.json`` in ``--out``): the gravity stage's check
(nodal pore pressure against hydrostatic, sigma'_v0 against the hand calculation), per element:
sigma'_v0, peak r_u (excess pore pressure, the mean of the four nodes' pressures less the hydrostatic
pressure at the centre, over sigma'_v0), time of first r_u > 0.95, peak |gamma| (relative horizontal
displacement of the element's nodes over its height), peak |tau_xy| / sigma'_v0 before and after the
first element liquefies; the liquefied range (elements with r_u > 0.95 during the shaking), the surface
PGA (absolute acceleration of the surface node, raw) and the surface settlement at t = 10 s.

    python benchmarks/opensees_layered.py --pga 0.15 --k 1e-6 [--base compliant|rigid]
        [--input force|relative] [--loose-set 50|40] [--loose-refine 0.5] [--dt 0.005] [--out DIR] [--json]
    python benchmarks/opensees_layered.py --dss 0.1,0.12,0.15,0.2 [--loose-set 50|40]

``--dss`` runs, instead of the site, undrained cyclic simple shear of the loose sand's set (one
element, sigma'_v 100 kPa): the cycles to r_u >= 0.98 or |gamma| >= 3 % at each CSR, to set the
PDMY02 triggering beside the Idriss-Boulanger CRR that twofluid is calibrated to.

Needs openseespy (``pip install -e '.[bench]'``); 5-10 s of one core per site run at dt = 5 ms.
"""
from __future__ import annotations

import argparse
import importlib.util
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
from bench_peers import MOTION, PEERS  # noqa: E402

_spec = importlib.util.spec_from_file_location("peer_column", PEERS / "opensees" / "column.py")
peer = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(peer)
ops = peer.ops

G_ACC = 9.80665        # m/s2
RHO_W = 1.0            # Mg/m3
GAMMA_W = RHO_W * G_ACC  # kN/m3
K_FLUID = 2.2e6        # kPa
RHO_S = 2.65           # Mg/m3, particle density (case: 2650 kg/m3)

# PressureDependMultiYield02: the suggested parameter sets of the material's documentation
# (OpenSees wiki, "PressureDependMultiYield02 Material"), common part and per relative density.
COMMON = dict(gmax=0.1, pr=101.0, d=0.5, nsurf=20, contrac2=5.0, dilat2=3.0, liquefac1=1.0,
              liquefac2=0.0, cs1=0.9, cs2=0.02, cs3=0.7, pa=101.0, c=0.1)
SETS = {
    40: dict(rho=1.8, Gr=9.0e4, Br=2.2e5, phi=32.0, phiPT=26.0, contrac1=0.067, contrac3=0.23,
             dilat1=0.06, dilat3=0.27, e=0.77),
    50: dict(rho=1.9, Gr=1.0e5, Br=2.33e5, phi=33.5, phiPT=25.5, contrac1=0.045, contrac3=0.15,
             dilat1=0.06, dilat3=0.15, e=0.70),
    75: dict(rho=2.1, Gr=1.3e5, Br=2.6e5, phi=36.5, phiPT=26.0, contrac1=0.013, contrac3=0.0,
             dilat1=0.3, dilat3=0.0, e=0.55),
}

# The case (src/twofluid/data/cases/liquefaction-layered-site/case.toml).
WATER_TABLE = 2.0
LAYERS = [  # name, thickness, element size, set, mass density (Mg/m3), void ratio (None: the set's)
    ("crust", 2.0, 0.5, 40, 18.0 / G_ACC, None),
    ("loose sand", 6.0, 0.25, 50, (1 - 0.44) * RHO_S + 0.44 * RHO_W, 0.44 / 0.56),
    ("dense sand", 7.0, 0.5, 75, (1 - 0.38) * RHO_S + 0.38 * RHO_W, 0.38 / 0.62),
]
BEDROCK_RHO, BEDROCK_VS = 2.4, 760.0   # Mg/m3, m/s
DAMPING, DAMP_F = 0.01, (1.0, 10.0)
DURATION = 10.0
WIDTH = 0.5


def parse_args(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--pga", type=float, default=0.15, help="peak of the (outcrop) record [g]")
    p.add_argument("--k", type=float, default=1e-6, help="hydraulic conductivity of both sands [m/s]")
    p.add_argument("--base", choices=("compliant", "rigid"), default="compliant")
    p.add_argument("--input", choices=("force", "relative"), default="force",
                   help="compliant base: outcrop velocity as a base force, or outcrop acceleration as a uniform excitation")
    p.add_argument("--loose-set", type=int, choices=(40, 50), default=50,
                   help="PDMY02 suggested set of the loose sand (Dr %%)")
    p.add_argument("--loose-refine", type=float, default=1.0,
                   help="factor on the loose sand's element size (0.5 halves its elements)")
    p.add_argument("--dt", type=float, default=0.005, help="time step of the shaking [s]")
    p.add_argument("--tol", type=float, default=1e-4, help="NormDispIncr tolerance (the peer's)")
    p.add_argument("--out", default=None, help="folder for profile.csv and summary.json")
    p.add_argument("--json", action="store_true", help="print the summary as JSON too")
    p.add_argument("--dss", default=None, metavar="CSR[,CSR...]",
                   help="instead of the site: undrained cyclic simple shear of the loose sand's set (one element, "
                        "sigma'_v 100 kPa, K0 from the elastic stage, uniform cycles at 1 Hz): cycles to r_u >= 0.98 "
                        "or |gamma| >= 3 %% at each CSR")
    return p.parse_args(argv)



def up_mesh(y, node_depth, water_table, c_dash, compliant=True):
    """The u-p column's nodes (two a level, ``WIDTH`` apart, at heights ``y``, bottom first), its
    periodic sides (equalDOF), the pressure fixed at the nodes at or above the water table
    (``node_depth`` [m] from the surface) and the base: on a compliant base a Lysmer dashpot
    ``c_dash`` [kN s/m] to a fixed node (2 nele + 101), else fixed horizontally."""
    nele = len(y) - 1
    ops.wipe()
    ops.model("basic", "-ndm", 2, "-ndf", 3)
    for j in range(nele + 1):
        ops.node(2 * j + 1, 0.0, y[j])
        ops.node(2 * j + 2, WIDTH, y[j])
    if compliant:
        ops.fix(1, 0, 1, 0)
        ops.fix(2, 0, 1, 0)
        ops.equalDOF(1, 2, 1)
    else:
        ops.fix(1, 1, 1, 0)
        ops.fix(2, 1, 1, 0)
    for j in range(1, nele + 1):
        ops.equalDOF(2 * j + 1, 2 * j + 2, 1, 2)
    for j in range(nele + 1):
        if node_depth[j] <= water_table + 1e-9:          # at or above the water table: p = 0
            ops.fix(2 * j + 1, 0, 0, 1)
            ops.fix(2 * j + 2, 0, 0, 1)
    if compliant:
        dash = 2 * nele + 101
        ops.node(dash, 0.0, 0.0)
        ops.fix(dash, 1, 1, 1)
        ops.uniaxialMaterial("Viscous", 100, c_dash, 1.0)
        ops.element("zeroLength", 10000, dash, 1, "-mat", 100, "-dir", 1)


def elastic_gravity(n_materials):
    """The first gravity stage: every material elastic (stage 0), ten steps of 500 in the static
    transient analysis (:func:`_static_transient` at 1e-6), then every material switched to its
    plastic stage (1); returns the peer's step statistics to go on with."""
    stats = peer.Stats()
    for i in range(n_materials):
        ops.updateMaterialStage("-material", i + 1, "-stage", 0)
    _static_transient(1.0e-6)
    peer.run_until(10 * 500.0, 500.0, stats)
    for i in range(n_materials):
        ops.updateMaterialStage("-material", i + 1, "-stage", 1)
    return stats


def dynamic_transient(tol):
    """The transient analysis of the shaking: Newton on NormDispIncr ``tol`` (30 iterations),
    Newmark with γ = 0.6 and β = (γ + 1/2)²/4 (numerical damping of the highest modes, as the peer),
    a banded solver."""
    ops.constraints("Transformation")
    ops.numberer("RCM")
    ops.system("BandGeneral")
    ops.test("NormDispIncr", tol, 30, 0)
    ops.algorithm("Newton")
    ops.integrator("Newmark", 0.6, 0.25 * 1.1 ** 2)
    ops.analysis("Transient")


def _static_transient(tol):
    """The transient analysis of the gravity stages: Newton on NormDispIncr ``tol`` (50 iterations),
    Newmark's average acceleration (no numerical damping), a banded solver."""
    ops.constraints("Transformation")
    ops.numberer("RCM")
    ops.system("BandGeneral")
    ops.test("NormDispIncr", tol, 50, 0)
    ops.algorithm("Newton")
    ops.integrator("Newmark", 0.5, 0.25)
    ops.analysis("Transient")

def dss(csr: float, dr: int, sigma_v: float = 100.0, freq: float = 1.0, n_max: float = 100.0) -> dict:
    """Cycles of uniform stress-controlled undrained simple shear to r_u >= 0.98 or |gamma| >= 3 %.

    r_u = 1 - sigma'_v / sigma'_v0 (the element's effective stress). The top nodes keep p = 0 (with
    k = 1e-12 m/s no water flows; the one-point element's pressure is the mean of its nodes').

    One SSPquadUP element 1 m x 1 m, the set of Dr = ``dr`` % with the loose sand's density and void
    ratio, no body force; base fixed, top nodes tied (constant width: K0 loading), consolidated
    drained (pore pressure fixed at the top, large permeability) under ``sigma_v`` in the elastic
    stage, then plastic; then k = 1e-12 m/s (undrained in the test's duration) and a horizontal
    force csr * sigma_v sin(2 pi f t) on the top.
    """
    s = dict(COMMON, **SETS[dr])
    s["rho"], s["e"] = LAYERS[1][4], LAYERS[1][5]
    ops.wipe()
    ops.model("basic", "-ndm", 2, "-ndf", 3)
    for tag, x, yy in ((1, 0.0, 0.0), (2, 1.0, 0.0), (3, 1.0, 1.0), (4, 0.0, 1.0)):
        ops.node(tag, x, yy)
    ops.fix(1, 1, 1, 0)
    ops.fix(2, 1, 1, 0)
    ops.fix(3, 0, 0, 1)
    ops.fix(4, 0, 0, 1)
    ops.equalDOF(3, 4, 1, 2)
    ops.nDMaterial("PressureDependMultiYield02", 1, 2, s["rho"], s["Gr"], s["Br"], s["phi"], s["gmax"], s["pr"],
                   s["d"], s["phiPT"], s["contrac1"], s["contrac3"], s["dilat1"], s["dilat3"], s["nsurf"],
                   s["contrac2"], s["dilat2"], s["liquefac1"], s["liquefac2"], s["e"], s["cs1"], s["cs2"], s["cs3"],
                   s["pa"], s["c"])
    g_e = s["Gr"] * (sigma_v / s["pr"]) ** s["d"]
    b_e = s["Br"] * (sigma_v / s["pr"]) ** s["d"]
    ops.element("SSPquadUP", 1, 1, 2, 3, 4, 1, 1.0, K_FLUID, RHO_W, 1.0 / GAMMA_W, 1.0 / GAMMA_W, s["e"],
                0.25 / (b_e + 4.0 * g_e / 3.0), 0.0, 0.0)
    ops.timeSeries("Linear", 1, "-factor", 1.0)
    ops.pattern("Plain", 1, 1)
    ops.load(3, 0.0, -0.5 * sigma_v, 0.0)
    ops.load(4, 0.0, -0.5 * sigma_v, 0.0)
    ops.updateMaterialStage("-material", 1, "-stage", 0)
    _static_transient(1.0e-8)
    ops.analyze(100, 0.01)                  # ramp to sigma_v over 1 s
    ops.loadConst("-time", 0.0)
    ops.analyze(50, 10.0)                   # drain
    ops.updateMaterialStage("-material", 1, "-stage", 1)
    ops.analyze(50, 10.0)
    ops.setParameter("-val", 1e-12 / GAMMA_W, "-ele", 1, "hPerm")
    ops.setParameter("-val", 1e-12 / GAMMA_W, "-ele", 1, "vPerm")
    sig0 = ops.eleResponse(1, "stress")
    ux0 = ops.nodeDisp(3, 1)
    ops.setTime(0.0)
    ops.timeSeries("Trig", 2, 0.0, 1e6, 1.0 / freq, "-factor", csr * sigma_v)
    ops.pattern("Plain", 2, 2)
    ops.load(3, 1.0, 0.0, 0.0)             # node 4 is tied to 3: the whole top carries tau
    ops.test("NormDispIncr", 1.0e-6, 50, 0)
    dt = 1.0 / freq / 200.0
    n = None
    ru = gam = 0.0
    while ops.getTime() < n_max / freq:
        if ops.analyze(1, dt) != 0:
            n = ops.getTime() * freq
            break
        ru = max(ru, 1.0 - ops.eleResponse(1, "stress")[1] / sig0[1])
        gam = max(gam, abs(ops.nodeDisp(3, 1) - ux0))
        if ru >= 0.98 or gam >= 0.03:
            n = ops.getTime() * freq
            break
    ops.wipe()
    return dict(csr=csr, dr=dr, cycles=n, ru=ru, gamma=gam, K0=sig0[0] / sig0[1])


def build_mesh(layers):
    """Element heights and layer index from the base up; node elevations."""
    h, lay = [], []
    for i, (_, thick, size, *_rest) in enumerate(layers):
        n = int(round(thick / size))
        h += [thick / n] * n
        lay += [i] * n
    h, lay = np.array(h[::-1]), np.array(lay[::-1])   # base first
    y = np.concatenate([[0.0], np.cumsum(h)])
    return h, lay, y


def hand_sigma_v(z):
    """sigma'_v [kPa] at depth z [m] from the layers' unit weights and the water table."""
    s, top = 0.0, 0.0
    for _, thick, _, _, rho, _ in LAYERS:
        bot = top + thick
        dz = max(0.0, min(z, bot) - top)
        s += rho * G_ACC * dz
        top = bot
    return s - GAMMA_W * max(0.0, z - WATER_TABLE)


def main(argv=None):
    a = parse_args(argv)
    if a.dss:
        res = [dss(float(c), a.loose_set) for c in a.dss.split(",")]
        for r in res:
            print(f"DSS, PDMY02 Dr {r['dr']} % set, sigma'_v 100 kPa, K0 {r['K0']:.2f}: CSR {r['csr']:.3f} -> "
                  f"{'> 100' if r['cycles'] is None else '%.2f' % r['cycles']} cycles (r_u {r['ru']:.2f}, "
                  f"|gamma| {100 * r['gamma']:.2f} %)")
        return res
    t_start = time.perf_counter()
    layers = [list(la) for la in LAYERS]
    layers[1][3] = a.loose_set
    layers[1][2] *= a.loose_refine
    h, lay, y = build_mesh(layers)
    nele = h.size
    depth_total = y[-1]
    zc = depth_total - 0.5 * (y[1:] + y[:-1])          # element centre depths
    yn_depth = depth_total - y                          # node depths
    sat = zc > WATER_TABLE

    dt_gm, gm = peer.read_at2(str(MOTION))
    n_gm = int(round(DURATION / dt_gm)) + 1
    rec = gm[:n_gm]
    acc = rec * (a.pga / np.max(np.abs(rec))) * G_ACC   # m/s2, first 10 s scaled to --pga
    vel = np.concatenate([[0.0], np.cumsum(0.5 * (acc[1:] + acc[:-1]) * dt_gm)])

    # material parameters and stabilisation
    mats = []
    for name, _, _, dr, rho, e in layers:
        s = dict(COMMON, **SETS[dr])
        s["rho"] = rho
        if e is not None:
            s["e"] = e
        mats.append(s)
    sv_est = np.array([hand_sigma_v(z) for z in zc])
    alpha = np.zeros(nele)
    for j in range(nele):
        s = mats[lay[j]]
        nu = (3 * s["Br"] - 2 * s["Gr"]) / (2 * (3 * s["Br"] + s["Gr"]))
        k0 = nu / (1 - nu)
        p_est = max(sv_est[j] * (1 + 2 * k0) / 3.0, 1.0)
        g_e = s["Gr"] * (p_est / s["pr"]) ** s["d"]
        b_e = s["Br"] * (p_est / s["pr"]) ** s["d"]
        alpha[j] = 0.25 * h[j] ** 2 / (b_e + 4.0 * g_e / 3.0)

    perm = a.k / GAMMA_W
    perm_gravity = 1.0 / GAMMA_W

    # ------------------------------------------------------------------ model
    compliant = a.base == "compliant"
    c_dash = BEDROCK_RHO * BEDROCK_VS * WIDTH          # kN s/m per metre of thickness
    up_mesh(y, yn_depth, WATER_TABLE, c_dash, compliant)

    for i, s in enumerate(mats):
        ops.nDMaterial("PressureDependMultiYield02", i + 1, 2, s["rho"], s["Gr"], s["Br"], s["phi"],
                       s["gmax"], s["pr"], s["d"], s["phiPT"], s["contrac1"], s["contrac3"],
                       s["dilat1"], s["dilat3"], s["nsurf"], s["contrac2"], s["dilat2"],
                       s["liquefac1"], s["liquefac2"], s["e"], s["cs1"], s["cs2"], s["cs3"],
                       s["pa"], s["c"])
    for j in range(nele):
        s = mats[lay[j]]
        ops.element("SSPquadUP", j + 1, 2 * j + 1, 2 * j + 2, 2 * j + 4, 2 * j + 3, int(lay[j]) + 1,
                    1.0, K_FLUID, RHO_W, perm_gravity, perm_gravity, s["e"], float(alpha[j]), 0.0, -G_ACC)

    # ---------------------------------------------------------------- gravity
    g_stats = elastic_gravity(len(mats))
    peer.run_until(20 * 500.0, 500.0, g_stats)
    ops.setParameter("-val", perm, "-eleRange", 1, nele, "hPerm")
    ops.setParameter("-val", perm, "-eleRange", 1, nele, "vPerm")

    nodes_l = [2 * j + 1 for j in range(nele + 1)]
    nodes_r = [2 * j + 2 for j in range(nele + 1)]
    p_hyd_node = GAMMA_W * np.maximum(yn_depth - WATER_TABLE, 0.0)
    p0 = np.array([ops.nodeVel(n, 3) for n in nodes_l])
    sig = np.array([ops.eleResponse(e, "stress") for e in range(1, nele + 1)])
    sv0 = -sig[:, 1]
    sh0 = -sig[:, 0]
    p_hyd_ele = GAMMA_W * np.maximum(zc - WATER_TABLE, 0.0)
    top = nodes_l[-1]
    uy0 = ops.nodeDisp(top, 2)
    ux0 = np.array([ops.nodeDisp(n, 1) for n in nodes_l])
    gravity = dict(max_p_error_kPa=float(np.max(np.abs(p0 - p_hyd_node))),
                   checks=[dict(depth_m=float(zc[j]), sigma_v0_kPa=float(sv0[j]), hand_kPa=float(hand_sigma_v(zc[j])),
                                K0=float(sh0[j] / sv0[j])) for j in
                           sorted({int(np.argmin(np.abs(zc - z))) for z in (1.25, 2.125, 5.0, 7.875, 11.75, 14.75)},
                                  key=lambda j: zc[j])])

    # ---------------------------------------------------------------- shaking
    ops.setTime(0.0)
    ops.wipeAnalysis()
    if compliant and a.input == "force":
        ops.timeSeries("Path", 2, "-dt", dt_gm, "-values", *vel.tolist(), "-factor", c_dash)
        ops.pattern("Plain", 2, 2)
        ops.load(1, 1.0, 0.0, 0.0)
        acc_ts = []
    else:
        ops.timeSeries("Path", 2, "-dt", dt_gm, "-values", *acc.tolist())
        ops.pattern("UniformExcitation", 2, 1, "-accel", 2)
        acc_ts = ["-timeSeries", 2]                      # absolute = relative + record
    w1, w2 = 2 * math.pi * DAMP_F[0], 2 * math.pi * DAMP_F[1]
    ops.rayleigh(2 * DAMPING * w1 * w2 / (w1 + w2), 2 * DAMPING / (w1 + w2), 0.0, 0.0)

    work = Path(tempfile.mkdtemp(prefix="os_layered_"))
    f_pp, f_ux, f_acc, f_uy, f_sig = (str(work / n) for n in ("pp", "ux", "acc", "uy", "sig"))
    ops.recorder("Node", "-file", f_pp, "-time", "-node", *(nodes_l + nodes_r), "-dof", 3, "vel")
    ops.recorder("Node", "-file", f_ux, "-time", "-node", *nodes_l, "-dof", 1, "disp")
    ops.recorder("Node", "-file", f_uy, "-time", "-node", top, "-dof", 2, "disp")
    ops.recorder("Node", "-file", f_acc, "-time", *acc_ts, "-node", top, "-dof", 1, "accel")
    ops.recorder("Element", "-file", f_sig, "-time", "-eleRange", 1, nele, "stress")

    dynamic_transient(a.tol)
    ops.record()
    d_stats = peer.Stats()
    t_d0 = time.perf_counter()
    peer.run_until(DURATION, a.dt, d_stats)
    wall_dyn = time.perf_counter() - t_d0
    ops.remove("recorders")
    ops.wipe()

    # ------------------------------------------------------------ post-process
    pp = np.loadtxt(f_pp, ndmin=2)
    t = pp[:, 0]
    pl, pr_ = pp[:, 1:nele + 2], pp[:, nele + 2:2 * nele + 3]
    p_ele = 0.25 * (pl[:, :-1] + pl[:, 1:] + pr_[:, :-1] + pr_[:, 1:])
    ru = np.where(sat[None, :], (p_ele - p_hyd_ele[None, :]) / sv0[None, :], 0.0)
    ux = np.loadtxt(f_ux, ndmin=2)[:, 1:] - ux0[None, :]
    gam = (ux[:, 1:] - ux[:, :-1]) / h[None, :]
    uy = np.loadtxt(f_uy, ndmin=2)
    settlement = float(-(uy[-1, 1] - uy0))
    acc_s = np.loadtxt(f_acc, ndmin=2)
    pga_surf = float(np.max(np.abs(acc_s[:, 1])) / G_ACC)
    sg = np.loadtxt(f_sig, ndmin=2)[:, 1:].reshape(len(t), nele, -1)
    tau = sg[:, :, 3]                                    # PDMY02 plane strain: sxx, syy, szz, txy, (ratio)
    for f in (f_pp, f_ux, f_acc, f_uy, f_sig):
        os.remove(f)
    os.rmdir(work)

    ru_max = ru.max(axis=0)
    liq = ru > 0.95
    t_liq = np.array([t[np.argmax(liq[:, j])] if liq[:, j].any() else np.nan for j in range(nele)])
    t_first = float(np.nanmin(t_liq)) if np.isfinite(t_liq).any() else None
    before = t <= (t_first if t_first is not None else t[-1])
    ru_at_first = ru[np.argmax(t >= t_first)] if t_first is not None else ru_max
    sr_before = np.abs(tau[before]).max(axis=0) / sv0
    sr_after = np.abs(tau[~before]).max(axis=0) / sv0 if (~before).any() else np.full(nele, np.nan)
    gmax = np.abs(gam).max(axis=0)
    liq_el = [j for j in range(nele) if np.isfinite(t_liq[j])]
    rng = None
    if liq_el:
        rng = [float(min(zc[j] - 0.5 * h[j] for j in liq_el)), float(max(zc[j] + 0.5 * h[j] for j in liq_el))]
    thick = float(sum(h[j] for j in liq_el))
    shallow = [j for j in range(nele) if lay[j] == 1 and zc[j] < 5.0]

    prof = []
    for j in range(nele - 1, -1, -1):
        prof.append(dict(depth_m=round(float(zc[j]), 4), layer=layers[lay[j]][0], sigma_v0_kPa=float(sv0[j]),
                         ru_max=float(ru_max[j]) if sat[j] else None,
                         t_first_ru_095_s=None if np.isnan(t_liq[j]) else float(t_liq[j]),
                         ru_at_first_liquefaction=float(ru_at_first[j]) if sat[j] else None,
                         peak_shear_strain=float(gmax[j]), tau_ratio_before=float(sr_before[j]),
                         tau_ratio_after=float(sr_after[j])))
    summary = dict(
        pga_g=a.pga, k_m_s=a.k, base=a.base, input=a.input if compliant else "uniform (within)",
        loose_set_Dr=a.loose_set, dt_s=a.dt, gravity=gravity, first_liquefaction_s=t_first,
        liquefied_range_m=rng, liquefied_thickness_m=thick,
        liquefied_elements_m=[float(zc[j]) for j in sorted(liq_el, key=lambda j: zc[j])],
        ru_max_shallow_loose=float(ru_max[shallow].max()), ru_min_shallow_loose=float(ru_max[shallow].min()),
        surface_pga_g=pga_surf, settlement_end_of_shaking_m=settlement, peak_shear_strain=float(gmax.max()),
        steps=d_stats.steps, failed_solves=d_stats.failures, retries=d_stats.retries, cut_steps=d_stats.substeps,
        first_failure_s=d_stats.fail_times[0] if d_stats.fail_times else None,
        wall_dynamic_s=wall_dyn, wall_total_s=time.perf_counter() - t_start, profile=prof)

    # ------------------------------------------------------------------ report
    print(f"=== OpenSees PDMY02 layered site: PGA {a.pga:g} g, k = {a.k:g} m/s, base {a.base}"
          f"{' (' + a.input + ')' if compliant else ''}, loose sand Dr {a.loose_set} % set, dt {a.dt:g} s ===")
    print(f"gravity: max |p - hydrostatic| at the nodes {gravity['max_p_error_kPa']:.3g} kPa; sigma'_v0 (OpenSees / hand):",
          "; ".join(f"{c['depth_m']:.3g} m {c['sigma_v0_kPa']:.2f}/{c['hand_kPa']:.2f} kPa (K0 {c['K0']:.2f})"
                    for c in gravity["checks"]))
    print(f"shaking: {d_stats.steps} steps, {wall_dyn:.1f} s wall, {d_stats.failures} failed solves"
          f"{' (first at %.3f s)' % d_stats.fail_times[0] if d_stats.fail_times else ''}, {d_stats.retries} retried, "
          f"{d_stats.substeps} cut")
    print("| depth [m] | layer | sigma'_v0 [kPa] | r_u at first liq. | peak r_u | r_u > 0.95 at [s] | peak |gamma| [%] | "
          "|tau|/sigma'_v0 before / after first liq. |")
    print("|---|---|---|---|---|---|---|---|")
    for r in prof:
        if r["layer"] == "crust":
            continue
        print(f"| {r['depth_m']:.3f} | {r['layer']} | {r['sigma_v0_kPa']:.1f} | {r['ru_at_first_liquefaction']:.2f} | "
              f"{r['ru_max']:.2f} | "
              f"{'-' if r['t_first_ru_095_s'] is None else '%.2f' % r['t_first_ru_095_s']} | "
              f"{100 * r['peak_shear_strain']:.2f} | {r['tau_ratio_before']:.3f} / {r['tau_ratio_after']:.3f} |")
    print(f"first r_u > 0.95: {'none' if t_first is None else '%.2f s' % t_first}; liquefied (during shaking): "
          f"{'none' if rng is None else '%.3g m in %g-%g m' % (thick, rng[0], rng[1])}; peak r_u of the loose sand "
          f"above 5 m {summary['ru_min_shallow_loose']:.2f}-{summary['ru_max_shallow_loose']:.2f}; peak strain "
          f"{100 * summary['peak_shear_strain']:.2f} %; surface PGA (raw) {pga_surf:.3f} g; settlement at t = 10 s "
          f"{100 * settlement:.2f} cm; total wall {summary['wall_total_s']:.1f} s")
    if a.out:
        out = Path(a.out)
        out.mkdir(parents=True, exist_ok=True)
        (out / "summary.json").write_text(json.dumps(summary, indent=1))
        with open(out / "profile.csv", "w") as f:
            f.write(",".join(prof[0]) + "\n")
            for r in prof:
                f.write(",".join("" if v is None else str(v) for v in r.values()) + "\n")
    if a.out:
        np.savetxt(Path(a.out) / "ru.csv", np.column_stack([t, ru[:, ::-1]]), delimiter=",", fmt="%.5g",
                   header="time_s," + ",".join("ru_z%.3f" % z for z in zc[::-1]), comments="")
    if a.json:
        print(json.dumps({k: v for k, v in summary.items() if k != "profile"}))
    return summary


if __name__ == "__main__":
    main()
