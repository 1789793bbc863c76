"""The hysteretic sub-steps' shortcuts give the numbers of the law evaluated in full, bit for bit:
the stress alone (``closures.hysteretic._stress_value`` and the ``*_value`` functions it calls, which
leave out the slope) is the stress of ``_stress_below``; an outer branch's floor made at any strain it
was evaluated at (``_floor_of``, as the kernel keeps the last Newton iterate's) holds beyond that
strain; and the kernel with its shortcuts (prepared branches kept while what they depend on is the
same, the last evaluation's floor, the commit that only moves the strain, the generated ratio the
commit made) gives the outputs it gives with each of them off, in effective stress (pore pressure
generated, dilation, liquefaction) as in total stress."""
from __future__ import annotations

import math

import numpy as np
import pytest

from twofluid.closures import hysteretic as law
from twofluid.closures import hysteretic_damage as hd
from twofluid.closures import hysteretic_memory as hm
from twofluid.models import hysteretic_sand as hs


def _element(kind):
    if kind == "liquefied":
        par = hs.parameters(sigma_v0=[100e3], n160cs=10.0)
        st = law.new_state(1, par)
        st[0, law.S_LIQ] = 1.0
        st[0, law.S_GD] = 0.002
        s, gm = law.strength_modulus(par[0, law.P_SR] / par[0, law.P_TANPHI], par, 0)
        return st, par, s, s / gm, 0.03
    par = hs.parameters(sigma_v0=[100e3], n160cs=10.0, liquefiable=False, mrdf=kind == "mrdf", gamma_d0=10.0)
    st = law.new_state(1, par)
    s, gm = law.strength_modulus(100e3, par, 0)
    return st, par, s, s / gm, 3e-3


def _path(scale, seed):
    """Decaying cycles with wiggles, nested reversal after reversal, then a first loading past them."""
    rng = np.random.default_rng(seed)
    points, amp = [0.0], scale
    for k in range(12):
        points.append((1.0 if k % 2 == 0 else -1.0) * amp * (1.0 + 0.2 * rng.random()))
        amp *= 0.75
    points.append(2.0 * scale)
    path = []
    for a, b in zip(points[:-1], points[1:]):
        path.extend(np.linspace(a, b, 21)[1:])
    return path


@pytest.mark.parametrize("kind", ["mrdf", "masing", "liquefied"])
def test_the_stress_alone_is_the_stress_with_its_slope_bit_for_bit(kind):
    st, par, s, gr, scale = _element(kind)
    checked = outer = 0
    for g_next in _path(scale, 3):
        c = law._constants(st, par, 0)
        for d in (1.0, -1.0):
            q = law._prepare(d, st, par, 0, s, gr, c, -1.0)
            a = st[0, law.S_G]
            for g in a + d * np.concatenate([np.linspace(0.0, 3.0 * scale, 40), [-1e-4, -1e-7]]):
                tau, k, to = law._stress_below(g, q, c, g, -math.inf)  # (to: the outer branch's floor)
                assert law._stress_value(g, q, c, g, -math.inf) == (tau, to) or (math.isnan(to) and law._stress_value(g, q, c, g, -math.inf)[0] == tau)
                if q[law.Q_N] > 0.0:
                    on = hm._on(g, d, *q[law.Q_A:law.Q_A + 6], s, q[law.Q_FM], c)
                    assert hm._on_value(g, d, *q[law.Q_A:law.Q_A + 6], s, q[law.Q_FM], c) == on[0]
                if q[law.Q_N] >= 3.0:
                    assert to == law._floor_of(hm._on(g, d, *q[law.Q_B:law.Q_B + 6], s, q[law.Q_FM], c)[0], q, c)
                    outer += 1
                else:
                    assert math.isnan(to)
                assert hm._backbone_value(g, d, s, gr, c) == hm._backbone(g, d, s, gr, c)[0]
                for fm in (0.0, 1.0, 0.37):
                    assert hm._branch_value((g - a) / gr, fm, c) == hm._branch((g - a) / gr, fm, c)[0]
                checked += 1
        dd = law.direction(g_next, st, 0)
        law.commit(g_next, dd, law.skeleton_stress(g_next, dd, st, par, 0, s, gr), st, par, 0, s, 0.0, gr)
    assert checked > 2000 and outer > 500


@pytest.mark.parametrize("kind", ["mrdf", "liquefied"])
def test_a_floor_made_where_the_outer_branch_was_evaluated_holds_beyond(kind):
    st, par, s, gr, scale = _element(kind)
    made = 0
    for g_next in _path(scale, 4):
        c = law._constants(st, par, 0)
        for d in (1.0, -1.0):
            q = law._prepare(d, st, par, 0, s, gr, c, -1.0)
            if q[law.Q_N] < 3.0:
                continue
            for a in st[0, law.S_G] + d * np.array([-0.3, 0.0, 0.4, 1.5]) * scale:  # trial strains, either side
                floor = law._stress_below(a, q, c, a, -math.inf)[2]  # (the floor its evaluation there gives)
                assert math.isfinite(floor) and floor == law._outer_floor(a, q, c)
                for g in a + d * np.linspace(0.0, 3.0 * scale, 50):
                    assert d * hm._on(g, d, *q[law.Q_B:law.Q_B + 6], s, q[law.Q_FM], c)[0] > floor
                    assert law._stress_below(g, q, c, a, floor)[:2] == law._stress_below(g, q, c, g, -math.inf)[:2]
                made += 1
        dd = law.direction(g_next, st, 0)
        law.commit(g_next, dd, law.skeleton_stress(g_next, dd, st, par, 0, s, gr), st, par, 0, s, 0.0, gr)
    assert made > 100


def _effective_stress_call(monkeypatch, off):
    """One call of the plain-Python sub-steps over 1.5 s of the coarse layered site's strong shaking,
    pore pressure generated (the run's own column, nothing moving vertically): its outputs and the
    state it leaves; ``off``: the kernel's shortcuts to switch off."""
    from twofluid.casefile.loader import load_case
    from twofluid.models import hysteretic_kernel as hk
    from twofluid.runners import liquefaction as rl

    c = load_case("liquefaction-layered-site")
    for la, size in zip(c["layers"], (1.0, 0.5, 1.0)):
        la["element_size"] = size
    c["ground_motion"]["duration"] = 1.5
    c["ground_motion"]["pga_g"] = 0.5
    c["shear_wave"]["free_vibration"] = 0.5
    with monkeypatch.context() as m:
        if "floor" in off:
            m.setattr(hk, "_keep_floor", lambda q, c, g, t, cert, e: None)
            m.setattr(hk, "_keep_seen", lambda cert, e, g, f: None)
        if "prepared" in off:
            m.setattr(hk, "_prepared_same", lambda pkey, e, d, st, s, gr, gd: False)
        if "commit" in off:
            m.setattr(hk, "_moves_on", lambda g, d, st, par, e: False)
        if "ratio" in off:  # the generated ratio always computed again after the commit
            generating = law._commit_generating
            m.setattr(law, "_commit_generating", lambda *a: (generating(*a)[0], math.nan, math.nan))
        if "known" in off:  # the generated ratio computed again where the damage is the same
            m.setattr(hd, "_generated_ratio_known", lambda damage, alpha, cap, dk, rk: hd._generated_ratio_of(damage, alpha, cap))
        b = rl.build_column(c)
        b.column.shear_only = True
        states = []

        def kernel(*args):
            code = hk._substeps(*args)
            states.append((code, args[3].copy(), args[5].copy(), args[25].copy()))
            return code

        t, a = rl._whole_wave(b, kernel=kernel)
    return t, a, states


def test_the_kernel_with_its_shortcuts_is_the_kernel_without_them(monkeypatch):
    t0, a0, s0 = _effective_stress_call(monkeypatch, ("floor", "prepared", "commit", "ratio", "known"))
    t1, a1, s1 = _effective_stress_call(monkeypatch, ())
    assert len(s0) == 1 and s0[0][0] == 0 and t0.size > 100
    st = s0[0][1]
    assert np.max(st[:, law.S_RG]) > 0.5 and np.max(st[:, law.S_NSTK]) >= 3.0  # generated, nested loops
    np.testing.assert_array_equal(t1, t0)
    np.testing.assert_array_equal(a1, a0)
    for x0, x1 in zip(s0[0][1:], s1[0][1:]):
        np.testing.assert_array_equal(x1, x0)
