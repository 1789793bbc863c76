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


def slope_summary(case: dict, col, site, rec, srec: SlopeRecorder, last, simp_run) -> dict:
    """The ``slope`` block of summary.json (docs/outputs.md)."""
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
        "groundwater": "water table parallel to the ground surface, slope-parallel seepage: the total weight "
                       "drives, tau_static = sigma_v sin(alpha) cos(alpha) (a submerged slope: about half)",
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
        "estimates": _estimates(case, col, site, rec, srec, simp_run, e_loc, tau_s, s_r),
    }
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


def _estimates(case, col, site, rec, srec, simp_run, e_loc, tau_s, s_r) -> dict:
    """Zhang et al. (2004) on the simplified table, the Newmark block on the run's own motion at the
    sliding depth, and why Youd et al. (2002) is not given."""
    slope = case["site"]["slope"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        z = ls.zhang2004(simp_run.z_top_m, simp_run.z_bottom_m, simp_run.FS, simp_run.relative_density,
                         slope_percent=slope)
    zhang = {"displacement_m": z.displacement_m, "ldi_m": z.ldi_m, "in_fitted_range": z.in_range,
             "method": "LD = (S + 0.2) LDI, LDI = sum gamma_max(FS, Dr) h over the simplified procedure's rows "
                       "(FS of the 'run' table: level-ground CRR, no K_alpha, as Zhang et al. 2004)"}
    newmark = {"method": "one-way rigid block on the localisation element's residual strength S_r (sigma_v: the "
                         "column's weight above the element's base), driven by the run's absolute acceleration of "
                         "the firm ground under it (the node below the band of liquefied elements that holds it; "
                         "sampled at the vertical steps) from the element's first liquefaction on"}
    first = rec.first
    t0 = first[e_loc] if e_loc < col.n_sat else np.nan
    if not np.isfinite(t0) and np.any(np.isfinite(first)):
        t0 = float(np.nanmin(first))
    if not np.isfinite(t0) or len(srec.acc_t) < 2:
        newmark.update(displacement_m=None, note="not evaluated: nothing liquefied while the shear wave ran")
    else:
        t = np.array(srec.acc_t)
        j = e_loc  # the firm ground: the node below the liquefied band that holds the sliding element
        while 0 < j <= col.n_sat and rec.ever[j - 1]:
            j -= 1
        a = np.array(srec.acc)[:, j]
        dt = float(np.median(np.diff(t)))
        grid = np.arange(t[0], t[-1] + 0.5 * dt, dt)
        a_grid = np.interp(grid, t, a)
        w = col.wave.rho * col.wave.h * col.v.mat.g
        sigma_v = float(w[e_loc:].sum())
        r = ls.newmark_infinite_slope(a_grid, dt, float(s_r[e_loc]), sigma_v, slope, t_start_s=float(t0 - t[0]))
        newmark.update(displacement_m=r.displacement_m, flow_failure=r.flow_failure, k_y_g=r.k_y,
                       fs_post=r.fs_post, triggering_time_s=float(t0), sliding_depth_m=float(
                           col.depth_all[e_loc] + 0.5 * col.wave.h[e_loc]),
                       driving_motion_depth_m=float(col.ground_surface - col.y_all[j]), message=r.message)
    return {"zhang_2004": zhang, "newmark": newmark, "youd_2002": _youd(case, site, simp_run)}


#: largest relative difference between pga_g and the record's own PGA for "unscaled"
UNSCALED = 0.005


def _youd(case, site, simp_run) -> dict:
    """Youd et al. (2002), ground-slope form, with its ×/÷ 2.5 band: only for an unscaled record
    (its M and R are the earthquake's) with ``[ground_motion] distance_km``, and the F15 and D50_15
    of the saturated rows with (N1)60 < 15 given (``fines_content``, ``mean_grain_size``)."""
    from ..casefile import schema_liquefaction as sl
    from ..io import ground_motion as gm

    g = case["ground_motion"]
    out = {"median_m": None, "method": "Youd, Hansen & Bartlett (2002) ground-slope MLR, median x/÷ 2.5; "
           "(N1)60 of the rows taken as their (N1)60cs; T15 over the saturated rows with (N1)60 < 15 "
           "above 20 m, F15 and D50_15 their thickness-weighted fines_content and mean_grain_size"}
    if g["distance_km"] <= 0.0:
        return dict(out, note="not evaluated: [ground_motion] distance_km not given")
    m = gm.load(sl._record_path(case, case.get("_source", "") or "<case>"),
                units=g["units"] if not g["file"].lower().endswith(".at2") else None)
    if g["duration"] > 0.0:
        m = gm.GroundMotion(*(x[m.time <= g["duration"] + 1e-12] for x in (m.time, m.acceleration)), m.name,
                            m.source, m.dt)
    own = m.pga / ls.G
    if abs(g["pga_g"] / own - 1.0) > UNSCALED:
        return dict(out, note=f"not evaluated: the record is scaled (pga_g = {g['pga_g']:g} g, its own PGA "
                              f"{own:.4g} g); Youd et al. depend on the earthquake's M and R, not on the record")
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
    ...       "estimates": {"newmark": {"displacement_m": 0.723}, "zhang_2004": {"displacement_m": 9.8},
    ...                     "youd_2002": {"median_m": None}}}
    >>> print("\\n".join(slope_lines(sl)))
      lateral spreading: surface 0.488 m downslope, 2.5 % of it after the shaking; flow stopped (99 % at 10.1 s, shear wave to 14.4 s)
      beside it: Newmark 0.723 m, Zhang et al. 2004 9.8 m, Youd et al. 2002 not evaluated
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
             f"Zhang et al. 2004 {est['zhang_2004']['displacement_m']:.3g} m",
             "Youd et al. 2002 " + (f"{est['youd_2002']['median_m']:.3g} m" if est["youd_2002"].get("median_m")
                                    is not None else "not evaluated")]
    return [line, "  beside it: " + ", ".join(parts)]
