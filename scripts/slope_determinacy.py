"""The bundled sloping site's surface displacement under the issue-22 checks, measured (not timed).

Runs ``sloping-site`` as shipped and with, one at a time: the PGA moved by ±1e-5 (relative), the
steps (vertical, shear and flow) halved and quartered, the flow step alone halved, the loose layer's
elements halved and quartered, the record reversed (polarity −1), alone and with the steps or the
loose layer's elements halved, the shear sub-step alone at 2.5 and 1.25 ms, the liquefied-soil
viscosity 0 and 1e4 Pa s, and a PGA sweep; prints the surface displacement at the end, its relative
change from the shipped case, the Zhang et al. (2004) and Newmark estimates beside it. Numbers in
data/cases/sloping-site/README.md.

    python scripts/slope_determinacy.py
"""
from __future__ import annotations

import copy
import warnings

from twofluid.casefile.loader import load_case
from twofluid.runners.common import run_case


def _run(case, edit):
    c = copy.deepcopy(case)
    edit(c)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = run_case(c)
    s = r.summary["slope"]
    f = s["flow_after_shaking"] or {}
    return (s["surface_displacement_end_m"], s["share_after_shaking"], r.summary["liquefied_depth_range_m"],
            s["estimates"]["zhang_2004_ib_gamma_max"]["displacement_m"], s["estimates"]["newmark"].get("displacement_m"),
            s["localisation"]["depth_m"], f.get("shear_wave_end_s"), f.get("time_99_percent_s"))


def _set(section, key, value):
    def edit(c):
        c[section][key] = value(c[section][key]) if callable(value) else value
    return edit


def _steps(f, flow_only=False):
    def edit(c):
        c["shear_wave"]["flow_step"] *= f
        if not flow_only:
            c["shear_wave"]["step"] *= f
            c["time"]["step"] *= f
    return edit


def _elements(f):
    def edit(c):
        c["layers"][1]["element_size"] *= f
    return edit


def _both(a, b):
    def edit(c):
        a(c)
        b(c)
    return edit


def _viscosity(eta):
    def edit(c):  # the liquefied-soil viscosity of the saturated layers
        for la in c["layers"][1:]:
            la["viscosity"] = eta
    return edit


def main() -> None:
    case = load_case("sloping-site")
    case["output"]["plots"] = False
    d0 = _run(case, lambda c: None)
    rows = [("as shipped", d0)]
    for label, edit in [("PGA x (1 + 1e-5)", _set("ground_motion", "pga_g", lambda v: v * (1 + 1e-5))),
                        ("PGA x (1 - 1e-5)", _set("ground_motion", "pga_g", lambda v: v * (1 - 1e-5))),
                        ("steps / 2", _steps(0.5)), ("steps / 4", _steps(0.25)),
                        ("flow step / 2", _steps(0.5, flow_only=True)),
                        ("loose elements / 2", _elements(0.5)), ("loose elements / 4", _elements(0.25)),
                        ("polarity -1", _set("ground_motion", "polarity", -1)),
                        ("polarity -1, steps / 2", _both(_set("ground_motion", "polarity", -1), _steps(0.5))),
                        ("polarity -1, loose elements / 2", _both(_set("ground_motion", "polarity", -1), _elements(0.5))),
                        ("shear sub-step 2.5 ms", _set("shear_wave", "step", 0.0025)),
                        ("shear sub-step 1.25 ms", _set("shear_wave", "step", 0.00125)),
                        ("viscosity 0 Pa s", _viscosity(0.0)), ("viscosity 1e4 Pa s", _viscosity(1e4)),
                        ("PGA 0.10 g", _set("ground_motion", "pga_g", 0.10)),
                        ("PGA 0.15 g", _set("ground_motion", "pga_g", 0.15)),
                        ("PGA 0.20 g", _set("ground_motion", "pga_g", 0.20)),
                        ("PGA 0.30 g", _set("ground_motion", "pga_g", 0.30)),
                        ("PGA 0.35 g", _set("ground_motion", "pga_g", 0.35))]:
        rows.append((label, _run(case, edit)))
    print("| run | surface displacement [m] | change | share after shaking | 99 % at [s] | shear wave end [s] "
          "| liquefied [m] | localised at [m] | Zhang 2004 [m] | Newmark [m] |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for label, (d, share, liq, z, nm, loc, end, t99) in rows:
        nm_s = "flow failure" if nm is None else f"{nm:.3f}"
        t99_s = "—" if t99 is None else f"{t99:.2f}"
        end_s = "—" if end is None else f"{end:.2f}"
        print(f"| {label} | {d:.4f} | {100 * (d / d0[0] - 1):+.1f} % | {share:+.3f} | {t99_s} | {end_s} | {liq} "
              f"| {loc:.3f} | {z:.2f} | {nm_s} |")


if __name__ == "__main__":
    main()
