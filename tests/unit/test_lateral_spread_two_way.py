"""The two-way Newmark sliding block (``newmark_sliding_two_way``) and its slope wrapper."""
import math
from fractions import Fraction as F

import numpy as np
import pytest

from twofluid.geotech import lateral_spread as ls
from twofluid.verification import sliding_block as sb


def _two(a, dt, ayd, ayu, history=False):
    a = np.asarray(a, dtype=float)
    d, v = np.zeros(a.size), np.zeros(a.size)
    out = ls.newmark_sliding_two_way(a, dt, ayd, ayu, d, v)
    assert out == d[-1]
    return (out, d, v) if history else out


def _one(a, dt, ay, history=False):
    a = np.asarray(a, dtype=float)
    d, v = np.zeros(a.size), np.zeros(a.size)
    out = ls.newmark_sliding(a, dt, ay, d, v)
    return (out, d, v) if history else out


def test_two_way_hand_value_trapezoid_pulse_each_way():
    """A trapezoidal pulse each way, exact by hand (a_yd = 1, a_yu = 1.5 m/s², samples every 0.5 s).
    Downslope 37/24 m (newmark_sliding's docstring). Upslope u = −a = 4 (t − 3) crosses 1.5 at
    3.375 s: w = 2τ² to 1/32 m/s, +1/768 m; u − 1.5 = 0.5 for 1 s: w = 17/32, +1/32 + 1/4 m; the
    ramp 0.5 − 4τ over 0.5 s: w = 9/32, +17/64 + 1/16 − 1/12 m; then −1.5: +(9/32)²/3 m."""
    a = [2.0, 2.0, 2.0, 0.0, 0.0, 0.0, 0.0, -2.0, -2.0, -2.0, 0.0, 0.0, 0.0, 0.0, 0.0]
    up = F(1, 768) + F(1, 32) + F(1, 4) + F(17, 64) + F(1, 16) - F(1, 12) + F(9, 32) ** 2 / 3
    exact = float(F(37, 24) - up)
    out, d, v = _two(a, 0.5, 1.0, 1.5, history=True)
    assert out == pytest.approx(exact, rel=1e-14)
    np.testing.assert_allclose(v[6:12], [0.0, -1 / 32, -9 / 32, -17 / 32, -9 / 32, 0.0], atol=1e-15)
    assert d[6] == pytest.approx(37 / 24, rel=1e-14)


def test_two_way_half_sine_pair_second_order():
    """A half sine each way, the block at rest between them: the exact value is the difference of
    two one-way closed forms (sliding_block.half_sine_pulse_displacement); order 2 in dt."""
    A, w = 2.0, 2.0 * math.pi                        # 0.5 s pulses at 0 s and 2 s
    ayd, ayu = 0.6, 0.9
    exact = sb.half_sine_pulse_displacement(A, w, ayd) - sb.half_sine_pulse_displacement(A, w, ayu)
    errs, dts = [], []
    for n in (25, 50, 100, 200, 400):
        t = np.linspace(0.0, 5.0, 10 * n + 1)
        a = (np.where(t <= 0.5, A * np.sin(w * np.minimum(t, 0.5)), 0.0)
             - np.where((t >= 2.0) & (t <= 2.5), A * np.sin(w * np.clip(t - 2.0, 0.0, 0.5)), 0.0))
        dt = t[1] - t[0]
        errs.append(abs(_two(a, dt, ayd, ayu) - exact))
        dts.append(dt)
    assert np.polyfit(np.log(dts), np.log(errs), 1)[0] == pytest.approx(2.0, abs=0.15)
    assert errs[-1] < 1e-4 * abs(exact)


def test_two_way_symmetric_block_mirrors_and_cancels():
    """τ_s = 0 (a_yd = a_yu): the negated record gives the negated history exactly, and a record
    followed by its negation (the block at rest between) ends where it started."""
    rng = np.random.default_rng(11)
    a = rng.normal(0.0, 2.0, 1500)
    a[-300:] = 0.0                                    # the block comes to rest
    d_p, d_m = _two(a, 0.01, 0.9, 0.9, True)[1], _two(-a, 0.01, 0.9, 0.9, True)[1]
    np.testing.assert_array_equal(d_m, -d_p)
    assert abs(d_p[-1]) > 1e-3                        # it did slide, both ways
    out, d, v = _two(np.concatenate([a, -a]), 0.01, 0.9, 0.9, history=True)
    assert v[a.size - 1] == 0.0
    assert abs(out) < 1e-12 * np.max(np.abs(d))
    # on a slope (a_yu > a_yd) the same pair ends downslope
    assert _two(np.concatenate([a, -a]), 0.01, 0.9, 1.1) > 1e-3


def test_two_way_with_a_large_upslope_yield_is_the_one_way_block():
    rng = np.random.default_rng(5)
    a = rng.normal(0.0, 2.0, 3000)
    ref, d1, v1 = _one(a, 0.01, 0.8, history=True)
    out, d2, v2 = _two(a, 0.01, 0.8, 1e3, history=True)
    assert ref > 0.0
    assert out == pytest.approx(ref, rel=1e-13)
    np.testing.assert_allclose(d2, d1, rtol=1e-13, atol=1e-15)
    np.testing.assert_allclose(v2, v1, rtol=1e-13, atol=1e-15)


def test_two_way_is_exact_for_piecewise_linear_records():
    """Inserting the record's own interpolated midpoints changes nothing (starts and stops both
    ways, several within one step, are found in closed form)."""
    rng = np.random.default_rng(9)
    a = rng.normal(0.0, 2.0, 400)
    ref = _two(a, 0.01, 0.7, 0.9)
    fine = np.empty(2 * a.size - 1)
    fine[0::2] = a
    fine[1::2] = 0.5 * (a[:-1] + a[1:])
    assert _two(fine, 0.005, 0.7, 0.9) == pytest.approx(ref, rel=1e-11, abs=1e-14)
    # a stop downslope and a start upslope within one step: v = 0.1 m/s at t = 1 s, a falls 0 → −4
    a = np.array([1.1, 1.1, -4.0, -4.0])
    n = 400
    tf = np.linspace(0.0, 3.0, 3 * n + 1)
    fine_out, _, vf = _two(np.interp(tf, np.arange(4.0), a), 1.0 / n, 1.0, 1.0, history=True)
    step = (tf > 1.0) & (tf < 2.0)
    assert np.any(vf[step] > 0.0) and np.any(vf[step] < 0.0) and np.any(vf[step] == 0.0)
    assert _two(a, 1.0, 1.0, 1.0) == pytest.approx(fine_out, rel=1e-12)


def test_two_way_kernel_compiles_with_numba():
    numba = pytest.importorskip("numba")
    rng = np.random.default_rng(3)
    a = rng.normal(0.0, 2.0, 2000)
    d1, v1, d2, v2 = (np.zeros(a.size) for _ in range(4))
    jit = numba.njit(ls.newmark_sliding_two_way)
    assert jit(a, 0.01, 0.7, 0.8, d1, v1) == pytest.approx(ls.newmark_sliding_two_way(a, 0.01, 0.7, 0.8, d2, v2),
                                                           rel=1e-13, abs=1e-15)
    np.testing.assert_allclose(d1, d2, rtol=1e-13, atol=1e-14)
    np.testing.assert_allclose(v1, v2, rtol=1e-13, atol=1e-14)


def test_newmark_infinite_slope_two_way():
    dt = 0.01
    t = dt * np.arange(1200)
    pulse = np.where((t > 1.0) & (t < 1.5), 2.0, 0.0) - np.where((t > 6.0) & (t < 6.5), 2.0, 0.0)
    s_r, sigma, slope = 3000.0, 100e3, 2.0
    tau = float(ls.static_shear_stress(sigma, slope))
    ky = float(ls.yield_coefficient(s_r, sigma, slope))
    one = ls.newmark_infinite_slope(-pulse, dt, s_r, sigma, slope)
    two = ls.newmark_infinite_slope(-pulse, dt, s_r, sigma, slope, two_way=True)
    assert one.k_y_up is None and two.k_y == one.k_y
    assert two.k_y_up == pytest.approx((s_r + tau) * (1 + 0.02 ** 2) / sigma, rel=1e-14)
    assert two.k_y_up > ky
    d, v = np.zeros(t.size), np.zeros(t.size)
    plain = ls.newmark_sliding_two_way(pulse, dt, ky * ls.G, two.k_y_up * ls.G, d, v)
    assert two.displacement_m == pytest.approx(math.cos(math.atan(0.02)) * plain, rel=1e-14)
    assert 0.0 < two.displacement_m < one.displacement_m
    assert two.message.startswith("two-way Newmark sliding block")
    # flow failure is the same for both
    assert ls.newmark_infinite_slope(pulse, dt, 1500.0, sigma, slope, two_way=True).flow_failure
