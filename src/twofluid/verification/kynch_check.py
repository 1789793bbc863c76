"""Kynch checks: step expansion, step contraction and batch settling against kinematic-wave theory.

Physics: 0.1 mm spheres (ρ_s = 2500 kg/m³) in water with the Stokes Wen–Yu drag,
so a uniform bed obeys Richardson–Zaki U = U_t n^4.65 exactly (Richardson & Zaki 1954), particle
inertia is negligible (relaxation time 1.4 ms against front times of minutes) and
P_s is negligible (n̄ = 0.3, A = 0.015: P_s < 1e-30 Pa at n ≥ 0.6); no viscous
stress. Porosities lie in the convex range n > (k − 1)/(k + 1) = 0.646.

Quantities (exact values from :mod:`twofluid.verification.kynch`):

- t1: the same definition (:func:`twofluid.postprocess.t1_from_history`, 2 % band)
  applied to the computed surface height and to the exact trajectory
  :func:`~twofluid.verification.kynch.bed_height` sampled at the same times; the
  surface is where the porosity crosses (1 + n_after)/2 (expansion) or (1 + n_before)/2;
- surface speed U1 − U0: slope of the computed surface over 10–60 % of the time
  before the first wave reaches it;
- fan speed c(n_mid) (expansion) or shock speed s (contraction): slope of the
  height of the porosity level n_mid = (n0 + n1)/2 over the same window;
- settling: descent speed U_t n0^k of the top interface over 5–35 % of the time
  it would take to reach the bottom.
Errors are relative; tolerance 3 %.
"""
from __future__ import annotations


from .. import postprocess as pp
from . import kynch
from .runs import KYNCH_MATERIAL, case_from, fit_speed, level_height, run_history

__all__ = ["K", "terminal_velocity", "step_change_rows", "settling_rows", "TOL"]

K = 4.65  # Richardson–Zaki exponent of the Stokes Wen–Yu law
TOL = 0.03


def terminal_velocity() -> float:
    """U_t [m/s] of the check's particles (Stokes)."""
    m = KYNCH_MATERIAL["materials"]
    return float(kynch.stokes_terminal_velocity(m["particle_diameter"], m["particle_density"],
                                                m["liquid_density"], m["liquid_viscosity"]))


def _row(check, quantity, ref, comp, unit, tol=TOL):
    err = abs(comp - ref) / abs(ref)
    return {"check": check, "quantity": quantity, "unit": unit, "reference": ref, "computed": comp,
            "error": err, "tolerance": tol, "error_kind": "relative", "pass": bool(err <= tol)}


def step_change_rows(n0: float, n1: float, H0: float = 0.2, dx: float = 1e-3, dt: float = 0.1,
                     model: str = "reduced_1d", with_t1: bool = True) -> list[dict]:
    """Run the step change n0 → n1 (bed height H0 [m], element size dx [m], step dt [s]).

    ``with_t1=False`` leaves out the t1 row (an expansion's t1 needs dx ≤ 0.5 mm for
    3 %: the smeared tail of the fan decides when the surface enters the 2 % band).
    """
    Ut = terminal_velocity()
    H1 = H0 * (1 - n0) / (1 - n1)
    L = 1.15 * max(H0, H1)
    t1_ex = float(kynch.step_change_t1(n0, n1, H0, Ut, K))
    case = case_from(KYNCH_MATERIAL, {
        "case": {"name": "kynch-step", "model": model, "study": "step_change"},
        "mesh": {"length": L, "elements": int(round(L / dx))},
        "initial": {"porosity": n0, "bed_height": H0},
        "boundary": {"bottom": {"kind": "inlet", "times": [0.0, 0.0], "porosities": [n0, n1]},
                     "top": {"kind": "outlet"}},
        "time": {"end": 1.6 * t1_ex, "step": dt}})
    thr = 0.5 * (1.0 + max(n0, n1))
    mid = 0.5 * (n0 + n1)
    expansion = n1 > n0
    h = run_history(case, {
        "surface": lambda m, s: pp.surface_height(m.mesh.centres, s.n, thr, m.mesh.y[0]),
        "level": lambda m, s: level_height(m.mesh.centres, s.n, mid, below_high=expansion)})
    t, hs = h.t, h.values["surface"]
    exact = kynch.bed_height(t, n0, n1, H0, Ut, K)
    t1_num, t1_ref = pp.t1_from_history(t, hs), pp.t1_from_history(t, exact)
    fr = kynch.step_change_fronts(n0, n1, Ut, K)
    # window before the first wave reaches the surface
    t_hit = H0 / float(fr.fast) if expansion else t1_ex
    win = (0.1 * t_hit, 0.6 * t_hit)
    name = f"Kynch {'expansion' if expansion else 'contraction'} n {n0:g} → {n1:g}"
    rows = [_row(name, "t1", t1_ref, t1_num, "s")] if with_t1 else []
    rows.append(_row(name, "surface speed U1 − U0", float(fr.surface), fit_speed(t, hs, *win), "m/s"))
    label = f"fan speed c(n = {mid:g})" if expansion else "shock speed"
    ref = float(kynch.wave_speed(mid, Ut * n1**K, Ut, K)) if expansion else float(fr.slow)
    rows.append(_row(name, label, ref, fit_speed(t, h.values["level"], *win), "m/s"))
    return rows


def settling_rows(n0: float = 0.8, L: float = 0.2, dx: float = 1e-3, dt: float = 0.1,
                  model: str = "reduced_1d") -> list[dict]:
    """Batch settling of a uniform suspension n0 in a closed-bottom column of height L [m]."""
    Ut = terminal_velocity()
    top, _ = kynch.batch_settling_speeds(n0, 0.5, Ut, K)
    t_fall = L / float(top)
    case = case_from(KYNCH_MATERIAL, {
        "case": {"name": "kynch-settling", "model": model, "study": "settling"},
        "closures": {"solids_pressure": {"compressibility": 0.1, "reference_porosity": 0.45}},
        "mesh": {"length": L, "elements": int(round(L / dx))},
        "initial": {"porosity": n0},
        "boundary": {"bottom": {"kind": "wall"}, "top": {"kind": "outlet"}},
        "time": {"end": 0.35 * t_fall, "step": dt}})
    thr = 0.5 * (1.0 + n0)
    h = run_history(case, {"top": lambda m, s: pp.surface_height(m.mesh.centres, s.n, thr, m.mesh.y[0])})
    speed = -fit_speed(h.t, h.values["top"], 0.05 * t_fall, 0.35 * t_fall)
    return [_row(f"Kynch batch settling n0 = {n0:g}", "interface descent speed U_t n0^k", float(top),
                 speed, "m/s")]
