"""The fast paths of the liquefaction column give the reference paths' results.

- The compiled shear kernel (numba) against the NumPy shear sub-steps: the same Newmark–Newton
  iterates up to the tridiagonal solve (Thomas here, banded LU with pivoting there), so the
  states agree to round-off amplified by the Newton stopping test; 1e-8 relative is far above
  that (measured 1e-11 after 2 s of shaking) and far below any physical change.
- The reduced (W, n) vertical model against the full (V, W, P, n) model: the same discrete
  equations, iterated differently; with a Picard tolerance of 1e-12 both converge to the same
  discrete solution, so one split step agrees to ~1e-10.
- Whole runs of the determinate bundled cases (fine sand and gravel, as shipped): the same
  liquefied depth range, settlement and peak r_u to 1e-6 relative (the Picard tolerance 1e-7 is
  absolute on porosity; its effect on the settlement Σ h Δn/(1 − n) is below 1e-7 relative here).
"""
from __future__ import annotations

import numpy as np
import pytest

from twofluid.casefile.loader import load_case
from twofluid.models import liquefaction_1d
from twofluid.models.reduced_column import ReducedVerticalColumn
from twofluid.runners.liquefaction import build_column, run_liquefaction
from twofluid.timestepping.backward_euler import PicardSettings


def _case(name, **shear_wave):
    c = load_case(f"liquefaction-{name}")
    c["output"]["plots"] = False
    c["shear_wave"] = dict(c["shear_wave"], **shear_wave)
    return c


def _advance(col, state, t_end, dt):
    for step in col.run(state, t_end, dt):
        state = step.state
    return state


def _rel(a, b):
    return float(np.max(np.abs(a - b)) / max(np.max(np.abs(a)), 1e-300))


@pytest.mark.parametrize("name, shear_wave", [
    ("fine", {}),
    ("layered-site", {"model": "thesis", "base": "rigid"}),  # per-layer K2max, Dr, γ_ref and a crust above the water table
    ("elcentro", {"base": "compliant", "bedrock_density": 2400.0, "bedrock_shear_velocity": 500.0}),
])
def test_compiled_shear_kernel_matches_the_reference_path(name, shear_wave):
    pytest.importorskip("numba")
    c = _case(name, **shear_wave)
    runs = {}
    for fast in (False, True):
        b = build_column(c, reference=True)  # full vertical model both times: the shear path differs
        col = b.column
        if fast:
            col._kernel = col._kernel_arguments()
            assert col._kernel is not None
        else:
            col._kernel = None
        runs[fast] = _advance(col, b.state, 2.0, b.dt)
    ref, fast = runs[False], runs[True]
    assert np.max(np.abs(ref.wave.gamma)) > 1e-5  # the column has been shaken
    for f in ("u", "v", "a", "gamma", "tau"):
        assert _rel(getattr(ref.wave, f), getattr(fast.wave, f)) < 1e-8, f
    assert fast.wave.t == ref.wave.t
    assert _rel(1.0 - ref.vertical.n_bar, 1.0 - fast.vertical.n_bar) < 1e-8
    for f in ("eps_v", "gamma_a", "gamma", "path"):
        assert _rel(getattr(ref.shear, f), getattr(fast.shear, f)) < 1e-8, f
    assert np.array_equal(ref.shear.direction, fast.shear.direction)


def test_kernel_hand_back_takes_the_reference_path():
    """A sub-step the kernel cannot take (Newton failure, non-finite value) is repeated on the
    reference path from the same start: the results are then the reference path's exactly."""
    pytest.importorskip("numba")
    c = _case("fine")
    b = build_column(c, reference=True)
    b.column._kernel = None
    ref = _advance(b.column, b.state, 0.2, b.dt)
    b = build_column(c, reference=True)
    b.column._kernel = b.column._kernel_arguments()
    assert b.column._kernel is not None
    b.column._kernel["run"] = lambda *a: 1
    out = _advance(b.column, b.state, 0.2, b.dt)
    assert np.array_equal(out.wave.u, ref.wave.u) and np.array_equal(out.vertical.n_bar, ref.vertical.n_bar)


def test_uncovered_cases_keep_the_reference_shear_path():
    c = _case("fine")
    c["layers"][0]["reference_porosity_law"] = "ann"
    assert build_column(c).column._kernel is None
    assert build_column(_case("fine"), reference=True).column._kernel is None


def test_reduced_vertical_step_solves_the_full_models_equations():
    """One split step (shear sub-steps, then the vertical step) from a shaken state: the reduced and
    the full vertical model converge to the same discrete solution (tight Picard tolerance)."""
    c = _case("gravel")
    b = build_column(c, reference=True)
    s = _advance(b.column, b.state, 1.0, b.dt)  # r_u > 0 and velocities ≠ 0 by now
    tight = PicardSettings(tol=1e-10, max_iter=40)
    out = {}
    for model in (liquefaction_1d.VerticalColumn, ReducedVerticalColumn):
        b = build_column(c, reference=True)
        v = b.column.v
        col = liquefaction_1d.LiquefactionColumn(
            model(v.mesh, v.mat, v.clo, v.bottom, v.top, surcharge=v.surcharge), b.column.sand,
            b.column.a_g, b.column.shaking_end, b.column.shear_step, settings=tight,
            fast_shear=False)
        col.initial_state(b.column.n0)
        out[model] = col.step(s, b.dt).state.vertical
    full, red = out[liquefaction_1d.VerticalColumn], out[ReducedVerticalColumn]
    assert np.max(np.abs(full.W)) > 1e-7
    assert np.max(np.abs(full.n - red.n)) < 1e-10
    assert np.max(np.abs(full.W - red.W)) < 1e-10 * max(np.max(np.abs(full.W)), 1e-2)
    assert np.max(np.abs(red.V)) == 0.0 and np.max(np.abs(full.V)) < 1e-12
    assert _rel(full.P - col.p_hydro, red.P - col.p_hydro) < 1e-6


@pytest.mark.parametrize("name", ["fine", "gravel"])
def test_fast_run_gives_the_reference_results(name, tmp_path):
    c = _case(name)
    ref = run_liquefaction(c, tmp_path / "ref", reference=True).summary
    fast = run_liquefaction(c, tmp_path / "fast").summary
    assert ref["status"] == fast["status"] == "completed"
    assert fast["liquefied_depth_range_m"] == ref["liquefied_depth_range_m"]
    assert fast["steps"] == ref["steps"] and fast["stopped_at_s"] == pytest.approx(ref["stopped_at_s"], rel=1e-12)
    for key in ("settlement_end_m", "settlement_end_of_shaking_m", "peak_r_u_top_element"):
        assert fast[key] == pytest.approx(ref[key], rel=1e-6), key
