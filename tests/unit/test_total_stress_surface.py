"""The total-stress companion run (``runners.liquefaction.total_stress_surface``), whose low-passed
peak surface acceleration is the simplified procedure's "run" a_max: the whole shear wave in one
call of the sub-steps gives the accelerations of the step-by-step run.

Both take the same sub-steps with the same law; only the sub-steps' times are summed differently
(from the start of the wave instead of from each vertical step's start) and the one call stops
Newton's iterations by their rate of contraction as well (``one_call``'s ``quick``), so they agree
to far below Newton's tolerance: asserted 1e-9 s on the times, 1e-9 of the peak on the accelerations
and 1e-12 relative on the low-passed peak on short waves (measured on the whole waves of the bundled
cases and the OpenSees peer column: at most 5e-13 s, 2.3e-9 of the peak (the sloping site; the peer
column 6e-10) and 3e-12 (the peer column)).
"""
from __future__ import annotations

import numpy as np
import pytest

from twofluid.casefile.loader import load_case
from twofluid.geotech import filtering
from twofluid.runners import liquefaction as rl


def _case(name, duration, changes=()):
    c = load_case(name)
    if name == "liquefaction-layered-site":  # coarse: a few seconds
        for la, size in zip(c["layers"], (1.0, 0.5, 1.0)):
            la["element_size"] = size
    c["ground_motion"]["duration"] = duration
    c["shear_wave"]["free_vibration"] = 1.0
    for section, key, value in changes:
        c[section][key] = value
    return c


@pytest.mark.parametrize("name, changes", [
    ("liquefaction-layered-site", ()),  # hysteretic law, crust, water table at 2 m
    ("liquefaction-elcentro", ()),  # the thesis's laws (their compiled kernel)
    ("liquefaction-layered-site", (("shear_wave", "step", 0.003),)),  # 7 sub-steps of 0.02/7 s a step
])
def test_the_whole_wave_in_one_call_repeats_the_run_step_by_step(name, changes):
    c = _case(name, 2.0, changes)
    t1, a1 = rl.total_stress_surface(c)
    t0, a0 = rl.total_stress_surface(c, one_call=False)
    assert t1.shape == t0.shape and t0.size > 100
    assert np.max(np.abs(t1 - t0)) <= 1e-9
    assert np.max(np.abs(a1 - a0)) <= 1e-9 * np.max(np.abs(a0))
    p1, p0 = filtering.low_passed_peak(t1, a1), filtering.low_passed_peak(t0, a0)
    assert p1 == pytest.approx(p0, rel=1e-12)


def test_a_wave_that_is_not_whole_steps_runs_step_by_step():
    """Shaking of 2.01 s with steps of 0.02 s: the run's last step before the end of the shaking is
    cut short (other sub-steps), so the companion runs step by step, as the run does."""
    c = _case("liquefaction-layered-site", 2.01)
    b = rl.build_column(c)
    b.column.shear_only = True
    assert rl._whole_wave(b) is None
    t1, a1 = rl.total_stress_surface(c)
    t0, a0 = rl.total_stress_surface(c, one_call=False)
    np.testing.assert_array_equal(t1, t0)
    np.testing.assert_array_equal(a1, a0)


def _companion_call(c):
    """The companion's one call of the hysteretic sub-steps (plain Python): its outputs."""
    from twofluid.models import hysteretic_kernel as hk

    b = rl.total_stress_column(c)
    t, a = rl._whole_wave(b, kernel=hk._substeps)
    return np.concatenate([t, a])


def test_strength_and_mrdf_factor_kept_over_the_call_are_those_of_every_substep(monkeypatch):
    """In total stress nothing changes P_s over the call (no drainage, no generation), so the
    sub-steps compute each element's strength, G_max, viscosity and the damping bands once, keep
    the MRDF factor F while the largest strain, γ_r and r_g are the same, and leave an outer branch
    unevaluated while its floor shows it is not the lower one: the same numbers, bit for bit, as
    computing them at every sub-step and evaluating every branch (the plain Python path, with the
    shortcuts off)."""
    from twofluid.models import hysteretic_kernel as hk

    c = _case("liquefaction-layered-site", 0.5)
    kept = _companion_call(c)

    def nothing_fixed(par, dn, ns, fixed):
        fixed[:] = 0.0
        return False

    monkeypatch.setattr(hk, "_fixed_strength", nothing_fixed)
    monkeypatch.setattr(hk, "_kept_factor", lambda keep, e, gm, gr, rg: -1.0)  # every F computed afresh
    monkeypatch.setattr(hk, "_keep_floor", lambda q, c, g, t, cert, e: None)  # no floor: every branch evaluated
    monkeypatch.setattr(hk, "_keep_seen", lambda cert, e, g, f: None)
    monkeypatch.setattr(hk, "_prepared_same", lambda pkey, e, d, st, s, gr, gd: False)  # every branch prepared afresh
    monkeypatch.setattr(hk, "_moves_on", lambda g, d, st, par, e: False)  # every commit the law's own
    every = _companion_call(c)
    assert kept.size > 100
    np.testing.assert_array_equal(kept, every)


def test_the_companion_compiled_and_plain_alike():
    """The companion's kernel compiled and as plain Python (``TWOFLUID_DISABLE_JIT``): 1e-12."""
    from twofluid.models import hysteretic_kernel as hk

    if hk.compiled() is None:
        pytest.skip("numba not available: only the plain path runs")
    c = _case("liquefaction-layered-site", 0.5)
    plain = _companion_call(c)
    t, a = rl.total_stress_surface(c)
    n = t.size
    np.testing.assert_allclose(t, plain[:n], rtol=0, atol=1e-12)
    np.testing.assert_allclose(a, plain[n:], rtol=0, atol=1e-12 * np.max(np.abs(a)))


def test_the_quick_iterations_give_the_same_wave_in_fewer_evaluations(monkeypatch):
    """The companion's one call stops Newton's iterations by their rate of contraction as well
    (``one_call``'s ``quick``, the kernel's last argument): the same accelerations as iterating to the
    tolerance, to far below it (measured 7e-10 of the peak here, 6e-10 on the peer column's whole
    35 s wave, 2e-9 on the bundled sloping site's), in fewer evaluations of the law (here 23 %
    fewer, as on the peer column; the plain-Python sub-steps counted). The elcentro column with the
    hysteretic law, 3 s of shaking, sub-steps of 0.005 s: its Newton iterations take three updates,
    the last only to confirm the second."""
    from twofluid.closures import hysteretic as law
    from twofluid.models import hysteretic_kernel as hk
    from twofluid.runners import liquefaction_total_stress as ts

    c = _case("liquefaction-elcentro", 3.0, (("shear_wave", "model", "hysteretic"), ("shear_wave", "damping_ratio", 0.01)))
    calls = []
    stress_below = law._stress_below

    def counted(*a):
        calls[-1] += 1
        return stress_below(*a)

    monkeypatch.setattr(law, "_stress_below", counted)
    waves = []
    for quick in (True, False):
        b = rl.total_stress_column(c)
        calls.append(0)
        total, _ = ts.plan(b.column, b.state, b.dt)
        waves.append(ts.one_call(b.column, b.state, total, False, kernel=hk._substeps, quick=quick))
    (t1, a1), (t0, a0) = waves
    assert t0.size == 800
    np.testing.assert_array_equal(t1, t0)
    assert 0.0 < np.max(np.abs(a1 - a0)) <= 1e-9 * np.max(np.abs(a0))
    assert calls[0] < 0.8 * calls[1], calls


def test_the_stop_test_of_the_quick_iterations():
    """Stop where the next update at the last rate of contraction would be within the tolerance; never
    on a first update (no rate) or on one that grew."""
    from twofluid.models import hysteretic_kernel as hk

    assert hk._contracted(1.5e-8, 4e-4, 1e-10)  # next about 6e-13
    assert not hk._contracted(1e-6, 4e-4, 1e-10)  # next about 2.5e-9
    assert not hk._contracted(1e-20, float("inf"), 1.0)
    assert not hk._contracted(2e-8, 1e-8, 1.0)
