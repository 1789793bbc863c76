"""Case-file sections of model ``liquefaction_1d``: a layered level site shaken at its base.

A site is a stack of ``[[layers]]`` from the ground surface down, on an impervious base (rigid,
or compliant for the shear wave), with the water table at ``[site] water_table_depth``: the
layers above it are a dry or moist crust (unit weight, stiffness; no pore pressure), those
below it are saturated soil (particle size or hydraulic conductivity, porosity or void ratio,
skeleton compressibility, shear modulus and its reduction curve, densification law,
liquefied-soil viscosity, liquefiable or not). Sections: ``[site]`` (water table, surcharge,
initial state), ``[[layers]]``, ``[ground_motion]`` (record, scaling, polarity, magnitude),
``[shear_wave]`` (horizontal equation: sub-step, damping, base), ``[reconsolidation]`` (vertical
step after the shaking, dissipation criterion) and ``[report]``. ``[closures.drag]`` and
``[closures.viscosity]`` are those of the 1D model; ``[time] step`` is the vertical step while
the column shakes and ``[time] end`` the latest end (the run ends earlier once the excess pore
pressure has dissipated).
"""
from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np

from ..geotech.correlations import CSR_N_SLOPE_RANGE
from ..geotech.profile import SIGMA_EFF_MAX_PA
from ..io.tables import TableError, read_columns
from .schema import (FLOATS, REQUIRED, SCHEMA, CaseError, CaseWarning, K, Suffixes, given_keys, given_section_keys,
                     register_model)

__all__ = ["SECTIONS_LIQUEFACTION", "LAYER_KEYS", "check_liquefaction", "report_depths", "case_relative_path",
           "load_motion",
           "load_ann_weights", "load_reduction_table", "base_impedance", "layer_label", "saturated",
           "layer_elements", "layer_porosity", "effective_stress_bounds", "VISCOSITY_MAX", "VISCOSITY_DEFAULT"]

#: Default liquefied-soil viscosity [Pa·s]: Chen et al. (2019), falling-ball tests in liquefied
#: silty sand, 0.8–1.7 kPa·s; "a very viscous fluid" (Pringle 2001, ch. 1).
VISCOSITY_DEFAULT = 1000.0
#: Largest viscosity [Pa·s] the shear wave takes (average-acceleration Newmark is not L-stable:
#: at 1e7 Pa·s the stress zig-zags from step to step with 0.25 m elements and 5 ms steps).
VISCOSITY_MAX = 1e5

_MATERIALS = [k for k in SCHEMA["materials"] if k.name != "particle_diameter"]

_SITE = [
    K("depth", float, 0.0, "m", "depth of the base below the ground surface; if given (> 0) the layer "
      "thicknesses must add up to it (0: their sum)", lo=0.0, hi=1000.0),
    K("water_table_depth", float, 0.0, "m", "depth of the water table below the ground surface; the "
      "layers above it are a crust (no pore pressure; it must fall on a layer boundary)", lo=0.0, hi=1000.0),
    K("surcharge", float, 0.0, "Pa", "load on the ground surface (fill, foundation)", lo=0.0),
    K("initial_excess_ratio", float, 0.0, "-", "imposed initial excess pore-pressure ratio r_u0 of the "
      "saturated layers (n̄ lowered at constant n so that P_s = (1 − r_u0) σ′_v0)", lo=0.0, hi=1.0,
      hi_open=True),
    K("water_table_pressure", float, 0.0, "Pa", "liquid pressure at the water table (datum of P)"),
    K("slope", float, 0.0, "%", "ground slope S = 100 tan α in per cent (0: level ground): an infinite "
      "slope, driven as [site] groundwater says; thicknesses and depths are measured normal to the "
      "slope. Needs [shear_wave] model = \"hysteretic\" and no surcharge (docs/lateral-spreading.md)",
      lo=0.0, hi=10.0),
    K("groundwater", str, "slope_parallel_seepage", "-", "a sloping site's groundwater: "
      "\"slope_parallel_seepage\" (the water table parallel to the ground surface, the pore pressure "
      "constant along the slope: the total weight drives, τ_s = σ_v sin α cos α) or \"submerged\" "
      "(under still open water, the water table at or above the ground surface and no crust: the "
      "buoyant weight drives, τ_s = σ′_v sin α cos α, about half; the inertia keeps the total mass). "
      "Not used on level ground", choices=("slope_parallel_seepage", "submerged")),
]

LAYER_KEYS = [
    K("name", str, REQUIRED, "-", "layer name used in messages and outputs"),
    K("thickness", float, REQUIRED, "m", "layer thickness", lo=0.0, lo_open=True, hi=1000.0),
    K("elements", int, 0, "-", "elements in the layer (0: from element_size)", lo=0, hi=5000),
    K("element_size", float, 0.25, "m", "largest element size; the layer gets ceil(thickness/size) "
      "equal elements (used when elements = 0)", lo=0.0, lo_open=True, hi=1000.0),
    K("unit_weight", float, 0.0, "N/m³", "crust (above the water table): total unit weight γ; it adds "
      "σ′_v = γ z, mass γ/g and stiffness to the column. Required there, not used below", lo=0.0, hi=3e4),
    K("particle_diameter", float, 0.0, "m", "saturated layer: grain size d_p of the drag law; give it or "
      "hydraulic_conductivity (0: not given)", lo=0.0, hi=0.1),
    K("hydraulic_conductivity", float, 0.0, "m/s", "saturated layer, instead of particle_diameter: k at "
      "the layer's porosity; sets the drag through the equivalent diameter of the drag law at zero slip "
      "(Kozeny–Carman for Ergun, k = ρ_f g n³ d² / (150 μ_f (1 − n)²)); reported back (0: not given)",
      lo=0.0, hi=10.0),
    K("porosity", float, 0.0, "-", "saturated layer: porosity n, valid [0.2, 0.7]; or void_ratio "
      "(0: not given)", lo=0.0, hi=0.7),
    K("void_ratio", float, 0.0, "-", "saturated layer, instead of porosity: e = n/(1 − n), valid "
      "[0.25, 2.33] (0: not given)", lo=0.0, hi=2.34),
    K("relative_density", float, 47.0, "%", "Dr in per cent (a value ≤ 1, a fraction given for per cent, "
      "is refused): Byrne's C1 = 7600 Dr^−2.5; the simplified procedure's (N1)60 = 46 (Dr/100)²; "
      "saturated layers only", lo=1.0, lo_open=True, hi=100.0),
    K("k2max", float, 30.0, "-", "Seed–Idriss modulus number: G_max = 218.8 K2max √(σ′/1 kPa) kPa "
      "(ignored when shear_wave_velocity > 0)", lo=0.0, lo_open=True, hi=200.0),
    K("shear_wave_velocity", float, 0.0, "m/s", "small-strain V_s instead of k2max: G_max = ρ V_s² at the "
      "initial state (then ∝ √P_s as the skeleton softens); 0: use k2max", lo=0.0, hi=3000.0),
    K("gamma_ref", float, 1e-3, "-", "reference strain of the hyperbolic G/G_max = 1/(1 + |γ|/γ_ref) of "
      "the thesis model (the hysteretic model ignores it, with a warning)", lo=0.0, lo_open=True, hi=1.0, used_when=("modulus_reduction", ("hyperbolic",))),
    K("modulus_reduction", str, "hyperbolic", "-", "G/G_max(γ) curve: hyperbolic 1/(1 + |γ|/γ_ref), or "
      "tabulated (reduction_strains + reduction_ratios, or reduction_file), interpolated linearly in "
      "log γ with the end values held outside the table", choices=("hyperbolic", "tabulated")),
    K("reduction_strains", FLOATS, [], "-", "tabulated: shear strains γ of the table (a fraction, not %): "
      "> 0, strictly increasing, at least 2", used_when=("modulus_reduction", ("tabulated",))),
    K("reduction_ratios", FLOATS, [], "-", "tabulated: G/G_max at reduction_strains: in (0, 1], "
      "non-increasing", used_when=("modulus_reduction", ("tabulated",))),
    K("reduction_file", str, "", "-", "tabulated, instead of the two lists: CSV file of rows \"shear "
      "strain, G/G_max\" (strain a fraction; a header line and # comments allowed), a path relative to "
      "the case file", used_when=("modulus_reduction", ("tabulated",))),
    K("compressibility", float, 6e-4, "-", "saturated layer: A of P_s = p_ref exp[(1/A)(1 − (1 − n̄)/(1 − n))]; "
      "6e-4 calibrates the loose sand (docs/liquefaction.md)", lo=0.0, lo_open=True, hi=1.0),
    K("p_ref", float, 1.0, "Pa", "saturated layer: reference pressure of P_s", lo=0.0, lo_open=True),
    K("viscosity", float, VISCOSITY_DEFAULT, "Pa·s", "saturated layer: viscosity η_s of liquefied soil in "
      "the shear wave, in parallel with the elastic backbone, τ = G γ + (μ_m + η_s) ∂γ/∂t (plus the "
      "Rayleigh damping); it acts once G has fallen. Default 1000: Chen et al. (2019), falling-ball tests "
      "in liquefied soil, 0.8–1.7 kPa·s; power_law: its value at viscosity_reference_rate",
      lo=0.0, hi=VISCOSITY_MAX),
    K("viscosity_law", str, "newtonian", "-", "newtonian: η_s constant; power_law: shear thinning "
      "η_s = viscosity (|∂γ/∂t|/viscosity_reference_rate)^(viscosity_exponent − 1), at most 1e5 Pa·s "
      "(Lirer & Mele 2019 measured shear thinning in cyclic triaxial tests)",
      choices=("newtonian", "power_law")),
    K("viscosity_exponent", float, 0.5, "-", "power_law: flow index m (1: Newtonian)", lo=0.0, lo_open=True,
      hi=1.0, used_when=("viscosity_law", ("power_law",))),
    K("viscosity_reference_rate", float, 1.0, "1/s", "power_law: shear-strain rate at which η_s = viscosity",
      lo=0.0, lo_open=True, hi=1e3, used_when=("viscosity_law", ("power_law",))),
    K("reference_porosity_law", str, "byrne", "-", "densification law lowering n̄ under shear (Byrne 1991, "
      "or the thesis's network)", choices=("byrne", "ann")),
    K("ann_weights", str, "", "-", "ann: weights JSON file, a path relative to the case file ('' = the "
      "shipped default, trained on byrne)"),
    K("gamma_law_max", float, 0.01, "-", "|γ| beyond which the strain path adds no densification "
      "(the range of Byrne's law; strains in a liquefied layer are not bounded by this model)",
      lo=0.0, lo_open=True, hi=1.0),
    K("liquefiable", bool, True, "-", "saturated layer: false keeps n̄ fixed under shear (no pore-pressure "
      "generation; the layer still consolidates and drains)"),
    K("fines_content", float, 0.0, "%", "saturated layer: fines content F (per cent passing 0.075 mm), "
      "Youd et al.'s (2002) F15 on a sloping site", lo=0.0, hi=99.0),
    K("mean_grain_size", float, 0.0, "m", "saturated layer: mean grain size D50 (a sieve's, not the drag "
      "law's equivalent diameter, which is D10-like and 3–10 times smaller), Youd et al.'s (2002) D50_15 "
      "on a sloping site; 0: not given", lo=0.0, hi=0.1),
    K("n160cs", float, 0.0, "blows/0.3 m", "hysteretic model: clean-sand equivalent SPT (N1)60cs; sets CRR, "
      "the CSR–N slope b, K_σ, the residual strength and γ_lim (Idriss & Boulanger 2008, Boulanger & "
      "Idriss 2014). 0: from q_c1ncs if given, else 46 (Dr/100)²", lo=0.0, hi=46.0),
    K("qc1ncs", float, 0.0, "-", "hysteretic model: clean-sand equivalent normalised CPT tip resistance "
      "q_c1Ncs, instead of n160cs (Boulanger & Idriss 2014 CPT route; also used by the simplified "
      "procedure). 0: not given", lo=0.0, hi=250.0),
    K("csr_n_slope", float, 0.0, "-", "hysteretic model: slope b of the layer's cyclic strength curve "
      "CSR ∝ N^−b from its own cyclic tests, in [0.05, 0.6], instead of the b that the magnitude scaling "
      "factor of Boulanger & Idriss (2014) implies for its (N1)60cs or q_c1Ncs (0.10 at (N1)60cs = 10); "
      "the CRR at 15 cycles is unchanged and the simplified procedure takes MSF_max = 1.8^(b/0.34) for the "
      "layer. 0: from the MSF", lo=0.0, hi=CSR_N_SLOPE_RANGE[1]),
    K("friction_angle", float, 0.0, "deg", "hysteretic model: φ′ of the strength τ_max = σ′_v tan φ′; 0: "
      "Bolton (1986), 33° + 3 I_R from Dr and σ′_m", lo=0.0, hi=50.0),
    K("gqh_theta", FLOATS, [], "-", "hysteretic model: GQ/H backbone θ1…θ5 (Groholski et al. 2016); "
      "[0, 0, 1, 1, 1] is the hyperbola with strength τ_max; empty: fitted to Menq's (2003) G/G_max curve "
      "at the layer's mid-depth σ′_m and to the strength"),
    K("mrdf", FLOATS, [], "-", "hysteretic model: p1, p2, p3 of the MRDF unload–reload factor "
      "F = p1 − p2 (1 − G(γ_m)/G_max)^p3 (Phillips & Hashash 2009); [1, 0, 1] is Masing's rule; empty: "
      "fitted to Menq's (2003) damping curve with the backbone"),
]

_MOTION = [
    K("file", str, "RSN6_IMPVALL.I_I-ELC180-hor1.AT2", "-", "acceleration record — of the base "
      "([shear_wave] base = \"rigid\") or of the bedrock outcrop (\"compliant\"): a bundled name "
      "(data/ground_motions: El Centro, Kobe Takatori, Loma Prieta LGPC, Chi-Chi CHY002, Hector Mine Amboy; "
      "PROVENANCE.md there) or a path (.AT2 in g, or .csv time_s,acceleration) relative to the case file"),
    K("units", str, "g", "-", "CSV acceleration units (an .AT2 record is in g by its format)",
      choices=("g", "m/s2"), used_when=("file", Suffixes((".csv",)))),
    K("pga_g", float, 0.1, "g", "peak |a| the record is scaled to; 0 switches the shaking off",
      lo=0.0, hi=5.0),
    K("duration", float, -1.0, "s", "shake for this long (the record is cut); -1: the whole record"),
    K("baseline_order", int, 1, "-", "polynomial order of the velocity baseline removed before scaling "
      "(0: none)", lo=0, hi=3),
    K("magnitude", float, 6.95, "-", "moment magnitude M_w of the earthquake (the simplified procedure's "
      "magnitude scaling factor); 6.95: Imperial Valley 1940, the bundled El Centro record (each bundled "
      "record's M_w: data/ground_motions/PROVENANCE.md)", lo=5.0, hi=9.0),
    K("distance_km", float, 0.0, "km", "horizontal distance R from the site to the nearest bound of the "
      "seismic energy source: on a sloping site whose record is scaled by a factor within 0.5-2 (chosen near "
      "this M and R) the summary adds Youd et al.'s (2002) estimate, which depends on M and R; 0: not given",
      lo=0.0, hi=500.0),
    K("polarity", int, 1, "-", "sign of the record: 1 as recorded, -1 reversed (a → −a, after the scaling); on "
      "level ground the response is the mirror image (same r_u, settlement, peak strains)", choices=(1, -1)),
]

_SHEAR = [
    K("model", str, "hysteretic", "-", "shear law of the soil: hysteretic (GQ/H backbone with Masing/MRDF "
      "rules, strength σ′_v tan φ′ floored by the residual strength, cyclic mobility, pore pressure "
      "calibrated to the CRR curve of (N1)60cs; docs/liquefaction.md) or thesis (the non-linear elastic "
      "backbone and densification law of Pringle 2001: thesis reproduction only, not for design; warns)",
      choices=("hysteretic", "thesis")),
    K("step", float, 0.005, "s", "sub-step of the horizontal equation (Newmark average acceleration)",
      lo=0.0, lo_open=True, hi=0.05),
    K("damping_ratio", float, 0.05, "-", "Rayleigh damping ratio ξ at the two frequencies: with the thesis "
      "model a stand-in for hysteretic damping, which its non-linear elastic backbone lacks; with the "
      "hysteretic model the small-strain viscous floor beside the hysteresis (0.01 when not given, a "
      "warning above 0.02; its stiffness part uses the current G_max(P_s))", lo=0.0, hi=0.5),
    K("damping_frequencies", FLOATS, [1.0, 10.0], "Hz", "the two frequencies of the Rayleigh damping"),
    K("numerical_damping", float, 0.05, "-", "hysteretic model: δ of Newmark's γ = 1/2 + δ, β = (γ + 1/2)²/4; "
      "damps the mesh's highest modes (the element-to-element oscillation a yielding skeleton excites) at "
      "about δ ω Δt/2 (0.4 % at 5 Hz with δ = 0.05 and 5 ms sub-steps); 0: average acceleration (the "
      "thesis model always uses it)", lo=0.0, hi=0.5),
    K("free_vibration", float, 5.0, "s", "the shear wave keeps running this long after the record ends (on a "
      "sloping site: at least this long, then while the column flows, flow_velocity)", lo=0.0),
    K("flow_velocity", float, 1e-5, "m/s", "sloping site: after free_vibration the shear wave runs on while the "
      "surface's mean downslope velocity relative to the base, v̄ = (D̄(t − T, t) − D̄(t − 2T, t − T))/T with D̄ "
      "the time mean of its displacement over flow_window T, is at least this (the flow has stopped below "
      "it); 0: stop at free_vibration. No effect on level ground", lo=0.0, hi=0.1),
    K("flow_window", float, 2.0, "s", "sloping site: the averaging window T of flow_velocity (longer than the "
      "column's ring-down period, so that an oscillation averages out)", lo=0.0, lo_open=True, hi=60.0),
    K("flow_max", float, 600.0, "s", "sloping site: the shear wave stops at the latest this long after the "
      "record ends, still flowing or not (the summary says which)", lo=0.0, hi=86400.0),
    K("flow_step", float, 0.1, "s", "sloping site: largest vertical step and shear sub-step while the column "
      "flows after free_vibration (reached by ×1.5 growth from [time] step; at least [shear_wave] step)",
      lo=0.0, lo_open=True, hi=1.0),
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
    K("dissipated_r_u", float, 0.01, "-", "the run ends once the shear wave has stopped and max r_u of the "
      "saturated elements is below this ([time] end is the latest end); 0: run to [time] end",
      lo=0.0, hi=0.5),
]

_REPORT = [
    K("depths", FLOATS, [], "m",
      "depths below the ground surface of the r_u and σ′_v time series (in the saturated layers; "
      "[output] probes, heights above the base, are added); empty: nine depths evenly spaced through "
      "the saturated layers, z_w + k (H − z_w)/10 for k = 1 … 9 (water table z_w, base H)"),
    K("ru_liquefied", float, 0.95, "-", "r_u above which an element counts as liquefied", lo=0.0, hi=1.0,
      lo_open=True),
    K("field_interval", float, 0.1, "s", "time between rows of the r_u depth–time field (0: every step)",
      lo=0.0),
    K("spectrum_periods", FLOATS, [], "s", "periods of the 5 %-damped response spectra (empty: 60 "
      "log-spaced periods from 0.02 to 5 s)"),
    K("spectrum_damping", float, 0.05, "-", "damping ratio of the response spectra", lo=0.0, hi=0.5,
      hi_open=True),
]

#: [time] end when not given: the run goes on to dissipation ([reconsolidation] dissipated_r_u), capped here
DEFAULT_END_CAP_S = 86400.0
_TIME = [K("end", float, DEFAULT_END_CAP_S, "s", "latest end: the run ends once the excess pore pressure has "
           "dissipated ([reconsolidation] dissipated_r_u), at this time at the latest (summary.json: end_cap_s)",
           lo=0.0, lo_open=True)] + [k for k in SCHEMA["time"] if k.name != "end"]

SECTIONS_LIQUEFACTION = {
    "time": _TIME,
    "materials": _MATERIALS,
    "site": _SITE,
    "closures.drag": SCHEMA["closures.drag"],
    "closures.viscosity": SCHEMA["closures.viscosity"],
    "ground_motion": _MOTION,
    "shear_wave": _SHEAR,
    "reconsolidation": _RECON,
    "report": _REPORT,
}


def layer_label(case_or_layers, i: int) -> str:
    """``[layers 2 'loose sand']``: how messages name layer ``i`` (0-based) of a case."""
    layers = case_or_layers["layers"] if isinstance(case_or_layers, dict) else case_or_layers
    return f"[layers {i + 1} {layers[i]['name']!r}]"


def saturated(case: dict) -> list[bool]:
    """Per layer: below the water table (True) or in the crust above it (False)."""
    zw, top, out = case["site"]["water_table_depth"], 0.0, []
    for la in case["layers"]:
        out.append(top >= zw - 1e-9 * max(1.0, zw))
        top += la["thickness"]
    return out


def layer_elements(layer: dict) -> int:
    """Elements of a layer: ``elements``, or ceil(thickness/element_size)."""
    if layer["elements"] > 0:
        return layer["elements"]
    return max(1, math.ceil(layer["thickness"] / layer["element_size"] - 1e-9))


def layer_porosity(layer: dict) -> float:
    """n of a saturated layer from ``porosity`` or ``void_ratio`` (checked)."""
    return layer["porosity"] if layer["porosity"] > 0.0 else layer["void_ratio"] / (1.0 + layer["void_ratio"])


HYSTERETIC_DAMPING_RATIO = 0.01  # [shear_wave] damping_ratio not given, hysteretic model [-]
_SATURATED_ONLY = ("particle_diameter", "hydraulic_conductivity", "porosity", "void_ratio", "csr_n_slope")


def _check_hysteretic(case: dict, source: str) -> None:
    """The hysteretic model's per-layer lists, and a warning for the thesis model."""
    if case["shear_wave"]["model"] == "thesis":
        warnings.warn(CaseWarning(f"{source}: [shear_wave] model = \"thesis\": the non-linear elastic backbone "
                                  "of Pringle (2001), kept to reproduce the thesis: no hysteresis, no residual "
                                  "strength, no cyclic mobility; not for design"), stacklevel=2)
        return
    sw = case["shear_wave"]
    if "damping_ratio" not in given_section_keys("shear_wave"):  # the hysteresis damps: a viscous floor only
        sw["damping_ratio"] = HYSTERETIC_DAMPING_RATIO
    elif sw["damping_ratio"] > 0.02:
        warnings.warn(CaseWarning(f"{source}: [shear_wave] damping_ratio = {sw['damping_ratio']:g}: above the "
                                  "hysteretic model's small-strain viscous floor (about 0.01, the default); the "
                                  "hysteresis gives the damping, Rayleigh damping adds to it"), stacklevel=3)
    for i in range(len(case["layers"])):
        # (with a tabulated modulus_reduction the key's used_when has warned already)
        if "gamma_ref" in given_keys("layers", i) and case["layers"][i]["modulus_reduction"] == "hyperbolic":
            warnings.warn(CaseWarning(f"{source}: {layer_label(case, i)} gamma_ref: ignored by the hysteretic "
                                      "model (its backbone is GQ/H: gqh_theta, else fitted to Menq's curves); it "
                                      "sets the thesis model's hyperbola only"), stacklevel=3)
    for i, la in enumerate(case["layers"]):
        th, p = la["gqh_theta"], la["mrdf"]
        if th and (len(th) != 5 or not (th[0] <= 1.0 and th[1] >= 0.0 and th[0] + th[1] <= 1.0 and th[2] > 0.0
                                and th[3] > 0.0 and th[4] > 0.0)):
            raise CaseError(source, f"{layer_label(case, i)} gqh_theta", f"{th} must be five numbers "
                            "θ1..θ5 with θ1 ≤ 1, θ1 + θ2 ≤ 1 and θ3, θ4, θ5 > 0 (or empty: fitted)")
        if p and (len(p) != 3 or not (0.0 < p[0] <= 1.0 and 0.0 <= p[1] <= p[0] and p[2] > 0.0)):
            raise CaseError(source, f"{layer_label(case, i)} mrdf", f"{p} must be three numbers p1, p2, p3 "
                            "with 0 < p1 ≤ 1, 0 ≤ p2 ≤ p1 and p3 > 0 (or empty: fitted)")
        if la["n160cs"] > 0.0 and la["qc1ncs"] > 0.0:
            raise CaseError(source, f"{layer_label(case, i)} qc1ncs", "give n160cs or qc1ncs, not both")
        lo, hi = CSR_N_SLOPE_RANGE
        if 0.0 < la["csr_n_slope"] < lo:
            raise CaseError(source, f"{layer_label(case, i)} csr_n_slope", f"{la['csr_n_slope']:g} is outside "
                            f"the valid range [{lo:g}, {hi:g}] (or 0: from the magnitude scaling factor)")


def report_depths(case: dict) -> list[float]:
    """``[report] depths``, or where it is empty the nine depths that fit the site: z_w + k (H − z_w)/10,
    k = 1 … 9, through the saturated layers (water table z_w, base H) [m].

    >>> report_depths({"report": {"depths": []}, "site": {"water_table_depth": 2.0},
    ...                "layers": [{"thickness": 2.0}, {"thickness": 10.0}]})[:3]
    [3.0, 4.0, 5.0]
    """
    given = case["report"]["depths"]
    if given:
        return list(given)
    zw = case["site"]["water_table_depth"]
    H = sum(la["thickness"] for la in case["layers"])
    return [zw + k * (H - zw) / 10.0 for k in range(1, 10)]


def check_liquefaction(case: dict, source: str) -> None:
    """Cross-key checks of a ``liquefaction_1d`` case (one-line CaseError naming file and key)."""
    t, out = case["time"], case["output"]
    _check_layers(case, source)
    H = sum(la["thickness"] for la in case["layers"])
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
    zw = case["site"]["water_table_depth"]
    for z in report_depths(case):
        if not zw <= z <= H:
            raise CaseError(source, "[report] depths", f"{z:g} lies outside [{zw:g}, {H:g}] m (the saturated "
                            "layers, depths below the ground surface)")
    for y in out["probes"]:
        if not 0.0 <= y <= H - zw:
            raise CaseError(source, "[output] probes", f"{y:g} lies outside [0, {H - zw:g}] m (heights above "
                            "the base, in the saturated layers)")
    for tt in out["times"]:
        if not 0.0 <= tt <= t["end"]:
            raise CaseError(source, "[output] times", f"{tt:g} lies outside [0, {t['end']:g}] s")
    periods = case["report"]["spectrum_periods"]
    if any(not 0.0 < T <= 100.0 for T in periods) or any(b <= a for a, b in zip(periods, periods[1:])):
        raise CaseError(source, "[report] spectrum_periods", f"{periods} must be increasing periods in "
                        "(0, 100] s (or empty for the default)")
    _check_hysteretic(case, source)
    _check_slope(case, source)
    _check_physics(case, source)
    # the files the case names, read and checked now: a bad one must not start a run
    tables = []
    for i in range(len(case["layers"])):
        load_ann_weights(case, source, i)
        tables.append(load_reduction_table(case, source, i))
    load_motion(case, source)
    _warn_liquefied_site_record(case, source)
    for i, table in enumerate(tables):  # last: a warning only for a valid case
        _warn_softening(case, source, i, table)
    flow = sorted(k for k in _FLOW_KEYS if k in given_section_keys("shear_wave"))
    if flow and case["site"]["slope"] == 0.0:
        warnings.warn(CaseWarning(f"{source}: [shear_wave] {', '.join(flow)}: ignored on level ground ([site] "
                                  "slope = 0: the shear wave stops free_vibration seconds after the shaking; "
                                  "these keys act on a sloping site only)"), stacklevel=3)
    if "distance_km" in given_section_keys("ground_motion") and case["site"]["slope"] == 0.0:
        warnings.warn(CaseWarning(f"{source}: [ground_motion] distance_km: ignored on level ground ([site] slope "
                                  "= 0; it acts only in the lateral-spread estimate of a sloping site)"), stacklevel=3)
    for i, wet in enumerate(saturated(case)):
        la = case["layers"][i]
        given = [k for k in _SATURATED_ONLY if not wet and la[k] > 0.0]
        given += [k for k in ("relative_density",) if not wet and k in given_keys("layers", i)
                  and not _crust_density_acts(case, la)]
        if given:
            warnings.warn(CaseWarning(f"{source}: {layer_label(case, i)} {', '.join(given)}: ignored above the "
                                      "water table (a crust has its unit_weight, stiffness and G/G_max only)"),
                          stacklevel=3)
        if la["shear_wave_velocity"] > 0.0 and "k2max" in given_keys("layers", i):
            warnings.warn(CaseWarning(f"{source}: {layer_label(case, i)} k2max: ignored (shear_wave_velocity = "
                                      f"{la['shear_wave_velocity']:g} m/s gives G_max; k2max is used only when "
                                      "shear_wave_velocity is 0)"), stacklevel=3)


_FLOW_KEYS = ("flow_velocity", "flow_window", "flow_max", "flow_step")  # a sloping site's flow after the shaking


def _check_slope(case: dict, source: str) -> None:
    """A sloping site needs the hysteretic law (its static state and strength) and no surcharge
    (whose downslope component the column does not carry)."""
    slope = case["site"]["slope"]
    if slope == 0.0:
        return
    if case["shear_wave"]["model"] != "hysteretic":
        raise CaseError(source, "[site] slope", f"{slope:g} %: a sloping site needs [shear_wave] model = "
                        "\"hysteretic\" (valid with the thesis model: 0 only)")
    if case["site"]["surcharge"] > 0.0:
        raise CaseError(source, "[site] surcharge", f"{case['site']['surcharge']:g} Pa on a slope of {slope:g} %: "
                        "valid on a sloping site is 0 only (its downslope component is not modelled)")
    if case["site"]["groundwater"] == "submerged" and case["site"]["water_table_depth"] > 0.0:
        raise CaseError(source, "[site] water_table_depth", f"{case['site']['water_table_depth']:g} m with "
                        "[site] groundwater = \"submerged\": valid is 0 only (a submerged slope has its water "
                        "table at or above the ground surface, no crust; water above it: water_table_pressure)")
    if case["ground_motion"]["pga_g"] > 0.0 and case["ground_motion"]["baseline_order"] == 0:
        raise CaseError(source, "[ground_motion] baseline_order", f"0 on a slope of {slope:g} %: valid on a "
                        "sloping site are 1-3 (its displacements need a baseline-corrected record)")
    sw = case["shear_wave"]
    if sw["free_vibration"] + sw["flow_max"] < 2.0 * sw["flow_window"]:
        raise CaseError(source, "[shear_wave] flow_max", f"free_vibration + flow_max = {sw['free_vibration']:g} + "
                        f"{sw['flow_max']:g} s is shorter than two flow windows (2 × flow_window = "
                        f"{2.0 * sw['flow_window']:g} s), which the flow criterion after the shaking needs on a "
                        "sloping site: raise flow_max or free_vibration, or shorten flow_window")


def _check_layers(case: dict, source: str) -> None:
    """The profile: at least one layer, elements within their layers, the water table on a layer
    boundary above the base, each layer's soil given once (particle size or k, porosity or e)."""
    layers = case["layers"]
    if not layers:
        raise CaseError(source, "[[layers]]", "missing: a site needs at least one layer (a [[layers]] table "
                        "with name and thickness, from the ground surface down)")
    names = [la["name"] for la in layers]
    H = sum(la["thickness"] for la in layers)
    depth = case["site"]["depth"]
    if depth > 0.0 and abs(depth - H) > 1e-9 * depth:
        raise CaseError(source, "[site] depth", f"{depth:g} m, but the {len(layers)} layer thicknesses add up "
                        f"to {H:g} m; valid: their sum, or 0")
    zw = case["site"]["water_table_depth"]
    if zw >= H:
        raise CaseError(source, "[site] water_table_depth", f"{zw:g} m is at or below the base of the "
                        f"layers ({H:g} m); valid: [0, {H:g})")
    bounds, top = [], 0.0
    for la in layers:
        bounds.append(top)
        top += la["thickness"]
    if not any(abs(zw - b) <= 1e-9 * max(1.0, H) for b in bounds):
        i = max(j for j, b in enumerate(bounds) if b < zw)
        raise CaseError(source, "[site] water_table_depth", f"{zw:g} m falls inside {layer_label(case, i)} "
                        f"({bounds[i]:g}–{bounds[i] + layers[i]['thickness']:g} m); the water table must lie "
                        "on a layer boundary: split the layer there")
    sat = saturated(case)
    for i, la in enumerate(layers):
        lab = layer_label(case, i)
        if names.count(la["name"]) > 1:
            raise CaseError(source, f"{lab} name", "is used by more than one layer; layer names must differ")
        if la["elements"] == 0 and la["element_size"] > la["thickness"] * (1.0 + 1e-9):
            raise CaseError(source, f"{lab} element_size", f"{la['element_size']:g} m is larger than the "
                            f"layer ({la['thickness']:g} m); valid: (0, {la['thickness']:g}]")
        if la["elements"] == 0 and la["thickness"] / la["element_size"] > 5000:  # as the elements key
            raise CaseError(source, f"{lab} element_size", f"{la['element_size']:g} m gives more than 5000 "
                            f"elements in the layer ({la['thickness']:g} m); valid: at least "
                            f"{la['thickness'] / 5000:g} m")
        if not sat[i]:
            if not la["unit_weight"] > 0.0:
                raise CaseError(source, f"{lab} unit_weight", "missing: a layer above the water table (crust) "
                                "needs its total unit weight, valid (0, 30000] N/m³")
            continue
        if la["unit_weight"] > 0.0:
            raise CaseError(source, f"{lab} unit_weight", "is for layers above the water table; a saturated "
                            "layer's weight follows from its porosity and [materials] particle_density")
        given = [k for k in ("particle_diameter", "hydraulic_conductivity") if la[k] > 0.0]
        if len(given) != 1:
            raise CaseError(source, f"{lab} particle_diameter", "give exactly one of particle_diameter "
                            "(0, 0.1] m and hydraulic_conductivity (0, 10] m/s for a saturated layer"
                            + (" (both given)" if given else ""))
        given = [k for k in ("porosity", "void_ratio") if la[k] > 0.0]
        if len(given) != 1:
            raise CaseError(source, f"{lab} porosity", "give exactly one of porosity [0.2, 0.7] and void_ratio "
                            "[0.25, 2.33] for a saturated layer" + (" (both given)" if given else ""))
        n = layer_porosity(la)
        if not 0.2 <= n <= 0.7:
            key = given[0]
            rng = "[0.2, 0.7]" if key == "porosity" else "[0.25, 2.33]"
            raise CaseError(source, f"{lab} {key}", f"{la[key]:g} is outside the valid range {rng} [-]")
        if la["ann_weights"] and la["reference_porosity_law"] != "ann":
            raise CaseError(source, f"{lab} ann_weights", "only used with reference_porosity_law = \"ann\"")


def base_impedance(case: dict) -> float | None:
    """c = ρ_r V_r [Pa·s/m] of a compliant base, None for a rigid one."""
    sw = case["shear_wave"]
    return None if sw["base"] == "rigid" else sw["bedrock_density"] * sw["bedrock_shear_velocity"]


def load_reduction_table(case: dict, source: str, i: int):
    """(strains, ratios) of layer ``i``'s tabulated ``modulus_reduction`` (None: hyperbolic), from
    the inline lists or the CSV file, checked; every problem is a CaseError naming file, layer and key."""
    from ..closures.shear_modulus import table_problem

    la, lab = case["layers"][i], layer_label(case, i)
    if la["modulus_reduction"] != "tabulated":
        return None
    lists = bool(la["reduction_strains"] or la["reduction_ratios"])
    if la["reduction_file"] and lists:
        raise CaseError(source, f"{lab} reduction_file", "give the table either as reduction_file or as "
                        "reduction_strains + reduction_ratios, not both")
    if not la["reduction_file"] and not lists:
        raise CaseError(source, f"{lab} modulus_reduction", "\"tabulated\" needs a table: reduction_strains "
                        "and reduction_ratios, or reduction_file")
    if la["reduction_file"]:
        key = f"{lab} reduction_file"
        path = case_relative_path(case, source, la["reduction_file"])
        strains, ratios = _read_table(path, source, key)
        problem = table_problem(strains, ratios)
        if problem is not None:
            raise CaseError(source, key, f"{path.name}: {problem[1]}")
        return strains, ratios
    strains, ratios = la["reduction_strains"], la["reduction_ratios"]
    problem = table_problem(strains, ratios)
    if problem is not None:
        what = "strains" if problem[0] == "strains" or len(strains) < 2 else "ratios"
        raise CaseError(source, f"{lab} reduction_{what}", problem[1])
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


def _warn_softening(case: dict, source: str, i: int, table) -> None:
    """A valid table whose log interpolation makes the stress–strain backbone decrease somewhere."""
    if table is None:
        return
    from ..closures.shear_modulus import backbone_dips

    g, r = table
    dips = backbone_dips(g, r)
    if dips:
        key = "reduction_file" if case["layers"][i]["reduction_file"] else "reduction_ratios"
        pairs = ", ".join(f"{g[j]:g}–{g[j + 1]:g}" for j in dips)
        warnings.warn(CaseWarning(f"{source}: {layer_label(case, i)} {key}: the stress G_max (G/G_max) γ "
                                  f"falls by more than 1 % with growing strain between the points at γ = {pairs} "
                                  "under log interpolation (a softening backbone; add points between them)"),
                      stacklevel=3)


def effective_stress_bounds(case: dict) -> list[tuple[float, float] | None]:
    """Per layer, (σ′_v at its top element's centre, σ′_v at its base) [Pa] at rest (None: crust).

    σ′_v = surcharge + crust weight + buoyant weight (1 − n)(ρ_s − ρ_f) g of the saturated soil above.
    """
    ma = case["materials"]
    sig, out = case["site"]["surcharge"], []
    sat = saturated(case)
    for la, wet in zip(case["layers"], sat):
        if not wet:
            sig += la["unit_weight"] * la["thickness"]
            out.append(None)
            continue
        unit = (1.0 - layer_porosity(la)) * (ma["particle_density"] - ma["liquid_density"]) * ma["gravity"]
        h = la["thickness"] / layer_elements(la)
        out.append((sig + 0.5 * unit * h, sig + unit * la["thickness"]))
        sig += unit * la["thickness"]
    return out


def _check_physics(case: dict, source: str) -> None:
    """Inputs each valid alone whose combination has no deposit at rest to start from."""
    ma = case["materials"]
    if not ma["gravity"] > 0.0:
        raise CaseError(source, "[materials] gravity", f"{ma['gravity']:g} is outside the valid range "
                        "(0, inf) [m/s²]: the deposit's weight drives the model")
    if not ma["particle_density"] > ma["liquid_density"]:
        raise CaseError(source, "[materials] particle_density", f"{ma['particle_density']:g} must exceed "
                        f"[materials] liquid_density = {ma['liquid_density']:g} kg/m³ (grains without "
                        "buoyant weight carry no effective stress)")
    # initial reference porosity n̄0 = 1 − (1 − n)(1 − A ln(σ′/p_ref)) must lie in (0, 1) over the
    # range of σ′_v0 (1 − r_u0) of each layer: top element centre .. base (bounds of the discrete values)
    keep = 1.0 - case["site"]["initial_excess_ratio"]
    for i, bounds in enumerate(effective_stress_bounds(case)):
        if bounds is None:
            continue
        la, lab = case["layers"][i], layer_label(case, i)
        n, A, p_ref = layer_porosity(la), la["compressibility"], la["p_ref"]
        lo, hi = keep * bounds[0], keep * bounds[1]
        if A * math.log(hi / p_ref) >= 1.0:
            raise CaseError(source, f"{lab} compressibility", f"{A:g} gives a reference porosity n̄ >= 1 at the "
                            f"layer's base (σ′ = {hi:.4g} Pa); valid: A < 1/ln(σ′/p_ref) = "
                            f"{1.0 / math.log(hi / p_ref):.4g}")
        if (1.0 - n) * (1.0 - A * math.log(lo / p_ref)) >= 1.0:
            limit = lo * math.exp(n / ((1.0 - n) * A))
            raise CaseError(source, f"{lab} p_ref", f"{p_ref:g} Pa gives a reference porosity n̄ <= 0 at the "
                            f"layer's top element (σ′ = {lo:.4g} Pa); valid: p_ref < {limit:.4g} Pa")
        if bounds[1] > SIGMA_EFF_MAX_PA:  # the simplified procedure beside every run needs K_σ there
            raise CaseError(source, f"{lab} thickness", f"the layer's base is at σ′_v = {bounds[1]:.4g} Pa; the "
                            "simplified procedure evaluated beside the run (its K_σ) is valid to "
                            f"{SIGMA_EFF_MAX_PA:.4g} Pa (20 atm): valid are sites whose base is at most that")


def case_relative_path(case: dict, source: str, name: str) -> Path:
    """``name`` as given, or relative to the case file's folder (current folder for a bundled
    case or one built in memory)."""
    p = Path(name)
    if p.is_absolute() or not source or source.startswith("<") or source.endswith("(bundled)"):
        return p
    return Path(source).parent / p


def load_ann_weights(case: dict, source: str, i: int):
    """Layer ``i``'s ``ann_weights`` network (None: the law's shipped default or not ann)."""
    la = case["layers"][i]
    name = la["ann_weights"]
    if not name or la["reference_porosity_law"] != "ann":
        return None
    from ..closures.reference_porosity import AnnWeightsError, load_weights

    path = case_relative_path(case, source, name)
    try:
        return load_weights(path)
    except AnnWeightsError as exc:
        raise CaseError(source, f"{layer_label(case, i)} ann_weights", f"{exc} (valid: a twofluid-ann-1 JSON "
                        "file; a relative path is taken from the case file's folder)") from None


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


def _warn_liquefied_site_record(case: dict, source: str) -> None:
    """A record made at a site that itself liquefied, used as an input motion (valid, but it carries
    that site's liquefied response: softened, long-period, its peaks clipped)."""
    from ..io import ground_motion as gm

    if case["ground_motion"]["pga_g"] == 0.0:
        return
    entry = gm.liquefied_site_record(_record_path(case, source))
    if entry is not None:
        warnings.warn(CaseWarning(f"{source}: [ground_motion] file: {entry.name} ({entry.earthquake}, "
                                  f"{entry.station}) was recorded at a site that itself liquefied: an example of "
                                  "such a surface record, not an input motion (data/ground_motions/PROVENANCE.md)"),
                      stacklevel=3)


#: the sample intervals [s] a record may have (strong-motion records: 0.001 to 0.05 s)
RECORD_DT = (1e-4, 1.0)


def _check_sampling(m, path: Path, source: str, key: str) -> None:
    """A record sampled at one constant interval within :data:`RECORD_DT` (the shear wave, the
    response spectra and the record's cut all take it so), else a CaseError saying where it is not."""
    steps = np.diff(m.time)
    if m.dt is None:
        i = int(np.argmax(np.abs(steps - steps[0]) > 1e-6 * steps[0]))
        raise CaseError(source, key, f"{path.name}: uneven time steps ({steps[0]:.6g} s, then {steps[i]:.6g} s "
                        f"after t = {m.time[i]:.6g} s); valid: a record sampled at one constant interval "
                        "(resample it, e.g. by linear interpolation, to a constant step)")
    if not RECORD_DT[0] <= m.dt <= RECORD_DT[1]:
        raise CaseError(source, key, f"{path.name}: sample interval DT = {m.dt:g} s is outside the valid range "
                        f"[{RECORD_DT[0]:g}, {RECORD_DT[1]:g}] s")


def load_motion(case: dict, source: str):
    """The base record in m/s²: read, cut to ``duration``, baseline-corrected, scaled to
    ``pga_g`` with the sign ``polarity``; None if ``pga_g = 0``. Every problem is a CaseError naming the file and key."""
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
    _check_sampling(m, path, source, key)
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
    return gm.scale_to_pga(m, g["pga_g"], polarity=g["polarity"])


def _crust_density_acts(case: dict, layer: dict) -> bool:
    """Whether a layer above the water table uses its relative_density: under the hysteretic model it
    sets the crust's friction angle and fitted backbone unless n160cs or qc1ncs describe the soil."""
    return case["shear_wave"]["model"] == "hysteretic" and not (layer["n160cs"] > 0.0 or layer["qc1ncs"] > 0.0)


def inactive_keys(case: dict) -> dict:
    """The keys of a resolved liquefaction ``case`` that have no effect for the reasons this module's
    check warns of (``schema.INACTIVE``): a layer's gamma_ref under the hysteretic model, the
    saturated-only keys above the water table (and relative_density there where the crust does not use
    it: :func:`_crust_density_acts`), k2max beside a shear-wave velocity,
    and the flow keys and distance_km on level ground."""
    layers = []
    hysteretic = case["shear_wave"]["model"] != "thesis"
    for wet, la in zip(saturated(case), case["layers"]):
        off = set()
        if hysteretic and la["modulus_reduction"] == "hyperbolic":
            off.add("gamma_ref")
        if not wet:
            off.update(_SATURATED_ONLY)
            if not _crust_density_acts(case, la):
                off.add("relative_density")
        if la["shear_wave_velocity"] > 0.0:
            off.add("k2max")
        layers.append(frozenset(off))
    out = {"layers": layers}
    if case["site"]["slope"] == 0.0:
        out["shear_wave"] = frozenset(_FLOW_KEYS)
        out["ground_motion"] = frozenset({"distance_km"})
    return out


register_model("liquefaction_1d", SECTIONS_LIQUEFACTION, check_liquefaction, {"layers": LAYER_KEYS},
               inactive=inactive_keys)
