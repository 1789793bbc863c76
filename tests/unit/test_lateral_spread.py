"""geotech.lateral_spread: Zhang et al. (2004), Youd et al. (2002), Newmark sliding block.

Compared quantities and tolerances:
- LDI [m], LD [m], D_H [m], k_y [-], FS_post [-]: hand values from the published equations,
  recomputed term by term in the test (relative 1e-12: the same arithmetic in another order);
- the Youd et al. coefficients: equal to the published table (as printed in Youd, Hansen &
  Bartlett 2002, Eq. 6, ground-slope model, and as coded in gem/oq-engine's youd_etal_2002.py
  and LiquPy's calc_ls_bartlett), and each one's effect isolated as an exact power law;
- the sliding-block integrator: the final displacement d [m] of the block against the exact
  solutions of :mod:`twofluid.verification.sliding_block`. It is exact for a linearly
  interpolated record, so the error is that of the record's interpolation: observed order 2
  (slope of log error against log dt, fitted over 4 halvings, within ±0.15) for a half-sine
  pulse, 1 (±0.15) for a sampled rectangular pulse (its jump is smeared over one step), and
  round-off (1e-12 relative) for a record that is piecewise linear.
"""
import math
import warnings

import numpy as np
import pytest

from twofluid.casefile.schema import CaseError, CaseWarning
from twofluid.geotech import lateral_spread as ls
from twofluid.geotech import settlement
from twofluid.verification import sliding_block as sb


def _one_line_error(excinfo, key):
    msg = str(excinfo.value)
    assert "\n" not in msg and msg.startswith("lateral_spread: ") and key in msg
    return msg


# ---------------------------------------------------------------- Zhang, Robertson & Brachman (2004)

def test_ldi_is_the_depth_integral_of_the_projects_gamma_max():
    """LDI = Σ γ_max h over the rows above 23 m (Zhang et al. 2004, Eq. for LDI), with γ_max the
    Idriss & Boulanger (2008) relation of settlement.max_shear_strain (Dr as a fraction there)."""
    z_top = np.array([0.0, 2.0, 5.0, 20.0])
    z_bot = np.array([2.0, 5.0, 9.0, 26.0])
    fs = np.array([np.inf, 0.9, 1.3, 0.5])
    dr = np.array([70.0, 45.0, 55.0, 40.0])
    ldi, gamma = ls.lateral_displacement_index(z_top, z_bot, fs, dr)
    g_ref = settlement.max_shear_strain(fs, dr / 100.0)
    np.testing.assert_allclose(gamma, g_ref, rtol=1e-15)
    # the last row counts to 23 m only (3 m of its 6 m)
    assert ldi == pytest.approx(0.0 * 2 + g_ref[1] * 3 + g_ref[2] * 4 + g_ref[3] * 3, rel=1e-12)
    # units: Zhang et al. use γ in per cent and z in m, which is a length in cm; here m
    assert 100.0 * ldi == pytest.approx(np.sum(100 * g_ref * np.array([2, 3, 4, 3])), rel=1e-12)
    # hand value of one row: Dr 50 %, FS 1 -> γ_max = 0.035 (F_α = 0.882), 4 m -> 0.14 m
    ldi1, _ = ls.lateral_displacement_index([2.0], [6.0], 1.0, 50.0)
    assert ldi1 == pytest.approx(0.14, rel=1e-12)


def test_ldi_z_max_and_no_strain_above_fs_2():
    ldi, g = ls.lateral_displacement_index([0.0], [10.0], 2.0, 40.0)
    assert ldi == 0.0 and g[0] == 0.0
    full, _ = ls.lateral_displacement_index([0.0], [10.0], 0.9, 40.0)
    half, _ = ls.lateral_displacement_index([0.0], [10.0], 0.9, 40.0, z_max_m=5.0)
    assert half == pytest.approx(0.5 * full, rel=1e-14)


def test_zhang_ground_slope_and_free_face_forms():
    """LD = (S + 0.2) LDI for 0.2 ≤ S ≤ 3.5 % and LD = 6 (L/H)^−0.8 LDI for 4 ≤ L/H ≤ 40
    (Zhang, Robertson & Brachman 2004, the two fitted relations of LD/LDI)."""
    assert ls.zhang2004_ground_slope(1.5, 2.5) == pytest.approx(2.7 * 1.5, rel=1e-15)
    assert ls.zhang2004_free_face(1.5, 4.0) == pytest.approx(6 * 4 ** -0.8 * 1.5, rel=1e-15)
    r = ls.zhang2004([0.0, 3.0], [3.0, 8.0], [np.inf, 0.9], 45.0, slope_percent=3.0)
    assert r.displacement_m == pytest.approx(3.2 * r.ldi_m, rel=1e-15) and r.in_range
    r = ls.zhang2004([0.0, 3.0], [3.0, 8.0], [np.inf, 0.9], 45.0, l_over_h=20.0)
    assert r.form == "free_face" and r.displacement_m == pytest.approx(6 * 20 ** -0.8 * r.ldi_m, rel=1e-15)


def test_zhang_outside_the_fit_warns_or_fails_in_one_line():
    with pytest.warns(CaseWarning, match="S = 5 outside 0.2–3.5"):
        r = ls.zhang2004([0.0], [5.0], 0.9, 45.0, slope_percent=5.0)
    assert not r.in_range and r.displacement_m == pytest.approx(5.2 * r.ldi_m)
    with pytest.raises(CaseError) as e:
        ls.zhang2004_ground_slope(1.0, 0.1, strict=True)
    _one_line_error(e, "slope_percent")
    with pytest.warns(CaseWarning, match="L/H = 50"):
        ls.zhang2004_free_face(1.0, 50.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")        # in range: no warning at all
        ls.zhang2004_ground_slope(1.0, 2.0)


@pytest.mark.parametrize("kwargs, key", [
    (dict(z_top_m=[0.0, 1.0], z_bottom_m=[1.0, 0.5], fs=1.0, dr_percent=50.0), "z_bottom_m"),
    (dict(z_top_m=[-1.0], z_bottom_m=[1.0], fs=1.0, dr_percent=50.0), "z_top_m"),
    (dict(z_top_m=[0.0, 1.0], z_bottom_m=[2.0, 3.0], fs=1.0, dr_percent=50.0), "overlap"),
    (dict(z_top_m=[0.0], z_bottom_m=[1.0], fs=float("nan"), dr_percent=50.0), "fs"),
    (dict(z_top_m=[0.0], z_bottom_m=[1.0], fs=-0.1, dr_percent=50.0), "fs"),
    (dict(z_top_m=[0.0], z_bottom_m=[1.0], fs=1.0, dr_percent=0.5e3), "dr_percent"),
    (dict(z_top_m=[0.0], z_bottom_m=[1.0], fs=[1.0, 1.0], dr_percent=50.0), "fs"),
    (dict(z_top_m=[0.0], z_bottom_m=[1.0], fs=1.0, dr_percent=50.0, z_max_m=30.0), "z_max_m"),
])
def test_ldi_bad_inputs(kwargs, key):
    with pytest.raises(CaseError) as e:
        ls.lateral_displacement_index(**kwargs)
    _one_line_error(e, key)


def test_zhang_needs_exactly_one_geometry():
    for kw in ({}, dict(slope_percent=1.0, l_over_h=10.0)):
        with pytest.raises(CaseError) as e:
            ls.zhang2004([0.0], [1.0], 1.0, 50.0, **kw)
        _one_line_error(e, "exactly one")


# -------------------------------------------------------------- Youd, Hansen & Bartlett (2002)

def test_youd_coefficients_are_the_published_ones():
    """Youd, Hansen & Bartlett (2002), ground-slope MLR: b0 = −16.213, M 1.532, log R* −1.406,
    R −0.012, log S 0.338, log T15 0.540, log(100 − F15) 3.413, log(D50_15 + 0.1) −0.795; R* = R +
    10^(0.89 M − 5.64); the same table is in gem/oq-engine (hazardlib/gsim/youd_etal_2002.py,
    COEFFS_SLOPE) and LiquPy (calc_ls_bartlett, mode 's'); σ_log10 D_H = 0.197."""
    assert ls.YOUD_COEFFS_SLOPE == (-16.213, 1.532, -1.406, -0.012, 0.338, 0.540, 3.413, -0.795)
    assert ls.YOUD_SIGMA_LOG10 == 0.197
    # the ×/÷ 2.5 band is about ±2σ of log10 D_H
    assert 10 ** (2 * ls.YOUD_SIGMA_LOG10) == pytest.approx(ls.YOUD_BAND_FACTOR, rel=0.01)


def test_youd_hand_value_term_by_term():
    """M 7.5, R 10 km, S 1 %, T15 5 m, F15 10 %, D50_15 0.3 mm (Youd et al. 2002, Eq. 6)."""
    r_star = 10.0 + 10 ** (0.89 * 7.5 - 5.64)
    log_d = (-16.213 + 1.532 * 7.5 - 1.406 * math.log10(r_star) - 0.012 * 10.0 + 0.338 * 0.0
             + 0.540 * math.log10(5.0) + 3.413 * math.log10(90.0) - 0.795 * math.log10(0.4))
    r = ls.youd2002_ground_slope(7.5, 10.0, 1.0, 5.0, 10.0, 0.3)
    assert r.r_star_km == pytest.approx(r_star, rel=1e-14)
    assert r.median_m == pytest.approx(10 ** log_d, rel=1e-12)
    assert r.median_m == pytest.approx(4.6375, abs=1e-4)
    assert r.lower_m * 2.5 == pytest.approx(r.median_m) and r.upper_m / 2.5 == pytest.approx(r.median_m)
    assert r.in_range and r.notes == ()


def test_youd_each_site_term_is_its_power_law():
    base = dict(magnitude=7.0, distance_km=20.0, slope_percent=1.0, t15_m=4.0, f15_percent=20.0,
                d50_15_mm=0.2)
    d0 = ls.youd2002_ground_slope(**base).median_m

    def ratio(**change):
        return ls.youd2002_ground_slope(**{**base, **change}).median_m / d0

    assert ratio(slope_percent=2.0) == pytest.approx(2 ** 0.338, rel=1e-12)
    assert ratio(t15_m=8.0) == pytest.approx(2 ** 0.540, rel=1e-12)
    assert ratio(f15_percent=40.0) == pytest.approx((60 / 80) ** 3.413, rel=1e-12)
    assert ratio(d50_15_mm=0.5) == pytest.approx((0.6 / 0.3) ** -0.795, rel=1e-12)
    # distance: both R terms
    r_star = lambda r: r + 10 ** (0.89 * 7.0 - 5.64)     # noqa: E731
    assert ratio(distance_km=40.0) == pytest.approx(
        (r_star(40.0) / r_star(20.0)) ** -1.406 * 10 ** (-0.012 * 20.0), rel=1e-12)
    # magnitude enters through 1.532 M and R*
    assert ratio(magnitude=7.5) == pytest.approx(
        10 ** (1.532 * 0.5) * ((20 + 10 ** (0.89 * 7.5 - 5.64)) / r_star(20.0)) ** -1.406, rel=1e-12)


def test_youd_outside_the_verified_range_warns_or_fails():
    with pytest.warns(CaseWarning, match="M = 5.5 outside 6–8"):
        r = ls.youd2002_ground_slope(5.5, 10.0, 1.0, 5.0, 10.0, 0.3)
    assert not r.in_range and len(r.notes) == 1
    with pytest.raises(CaseError) as e:
        ls.youd2002_ground_slope(7.0, 10.0, 8.0, 5.0, 10.0, 0.3, strict=True)
    msg = _one_line_error(e, "youd2002")
    assert "S [%] = 8 outside 0.1–6" in msg
    with pytest.warns(CaseWarning, match="T15"):
        ls.youd2002_ground_slope(7.0, 10.0, 1.0, 20.0, 10.0, 0.3)


@pytest.mark.parametrize("change, key", [
    (dict(magnitude=float("nan")), "magnitude"), (dict(distance_km=-1.0), "distance_km"),
    (dict(slope_percent=0.0), "slope_percent"), (dict(t15_m=0.0), "t15_m"),
    (dict(f15_percent=100.0), "f15_percent"), (dict(d50_15_mm=0.0), "d50_15_mm"),
    (dict(magnitude="seven"), "magnitude"), (dict(band_factor=0.5), "band_factor"),
])
def test_youd_bad_inputs(change, key):
    args = dict(magnitude=7.0, distance_km=10.0, slope_percent=1.0, t15_m=5.0, f15_percent=10.0,
                d50_15_mm=0.3)
    with pytest.raises(CaseError) as e:
        ls.youd2002_ground_slope(**{**args, **change})
    _one_line_error(e, key)


def test_youd_site_terms_from_a_profile():
    """T15: saturated granular rows with (N1)60 < 15 above 20 m; F15, D50_15 thickness-weighted."""
    t15, f15, d50 = ls.youd2002_site_terms(
        [0.0, 2.0, 5.0, 9.0, 18.0], [2.0, 5.0, 9.0, 12.0, 24.0], [8, 10, 20, 14, 5],
        [False, True, True, True, True], [5.0, 10.0, 30.0, 40.0, 0.0], [0.3, 0.2, 0.1, 0.1, 0.5])
    # rows 1 (3 m), 3 (3 m), 4 (2 m above 20 m); row 0 dry, row 2 too dense
    assert t15 == pytest.approx(8.0)
    assert f15 == pytest.approx((3 * 10 + 3 * 40 + 2 * 0) / 8)
    assert d50 == pytest.approx((3 * 0.2 + 3 * 0.1 + 2 * 0.5) / 8)
    t, f, d = ls.youd2002_site_terms([0.0], [5.0], 30.0, True, 5.0, 0.3)
    assert t == 0.0 and math.isnan(f) and math.isnan(d)
    with pytest.raises(CaseError) as e:
        ls.youd2002_site_terms([0.0], [5.0], 10.0, 1, 5.0, 0.3)
    _one_line_error(e, "saturated")


# ---------------------------------------------------------------------- Newmark sliding block

def test_infinite_slope_statics_hand_values():
    """τ = σ_d sin α cos α, FS_post = S_r/τ, k_y = (S_r − τ)/(σ_v cos²α) = tan α (FS_post − 1)
    when σ_d = σ_v (infinite-slope equilibrium with a normal-stress-independent S_r)."""
    a = math.atan(0.03)
    tau = float(ls.static_shear_stress(80e3, 3.0))
    assert tau == pytest.approx(80e3 * math.sin(a) * math.cos(a), rel=1e-14)
    fs = float(ls.post_liquefaction_fs(4000.0, tau))
    ky = float(ls.yield_coefficient(4000.0, 80e3, 3.0))
    assert ky == pytest.approx((4000.0 - tau) / (80e3 * math.cos(a) ** 2), rel=1e-13)
    assert ky == pytest.approx(0.03 * (fs - 1.0), rel=1e-12)
    # submerged: the buoyant weight drives, the soil's mass resists acceleration
    ky_sub = float(ls.yield_coefficient(4000.0, 80e3, 3.0, sigma_drive_Pa=40e3))
    assert ky_sub == pytest.approx((4000.0 - 40e3 * math.sin(a) * math.cos(a)) / (80e3 * math.cos(a) ** 2),
                                   rel=1e-13)
    np.testing.assert_array_equal(ls.post_liquefaction_fs([1.0, 2.0], [0.0, 1.0]), [np.inf, 2.0])


def _sample(fn, t_end, n):
    t = np.linspace(0.0, t_end, n + 1)
    return t[1] - t[0], fn(t)


def _final(a, dt, ay, history=False):
    a = np.asarray(a, dtype=float)
    d, v = np.zeros(a.size), np.zeros(a.size)
    out = ls.newmark_sliding(a, dt, ay, d, v)
    assert np.all(v >= 0.0) and np.all(np.diff(d) >= -1e-15)    # one way, never backwards
    assert out == d[-1]
    return (out, d, v) if history else out


def _order(errors, dts):
    return np.polyfit(np.log(dts), np.log(errors), 1)[0]


def test_newmark_half_sine_pulse_second_order():
    """Exact: sliding_block.half_sine_pulse_displacement (closed form; block still sliding at the
    end of the pulse for a_y/A = 0.3, stopping within it for a_y/A = 0.8)."""
    for ay in (0.6, 1.6):
        A, w = 2.0, 2.0 * math.pi                    # 0.5 s pulse
        exact = sb.half_sine_pulse_displacement(A, w, ay)
        errs, dts = [], []
        for n in (25, 50, 100, 200, 400):
            dt, a = _sample(lambda t: np.where(t <= 0.5, A * np.sin(w * np.minimum(t, 0.5)), 0.0), 4.0, 8 * n)
            errs.append(abs(_final(a, dt, ay) - exact))
            dts.append(dt)
        assert _order(errs, dts) == pytest.approx(2.0, abs=0.15)
        assert errs[-1] < 1e-4 * exact


def test_newmark_rectangular_pulse_first_order_and_newmark_formula():
    """Newmark (1965): d = A (A − a_y) T²/(2 a_y). A sampled jump is smeared over one step, so the
    error is first order in dt."""
    A, T, ay = 3.0, 0.4, 1.0
    exact = sb.rectangular_pulse_displacement(A, T, ay)
    assert exact == pytest.approx(3 * 2 * 0.16 / 2)
    errs, dts = [], []
    for n in (10, 20, 40, 80, 160):
        dt = T / n
        t = dt * np.arange(int(3.0 / dt) + 1)
        a = np.where(t < T - 1e-12, A, 0.0)
        errs.append(abs(_final(a, dt, ay) - exact))
        dts.append(dt)
    assert _order(errs, dts) == pytest.approx(1.0, abs=0.15)


def test_newmark_is_exact_for_piecewise_linear_records():
    """Refining a piecewise-linear record (inserting its own interpolated midpoints) changes
    nothing: start and stop instants are found exactly within a step."""
    rng = np.random.default_rng(7)
    a = rng.normal(0.0, 2.0, 400)
    dt, ay = 0.01, 0.8
    ref = _final(a, dt, ay)
    assert ref > 0.0
    fine = np.empty(2 * a.size - 1)
    fine[0::2] = a
    fine[1::2] = 0.5 * (a[:-1] + a[1:])
    finer = np.empty(2 * fine.size - 1)
    finer[0::2] = fine
    finer[1::2] = 0.5 * (fine[:-1] + fine[1:])
    assert _final(fine, dt / 2, ay) == pytest.approx(ref, rel=1e-12)
    assert _final(finer, dt / 4, ay) == pytest.approx(ref, rel=1e-12)


def test_newmark_hand_value_and_no_upslope_sliding():
    # doctest record: 37/24 m (hand integration in newmark_sliding's docstring)
    assert _final([2.0, 2.0, 2.0, 0.0, 0.0, 0.0, 0.0], 0.5, 1.0) == pytest.approx(37 / 24, rel=1e-14)
    # one way: a strong pulse pushing upslope (a < 0) and anything below a_y do nothing
    assert _final([0.0, -5.0, -5.0, 0.9, 0.0], 0.1, 1.0) == 0.0
    # restart within one step after a stop: v = 0.025 m/s at t = 2 s, a − a_y rises from −1 to 2
    # over the next second: the block stops at t = 2.026 s and starts again at t = 2.333 s
    a = np.array([1.35, 1.35, 0.0, 3.0, 0.0])
    n = 300
    t_fine = np.linspace(0.0, 4.0, 4 * n + 1)
    fine, d, v = _final(np.interp(t_fine, np.arange(5.0), a), 1.0 / n, 1.0, history=True)
    in_step = (t_fine > 2.0) & (t_fine < 3.0)
    assert np.any(v[in_step] == 0.0) and v[3 * n] > 0.0
    assert _final(a, 1.0, 1.0) == pytest.approx(fine, rel=1e-12)


def test_newmark_kernel_compiles_with_numba(monkeypatch):
    numba = pytest.importorskip("numba")
    rng = np.random.default_rng(3)
    a = rng.normal(0.0, 2.0, 2000)
    d1, v1, d2, v2 = (np.zeros(a.size) for _ in range(4))
    expected = ls.newmark_sliding(a, 0.01, 0.7, d2, v2)
    # the one-way block calls the two-way integrator: compiled, it calls that one compiled
    monkeypatch.setattr(ls, "newmark_sliding_two_way", numba.njit(ls.newmark_sliding_two_way))
    jit = numba.njit(ls.newmark_sliding)
    assert jit(a, 0.01, 0.7, d1, v1) == expected
    np.testing.assert_allclose(d1, d2, rtol=1e-13, atol=1e-15)


def test_newmark_infinite_slope_polarity_scaling_and_start():
    dt = 0.01
    t = dt * np.arange(600)
    pulse = np.where((t > 1.0) & (t < 1.5), 2.0, 0.0)
    s_r, sigma, slope = 3000.0, 100e3, 2.0
    ky = float(ls.yield_coefficient(s_r, sigma, slope))
    # the ground accelerating upslope (negative) pushes the block downslope
    up = ls.newmark_infinite_slope(-pulse, dt, s_r, sigma, slope)
    down = ls.newmark_infinite_slope(pulse, dt, s_r, sigma, slope)
    assert down.displacement_m == 0.0 and up.displacement_m > 0.0
    d, v = np.zeros(t.size), np.zeros(t.size)
    plain = ls.newmark_sliding(pulse, dt, ky * ls.G, d, v)
    cos_a = math.cos(math.atan(0.02))
    assert up.displacement_m == pytest.approx(cos_a * plain, rel=1e-14)
    assert up.horizontal_displacement_m == pytest.approx(cos_a ** 2 * plain, rel=1e-14)
    np.testing.assert_allclose(up.displacement_history_m, cos_a * d, rtol=1e-14)
    # triggering after the pulse: nothing moves
    late = ls.newmark_infinite_slope(-pulse, dt, s_r, sigma, slope, t_start_s=2.0)
    assert late.displacement_m == 0.0
    assert "Newmark" in up.message and "\n" not in up.message


def test_newmark_flow_failure_is_a_result_not_a_number():
    r = ls.newmark_infinite_slope(np.zeros(10), 0.01, 1500.0, 100e3, 2.0)
    assert r.flow_failure and r.displacement_m is None and r.displacement_history_m is None
    assert r.fs_post == pytest.approx(1500.0 / float(ls.static_shear_stress(100e3, 2.0)))
    assert r.k_y <= 0.0 and r.message.startswith("flow failure: FS_post = 0.750")
    assert r.horizontal_displacement_m is None
    # exactly FS_post = 1 is a flow failure too (k_y = 0)
    tau = float(ls.static_shear_stress(100e3, 2.0))
    assert ls.newmark_infinite_slope(np.zeros(10), 0.01, tau, 100e3, 2.0).flow_failure


@pytest.mark.parametrize("args, kwargs, key", [
    (([0.0, float("nan")], 0.01, 1e3, 1e5, 2.0), {}, "ground_accel_m_s2"),
    (([0.0], 0.01, 1e3, 1e5, 2.0), {}, "ground_accel_m_s2"),
    ((np.zeros(5), 0.0, 1e3, 1e5, 2.0), {}, "dt_s"),
    ((np.zeros(5), 0.01, -1.0, 1e5, 2.0), {}, "residual_strength_Pa"),
    ((np.zeros(5), 0.01, 1e3, 0.0, 2.0), {}, "sigma_v_Pa"),
    ((np.zeros(5), 0.01, 1e3, 1e5, 0.0), {}, "slope_percent"),
    ((np.zeros(5), 0.01, 1e3, 1e5, 2.0), dict(sigma_drive_Pa=2e5), "sigma_drive_Pa"),
    ((np.zeros(5), 0.01, 1e3, 1e5, 2.0), dict(t_start_s=-1.0), "t_start_s"),
])
def test_newmark_bad_inputs(args, kwargs, key):
    with pytest.raises(CaseError) as e:
        ls.newmark_infinite_slope(*args, **kwargs)
    _one_line_error(e, key)
