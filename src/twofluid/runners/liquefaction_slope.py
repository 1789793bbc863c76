"""What a sloping ``liquefaction_1d`` run adds to its results: the lateral displacements, where the
strain localised, the post-liquefaction factor of safety per layer and the engineering estimates
beside them (docs/lateral-spreading.md, docs/outputs.md).

Displacements are downslope, relative to the base, measured from the static state the run starts
at (:meth:`twofluid.models.liquefaction_1d.LiquefactionColumn.lateral_displacement`), never
baseline-corrected; depths are below the ground surface, normal to the slope. The input record
is baseline-corrected before use (:func:`twofluid.io.ground_motion.baseline_correct`: a
least-squares polynomial of ``[ground_motion] baseline_order`` fitted to the integrated velocity
and its derivative removed from the acceleration, before the scaling).

Files (only for a slope > 0):

- ``lateral_displacement.csv`` — the displacement profile at t = 0, the ``[output] times``, the end
  of the shaking, the end of the shear wave and the end of the run: ``time_s`` and one column
  ``u@<depth>m`` per node of the shear column, from the ground surface down;
- ``surface_displacement.csv`` — ``time_s``, ``surface_displacement_m``, ``surface_velocity_m_s``
  (downslope, relative to the base) after every vertical step.
"""
from __future__ import annotations

import math
import warnings

import numpy as np

from ..closures import hysteretic as law
from ..geotech import lateral_spread as ls
from ..io.results import CsvStream
from ..postprocess import median

__all__ = ["SlopeRecorder", "slope_summary", "slope_lines", "MOVING_M_S"]

#: surface velocity [m/s] above which the column counts as still moving when its shear wave stops
MOVING_M_S = 1e-4


class SlopeRecorder:
    """Surface displacement and velocity after every step, the absolute acceleration of every node
    while the shear wave runs (the Newmark block's input), and the displacement profiles."""

    def __init__(self, col, out=None):
        self.col = col
        self.t, self.d, self.v = [], [], []
        self.acc_t, self.acc = [], []
        self.profiles = {}
        z = col.ground_surface - col.y_all  # node depths, bottom first
        self.depths = z[::-1]
        self.stream = None
        if out is not None:
            self.stream = CsvStream(out / "surface_displacement.csv",
                                    ["time_s", "surface_displacement_m", "surface_velocity_m_s"])
            self.prof = CsvStream(out / "lateral_displacement.csv",
                                  ["time_s"] + [f"u@{x:.6g}m" for x in self.depths])

    def record(self, s) -> None:
        col = self.col
        d = col.surface_displacement(s)
        v = float(s.wave.v[-1] - s.wave.v[0]) if s.t <= col.shear_end + 1e-12 else 0.0
        self.t.append(s.t)
        self.d.append(d)
        self.v.append(v)
        if self.stream is not None:
            self.stream.table(np.array([[s.t, d, v]]), ["%.10g", "%.10g", "%.6g"])
        if s.t <= col.shear_end + 1e-12:
            a_in = col.a_g(s.t) if s.t <= col.shaking_end else 0.0
            self.acc_t.append(s.t)
            self.acc.append(a_in + np.asarray(s.wave.a, dtype=float))

    def profile(self, s) -> None:
        key = round(s.t, 9)
        if key in self.profiles:
            return
        u = self.col.lateral_displacement(s)[::-1]
        self.profiles[key] = u
        if self.stream is not None:
            self.prof.table(np.concatenate([[s.t], u])[None, :], ["%.10g"] + ["%.8g"] * u.size)

    def close(self) -> None:
        if self.stream is not None:
            self.stream.close()
            self.prof.close()


def _at(times, values, t) -> float:
    i = int(np.searchsorted(np.asarray(times), t - 1e-9))
    return float(values[min(i, len(values) - 1)]) if values else 0.0


#: the ``groundwater`` text of the summary's ``slope`` block, per [site] groundwater
GROUNDWATER = {
    "slope_parallel_seepage": "slope_parallel_seepage: water table parallel to the ground surface, slope-parallel "
                              "seepage: the total weight drives, tau_static = sigma_v sin(alpha) cos(alpha) (a "
                              "submerged slope: about half)",
    "submerged": "submerged: under still open water, the water table at or above the ground surface: the buoyant "
                 "weight drives, tau_static = sigma'_v sin(alpha) cos(alpha) (tau_static/P_s = tan(alpha), P_s the "
                 "effective stress normal to the slope); the inertia keeps the total mass"}


def slope_summary(case: dict, col, site, rec, srec: SlopeRecorder, last, simp_run, companion=None) -> dict:
    """The ``slope`` block of summary.json (docs/outputs.md); ``companion``: the run's total-stress
    companion call where it kept every node (:func:`total_stress_node_motion`), or None."""
    par, ns = col.hysteretic, col.n_sat
    slope = case["site"]["slope"]
    n0 = col.n0
    tau_s = col.static_shear(n0)
    s_r = par[:, law.P_SR]
    liq = par[:, law.P_LIQ] > 0.0
    fs_post = np.where(liq & (tau_s > 0.0), s_r / np.where(tau_s > 0.0, tau_s, 1.0), np.inf)
    owner = np.concatenate([site.layer_of, site.crust_layer_of])
    layers = []
    for i, la in enumerate(case["layers"]):
        e = np.flatnonzero((owner == i) & liq)
        if not e.size:
            continue
        f = float(fs_post[e].min())
        layers.append({"name": la["name"], "FS_post_min": f, "flow_slide": f <= 1.0,
                       "residual_strength_Pa": [float(s_r[e].min()), float(s_r[e].max())],
                       "static_shear_Pa": [float(tau_s[e].min()), float(tau_s[e].max())],
                       "alpha_static": [float((tau_s[e] / par[e, law.P_SIG0]).min()),
                                        float((tau_s[e] / par[e, law.P_SIG0]).max())],
                       "note": ("flow slide: FS_post <= 1, the liquefied layer cannot carry the static shear on "
                                "its residual strength; the column flows after the shaking until the strength "
                                "returns as the excess pore pressure dissipates or the strain reaches the shear "
                                "law's limiting strain gamma_lim, where cyclic mobility stiffens it "
                                "(flow_after_shaking), on an infinite slope that keeps its geometry and with S_r "
                                "not lowered by void redistribution: a real flow slide can run much further"
                                if f <= 1.0
                                else "FS_post > 1: the residual strength carries the static shear once shaking "
                                "stops")})
    d_end = srec.d[-1]
    d_shake = _at(srec.t, srec.d, col.shaking_end) if col.shaking_end > 0.0 else 0.0
    d_wave = _at(srec.t, srec.d, col.shear_end) if col.shear_end > 0.0 else 0.0
    v_wave = _at(srec.t, srec.v, col.shear_end - 1e-6) if col.shear_end > 0.0 else 0.0
    flow = _flow_block(col, srec, d_end)
    gamma0 = np.diff(col.u_static) / col.wave.h
    strain = np.abs(last.wave.gamma - gamma0)
    e_loc = int(np.argmax(strain))
    depth_all = col.depth_all
    band = strain >= 0.5 * strain[e_loc]
    loc = {"depth_m": float(depth_all[e_loc]), "shear_strain_from_static": float(strain[e_loc]),
           "depth_range_half_peak_m": [float(depth_all[band].min() - 0.5 * col.wave.h[band][np.argmin(depth_all[band])]),
                                       float(depth_all[band].max() + 0.5 * col.wave.h[band][np.argmax(depth_all[band])])],
           "layer": case["layers"][int(owner[e_loc])]["name"],
           "definition": "the element with the largest |gamma_end - gamma_static| (shear strain gained since "
                         "the static start); the range: elements with at least half of it"}
    out = {
        "slope_percent": slope, "angle_deg": math.degrees(math.atan(slope / 100.0)),
        "groundwater": GROUNDWATER[case["site"]["groundwater"]],
        "displacement_definition": "downslope, relative to the base, from the static state at t = 0; never "
                                   "baseline-corrected (the input record is: [ground_motion] baseline_order)",
        "surface_displacement_end_m": d_end,
        "surface_displacement_end_of_shaking_m": d_shake,
        "surface_displacement_end_of_shear_wave_m": d_wave,
        "share_after_shaking": None if d_end == 0.0 else (d_end - d_shake) / d_end,
        "surface_velocity_end_of_shear_wave_m_s": v_wave,
        "still_moving_when_shear_wave_stopped": (abs(v_wave) > MOVING_M_S if flow is None
                                                 else not flow["flow_stopped"]),
        "flow_after_shaking": flow,
        "localisation": loc,
        "layers": layers,
        "estimates": _estimates(case, col, site, rec, srec, simp_run, e_loc, tau_s, s_r, companion),
    }
    out["beyond_measured_spreads"] = _beyond_field(d_end, layers, out["estimates"][ZHANG_KEY]["displacement_m"])
    if out["still_moving_when_shear_wave_stopped"]:
        if flow is None:
            out["note"] = (f"the surface still moved at {v_wave:.3g} m/s when the shear wave stopped: the "
                           "displacement is a lower bound; raise [shear_wave] free_vibration")
        elif col.flow_stopped is False:
            out["note"] = (f"the column still flowed (mean surface velocity {flow['flow_velocity_end_m_s']:.3g} m/s) "
                           f"when the shear wave stopped at {col.shear_end:g} s, [shear_wave] flow_max after the "
                           "record's end: the displacement is a lower bound")
        else:
            out["note"] = (f"the run ended at {last.t:g} s while the shear wave still ran (the flow had not been "
                           "found stopped): the displacement is a lower bound; raise [time] end")
    return out


def _settled_time(t, d, d_end: float, fraction: float) -> float | None:
    """The first time [s] after which the displacement stays within (1 − fraction)|d_end| of d_end."""
    t, d = np.asarray(t), np.asarray(d)
    if d_end == 0.0 or t.size == 0:
        return None
    off = np.flatnonzero(np.abs(d - d_end) > (1.0 - fraction) * abs(d_end))
    return float(t[0]) if off.size == 0 else float(t[min(off[-1] + 1, t.size - 1)])


def _flow_block(col, srec: SlopeRecorder, d_end: float) -> dict | None:
    """How the flow after the shaking ended (the column's :class:`~twofluid.models.liquefaction_1d.FlowStop`
    criterion), or None where it is off (``flow_velocity = 0``, no shaking)."""
    f = col.flow
    if f is None:
        return None
    t95, t99 = (_settled_time(srec.t, srec.d, d_end, q) for q in (0.95, 0.99))
    v = col.flow_velocity_end
    return {
        "criterion": (f"after free_vibration the shear wave runs on while |v_mean| >= {f.velocity:g} m/s, v_mean = "
                      f"(D(t - T, t) - D(t - 2T, t - T))/T, D the time mean of the surface displacement over T = "
                      f"{f.window:g} s; at most {f.max_after:g} s after the record's end; step growing x1.5 to "
                      f"{f.step:g} s while it flows"),
        "flow_stopped": col.flow_stopped is True,
        "shear_wave_stopped_by": ("the criterion: the flow had stopped" if col.flow_stopped is True else
                                  "flow_max: the column still flowed" if col.flow_stopped is False else
                                  "the end of the run: the shear wave still ran"),
        "shear_wave_end_s": col.shear_end,
        "shear_wave_end_after_shaking_s": col.shear_end - col.shaking_end,
        "flow_velocity_end_m_s": v,
        "time_95_percent_s": t95, "time_99_percent_s": t99,
        "time_definition": "time_X_percent_s: the first time after which the surface displacement stays within "
                           "(100 - X) % of its final value",
    }


#: no measured ground-slope spread in the Youd et al. (2002) database exceeds this [m]
FIELD_MAX_M = 5.4
#: name of the strain-potential estimate: Zhang et al.'s (2004) LD = (S + 0.2) LDI with the γ_max(FS, Dr)
#: of Idriss & Boulanger (2008), not Zhang et al.'s own γ_max curves
ZHANG_KEY = "zhang_2004_ib_gamma_max"
ZHANG_NAME = "Zhang 2004 with I&B gamma_max"


def total_stress_node_motion(case: dict, polarity: int, one_call: bool = True, companion=None):
    """(t [s], absolute acceleration [m/s²] of every node, bottom first) of the total-stress
    companion of ``case`` (every layer ``liquefiable = false``, n̄ held: the column without
    pore-pressure generation, as :func:`twofluid.runners.liquefaction.total_stress_surface`) with
    the record's sign ``polarity``, run to the end of its shear wave in steps of the record's
    sample interval (at least the shear sub-step), sampled after each step. None without shaking.

    With ``one_call`` (the default) the whole wave is one call of the compiled sub-steps where that
    repeats the steps' sub-steps (:mod:`twofluid.runners.liquefaction_total_stress`): the same
    accelerations to far below Newton's tolerance (the sub-steps' times summed from the start instead
    of from each step's, and Newton's iterations stopped by their rate of contraction as well;
    tests/unit/test_total_stress_nodes.py); ``companion``, the run's own companion call
    (:class:`~twofluid.runners.liquefaction_total_stress.WholeWave`), serves where it is that call
    (the same polarity and count of sub-steps). Otherwise, or with ``one_call=False``, the column
    runs step by step."""
    from . import liquefaction_total_stress as ts
    from .liquefaction import total_stress_column

    b = total_stress_column(case, polarity)
    if b is None:
        return None
    col = b.column
    dt = max(col.shear_step, float(b.motion.dt) if b.motion.dt else b.dt)
    plan = ts.plan(col, b.state, dt) if one_call and col.hysteretic is not None else None
    if plan is not None:
        w = companion
        if w is None or w.polarity != int(polarity) or w.times.size != plan[0]:
            r = ts.one_call(col, b.state, plan[0], True)
            w = None if r is None else ts.WholeWave(*r, int(polarity))
        if w is not None:
            return w.rows(round(col.shear_end / dt))
    s = b.state
    t, a = [s.t], [np.zeros(len(s.wave.a))]
    for step in col.run(s, col.shear_end, dt, dt):
        s = step.state
        a_in = col.a_g(s.t) if s.t <= col.shaking_end + 1e-12 else 0.0
        t.append(s.t)
        a.append(a_in + np.asarray(s.wave.a, dtype=float))
    return np.array(t), np.array(a)


TWO_WAY_METHOD = ("two-way rigid block, a diagnostic beside newmark: the same depth, S_r, drive and polarities, "
                  "sliding downslope on k_y = (S_r - tau_static)/(sigma_v cos^2 a) and upslope on "
                  "k_y_up = (S_r + tau_static)/(sigma_v cos^2 a); displacements signed, positive downslope")


def _newmark(case, col, rec, s_r, companion=None) -> dict:
    """The Newmark block on S_r at the liquefied element of least k_y, driven by the total-stress
    companion's absolute acceleration at that element's base, for both polarities of the record;
    beside it (a diagnostic, under the key ``_two_way``) the two-way block on the same depth and drive."""
    slope = case["site"]["slope"]
    out = {"method": "one-way rigid block on the residual strength S_r of the liquefied element (r_u >= 0.95 in "
                     "this run) with the least yield coefficient k_y (sigma_v: the column's weight above the "
                     "element's base), driven by the absolute acceleration at that depth of the total-stress "
                     "companion run (every layer liquefiable = false: independent of the effective-stress law), "
                     "from the element's first liquefaction in this run on; the record run with both polarities, "
                     "displacement_m their mean"}
    ns = col.n_sat
    liq = np.flatnonzero(np.asarray(rec.ever[:ns], dtype=bool))
    if not liq.size:
        note = "not evaluated: nothing liquefied while the shear wave ran"
        return dict(out, displacement_m=None, note=note, _two_way={"method": TWO_WAY_METHOD, "displacement_m": None,
                                                                     "note": note})
    w = col.wave.rho * col.wave.h * col.v.mat.g
    sigma_v = np.cumsum(w[::-1])[::-1]  # weight above each element's base [Pa]
    sigma_d = sigma_v  # the weight that drives: the total (slope-parallel seepage) ...
    if col.rho_b != 0.0:  # ... or the buoyant (a submerged slope: no crust, every element saturated)
        wd = w.copy()
        wd[:ns] -= col.rho_b * col.wave.h[:ns] * col.v.mat.g
        sigma_d = np.cumsum(wd[::-1])[::-1]
        out["method"] += ("; a submerged slope: the buoyant weight above the element's base drives "
                          "(sigma_drive = sigma'_v), the total weight is the inertia")
    k_y = ls.yield_coefficient(s_r[liq], sigma_v[liq], slope, sigma_d[liq])
    e = int(liq[int(np.argmin(k_y))])
    first = np.asarray(rec.first, dtype=float)
    t0 = float(first[e]) if np.isfinite(first[e]) else float(np.nanmin(first[:ns]))
    depth = float(col.ground_surface - col.y_all[e])
    out.update(sliding_depth_m=depth, triggering_time_s=t0, k_y_g=float(k_y.min()),
               fs_post=float(ls.post_liquefaction_fs(s_r[e], ls.static_shear_stress(sigma_d[e], slope))))
    two = {"method": TWO_WAY_METHOD, "sliding_depth_m": depth}
    if k_y.min() <= 0.0:
        msg = f"flow failure: k_y = {k_y.min():.4f} g <= 0 at {depth:g} m (FS_post <= 1)"
        return dict(out, displacement_m=None, flow_failure=True, message=msg,
                    _two_way=dict(two, displacement_m=None, flow_failure=True, message=msg))
    pol = int(case["ground_motion"]["polarity"])
    by, by2, k_up = {}, {}, None
    for p in (pol, -pol):
        try:
            t, a = total_stress_node_motion(case, p, companion=companion)
        except (ArithmeticError, ValueError, RuntimeError) as exc:  # StepFailure is a RuntimeError
            note = f"not evaluated: the total-stress companion failed ({exc})"
            return dict(out, displacement_m=None, note=note, _two_way=dict(two, displacement_m=None, note=note))
        dt = median(np.diff(t))  # (np.median's value, without its import of numpy.ma)
        grid = np.arange(0.0, t[-1] + 0.5 * dt, dt)
        acc = np.interp(grid, t, a[:, e])
        args = (acc, dt, float(s_r[e]), float(sigma_v[e]), slope)
        r = ls.newmark_infinite_slope(*args, sigma_drive_Pa=float(sigma_d[e]), t_start_s=t0)
        r2 = ls.newmark_infinite_slope(*args, sigma_drive_Pa=float(sigma_d[e]), t_start_s=t0, two_way=True)
        by[str(p)] = r.displacement_m
        by2[str(p)] = r2.displacement_m
        k_up = r2.k_y_up
    mean = 0.5 * (by["1"] + by["-1"])
    mean2 = 0.5 * (by2["1"] + by2["-1"])
    two.update(displacement_m=mean2, displacement_by_polarity_m=by2, flow_failure=False, k_y_g=float(k_y.min()),
               k_y_up_g=k_up, message=f"two-way Newmark sliding block on S_r at {depth:g} m, k_y = {k_y.min():.4f} g "
                                      f"downslope, {k_up:.4f} g upslope: {by2['1']:.3g} m (polarity 1), "
                                      f"{by2['-1']:.3g} m (polarity -1), mean {mean2:.3g} m along the slope")
    return dict(out, displacement_m=mean, displacement_by_polarity_m=by, flow_failure=False,
                message=f"Newmark sliding block on S_r at {depth:g} m, k_y = {k_y.min():.4f} g: {by['1']:.3g} m "
                        f"(polarity 1), {by['-1']:.3g} m (polarity -1), mean {mean:.3g} m along the slope",
                _two_way=two)


def _estimates(case, col, site, rec, srec, simp_run, e_loc, tau_s, s_r, companion=None) -> dict:
    """Zhang et al.'s (2004) LD with I&B's γ_max on the simplified table, the Newmark block on the
    total-stress companion's motion, and Youd et al. (2002) where M and R apply."""
    slope = case["site"]["slope"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        z = ls.zhang2004(simp_run.z_top_m, simp_run.z_bottom_m, simp_run.FS, simp_run.relative_density,
                         slope_percent=slope)
    zhang = {"name": ZHANG_NAME, "displacement_m": z.displacement_m, "ldi_m": z.ldi_m,
             "in_fitted_range": z.in_range,
             "method": "a second estimate: Zhang et al.'s (2004) LD = (S + 0.2) LDI, LDI = sum gamma_max(FS, Dr) h "
                       "over the simplified procedure's rows (FS of the 'run' table: level-ground CRR, no K_alpha), "
                       "with gamma_max(FS, Dr) of Idriss & Boulanger (2008), not Zhang et al.'s own curves"}
    one_way = _newmark(case, col, rec, s_r, companion)
    two_way = one_way.pop("_two_way")
    return {ZHANG_KEY: zhang, "newmark": one_way, "newmark_two_way": two_way, "youd_2002": _youd(case, site, simp_run)}


def _beyond_field(d_end: float, layers: list, zhang_m: float) -> dict:
    """The flag for a column that spreads further than any measured ground-slope spread without a
    flow slide: FS_post > 1 in every liquefied layer and d_end > max(Zhang, 5.4 m)."""
    limit = max(float(zhang_m), FIELD_MAX_M)
    flag = bool(layers) and all(not la["flow_slide"] for la in layers) and d_end > limit
    return {"flag": flag, "limit_m": limit,
            "definition": f"FS_post > 1 in every liquefied layer and the surface displacement above max({ZHANG_NAME}, "
                          f"{FIELD_MAX_M:g} m): no measured ground-slope spread in the Youd et al. (2002) database "
                          f"exceeds {FIELD_MAX_M:g} m"}


#: the scale factors (pga_g over the record's own PGA) within which a record stands for its case's M and R
SCALE_RANGE = (0.5, 2.0)


def _youd(case, site, simp_run) -> dict:
    """Youd et al. (2002), ground-slope form, with its ×/÷ 2.5 band, for the earthquake the case states
    (``[ground_motion] magnitude`` and ``distance_km``), where the record is scaled by a factor within
    0.5–2 (a record chosen near that M and R and scaled to a ground-motion model's median PGA there) and
    the F15 and D50_15 of the saturated rows with (N1)60 < 15 are given (``fines_content``,
    ``mean_grain_size``)."""
    from ..casefile import schema_liquefaction as sl
    from ..io import ground_motion as gm

    g = case["ground_motion"]
    out = {"median_m": None, "method": "Youd, Hansen & Bartlett (2002) ground-slope MLR, median x/÷ 2.5, at the "
           "case's [ground_motion] magnitude and distance_km; (N1)60 of the rows taken as their (N1)60cs; T15 "
           "over the saturated rows with (N1)60 < 15 above 20 m, F15 and D50_15 their thickness-weighted "
           "fines_content and mean_grain_size"}
    if g["distance_km"] <= 0.0:
        return dict(out, note="not evaluated: [ground_motion] distance_km not given")
    m = gm.load(sl._record_path(case, case.get("_source", "") or "<case>"),
                units=g["units"] if not g["file"].lower().endswith(".at2") else None)
    if g["duration"] > 0.0:
        m = gm.GroundMotion(*(x[m.time <= g["duration"] + 1e-12] for x in (m.time, m.acceleration)), m.name,
                            m.source, m.dt)
    factor = g["pga_g"] / (m.pga / ls.G)
    out["scale_factor"] = factor
    lo, hi = SCALE_RANGE
    if not lo <= factor <= hi:
        return dict(out, note=f"not evaluated: the record is scaled by {factor:.3g}, outside {lo:g}-{hi:g}; "
                              "Youd et al. depend on the earthquake's M and R, which such a record no longer stands for")
    layers = case["layers"]
    owner = np.concatenate([site.layer_of, site.crust_layer_of])
    fines = np.array([layers[i]["fines_content"] for i in owner])
    d50 = np.array([layers[i]["mean_grain_size"] for i in owner]) * 1e3
    sat = np.arange(owner.size) < site.layer_of.size  # the rows below the water table (column order)
    need = sat & (simp_run.N1_60cs < 15.0)
    missing = sorted({layers[i]["name"] for i in owner[need & (d50 <= 0.0)]})
    if missing:
        return dict(out, note="not evaluated: mean_grain_size not given for " + ", ".join(missing))
    t15, f15, d15 = ls.youd2002_site_terms(simp_run.z_top_m, simp_run.z_bottom_m, simp_run.N1_60cs, sat, fines,
                                           np.where(d50 > 0.0, d50, 1.0))
    if t15 == 0.0:
        return dict(out, median_m=0.0, note="T15 = 0: no saturated granular row with (N1)60 < 15")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = ls.youd2002_ground_slope(g["magnitude"], g["distance_km"], case["site"]["slope"], t15, f15, d15)
    return dict(out, median_m=r.median_m, lower_m=r.lower_m, upper_m=r.upper_m, t15_m=t15, f15_percent=f15,
                d50_15_mm=d15, in_verified_range=r.in_range, range_notes=list(r.notes))


def slope_lines(sl: dict) -> list[str]:
    """What ``twofluid run`` prints of a summary's ``slope`` block: the surface displacement, its share
    after the shaking, how the flow ended, and the estimates beside it.

    >>> sl = {"surface_displacement_end_m": 0.4876, "share_after_shaking": 0.0255,
    ...       "flow_after_shaking": {"flow_stopped": True, "shear_wave_end_s": 14.44, "time_99_percent_s": 10.14},
    ...       "estimates": {"newmark": {"displacement_m": 0.723}, ZHANG_KEY: {"displacement_m": 9.8},
    ...                     "youd_2002": {"median_m": None}}}
    >>> print("\\n".join(slope_lines(sl)))
      lateral spreading: surface 0.488 m downslope, 2.5 % of it after the shaking; flow stopped (99 % at 10.1 s, shear wave to 14.4 s)
      beside it: Newmark 0.723 m, Zhang 2004 with I&B gamma_max 9.8 m, Youd et al. 2002 not evaluated
    """
    d, share, f = sl["surface_displacement_end_m"], sl["share_after_shaking"], sl.get("flow_after_shaking")
    line = f"  lateral spreading: surface {d:.3g} m downslope"
    if share is not None:
        line += f", {100.0 * share:.2g} % of it after the shaking"
    if f is not None:
        t99 = f.get("time_99_percent_s")
        when = f"shear wave to {f['shear_wave_end_s']:.3g} s" if f.get("shear_wave_end_s") is not None else ""
        line += ("; flow stopped (" + (f"99 % at {t99:.3g} s, " if t99 is not None else "") + when + ")"
                 if f["flow_stopped"] else "; still flowing when the shear wave stopped: a lower bound")
    est = sl["estimates"]
    nm = est["newmark"]
    parts = ["Newmark " + ("flow failure" if nm.get("flow_failure") else f"{nm['displacement_m']:.3g} m"
                          if nm.get("displacement_m") is not None else "not evaluated"),
             f"{ZHANG_NAME} {est[ZHANG_KEY]['displacement_m']:.3g} m",
             "Youd et al. 2002 " + (f"{est['youd_2002']['median_m']:.3g} m" if est["youd_2002"].get("median_m")
                                    is not None else "not evaluated")]
    lines = [line, "  beside it: " + ", ".join(parts)]
    if sl.get("beyond_measured_spreads", {}).get("flag"):
        lines.append(f"  flag: FS_post > 1 yet the surface moved more than {sl['beyond_measured_spreads']['limit_m']:.3g} m, "
                     "beyond every measured ground-slope spread")
    return lines
