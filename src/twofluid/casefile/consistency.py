"""Checks across keys of a resolved case (each key alone is checked by the schema)."""
from __future__ import annotations

from .schema import INITIAL_1D, SCHEMA, CaseError, check_schedule, register_model

__all__ = ["check_consistency"]


def _boundary(case: dict, end: str, source: str) -> None:
    b = case["boundary"][end]
    where = f"[boundary.{end}]"
    vel, por = b["velocities"], b["porosities"]
    if b["kind"] != "inlet":
        for key, val in (("velocities", vel), ("porosities", por)):
            if val:
                raise CaseError(source, f"{where} {key}", f"only an inlet takes a schedule (kind = {b['kind']!r})")
        return
    check_schedule(b, where, source)


def check_consistency(case: dict, source: str) -> None:
    from .bed import flow_rate_inputs

    flow_rate_inputs(case, source)  # L/min, m³/h and a column diameter to the model's m/s and m²
    mesh, init, time, out = case["mesh"], case["initial"], case["time"], case["output"]
    if mesh["area_top"] != -1.0 and mesh["area_top"] <= 0.0:
        raise CaseError(source, "[mesh] area_top", "must be > 0 [m²] (or -1 for a constant area)")
    h = init["bed_height"]
    if h != -1.0 and not 0.0 < h <= mesh["length"]:
        raise CaseError(source, "[initial] bed_height", f"must lie in (0, {mesh['length']:g}] [m] "
                        "(the column length), or be -1 for the whole column")
    if init["solids_mass"] != -1.0 and not init["solids_mass"] > 0.0:
        raise CaseError(source, "[initial] solids_mass", "must be > 0 [kg] (or -1: not given)")
    if init["settled_height"] != -1.0 and not 0.0 < init["settled_height"] <= mesh["length"]:
        raise CaseError(source, "[initial] settled_height", f"must lie in (0, {mesh['length']:g}] [m] "
                        "(the column length), or be -1: not given")
    given = [k for k in ("bed_height", "solids_mass", "settled_height") if init[k] != -1.0]
    if len(given) > 1:
        raise CaseError(source, "[initial] " + "/".join(given), "give the bed by one of bed_height [m], "
                        "solids_mass [kg] or settled_height [m]")
    if init["state"] == "fluidized":
        b = case["boundary"]["bottom"]
        if b["kind"] != "inlet":
            raise CaseError(source, "[initial] state", "'fluidized' needs an inlet at the bottom (its "
                            "velocity at t = 0 sets the porosity)")
    elif init["porosity"] == -1.0:
        raise CaseError(source, "[initial] porosity", "missing (required unless state = 'fluidized'; "
                        "porosity of the bed, in (0, 1])")
    elif not 0.0 < init["porosity"] <= 1.0:
        raise CaseError(source, "[initial] porosity", f"{init['porosity']!r} is outside the valid range (0, 1] [-]")
    if case["numerics"]["solids_flux"] == "galerkin":
        # the Galerkin vertex flux (1 − n_f)U_s takes solids out of an element that has none (n > 1) as
        # soon as clear liquid meets solids that move: at a bed surface, or above a settling suspension
        free = init["solids_mass"] != -1.0 or init["settled_height"] != -1.0 or \
            (h != -1.0 and h < mesh["length"])
        if free or case["case"]["study"] == "settling":
            raise CaseError(source, "[numerics] solids_flux", "'galerkin' cannot follow a free surface "
                            "(a bed below the column top, or a settling study): it takes solids from the "
                            "clear liquid above it (porosity > 1); use 'upwind'")
    for end in ("bottom", "top"):
        _boundary(case, end, source)
    kinds = (case["boundary"]["bottom"]["kind"], case["boundary"]["top"]["kind"])
    if "outlet" not in kinds:
        raise CaseError(source, "[boundary.bottom/top] kind", "one end must be an outlet: it fixes the "
                        "pressure datum")
    if kinds == ("outlet", "outlet"):
        raise CaseError(source, "[boundary.bottom/top] kind", "one end must be an inlet or a wall: with "
                        "two outlets the mixture flux through the column is undetermined")
    if time["step"] > time["end"]:
        raise CaseError(source, "[time] step", f"must not exceed [time] end = {time['end']:g} s")
    for t in out["times"]:
        if not 0.0 <= t <= time["end"]:
            raise CaseError(source, "[output] times", f"{t:g} lies outside [0, {time['end']:g}] s")
    for y in out["probes"]:
        if not 0.0 <= y <= mesh["length"]:
            raise CaseError(source, "[output] probes", f"{y:g} lies outside [0, {mesh['length']:g}] m")
    study = case["case"]["study"]
    if study == "step_change":
        b = case["boundary"]["bottom"]
        if b["kind"] != "inlet" or len(b["times"]) < 2:
            raise CaseError(source, "[case] study", "step_change needs an inlet at the bottom with a "
                            "schedule of at least two values")


_SECTIONS_1D = ("mesh", "closures.drag", "closures.solids_pressure", "closures.viscosity", "initial",
                "boundary.bottom", "boundary.top", "numerics")
_SCHEMA_1D = {k: INITIAL_1D if k == "initial" else SCHEMA[k] for k in _SECTIONS_1D}
register_model("two_fluid_1d", _SCHEMA_1D, check_consistency)
register_model("reduced_1d", _SCHEMA_1D, check_consistency)
