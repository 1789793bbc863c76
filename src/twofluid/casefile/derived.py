"""Checks of quantities derived from several keys, run by ``validate`` after the key checks.

Each key of a case may lie in its range while the case as a whole has no solution: particles
lighter than the liquid with an inlet given by the porosity it should fluidize, a diameter so
small that the terminal velocity underflows to zero, densities of 1e308 whose hydrostatic
pressure overflows, a time step that makes a run of 1e300 steps. The builder would meet these
as a root finder's ``ValueError``, an overflow or a run that never ends; here each is computed
once, from the same functions the builder uses, and a failure is a :class:`CaseError` naming
the keys involved, before anything is built or written.
"""
from __future__ import annotations

import numpy as np

from .case import section, sections
from .schema import WORKING_MAX, CaseError

__all__ = ["check_derived", "MAX_STEPS", "SCALE_LIMIT"]

#: [time] end / step above which a run would not end in practice (one step is ≥ 10 µs of work)
MAX_STEPS = 1e7
#: magnitude a derived scale (pressure, velocity, drag coefficient) may reach: far below the
#: float range, so the products formed in assembly (scale × element size × area …) stay finite
SCALE_LIMIT = WORKING_MAX

_MATERIAL_KEYS = "[materials] particle_density, liquid_density, particle_diameter, sphericity, liquid_viscosity"


def _finite_scale(source: str, keys: str, what: str, value, positive: bool = True) -> float:
    v = np.asarray(value, dtype=float)
    if not np.all(np.isfinite(v)) or np.any(np.abs(v) > SCALE_LIMIT) or (positive and np.any(v <= 0.0)):
        shown = float(v.flat[0]) if v.size == 1 else v.tolist()
        raise CaseError(source, keys, f"together give {what} = {shown!r}, which is not a usable finite "
                        f"{'positive ' if positive else ''}number (at most {SCALE_LIMIT:g} in magnitude): "
                        "check the values and their units")
    return float(v.flat[0]) if v.size == 1 else v


def _column_length(case: dict) -> float | None:
    m = case.get("mesh", {})
    if "length" in m:
        return m["length"]
    if m.get("kind") == "rectangle":
        return max(m["y1"] - m["y0"], m["x1"] - m["x0"])
    if "deposit" in case:
        return case["deposit"]["depth"]
    return None


def _steps(case: dict, source: str) -> None:
    t = case["time"]
    if t.get("stepping", "fixed") == "pseudo_transient":
        return  # Δt grows there
    # a liquefaction column takes [time] and [shear_wave] steps only while it shakes, and
    # [reconsolidation] steps after: each is counted over the span it covers
    shaking = case.get("ground_motion", {}).get("duration") if "reconsolidation" in case else None
    for where in ("time", "shear_wave", "reconsolidation"):
        step = case.get(where, {}).get("step")
        span = t["end"] if shaking is None or where == "reconsolidation" else min(t["end"], shaking)
        if step is not None and span / step > MAX_STEPS:
            what = "[time] end" if span == t["end"] else "[ground_motion] duration"
            raise CaseError(source, f"[{where}] step", f"{step:g} s makes {what} = {span:g} s "
                            f"{span / step:.3g} steps, more than {MAX_STEPS:g}: a run that would not "
                            "end; raise the step or lower the end time")


def _inlets(case: dict, source: str, clo, mat) -> None:
    for where, b in sections(case).items():
        if not (where.startswith("boundary.") and isinstance(b, dict)) or b.get("kind") != "inlet":
            continue
        if not b.get("porosities"):
            continue
        key = f"[{where}] porosities"
        if not mat.rho_s > mat.rho_f:
            raise CaseError(source, key, f"an inlet given by the porosity it fluidizes needs particles "
                            f"denser than the liquid ([materials] particle_density = {mat.rho_s:g} ≤ "
                            f"liquid_density = {mat.rho_f:g} kg/m³): give velocities [m/s] instead")
        for n in b["porosities"]:
            try:
                u = clo.fluidization_velocity(n, mat)
            except (ValueError, ArithmeticError) as exc:
                raise CaseError(source, key, f"no velocity fluidizes a bed at porosity {n:g} with "
                                f"{_MATERIAL_KEYS} and the drag law ({exc})") from None
            _finite_scale(source, f"{key} with {_MATERIAL_KEYS}", f"a fluidization velocity at n = {n:g} [m/s]", u)


def check_derived(case: dict, source: str) -> None:
    """Raise :class:`CaseError` if a quantity derived from several keys is unusable (see module doc)."""
    _steps(case, source)
    if "materials" not in case or section(case, "closures.drag") is None:
        return
    from .builder import closures, materials

    pressure = "closures.solids_pressure" if section(case, "closures.solids_pressure") is not None else "sand"
    if section(case, pressure) is None:
        return
    with np.errstate(all="ignore"):
        mat = materials(case)
        ma = case["materials"]
        length = _column_length(case)
        if length is not None:
            heavy = max(ma["particle_density"], ma["liquid_density"])
            _finite_scale(source, "[materials] densities, gravity and the column size",
                          "a hydrostatic pressure ρ g L [Pa]", heavy * ma["gravity"] * length)
        _finite_scale(source, "[materials] particle_diameter, sphericity", "a drag diameter ψ d_p [m]", mat.d)
        try:
            clo = closures(case, mat, pressure_section=pressure)
        except (ValueError, ArithmeticError) as exc:
            raise CaseError(source, _MATERIAL_KEYS, f"no drag law can be set up ({exc})") from None
        if np.isfinite(clo.slip_max):  # the terminal velocity (inf: a law without a dilute limit)
            _finite_scale(source, _MATERIAL_KEYS, "a slip limit (slip_saturation × terminal velocity) [m/s]",
                          clo.slip_max)
        n0 = case.get("initial", case.get("deposit", {})).get("porosity")
        if n0 is not None and 0.0 < n0 < 1.0:  # -1: not given (e.g. a fluidized initial state)
            beta = clo.drag(np.array([n0]), np.array([0.0]), mat.d, mat.rho_f, mat.mu_f, **clo.drag_params)
            _finite_scale(source, f"{_MATERIAL_KEYS} at the initial porosity", "a drag coefficient β [kg/(m³ s)]",
                          beta)
        _inlets(case, source, clo, mat)
