"""A submerged slope: the buoyant weight drives the sloping liquefaction column.

Compared quantities, each with its definition:

- τ_s/P_s of every saturated element at the static start, τ_s the column's static shear
  (:meth:`LiquefactionColumn.static_shear`) and P_s the granular pressure of the start state (the
  effective stress normal to the slope, g cos α Σ (ρ̄ − ρ_f) h above the element's centre), against
  tan α; to 1e-9 relative (P_s comes back from n̄ through the skeleton law's log and exp);
- the same ratio with slope-parallel seepage against tan α ρ̄/(ρ̄ − ρ_f) of a uniform layer (the total
  weight drives, τ_s = σ_v sin α cos α: its tests are in test_slope_column.py);
- rest: the largest downslope displacement of any node relative to the base, from the static state,
  after 50 s without shaking (at most 1e-9 m, as the seepage column's rest test), and the stress of
  every element then still τ_s (1e-9 relative): the kernel's buoyant body force and the static
  shear are the same discrete load, else the column would move;
- the compiled and the plain-Python sub-steps of a submerged column alike to 1e-12 relative.
"""
import math
import numpy as np
import pytest

from twofluid.casefile.schema import CaseError
from twofluid.closures import hysteretic as law
from twofluid.geotech import lateral_spread as ls
from twofluid.models import hysteretic_kernel as hk
from twofluid.models.liquefaction_1d import ColumnState
from twofluid.runners.common import run_case
from twofluid.runners.liquefaction import build_column
from twofluid.runners.liquefaction_slope import GROUNDWATER
from slope_cases import assert_site_line_refused, sloping_case

TAN = 0.03  # the bundled site's slope, 3 %


def _submerged(groundwater="submerged", **edits):
    """The bundled sloping site without its crust (water table at the ground surface), unshaken
    unless ``edits`` say otherwise."""
    c = sloping_case(**{"ground_motion__pga_g": 0.0, **edits})
    c["site"]["water_table_depth"] = 0.0
    c["site"]["groundwater"] = groundwater
    c["layers"] = c["layers"][1:]
    c["report"]["depths"] = []
    return c


@pytest.mark.parametrize("value", ["\"seepage\"", "1.0", "\"\""])
def test_bad_groundwater_is_one_line_and_exit_2(value, tmp_path, capsys):
    assert_site_line_refused(f"slope = 3.0\ngroundwater = {value}", "[site] groundwater", tmp_path, capsys)


def test_submerged_slope_with_a_crust_is_refused():
    c = sloping_case(ground_motion__pga_g=0.0)
    c["site"]["groundwater"] = "submerged"
    with pytest.raises(CaseError) as exc:
        run_case(c)
    msg = str(exc.value)
    assert "[site] water_table_depth" in msg and "submerged" in msg and "\n" not in msg


@pytest.fixture(scope="module")
def columns():
    return {gw: build_column(_submerged(gw)) for gw in ("submerged", "slope_parallel_seepage")}


def test_submerged_static_shear_over_normal_effective_stress_is_tan_alpha(columns):
    b = columns["submerged"]
    col, s = b.column, b.state
    ns = col.n_sat
    assert ns == col.wave.h.size  # no crust
    tau = col.static_shear(b.site.porosity)
    ps = col.granular_pressure(s)
    np.testing.assert_allclose(tau / ps, TAN, rtol=1e-9)
    np.testing.assert_allclose(tau / col.hysteretic[:, law.P_SIG0], TAN, rtol=1e-9)
    np.testing.assert_allclose(s.shear[:, law.S_TAU], tau, rtol=1e-12)  # the static start is at τ_s
    # the buoyant weight by hand: g sin α Σ (ρ̄ − ρ_f) h above the centre
    rho_b = col.mixture_density(b.site.porosity) - 1000.0
    w = rho_b * col.wave.h
    by_hand = 9.81 * math.sin(math.atan(TAN)) * (np.cumsum(w[::-1])[::-1] - 0.5 * w)
    np.testing.assert_allclose(tau, by_hand, rtol=1e-12)


def test_seepage_drives_with_the_total_weight(columns):
    sub, tot = columns["submerged"].column, columns["slope_parallel_seepage"].column
    n = columns["submerged"].site.porosity
    rho = sub.mixture_density(n)
    top = np.flatnonzero(columns["submerged"].site.layer_of == 0)  # the uniform loose sand on top
    ratio = tot.static_shear(n)[top] / sub.static_shear(n)[top]
    np.testing.assert_allclose(ratio, rho[top] / (rho[top] - 1000.0), rtol=1e-12)
    ps = tot.granular_pressure(columns["slope_parallel_seepage"].state)
    np.testing.assert_allclose(tot.static_shear(n)[top] / ps[top], TAN * rho[top] / (rho[top] - 1000.0),
                               rtol=1e-9)
    assert sub.rho_b == 1000.0 and tot.rho_b == 0.0


@pytest.mark.parametrize("base", ["rigid", "compliant"])
def test_unshaken_submerged_slope_stays_at_rest(base):
    b = build_column(_submerged(shear_wave__base=base))
    col, s = b.column, b.state
    tau = col.static_shear(b.site.porosity)
    col.shear_end = 1e9  # the shear wave runs (no record: a_g = 0)
    w, _, st, m, _ = col._shear_hysteretic(s, 50.0)
    assert m == 10000
    moved = col.lateral_displacement(ColumnState(s.vertical.copy(t=50.0), w, st))
    assert np.max(np.abs(moved)) <= 1e-9
    np.testing.assert_allclose(w.tau, tau, rtol=1e-9)
    np.testing.assert_allclose(w.tau / col.granular_pressure(s), TAN, rtol=1e-8)


def test_submerged_kernel_compiled_and_plain_alike():
    if hk.compiled() is None:
        pytest.skip("numba not available: only the plain path runs")
    b = build_column(_submerged())
    col, s = b.column, b.state
    col.a_g_at = lambda t: 0.5 * np.sin(2.0 * np.pi * 2.0 * t)  # a short shake, m/s²
    col.shaking_end = col.shear_end = 1e9
    out = {}
    for jit in (True, False):
        col._hyst_run = hk.compiled() if jit else hk._substeps  # (the column resolves it once per run)
        w, nb, st, m, _ = col._shear_hysteretic(s, 0.1)
        out[jit] = (w.u, w.tau, st)
    for a, b_ in zip(out[True], out[False]):
        np.testing.assert_allclose(a, b_, rtol=1e-12, atol=1e-300)
    assert np.max(np.abs(out[True][0])) > 0.0


def test_summary_names_the_groundwater(tmp_path):
    c = _submerged(time__end=0.2)
    c["output"]["times"] = []
    r = run_case(c, tmp_path / "out")
    sl = r.summary["slope"]
    assert sl["groundwater"] == GROUNDWATER["submerged"] and sl["groundwater"].startswith("submerged")
    for la in sl["layers"]:
        np.testing.assert_allclose(la["alpha_static"], [TAN, TAN], rtol=1e-9)


def test_newmark_block_drives_with_the_buoyant_weight(tmp_path):
    c = _submerged(ground_motion__pga_g=0.315, ground_motion__duration=4.0, time__end=30.0)
    c["output"]["times"] = []
    r = run_case(c, tmp_path / "out")
    nm = r.summary["slope"]["estimates"]["newmark"]
    if "sliding_depth_m" not in nm:
        pytest.fail(f"nothing liquefied in the shaken submerged column: {nm}")
    # the block's S_r, τ_d = S_r/FS_post and k_y = (S_r − τ_d)(1 + t²)/σ_v give σ_v (its inertia) and
    # σ_d = τ_d (1 + t²)/t (what drives); their difference must be the water's weight above the
    # element's base, ρ_f g d, whatever the column's density at the end of the run
    b = build_column(c)
    col = b.column
    d = nm["sliding_depth_m"]
    e = int(np.argmin(np.abs((col.ground_surface - col.y_all[:-1]) - d)))
    s_r = col.hysteretic[e, law.P_SR]
    t = 0.03
    tau_d = s_r / nm["fs_post"]
    sigma_v = (s_r - tau_d) * (1.0 + t * t) / nm["k_y_g"]
    sigma_d = tau_d * (1.0 + t * t) / t
    assert sigma_v - sigma_d == pytest.approx(1000.0 * c["materials"]["gravity"] * d, rel=1e-9)
    assert "submerged" in nm["method"]
