"""Small helpers the verification checks share: build a case from a dict, run it, read fronts.

A check builds its column from a nested dict (validated by the case schema, so it
is an ordinary case), runs it through :func:`twofluid.timestepping.integrate` and
records what it needs at every step, without writing files.
"""
from __future__ import annotations

import copy
import time
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from ..casefile.builder import build
from ..casefile.schema import validate
from ..timestepping.backward_euler import integrate

__all__ = ["case_from", "History", "run_history", "level_height", "fit_speed", "KYNCH_MATERIAL"]

# Glass-like spheres, 0.1 mm, in water: U_t = 8.2 mm/s, particle relaxation time 1.4 ms,
# P_s negligible above n = 0.5 (n̄ = 0.3), no viscous stress: the Kynch limit.
KYNCH_MATERIAL = {
    "materials": {"liquid_density": 1000.0, "liquid_viscosity": 1.0e-3, "particle_density": 2500.0,
                  "particle_diameter": 1.0e-4},
    "closures": {"drag": {"law": "wen_yu", "stokes": True},
                 "solids_pressure": {"compressibility": 0.015, "reference_porosity": 0.3},
                 "viscosity": {"law": "none"}},
}


def case_from(doc: dict, *overlays: dict) -> dict:
    """Resolved case from nested dicts (later overlays win, recursively)."""
    out = copy.deepcopy(doc)
    for ov in overlays:
        stack = [(out, ov)]
        while stack:
            dst, src = stack.pop()
            for k, v in src.items():
                if isinstance(v, dict) and isinstance(dst.get(k), dict):
                    stack.append((dst[k], v))
                else:
                    dst[k] = copy.deepcopy(v)
    out.setdefault("output", {})["plots"] = False
    return validate(out, "<verification>")


@dataclass
class History:
    """Recorded values of a run: ``t`` [s] and one array per recorder name."""

    t: np.ndarray
    values: dict = field(default_factory=dict)
    model: object = None
    final: object = None
    steps: int = 0


def run_history(case: dict, recorders: dict[str, Callable], state=None, model=None,
                t_end: float | None = None, stops=(), wall_limit: float | None = None) -> History:
    """Run ``case`` and call each recorder ``f(model, state) -> float | array`` at every step.

    ``state``/``model`` replace the built ones (e.g. a hand-made initial profile);
    the steps land exactly on ``stops`` [s]; ``wall_limit`` [s] of wall-clock time
    raises :class:`TimeoutError` (a run that crawls at tiny steps is reported, not waited for).
    """
    b = build(case)
    m = model if model is not None else b.model
    s = state if state is not None else b.state
    ts, rec = [s.t], {k: [f(m, s)] for k, f in recorders.items()}
    n = 0
    wall0 = time.perf_counter()
    for step in integrate(m, s, t_end or b.t_end, b.dt, stops=stops, settings=b.settings):
        s = step.state
        n = step.n_steps
        ts.append(s.t)
        for k, f in recorders.items():
            rec[k].append(f(m, s))
        if wall_limit is not None and time.perf_counter() - wall0 > wall_limit:
            raise TimeoutError(f"stopped after {wall_limit:g} s of wall time at t = {s.t:.4g} s "
                               f"({n} steps, last step {step.dt:.3g} s)")
    return History(np.array(ts), {k: np.array(v) for k, v in rec.items()}, m, s, n)


def level_height(y: np.ndarray, n: np.ndarray, level: float, below_high: bool) -> float:
    """Lowest height [m] where the porosity profile crosses ``level`` (scanning up).

    ``below_high``: the porosity below the crossing is above ``level`` (an
    expansion's fan) or below it (a contraction's shock). Linear interpolation
    between element centres; NaN if there is no crossing.
    """
    side = n > level if below_high else n < level
    j = int(np.argmin(side)) if not side.all() else -1
    if j <= 0:
        return float("nan")
    f = (level - n[j - 1]) / (n[j] - n[j - 1])
    return float(y[j - 1] + f * (y[j] - y[j - 1]))


def fit_speed(t: np.ndarray, h: np.ndarray, t0: float, t1: float) -> float:
    """Least-squares slope [m/s] of h(t) over t0 ≤ t ≤ t1."""
    sel = (t >= t0) & (t <= t1) & np.isfinite(h)
    return float(np.polyfit(t[sel], h[sel], 1)[0])
