"""Strain after triggering of the hysteretic law (closures/hysteretic_ratchet.py) against OpenSees
PM4Sand's undrained cyclic DSS elements (benchmarks/pm4sand_element_results.json, frozen numbers).

The element test is stress-controlled: σ′_v0 = 101.3 kPa, the static shear α σ′_v0 applied before
the cycles (as PM4Sand's), uniform cycles of CSR about it. N_3% is the first time the single-amplitude
strain from the static strain reaches 3 %; the strains after it are compared at N_3% + 2 and + 5
cycles (linear between cycle ends, PM4Sand's frozen per cycle). The criteria are the comparison's
own: within a factor 2 of PM4Sand's where the stress reverses, increments growing where its grow,
no strain where the static margin α − CSR ≥ 0.04, level ground at CSR = CRR unchanged in kind and
within a factor 2 and below γ_lim. Nothing before triggering differs with the mechanism off.
"""
import json
from pathlib import Path

import numpy as np
import pytest

from twofluid.closures import hysteretic as law
from twofluid.models import hysteretic_kernel as hk
from twofluid.models import hysteretic_sand as hs

DATA = json.loads((Path(__file__).resolve().parents[2] / "benchmarks" / "pm4sand_element_results.json").read_text())
SIG = DATA["sigma_v0_kPa"] * 1e3
SPC = 100


def _case(dr, alpha):
    return next(c for c in DATA["cases"] if c["dr_percent"] == dr and c["alpha"] == alpha)


def _run(dr, alpha, csr, cycles=30, **opts):
    par = hs.parameters(sigma_v0=[SIG], dr=dr, **opts)
    st = law.new_state(1, par)
    if alpha > 0.0:
        par = hs.apply_k_alpha(par, alpha)
        par[0, law.P_TAUS] = alpha * SIG
        law.static_state(st, par, 0, alpha * SIG, SIG)
    size = SPC * cycles + 1
    g, tau, ru = np.zeros(size), np.zeros(size), np.zeros(size)
    n = hk.element_cycles(st, par, 0, csr, SPC, cycles, 2.0, 10.0, g, tau, ru, bias=alpha)
    last = size if n < 0 else int(round(n * SPC)) + 1
    dg = g[:last] - g[0]
    k3 = np.flatnonzero(np.abs(dg) >= 0.03)
    n3 = k3[0] / SPC if k3.size else None
    ends = np.array([dg[c * SPC] for c in range(1, cycles + 1) if c * SPC < last])
    amp = np.array([np.abs(dg[(c - 1) * SPC:c * SPC + 1]).max() for c in range(1, cycles + 1) if c * SPC < last])
    return n3, ends, amp, dg


def _at(per_cycle, x):
    """A per-cycle quantity (cycle k at index k − 1) at fractional cycle x, linear between cycles."""
    k = np.arange(1, len(per_cycle) + 1)
    assert x <= k[-1], "ran out of cycles"
    return float(np.interp(x, k, per_cycle))


@pytest.mark.parametrize("dr,alpha", [(35, 0.05), (55, 0.1)])
def test_strain_keeps_accumulating_after_triggering_where_the_stress_reverses(dr, alpha):
    case = _case(dr, alpha)
    assert case["stress_reversal"]
    pm = case["pm4sand"]
    n3, ends, _, _ = _run(dr, alpha, case["csr"])
    assert n3 is not None
    for k in (2, 5):
        ours, theirs = _at(ends, n3 + k), _at(pm["gamma_end"], pm["n3"] + k)
        assert 0.5 < ours / theirs < 2.0, (k, ours, theirs)
    ours_inc = np.diff([_at(ends, n3 + k) for k in range(1, 7)])
    pm_inc = np.diff([_at(pm["gamma_end"], pm["n3"] + k) for k in range(1, 6)])
    mean_ours = (_at(ends, n3 + 5) - _at(ends, n3 + 2)) / 3.0
    mean_pm = (_at(pm["gamma_end"], pm["n3"] + 5) - _at(pm["gamma_end"], pm["n3"] + 2)) / 3.0
    assert 0.5 < mean_ours / mean_pm < 2.0
    assert np.all(ours_inc > 0.0)
    if pm_inc[-1] / pm_inc[0] > 1.2:  # PM4Sand's increments grow: so do ours
        assert ours_inc[4] / ours_inc[0] > 1.2


def test_without_the_mechanism_the_sloping_element_shakes_down():
    """The reason for the mechanism: with γ_c fixed the element stops near 3 %, and the two runs are
    identical up to the cycle in which it triggers."""
    case = _case(35, 0.05)
    n3, ends_off, _, dg_off = _run(35, 0.05, case["csr"], cycles=20, k_centre=0.0, gamma_weakening=0.0)
    _, _, _, dg_on = _run(35, 0.05, case["csr"], cycles=20)
    assert abs(ends_off[-1] - ends_off[-5]) < 0.005 and ends_off[-1] < 0.04
    k = int(np.floor(n3)) * SPC
    assert np.array_equal(dg_on[:k + 1], dg_off[:k + 1])


def test_a_static_margin_of_0_04_strains_little():
    case = _case(35, 0.1)
    assert case["csr"] == 0.06 and case["margin"] >= 0.04
    _, ends, _, _ = _run(35, 0.1, case["csr"], cycles=20)
    assert np.max(np.abs(ends)) < 0.005


def test_level_ground_at_crr_is_untouched_and_close_to_pm4sand():
    """Dr 35 % at the model's CRR (15 cycles): the reversals sit on the dilation stops, the cycles'
    mean stays at γ_c, and the single amplitude at N_3% + 10 is the one without the mechanism,
    within a factor 2 of PM4Sand's and below γ_lim(Dr)."""
    case = _case(35, 0.0)
    crr = 0.0904  # model_crr(dr=35, sigma_v0=101.3e3) to 0.1 %
    n3, _, amp, dg = _run(35, 0.0, crr)
    _, _, amp_off, dg_off = _run(35, 0.0, crr, k_centre=0.0, gamma_weakening=0.0)
    assert np.allclose(dg, dg_off, rtol=0.0, atol=1e-12)
    ours, theirs = _at(amp, n3 + 10), _at(case["pm4sand"]["gamma_peak"], case["pm4sand"]["n3"] + 10)
    assert 0.5 < ours / theirs < 2.0
    assert ours < hs.parameters(sigma_v0=[SIG], dr=35)[0, law.P_GLIM]


def test_mirror_symmetry_on_a_slope():
    """The mechanism is odd in γ: the upslope-facing slope (α < 0) mirrors the downslope one."""
    a = _run(55, 0.1, 0.147, cycles=22)[3]
    par = hs.parameters(sigma_v0=[SIG], dr=55)
    st = law.new_state(1, par)
    par = hs.apply_k_alpha(par, 0.1)
    par[0, law.P_TAUS] = -0.1 * SIG
    law.static_state(st, par, 0, -0.1 * SIG, SIG)
    size = SPC * 22 + 1
    g, tau, ru = np.zeros(size), np.zeros(size), np.zeros(size)
    hk.element_cycles(st, par, 0, -0.147, SPC, 22, 2.0, 10.0, g, tau, ru, bias=-0.1)
    b = g - g[0]
    assert np.allclose(a, -b[:a.size], rtol=0.0, atol=1e-9)
