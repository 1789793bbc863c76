"""The liquefaction column's per-step record kernel (models/record_kernel.py).

Its plain Python (what ``TWOFLUID_DISABLE_JIT=1`` runs: the same function object) and its compiled
build give the same numbers bit for bit, and both give what the NumPy expressions of the record
give (r_u, its peak and time, the first liquefaction, np.maximum's NaN rule, the settlement
summed in NumPy's pairwise order), on random states with NaNs and signed zeros and on the states
of a real column run.
"""
from __future__ import annotations

import numpy as np
import pytest

from twofluid.models import record_kernel


@pytest.mark.parametrize("n", [*range(0, 300, 7), 1, 8, 9, 16, 127, 128, 129, 255, 256, 257, 1025, 4097])
def test_the_sum_is_numpys_bit_for_bit(n):
    rng = np.random.default_rng(n)
    for _ in range(5):
        a = rng.standard_normal(n) * 10.0 ** rng.uniform(-8, 8, n)
        assert record_kernel._np_sum(a) == float(np.sum(a))
    assert record_kernel._np_sum(np.ones(n)) == n


def _numpy_record(t, P, p_hydro, sigma_v0, n, n0, lengths, gamma, ps, elem, sig0_elem, ru_liq, V_top, W_top,
                  peak, t_peak, first, ever, peak_strain, max_contribution):
    """The record as NumPy expressions (what the recorder did before the kernel), in place."""
    excess = P - p_hydro
    ru = excess / sigma_v0
    up = ru > peak
    np.copyto(peak, ru, where=up)
    np.copyto(t_peak, t, where=up)
    liq = ru > ru_liq
    np.copyto(first, t, where=np.isnan(first) & liq)
    ever |= liq
    np.maximum(peak_strain, np.abs(gamma), out=peak_strain)
    c = lengths * (n0 - n) / (1.0 - n)
    np.maximum(max_contribution, c, out=max_contribution)
    nt = n[-1]
    flux = float(0.5 * (V_top + W_top) - nt * 0.5 * (V_top - W_top) / (1.0 - nt))
    return ru, c, liq, ru[elem], ps[elem] / sig0_elem, [float(c.sum()), float(excess[0]), float(ru[-1]), flux]


def _memory(ne, ng):
    return [np.full(ne, -np.inf), np.zeros(ne), np.full(ne, np.nan), np.zeros(ne, dtype=bool), np.zeros(ng),
            np.zeros(ne)]


def _kernel_record(f, args, mem, ne, k):
    peak, t_peak, first, ever, peak_strain, max_c = mem
    liq = np.zeros(ne, dtype=bool)
    ru, c, ru_e, sig_e, sc = np.empty(ne), np.empty(ne), np.empty(k), np.empty(k), np.zeros(5)
    f(*args, peak, t_peak, first, ever, liq, peak_strain, max_c, ru, c, ru_e, sig_e, sc)
    # the fifth entry: the lowest liquefied element (what the damage record took from liq.argmax()), -1 for none
    assert sc[4] == (int(liq.argmax()) if liq.any() else -1)
    sc4 = np.zeros(4)  # (four entries: the same four, nothing more written)
    f(*args, peak.copy(), t_peak.copy(), first.copy(), ever.copy(), liq.copy(), peak_strain.copy(), max_c.copy(),
      np.empty(ne), np.empty(ne), np.empty(k), np.empty(k), sc4)
    assert sc4.tolist() == sc[:4].tolist() or np.isnan(sc[:4]).any()
    return ru, c, liq, ru_e, sig_e, list(map(float, sc[:4]))


def _same(a, b):
    a, b = np.asarray(a), np.asarray(b)
    assert a.shape == b.shape
    assert np.array_equal(a, b, equal_nan=True)
    assert np.array_equal(np.signbit(a), np.signbit(b))


def _random_steps(ne, ng, steps, seed):
    rng = np.random.default_rng(seed)
    p_hydro = np.linspace(1e5, 0.0, ne)
    sigma_v0 = np.linspace(2e5, 1e3, ne)
    n0 = rng.uniform(0.38, 0.45, ne)
    lengths = rng.uniform(0.2, 0.6, ne)
    elem = np.array(sorted(rng.choice(ne, 3, replace=False)), dtype=np.int64)
    for step in range(steps):
        P = p_hydro + sigma_v0 * rng.uniform(-0.2, 1.2, ne) * min(1.0, step / 5)
        n = n0 + rng.normal(0.0, 1e-3, ne)
        n[rng.integers(ne)] = n0[0] if step % 3 == 0 else n[0]  # a zero (or signed zero) contribution
        gamma = rng.normal(0.0, 1e-2, ng)
        if step == 4:
            P[1], gamma[2], n[3] = np.nan, np.nan, np.nan  # NaNs: kept as np.maximum keeps them
        ps = rng.uniform(0.0, 2e5, ne)
        yield (0.01 * (step + 1), P, p_hydro, sigma_v0, n, n0, lengths, gamma, ps, elem, sigma_v0[elem],
               0.9, rng.normal(0.0, 1e-4), rng.normal(0.0, 1e-4))


def _check_paths(states, ne, ng):
    """Plain Python kernel, compiled kernel (where there is one) and NumPy expressions, step by step."""
    plain = record_kernel.record_step
    compiled = record_kernel.compiled()
    paths = [plain] + ([compiled] if compiled is not None and compiled is not plain else [])
    mems = [_memory(ne, ng) for _ in range(len(paths) + 1)]
    k = None
    for args in states:
        k = args[9].size
        ref = _numpy_record(*args, *mems[0])
        for f, mem in zip(paths, mems[1:]):
            got = _kernel_record(f, args, mem, ne, k)
            for a, b in zip(ref, got):
                _same(a, b)
            for a, b in zip(mems[0], mem):
                _same(a, b)
    return len(paths)


def test_plain_compiled_and_numpy_records_agree_on_random_states():
    ne, ng = 29, 33  # more than one block of eight, a crust above the saturated elements
    _check_paths(_random_steps(ne, ng, 12, 3), ne, ng)


def test_plain_and_compiled_records_agree_on_a_column_run():
    """The first shaking steps of the bundled thesis column, recorded by every path."""
    from twofluid.casefile.loader import load_case
    from twofluid.runners.liquefaction import build_column

    case = load_case("liquefaction-elcentro")
    b = build_column(case)
    col, s = b.column, b.state
    ne, ng = col.v.mesh.n_elements, s.wave.gamma.size
    states = []
    rec_elem = np.array([0, ne // 2, ne - 1], dtype=np.int64)
    for i, step in enumerate(col.run(s, 40 * b.dt, b.dt)):
        st = step.state
        v = st.vertical
        states.append((st.t, v.P.copy(), col.p_hydro, col.sigma_v0, v.n.copy(), col.n0, col.v.mesh.lengths,
                       st.wave.gamma.copy(), col.granular_pressure(st), rec_elem, col.sigma_v0[rec_elem], 0.1,
                       float(v.V[-1]), float(v.W[-1])))
    assert len(states) >= 40
    _check_paths(states, ne, ng)
