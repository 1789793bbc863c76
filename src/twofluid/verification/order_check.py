"""Observed order of convergence in space and time on a smooth problem.

A fluidized bed filling a 0.2 m column at n0 = 0.75 (the Kynch particles of
:mod:`.runs`, Stokes Wen–Yu drag, inlet velocity U_t n0^4.65) carries a smooth
porosity bump n = n0 + 0.02 exp(−((y − 0.05)/0.015)²) upward as a kinematic
wave; at T = 8 s it has moved ~2.6 cm and is still smooth (no shock yet).

- space: N = 50, 100, 200, 400 elements at Δt = 0.01 s, error = L1 distance of
  the element porosities from the N = 1600 solution (same Δt) averaged onto each
  mesh (nested, exact averaging). N = 25 (two elements per e-folding width of the
  bump) is not yet in the asymptotic range of the upwind-tested bed forces: its
  error is twice that of the Galerkin forces and steepens the fitted rate to 1.4,
  while from N = 50 on the local rates are 1.34, 1.17, 1.24;
- time: N = 200, Δt = T/10 … T/80, error against Δt = T/1280 on the same mesh.
Both schemes are first order (upwind solids flux, backward Euler): the
least-squares rate must lie in [0.8, 1.3] and the finest error (mean absolute
porosity difference) below 3e-5 (space) and 1.5e-4 (time).
"""
from __future__ import annotations

import numpy as np

from ..casefile.builder import build
from .order import observed_order
from .runs import KYNCH_MATERIAL, case_from, run_history

__all__ = ["bump_solution", "space_rows", "time_rows", "RATE", "CAP"]

RATE = (0.8, 1.3)
CAP = {"space": 3e-5, "time": 1.5e-4}
T = 8.0
L = 0.2
N0 = 0.75


def bump_solution(elements: int, dt: float) -> np.ndarray:
    """Element porosities at T of the bump problem on ``elements`` elements with step ``dt`` [s]."""
    case = case_from(KYNCH_MATERIAL, {
        "case": {"name": "bump", "model": "reduced_1d"},
        "mesh": {"length": L, "elements": elements},
        "initial": {"porosity": N0},
        "boundary": {"bottom": {"kind": "inlet", "porosities": [N0]}, "top": {"kind": "outlet"}},
        "time": {"end": T, "step": dt, "picard_tol": 1e-9}})
    b = build(case)
    # cell averages of the bump (exact integral) so every mesh starts from the same field
    e = b.model.mesh.y
    from scipy.special import erf
    w = 0.015
    F = lambda x: 0.5 * np.sqrt(np.pi) * w * erf((x - 0.05) / w)  # noqa: E731
    n = N0 + 0.02 * (F(e[1:]) - F(e[:-1])) / np.diff(e)
    return run_history(case, {}, state=b.state.copy(n=n)).final.n


def _restrict(fine: np.ndarray, n: int) -> np.ndarray:
    return fine.reshape(n, -1).mean(axis=1)


def _rows(name, h, errs, unit, cap):
    o = observed_order(h, errs)
    ok_rate = RATE[0] <= o.rate <= RATE[1]
    return [{"check": name, "quantity": "least-squares observed order", "unit": "-", "reference": 1.0,
             "computed": o.rate, "error": abs(o.rate - 1.0), "tolerance": f"rate in [{RATE[0]}, {RATE[1]}]",
             "error_kind": "absolute", "pass": bool(ok_rate),
             "detail": f"{unit}: " + ", ".join(f"{x:g}" for x in h) + "; errors: "
             + ", ".join(f"{x:.3g}" for x in errs)},
            {"check": name, "quantity": "L1 porosity error on the finest level", "unit": "-", "reference": 0.0,
             "computed": float(errs[-1]), "error": float(errs[-1]), "tolerance": cap, "error_kind": "absolute",
             "pass": bool(errs[-1] <= cap)}]


def space_rows(levels=(50, 100, 200, 400), ref: int = 1600, dt: float = 0.01) -> list[dict]:
    """Spatial refinement study (module docstring)."""
    fine = bump_solution(ref, dt)
    errs = [float(np.mean(np.abs(bump_solution(n, dt) - _restrict(fine, n)))) for n in levels]
    return _rows("observed order in space (smooth kinematic wave)", [L / n for n in levels], errs, "h [m]", CAP["space"])


def time_rows(divs=(10, 20, 40, 80), ref: int = 1280, elements: int = 200) -> list[dict]:
    """Temporal refinement study (module docstring)."""
    fine = bump_solution(elements, T / ref)
    errs = [float(np.mean(np.abs(bump_solution(elements, T / d) - fine))) for d in divs]
    return _rows("observed order in time (smooth kinematic wave)", [T / d for d in divs], errs, "Δt [s]", CAP["time"])
