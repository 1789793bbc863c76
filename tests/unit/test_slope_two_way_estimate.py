"""The two-way Newmark block beside a sloping column (``slope.estimates.newmark_two_way``): the same
depth, drive and polarities as the one-way block, sliding upslope once the drive falls below
−k_y,up g, k_y,up = (S_r + τ_static)/(σ_v cos²α).

The companion's motion is replaced by a half-sine pulse at the node under the element of least
k_y (strong enough to pass both yields), sampled every 1 ms: each polarity's displacement is the
closed form of :func:`twofluid.verification.sliding_block.half_sine_pulse_displacement` times
cos α, downslope on k_y for one polarity and upslope on k_y,up for the other. The interpolation
error is O((ω Δt)²) ≈ 1e-5 of the displacement; tolerance 1e-3.
"""
import math
from types import SimpleNamespace

import numpy as np
import pytest

from twofluid.closures import hysteretic as law
from twofluid.geotech import lateral_spread as ls
from twofluid.runners import liquefaction_slope as lsr
from twofluid.runners.liquefaction import build_column
from twofluid.verification import sliding_block as sb
from slope_cases import sloping_case


def test_two_way_block_beside_the_one_way_block(monkeypatch):
    c = sloping_case()
    b = build_column(c)
    col = b.column
    ns = col.n_sat
    s_r = col.hysteretic[:, law.P_SR]
    loose = np.flatnonzero(b.site.layer_of == 1)
    ever = np.isin(np.arange(ns), loose)
    rec = SimpleNamespace(ever=ever, first=np.where(ever, 1.0, np.nan))
    w = col.wave.rho * col.wave.h * col.v.mat.g
    sigma_v = np.array([w[e:].sum() for e in range(w.size)])
    k_y = ls.yield_coefficient(s_r[loose], sigma_v[loose], 3.0)
    e = int(loose[np.argmin(k_y)])
    tau = sigma_v[e] * 0.03 / (1.0 + 0.03 ** 2)
    k_up = (s_r[e] + tau) * (1.0 + 0.03 ** 2) / sigma_v[e]
    a_y, a_yu = float(k_y.min()) * ls.G, float(k_up) * ls.G
    amp, omega, t_on = 1.5 * a_yu, 2.0 * math.pi, 1.5

    def companion(case, polarity, **kw):  # the ground under the element accelerates upslope for polarity 1
        t = np.arange(0.0, 30.0 + 5e-4, 1e-3)  # long enough for the block to stop
        pulse = np.where((t >= t_on) & (t <= t_on + math.pi / omega), np.sin(omega * (t - t_on)), 0.0)
        a = np.zeros((t.size, col.y_all.size))
        a[:, e] = -polarity * amp * pulse
        return t, a

    monkeypatch.setattr(lsr, "total_stress_node_motion", companion)
    r = lsr._newmark(c, col, rec, s_r)
    two = r.pop("_two_way")
    cos_a = math.cos(math.atan(0.03))
    down = cos_a * sb.half_sine_pulse_displacement(amp, omega, a_y)
    up = cos_a * sb.half_sine_pulse_displacement(amp, omega, a_yu)
    assert up > 0.0
    assert r["displacement_by_polarity_m"] == pytest.approx({"1": down, "-1": 0.0}, rel=1e-3)
    assert two["displacement_by_polarity_m"]["1"] == pytest.approx(down, rel=1e-3)
    assert two["displacement_by_polarity_m"]["-1"] == pytest.approx(-up, rel=1e-3)
    assert two["displacement_m"] == pytest.approx(0.5 * (down - up), rel=1e-3)
    assert two["k_y_g"] == r["k_y_g"] and two["k_y_up_g"] == pytest.approx(k_up, rel=1e-12)
    assert two["sliding_depth_m"] == r["sliding_depth_m"] and two["flow_failure"] is False


def test_two_way_block_flow_failure_and_nothing_liquefied():
    c = sloping_case(site__slope=5.0)
    b = build_column(c)
    loose = np.flatnonzero(b.site.layer_of == 1)
    ever = np.isin(np.arange(b.column.n_sat), loose)
    rec = SimpleNamespace(ever=ever, first=np.where(ever, 1.0, np.nan))
    two = lsr._newmark(c, b.column, rec, b.column.hysteretic[:, law.P_SR])["_two_way"]
    assert two["flow_failure"] is True and two["displacement_m"] is None
    rec.ever[:] = False
    two = lsr._newmark(c, b.column, rec, b.column.hysteretic[:, law.P_SR])["_two_way"]
    assert two["displacement_m"] is None and "nothing liquefied" in two["note"]
