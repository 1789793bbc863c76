"""The 1D column runner (``two_fluid_1d``, ``reduced_1d``): build, steps, consumers, summary.

Output, probes, the progress bar and plots all consume the generator of
:func:`twofluid.timestepping.integrate` from outside the solver.
"""
from __future__ import annotations

import bisect
import copy
import time
import weakref
from dataclasses import replace
from pathlib import Path

import numpy as np

from .. import postprocess as pp
from ..casefile.builder import build
from ..io.results import ResultWriter, write_json, write_resolved_case
from ..timestepping.backward_euler import integrate, picard_step
from ..io.folders import default_out_dir
from .common import RunResult, run_guard

__all__ = ["run_1d"]

PROFILE_COLUMNS = ["y_m", "porosity", "reference_porosity", "P_Pa", "Ps_Pa", "V_m_s", "W_m_s",
                   "Uf_m_s", "Us_m_s"]


def _held_ends(model, state):
    """A shallow copy of the model whose inlets keep their velocity at ``state.t``.

    A copy with other boundaries, not a wrapper of ``dirichlet``: the models' own
    solves (band LU, the reduced model's continuity A V = c(t)) read the boundary
    velocities themselves.
    """
    held = copy.copy(model)
    for side in ("bottom", "top"):
        b = getattr(model, side)
        if b.kind == "inlet":
            setattr(held, side, replace(b, velocity=lambda t, v=b.velocity(state.t): v))
    return held


def _initial_pressure(model, state, dt):
    """P consistent with the initial state: one step of negligible length (1e-6 Δt).

    The inlet is held at its initial velocity for it, so that a step change of
    the inlet at t = 0 does not show up as the pressure impulse of an
    instantaneous acceleration.
    """
    new, _ = picard_step(_held_ends(model, state), state, 1e-6 * dt)
    if new is not None:
        state = state.copy(P=new.P)
    return state


class _Figures:
    """Tracks the case's key heights at every step (cheap: one scan of the porosity)."""

    def __init__(self, case, model, state, n_final=None):
        self.study = case["case"]["study"]
        self.model, self.state0 = model, state
        self.y = model.mesh.centres
        self.y0 = model.mesh.y[0]
        n_bed = state.n[state.n < 1.0]
        self.n0 = pp.median(n_bed) if n_bed.size else 1.0  # the bed, not its cut surface element
        self.thr = 0.5 * (1.0 + self.n0)
        if self.study == "step_change" and case["boundary"]["bottom"]["porosities"]:
            self.thr = 0.5 * (1.0 + max(case["boundary"]["bottom"]["porosities"]))
        elif self.study == "step_change" and n_final is not None and n_final < 1.0:
            self.thr = 0.5 * (1.0 + max(self.n0, n_final))  # the bed after the step (its model equilibrium)
        self.t, self.dp = [], []
        self.keys = ("bed_height_m", "sediment_height_m") if self.study == "settling" else ("bed_height_m",)
        self.columns = tuple([] for _ in self.keys)  # each key's value at every step
        faces = model.mesh.y
        self._faces, self._lengths = faces, faces[1:] - faces[:-1]  # (interface_height's element lengths)
        self._dp = _pressure_drop_terms(model)

    def _heights(self, s) -> tuple[float, ...]:
        if self.study == "settling":  # the settling interfaces keep their definitions (summary "interfaces")
            top = pp.surface_height(self.y, s.n, self.thr, self.y0)
            return top, pp.sediment_height(self.y, s.n, self.n0, top, bottom=self.y0)
        return (pp.interface_height(self._faces, s.n, self.thr, self._lengths),)

    def record(self, s) -> tuple[tuple[float, ...], float]:
        """Record state ``s`` (its time, heights and bed pressure drop); returns (its heights, the drop)."""
        self.t.append(s.t)
        h = self._heights(s)
        for col, v in zip(self.columns, h):
            col.append(v)
        dp = bed_pressure_drop(self.model, s, terms=self._dp)
        self.dp.append(dp)
        return h, dp

    def leading(self, h: tuple[float, ...], dp: float) -> tuple:
        """A probe row's first columns, (name, value) pairs: the heights ``h`` and the drop ``dp`` that
        :meth:`record` returned."""
        return (*zip(self.keys, h), ("bed_pressure_drop_Pa", dp))

    def series(self) -> dict[str, np.ndarray]:
        if not self.t:
            return {}
        return {k: np.array(col) for k, col in zip(self.keys, self.columns)}


def _pressure_drop_terms(model) -> tuple[float, float] | None:
    """(the outlet pressure, the liquid's hydrostatic head from the lowest element's centre to it) [Pa]
    of :func:`bed_pressure_drop`, or None where the outlet is not at the top."""
    if model.top.kind != "outlet":
        return None
    y = model.mesh.y
    return model.top.pressure, -model.mat.rho_f * model.g_y * (y[-1] - 0.5 * (y[1] + y[0]))


def bed_pressure_drop(model, s, f: dict | None = None, terms=False) -> float:
    """Liquid pressure drop over the bed beyond hydrostatic [Pa], from the lowest element to the outlet.

    P at the centre of the lowest element minus the outlet pressure and the liquid's
    hydrostatic head between them; in a fluidized bed it equals the buoyant weight of the
    solids per unit area, (ρ_s − ρ_f) g cos θ V_s/A. NaN when the outlet is not at the top.
    ``f``: the element fields of ``s`` if already computed; ``terms``: the model's
    :func:`_pressure_drop_terms` if already computed (a run's every step).
    """
    if terms is False:
        terms = _pressure_drop_terms(model)
    if terms is None:
        return float("nan")
    if f is not None:
        P0 = float(f["P_Pa"][0])
    else:  # the lowest element's centre alone, as element_fields gives it (every step: no other field)
        P0 = float(s.P[0] if model.p_order == 0 else 0.5 * (s.P[0] + s.P[1]))
    return P0 - terms[0] - terms[1]


_PROBED = ("porosity", "P_Pa", "Ps_Pa", "Us_m_s")  # the fields of a probe, its columns "{name}@{y:g}m"
_PLANS: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()  # model -> (probes, elements, column names)


def _probe_values(model, s, probes, leading):
    """The probe row of state ``s``: ``leading`` ((name, value) pairs: :meth:`_Figures.leading`, the
    heights and the bed pressure drop), then each probe's fields."""
    elements, names = _probe_plan(model, probes)
    vals = dict(leading)
    f = model.element_fields(s, elements)  # at the probes' elements only
    fields = [f[field].tolist() for field in _PROBED]  # (each entry as float() of it gives it)
    for j, keys in enumerate(names):
        for key, field in zip(keys, fields):
            vals[key] = field[j]
    return vals


def _probe_plan(model, probes) -> tuple[np.ndarray, list[tuple[str, ...]]]:
    """(the element of each probe, its column names), worked out once per model and probe list."""
    plan = _PLANS.get(model)
    if plan is None or plan[0] != tuple(probes):
        names = [tuple(f"{name}@{y:g}m" for name in _PROBED) for y in probes]
        elements = _probe_elements(model, probes)
        elements.flags.writeable = False  # (read only: the model keeps what it derives from it, TwoFluid1D.element_mean)
        plan = _PLANS[model] = (tuple(probes), elements, names)
    return plan[1], plan[2]


def _probe_elements(model, probes) -> np.ndarray:
    """The element holding each probe height [m above the bottom] (the top one for the top end)."""
    return np.clip(np.searchsorted(model.mesh.y, np.asarray(probes, dtype=float) + model.mesh.y[0], side="right") - 1,
                   0, model.mesh.n_elements - 1)


def _at_output_time(t: float, out_times: list[float], near: float) -> bool:
    """Whether ``t`` is one of the sorted ``out_times`` (within 1e-9 relative, 1e-9 s below 1 s): the
    test ``any(abs(t - tt) < 1e-9 * max(1.0, tt) for tt in out_times)`` made on the output times within
    ``near`` (1e-9 max(1, the last one)) of ``t`` only, found by bisection (every step asks).

    >>> _at_output_time(2.0 + 1e-12, [0.0, 2.0, 10.0], 1e-8), _at_output_time(2.5, [0.0, 2.0, 10.0], 1e-8)
    (True, False)
    """
    i = bisect.bisect_left(out_times, t - near)
    while i < len(out_times) and out_times[i] <= t + near:
        tt = out_times[i]
        if abs(t - tt) < 1e-9 * max(1.0, tt):
            return True
        i += 1
    return False


def run_1d(case: dict, out_dir=None, progress: bool = False) -> RunResult:
    """The column runner of ``two_fluid_1d`` and ``reduced_1d``."""
    b = build(case)  # before anything is written
    out = Path(out_dir or default_out_dir(case))
    out.mkdir(parents=True, exist_ok=True)
    write_resolved_case(out / "case.resolved.toml", case)
    model, state = b.model, _initial_pressure(b.model, b.state, b.dt)
    bed = _bed_figures(case, model, b)
    n_final = bed.get("expanded", {}).get("model", {}).get("porosity")
    fig = _Figures(case, model, state, n_final)
    probes = case["output"]["probes"]
    lead0 = fig.leading(*fig.record(state))
    probe_cols = list(_probe_values(model, state, probes, lead0))
    writer = ResultWriter(out, PROFILE_COLUMNS, probe_cols, block=True)  # rows written at least once a second
    out_times = sorted(set(case["output"]["times"]) | {0.0, b.t_end})
    near = 1e-9 * max(1.0, out_times[-1])  # the widest tolerance of _at_output_time
    profiles: dict[float, dict] = {}

    def save_profile(s):
        f = model.element_fields(s)
        profiles[round(s.t, 12)] = f
        writer.profile(s.t, f)

    solids0 = model.solids_volume(state)
    outflow = 0.0
    save_profile(state)
    writer.probe(state.t, _probe_values(model, state, probes, lead0))
    interval = case["output"]["probe_interval"]
    next_probe, last_probe = interval, b.t_end - 1e-12
    n_steps, last = 0, state
    outflow_rate, record, leading = model.solids_outflow, fig.record, fig.leading
    wall0 = time.perf_counter()
    with run_guard(b.t_end, progress, writer) as run:
        bar = run.bar
        shown = bar.n  # (the bar's n, kept here as the bar sums it)
        for step in integrate(model, state, b.t_end, b.dt, stops=out_times, settings=b.settings):
            s = step.state
            outflow += step.dt * outflow_rate(s)
            n_steps, last = step.n_steps, s
            h, dp = record(s)
            t = s.t
            if t >= next_probe - 1e-12 or t >= last_probe:  # (the values in probe_cols' order)
                writer.probe_row(t, list(_probe_values(model, s, probes, leading(h, dp)).values()))
                next_probe = t + interval
            if _at_output_time(t, out_times, near):
                save_profile(s)
            dn = t - shown
            bar.update(dn)
            shown += dn
        writer.flush()  # in the guard: a full disk here is a failed run, said in its summary
    status, reason = run.status, run.reason
    wall = time.perf_counter() - wall0
    if status != "completed" and round(last.t, 12) not in profiles:
        save_profile(last)  # the state it stopped at, in profiles.csv too
    summary = _summary(case, b, model, fig, status, reason, last, n_steps, wall,
                       solids0, outflow, bed)
    write_json(out / "summary.json", summary)
    if case["output"]["plots"]:
        _plots(case, fig, profiles, out, summary)
    return RunResult(status, out, summary, profiles, {"t": np.array(fig.t), **fig.series()})


def _bed_figures(case, model, b) -> dict:
    """U_mf, U_t, the initial bed and the expanded bed at the last inlet velocity
    (:func:`twofluid.casefile.bed.bed_figures`), for a column fed through its bottom; {} otherwise."""
    from ..casefile.bed import bed_figures

    if model.bottom.kind != "inlet":
        return {}
    u_end = b.inlet_velocities[-1] if b.inlet_velocities else None
    return bed_figures(model.mesh, case, model.clo, model.mat, model.bottom.velocity(0.0), u_end)


def _summary(case, b, model, fig, status, reason, last, n_steps, wall, solids0, outflow, bed=None):
    solids = model.solids_volume(last)
    balance = (solids - solids0 + outflow) / solids0 if solids0 > 0 else 0.0
    s = {
        "case": case["case"]["name"], "status": status, "stopped_at_s": last.t,
        "reason": reason, "end_time_s": b.t_end, "wall_time_s": wall, "steps": n_steps,
        "element": model.element, "elements": model.mesh.n_elements,
        "solids_volume_m3": {"initial": solids0, "final": solids, "outflow": outflow},
        "solids_volume_balance_error": balance,
        "solids_volume_balance_error_definition":
            "(solids volume now − initial + solids that left through the ends) / initial",
        # the stepper admits n up to 1 + 1e-9 (round-off of an emptied element): clear liquid is n = 1
        "porosity_range": [float(last.n.min()), min(float(last.n.max()), 1.0)],
    }
    ser, t = fig.series(), np.array(fig.t)
    if fig.study == "step_change" and len(t) > 1:
        h = ser["bed_height_m"]
        s["inlet_velocities_m_s"] = list(b.inlet_velocities)
        s["bed_height_initial_m"] = float(h[0])
        s["bed_height_final_m"] = float(h[-1])
        theory = (bed or {}).get("expanded", {}).get("model", {})
        if theory.get("height_m") is not None:
            s["bed_height_theory_final_m"], s["bed_porosity_theory_final"] = theory["height_m"], theory["porosity"]
        t_step = step_time(case)
        s["step_time_s"] = t_step
        s["t1_s"] = pp.t1_from_history(t, h) - t_step if status == "completed" else None
        s["t1_definition"] = ("time from the step (step_time_s: when the inlet schedule starts to change) "
                              "after which the bed surface height stays within 2 % of "
                              "|H_final − H_initial| of its final height; the surface: scanning down from the "
                              "top, the first element whose porosity falls below (1 + max(n_before, n_after))/2 "
                              "holds it, at the height its solids and those above fill at the porosity of the "
                              "element below (twofluid.postprocess.interface_height)")
        dp = np.asarray(fig.dp)
        if np.isfinite(dp).all():
            s["bed_pressure_drop_Pa"] = {"initial": float(dp[0]), "final": float(dp[-1]),
                                         "buoyant_weight_per_area": buoyant_weight_per_area(model, solids0)}
    if bed:
        s["bed"] = bed
    if fig.study == "settling":
        times = sorted(set(case["output"]["times"]) | {0.0, last.t})
        idx = [int(np.argmin(np.abs(t - tt))) for tt in times]
        s["interfaces"] = {
            "definition": ("top: height where the porosity first falls below (1 + n0)/2 scanning "
                           "down; sediment: highest height below it where n < n0 − 0.01"),
            "time_s": [float(t[i]) for i in idx],
            "top_interface_m": [float(ser["bed_height_m"][i]) for i in idx],
            "sediment_interface_m": [float(ser["sediment_height_m"][i]) for i in idx],
        }
    return s


def step_time(case) -> float:
    """When the bottom inlet's schedule starts to change [s] (the step of a step-change study)."""
    b = case["boundary"]["bottom"]
    values = b["velocities"] or b["porosities"]
    for i in range(len(values) - 1):
        if values[i + 1] != values[i]:
            return float(b["times"][i])
    return float(b["times"][0]) if b["times"] else 0.0


def buoyant_weight_per_area(model, solids_volume: float) -> float:
    """(ρ_s − ρ_f) g cos θ V_s / A_bottom [Pa]: the pressure drop a fluidized bed of the solids has."""
    return float((model.mat.rho_s - model.mat.rho_f) * -model.g_y * solids_volume / model.mesh.area[0])


def _plots(case, fig, profiles, out, summary):
    from ..plots.profiles import history_plot, profile_plots

    title = case["case"]["name"]
    profile_plots(profiles, out, title)
    ser = fig.series()
    t = np.array(fig.t)
    if ser:
        labels = {"bed_height_m": "bed surface" if fig.study != "settling" else "top interface",
                  "sediment_height_m": "sediment interface"}
        marks = None
        if summary.get("t1_s") is not None:
            marks = {"t1": (summary["step_time_s"] + summary["t1_s"], f"t1 = {summary['t1_s']:.3g} s after the step")}
        levels = {}
        if summary.get("bed_height_theory_final_m") is not None:
            levels["uniform bed at the final inlet velocity (model equilibrium)"] = summary["bed_height_theory_final_m"]
        rz = summary.get("bed", {}).get("expanded", {}).get("richardson_zaki", {})
        if fig.study == "step_change" and rz.get("height_m") is not None:
            levels["the same by Richardson–Zaki (Khan–Richardson k)"] = rz["height_m"]
        history_plot(t, {labels[k]: v for k, v in ser.items()}, out / "heights.png", title,
                     ylabel="height above the bottom [m]", marks=marks, levels=levels)
    dp = np.asarray(fig.dp)
    if dp.size and np.isfinite(dp).all():
        history_plot(t, {"bed pressure drop ΔP": dp}, out / "bed_pressure_drop.png", title,
                     ylabel="bed pressure drop beyond hydrostatic ΔP [Pa]",
                     scale_after=t[0] + 0.01 * (t[-1] - t[0]),  # the start-up impulse of a step: named, not scaled
                     levels={"buoyant weight of the solids per area": buoyant_weight_per_area(
                         fig.model, float(fig.model.solids_volume(fig.state0)))})
