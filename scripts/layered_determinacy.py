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
  run's a_max, and the settlement against Ishihara-Yoshimine).

    python scripts/layered_determinacy.py [sweep] [mesh] [steps] [viscosity] [undrained] [--pga=0.15,0.2]

(all five by default; about 1.5 min of CPU). Numbers in docs/liquefaction.md, "The hysteretic model".
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


if __name__ == "__main__":
    main(sys.argv[1:])
