"""Scott (1986) check: a fully liquefied sand column solidifies from its base.

Column: quartz sand (d = 0.2 mm, ρ_s = 2650 kg/m³) in water, H = 1 m of liquefied sand at
n_l = 0.46 whose skeleton has reference porosity n̄ = 0.42 (P_s(n_l, n̄) ≈ 1e-58 Pa at
A = 3e-4: zero effective stress, r_u = 1 everywhere), Kozeny–Carman drag (Ergun, Stokes
limit: v_s = 0.778 mm/s, k = 0.87 mm/s), exponential P_s with A = 3e-4 (the liquefaction
cases use 6e-4; consolidation number Λ = A (1 − n_l)/(n_l − n̄) = 0.004), no viscous
stress, impervious wall at the base, drained outlet at the top, nothing shaking. Exact
values: the drained solution of :mod:`twofluid.verification.scott` (t_end = 91.5 s,
final settlement 71.2 mm; Scott's rigid grains, A → 0: 88.6 s and 69.0 mm).

Two models:

- **The two-fluid model, large strain** (``reduced_1d``, upwind solids flux): the mesh
  reaches 10 % above the sand (clear water), so the sand's top descends inside it (were the
  sand to start at the outlet, the top element would empty through it). N elements over H,
  Δt = 0.2 h/v_f (front Courant number 0.2, v_f = (1 − n_l) v_s/(n_l − n̄)).
- **The liquefaction column** (:class:`~twofluid.models.liquefaction_1d.LiquefactionColumn`,
  its reduced vertical model, Galerkin solids flux, drained top fixed at the top of the
  mesh, no record): the same column, state from ``initial_state(n_l, excess_ratio=0.99)``
  with the liquefied skeleton's n̄ = 0.42; compared with the fixed-surface (small-strain)
  form of the theory.

Quantities:

- front y_f: the lowest height where the element porosity, scanned upward, exceeds
  n_c = (n_l + n̄)/2 = 0.44, interpolated linearly between element centres; theory: the
  height of the porosity n_c in the drained deposit, Z(σ_M) − Z(σ_c) (σ_c ≈ 1e-26 Pa: the
  deposit's top). Not r_u: in the deposit the excess pore pressure is the weight of the
  suspension above, so r_u there is not small until the end.
- settlement: H minus the top of the sand, the highest downward crossing of (1 + n_l)/2
  (:func:`twofluid.postprocess.surface_height`); in the liquefaction column its own
  ``settlement`` (Σ h (n0 − n)/(1 − n));
- base excess pore pressure u_b: P − p_top − ρ_f g (y_top − y) of the lowest element.

Tolerances from the discretisation: front and settlement within one element plus the
distance the front (surface) travels in one step, h + v_f Δt (h + v_s Δt), at t = 0.1 … 0.9
t_end; the final settlement (1.5 t_end) within h/2 (the top of a deposit at rest, located
between two element centres); the liquefaction column's settlement within the compression
of one element, h (n_l − n_b)/(1 − n_b), n_b the base porosity; u_b within Δγ (1 − n_l)
times the sum of the front and surface tolerances, plus 2Λ u_0 for the consolidation lag
(measured 1.0–1.2 Λ u_0 at A = 1e-3 and 3e-3, vanishing linearly with A; u_0 = Δγ (1 − n_l) H).

Measured (tests/convergence/test_scott_solidification.py), two-fluid column, A = 3e-4, Δt = 0.2 h/v_f:

    elements          20       40       80       160      320
    max front error   12.1 mm  6.10 mm  3.03 mm  1.47 mm  0.74 mm   (0.24 h at every level)
    max settl. error  4.53 mm  2.27 mm  0.97 mm  0.48 mm  0.25 mm   (0.08–0.09 h)
    observed order 1.01 (front) and 1.09 (settlement) over 20–160 elements, 1.01 and 1.06 to 320.

The base excess pore pressure lags the drained value (at 0.5 t_end, 160 elements) by 2.43 %,
0.98 % and 0.38 % of u_0 at A = 3e-3, 1e-3, 3e-4 (Λ = 0.041, 0.014, 0.004): the consolidation of
the accreting layer that Scott measured, vanishing about linearly with A. At A = 3e-4 the drained
front is 3 % below Scott's rigid-grain front at the same time (the deposit compresses by
A (1 − n) ln(σ/p_ref) ≈ 0.0016 in porosity). The liquefaction column follows the fixed-surface
theory to 3 µm in settlement (its kinematics, not its discretisation, set the difference from the
true column): its settlement rate is c = (1 − n_l)/(1 − n̄) = 0.93 of the true one and it takes
98.6 s instead of 91.5 s to solidify, to the same final settlement (71.2 mm). Its top element
reports r_u = 2.0 in the liquefied state (the upwind bed-force test functions, α ≈ 0.5 in a
settling suspension, put the element's whole buoyant weight on its top vertex; r_u = 1 with
``bed_forces = "galerkin"``).

A Newton iterate that diverges (the deposit's first elements at small A) raises
ZeroDivisionError in the compiled closure points; the stepper takes it as a failed iterate and
halves the step, as after non-finite values.
"""
from __future__ import annotations

import numpy as np

from .. import postprocess as pp
from ..casefile.builder import build
from ..models.data_1d import Boundary
from . import scott
from .runs import case_from, run_history

__all__ = ["N_L", "N_BAR", "HEIGHT", "COURANT", "case_for", "theory", "eulerian_run",
           "column_run", "solidification_rows", "liquefaction_column_rows"]

N_L, N_BAR, HEIGHT = 0.46, 0.42, 1.0
A_CHECK = 3e-4
COURANT = 0.2  # v_f Δt / h
TIMES = np.arange(1, 10) / 10.0  # of t_end
G = 9.81

MATERIAL = {
    "materials": {"liquid_density": 1000.0, "liquid_viscosity": 1.0e-3, "particle_density": 2650.0,
                  "particle_diameter": 2.0e-4, "gravity": G},
    "closures": {"drag": {"law": "ergun", "stokes": True}, "viscosity": {"law": "none"}},
}


def case_for(A: float, elements: int, headroom: int = 0, dt: float = 1.0) -> dict:
    """The column as a case: ``elements`` over the sand, ``headroom`` more of clear water above it."""
    h = HEIGHT / elements
    return case_from(MATERIAL, {
        "case": {"name": "scott-solidification", "model": "reduced_1d"},
        "closures": {"solids_pressure": {"compressibility": A, "reference_porosity": N_BAR}},
        "mesh": {"length": h * (elements + headroom), "elements": elements + headroom},
        "initial": {"porosity": N_L, "bed_height": HEIGHT if headroom else -1.0},
        "boundary": {"bottom": {"kind": "wall"}, "top": {"kind": "outlet"}},
        "time": {"end": 1.0, "step": dt}})


def theory(model, A: float) -> scott.ScottColumn:
    """The exact drained solution for a built model's own drag law and materials."""
    mat, clo = model.mat, model.clo
    beta = lambda n, s: float(clo.beta_per_solids(np.array([n]), np.array([s]), mat)[0]) * (1.0 - n)  # noqa: E731
    rho_s, rho_f = float(mat.rho_s), float(mat.rho_f)
    vs = scott.settling_velocity(N_L, beta, rho_s, rho_f, G)
    return scott.ScottColumn(HEIGHT, N_L, N_BAR, A, vs, (rho_s - rho_f) * G, float(np.asarray(clo.p_ref)))


def front_height(y: np.ndarray, n: np.ndarray, level: float = 0.5 * (N_L + N_BAR)) -> float:
    """Lowest height [m] where n, scanned upward from the base, exceeds ``level`` (linear between
    element centres); NaN where the lowest element is already above it (no deposit yet).

    >>> front_height(np.array([0.5, 1.5, 2.5]), np.array([0.42, 0.42, 0.46]))
    2.0
    """
    above = n > level
    j = int(np.argmax(above))
    if j == 0 or not above[j]:
        return float("nan")
    return float(y[j - 1] + (level - n[j - 1]) / (n[j] - n[j - 1]) * (y[j] - y[j - 1]))


def _excess_base(model, s) -> float:
    y = model.mesh
    return float(s.P[0] - model.top.pressure + float(model.mat.rho_f) * G * (y.centres[0] - y.y[-1]))


def eulerian_run(A: float = A_CHECK, elements: int = 80, courant: float = COURANT) -> dict:
    """Run the large-strain column; returns {"theory", "t", "front", "surface", "u_base", "h", "dt",
    "steps"} at t = TIMES t_end and (last) 1.5 t_end."""
    probe = build(case_for(A, elements))
    th = theory(probe.model, A)
    h = HEIGHT / elements
    dt = courant * h / th.front_speed_rigid
    case = case_for(A, elements, headroom=max(2, elements // 10), dt=dt)
    b = build(case)
    stops = [float(x) for x in TIMES * th.end_time] + [1.5 * th.end_time]
    thr = 0.5 * (1.0 + N_L)
    hist = run_history(case, {
        "front": lambda m, s: front_height(m.mesh.centres, s.n),
        "surface": lambda m, s: pp.surface_height(m.mesh.centres, s.n, thr, m.mesh.y[0]),
        "u_base": _excess_base}, model=b.model, t_end=stops[-1], stops=stops)
    at = [int(np.argmin(np.abs(hist.t - t))) for t in stops]
    return {"theory": th, "t": hist.t[at], "front": hist.values["front"][at],
            "surface": hist.values["surface"][at], "u_base": hist.values["u_base"][at], "h": h, "dt": dt,
            "steps": hist.steps}


def column_run(A: float = A_CHECK, elements: int = 100, courant: float = COURANT) -> dict:
    """Run the liquefaction column (fixed drained top, Galerkin flux, no record); returns
    {"theory", "t", "front", "settlement", "max_r_u", "h", "dt"} at t = TIMES t_ss and 1.2 t_ss,
    t_ss the fixed-surface column's solidification time."""
    from ..models.liquefaction_1d import LiquefactionColumn
    from ..models.reduced_column import ReducedVerticalColumn

    b = build(case_for(A, elements))
    m = b.model
    th = theory(m, A)
    vertical = ReducedVerticalColumn(m.mesh, m.mat, m.clo, Boundary("wall"), Boundary("outlet", pressure=0.0))
    col = LiquefactionColumn(vertical)
    s = col.initial_state(N_L, excess_ratio=0.99)
    s.vertical.n_bar[:] = N_BAR  # the liquefied skeleton (r_u = 1 once the first step has set P)
    h = HEIGHT / elements
    dt = courant * h / th.front_speed_rigid
    t_ss = th.fixed_surface_end_time
    stops = [float(x) for x in TIMES * t_ss] + [1.2 * t_ss]
    out = {"t": [], "front": [], "settlement": [], "max_r_u": []}
    for step in col.run(s, stops[-1], dt, dt_after=dt, stops=stops):
        s = step.state
        if min(abs(s.t - x) for x in stops) < 1e-9 * t_ss:
            out["t"].append(s.t)
            out["front"].append(front_height(vertical.mesh.centres, s.vertical.n))
            out["settlement"].append(col.settlement(s))
            out["max_r_u"].append(float(np.max(col.excess_ratio(s))))
    out = {k: np.array(v) for k, v in out.items()}
    out.update(theory=th, h=h, dt=dt)
    return out


def _row(check, quantity, unit, ref, comp, tol):
    err = abs(comp - ref)
    return {"check": check, "quantity": quantity, "unit": unit, "reference": float(ref), "computed": float(comp),
            "error": float(err), "tolerance": float(tol), "error_kind": "absolute", "pass": bool(err <= tol)}


def solidification_rows(A: float = A_CHECK, elements: int = 80) -> list[dict]:
    """The large-strain column against the drained theory (module docstring)."""
    r = eulerian_run(A, elements)
    th, h, dt = r["theory"], r["h"], r["dt"]
    t = r["t"][:-1]
    name = f"Scott solidification (two-fluid, A = {A:g}, {elements} elements)"
    tol_f = h + th.front_speed_rigid * dt
    tol_s = h + th.settling_velocity * dt
    ef = r["front"][:-1] - th.front(t)
    es = (HEIGHT - r["surface"][:-1]) - th.settlement(t)
    i = len(t) // 2  # t = 0.5 t_end
    u0 = th.base_stress_end - th.liquefied_pressure
    tol_u = th.buoyant_unit_weight * (1.0 - N_L) * (tol_f + tol_s) + 2.0 * th.consolidation_number * u0
    return [
        _row(name, "front y_f at t = 0.5 t_end", "m", th.front(t[i]), r["front"][i], tol_f),
        _row(name, "max |y_f − theory|, t = 0.1 … 0.9 t_end", "m", 0.0, np.max(np.abs(ef)), tol_f),
        _row(name, "settlement at t = 0.5 t_end", "m", th.settlement(t[i]), HEIGHT - r["surface"][i], tol_s),
        _row(name, "max |settlement − theory|, t = 0.1 … 0.9 t_end", "m", 0.0, np.max(np.abs(es)), tol_s),
        _row(name, "final settlement (t = 1.5 t_end)", "m", th.final_settlement, HEIGHT - r["surface"][-1], 0.5 * h),
        _row(name, "base excess pore pressure at t = 0.5 t_end", "Pa", th.base_excess_pressure(t[i]),
             r["u_base"][i], tol_u),
    ]


def liquefaction_column_rows(A: float = A_CHECK, elements: int = 100) -> list[dict]:
    """The liquefaction column against the fixed-surface form of the theory (module docstring)."""
    r = column_run(A, elements)
    th, h, dt = r["theory"], r["h"], r["dt"]
    t = r["t"][:-1]
    i = len(t) // 2
    name = f"Scott solidification (liquefaction column, A = {A:g}, {elements} elements)"
    n_b = float(th.porosity_at(th.fixed_surface_stress_end))
    tol_s = h * (N_L - n_b) / (1.0 - n_b)
    tol_f = h + th.front_speed_rigid * dt
    es = r["settlement"][:-1] - th.fixed_surface_settlement(t)
    return [
        _row(name, "front y_f at t = 0.5 t_ss", "m", th.fixed_surface_front(t[i]), r["front"][i], tol_f),
        _row(name, "settlement at t = 0.5 t_ss", "m", th.fixed_surface_settlement(t[i]), r["settlement"][i], tol_s),
        _row(name, "max |settlement − theory|, t = 0.1 … 0.9 t_ss", "m", 0.0, np.max(np.abs(es)), tol_s),
        _row(name, "final settlement (t = 1.2 t_ss)", "m", th.fixed_surface_settlement(1.2 * th.fixed_surface_end_time),
             r["settlement"][-1], tol_s),
    ]
