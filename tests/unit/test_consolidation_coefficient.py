"""summary.json's consolidation_coefficient_m2_s: the documented formula on the run's initial profile.

c_v = k M/(ρ_f g), M = P_s (1 − n̄)/(A (1 − n)), n̄ = 1 − (1 − n)(1 − A ln(P_s/p_ref)), with the
layer's given k, A and p_ref, the initial porosity and P_s = σ′_v0 of the unrun column. The run
softens A while the sand reconsolidates, so a value read after the run depended on its length.
"""
import numpy as np
import pytest

from twofluid.casefile.loader import load_case
from twofluid.runners.liquefaction import build_column, run_liquefaction

G, RHO_F = 9.80665, 1000.0


def _formula(case) -> dict:
    col = build_column(case).column  # not run: σ′_v0 and the element depths of the initial profile
    sat = [la for la in case["layers"] if la.get("hydraulic_conductivity")]
    per_el = []
    for d in col.depth:  # saturated element centres below the surface, base first
        top = 0.0
        for la in case["layers"]:
            if top <= d < top + la["thickness"]:
                per_el.append(la)
                break
            top += la["thickness"]
    assert len(per_el) == col.depth.size and all(la in sat for la in per_el)
    k = np.array([la["hydraulic_conductivity"] for la in per_el])
    n = np.array([la["porosity"] for la in per_el])
    A = np.array([la["compressibility"] for la in per_el])
    p_ref = np.array([la["p_ref"] for la in per_el])
    ps = col.sigma_v0
    n_bar = 1.0 - (1.0 - n) * (1.0 - A * np.log(ps / p_ref))
    c_v = k * ps * (1.0 - n_bar) / (A * (1.0 - n)) / (RHO_F * G)
    zw, H = case["site"]["water_table_depth"], col.ground_surface
    mid = float(np.interp(zw + (H - zw) / 2, col.depth[::-1], c_v[::-1]))
    return {"top": float(c_v[-1]), "mid_depth": mid, "base": float(c_v[0])}


@pytest.mark.parametrize("end", [10.0, 600.0])
def test_layered_site_consolidation_coefficient_is_the_formula_on_the_initial_state(end, tmp_path):
    case = load_case("liquefaction-layered-site")
    case["time"]["end"] = end
    case["output"].update(plots=False, times=[t for t in case["output"]["times"] if t <= end])
    got = run_liquefaction(case, out_dir=tmp_path / "run").summary["consolidation_coefficient_m2_s"]
    ref = _formula(load_case("liquefaction-layered-site"))
    for where in ("top", "mid_depth", "base"):
        assert got[where] == pytest.approx(ref[where], rel=0.01), (where, got, ref)
    assert ref["top"] < ref["mid_depth"] < ref["base"]  # σ′_v0 grows with depth: a real profile, not one value
