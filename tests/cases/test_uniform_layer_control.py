"""The bundled ``uniform-layer-control``: one uniform loose layer under a crust, over dense sand,
shaken so that the simplified procedure at the column's own total-stress a_max gives FS 0.7-0.9
through the loose layer.

The case runs as shipped (every element size, step and the whole record to its Arias t95; a few
seconds of CPU, the total-stress companion included), once per module. Checked:

- the frozen scale still does what it was chosen for: FS 0.7-0.9 in every loose element at the
  run's a_max (the summary's "run" column, from the total-stress companion), FS > 1.3 in the
  dense sand;
- the dense sand's peak r_u stays below 0.95;
- the column liquefies (r_u > 0.95 first reached while the shear wave runs) at least 70 % of the
  thickness where FS < 0.9.

Criteria the model does not meet are marked ``xfail(strict=True)`` with the numbers it gives: they
are recorded, not loosened, and the mark fails the suite once the model meets them.
"""
from __future__ import annotations

import csv

import pytest

from twofluid.casefile.loader import load_case
from twofluid.runners.liquefaction import run_liquefaction

CASE = "uniform-layer-control"


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    c = load_case(CASE)
    c["output"].update(plots=False)
    out = tmp_path_factory.mktemp("control") / "run"
    res = run_liquefaction(c, out)
    with open(out / "elements.csv", newline="") as f:
        rows = [r for r in csv.DictReader(f) if r["saturated"] == "yes"]
    return res.summary, rows


def _num(x):
    return float(x) if x not in ("", None) else None


def test_the_frozen_scale_puts_the_loose_layer_at_fs_0p7_to_0p9_at_the_columns_own_a_max(run):
    s, rows = run
    simp = s["simplified_procedure"]
    assert "total stress" in simp["a_max_run_definition"]  # the companion ran, not a fallback
    assert simp["a_max_run_g"] > s["shaking"]["pga_g"]       # the site amplifies the outcrop motion
    loose = [_num(r["FS_simplified_run"]) for r in rows if r["layer"] == "loose sand"]
    dense = [_num(r["FS_simplified_run"]) for r in rows if r["layer"] == "dense sand"]
    assert len(loose) == 8 and all(0.7 <= f <= 0.9 for f in loose), loose
    assert dense and min(dense) > 1.3, min(dense)


def test_the_dense_layer_stays_below_liquefaction(run):
    s, rows = run
    dense = next(la for la in s["layers"] if la["name"] == "dense sand")
    assert dense["peak_r_u"] < 0.95
    assert max(_num(r["peak_r_u"]) for r in rows if r["layer"] == "dense sand") < 0.95


def _liquefied_while_shaking(s, rows):
    """(liquefied thickness where FS < 0.9, thickness where FS < 0.9) [m]."""
    end = s["shaking"]["shear_wave_end_s"]
    weak = [r for r in rows if _num(r["FS_simplified_run"]) is not None and _num(r["FS_simplified_run"]) < 0.9]
    h = [_num(r["depth_bottom_m"]) - _num(r["depth_top_m"]) for r in weak]
    liq = [hi for hi, r in zip(h, weak)
           if _num(r["time_first_liquefied_s"]) is not None and _num(r["time_first_liquefied_s"]) < end]
    return sum(liq), sum(h)


def test_liquefaction_starts_at_the_base_of_the_loose_layer_and_climbs(run):
    """Where the column does liquefy: a zone that reaches the base of the loose layer (the element
    farthest from the drained water table), with r_u falling towards the water table."""
    s, rows = run
    top, bottom = s["liquefied_depth_range_shaking_m"]
    assert bottom == pytest.approx(4.5) and 2.5 < top < 4.5
    loose = [_num(r["peak_r_u"]) for r in rows if r["layer"] == "loose sand"]
    assert loose[0] < 0.5 < loose[-1]
    assert all(a <= b + 1e-9 for a, b in zip(loose[:-2], loose[1:-1]))  # rising with depth to the base


@pytest.mark.xfail(strict=True, reason="the hysteretic law liquefies 0.75 m (3.75-4.5 m) of the 2.0 m at FS < 0.9, "
                   "37.5 %: the upper metre drains to the water table (k = 1e-4 m/s) and stays at r_u 0.18-0.85; "
                   "1.0 m (50 %) even at a 0.2 g input")
def test_the_column_liquefies_70_percent_of_the_thickness_where_fs_is_below_0p9(run):
    s, rows = run
    liq, weak = _liquefied_while_shaking(s, rows)
    assert weak == pytest.approx(2.0)
    assert liq >= 0.7 * weak, f"{liq:g} m of {weak:g} m"
