"""Perturbation ensemble of a liquefaction case: how far do its results move under tiny changes?

Each member runs the case with the drag law multiplied by (1 + δ), a relative change far
below any modelling uncertainty; a result that moves by O(1) across the members is a sample
of a spread, not a determinate output of the model (docs/liquefaction.md, "Robustness of
the medium sand"). Prints one row per member.

    python scripts/liquefaction_ensemble.py liquefaction-elcentro
    python scripts/liquefaction_ensemble.py liquefaction-elcentro --set sand.viscosity=1000 \
        --deltas=0,1e-5,-1e-5,2e-5,-2e-5
"""
from __future__ import annotations

import argparse
import tempfile
import tomllib

import twofluid.runners.liquefaction as liq
from twofluid.casefile.loader import load_case


def _with_drag_factor(factor: float):
    """build_column with the column's drag law scaled by ``factor``."""
    build = liq.build_column

    def patched(case):
        b = build(case)
        clo = b.column.v.clo
        law = clo.drag
        object.__setattr__(clo, "drag", lambda *a, **k: factor * law(*a, **k))
        return b
    return patched


def run_member(case: dict, delta: float) -> dict:
    original = liq.build_column
    liq.build_column = _with_drag_factor(1.0 + delta)
    try:
        with tempfile.TemporaryDirectory() as out:
            case = dict(case, output=dict(case["output"], plots=False))
            return liq.run_liquefaction(case, out).summary
    finally:
        liq.build_column = original


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("case", help="bundled case name or TOML path (a liquefaction_1d case)")
    p.add_argument("--deltas", type=lambda v: [float(x) for x in v.split(",")],
                   default=[0.0, 1e-5, -1e-5, 2e-5, -2e-5, 3e-5, -3e-5],
                   help="comma-separated relative drag perturbations δ of the members (default %(default)s)")
    p.add_argument("--set", action="append", default=[], metavar="SECTION.KEY=VALUE",
                   help="override a case key (TOML value), e.g. sand.viscosity=1000")
    args = p.parse_args(argv)
    case = load_case(args.case)
    for item in args.set:
        key, value = item.split("=", 1)
        section, name = key.rsplit(".", 1)
        case[section][name] = tomllib.loads(f"v = {value}")["v"]
    print("delta, liquefied_ever_m, thickness_m, first_s, settlement_shaking_cm, settlement_end_cm, "
          "top_peak_r_u, base_peak_kPa, status")
    for d in args.deltas:
        s = run_member(case, d)
        first = s["first_liquefaction"]
        print(f"{d:+.0e}, {s['liquefied_depth_range_m']}, {s['liquefied_thickness_m']:.3g}, "
              f"{first['time_s'] if first else None}, {100 * (s['settlement_end_of_shaking_m'] or 0):.3g}, "
              f"{100 * s['settlement_end_m']:.3g}, {s['peak_r_u_top_element']:.3f}, "
              f"{s['base_excess_pore_pressure']['peak_Pa'] / 1e3:.1f}, {s['status']}", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
