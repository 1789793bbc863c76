"""Case-file sections of model ``two_fluid_2d`` (2DQ1, planar or axisymmetric).

Boundary conditions are attached to *named boundary groups* of the mesh through
fixed section names, one per standard group: ``[boundary.left]``, ``right``,
``bottom``, ``top``, ``inner``, ``outer``, ``axis``, ``cut`` (the surface left by
``[mesh] cut``). A section applies to the mesh group of its own name unless its
``group`` key names another one — that is how the physical groups of a Gmsh file
(any names) are used: e.g. ``[boundary.bottom] group = "Inflow"``. Sections with
``kind = "none"`` (the default) are unused. Structured meshes have the groups
left/right/bottom/top, plus inner/outer in axisymmetry and ``axis`` (= left) when
r starts at 0. Every boundary edge must be covered by some condition (checked when
the mesh is built).
"""
from __future__ import annotations

from .mesh_2d import BOUNDARY_NAMES, check_mesh
from .schema import BOUNDARY, FLOATS, SCHEMA, CaseError, K, check_schedule, register_model

__all__ = ["SECTIONS_2D", "BOUNDARY_NAMES", "check_2d"]

_RECT = {"used_when": ("kind", ("rectangle",))}
_SF = {"used_when": ("enabled", (True,))}

_MESH = [
    K("kind", str, "rectangle", "-", "rectangle (structured, built in code) or gmsh (any meshio-readable "
      "quadrilateral mesh with named boundary groups)", choices=("rectangle", "gmsh")),
    K("x0", float, 0.0, "m", "rectangle: first coordinate min (r_inner in axisymmetry)", lo=0.0, **_RECT),
    K("x1", float, 1.0, "m", "rectangle: first coordinate max (r_outer)", lo=0.0, lo_open=True, **_RECT),
    K("y0", float, 0.0, "m", "rectangle: height min (z)", **_RECT),
    K("y1", float, 1.0, "m", "rectangle: height max (z); gravity points to −y", **_RECT),
    K("nx", int, 10, "-", "rectangle: elements across (even keeps the checkerboard stabilisation)",
      lo=1, hi=2000, **_RECT),
    K("ny", int, 10, "-", "rectangle: elements up (even keeps the checkerboard stabilisation)",
      lo=1, hi=4000, **_RECT),
    K("grading_x", float, 1.0, "-", "rectangle: last/first element width ratio across", lo=0.0, lo_open=True,
      **_RECT),
    K("grading_y", float, 1.0, "-", "rectangle: last/first element height ratio up", lo=0.0, lo_open=True,
      **_RECT),
    K("cut", FLOATS, [], "m", "rectangle: [x0, x1, y0, y1] of a block of elements removed (e.g. a "
      "spindle); its wetted surface is the group 'cut'", **_RECT),
    K("file", str, "", "-", "gmsh: mesh file (relative to the case file)", used_when=("kind", ("gmsh",))),
    K("axisymmetric", bool, False, "-", "(r, z) coordinates with the 2πr measure"),
    K("swirl", bool, False, "-", "third velocity component (u_θ in axisymmetry)"),
]

_BOUNDARY_2D = [
    K("kind", str, "none", "-", "none (unused), inlet (porous distributor: V = W = inflow along the "
      "inward normal), wall (no slip), slip (normal velocity 0), axis (r = 0), rotating_wall "
      "(no slip, u_θ = ω r) or outlet (prescribed liquid pressure)",
      choices=("none", "inlet", "wall", "slip", "axis", "rotating_wall", "outlet")),
    K("group", str, "", "-", "mesh boundary group this applies to ('' = the section name)"),
    *[k for k in BOUNDARY if k.name in ("pressure", "times", "velocities", "porosities")],
    K("solids_velocity", float, 0.0, "m/s", "inlet: superficial solids velocity fed with the liquid", lo=0.0,
      used_when=("kind", ("inlet",))),
    K("omega", float, 0.0, "rad/s", "rotating_wall: angular speed (positive anticlockwise about +z)",
      used_when=("kind", ("rotating_wall",))),
    K("tangential", str, "no_slip", "-", "wall, rotating_wall: no_slip holds both phases' velocity "
      "in the (r, z) plane at 0; free_slip holds only its normal component (the swirl stays "
      "set). A wall of a fluidized bed on a mesh that cannot resolve the liquid's drag "
      "boundary layer (thickness √(nμ_f/β), well below a particle diameter) loses the drag "
      "that holds up the solids in its wall elements under no_slip", choices=("no_slip", "free_slip"),
      used_when=("kind", ("wall", "rotating_wall"))),
]

_NUMERICS = [
    K("solids_flux", str, "upwind", "-", "porosity equation: upwinded face solids flux or galerkin",
      choices=("upwind", "galerkin")),
    K("stabilisation_delta", float, 0.25, "-", "checkerboard-penalty parameter δ (scale δ/μ_f); 0: none",
      lo=0.0),
    K("linear_solver", str, "lagged", "-", "lagged: LU of an earlier matrix preconditions GMRES across "
      "iterations and steps (modified Newton), refactorised when GMRES would cost more than a new LU; "
      "direct: new LU every iteration", choices=("lagged", "direct")),
]

_PROFILES = [
    K("heights", FLOATS, [], "m", "heights (y/z) of the radial (horizontal) profiles written and plotted"),
    K("steady_tolerance", float, 0.0, "1/s", "stop before [time] end when the relative rates of change "
      "max |Δn|/Δt and max(|ΔV|, |ΔW|)/(|V, W|max Δt) — the steady residual of the discrete equations "
      "scaled by their mass matrix — stay below this for 3 steps (0: run to the end)", lo=0.0),
    K("steady_change", float, 0.0, "-", "and (if > 0) the change over one step, max |Δn| and "
      "max(|ΔV|, |ΔW|)/|V, W|max, stays below this: with pseudo_transient steps far longer than the "
      "slowest relaxation time it estimates the distance to the steady state", lo=0.0),
]

_TIME = [
    *SCHEMA["time"],
    K("stepping", str, "fixed", "-", "fixed: Δt = step (shrinks where needed, lands on [output] times; "
      "the transient); pseudo_transient: Δt grows as the fields settle (switched evolution relaxation, "
      "up to max_step), for the steady state only: [output] times are written at the first step "
      "reaching them; inlets must then hold one value. If the continuation stalls (its change per "
      "step not down tenfold in 25 steps) the run says so and continues with the transient from the "
      "initial state (Δt = step) until steady", choices=("fixed", "pseudo_transient")),
    K("max_step", float, 0.0, "s", "pseudo_transient: largest Δt (0: [time] end)", lo=0.0,
      used_when=("stepping", ("pseudo_transient",))),
    K("iterations_per_step", int, 1, "-", "pseudo_transient: Newton iterates per step (pseudo-transient "
      "continuation: the intermediate states are not wanted, so one is the usual choice); 0: converge "
      "every step to picard_tol", lo=0, hi=1000, used_when=("stepping", ("pseudo_transient",))),
]

_SINGLE = [
    K("enabled", bool, False, "-", "before the mixture: solve steady single-fluid Stokes flow on the same "
      "mesh and boundary conditions and compare with the analytic annulus (thesis appendix 4.3)"),
    K("density", float, 1600.0, "kg/m³", "single fluid density", lo=0.0, lo_open=True, **_SF),
    K("viscosity", float, 1.0, "Pa·s", "single fluid viscosity", lo=0.0, lo_open=True, **_SF),
    K("height", float, 0.0, "m", "height of the fully developed section where profiles are compared", **_SF),
    K("r_inner", float, 0.0, "m", "inner radius of the annulus (spindle)", lo=0.0, **_SF),
]

SECTIONS_2D = {
    "time": _TIME,
    "mesh": _MESH,
    "closures.drag": SCHEMA["closures.drag"],
    "closures.solids_pressure": SCHEMA["closures.solids_pressure"],
    "closures.viscosity": SCHEMA["closures.viscosity"],
    "initial": SCHEMA["initial"],
    **{f"boundary.{b}": _BOUNDARY_2D for b in BOUNDARY_NAMES},
    "numerics": _NUMERICS,
    "profiles": _PROFILES,
    "single_fluid": _SINGLE,
}


def check_2d(case: dict, source: str) -> None:
    """Cross-key checks of a ``two_fluid_2d`` case (one-line CaseError naming file and key)."""
    m = case["mesh"]
    if m["kind"] == "rectangle":
        if not m["x1"] > m["x0"]:
            raise CaseError(source, "[mesh] x1", f"must exceed x0 = {m['x0']:g} m")
        if not m["y1"] > m["y0"]:
            raise CaseError(source, "[mesh] y1", f"must exceed y0 = {m['y0']:g} m")
        if m["cut"] and len(m["cut"]) != 4:
            raise CaseError(source, "[mesh] cut", "must be [x0, x1, y0, y1] in m (or empty)")
    elif not m["file"]:
        raise CaseError(source, "[mesh] file", "a gmsh mesh needs a file")
    used = {b: case["boundary"][b] for b in BOUNDARY_NAMES if case["boundary"][b]["kind"] != "none"}
    if not any(b["kind"] == "outlet" for b in used.values()):
        raise CaseError(source, "[boundary.*] kind", "one boundary must be an outlet: it fixes the "
                        "pressure datum")
    for name, b in used.items():
        where = f"[boundary.{name}]"
        if b["kind"] == "inlet":
            check_schedule(b, where, source)
            vel, por = b["velocities"], b["porosities"]
            if case["time"]["stepping"] == "pseudo_transient" and len(set(vel or por)) > 1:
                key = "velocities" if vel else "porosities"
                raise CaseError(source, f"{where} {key}", "stepping = 'pseudo_transient' seeks the steady "
                                "state of one inflow (its clock is a pseudo-time): give one value, or use "
                                "stepping = 'fixed'")
        elif b["velocities"] or b["porosities"] or b["solids_velocity"]:
            raise CaseError(source, f"{where} velocities", f"only an inlet takes inflow (kind = {b['kind']!r})")
        if b["kind"] == "rotating_wall" and not m["swirl"]:
            raise CaseError(source, f"{where} kind", "rotating_wall needs [mesh] swirl = true")
        if b["kind"] == "axis" and not m["axisymmetric"]:
            raise CaseError(source, f"{where} kind", "axis needs [mesh] axisymmetric = true")
    t = case["time"]
    if t["step"] > t["end"]:
        raise CaseError(source, "[time] step", f"must not exceed [time] end = {t['end']:g} s")
    for tt in case["output"]["times"]:
        if not 0.0 <= tt <= t["end"]:
            raise CaseError(source, "[output] times", f"{tt:g} lies outside [0, {t['end']:g}] s")
    check_mesh(case, source)  # groups, axis at r = 0, cut, element shapes, profile heights
    sf = case["single_fluid"]
    if sf["enabled"] and not (m["axisymmetric"] and m["swirl"]):
        raise CaseError(source, "[single_fluid] enabled", "the annulus check needs an axisymmetric mesh "
                        "with swirl")


register_model("two_fluid_2d", SECTIONS_2D, check_2d,
               ignored={"output": {"probes": "2D runs write no probes; [profiles] heights and steps.csv give "
                                   "the time series", "probe_interval": "2D runs write no probes"}})
