"""Perturbation ensemble of a liquefaction case: how far do its results move under tiny changes?

Each member runs the case with the drag law multiplied by (1 + δ), a relative change far
below any modelling uncertainty; a result that moves by O(1) across the members is a sample
of a spread, not a determinate output of the model (docs/liquefaction.md, "Determinate
results"). Prints one row per member, then the spread against the criteria: the liquefied
depth range moves by at most one element and the settlement by at most 2 %; with
``--halve`` a member with both time steps halved is added, whose settlement must stay within
5 % of the δ = 0 member.

    python scripts/liquefaction_ensemble.py liquefaction-elcentro
    python scripts/liquefaction_ensemble.py liquefaction-elcentro --set layers.viscosity=0 \
        --deltas=0,1e-5,-1e-5 --halve
"""
from __future__ import annotations

import argparse
import tempfile
import tomllib

import twofluid.runners.liquefaction as liq
from twofluid.casefile.loader import load_case
from twofluid.casefile.schema_liquefaction import layer_elements
from twofluid.ensemble.members import locate


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


def run_member(case: dict, delta: float, step_factor: float = 1.0) -> dict:
    """Summary of ``case`` with drag × (1 + δ) and both time steps × ``step_factor``."""
    original = liq.build_column
    liq.build_column = _with_drag_factor(1.0 + delta)
    try:
        with tempfile.TemporaryDirectory() as out:
            case = dict(case, output=dict(case["output"], plots=False))
            if step_factor != 1.0:
                case["time"] = dict(case["time"], step=case["time"]["step"] * step_factor)
                case["shear_wave"] = dict(case["shear_wave"], step=case["shear_wave"]["step"] * step_factor)
            return liq.run_liquefaction(case, out).summary
    finally:
        liq.build_column = original


def set_key(case: dict, item: str) -> None:
    """Apply ``SECTION.KEY=VALUE`` (TOML value); ``layers.KEY`` sets every layer, ``layers.N.KEY``
    layer N (1-based)."""
    key, value = item.split("=", 1)
    v = tomllib.loads(f"v = {value}")["v"]
    parts = key.split(".")
    if parts[0] == "layers":
        targets = case["layers"] if len(parts) == 2 else [case["layers"][int(parts[1]) - 1]]
        for la in targets:
            la[parts[-1]] = v
        return
    node, name = locate(case, key)  # a path through the nested case: closures.drag.law
    node[name] = v


def spread(members: list[dict], element_size: float) -> dict:
    """Largest shift of the liquefied depth range [elements] and settlement spread [%] against
    the first member."""
    ref = members[0]

    def ends(s):
        z = s["liquefied_depth_range_m"]
        return (0.0, 0.0) if z is None else tuple(z)

    shift = max(max(abs(a - b) for a, b in zip(ends(s), ends(ref))) for s in members) / element_size
    s0 = ref["settlement_end_m"]
    rel = max(abs(s["settlement_end_m"] - s0) for s in members) / abs(s0) if s0 else 0.0
    return {"range_shift_elements": shift, "settlement_spread": rel}


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("case", help="bundled case name or TOML path (a liquefaction_1d case)")
    p.add_argument("--deltas", type=lambda v: [float(x) for x in v.split(",")],
                   default=[0.0, 1e-5, -1e-5, 2e-5, -2e-5, 3e-5, -3e-5],
                   help="comma-separated relative drag perturbations δ of the members (default %(default)s)")
    p.add_argument("--set", action="append", default=[], metavar="SECTION.KEY=VALUE",
                   help="override a case key (TOML value), e.g. layers.viscosity=0 (every layer)")
    p.add_argument("--halve", action="store_true", help="add a member with both time steps halved")
    args = p.parse_args(argv)
    case = load_case(args.case)
    for item in args.set:
        set_key(case, item)
    print("delta, step_factor, liquefied_ever_m, thickness_m, first_s, settlement_shaking_cm, "
          "settlement_end_cm, sand_boil, top_peak_r_u, stopped_at_s, status")
    members, halved = [], None
    runs = [(d, 1.0) for d in args.deltas] + ([(args.deltas[0], 0.5)] if args.halve else [])
    for d, f in runs:
        s = run_member(case, d, f)
        if f == 1.0:
            members.append(s)
        else:
            halved = s
        first = s["first_liquefaction"]
        print(f"{d:+.0e}, {f:g}, {s['liquefied_depth_range_m']}, {s['liquefied_thickness_m']:.3g}, "
              f"{first['time_s'] if first else None}, {100 * (s['settlement_end_of_shaking_m'] or 0):.4g}, "
              f"{100 * s['settlement_end_m']:.4g}, {s['surface']['sand_boil']}, "
              f"{s['peak_r_u_top_element']:.3f}, {s['stopped_at_s']:.5g}, {s['status']}", flush=True)
    h = min(la["thickness"] / layer_elements(la) for la in case["layers"])  # the finest element
    sp = spread(members, h)
    print(f"range shift {sp['range_shift_elements']:.2f} element(s) (criterion <= 1), settlement spread "
          f"{100 * sp['settlement_spread']:.2f} % (criterion <= 2 %)")
    if halved is not None:
        rel = abs(halved["settlement_end_m"] - members[0]["settlement_end_m"]) / members[0]["settlement_end_m"]
        print(f"steps halved: settlement changes by {100 * rel:.2f} % (criterion <= 5 %)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
