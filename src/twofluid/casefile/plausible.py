"""Physically plausible ranges of the dimensional keys: a value typed in the wrong unit is caught.

The schema's valid range (:class:`~twofluid.casefile.schema.Key` ``lo``/``hi``) says what the model
can compute; this table says what a real site, bed or liquid can be. For every key whose unit is
not "-" it gives

- ``refuse``: outside it (zero, "off", allowed where ``zero_ok``), the value is refused
  (:class:`~twofluid.casefile.schema.CaseError`, exit status 2), naming the likely unit mistake:
  ``unit_weight = 18.5`` is "18.5 N/m³ … did you mean 18500 (kN/m³ typed into an N/m³ key, ×1000)?";
- ``usual``: outside it but inside ``refuse``, a one-line warning (the value is possible but rare,
  and the same hint where a unit mistake would explain it).

``mistakes`` lists (factor, what): the value times the factor is what was probably meant, named
when it lands in ``usual``. Bounds apply to ``|value|`` where ``signed`` (a pressure, a velocity
may be negative). A key given at its "not set" sentinel (``-1``) is not checked. The table is
rendered into docs/case-file.md (:func:`markdown_rows`), and a test checks that every dimensional
key of every schema has an entry here.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["Plausible", "PLAUSIBLE", "lookup", "check", "markdown_rows"]

G = 9.80665


@dataclass(frozen=True)
class Plausible:
    refuse: tuple  # (lo, hi): outside is an error; None: no bound
    usual: tuple  # (lo, hi): outside (inside refuse) is a warning
    mistakes: tuple = ()  # ((factor, "what was typed"), ...)
    zero_ok: bool = True  # 0 means "off" / "not given" / the datum: never refused or warned
    signed: bool = False  # bounds on |value|
    note: str = ""  # why these bounds


def _p(refuse, usual, *mistakes, **kw) -> Plausible:
    return Plausible(tuple(refuse), tuple(usual), tuple(mistakes), **kw)


# common unit mistakes: (factor to the key's unit, what was typed)
KN = (1e3, "kN/m³ typed into an N/m³ key, ×1000")
G_CC = (1e3, "g/cm³ or t/m³ typed into a kg/m³ key, ×1000")
MPAS = (1e-3, "mPa·s (cP) typed into a Pa·s key, ×0.001")
MM = (1e-3, "mm typed into a metre key, ×0.001")
UM = (1e-6, "µm typed into a metre key, ×1e-6")
CM = (1e-2, "cm typed into a metre key, ×0.01")
KPA = (1e3, "kPa typed into a Pa key, ×1000")
MS2_AS_G = (1.0 / G, "m/s² typed into a key in g, ÷9.81")
G_AS_MS2 = (G, "g typed into an m/s² key, ×9.81")
FRACTION = (100.0, "a fraction typed into a per-cent key, ×100")
MM_S = (1e-3, "mm/s typed into an m/s key, ×0.001")
CM_S = (1e-2, "cm/s typed into an m/s key, ×0.01")
KM_S = (1e3, "km/s typed into an m/s key, ×1000")
RAD = (180.0 / math.pi, "radians typed into a degree key, ×57.3")
RPM = (2.0 * math.pi / 60.0, "rev/min typed into a rad/s key, ×2π/60")
CM2 = (1e-4, "cm² typed into an m² key, ×1e-4")
M_AS_KM = (1e-3, "metres typed into a km key, ×0.001")

_LENGTH = _p((1e-6, 1e4), (1e-3, 100.0), MM, signed=True)  # a column, a bed, a height in it [m]
_TIME = _p((None, 3.2e9), (None, 1e8), note="100 years refused, 3 years warned")  # [s]
_PRESSURE = _p((None, 1e9), (None, 1e7), signed=True, note="1 GPa refused")  # [Pa]
_INLET = _p((None, 100.0), (None, 1.0), MM_S, signed=True, note="superficial velocity of a bed or a flow")

#: (section, key) -> Plausible. A section "boundary.*" stands for every boundary, "layers" for every
#: entry of [[layers]].
PLAUSIBLE: dict[tuple[str, str], Plausible] = {
    ("materials", "liquid_density"): _p((10.0, 2.5e4), (500.0, 2000.0), G_CC, zero_ok=False,
                                        note="a liquid: water 1000, mercury 13546"),
    ("materials", "particle_density"): _p((50.0, 2.5e4), (500.0, 12000.0), G_CC, zero_ok=False,
                                          note="hollow spheres to heavy metals; quartz 2650"),
    ("materials", "liquid_viscosity"): _p((1e-6, 1e4), (2e-4, 10.0), MPAS, zero_ok=False,
                                          note="water 1e-3, glycerol 1.4"),
    ("materials", "particle_diameter"): _p((1e-8, 0.1), (1e-6, 0.02), MM, UM, zero_ok=False,
                                           note="10 nm to 100 mm"),
    ("materials", "gravity"): _p((0.5, 2000.0), (9.7, 9.9), G_AS_MS2, zero_ok=False,
                                 note="the Moon to a geotechnical centrifuge"),
    ("time", "end"): _TIME,
    ("time", "step"): _p((None, 1e8), (1e-8, 1e5)),
    ("time", "max_step"): _p((None, 1e8), (None, 1e6)),
    ("output", "times"): _TIME,
    ("output", "probes"): _LENGTH,
    ("output", "probe_interval"): _TIME,
    ("mesh", "length"): _p((1e-5, 1e4), (1e-3, 100.0), MM, zero_ok=False),
    ("mesh", "area"): _p((1e-10, 1e6), (1e-6, 100.0), CM2, zero_ok=False),
    ("mesh", "area_top"): _p((1e-10, 1e6), (1e-6, 100.0), CM2),
    ("mesh", "inclination_deg"): _p((None, 89.0), (None, 89.0), signed=True, note="the schema's range"),
    ("mesh", "x0"): _LENGTH, ("mesh", "x1"): _LENGTH, ("mesh", "y0"): _LENGTH, ("mesh", "y1"): _LENGTH,
    ("mesh", "cut"): _LENGTH,
    ("closures.solids_pressure", "p_ref"): _p((None, 1e9), (None, 1e6), zero_ok=False),
    ("initial", "bed_height"): _LENGTH,
    ("initial", "settled_height"): _LENGTH,
    ("initial", "solids_mass"): _p((1e-9, 1e9), (1e-6, 1e6)),
    ("boundary.*", "pressure"): _PRESSURE,
    ("boundary.*", "times"): _TIME,
    ("boundary.*", "velocities"): _INLET,
    ("boundary.*", "solids_velocity"): _INLET,
    ("boundary.*", "omega"): _p((None, 1e4), (None, 100.0), RPM, signed=True,
                                note="rad/s; 100 rad/s is about 950 rev/min"),
    # a 1D inlet given by its flow rate, and a round column by its diameter (where the schema has them)
    ("boundary.*", "flow_rates_l_min"): _p((None, 1e6), (None, 1000.0), note="laboratory beds 0.1 to 10 L/min"),
    ("boundary.*", "flow_rates_m3_h"): _p((None, 1e5), (None, 100.0)),
    ("mesh", "diameter"): _p((1e-4, 100.0), (5e-3, 5.0), MM),
    ("profiles", "heights"): _LENGTH,
    ("profiles", "steady_tolerance"): _p((None, 1e3), (None, 1.0)),
    ("single_fluid", "density"): _p((10.0, 2.5e4), (500.0, 5000.0), G_CC, zero_ok=False),
    ("single_fluid", "viscosity"): _p((1e-6, 1e7), (2e-4, 1e4), MPAS, zero_ok=False,
                                      note="up to pastes and liquefied soil"),
    ("single_fluid", "height"): _LENGTH,
    ("single_fluid", "r_inner"): _LENGTH,
    # liquefaction_1d
    ("site", "depth"): _p((None, 1000.0), (None, 100.0), note="a soil column; the schema allows 1000 m"),
    ("site", "water_table_depth"): _p((None, 1000.0), (None, 50.0)),
    ("site", "surcharge"): _p((None, 1e7), (1e3, 1e6), KPA,
                              note="0: none; a few hundred Pa is no fill or foundation (kPa typed as Pa?)"),
    ("site", "water_table_pressure"): _PRESSURE,
    ("site", "slope"): _p((None, 10.0), (0.5, 10.0), FRACTION, note="per cent; 0: level ground"),
    ("ground_motion", "pga_g"): _p((None, 2.0), (None, 1.0), MS2_AS_G,
                                   note="in g: the largest recorded horizontal PGAs are 1-3 g"),
    ("ground_motion", "duration"): _p((None, 1e4), (None, 600.0)),
    ("ground_motion", "distance_km"): _p((None, 500.0), (None, 300.0), M_AS_KM),
    ("shear_wave", "step"): _p((None, 0.05), (1e-5, 0.05)),
    ("shear_wave", "damping_frequencies"): _p((1e-3, 1e3), (0.05, 50.0)),
    ("shear_wave", "free_vibration"): _p((None, 1e5), (None, 600.0)),
    ("shear_wave", "flow_velocity"): _p((None, 0.1), (None, 0.1), note="the schema's range"),
    ("shear_wave", "flow_window"): _p((None, 60.0), (None, 60.0), note="the schema's range"),
    ("shear_wave", "flow_max"): _p((None, 86400.0), (None, 86400.0), note="the schema's range"),
    ("shear_wave", "flow_step"): _p((None, 1.0), (None, 1.0), note="the schema's range"),
    ("shear_wave", "bedrock_density"): _p((1000.0, 5000.0), (1800.0, 3200.0), G_CC, zero_ok=False),
    ("shear_wave", "bedrock_shear_velocity"): _p((50.0, 1e4), (300.0, 3500.0), KM_S, zero_ok=False,
                                                 note="760 m/s: the B/C boundary"),
    ("reconsolidation", "step"): _p((None, 1e6), (None, 3600.0)),
    ("report", "depths"): _p((None, 1000.0), (None, 100.0)),
    ("report", "field_interval"): _TIME,
    ("report", "spectrum_periods"): _p((1e-3, 100.0), (0.01, 10.0)),
    ("layers", "thickness"): _p((1e-3, 1000.0), (0.1, 50.0), CM, zero_ok=False),
    ("layers", "element_size"): _p((1e-3, 1000.0), (0.01, 5.0), CM, zero_ok=False),
    ("layers", "unit_weight"): _p((100.0, 30000.0), (13000.0, 23000.0), KN,
                                  note="a soil's total unit weight: 13 to 23 kN/m³; lightweight fill (EPS "
                                       "0.2 kN/m³) warns (0: not given)"),
    ("layers", "particle_diameter"): _p((1e-7, 0.1), (1e-6, 0.01), MM, UM,
                                        note="silt to gravel (0: not given)"),
    ("layers", "hydraulic_conductivity"): _p((1e-13, 1.0), (1e-9, 0.01), CM_S,
                                             note="clay to clean gravel (0: not given)"),
    ("layers", "relative_density"): _p((1.0, 100.0), (15.0, 95.0), FRACTION),
    ("layers", "shear_wave_velocity"): _p((30.0, 3000.0), (60.0, 800.0), KM_S,
                                          note="a soil's V_s (0: from k2max)"),
    ("layers", "p_ref"): _p((None, 1e9), (None, 1e6), zero_ok=False),
    ("layers", "viscosity"): _p((None, 1e5), (None, 1e5), note="the schema's range"),
    ("layers", "viscosity_reference_rate"): _p((None, 1000.0), (1e-3, 1000.0)),
    ("layers", "fines_content"): _p((1.0, 99.0), (1.0, 70.0), FRACTION,
                                    note="per cent; below 1 % reads as a fraction (0: clean sand)"),
    ("layers", "mean_grain_size"): _p((1e-6, 0.1), (1e-5, 0.02), MM, note="0: not given"),
    ("layers", "n160cs"): _p((None, 46.0), (2.0, 46.0), note="(N1)60cs; 0: from relative_density"),
    ("layers", "friction_angle"): _p((1.1, 50.0), (20.0, 45.0), RAD,
                                     note="degrees; ≤ 1.1 reads as radians (0: from the density)"),
    # the immersed granular layer on an incline ([layer] of an immersed_avalanche case)
    ("layer", "thickness"): _p((1e-5, 1.0), (1e-3, 0.1), MM, zero_ok=False,
                               note="a laboratory layer: 1 mm to 10 cm usual (Pailha et al. 4.9 mm)"),
    ("layer", "slope_deg"): _p((1.1, 60.0), (5.0, 45.0), RAD, zero_ok=False,
                               note="degrees; ≤ 1.1 reads as radians"),
    ("layer", "skeleton_modulus"): _p((1e3, 1e12), (1e5, 1e10), KPA, zero_ok=False,
                                      note="the contact stiffness of the grains (glass beads ~4e7 Pa at 10–40 Pa)"),
}


def lookup(where: str, name: str) -> Plausible | None:
    """The entry of key ``name`` in section ``where`` (a section, "boundary.left", or an array
    entry's label such as ``layers 2 'loose sand'``)."""
    if (where, name) in PLAUSIBLE:
        return PLAUSIBLE[(where, name)]
    if where.startswith("boundary."):
        return PLAUSIBLE.get(("boundary.*", name))
    return PLAUSIBLE.get((where.split(" ")[0], name))


def _outside(b: tuple, v: float) -> bool:
    return (b[0] is not None and v < b[0]) or (b[1] is not None and v > b[1])


def check(where: str, name: str, unit: str, value: float, sentinel=None) -> tuple[str, str] | None:
    """("error" | "warning", message) for ``value`` of key ``name`` in ``where``, or None when it
    is plausible. The message names the likely unit mistake where one explains the value.

    >>> check("layers 1 'crust'", "unit_weight", "N/m³", 18.5)[1]
    '18.5 N/m³ is physically implausible (plausible: 100 to 30000); did you mean 18500 (kN/m³ typed into an N/m³ key, ×1000)?'
    >>> check("ground_motion", "pga_g", "g", 2.45)[1]
    '2.45 g is physically implausible (plausible: ≤ 2); did you mean 0.25 (m/s² typed into a key in g, ÷9.81)?'
    >>> check("ground_motion", "pga_g", "g", 1.2)[0], check("ground_motion", "pga_g", "g", 0.3)
    ('warning', None)
    """
    p = lookup(where, name)
    if p is None or (sentinel is not None and value == sentinel) or (value == 0.0 and p.zero_ok):
        return None
    v = abs(value) if p.signed else value
    if not _outside(p.refuse, v) and not _outside(p.usual, v):
        return None
    hint = ""
    for factor, what in p.mistakes:
        if not _outside(p.usual, v * factor) and not _outside(p.refuse, v * factor):
            hint = f"; did you mean {float(f'{value * factor:.3g}'):.10g} ({what})?"
            break
    lo, hi = p.refuse if _outside(p.refuse, v) else p.usual
    bounds = f"{lo:g} to {hi:g}" if lo is not None and hi is not None else (
        f"≥ {lo:g}" if lo is not None else f"≤ {hi:g}")
    bounds = ("|value| " if p.signed else "") + bounds
    if _outside(p.refuse, v):
        return "error", f"{value:g} {unit} is physically implausible (plausible: {bounds}){hint}"
    return "warning", f"{value:g} {unit} is unusual (usual: {bounds}){hint}; check its unit"


def markdown_rows() -> list[str]:
    """The table of docs/case-file.md's "Plausible ranges" section."""
    lines = ["| key | refused outside | warned outside | likely mistakes named | note |", "|---|---|---|---|---|"]

    def iv(b, signed):
        lo = "" if b[0] is None else f"{b[0]:g}"
        hi = "" if b[1] is None else f"{b[1]:g}"
        s = f"{lo} to {hi}" if lo and hi else (f"≥ {lo}" if lo else f"≤ {hi}" if hi else "-")
        return ("\\|value\\| " if signed and s != "-" else "") + s
    for (where, name), p in PLAUSIBLE.items():
        sect = "[[layers]]" if where == "layers" else f"[{where}]"
        zero = "" if not p.zero_ok else "0 allowed"
        note = "; ".join(x for x in (p.note, zero) if x)
        lines.append(f"| `{sect} {name}` | {iv(p.refuse, p.signed)} | {iv(p.usual, p.signed)} | "
                     f"{'; '.join(w for _, w in p.mistakes) or '-'} | {note} |")
    return lines
