"""Discrete properties (docs/model.md): conservation, hydrostatic consistency, gauge invariance,
and agreement of the reduced model with the full one.

- conservation: (solids volume now − initial + solids that left) / initial after a
  run of the bundled case (reference 0, absolute tolerance 1e-10);
- hydrostatic consistency: a graded deposit (n from 0.40 at the bottom to 0.50 at
  its top, 0.3 m, clear liquid above to 0.5 m) in the settled state stays at rest
  for 20 steps of 0.1 s: max |V|, |W| [m/s] (tolerance 1e-10), and P against the
  liquid hydrostatic ρ_f g (H − y) relative to ρ_f g H (tolerance 1e-8). Picard
  tolerance 1e-5 here: the velocities are round-off (1e-13 m/s) and the stepper
  measures their change against a 1e-6 m/s floor, so 1e-7 is never met at rest;
- gauge invariance: the bundled case with outlet pressure 0 and 1e5 Pa; max
  difference of porosity and velocities after the run (tolerance 1e-8: the two
  runs stop their Picard iterations at different iterates within the 1e-7
  tolerance; the thesis's ∇(nP) form would change n at the 1e-2 level);
- reduced vs full: max |n_reduced − n_full| / n_full over all steps' end profile
  times of a bundled case (tolerance 1 %).
"""
from __future__ import annotations

import numpy as np

from ..casefile.builder import build
from ..casefile.case import section
from ..casefile.loader import load_case
from .runs import case_from, run_history

__all__ = ["conservation_rows", "hydrostatic_rows", "gauge_rows", "agreement_rows"]


def _row(check, quantity, ref, comp, tol, unit="-", kind="absolute"):
    err = abs(comp - ref) if kind == "absolute" else abs(comp - ref) / abs(ref)
    return {"check": check, "quantity": quantity, "unit": unit, "reference": ref, "computed": comp,
            "error": err, "tolerance": tol, "error_kind": kind, "pass": bool(err <= tol)}


def _bundled(name: str, model: str, t_end: float | None = None, **changes) -> dict:
    case = load_case(name)
    case["case"]["model"] = model
    if t_end:
        case["time"]["end"] = t_end
    for sec, kv in changes.items():
        section(case, sec.replace("__", ".")).update(kv)  # boundary__top: case["boundary"]["top"]
    return case


def conservation_rows(name: str = "fluidized-bed-step", model: str = "reduced_1d",
                      t_end: float = 10.0) -> list[dict]:
    """Solids volume balance of a bundled case run to ``t_end`` [s]."""
    case = _bundled(name, model, t_end)
    h = run_history(case, {"solids": lambda m, s: m.solids_volume(s),
                           "out": lambda m, s: m.solids_outflow(s)})
    outflow = float(np.sum(np.diff(h.t) * h.values["out"][1:]))
    s = h.values["solids"]
    bal = (s[-1] - s[0] + outflow) / s[0]
    return [_row(f"conservation ({name}, {model})", "solids volume balance error", 0.0, float(bal), 1e-10)]


def hydrostatic_rows(model: str = "two_fluid_1d") -> list[dict]:
    """A settled graded deposit under clear liquid stays at rest (module docstring)."""
    case = case_from({
        "case": {"name": "hydrostatic", "model": model},
        "materials": {"liquid_density": 1000.0, "liquid_viscosity": 1e-3, "particle_density": 2650.0,
                      "particle_diameter": 2e-4},
        "mesh": {"length": 0.5, "elements": 50},
        "initial": {"porosity": 0.45, "bed_height": 0.3, "state": "settled"},
        "boundary": {"bottom": {"kind": "wall"}, "top": {"kind": "outlet", "pressure": 2e3}},
        "time": {"end": 2.0, "step": 0.1, "picard_tol": 1e-5}})
    b = build(case)
    m, s0 = b.model, b.state
    y = m.mesh.centres
    n = np.where(y < 0.3, 0.40 + 0.10 * y / 0.3, 1.0)
    ps = m.settled_solids_pressure(n)
    from ..closures.solids_pressure import reference_porosity_for
    nbar = np.where(ps > 0, reference_porosity_for(n, np.where(ps > 0, ps, 1.0), m.clo.A, m.clo.p_ref),
                    s0.n_bar)
    state = s0.copy(n=n, n_bar=nbar)
    h = run_history(case, {"u": lambda mm, s: max(np.abs(s.V).max(), np.abs(s.W).max())}, state=state)
    rho_g = m.mat.rho_f * m.mat.g
    P_hyd = 2e3 + rho_g * (0.5 - y)
    dP = float(np.abs(h.final.P - P_hyd).max() / (rho_g * 0.5))
    tag = f"hydrostatic consistency ({model})"
    return [_row(tag, "max |V|, |W| of a graded settled deposit", 0.0, float(h.values["u"][1:].max()), 1e-10,
                 "m/s"),
            _row(tag, "max |P − ρ_f g (H − y)| / (ρ_f g H)", 0.0, dP, 1e-8)]


def gauge_rows(name: str = "fluidized-bed-step", model: str = "two_fluid_1d", t_end: float = 5.0) -> list[dict]:
    """Adding 1e5 Pa to the outlet pressure changes no porosity or velocity."""
    out = []
    for p in (0.0, 1e5):
        case = _bundled(name, model, t_end, boundary__top={"pressure": p})
        out.append(run_history(case, {}).final)
    dn = float(np.abs(out[0].n - out[1].n).max())
    dw = float(max(np.abs(out[0].W - out[1].W).max(), np.abs(out[0].V - out[1].V).max()))
    tag = f"gauge invariance ({name}, {model})"
    return [_row(tag, "max |Δn| for outlet pressure +1e5 Pa", 0.0, dn, 1e-8),
            _row(tag, "max |ΔV|, |ΔW| for outlet pressure +1e5 Pa", 0.0, dw, 1e-8, "m/s")]


def agreement_rows(name: str, t_end: float | None = None) -> list[dict]:
    """Max relative porosity difference reduced vs full at the case's output times."""
    res = {}
    for model in ("two_fluid_1d", "reduced_1d"):
        case = _bundled(name, model, t_end)
        times = sorted(t for t in case["output"]["times"] if t <= case["time"]["end"]) + [case["time"]["end"]]
        h = run_history(case, {"n": lambda m, s: s.n.copy()}, stops=times)
        idx = [int(np.argmin(np.abs(h.t - t))) for t in times]
        res[model] = np.array([h.values["n"][i] for i in idx])
    diff = float(np.max(np.abs(res["reduced_1d"] - res["two_fluid_1d"]) / res["two_fluid_1d"]))
    return [_row(f"reduced vs full model ({name})", "max |n_reduced − n_full| / n_full at output times",
                 0.0, diff, 0.01)]
