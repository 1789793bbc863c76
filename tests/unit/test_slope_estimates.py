"""The engineering estimates beside a sloping column: the Newmark block on the total-stress
companion's motion, the Zhang et al. (2004) estimate with I&B's γ_max, and the flag for a spread
beyond every measured one.

Compared quantities:

- the Newmark block of the summary, with the companion's motion replaced by a half-sine pulse at
  the node under the element of least k_y, against the closed form of
  :func:`twofluid.verification.sliding_block.half_sine_pulse_displacement` times cos α (the block
  slides along the slope: v̇ = cos α (a − a_y)). The record is sampled every 1 ms and linearly
  interpolated: the error is O((ω Δt)²) ≈ 1e-5 of the displacement; tolerance 1e-3;
- the companion's surface acceleration against total_stress_surface stepping the same column:
  the same sub-steps, so the same numbers to round-off (1e-9 of the peak).
"""
import math
from types import SimpleNamespace

import numpy as np
import pytest

from twofluid.closures import hysteretic as law
from twofluid.geotech import lateral_spread as ls
from twofluid.runners import liquefaction_slope as lsr
from twofluid.runners.liquefaction import build_column, total_stress_surface
from twofluid.verification import sliding_block as sb
from slope_cases import sloping_case


def _liquefied_loose_sand(b):
    ns = b.column.n_sat
    loose = np.flatnonzero(b.site.layer_of == 1)
    ever = np.isin(np.arange(ns), loose)
    return loose, SimpleNamespace(ever=ever, first=np.where(ever, 1.0, np.nan))


def test_newmark_slides_on_the_companion_motion_at_the_least_yield_depth(monkeypatch):
    c = sloping_case()
    b = build_column(c)
    col = b.column
    s_r = col.hysteretic[:, law.P_SR]
    loose, rec = _liquefied_loose_sand(b)
    w = col.wave.rho * col.wave.h * col.v.mat.g
    sigma_v = np.array([w[e:].sum() for e in range(w.size)])
    k_y = ls.yield_coefficient(s_r[loose], sigma_v[loose], 3.0)
    e = int(loose[np.argmin(k_y)])
    a_y = float(k_y.min()) * ls.G
    amp, omega, t_on = 3.0 * a_y, math.pi, 1.5
    seen = []

    def companion(case, polarity, **kw):  # the ground under the element accelerates upslope for polarity 1
        seen.append(polarity)
        t = np.arange(0.0, 4.0 + 5e-4, 1e-3)
        pulse = np.where((t >= t_on) & (t <= t_on + math.pi / omega), np.sin(omega * (t - t_on)), 0.0)
        a = np.zeros((t.size, col.y_all.size))
        a[:, e] = -polarity * amp * pulse
        a[:, e + 1] = 10.0 * amp * pulse  # another depth: must not drive the block
        return t, a

    monkeypatch.setattr(lsr, "total_stress_node_motion", companion)
    r = lsr._newmark(c, col, rec, s_r)
    cos_a = math.cos(math.atan(0.03))
    exact = cos_a * sb.half_sine_pulse_displacement(amp, omega, a_y)
    assert sorted(seen) == [-1, 1]
    assert r["sliding_depth_m"] == pytest.approx(col.ground_surface - col.y_all[e], abs=1e-12)
    assert r["k_y_g"] == pytest.approx(float(k_y.min()), rel=1e-12)
    assert r["displacement_by_polarity_m"]["1"] == pytest.approx(exact, rel=1e-3)
    assert r["displacement_by_polarity_m"]["-1"] == 0.0
    assert r["displacement_m"] == pytest.approx(0.5 * exact, rel=1e-3)


def test_newmark_before_triggering_does_not_slide(monkeypatch):
    """The block is held until the element's first liquefaction: a pulse before it moves nothing."""
    c = sloping_case()
    b = build_column(c)
    col = b.column
    loose, rec = _liquefied_loose_sand(b)
    rec.first[:] = np.where(rec.ever, 3.0, np.nan)

    def companion(case, polarity, **kw):
        t = np.arange(0.0, 4.0 + 5e-4, 1e-3)
        a = np.zeros((t.size, col.y_all.size))
        a[(t > 1.0) & (t < 2.0), :] = -5.0 * polarity
        return t, a

    monkeypatch.setattr(lsr, "total_stress_node_motion", companion)
    r = lsr._newmark(c, col, rec, col.hysteretic[:, law.P_SR])
    assert r["displacement_m"] == 0.0 and r["triggering_time_s"] == 3.0


def test_newmark_flow_failure_and_nothing_liquefied():
    c = sloping_case(site__slope=5.0)
    b = build_column(c)
    loose, rec = _liquefied_loose_sand(b)
    r = lsr._newmark(c, b.column, rec, b.column.hysteretic[:, law.P_SR])
    assert r["flow_failure"] is True and r["displacement_m"] is None and r["k_y_g"] <= 0.0
    rec.ever[:] = False
    r = lsr._newmark(c, b.column, rec, b.column.hysteretic[:, law.P_SR])
    assert r["displacement_m"] is None and "nothing liquefied" in r["note"]


def test_companion_surface_is_the_total_stress_run():
    """The companion's surface node is total_stress_surface's surface motion (the same column in
    total stress), at the companion's sample times; the record's sign flips it."""
    c = sloping_case(ground_motion__duration=2.0)
    c["shear_wave"]["free_vibration"] = 1.0
    t, a = lsr.total_stress_node_motion(c, 1)
    c2 = dict(c)
    ts, asurf = total_stress_surface(c2, one_call=False)
    common = np.isin(np.round(ts, 9), np.round(t, 9))
    idx = np.searchsorted(np.round(t, 9), np.round(ts[common], 9))
    assert common.sum() > 100
    peak = np.abs(asurf).max()
    assert np.max(np.abs(a[idx, -1] - asurf[common])) <= 1e-9 * peak
    assert np.abs(a[:, -1]).max() > 0.5  # it shakes [m/s²]


@pytest.mark.parametrize("d_end, zhang, flow, flag", [
    (6.0, 3.0, False, True), (5.0, 3.0, False, False), (6.0, 7.0, False, False), (8.0, 7.0, False, True),
    (9.0, 3.0, True, False)])
def test_beyond_measured_spreads_flag(d_end, zhang, flow, flag):
    layers = [{"name": "loose", "flow_slide": flow}, {"name": "other", "flow_slide": False}]
    f = lsr._beyond_field(d_end, layers, zhang)
    assert f["flag"] is flag and f["limit_m"] == max(zhang, 5.4)
    assert lsr._beyond_field(d_end, [], zhang)["flag"] is False


def test_slope_lines_say_the_flag():
    sl = {"surface_displacement_end_m": 7.0, "share_after_shaking": None, "flow_after_shaking": None,
          "estimates": {"newmark": {"displacement_m": 1.0}, lsr.ZHANG_KEY: {"displacement_m": 3.0},
                        "youd_2002": {"median_m": 2.0}},
          "beyond_measured_spreads": {"flag": True, "limit_m": 5.4}}
    lines = lsr.slope_lines(sl)
    assert "Zhang 2004 with I&B gamma_max 3 m" in lines[1] and lines[2].startswith("  flag:")
