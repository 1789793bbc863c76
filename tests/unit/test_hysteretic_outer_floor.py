"""The floor of the outer branch (``closures.hysteretic._outer_floor``) with which the column's
sub-steps leave that branch unevaluated while the current branch is far below it
(``_stress_below``): the floor lies below the outer branch at every strain beyond the one it was
made at, and the stress with it is the stress without it, bit for bit, whether the branch was left
out or not; on elements with nested loops, in total stress (MRDF and Masing) and liquefied with
dilation."""
from __future__ import annotations

import math

import numpy as np
import pytest

from twofluid.closures import hysteretic as law
from twofluid.closures import hysteretic_memory as hm
from twofluid.models import hysteretic_sand as hs


def _total_stress(mrdf):
    par = hs.parameters(sigma_v0=[100e3], n160cs=10.0, liquefiable=False, mrdf=mrdf, gamma_d0=10.0)
    st = law.new_state(1, par)
    s, gm = law.strength_modulus(100e3, par, 0)
    return st, par, s, s / gm


def _liquefied():
    par = hs.parameters(sigma_v0=[100e3], n160cs=10.0)
    st = law.new_state(1, par)
    st[0, law.S_LIQ] = 1.0
    st[0, law.S_GD] = 0.002
    s, gm = law.strength_modulus(par[0, law.P_SR] / par[0, law.P_TANPHI], par, 0)
    return st, par, s, s / gm


def _nested_path(scale, seed):
    """Decaying cycles with wiggles: reversal after reversal nested inside the last (scale: the
    first amplitude [-])."""
    rng = np.random.default_rng(seed)
    points = [0.0]
    amp = scale
    for k in range(14):
        points.append((1.0 if k % 2 == 0 else -1.0) * amp * (1.0 + 0.2 * rng.random()))
        amp *= 0.75
    path = []
    for a, b in zip(points[:-1], points[1:]):
        path.extend(np.linspace(a, b, 25)[1:])
    return path


@pytest.mark.parametrize("element, scale", [(lambda: _total_stress(True), 3e-3), (lambda: _total_stress(False), 3e-3),
                                            (_liquefied, 0.03)])
def test_the_outer_floor_holds_and_leaves_the_stress_unchanged(element, scale):
    st, par, s, gr = element()
    checked = skipped = 0
    for g_next in _nested_path(scale, 1):
        c = law._constants(st, par, 0)
        for d in (1.0, -1.0):
            q = law._prepare(d, st, par, 0, s, gr, c, -1.0)
            if q[law.Q_N] < 3.0:
                continue
            a = st[0, law.S_G]
            floor = law._outer_floor(a, q, c)
            assert math.isfinite(floor)
            reach = 4.0 * abs(a - st[0, law.S_STK + 2 * (int(q[law.Q_N]) - 2)]) + 1e-4
            for g in a + d * np.concatenate([np.linspace(0.0, reach, 60), [-1e-4, -1e-7]]):
                to = hm._on(g, d, *q[law.Q_B:law.Q_B + 6], s, q[law.Q_FM], c)[0]
                if d * (g - a) >= 0.0:
                    assert d * to > floor  # the floor holds beyond the strain it was made at
                tau = hm._on(g, d, *q[law.Q_A:law.Q_A + 6], s, q[law.Q_FM], c)[0]
                skipped += d * (g - a) >= 0.0 and d * tau <= floor
                assert law._stress_below(g, q, c, a, floor)[:2] == law._stress_below(g, q, c, g, -math.inf)[:2]
                checked += 1
        dd = law.direction(g_next, st, 0)
        law.commit(g_next, dd, law.skeleton_stress(g_next, dd, st, par, 0, s, gr), st, par, 0, s, 0.0, gr)
    assert checked > 1000 and skipped > 500  # the branch was left out, and often


def test_no_floor_where_the_branch_may_not_be_monotone():
    """F outside [0, 1] (Φ′ = F f′(y/2) + (1 − F) f′(y) may change sign) or a falling θ_τ: −inf."""
    st, par, s, gr = _total_stress(True)
    for g in _nested_path(3e-3, 2)[:80]:
        d = law.direction(g, st, 0)
        law.commit(g, d, law.skeleton_stress(g, d, st, par, 0, s, gr), st, par, 0, s, 0.0, gr)
    c = law._constants(st, par, 0)
    d = -st[0, law.S_DIR]
    q = law._prepare(d, st, par, 0, s, gr, c, -1.0)
    assert q[law.Q_N] >= 3.0 and math.isfinite(law._outer_floor(st[0, law.S_G], q, c))
    bad_f = q[:law.Q_FM] + (1.5,) + q[law.Q_FM + 1:]
    assert law._outer_floor(st[0, law.S_G], bad_f, c) == -math.inf
    falling = c[:law.C_TH2] + (-abs(c[law.C_TH2]) - 1.0,) + c[law.C_TH2 + 1:]
    assert law._outer_floor(st[0, law.S_G], q, falling) == -math.inf
