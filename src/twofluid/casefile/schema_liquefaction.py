"""Case-file sections of model ``liquefaction_1d`` (thesis 5.4–5.5; docs/model.md, "Liquefaction column").

A level deposit of loose saturated sand on an impervious base (rigid, or compliant for the
shear wave), water table at the surface (drained top), shaken by an acceleration record,
then left to reconsolidate. Sections: ``[deposit]`` (geometry, initial state), ``[sand]``
(skeleton: compressibility, shear modulus and its reduction curve, densification law),
``[ground_motion]`` (record and scaling), ``[shear_wave]`` (horizontal
equation: sub-step, damping, base), ``[reconsolidation]`` (vertical step after the
shaking) and ``[report]`` (depths of the time series). ``[closures.drag]`` and
``[closures.viscosity]`` are those of the 1D model; ``[time] step`` is the
vertical step while the column shakes.
"""
from __future__ import annotations

import math
import warnings
from pathlib import Path

from ..io.tables import TableError, read_columns
from .schema import FLOATS, SCHEMA, CaseError, CaseWarning, K, register_model

__all__ = ["SECTIONS_LIQUEFACTION", "check_liquefaction", "case_relative_path", "load_motion",
           "load_ann_weights", "load_reduction_table", "base_impedance"]

_DEPOSIT = [
    K("depth", float, 10.0, "m", "deposit thickness H (base to surface)", lo=0.0, lo_open=True, hi=1000.0),
    K("elements", int, 40, "-", "number of elements over the depth", lo=2, hi=5000),
    K("porosity", float, 0.44, "-", "initial porosity n (uniform)", lo=0.2, hi=0.7),
    K("surcharge", float, 0.0, "Pa", "load on the skeleton at the surface (fill, foundation)", lo=0.0),
    K("initial_excess_ratio", float, 0.0, "-", "imposed initial excess pore-pressure ratio r_u0 "
      "(n̄ lowered at constant n so that P_s = (1 − r_u0) σ′_v0)", lo=0.0, hi=1.0, hi_open=True),
    K("surface_pressure", float, 0.0, "Pa", "liquid pressure at the drained surface (datum)"),
]

_SAND = [
    K("compressibility", float, 6e-4, "-", "A of P_s = p_ref exp[(1/A)(1 − (1 − n̄)/(1 − n))]; "
      "6e-4 calibrates the loose sand (docs/liquefaction.md)", lo=0.0, lo_open=True, hi=1.0),
    K("p_ref", float, 1.0, "Pa", "reference pressure of P_s", lo=0.0, lo_open=True),
    K("relative_density", float, 47.0, "%", "Dr: Byrne's C1 = 7600 Dr^−2.5", lo=0.0, lo_open=True, hi=100.0),
    K("k2max", float, 30.0, "-", "Seed–Idriss modulus number: G_max = 218.8 K2max √(P_s/1 kPa) kPa",
      lo=0.0, lo_open=True, hi=200.0),
    K("gamma_ref", float, 1e-3, "-", "reference strain of the hyperbolic G/G_max = 1/(1 + |γ|/γ_ref)",
      lo=0.0, lo_open=True, hi=1.0, used_when=("modulus_reduction", ("hyperbolic",))),
    K("modulus_reduction", str, "hyperbolic", "-", "G/G_max(γ) curve (docs/model.md, Shear modulus): hyperbolic "
      "1/(1 + |γ|/γ_ref), or tabulated (reduction_strains + reduction_ratios, or reduction_file), "
      "interpolated linearly in log γ with the end values held outside the table",
      choices=("hyperbolic", "tabulated")),
    K("reduction_strains", FLOATS, [], "-", "tabulated: shear strains γ of the table (a fraction, not %): "
      "> 0, strictly increasing, at least 2", used_when=("modulus_reduction", ("tabulated",))),
    K("reduction_ratios", FLOATS, [], "-", "tabulated: G/G_max at reduction_strains: in (0, 1], "
      "non-increasing", used_when=("modulus_reduction", ("tabulated",))),
    K("reduction_file", str, "", "-", "tabulated, instead of the two lists: CSV file of rows \"shear "
      "strain, G/G_max\" (strain a fraction; a header line and # comments allowed), a path relative to "
      "the case file", used_when=("modulus_reduction", ("tabulated",))),
    K("viscosity", float, 0.0, "Pa·s", "extra viscosity η_s of the sand–water mixture in the shear wave, "
      "in parallel with the elastic backbone: τ = G γ + (μ_m + η_s) ∂γ/∂t, plus the Rayleigh damping. It "
      "matters once G has fallen: liquefied soil as a very viscous fluid (thesis chapter 1; the Bingham "
      "viscosity of Uzuoka et al. 1998). 0: none (the bundled cases; docs/liquefaction.md measures 100–10⁴)",
      lo=0.0, hi=1e5),
    K("reference_porosity_law", str, "byrne", "-", "densification law lowering n̄ under shear (Byrne 1991 or the thesis's ANN)",
      choices=("byrne", "ann")),
    K("ann_weights", str, "", "-", "ann: weights JSON file, a path relative to the case file ('' = the "
      "shipped default, trained on byrne)"),
    K("gamma_law_max", float, 0.01, "-", "|γ| beyond which the strain path adds no densification "
      "(the range of Byrne's law; strains in a liquefied layer are not bounded by this model)",
      lo=0.0, lo_open=True, hi=1.0),
]

_MOTION = [
    K("file", str, "RSN6_IMPVALL.I_I-ELC180-hor1.AT2", "-", "acceleration record — of the base "
      "([shear_wave] base = \"rigid\") or of the bedrock outcrop (\"compliant\"): a bundled name "
      "(data/ground_motions) or a path (.AT2 in g, or .csv time_s,acceleration) relative to the case file"),
    K("units", str, "g", "-", "CSV acceleration units", choices=("g", "m/s2")),
    K("pga_g", float, 0.1, "g", "peak |a| the record is scaled to; 0 switches the shaking off",
      lo=0.0, hi=5.0),
    K("duration", float, -1.0, "s", "shake for this long (the record is cut); -1: the whole record"),
    K("baseline_order", int, 1, "-", "polynomial order of the velocity baseline removed before scaling "
      "(0: none)", lo=0, hi=3),
]

_SHEAR = [
    K("step", float, 0.005, "s", "sub-step of the horizontal equation (Newmark average acceleration)",
      lo=0.0, lo_open=True, hi=0.05),
    K("damping_ratio", float, 0.05, "-", "Rayleigh damping ratio ξ at the two frequencies (stand-in for "
      "hysteretic damping, which the non-linear elastic backbone lacks)", lo=0.0, hi=0.5),
    K("damping_frequencies", FLOATS, [1.0, 10.0], "Hz", "the two frequencies of the Rayleigh damping"),
    K("free_vibration", float, 5.0, "s", "the shear wave keeps running this long after the record ends",
      lo=0.0),
    K("base", str, "rigid", "-", "rigid: the record is the motion of the base; compliant: the record is the "
      "outcrop motion of an elastic bedrock and the base has a Lysmer–Kuhlemeyer dashpot ρ_r V_r "
      "(docs/liquefaction.md)", choices=("rigid", "compliant")),
    K("bedrock_density", float, 2400.0, "kg/m³", "compliant base: bedrock density ρ_r", lo=1000.0, hi=5000.0,
      used_when=("base", ("compliant",))),
    K("bedrock_shear_velocity", float, 760.0, "m/s", "compliant base: bedrock shear-wave velocity V_r "
      "(760 m/s: the NEHRP B/C boundary)", lo=0.0, lo_open=True, hi=10000.0,
      used_when=("base", ("compliant",))),
]

_RECON = [
    K("step", float, 1.0, "s", "largest vertical step after the shear wave stops (reached by ×1.5 growth)",
      lo=0.0, lo_open=True),
]

_REPORT = [
    K("depths", FLOATS, [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0], "m",
      "depths below the surface of the r_u and σ′_v time series ([output] probes, heights above the "
      "base, are added)"),
    K("ru_liquefied", float, 0.95, "-", "r_u above which an element counts as liquefied", lo=0.0, hi=1.0,
      lo_open=True),
    K("field_interval", float, 0.1, "s", "time between rows of the r_u depth–time field (0: every step)",
      lo=0.0),
]

SECTIONS_LIQUEFACTION = {
    "deposit": _DEPOSIT,
    "sand": _SAND,
    "closures.drag": SCHEMA["closures.drag"],
    "closures.viscosity": SCHEMA["closures.viscosity"],
    "ground_motion": _MOTION,
    "shear_wave": _SHEAR,
    "reconsolidation": _RECON,
    "report": _REPORT,
}


def check_liquefaction(case: dict, source: str) -> None:
    """Cross-key checks of a ``liquefaction_1d`` case (one-line CaseError naming file and key)."""
    d, t, out = case["deposit"], case["time"], case["output"]
    H = d["depth"]
    if t["step"] > t["end"]:
        raise CaseError(source, "[time] step", f"must not exceed [time] end = {t['end']:g} s")
    if case["shear_wave"]["step"] > t["step"]:
        raise CaseError(source, "[shear_wave] step", f"must not exceed [time] step = {t['step']:g} s "
                        "(the shear sub-steps divide the vertical step)")
    if case["reconsolidation"]["step"] < t["step"]:
        raise CaseError(source, "[reconsolidation] step", f"must be at least [time] step = {t['step']:g} s")
    f = case["shear_wave"]["damping_frequencies"]
    if len(f) != 2 or not 0.0 < f[0] < f[1]:
        raise CaseError(source, "[shear_wave] damping_frequencies", f"must be two increasing positive "
                        f"frequencies [Hz], got {f}")
    g = case["ground_motion"]
    if g["duration"] != -1.0 and g["duration"] <= 0.0:
        raise CaseError(source, "[ground_motion] duration", "must be > 0 s, or -1 for the whole record")
    if not g["file"] and g["pga_g"] > 0.0:
        raise CaseError(source, "[ground_motion] file", "a record is needed when pga_g > 0")
    if case["sand"]["ann_weights"] and case["sand"]["reference_porosity_law"] != "ann":
        raise CaseError(source, "[sand] ann_weights", "only used with reference_porosity_law = \"ann\"")
    for z in case["report"]["depths"]:
        if not 0.0 <= z <= H:
            raise CaseError(source, "[report] depths", f"{z:g} lies outside [0, {H:g}] m (the deposit)")
    for y in out["probes"]:
        if not 0.0 <= y <= H:
            raise CaseError(source, "[output] probes", f"{y:g} lies outside [0, {H:g}] m (heights above "
                            "the base)")
    for tt in out["times"]:
        if not 0.0 <= tt <= t["end"]:
            raise CaseError(source, "[output] times", f"{tt:g} lies outside [0, {t['end']:g}] s")
    _check_physics(case, source)
    # the files the case names, read and checked now: a bad one must not start a run
    load_ann_weights(case, source)
    load_motion(case, source)
    _warn_softening(case, source, load_reduction_table(case, source))  # last: a warning only for a valid case


def base_impedance(case: dict) -> float | None:
    """c = ρ_r V_r [Pa·s/m] of a compliant base, None for a rigid one."""
    sw = case["shear_wave"]
    return None if sw["base"] == "rigid" else sw["bedrock_density"] * sw["bedrock_shear_velocity"]


def load_reduction_table(case: dict, source: str):
    """(strains, ratios) of a tabulated ``[sand] modulus_reduction`` (None: hyperbolic), from the
    inline lists or the CSV file, checked; every problem is a CaseError naming file and key."""
    from ..closures.shear_modulus import table_problem

    sa = case["sand"]
    if sa["modulus_reduction"] != "tabulated":
        return None
    lists = bool(sa["reduction_strains"] or sa["reduction_ratios"])
    if sa["reduction_file"] and lists:
        raise CaseError(source, "[sand] reduction_file", "give the table either as reduction_file or as "
                        "reduction_strains + reduction_ratios, not both")
    if not sa["reduction_file"] and not lists:
        raise CaseError(source, "[sand] modulus_reduction", "\"tabulated\" needs a table: reduction_strains "
                        "and reduction_ratios, or reduction_file")
    if sa["reduction_file"]:
        key = "[sand] reduction_file"
        path = case_relative_path(case, source, sa["reduction_file"])
        strains, ratios = _read_table(path, source, key)
        problem = table_problem(strains, ratios)
        if problem is not None:
            raise CaseError(source, key, f"{path.name}: {problem[1]}")
        return strains, ratios
    strains, ratios = sa["reduction_strains"], sa["reduction_ratios"]
    problem = table_problem(strains, ratios)
    if problem is not None:
        what = "strains" if problem[0] == "strains" or len(strains) < 2 else "ratios"
        raise CaseError(source, f"[sand] reduction_{what}", problem[1])
    return list(strains), list(ratios)


def _read_table(path: Path, source: str, key: str):
    """Rows "strain, G/G_max" of a CSV file; the first row may be a header, # starts a comment."""
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise CaseError(source, key, f"{path}: no such file (valid: a CSV file of shear strain, G/G_max "
                        "rows; a relative path is taken from the case file's folder)") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise CaseError(source, key, f"{path}: cannot be read ({exc})") from None
    try:
        rows = read_columns(text, 2)
    except TableError as exc:
        raise CaseError(source, key, f"{path.name} line {exc.line}: {exc.what} (valid: two numbers, "
                        "shear strain [-] and G/G_max)") from None
    strains = [g for _, (g, _) in rows]
    ratios = [r for _, (_, r) in rows]
    return strains, ratios


def _warn_softening(case: dict, source: str, table) -> None:
    """A valid table whose log interpolation makes the stress–strain backbone decrease somewhere."""
    if table is None:
        return
    from ..closures.shear_modulus import backbone_dips

    g, r = table
    dips = backbone_dips(g, r)
    if dips:
        key = "reduction_file" if case["sand"]["reduction_file"] else "reduction_ratios"
        pairs = ", ".join(f"{g[i]:g}–{g[i + 1]:g}" for i in dips)
        warnings.warn(CaseWarning(f"{source}: [sand] {key}: the stress G_max (G/G_max) γ falls by more than "
                                  f"1 % with growing strain between the points at γ = {pairs} under log "
                                  "interpolation (a softening backbone; add points between them)"), stacklevel=3)


def _check_physics(case: dict, source: str) -> None:
    """Inputs each valid alone whose combination has no deposit at rest to start from."""
    ma, d, sa = case["materials"], case["deposit"], case["sand"]
    if not ma["gravity"] > 0.0:
        raise CaseError(source, "[materials] gravity", f"{ma['gravity']:g} is outside the valid range "
                        "(0, inf) [m/s²]: the deposit's weight drives the model")
    if not ma["particle_density"] > ma["liquid_density"]:
        raise CaseError(source, "[materials] particle_density", f"{ma['particle_density']:g} must exceed "
                        f"[materials] liquid_density = {ma['liquid_density']:g} kg/m³ (grains without "
                        "buoyant weight carry no effective stress)")
    # initial reference porosity n̄0 = 1 − (1 − n)(1 − A ln(σ′/p_ref)) must lie in (0, 1) over the
    # range of σ′_v0 (1 − r_u0): top element centre .. base (bounds of the discrete values)
    n, A, p_ref = d["porosity"], sa["compressibility"], sa["p_ref"]
    unit = (1.0 - n) * (ma["particle_density"] - ma["liquid_density"]) * ma["gravity"]
    keep = 1.0 - d["initial_excess_ratio"]
    hi = keep * (unit * d["depth"] + d["surcharge"])
    lo = keep * (unit * 0.5 * d["depth"] / d["elements"] + d["surcharge"])
    if A * math.log(hi / p_ref) >= 1.0:
        raise CaseError(source, "[sand] compressibility", f"{A:g} gives a reference porosity n̄ >= 1 at the "
                        f"base (σ′ = {hi:.4g} Pa); valid: A < 1/ln(σ′/p_ref) = {1.0 / math.log(hi / p_ref):.4g}")
    if (1.0 - n) * (1.0 - A * math.log(lo / p_ref)) >= 1.0:
        limit = lo * math.exp(n / ((1.0 - n) * A))
        raise CaseError(source, "[sand] p_ref", f"{p_ref:g} Pa gives a reference porosity n̄ <= 0 at the "
                        f"top element (σ′ = {lo:.4g} Pa); valid: p_ref < {limit:.4g} Pa")


def case_relative_path(case: dict, source: str, name: str) -> Path:
    """``name`` as given, or relative to the case file's folder (current folder for a bundled
    case or one built in memory)."""
    p = Path(name)
    if p.is_absolute() or not source or source.startswith("<") or source.endswith("(bundled)"):
        return p
    return Path(source).parent / p


def load_ann_weights(case: dict, source: str):
    """The ``[sand] ann_weights`` network (None: the law's shipped default or not ann)."""
    name = case["sand"]["ann_weights"]
    if not name or case["sand"]["reference_porosity_law"] != "ann":
        return None
    from ..closures.reference_porosity import AnnWeightsError, load_weights

    path = case_relative_path(case, source, name)
    try:
        return load_weights(path)
    except AnnWeightsError as exc:
        raise CaseError(source, "[sand] ann_weights", f"{exc} (valid: a twofluid-ann-1 JSON file; a "
                        "relative path is taken from the case file's folder)") from None


def _record_path(case: dict, source: str) -> Path:
    from ..io import ground_motion as gm

    name = case["ground_motion"]["file"]
    path = case_relative_path(case, source, name)
    if path.is_file():
        return path
    try:
        return gm.bundled_record(name)
    except FileNotFoundError as exc:
        raise CaseError(source, "[ground_motion] file", f"{name!r} is neither a file ({path}) nor a "
                        f"bundled record ({exc})") from None


def load_motion(case: dict, source: str):
    """The base record in m/s²: read, cut to ``duration``, baseline-corrected, scaled to
    ``pga_g``; None if ``pga_g = 0``. Every problem is a CaseError naming the file and key."""
    from ..io import ground_motion as gm

    g = case["ground_motion"]
    if g["pga_g"] == 0.0:
        return None
    path = _record_path(case, source)
    key = "[ground_motion] file"
    try:
        m = gm.load(path, units=g["units"] if path.suffix.lower() != ".at2" else None)
    except gm.GroundMotionError as exc:
        raise CaseError(source, key, str(exc)) from None
    except (OSError, UnicodeDecodeError) as exc:
        raise CaseError(source, key, f"{path}: cannot be read ({exc})") from None
    if g["duration"] > 0.0:
        keep = m.time <= g["duration"] + 1e-12
        if int(keep.sum()) < 2:
            raise CaseError(source, "[ground_motion] duration", f"{g['duration']:g} s keeps "
                            f"{int(keep.sum())} sample(s) of {path.name} (its first samples are at "
                            f"{', '.join(f'{x:g}' for x in m.time[:2])} s); valid: a duration that keeps "
                            "at least 2 samples, or -1 for the whole record")
        m = gm.GroundMotion(m.time[keep], m.acceleration[keep], m.name, m.source, m.dt)
    elif m.npts < 2:
        raise CaseError(source, key, f"{path.name}: has {m.npts} sample(s); a record needs at least 2")
    order = g["baseline_order"]
    if m.npts < order + 1:
        raise CaseError(source, "[ground_motion] baseline_order", f"{order} needs at least {order + 1} "
                        f"samples, the record has {m.npts}; valid: 0 .. {m.npts - 1}")
    raw = m.pga
    if order > 0:
        m = gm.baseline_correct(m, order)
    if not raw > 0.0 or not m.pga > 1e-9 * raw:
        what = ("all zero" if not raw > 0.0 else
                f"zero once the velocity baseline of order {order} is removed")
        cut = f" (first {g['duration']:g} s)" if g["duration"] > 0.0 else ""
        raise CaseError(source, key, f"{path.name}{cut} is {what}: it cannot be scaled to pga_g = "
                        f"{g['pga_g']:g}; valid: a record with non-zero acceleration, or pga_g = 0 "
                        "for no shaking")
    return gm.scale_to_pga(m, g["pga_g"])


register_model("liquefaction_1d", SECTIONS_LIQUEFACTION, check_liquefaction)
