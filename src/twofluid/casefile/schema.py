"""The one schema of twofluid case files: every key with type, default, unit, range, doc.

Sections mirror the package (``[mesh]``, ``[materials]``, ``[closures.drag]`` …).
``validate`` checks a parsed TOML document against it before any computation and
returns the fully resolved case (defaults filled in); ``markdown`` renders the
reference table of ``docs/case-file.md`` from the same data.
"""
from __future__ import annotations

import contextvars
import math
import warnings
from dataclasses import dataclass
from typing import Any

from .case import nest, sections

__all__ = ["Key", "SCHEMA", "INITIAL_1D", "SCHEMAS", "COMMON", "register_model", "CaseError", "CaseWarning",
           "validate", "revalidate", "effective", "markdown", "check_schedule", "given_keys", "given_section_keys"]

REQUIRED = object()
#: every number of a case lies in ±[WORKING_MIN, WORKING_MAX] or is 0: no quantity of the model
#: in SI units is near either bound, and products of a few such numbers (pressure = ρ g L,
#: exp(1/A) …) then stay inside the floating-point range instead of overflowing mid-run
WORKING_MIN, WORKING_MAX = 1e-100, 1e100


class Suffixes(tuple):
    """File-name endings for ``K.used_when`` on a file key: a name is "in" it if it ends so.

    >>> "record.CSV" in Suffixes((".csv",)), "x.AT2" in Suffixes((".csv",))
    (True, False)
    """

    def __contains__(self, name) -> bool:
        return isinstance(name, str) and name.lower().endswith(tuple(self))

    def describe(self) -> str:
        return "a " + " or ".join(repr(x) for x in self) + " file"


@dataclass(frozen=True)
class Key:
    name: str
    type: type | tuple  # float, int, str, bool, or ("list", float)
    default: Any
    unit: str
    doc: str
    lo: float | None = None  # inclusive lower bound unless lo_open
    hi: float | None = None
    lo_open: bool = False
    hi_open: bool = False
    choices: tuple | None = None
    used_when: tuple[str, tuple] | None = None  # (other key of the section, values that use this key:
    # a tuple, or a `Suffixes` for a file key)
    sentinel: Any = None  # a value meaning "not set" (e.g. -1 for area_top): left out of a resolved case

    def range_text(self) -> str:
        if self.choices:
            return "one of " + ", ".join(repr(c) for c in self.choices)
        if self.lo is None and self.hi is None:
            return ""
        lo = "-inf" if self.lo is None else f"{self.lo:g}"
        hi = "inf" if self.hi is None else f"{self.hi:g}"
        return f"{'(' if self.lo_open or self.lo is None else '['}{lo}, {hi}{')' if self.hi_open or self.hi is None else ']'}"


def K(name, type_, default, unit, doc, **kw) -> Key:
    return Key(name, type_, default, unit, doc, **kw)


FLOATS = ("list", float)
BOUNDARY = [
    K("kind", str, REQUIRED, "-", "inlet (porous distributor, V = W = inflow), wall (V = W = 0) "
      "or outlet (prescribed liquid pressure)", choices=("inlet", "wall", "outlet")),
    K("pressure", float, 0.0, "Pa", "liquid pressure on an outlet", used_when=("kind", ("outlet",))),
    K("times", FLOATS, [0.0], "s", "inlet schedule: times, non-decreasing; a repeated time is a step "
      "(value before = first, after = second); constant before the first and after the last",
      used_when=("kind", ("inlet",))),
    K("velocities", FLOATS, [], "m/s", "inlet schedule: superficial liquid velocity into the column at `times`"),
    K("porosities", FLOATS, [], "-", "inlet schedule instead of velocities: the velocity that holds a "
      "uniform bed fluidized at each porosity (computed with the drag law)", lo=0.0, hi=1.0,
      lo_open=True, hi_open=True),
]

# a 1D inlet's schedule as a volumetric flow rate: converted to velocities at the edge (casefile.bed.flow_rate_inputs)
FLOW_RATES = [
    K("flow_rates_l_min", FLOATS, [], "L/min", "inlet schedule instead of velocities: volumetric liquid flow "
      "rate at `times`; the superficial velocity is Q/A, A the bottom cross-section ([mesh] area or diameter)",
      lo=0.0),
    K("flow_rates_m3_h", FLOATS, [], "m³/h", "the same in m³/h", lo=0.0),
]

SCHEMA: dict[str, list[Key]] = {
    "case": [
        K("name", str, "", "-", "short name used in outputs and in the default output folder "
          "twofluid-out/<name> ('': the case file's name without .toml)"),
        K("description", str, "", "-", "one line shown by `twofluid cases`"),
        K("model", str, "two_fluid_1d", "-", "equation set; each model has its own sections (below)",
          choices=("two_fluid_1d", "reduced_1d", "two_fluid_2d", "liquefaction_1d", "immersed_avalanche")),
        K("study", str, "general", "-", "which key figures the summary reports: step_change (t1, bed "
          "heights), settling (interface heights) or general", choices=("step_change", "settling", "general")),
    ],
    "mesh": [
        K("length", float, REQUIRED, "m", "column length along the line", lo=0.0, lo_open=True),
        K("elements", int, REQUIRED, "-", "number of elements", lo=1, hi=100000),
        K("element", str, "1VW/0P/0n", "-", "1D element: linear V, W with constant P (default) or "
          "quadratic V, W with linear P", choices=("1VW/0P/0n", "2VW/1P/0n")),
        K("area", float, 1.0, "m²", "cross-section area at the bottom (and everywhere unless area_top)",
          lo=0.0, lo_open=True),
        K("area_top", float, -1.0, "m²", "cross-section area at the top for a linear taper (-1: same as area)",
          sentinel=-1.0),
        K("inclination_deg", float, 0.0, "deg", "angle of the column to the vertical", lo=-89.0, hi=89.0),
        K("diameter", float, -1.0, "m", "inner diameter of a round column: area = π D²/4 instead of area "
          "(-1: not given)", sentinel=-1.0),
    ],
    "materials": [
        K("liquid_density", float, REQUIRED, "kg/m³", "ρ_f", lo=0.0, lo_open=True),
        K("liquid_viscosity", float, REQUIRED, "Pa·s", "μ_f", lo=0.0, lo_open=True),
        K("particle_density", float, REQUIRED, "kg/m³", "ρ_s", lo=0.0, lo_open=True),
        K("particle_diameter", float, REQUIRED, "m", "d_p", lo=0.0, lo_open=True),
        K("sphericity", float, 1.0, "-", "ψ; the drag laws use d = ψ d_p", lo=0.0, hi=1.0, lo_open=True),
        K("gravity", float, 9.81, "m/s²", "|g|", lo=0.0, lo_open=True),
    ],
    "closures.drag": [
        K("law", str, "gidaspow", "-", "drag law (docs/model.md, Drag); ergun_richardson_zaki: Ergun in packed "
          "beds, Richardson–Zaki in fluidized ones (the bundled fluidized-bed cases)",
          choices=("gidaspow", "ergun", "wen_yu", "richardson_zaki", "ergun_richardson_zaki")),
        K("exponent", float, 0.0, "-", "richardson_zaki, ergun_richardson_zaki: the Richardson–Zaki exponent k "
          "(0: Khan & Richardson's, from the Archimedes number of the particles)", lo=0.0, hi=10.0,
          used_when=("law", ("richardson_zaki", "ergun_richardson_zaki"))),
        K("stokes", bool, False, "-", "drop the inertial part of the drag (Stokes limits)"),
        K("n_switch", float, 0.6, "-", "gidaspow: Ergun below, Wen–Yu above", lo=0.0, hi=1.0,
          used_when=("law", ("gidaspow",))),
        K("blend_width", float, 0.0, "-", "gidaspow: half-width of a C¹ smoothstep blend across n_switch "
          "(0: the sharp switch of the thesis)", lo=0.0, used_when=("law", ("gidaspow",))),
        K("slip_saturation", float, 3.0, "-", "the |slip| the law sees saturates smoothly at this multiple of "
          "the single-particle terminal velocity, which keeps nearly empty elements (1 − n → 0) "
          "finite and fast to converge; 0 = off (the law as published)", lo=0.0),
    ],
    "closures.solids_pressure": [
        K("law", str, "exponential", "-", "P_s = p_ref exp[(1/A)(1 − (1 − n̄)/(1 − n))]", choices=("exponential",)),
        K("compressibility", float, 0.015, "-", "A", lo=0.0, lo_open=True),
        K("reference_porosity", float, 0.4, "-", "n̄ (P_s = p_ref at n = n̄); ignored where [initial] "
          "state = \"settled\" computes it", lo=0.0, hi=1.0, lo_open=True, hi_open=True),
        K("p_ref", float, 1.0, "Pa", "reference pressure", lo=0.0, lo_open=True),
        K("fluidized", str, "none", "-", "particle-phase pressure of a fluidized bed added to P_s: "
          "foscolo_gibilaro = (c/2) g d (ρ_s − ρ_f)(1 − n)², the elasticity that makes liquid-fluidized "
          "beds stable (Foscolo & Gibilaro 1984); none: P_s alone (uniform fluidization is then "
          "unstable, Jackson 1963)", choices=("none", "foscolo_gibilaro")),
        K("fluidized_coefficient", float, 3.2, "-", "c of the foscolo_gibilaro term (3.2 in the paper)",
          lo=0.0, lo_open=True, used_when=("fluidized", ("foscolo_gibilaro",))),
    ],
    "closures.viscosity": [
        K("law", str, "mooney_pringle", "-", "mixture viscosity (Pringle 2001 eq. 3.36)", choices=("mooney_pringle", "none")),
    ],
    "initial": [
        K("porosity", float, REQUIRED, "-", "porosity of the bed", lo=0.0, hi=1.0, lo_open=True),
        K("bed_height", float, -1.0, "m", "height of the bed above the bottom; clear liquid (n = 1) "
          "above it (-1: the whole column)", sentinel=-1.0),
        K("state", str, "uniform", "-", "uniform: n̄ from [closures.solids_pressure]; settled: n̄ such "
          "that P_s carries the buoyant weight of the solids above (a deposit at rest)",
          choices=("uniform", "settled")),
    ],
    "boundary.bottom": BOUNDARY + FLOW_RATES,
    "boundary.top": BOUNDARY + FLOW_RATES,
    "time": [
        K("end", float, REQUIRED, "s", "end time", lo=0.0, lo_open=True),
        K("step", float, REQUIRED, "s", "time step (shrinks by itself where needed)", lo=0.0, lo_open=True),
        K("picard_tol", float, 1e-7, "-", "convergence tolerance of the Picard/Newton iterations (relative "
          "change of the velocities, absolute of the porosity); at least 1e-12: the iterates' own round-off "
          "(3e-14 to 3e-12 on the bundled cases, the 2D ones with GMRES highest) is the floor no tolerance "
          "below it can pass", lo=1e-12, hi=1e-2),
        K("picard_max_iter", int, 40, "-", "iterations before the step is retried with half the step",
          lo=1, hi=1000),
    ],
    "output": [
        K("times", FLOATS, [], "s", "times at which profiles are written (the end time always is)"),
        K("probes", FLOATS, [], "m", "heights above the bottom whose time series are written"),
        K("probe_interval", float, 0.0, "s", "time between probe samples (0: every step)", lo=0.0),
        K("plots", bool, True, "-", "write PNG plots"),
    ],
    "numerics": [
        K("solids_flux", str, "upwind", "-", "porosity equation: upwind solids flux at vertices (keeps "
          "n ≤ 1 at a descending bed surface) or the thesis's galerkin form", choices=("upwind", "galerkin")),
    ],
}


# [initial] of the 1D column models: the bed by porosity or fluidized state, and by height,
# solids mass or settled height (twofluid.casefile.bed)
INITIAL_1D: list[Key] = [
    K("porosity", float, -1.0, "-", "porosity of the bed, in (0, 1] (required unless state = \"fluidized\")",
      used_when=("state", ("uniform", "settled")), sentinel=-1.0),
    K("bed_height", float, -1.0, "m", "height of the bed above the bottom; clear liquid (n = 1) "
      "above it; the bed fills the elements whose centres lie below it (a warning says so when "
      "that moves the surface) (-1: the whole column, or the height that solids_mass or "
      "settled_height give)", sentinel=-1.0),
    K("solids_mass", float, -1.0, "kg", "the bed given by its solids inventory instead of "
      "bed_height: its height is the mass/(ρ_s (1 − n)) over the cross-section, the element "
      "the surface cuts holding the remainder; > 0 (-1: not given)", sentinel=-1.0),
    K("settled_height", float, -1.0, "m", "the bed given by the height it settles to at "
      "settled_porosity instead of bed_height, in (0, length] (-1: not given)", sentinel=-1.0),
    K("settled_porosity", float, 0.4, "-", "porosity of the settled bed of settled_height",
      lo=0.0, hi=1.0, lo_open=True, hi_open=True),
    K("state", str, "uniform", "-", "uniform: n̄ from [closures.solids_pressure]; settled: n̄ such "
      "that P_s carries the buoyant weight of the solids above (a deposit at rest); fluidized: "
      "uniform at the porosity at which the inlet velocity at t = 0 holds the bed (the case's "
      "drag law), porosity not given", choices=("uniform", "settled", "fluidized")),
]


# Sections every model shares; a model adds its own with ``register_model``.
COMMON = ("case", "materials", "time", "output")
SCHEMAS: dict[str, dict[str, list[Key]]] = {}
MODEL_CHECKS: dict[str, object] = {}
# Arrays of tables (TOML ``[[name]]``) of a model: name -> keys of each entry.
ARRAYS: dict[str, dict[str, list[Key]]] = {}


IGNORED: dict[str, dict[str, dict[str, str]]] = {}
#: a model's keys that have no effect in a given resolved case, beyond ``Key.used_when`` and
#: ``IGNORED`` (model -> inactive(case) -> {section: set of keys, array: [set of keys per entry]}):
#: left out of the resolved case, so that checking it again warns of none of them
INACTIVE: dict[str, object] = {}

#: the keys a document gives in each entry of its arrays of tables, while its model's check runs
#: ({array: [set of keys per entry]}; see :func:`given_keys`)
_GIVEN: "contextvars.ContextVar[dict]" = contextvars.ContextVar("twofluid_given_keys", default={})


def given_keys(array: str, i: int) -> set:
    """The keys the case file gave in entry ``i`` of ``[[array]]`` (for a model's check: a key left at
    its default is not "given"; a resolved case checked again gives every key, and warns of none)."""
    entries = _GIVEN.get().get(array, [])
    return entries[i] if i < len(entries) else set()


_SECTIONS = "[sections]"  # the key of the sections' given keys in _GIVEN (not an array's name)


def given_section_keys(section: str) -> set:
    """The keys the case file gave in ``[section]`` (dotted for nested sections, e.g. "closures.drag"),
    for a model's check, as :func:`given_keys` for an array's entries."""
    return _GIVEN.get().get(_SECTIONS, {}).get(section, set())


def register_model(model: str, sections: dict[str, list[Key]], check=None,
                   arrays: dict[str, list[Key]] | None = None,
                   ignored: dict[str, dict[str, str]] | None = None, inactive=None) -> None:
    """Declare the sections (besides COMMON) of ``model``; ``check(case, source)`` runs after.

    ``arrays`` declares arrays of tables (``[[layers]]``): each entry is checked against the
    keys and resolved like a section; an entry's ``name`` key, if any, labels its messages.
    ``ignored`` = {section: {key: why}}: keys of a shared section this model does not use
    (a warning when given, left out of the resolved case). ``inactive(case)``: the keys that have no
    effect in a resolved ``case`` for reasons of the model's own check (see :data:`INACTIVE`).
    """
    SCHEMAS[model] = {**{k: SCHEMA[k] for k in COMMON}, **sections}
    ARRAYS[model] = dict(arrays or {})
    if check is not None:
        MODEL_CHECKS[model] = check
    IGNORED[model] = dict(ignored or {})
    if inactive is not None:
        INACTIVE[model] = inactive


def _model_schema(model: str) -> dict[str, list[Key]]:
    if model not in SCHEMAS:  # the modules of other models register on import
        import importlib

        importlib.import_module(_MODEL_MODULES[model])
    return SCHEMAS[model]


_MODEL_MODULES = {"two_fluid_1d": "twofluid.casefile.consistency",
                  "reduced_1d": "twofluid.casefile.consistency",
                  "two_fluid_2d": "twofluid.casefile.schema_2d",
                  "liquefaction_1d": "twofluid.casefile.schema_liquefaction",
                  "immersed_avalanche": "twofluid.casefile.schema_avalanche"}


class CaseWarning(UserWarning):
    """A case-file key that is valid but has no effect (e.g. ``pressure`` on a wall)."""


class CaseError(ValueError):
    """A case file problem: names the file, the key and what is valid."""

    def __init__(self, source: str, key: str, message: str):
        super().__init__(f"{source}: {key}: {message}")
        self.source, self.key = source, key


def _out_of_range(key: Key, value) -> bool:
    return ((key.lo is not None and (value < key.lo or (key.lo_open and value == key.lo)))
            or (key.hi is not None and (value > key.hi or (key.hi_open and value == key.hi))))


def _workable(v: float) -> bool:
    return v == 0.0 or WORKING_MIN <= abs(v) <= WORKING_MAX


def _check_value(source: str, where: str, key: Key, value: Any) -> Any:
    full = f"[{where}] {key.name}"
    if key.type == FLOATS:
        if not isinstance(value, (list, tuple)) or not all(
                isinstance(v, (int, float)) and not isinstance(v, bool) for v in value):
            raise CaseError(source, full, f"must be a list of numbers, got {value!r}")
        out = [float(v) for v in value]
        for i, v in enumerate(out):  # TOML has nan and inf literals: a list entry is a value too
            if not math.isfinite(v):
                raise CaseError(source, full, f"entry {i + 1} ({v!r}) must be finite")
            if not _workable(v):
                raise CaseError(source, full, f"entry {i + 1} ({v!r}) is outside the working range: "
                                f"0 or {WORKING_MIN:g} ≤ |value| ≤ {WORKING_MAX:g} [{key.unit}]")
            if _out_of_range(key, v):
                raise CaseError(source, full, f"entry {i + 1} ({v!r}) is outside the valid range "
                                f"{key.range_text()} [{key.unit}]{_unit_hint(where, key, v)}")
        return out
    if key.type is float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise CaseError(source, full, f"must be a number, got {value!r}")
        value = float(value)
        if not math.isfinite(value):
            raise CaseError(source, full, "must be finite")
        if not _workable(value):
            raise CaseError(source, full, f"{value!r} is outside the working range: 0 or {WORKING_MIN:g} ≤ "
                            f"|value| ≤ {WORKING_MAX:g} [{key.unit}]")
    elif key.type is int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise CaseError(source, full, f"must be an integer, got {value!r}")
    elif key.type is bool:
        if not isinstance(value, bool):
            raise CaseError(source, full, f"must be true or false, got {value!r}")
    elif key.type is str:
        if not isinstance(value, str):
            raise CaseError(source, full, f"must be a string, got {value!r}")
    if key.choices and value not in key.choices:
        raise CaseError(source, full, f"{value!r} is not valid; valid: {key.range_text()}")
    if key.lo is not None or key.hi is not None:
        if _out_of_range(key, value):
            hint = (f"; the unit is per cent: did you mean {value * 100:g} (×100)?"
                    if key.unit == "%" and 0.0 < value <= 1.0 else _unit_hint(where, key, value))
            raise CaseError(source, full, f"{value!r} is outside the valid range {key.range_text()} "
                            f"[{key.unit}]{hint}")
    return value


def _unit_hint(where: str, key: Key, value) -> str:
    """"; did you mean …" where a unit mistake explains ``value`` (:mod:`.plausible`), else ""."""
    if key.type not in (float, FLOATS) or isinstance(value, bool) or not isinstance(value, (int, float)):
        return ""
    from .plausible import check

    found = check(where, key.name, key.unit, float(value))
    return found[1][found[1].index("; did you mean"):].split("; check")[0] if found and "did you mean" in found[1] \
        else ""


def _plausible(source: str, where: str, key: Key, value, unused: list[str]) -> None:
    """A dimensional value outside its physically plausible range (:mod:`.plausible`): refused, with the
    likely unit mistake named; outside its usual range: a warning (in ``unused``, issued for a valid case)."""
    if key.unit in ("-", "") or key.type not in (float, FLOATS):
        return
    from .plausible import check

    for i, v in enumerate(value if isinstance(value, list) else [value]):
        found = check(where, key.name, key.unit, v, key.sentinel)
        if found is None:
            continue
        entry = f" entry {i + 1}" if isinstance(value, list) else ""
        if found[0] == "error":
            raise CaseError(source, f"[{where}] {key.name}{entry}", found[1])
        unused.append(f"{source}: [{where}] {key.name}{entry}: {found[1]}")


def validate(doc: dict, source: str = "<case>", name: str = "case") -> dict:
    """Check ``doc`` against the schema; return the resolved case (all keys, defaults filled).

    Every check that needs no computation runs here, in this order: the keys one by one
    (type, range, finite), the model's cross-key checks, then the quantities derived from
    several keys (:mod:`twofluid.casefile.derived`: terminal and fluidization velocities,
    pressure scales, number of steps), so a case that is valid key by key but impossible as
    a whole is a :class:`CaseError` naming the keys before anything is built or written.
    ``name`` fills an empty ``[case] name`` (the file's name for a case file).
    """
    if not isinstance(doc, dict):
        raise CaseError(source, "case", f"must be a table of sections (a dict), got {type(doc).__name__}")
    tables = {k: v for k, v in doc.items() if _is_table_array(v)}
    flat = _flatten_sections({k: v for k, v in doc.items() if k not in tables}, source)
    case = _resolve_section(source, "case", SCHEMA["case"], flat.get("case", {}))
    if not case["name"]:
        case["name"] = name
    if any(c in case["name"] for c in "/\\\0") or case["name"].strip(". ") == "" or len(case["name"]) > 100:
        raise CaseError(source, "[case] name", f"{case['name']!r} must be a plain name of at most 100 "
                        "characters, without / or \\ (it names the output folder twofluid-out/<name>)")
    schema = _model_schema(case["model"])
    for where in flat:
        if where not in schema:
            raise CaseError(source, f"[{where}]", f"unknown section for model {case['model']!r}; "
                            + _nearest(where, schema, "sections"))
    arrays = ARRAYS.get(case["model"], {})
    for name in tables:
        if name not in arrays:
            raise CaseError(source, f"[[{name}]]", f"unknown array of tables for model {case['model']!r}"
                            + (f"; valid: {', '.join(f'[[{a}]]' for a in arrays)}" if arrays else ""))
    unused: list[str] = []
    resolved = {where: _resolve_section(source, where, keys, flat.get(where, {}), unused)
                for where, keys in schema.items()}
    for name, keys in arrays.items():
        resolved[name] = [_resolve_section(source, _entry_label(name, i, item), keys, item, unused)
                          for i, item in enumerate(tables.get(name, []))]
    resolved["case"] = case
    resolved = nest(resolved)  # as the TOML file nests it: resolved["closures"]["drag"]
    for where, keys in IGNORED.get(case["model"], {}).items():
        for key, why in keys.items():
            if key in flat.get(where, {}):
                unused.append(f"{source}: [{where}] {key}: ignored ({why})")
    check = MODEL_CHECKS.get(case["model"])
    if check is not None:
        token = _GIVEN.set({**{name: [set(item) for item in tables.get(name, [])] for name in arrays},
                            _SECTIONS: {where: set(keys) for where, keys in flat.items()}})
        try:
            check(resolved, source)
        finally:
            _GIVEN.reset(token)
    from .derived import check_derived

    check_derived(resolved, source)
    for message in unused:  # only for a valid case: an error is the one line a bad case gets
        warnings.warn(CaseWarning(message), stacklevel=2)
    return resolved


def check_schedule(b: dict, where: str, source: str) -> None:
    """An inlet's schedule: exactly one of velocities/porosities, one value per time, times
    non-decreasing with a time at most twice (a step). ``where`` is e.g. "[boundary.bottom]"."""
    times, vel, por = b["times"], b["velocities"], b["porosities"]
    if bool(vel) == bool(por):
        raise CaseError(source, f"{where} velocities/porosities",
                        "an inlet needs exactly one of velocities [m/s] or porosities [-]")
    values, name = (vel, "velocities") if vel else (por, "porosities")
    if len(values) != len(times):
        raise CaseError(source, f"{where} {name}", f"needs one value per entry of times ({len(times)}), "
                        f"got {len(values)}")
    if any(t2 < t1 for t1, t2 in zip(times, times[1:])):
        raise CaseError(source, f"{where} times", "must be non-decreasing")
    if any(t1 == t2 == t3 for t1, t2, t3 in zip(times, times[1:], times[2:])):
        raise CaseError(source, f"{where} times", "a time may appear at most twice (a step)")


def effective(case: dict) -> dict:
    """The resolved ``case`` with only the keys that act in it: without the keys that have no
    effect (``Key.used_when``, a model's ignored keys), keys left at their "not set" sentinel
    (``Key.sentinel``, e.g. ``area_top = -1``) and sections switched off (``kind = "none"``).
    Nested as the case is (``out["closures"]["drag"]``)."""
    model = case["case"]["model"]
    schema = _model_schema(model)
    arrays = ARRAYS.get(model, {})
    ignored = IGNORED.get(model, {})
    inactive = INACTIVE[model](case) if model in INACTIVE else {}

    def acting(where: str, table: dict, keys: dict, off=frozenset()) -> dict:
        def acts(name, value):
            k = keys.get(name)
            if name in ignored.get(where, {}) or name in off:
                return False
            if k is None:
                return True
            if k.sentinel is not None and value == k.sentinel:
                return False
            return not (k.used_when and table.get(k.used_when[0], None) not in k.used_when[1])

        return {name: value for name, value in table.items() if acts(name, value)}

    out = {}
    for where, table in sections(case).items():
        if where in arrays and isinstance(table, list):  # [[layers]]: each entry as a table of its own
            keys = {k.name: k for k in arrays[where]}
            off = inactive.get(where, [])
            out[where] = [acting(where, entry, keys, off[i] if i < len(off) else frozenset())
                          if isinstance(entry, dict) else entry for i, entry in enumerate(table)]
            continue
        if not isinstance(table, dict):
            out[where] = table
            continue
        if table.get("kind") == "none":
            continue
        out[where] = acting(where, table, {k.name: k for k in schema.get(where, [])}, inactive.get(where, frozenset()))
    return nest(out)


def revalidate(case: dict, source: str) -> dict:
    """Validate a resolved (possibly edited) case again: every key is range-checked, but the
    keys without effect that a resolved case carries raise no warning."""
    if not isinstance(case, dict):
        raise CaseError(source, "case", f"must be a table of sections (a dict), got {type(case).__name__}")
    if not isinstance(case.get("_source", ""), str):
        raise CaseError("<api>", "_source", f"must be a string (the file the case was loaded from), got "
                        f"{type(case['_source']).__name__}")
    doc = {k: v for k, v in case.items() if not (isinstance(k, str) and k.startswith("_"))}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CaseWarning)
        out = validate(doc, source)
    out["_source"] = case.get("_source", source)
    return out


def _resolve_section(source: str, where: str, keys: list[Key], given: dict,
                     unused: list[str] | None = None) -> dict:
    """Section with defaults filled in; keys given without effect are appended to ``unused``."""
    unused = [] if unused is None else unused
    known = {k.name for k in keys}
    for name in given:
        if name not in known:
            raise CaseError(source, f"[{where}] {name}", "unknown key; " + _nearest(name, known, "keys"))
    out = {}
    for key in keys:
        if key.name in given:
            out[key.name] = _check_value(source, where, key, given[key.name])
            _plausible(source, where, key, out[key.name], unused)
        elif key.default is REQUIRED:
            raise CaseError(source, f"[{where}] {key.name}", f"missing (required; {key.doc} [{key.unit}])")
        else:
            out[key.name] = list(key.default) if isinstance(key.default, list) else key.default
    for key in keys:
        if key.name in given and key.used_when and key.used_when[0] in out \
                and out[key.used_when[0]] not in key.used_when[1]:
            other, values = key.used_when
            wanted = values.describe() if isinstance(values, Suffixes) else " or ".join(map(repr, values))
            unused.append(f"{source}: [{where}] {key.name}: ignored ({other} = {out[other]!r}; used only "
                          f"when {other} is {wanted})")
    return out


def _nearest(name: str, valid, what: str) -> str:
    """"did you mean 'x'?" for the valid name nearest to ``name`` (difflib), else the valid names.

    >>> _nearest("unit_wieght", ["unit_weight", "thickness", "porosity"], "keys")
    "did you mean 'unit_weight'? (valid keys: porosity, thickness, unit_weight)"
    """
    import difflib

    names = sorted(map(str, valid))
    close = difflib.get_close_matches(str(name), names, n=1, cutoff=0.6)
    if close:
        return f"did you mean {close[0]!r}?" + (f" (valid {what}: {', '.join(names)})" if len(names) <= 8 else "")
    return f"valid {what}: {', '.join(names)}"


def _is_table_array(value) -> bool:
    return isinstance(value, list) and bool(value) and all(isinstance(x, dict) for x in value)


def _entry_label(name: str, i: int, item: dict) -> str:
    """``layers 2 "loose sand"``: the array, the entry's 1-based index and its name (if a string)."""
    label = item.get("name")
    return f"{name} {i + 1}" + (f" {label!r}" if isinstance(label, str) else "")


def _flatten_sections(doc: dict, source: str) -> dict[str, dict]:
    """{"closures": {"drag": {...}}} -> {"closures.drag": {...}}; a flat dotted section name given
    (``{"closures.drag": {...}}``, the resolved case of version 0.1.0) is a :class:`FlatKeyWarning`."""
    flat: dict[str, dict] = {}

    def walk(prefix: str, table: dict):
        for k in table:
            if not isinstance(k, str):
                raise CaseError(source, f"[{prefix}] {k!r}" if prefix else repr(k), "keys must be strings")
        plain = {k: v for k, v in table.items() if not isinstance(v, dict)}
        subs = {k: v for k, v in table.items() if isinstance(v, dict)}
        if prefix and (plain or not subs):
            if prefix in flat:
                raise CaseError(source, f"[{prefix}]", "given twice: nested and by its flat dotted name; "
                                "give it once, nested")
            flat[prefix] = plain
        elif not prefix and plain:
            raise CaseError(source, ", ".join(plain), "keys must sit inside a [section]")
        for k, v in subs.items():
            walk(f"{prefix}.{k}" if prefix else k, v)

    dotted = [k for k, v in doc.items() if isinstance(k, str) and "." in k and isinstance(v, dict)]
    if dotted:
        from .case import FlatKeyWarning, caller_stacklevel, nested_spelling

        warnings.warn(FlatKeyWarning(
            f"{source}: sections given by flat dotted names ({', '.join(dotted)}) are deprecated and will "
            f"be refused in the next release; nest them as the TOML file does: "
            f"{nested_spelling(dotted[0])} in Python, [{dotted[0]}] in TOML"), stacklevel=caller_stacklevel())
    walk("", doc)
    return flat


def _key_table(heading: str, keys) -> list[str]:
    """Markdown lines of one section's keys: type, default, unit, valid range, meaning."""
    lines = [heading, "", "| key | type | default | unit | valid | meaning |", "|---|---|---|---|---|---|"]
    for k in keys:
        t = "list of numbers" if k.type == FLOATS else k.type.__name__
        d = "required" if k.default is REQUIRED else repr(k.default)
        lines.append(f"| `{k.name}` | {t} | {d} | {k.unit} | {k.range_text()} | {k.doc} |")
    return lines + [""]


def markdown() -> str:
    """The case-file reference (docs/case-file.md), generated from the registered schemas."""
    for model in _MODEL_MODULES:
        try:
            _model_schema(model)
        except ModuleNotFoundError:  # a model whose module is not written yet
            pass
    lines = ["# Case-file reference", "",
             "Generated from the schemas in `twofluid.casefile` (`python -m twofluid.casefile.schema "
             "> docs/case-file.md`). Values are in SI units except where the unit column says otherwise (degrees, per cent, g). Unknown sections or keys are errors; a key without effect (e.g. `pressure` on a wall) is a warning. "
             "Every number, also each entry of a list, must be finite and 0 or of magnitude 1e-100 to 1e100 "
             "(the program's working range); the valid range of a list applies to each entry. After the keys, "
             "quantities derived from several keys are checked (terminal and fluidization velocities, drag, "
             "pressure scales, at most 1e7 time steps; 2D: the mesh, its boundary groups and the heights), so "
             "a combination that cannot run is refused before anything is computed.",
             "`[case] model` chooses the equation set; each model lists its sections below. From Python, "
             "`twofluid.load_case` returns the case nested as the TOML file: `[closures.drag] law` is "
             "`case[\"closures\"][\"drag\"][\"law\"]`.", ""]
    seen: set[str] = set()
    for model, schema in SCHEMAS.items():
        arrays = ", ".join(f"[[{a}]]" for a in ARRAYS.get(model, {}))
        lines += [f"## model = \"{model}\"", "", "Sections: " + ", ".join(f"[{w}]" for w in schema)
                  + (f"; arrays of tables: {arrays}" if arrays else ""), ""]
    for model, schema in SCHEMAS.items():
        for where, keys in schema.items():
            ident = f"{where}:{id(keys)}"
            if ident in seen:
                continue
            seen.add(ident)
            owners = [m for m, sc in SCHEMAS.items() if sc.get(where) is keys]
            lines += _key_table(f"### [{where}] ({', '.join(owners)})", keys)
    for model, arrays in ARRAYS.items():
        for name, keys in arrays.items():
            lines += _key_table(f"### [[{name}]] ({model}; one table per entry)", keys)
    from .plausible import markdown_rows

    lines += ["## Plausible ranges (units that cannot be mistaken)", "",
              "Besides its valid range, every key with a unit has a physically plausible range "
              "(`twofluid.casefile.plausible`). A value outside it is refused (exit status 2) with the likely "
              "unit mistake named, e.g. `[[layers]] unit_weight = 18.5`: \"18.5 N/m³ is physically implausible "
              "(plausible: 100 to 30000); did you mean 18500 (kN/m³ typed into an N/m³ key, ×1000)?\". A value "
              "inside it but outside the usual range runs, with a one-line warning (and the same hint where a "
              "unit mistake would explain it). Where \"0 allowed\" is noted, 0 (off, not given) is never "
              "refused; a key at its \"not set\" value (-1) is not checked. An unknown key or section is refused "
              "with the nearest valid name (\"did you mean 'unit_weight'?\"); a key without effect in the case "
              "at hand (a slope's keys or `distance_km` on level ground, `pressure` on a wall) warns.", "",
              *markdown_rows(), ""]
    return "\n".join(lines)


if __name__ == "__main__":  # pragma: no cover
    from twofluid.casefile.schema import markdown as _markdown  # the registered instance

    print(_markdown())
