"""The bundled layered site under the determinacy criteria of the liquefaction issue, measured (not timed).

Runs ``liquefaction-layered-site`` (El Centro as the outcrop motion, k = 1e-4 m/s as shipped, every
run to dissipation) and prints, per run: the liquefied thickness and range (r_u > 0.95 reached while
the shear wave runs), the peak shear strain (largest |γ| of any element at the vertical steps'
ends), the settlement at the end, the surface PGA raw and low-passed (15 Hz) and Sa(0.05 s) and
Sa(0.1 s) of the surface motion (5 % damping, the sub-step history). Then each criterion against
its reference run:

* ``sweep``: PGA 0.05-0.4 g as shipped (settlement and liquefied thickness non-decreasing);
* ``mesh``: the loose layer's elements halved (peak strain within 25 %) at 0.15 and 0.2 g;
* ``steps``: the vertical and shear steps halved (surface PGA and Sa(0.05 s) within 5 %);
* ``viscosity``: the liquefied-soil viscosity 0 and 1e4 Pa s against 1e3 (settlement and liquefied
  thickness within 20 %);
* ``undrained``: k = 1e-6 m/s (the simplified procedure's FS < 0.8 zone with the total-stress
  run's a_max, and the settlement against Ishihara-Yoshimine);
* ``isolation`` (not in the default set): the shaking of the site (k = 1e-6 m/s, or ``--k``) beside its total-stress
  companion (the same column without pore-pressure generation), per element of the loose sand: peak
  r_u, the time r_u passes 0.95, and the peak stress ratio |tau|/sigma'_v0 of both runs before the
  first element liquefies and after it, beside the element's CRR and CRR 30^b, the stress ratio of
  a single half cycle that liquefies it (D = 1 from one half cycle: N_L = 1/2).

    python scripts/layered_determinacy.py [sweep] [mesh] [steps] [viscosity] [undrained] [isolation]
        [--pga=0.15,0.2] [--k=1e-6] [--set=gamma_dilation=0.02,gamma_d0=0.001] [--b-min=0.34] [--sr-scale=1.5]

(the first five by default; about 1.5 min of CPU). ``--set`` overrides defaults of the hysteretic
law's parameters (:data:`twofluid.models.hysteretic_sand.DEFAULTS`) for every run, to measure what
a parameter does; ``--b-min`` raises the CSR-N slope b of every element to at least that value (the
CRR at 15 cycles kept) and ``--sr-scale`` scales the residual strength, diagnostics that are not
the shipped calibration. Numbers in docs/liquefaction.md, "The hysteretic model".
"""
from __future__ import annotations

import copy
import sys
import warnings

import numpy as np

from twofluid.casefile.loader import load_case
from twofluid.geotech.filtering import spectral_ordinates
from twofluid.runners.common import run_case

G = 9.80665


def run(pga: float, loose: float = 1.0, steps: float = 1.0, viscosity: float | None = None,
        k: float | None = None) -> dict:
    """Summary numbers of the layered site at ``pga`` [g], the loose layer's element size × ``loose``,
    both steps × ``steps``, the liquefied-soil viscosity of the sands [Pa s] and their k [m/s]."""
    case = load_case("liquefaction-layered-site")
    case["output"]["plots"] = False
    case["ground_motion"]["pga_g"] = pga
    case["layers"][1]["element_size"] *= loose
    case["time"]["step"] *= steps
    case["shear_wave"]["step"] *= steps
    for la in case["layers"][1:]:
        if viscosity is not None:
            la["viscosity"] = viscosity
        if k is not None:
            la["hydraulic_conductivity"] = k
    if k is not None and k < 1e-5:
        case["time"]["end"] = max(case["time"]["end"], 2e5)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = run_case(case)
    s = r.summary
    sa = spectral_ordinates(r.history["surface_t"], np.asarray(r.history["surface_acceleration_m_s2"]) / G,
                            periods=(0.05, 0.1))
    sp = s["simplified_procedure"]
    fs08 = _fs_zone(sp["table_run"], 0.8)
    return {"liq": s["liquefied_thickness_shaking_m"], "range": s["liquefied_depth_range_shaking_m"],
            "strain": max(la["peak_shear_strain"] for la in s["layers"]), "settle": s["settlement_end_m"],
            "pga": s["shaking"]["peak_surface_acceleration_g"],
            "pga_lp": s["shaking"]["peak_surface_acceleration_low_passed_g"], "sa05": sa[0.05], "sa10": sa[0.1],
            "iy_run": sp["settlement_run_m"], "iy_in": sp["settlement_input_m"], "fs08_run": fs08,
            "fs1_in": _fs_zone(sp["table_input"], 1.0), "fs12_run": _fs_zone(sp["table_run"], 1.2),
            "ts_lp": s["shaking"]["peak_surface_acceleration_total_stress_low_passed_g"], "status": s["status"]}


def isolation(pga: float, k: float = 1e-6) -> None:
    """Print the per-element comparison of the ``isolation`` mode (module docstring) at ``pga`` [g]."""
    from twofluid.closures import hysteretic as law
    from twofluid.runners.liquefaction import build_column

    case = load_case("liquefaction-layered-site")
    case["output"]["plots"] = False
    case["ground_motion"]["pga_g"] = pga
    for la in case["layers"][1:]:
        la["hydraulic_conductivity"] = k

    def shake(total_stress):
        c = copy.deepcopy(case)
        if total_stress:
            for la in c["layers"]:
                la["liquefiable"] = False
        b = build_column(c)
        col = b.column
        col.shear_only = total_stress
        t, tau, ru = [], [], []
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            for step in col.run(b.state, col.shear_end, b.dt, b.dt_after):
                sh = np.asarray(step.state.shear)
                t.append(step.state.t)
                tau.append(sh[:, law.S_TAU].copy())
                ru.append(np.asarray(col.excess_ratio(step.state)).copy())
        return col, np.array(t), np.array(tau), np.array(ru)

    col, t, tau, ru = shake(False)
    _, t2, tau2, _ = shake(True)
    par = col.hysteretic
    ns = ru.shape[1]  # saturated elements first, from the base up
    h = np.asarray(col.wave.h)
    z = np.concatenate([[0.0], np.cumsum(h)])
    depth = z[-1] - 0.5 * (z[1:] + z[:-1])
    loose = [e for e in range(ns) if par[e, law.P_LIQ] > 0.0 and depth[e] < 8.0]
    liq = ru > 0.95
    first = t[np.argmax(liq.any(axis=1))] if liq.any() else t[-1]
    print(f"\nisolation {pga:g} g, k = {k:g} m/s: first element liquefied at {first:.2f} s; peak |tau|/sigma'_v0 "
          "effective-stress / total-stress run, before and after it")
    print("| depth | CRR | CRR 30^b | peak r_u | r_u > 0.95 at | before: ES / TS | after: ES / TS | S_r/sigma'_v0 |")
    print("|---|---|---|---|---|---|---|---|")
    a, a2 = t <= first, t2 <= first  # before the first liquefaction, in each run

    def peak(x, m, e):
        return float(np.abs(x[m, e]).max() / par[e, law.P_SIG0]) if m.any() else float("nan")

    for e in sorted(loose, key=lambda i: depth[i]):
        tl = f"{t[np.argmax(liq[:, e])]:.2f} s" if liq[:, e].any() else "-"
        print(f"| {depth[e]:.2f} m | {par[e, law.P_CRR]:.3f} | {par[e, law.P_CRR] * 30.0 ** par[e, law.P_B]:.3f} | "
              f"{ru[:, e].max():.2f} | {tl} | {peak(tau, a, e):.3f} / {peak(tau2, a2, e):.3f} | "
              f"{peak(tau, ~a, e):.3f} / {peak(tau2, ~a2, e):.3f} | {par[e, law.P_SR] / par[e, law.P_SIG0]:.3f} |",
              flush=True)


def _derived(key, change) -> None:
    """Every element's correlated parameter ``key`` (:func:`twofluid.models.hysteretic_sand.derive`)
    passed through ``change``: a diagnostic, not the shipped calibration."""
    from twofluid.models import hysteretic_sand

    derive = hysteretic_sand.derive

    def changed(*args, **kw):
        out = derive(*args, **kw)
        out[key] = change(out[key])
        return out

    hysteretic_sand.derive = changed


def _fs_zone(table, limit):
    """[top, bottom] depth [m] of the rows of the simplified table with FS < ``limit`` (None: none)."""
    rows = [r for r in table if r["FS [-]"] < limit]
    if not rows:
        return None
    return [min(r["z_mid [m]"] - 0.5 * r["h [m]"] for r in rows), max(r["z_mid [m]"] + 0.5 * r["h [m]"] for r in rows)]


def row(label, m):
    rng = "none" if m["range"] is None else f"{m['range'][0]:g}-{m['range'][1]:g} m"
    print(f"| {label} | {m['liq']:.3g} m ({rng}) | {100 * m['strain']:.2f} % | {100 * m['settle']:.2f} cm | "
          f"{m['pga']:.3f} / {m['pga_lp']:.3f} g | {m['sa05']:.3f} g | {m['sa10']:.3f} g |", flush=True)


def change(a, b):
    return 100.0 * (b / a - 1.0) if a else float("nan")


def main(argv) -> None:
    what = [a for a in argv if not a.startswith("--")] or ["sweep", "mesh", "steps", "viscosity", "undrained"]
    pgas = [0.15, 0.2]
    for a in argv:
        if a.startswith("--pga="):
            pgas = [float(x) for x in a[6:].split(",")]
        if a.startswith("--set="):
            from twofluid.models import hysteretic_sand
            for kv in a[6:].split(","):
                key, val = kv.split("=")
                if key not in hysteretic_sand.DEFAULTS:
                    sys.exit(f"layered_determinacy: --set {key}: not one of {', '.join(hysteretic_sand.DEFAULTS)}")
                hysteretic_sand.DEFAULTS[key] = float(val)
    for a in argv:
        name, _, value = a.partition("=")
        if name == "--b-min":
            _derived("b", lambda b, x=float(value): max(b, x))
        elif name == "--sr-scale":
            _derived("residual_strength", lambda sr, x=float(value): sr * x)
    k_iso = 1e-6
    for a in argv:
        if a.startswith("--k="):
            k_iso = float(a[4:])
    if what == ["isolation"]:
        for pga in pgas:
            isolation(pga, k_iso)
        return
    print("| run | liquefied (shaking) | peak strain | settlement | surface PGA raw / 15 Hz | Sa(0.05 s) | Sa(0.1 s) |")
    print("|---|---|---|---|---|---|---|")
    base = {}
    if "sweep" in what:
        sweep = []
        for pga in (0.05, 0.1, 0.15, 0.2, 0.3, 0.4):
            m = base[pga] = run(pga)
            sweep.append(m)
            row(f"{pga:g} g", m)
        print("\n| PGA | liquefied by shaking | peak strain | settlement | simplified FS < 1 (in) | I-Y settlement (in / run) "
              "| surface PGA raw / 15 Hz / total-stress 15 Hz |\n|---|---|---|---|---|---|---|")
        for pga, m in zip((0.05, 0.1, 0.15, 0.2, 0.3, 0.4), sweep):
            rng = "none" if m["range"] is None else f"{m['liq']:.3g} m in {m['range'][0]:g}-{m['range'][1]:g} m"
            fs = "none" if m["fs1_in"] is None else f"{m['fs1_in'][0]:g}-{m['fs1_in'][1]:g} m"
            print(f"| {pga:.2f} g | {rng} | {100 * m['strain']:.2g} % | {100 * m['settle']:.1f} cm | {fs} | "
                  f"{100 * m['iy_in']:.1f} / {100 * m['iy_run']:.1f} cm | {m['pga']:.3f} / {m['pga_lp']:.3f} / {m['ts_lp']:.3f} g |")
        print()
        dec = [change(a["settle"], b["settle"]) for a, b in zip(sweep, sweep[1:])]
        print(f"sweep: settlement steps {', '.join(f'{x:+.1f} %' for x in dec)}; worst {min(dec):+.1f} % "
              f"(criterion >= -10 %); 0.4/0.1 g = {sweep[-1]['settle'] / sweep[1]['settle']:.2f} (>= 1.5)")
    for pga in pgas:
        if pga not in base:
            base[pga] = run(pga)
            row(f"{pga:g} g", base[pga])
        b = base[pga]
        if "mesh" in what:
            m = run(pga, loose=0.5)
            row(f"{pga:g} g, loose elements / 2", m)
            print(f"mesh {pga:g} g: peak strain {change(b['strain'], m['strain']):+.1f} % (criterion <= 25 %)")
        if "steps" in what:
            m = run(pga, steps=0.5)
            row(f"{pga:g} g, steps / 2", m)
            print(f"steps {pga:g} g: PGA raw {change(b['pga'], m['pga']):+.1f} %, low-passed "
                  f"{change(b['pga_lp'], m['pga_lp']):+.1f} %, Sa(0.05) {change(b['sa05'], m['sa05']):+.1f} % "
                  f"(criterion < 5 %)")
        if "viscosity" in what:
            for eta in (0.0, 1e4):
                m = run(pga, viscosity=eta)
                row(f"{pga:g} g, viscosity {eta:g} Pa s", m)
                print(f"viscosity {eta:g} at {pga:g} g: settlement {change(b['settle'], m['settle']):+.1f} %, "
                      f"liquefied {b['liq']:.3g} -> {m['liq']:.3g} m (criterion < 20 %)")
    if "undrained" in what:
        for pga in pgas:
            m = run(pga, k=1e-6)
            row(f"{pga:g} g, k = 1e-6 m/s", m)
            print(f"undrained {pga:g} g: FS < 0.8 (run a_max) {m['fs08_run']}, FS < 1.2 {m['fs12_run']}, liquefied {m['range']}; "
                  f"settlement {100 * m['settle']:.2f} cm, I-Y (run) {100 * m['iy_run']:.2f} cm, "
                  f"ratio {m['iy_run'] / max(m['settle'], 1e-12):.2f}")
    if "isolation" in what:
        for pga in pgas:
            isolation(pga, k_iso)


if __name__ == "__main__":
    main(sys.argv[1:])
