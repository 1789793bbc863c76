"""Run a ``two_fluid_2d`` case: build mesh and model, step, write fields, profiles, summary, plots.

Outputs in ``out_dir``: ``case.resolved.toml``; ``fields.pvd`` + ``fields_NNNN.vtu``
(ParaView, every [output] time); ``profiles.csv`` (horizontal/radial profiles at the
[profiles] heights, long format); ``steps.csv`` (one row per step: Δt, iterations,
rates and changes of the fields, linear-solver counts, U_f along the axis at the
[profiles] heights; after a fallback from pseudo-transient continuation to the transient
the step count goes on and the time starts again from 0); ``summary.json``; PNGs (``porosity.png``,
``velocity.png``, ``profiles.png``, and ``single_fluid.png`` with the annulus check).
Ctrl-C or a step that cannot be made keeps what was written; the summary says
where the run stopped. ``[time] stepping = "pseudo_transient"`` replaces the
transient stepper by pseudo-transient continuation to the steady state
(:func:`pseudo_transient`).
"""
from __future__ import annotations

import time
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from ..casefile.builder import Schedule, closures, inlet_velocities, materials, settled_reference_porosity
from ..casefile.mesh_2d import BOUNDARY_NAMES, build_mesh, element_row, uncovered_edges
from ..casefile.schema import CaseError, CaseWarning
from ..casefile.validity import drag_validity_warnings
from ..io.fields import FieldWriter
from ..io.folders import default_out_dir
from ..io.results import CsvStream, check_finite, write_json, write_resolved_case
from ..mesh.quad import QuadMesh
from ..models.two_fluid_1d import State
from ..models.two_fluid_2d import Boundary2D, TwoFluid2D
from . import viscometer
from .common import RunResult, run_guard
from ..timestepping.backward_euler import (PicardSettings, Step, StepFailure, integrate, picard_step,
                                          relative_change)

__all__ = ["build_mesh", "build_2d", "Built2D", "run_2d", "horizontal_profile", "pseudo_transient",
           "SteadySteps"]

#: [m/s] velocity scale floor of the steady-state measures (rates, change per step, the
#: pseudo-transient Δt growth): they compare a flow with itself down to this speed, unlike the
#: Picard test, whose floor (``TwoFluid2D.velocity_floor``) sits above the solver's round-off
STEADY_VELOCITY_FLOOR = 1e-9


@dataclass
class Built2D:
    model: TwoFluid2D
    state: State
    t_end: float
    dt: float
    settings: PicardSettings


def build_2d(case: dict) -> Built2D:
    """Model, initial state (bed at rest in the initial inflow, P from a tiny step) and settings."""
    src = case.get("_source", "<case>")
    mesh = build_mesh(case)
    mat = materials(case)
    clo = closures(case, mat)
    bcs, inlet_speeds, inlet_porosities = [], [], []
    for name in BOUNDARY_NAMES:
        b = case["boundary"][name]
        if b["kind"] == "none":
            continue
        group = b["group"] or name
        if group not in mesh.boundaries:
            raise CaseError(src, f"[boundary.{name}] group", f"mesh has no boundary group {group!r}; "
                            f"groups: {', '.join(sorted(mesh.boundaries))}")
        vel = None
        if b["kind"] == "inlet":
            speeds = inlet_velocities(b, clo, mat)
            vel = Schedule(tuple(b["times"]), speeds)
            inlet_speeds += list(speeds)
            inlet_porosities += b["porosities"]
        bcs.append(Boundary2D(group, b["kind"], velocity=vel, solids_velocity=b["solids_velocity"],
                              pressure=b["pressure"], omega=b["omega"],
                              free_slip=b["tangential"] == "free_slip"))
    drag_validity_warnings(case, clo, mat, inlet_speeds, [case["initial"]["porosity"]] + inlet_porosities)
    missing = uncovered_edges(mesh, [b.group for b in bcs])
    if missing:
        raise CaseError(src, "[boundary.*]", f"{missing} boundary edges have no condition; mesh groups: "
                        f"{', '.join(sorted(mesh.boundaries))}")
    nm = case["numerics"]
    try:
        model = TwoFluid2D(mesh, mat, clo, bcs, swirl=case["mesh"]["swirl"],
                           delta=nm["stabilisation_delta"], solids_flux=nm["solids_flux"],
                           solver=nm["linear_solver"])
    except ValueError as exc:
        raise CaseError(src, "[boundary.*]", str(exc)) from None
    tm = case["time"]
    settings = PicardSettings(tol=tm["picard_tol"], max_iter=tm["picard_max_iter"],
                              dt_min=min(1e-7, tm["step"] * 1e-4))
    return Built2D(model, initial_state(model, case, settings), tm["end"], tm["step"], settings)


def initial_state(model: TwoFluid2D, case: dict, settings: PicardSettings | None = None) -> State:
    """Bed of ``[initial] porosity`` up to ``bed_height`` (clear liquid above), V = W = inflow,
    P from :func:`steady_flow` with the case's Picard ``settings``."""
    init, mesh = case["initial"], model.mesh
    yc = mesh.points[mesh.cells].mean(axis=1)[:, 1]
    y0 = mesh.points[:, 1].min()
    h = init["bed_height"] if init["bed_height"] > 0 else np.inf
    n = np.where(yc - y0 < h, init["porosity"], 1.0)
    n_bar = np.full(model.ne, case["closures"]["solids_pressure"]["reference_porosity"])
    if init["state"] == "settled":
        settled_reference_porosity(n_bar, n, model.settled_solids_pressure(n), model.clo, model.mat)
    V, W = np.zeros(model.nv), np.zeros(model.nv)
    model._node_porosity = model.nodal_porosity(n)  # rotating walls: W_θ = (2n − 1)ωr
    idx, val = model.dirichlet(0.0)
    half = idx.size // 2
    vy = val[:half][idx[:half] // model.nn == 1]
    wy = val[half:][idx[:half] // model.nn == 1]
    if vy.size and np.abs(vy).max() > 0:  # plug flow at the inflow velocity
        V[model.nn:2 * model.nn] = vy[np.argmax(np.abs(vy))]
        W[model.nn:2 * model.nn] = wy[np.argmax(np.abs(vy))]
    state = State(0.0, V, W, np.zeros(model.ne), n, n_bar)
    state.V[idx[:half]] = val[:half]
    state.W[idx[:half]] = val[half:]
    return steady_flow(model, state, settings or PicardSettings(tol=case["time"]["picard_tol"],
                                                             max_iter=case["time"]["picard_max_iter"]))


def steady_flow(model: TwoFluid2D, state: State, settings: PicardSettings = PicardSettings()) -> State:
    """V, W, P in equilibrium with the porosity of ``state`` (n frozen; a step of 10⁶ s), solved
    to ``settings`` (the case's ``picard_tol`` and ``picard_max_iter`` in a run)."""
    model.freeze_porosity = True
    try:
        new, info = picard_step(model, state, 1e6, settings)
    finally:
        model.freeze_porosity = False
        model.linear.lu = None
    if new is None:
        raise StepFailure(state.t, 1e6, f"initial flow field: {info}", state)
    return state.copy(V=new.V, W=new.W, P=new.P)


#: pseudo-transient continuation is declared stalled after this many steps without a tenfold
#: drop of its change per step, max(|Δn|, |ΔV|/|V|max) (a continuation that works drops it a
#: decade in at most 12 steps in the runs of docs/benchmarks_2d.md)
STALL_STEPS = 25
#: pseudo-transient trust region: a step longer than the first Δt that changes some element's solids
#: fraction 1 − n by more than this share of it (of 0.01 at least) is retried with half the Δt
MAX_SOLIDS_CHANGE = 0.1


def pseudo_transient(model: TwoFluid2D, state: State, t_end: float, dt: float, dt_max: float,
                     settings: PicardSettings, grow: float = 2.0,
                     iterations: int = 0, stall_steps: int = STALL_STEPS,
                     max_solids_change: float = MAX_SOLIDS_CHANGE):
    """Backward Euler with switched evolution relaxation (SER): Δt grows as the fields settle.

    After each converged step Δt ← Δt · min(``grow``, r_prev / r), r the relative rate
    of change max(|Δn|, |ΔV|/|V|max)/Δt (the steady residual of the discrete
    equations, scaled by their mass matrix), kept within [``dt``, ``dt_max``]; not
    grown after a step that needed more than ``settings.easy_iters`` iterations;
    halved (down to ``settings.dt_min``) when a step fails. Backward Euler is
    unconditionally stable, so once Δt is far above the slowest relaxation time each
    step is a (modified) Newton step on the steady equations: for the steady state
    only, not for the transient. ``iterations`` > 0: at most that many Newton
    iterates per step, the last one taken even if not converged (one per step is
    the classic choice, Kelley & Keyes 1998); 0: each step converged to
    ``settings.tol``. Yields :class:`Step` as ``integrate``.

    Trust region: a step longer than ``dt`` that changes some element's solids fraction
    1 − n by more than ``max_solids_change`` of it (of 0.01 at least) is retried with
    half the Δt (0: off). An element-wise porosity error of 1e-3 in a suspension at
    n = 0.97 already lies outside Newton's region of convergence (docs/benchmarks_2d.md).

    Stall: when the smallest change per step, max(|Δn|, |ΔV|/|V|max), has not dropped
    tenfold within ``stall_steps`` steps (0: never), the generator stops and returns the
    reason (``StopIteration.value``). The change, not the rate: with unconverged iterates
    the rate falls as Δt grows even when the change does not. It is the safety net for
    a case whose iterates the trust region does not keep inside Newton's region of
    convergence; the caller then falls back to the transient (:class:`SteadySteps`).
    """
    eps = 1e-9 * max(dt, 1e-12)
    h, n_steps, prev = dt, 0, None
    best, since = np.inf, 0
    while state.t < t_end - eps:
        h_try = min(h, t_end - state.t)
        if iterations > 0:
            new, info = picard_step(model, state, h_try, replace(settings, max_iter=iterations),
                                    accept_unconverged=True)
        else:
            new, info = picard_step(model, state, h_try, settings)
        if new is None:
            if h_try / 2 < settings.dt_min:
                raise StepFailure(state.t, h_try, info, state)
            h = h_try / 2
            prev = None
            continue
        if max_solids_change > 0.0 and h_try > dt * (1.0 + 1e-9) and np.max(
                np.abs(new.n - state.n) / np.maximum(1.0 - state.n, 0.01)) > max_solids_change:
            h = h_try / 2  # outside the trust region: the same step, shorter
            continue
        n_steps += 1
        c = max(relative_change(model, new, state, floor=STEADY_VELOCITY_FLOOR))
        r = c / h_try
        if prev is not None and r > 0.0:
            h = h_try * min(grow, prev / r)
        if info > settings.easy_iters:
            h = min(h, h_try)
        h = min(max(h, dt), dt_max)
        prev, state = r, new
        yield Step(state.t, h_try, info, state, n_steps)
        if c < best / 10.0 or best == np.inf:
            best, since = c, 0
        else:
            since += 1
        if stall_steps and since >= stall_steps:
            return (f"pseudo-transient continuation stalled: the change per step did not drop tenfold in "
                    f"{stall_steps} steps (after {n_steps} steps: {c:.3g}, smallest {best:.3g}, Δt {h_try:.3g} s)")
    return None


class SteadySteps:
    """The steps of a steady-state run: pseudo-transient continuation, and the transient if it stalls.

    Iterates :func:`pseudo_transient`; if that stalls, says so on the console and
    continues with the transient (``integrate``, Δt = [time] step, every step converged)
    from the initial state, which is where a stalled continuation has no better
    state to offer (its iterates are not converged). ``fallback`` then holds what
    happened and ``restart`` the initial state until the runner has taken it.
    """

    def __init__(self, model, state, b, time_section, echo=print, stops=()):
        self.model, self.initial, self.b, self.tm, self.echo = model, state, b, time_section, echo
        self.stops = stops  # [output] times the transient lands on
        self.fallback, self.restart = None, None

    def __iter__(self):
        b, tm = self.b, self.tm
        reason = yield from pseudo_transient(self.model, self.initial, b.t_end, b.dt, tm["max_step"] or b.t_end,
                                             b.settings, iterations=tm["iterations_per_step"],
                                             stall_steps=STALL_STEPS, max_solids_change=MAX_SOLIDS_CHANGE)
        if reason is None:
            return
        self.fallback = {"reason": reason, "then": f"transient from the initial state (t = 0) with Δt = "
                         f"[time] step = {b.dt:g} s, every step converged to picard_tol, until steady"}
        self.echo(f"{reason}; falling back to the {self.fallback['then']}")
        self.model.linear.lu = None
        self.restart = self.initial
        yield from integrate(self.model, self.initial, b.t_end, b.dt, stops=self.stops, settings=b.settings)


def _warn_stall(message: str) -> None:
    import warnings

    warnings.warn(message, CaseWarning, stacklevel=2)


def horizontal_profile(model: TwoFluid2D, fields: dict, height: float) -> dict:
    """Element values along the row of elements containing ``height`` [m] (the top row at the top
    of the mesh), sorted by x (r)."""
    row = element_row(model.mesh, height)
    row = row[np.argsort(fields["x_m"][row])]
    p = {"x_m": fields["x_m"][row], "porosity": fields["porosity"][row], "P_Pa": fields["P_Pa"][row],
         "Ps_Pa": fields["Ps_Pa"][row], "Uf_x": fields["Uf_m_s"][row, 0], "Uf_y": fields["Uf_m_s"][row, 1],
         "Us_x": fields["Us_m_s"][row, 0], "Us_y": fields["Us_m_s"][row, 1]}
    if model.nc == 3:
        p["Uf_theta"] = fields["Uf_m_s"][row, 2]
        p["Us_theta"] = fields["Us_m_s"][row, 2]
    return p


class _Profiles:
    """Streams horizontal profiles to profiles.csv (whole rows, finite values; flushed per time)."""

    def __init__(self, out: Path, model, heights):
        self.model, self.heights, self.last = model, heights, {}
        self.path, self.f, self.cols = out / "profiles.csv", None, None

    def write(self, t, fields):
        rows = []
        for h in self.heights:
            p = horizontal_profile(self.model, fields, h)
            if not check_finite(f"profiles.csv at height {h:g} m", t, p, undefined=("Us_",)):
                return
            self.last[h] = p
            if self.cols is None:
                self.cols = list(p)
                self.f = CsvStream(self.path, ["time_s", "height_m"] + self.cols)
            rows += [[t, h, *row] for row in zip(*(p[c] for c in self.cols))]
        if rows:
            self.f.rows(rows)

    def close(self):
        if self.f is not None:
            self.f.close()


class _History:
    """Streams one row per step to steps.csv: Δt, iterations, rates, changes, solver counts, centreline U_f."""

    def __init__(self, out: Path, model, heights):
        self.model, self.heights = model, list(heights)
        mesh = model.mesh
        xc = mesh.points[mesh.cells].mean(axis=1)
        self.axis_el = []
        for h in self.heights:  # element of the row at height h nearest to x (r) minimum
            row = element_row(mesh, h)
            self.axis_el.append(int(row[np.argmin(xc[row, 0])]) if row.size else -1)
        self.f = CsvStream(out / "steps.csv", ["step", "time_s", "dt_s", "iterations", "max_dn_dt_1_s",
                                               "max_dV_dt_over_V_1_s", "max_dn", "max_dV_over_V", "factorisations",
                                               "solves", "gmres_iterations"]
                           + [f"Uf_axial_at_{h:g}m_x_min" for h in self.heights])
        self.last = {}

    def write(self, k, s, dt, its, rate, change):
        """One row; ``rate`` and ``change`` None before the first step (written as empty cells)."""
        st = getattr(self.model.linear, "stats", {})
        v = self.model.element_mean(s.V)
        w = self.model.element_mean(s.W)
        uf = [(v[e, 1] + w[e, 1]) / (2.0 * s.n[e]) for e in self.axis_el]
        values = {"Uf_axial": np.array(uf)} if k == 0 else {
            "Uf_axial": np.array(uf), "rates": np.array(rate), "changes": np.array(change)}
        if not check_finite("steps.csv", s.t, values, element_name="entry"):
            return
        self.last = {"uf": uf, "prev": self.last.get("uf")}
        r, c = (None, None) if k == 0 else (rate, change)
        self.f.rows([[k, s.t, f"{dt:.6g}", its, *(("", "") if r is None else (f"{r[0]:.4g}", f"{r[1]:.4g}")),
                      *(("", "") if c is None else (f"{c[0]:.4g}", f"{c[1]:.4g}")), st.get("factorisations", 0),
                      st.get("solves", 0), st.get("gmres_iterations", 0), *uf]])

    def centreline(self) -> dict:
        """U_f,axial of the element next to the axis (x min) at each profile height, and its last change."""
        out = {}
        for i, h in enumerate(self.heights):
            u = float(self.last["uf"][i]) if self.last else float("nan")
            d = float(self.last["uf"][i] - self.last["prev"][i]) if self.last.get("prev") else float("nan")
            out[f"{h:g} m"] = {"value": u, "change_in_last_step": d}
        return out

    def close(self):
        self.f.close()


def single_fluid_check(case: dict, mesh: QuadMesh, out: Path, plots: bool = True) -> dict:
    """Steady single-fluid Stokes flow on the case's mesh and conditions vs the analytic annulus.

    Boundary conditions as the mixture's (inlet: uniform u_z; walls no slip; rotating
    wall u_θ = ω r; axis; outlet traction free). At ``[single_fluid] height`` (in the
    annulus r_inner < r < r_outer, assumed fully developed) the nodal u_z and u_θ are
    compared with annular Poiseuille flow of the same flow rate and Couette swirl
    (thesis appendix 4.3): relative L2 errors along the radius with the r weight.
    """
    from ..models.single_fluid import solve_stokes
    from ..verification.annular import annular_poiseuille, annular_poiseuille_gradient, couette_swirl

    sf, g = case["single_fluid"], case["materials"]["gravity"]
    mat = materials(case)
    clo = closures(case, mat)
    dirichlet, omega = {}, 0.0
    for name in BOUNDARY_NAMES:
        b = case["boundary"][name]
        grp = b["group"] or name
        if b["kind"] == "inlet":
            dirichlet[grp] = {"r": 0.0, "z": inlet_velocities(b, clo, mat)[0], "theta": 0.0}
        elif b["kind"] == "wall":
            dirichlet[grp] = {"r": 0.0, "z": 0.0, "theta": 0.0}
        elif b["kind"] == "axis":
            dirichlet[grp] = {"r": 0.0, "theta": 0.0}
        elif b["kind"] == "rotating_wall":
            omega = b["omega"]
            dirichlet[grp] = {"r": 0.0, "z": 0.0, "theta": lambda x, w=omega: w * x[:, 0]}
    res = solve_stokes(mesh, sf["viscosity"], dirichlet, rho=sf["density"], gravity=(0.0, -g), swirl=True)
    ys = np.unique(mesh.points[:, 1])
    y = ys[np.argmin(np.abs(ys - sf["height"]))]
    r_i, r_o = sf["r_inner"], mesh.points[:, 0].max()
    line = np.nonzero((np.abs(mesh.points[:, 1] - y) < 1e-12) & (mesh.points[:, 0] >= r_i - 1e-12))[0]
    line = line[np.argsort(mesh.points[line, 0])]
    r, uz, ut = mesh.points[line, 0], res.velocity[line, 1], res.velocity[line, 2]
    q = np.trapezoid(uz * r, r) * 2.0 * np.pi
    u_mean = q / (np.pi * (r_o ** 2 - r_i ** 2))
    uz_ex = annular_poiseuille(r, r_i, r_o, annular_poiseuille_gradient(r_i, r_o, sf["viscosity"], u_mean),
                               sf["viscosity"])
    ut_ex = couette_swirl(r, r_i, r_o, omega)

    def err(u, ex):
        return float(np.sqrt(np.trapezoid((u - ex) ** 2 * r, r) / np.trapezoid(ex ** 2 * r, r)))

    out_d = {"height_m": float(y), "r_inner_m": r_i, "r_outer_m": float(r_o),
             "mean_axial_velocity_m_s": float(u_mean), "u_z_relative_L2_error": err(uz, uz_ex),
             "u_theta_relative_L2_error": err(ut, ut_ex),
             "definition": "relative L2 error of the nodal profile along r (weight r) against annular "
                           "Poiseuille flow of the same flow rate and Couette swirl"}
    spindle = viscometer.spindle(case)
    if spindle is not None:
        out_d["viscometer"] = viscometer.single_fluid(mesh, res, spindle, sf["viscosity"])
    if plots:
        from ..plots.fields import single_fluid_plot

        rf = np.linspace(r_i, r_o, 201)
        single_fluid_plot(r, uz, ut, rf, annular_poiseuille(rf, r_i, r_o, annular_poiseuille_gradient(
                              r_i, r_o, sf["viscosity"], u_mean), sf["viscosity"]), couette_swirl(rf, r_i, r_o, omega),
                          out / "single_fluid.png",
                          f"single fluid (ρ = {sf['density']:g} kg/m³, μ = {sf['viscosity']:g} Pa·s) at "
                          f"z = {y:g} m against the exact annulus")
    return out_d


def _write_fields(writer, model, s):
    f = model.element_fields(s)
    nn, nc = model.nn, model.nc
    writer.write(s.t, {"V": s.V.reshape(nc, nn).T, "W": s.W.reshape(nc, nn).T},
                 {"porosity": s.n, "reference_porosity": s.n_bar, "P": s.P, "P_s": f["Ps_Pa"],
                  "U_f": f["Uf_m_s"], "U_s": f["Us_m_s"]})
    return f


def run_2d(case: dict, out_dir=None, progress: bool = False) -> RunResult:
    """Run a resolved ``two_fluid_2d`` case; returns :class:`~twofluid.runners.RunResult`."""
    wall0 = time.perf_counter()
    b = build_2d(case)  # before anything is written; a failed initial flow field is a StepFailure,
    # which run_case reports as a failed run with a summary
    out = Path(out_dir or default_out_dir(case))
    out.mkdir(parents=True, exist_ok=True)
    write_resolved_case(out / "case.resolved.toml", case)
    extra = {}
    if case["single_fluid"]["enabled"]:
        extra["single_fluid"] = single_fluid_check(case, b.model.mesh, out, case["output"]["plots"])
    model, state = b.model, b.state
    writer = FieldWriter(out, model.mesh)
    prof = _Profiles(out, model, case["profiles"]["heights"])
    out_times = sorted(set(case["output"]["times"]) | {b.t_end})
    f = _write_fields(writer, model, state)
    prof.write(state.t, f)
    solids0, outflow = model.solids_volume(state), 0.0
    pc = case["profiles"]
    tol, tol_change, calm = pc["steady_tolerance"], pc["steady_change"], 0
    n_steps, last, rate, change, steady_reason = 0, state, (np.inf, np.inf), (np.inf, np.inf), ""
    tm = case["time"]
    if tm["stepping"] == "pseudo_transient":
        steps = SteadySteps(model, state, b, tm, echo=_warn_stall, stops=out_times)
    else:
        steps = integrate(model, state, b.t_end, b.dt, stops=out_times, settings=b.settings)
    history = _History(out, model, pc["heights"])
    history.write(0, state, 0.0, 0, None, None)
    pending = [t for t in out_times if t > state.t]
    offset = 0  # steps before a fallback to the transient
    pseudo = isinstance(steps, SteadySteps)
    with run_guard(b.t_end, progress, history) as run:
        time_format = getattr(run.bar, "bar_format", None)  # a disabled bar has none
        if pseudo and time_format:  # its clock is not a time: count steps
            run.bar.bar_format = "steady state by pseudo-transient continuation: step {n} [{elapsed}]"
            run.bar.reset(total=None)
        for step in steps:
            if getattr(steps, "restart", None) is not None:  # the continuation stalled: transient from t = 0
                last, calm, outflow, offset, steps.restart = steps.restart, 0, 0.0, n_steps, None
                pending = [t for t in out_times if t > last.t]
                pseudo = False
                if time_format:
                    run.bar.bar_format = time_format
                run.bar.reset(total=b.t_end)
            step = replace(step, n_steps=step.n_steps + offset)
            s = step.state
            outflow += step.dt * model.solids_outflow(s)
            change = relative_change(model, s, last, floor=STEADY_VELOCITY_FLOOR)
            rate = (change[0] / step.dt, change[1] / step.dt)
            n_steps, last = step.n_steps, s
            history.write(n_steps, s, step.dt, step.iterations, rate, change)
            criteria = (tol > 0 or tol_change > 0) and (tol <= 0 or max(rate) < tol) \
                and (tol_change <= 0 or max(change) < tol_change)  # each criterion set (> 0) must hold
            calm = calm + 1 if criteria else 0
            steady = calm >= 3
            due = bool(pending) and s.t >= pending[0] * (1 - 1e-9)
            while pending and s.t >= pending[0] * (1 - 1e-9):
                pending.pop(0)
            if steady or due:
                prof.write(s.t, _write_fields(writer, model, s))
            run.bar.update(1 if pseudo else min(s.t, b.t_end) - run.bar.n)
            if steady:
                steady_reason = (f"steady: max |dn/dt| = {rate[0]:.3g} 1/s, max |dV/dt|/|V| = {rate[1]:.3g} 1/s, "
                                 f"change in the last step {max(change):.3g} (Δt = {step.dt:.4g} s)")
                break
    status, reason = run.status, run.reason or steady_reason
    if getattr(steps, "fallback", None):
        extra["stepping_fallback"] = steps.fallback
        reason = f"{reason} (after the fallback to the transient: {steps.fallback['reason']})"
    if not writer.entries or writer.entries[-1][0] != last.t:
        prof.write(last.t, _write_fields(writer, model, last))
    prof.close()
    wall = time.perf_counter() - wall0
    try:  # a reading that cannot be made must not cost the summary of the run
        visc = viscometer.mixture(case, model, last)
    except (ValueError, RuntimeError, ArithmeticError, np.linalg.LinAlgError) as exc:
        visc = {"error": f"{type(exc).__name__}: {exc}"}
    if visc is not None:
        extra["viscometer"] = visc
    summary = _summary(case, b, model, status, reason, last, n_steps, wall, solids0, outflow, rate, extra,
                       change, history)
    write_json(out / "summary.json", summary)
    if case["output"]["plots"]:
        _plots(case, model, last, prof.last, out, extra, reason)
    return RunResult(status, out, summary, {last.t: model.element_fields(last)}, {})


def _summary(case, b, model, status, reason, last, n_steps, wall, solids0, outflow, rate, extra,
             change=(np.nan, np.nan), history=None):
    solids = model.solids_volume(last)
    fluxes = model.boundary_fluxes(last)
    # after a fallback the steps are a transient from the initial state: its history balance holds
    pseudo = case["time"]["stepping"] == "pseudo_transient" and "stepping_fallback" not in extra
    sol_in = sum(-v["solids_m3_s"] for v in fluxes.values() if v["solids_m3_s"] < 0.0)
    history_balance = (solids - solids0 + outflow) / solids0 if solids0 > 0 else 0.0
    steady = pseudo and sol_in > 0  # a pseudo-transient run with no solids inflow keeps the history balance
    # ... unless solids left: the outflow counted from each new state is not the linearised flux its
    # (unconverged) iterate used, so that history is not a balance
    unknown = pseudo and not steady and (outflow != 0.0 or any(
        v["solids_m3_s"] != 0.0 for v in fluxes.values() if v["kind"] == "outlet"))
    inl = {k: sum(-v[k] for v in fluxes.values() if v["kind"] == "inlet") for k in ("liquid_m3_s", "solids_m3_s")}
    outl = {k: sum(v[k] for v in fluxes.values() if v["kind"] == "outlet") for k in ("liquid_m3_s", "solids_m3_s")}
    s = {
        "case": case["case"]["name"], "status": status, "stopped_at_s": last.t, "reason": reason,
        "end_time_s": b.t_end, "wall_time_s": wall, "steps": n_steps, "element": model.element,
        "elements": model.ne, "nodes": model.nn, "unknowns": model.size,
        "linear_solver": {"kind": model.linear.kind, **model.linear.stats},
        "solids_volume_m3": {"initial": solids0, "final": solids, "outflow": outflow},
        "solids_volume_balance_error":
            sum(v["solids_m3_s"] for v in fluxes.values()) / sol_in if steady else
            None if unknown else history_balance,
        "solids_volume_balance_error_definition": (
            "steady balance (pseudo_transient stepping with a solids inflow): (net solids outflow through "
            "the boundary) / solids inflow, at the final state. The time-history balance says nothing there: "
            "pseudo-transient steps are not a history (one Newton iterate each)"
            if steady else
            "not computed (null): pseudo_transient stepping with solids leaving and none entering; its steps "
            "are unconverged iterates whose outlet flux is not the one counted from the new state"
            if unknown else
            "(solids volume now − initial + net solids that left through the boundary) / initial "
            "(volumes with the 2πr weight in axisymmetry; under pseudo_transient stepping with no solids "
            "crossing the boundary each linearised iterate conserves solids as a converged step does)"),
        "stepping": case["time"]["stepping"],
        "boundary_fluxes_m3_s": fluxes,
        "inflow_m3_s": inl, "outflow_m3_s": outl,
        "liquid_outflow_over_inflow": outl["liquid_m3_s"] / inl["liquid_m3_s"] if inl["liquid_m3_s"] else None,
        "solids_outflow_over_inflow": outl["solids_m3_s"] / inl["solids_m3_s"] if inl["solids_m3_s"] else None,
        "final_rates_1_s": {"max_dn_dt": rate[0], "max_dV_dt_over_Vmax": rate[1]},
        "final_change": {"max_dn": change[0], "max_dV_over_Vmax": change[1],
                         "definition": "change over the last step: max |Δn| and max(|ΔV|, |ΔW|)/|V, W|max; "
                                       "rates are these over Δt"},
        "centreline_liquid_velocity_m_s": history.centreline() if history is not None else {},
        "porosity_range": [float(last.n.min()), float(last.n.max())],
        **extra,
    }
    f = model.element_fields(last)
    s["profiles"] = {}
    for h in case["profiles"]["heights"]:
        p = horizontal_profile(model, f, h)
        s["profiles"][f"{h:g} m"] = {"porosity_min": float(p["porosity"].min()),
                                     "porosity_max": float(p["porosity"].max()),
                                     "Uf_axial_min_m_s": float(p["Uf_y"].min()),
                                     "Uf_axial_max_m_s": float(p["Uf_y"].max())}
    cut = case["mesh"]["cut"] if case["mesh"]["kind"] == "rectangle" else []
    if cut:  # the region directly below the cut-out (e.g. below a rotor tip)
        side = (f["x_m"] >= cut[0]) & (f["x_m"] <= cut[1]) & (f["y_m"] < cut[2])
        below = side & (f["y_m"] > cut[2] - (cut[1] - cut[0]))
        if side.any() and not below.any():  # elements taller than the cut is wide: the row below it
            below = side & (f["y_m"] == f["y_m"][side].max())
    if cut and below.any():
        s["below_cut"] = {"definition": "elements with x in the cut's range, within one cut width below it",
                          "porosity_max": float(last.n[below].max()),
                          "porosity_mean": float(last.n[below].mean())}
    return s


def _plots(case, model, s, profiles, out, extra, reason=""):
    from ..plots.fields import field_plot, profile_plot, velocity_plot

    name = case["case"]["name"]
    if case["time"]["stepping"] == "pseudo_transient" and "stepping_fallback" not in extra:
        # the clock of pseudo-transient continuation is not a time: say what the state is
        title = f"{name}, steady state" if reason.startswith("steady") else f"{name}, not steady (see summary.json)"
    else:
        title = f"{name}, t = {s.t:.4g} s" + (", steady" if reason.startswith("steady") else "")
    f = model.element_fields(s)
    field_plot(model.mesh, s.n, out / "porosity.png", title, "porosity n [-]")
    velocity_plot(model.mesh, f, out / "velocity.png", title)
    if profiles:
        profile_plot(profiles, out / "profiles.png", title, model.mesh.axisymmetric)
