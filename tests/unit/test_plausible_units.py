"""Units that cannot be mistaken: every dimensional key of every schema has a physically plausible
range (twofluid.casefile.plausible); outside it a case is refused naming the likely unit mistake,
outside the usual range it warns in one line."""
import math
import shutil
import subprocess
import sys
import warnings

import pytest

from twofluid.casefile import schema as S
from twofluid.casefile.loader import load_case
from twofluid.casefile.plausible import PLAUSIBLE, check, lookup
from twofluid.casefile.schema import CaseError, CaseWarning, revalidate

for _m in S._MODEL_MODULES:
    S._model_schema(_m)

#: a bundled case of each model, where a key of that model's sections is set
BASE = {"two_fluid_1d": "settling-illite", "reduced_1d": "settling-illite", "two_fluid_2d": "viscometer",
        "liquefaction_1d": "liquefaction-layered-site", "immersed_avalanche": "immersed-avalanche"}


def _dimensional():
    """(model, section, key) of every dimensional number key of every schema, each (section, key) once."""
    seen, out = set(), []
    for model, schema in S.SCHEMAS.items():
        items = list(schema.items()) + [(a, k) for a, k in S.ARRAYS[model].items()]
        for where, keys in items:
            for k in keys:
                if k.unit not in ("-", "") and k.type in (float, int, S.FLOATS) and (where, k.name) not in seen:
                    seen.add((where, k.name))
                    out.append((model, where, k))
    return out


DIMENSIONAL = _dimensional()


@pytest.mark.parametrize("model, where, key", DIMENSIONAL, ids=[f"{w}.{k.name}" for _, w, k in DIMENSIONAL])
def test_every_dimensional_key_has_a_plausible_range(model, where, key):
    assert lookup(where, key.name) is not None, f"add [{where}] {key.name} [{key.unit}] to plausible.PLAUSIBLE"


def _implausible(p):
    lo, hi = p.refuse
    return hi * 10.0 if hi is not None else lo / 10.0


def _case_with(model, where, key, value):
    """The bundled case of ``model`` with [where] key = value (a list key as a one-entry list)."""
    name = BASE[model]
    if model == "two_fluid_1d" and where in ("time", "output", "materials") and key.name == "max_step":
        name = "viscometer"
    case = load_case(name)
    v = [value] if key.type == S.FLOATS else value
    if where == "layers":
        case["layers"][-1][key.name] = v
    else:
        table = case
        for part in where.split("."):
            table = table.setdefault(part, {})
        table[key.name] = v
    return case


def _model_of(where, key):
    for model, w, k in DIMENSIONAL:
        if w == where and k.name == key:
            return model, k
    return None, None


IN_SCHEMA = sorted((w, n) for w, n in PLAUSIBLE
                   if any(k.name == n and (w == ws or (w == "boundary.*" and ws.startswith("boundary.")))
                          for _, ws, k in DIMENSIONAL))


def test_most_plausible_ranges_are_of_keys_of_the_schemas():
    assert len(IN_SCHEMA) >= len(PLAUSIBLE) - 3  # the table may lead the schema by a few keys, not more


@pytest.mark.parametrize("where, name", IN_SCHEMA, ids=[f"{w}.{n}" for w, n in IN_SCHEMA])
def test_a_value_outside_the_plausible_range_is_refused_in_one_line(where, name):
    p = PLAUSIBLE[(where, name)]
    sect = "boundary.bottom" if where == "boundary.*" else where
    model, key = _model_of(sect, name)
    if model is None:  # a key of a boundary the 1D models do not have (2D: boundary.left …)
        model, key = _model_of("boundary.left", name)
        sect = "boundary.left"
    case = _case_with(model, sect, key, _implausible(p))
    with pytest.raises(CaseError) as exc, warnings.catch_warnings():
        warnings.simplefilter("ignore", CaseWarning)
        revalidate(case, "c.toml")
    msg = str(exc.value)
    assert "\n" not in msg and name in msg
    assert "physically implausible" in msg or "outside the valid range" in msg, msg


BANDS = [(w, n) for (w, n), p in sorted(PLAUSIBLE.items()) if p.usual != p.refuse]


@pytest.mark.parametrize("where, name", BANDS, ids=[f"{w}.{n}" for w, n in BANDS])
def test_an_unusual_but_possible_value_warns(where, name):
    p = PLAUSIBLE[(where, name)]
    (rlo, rhi), (ulo, uhi) = p.refuse, p.usual
    if uhi is not None and (rhi is None or uhi < rhi):
        v = uhi * 1.5 if rhi is None else math.sqrt(uhi * rhi) if uhi > 0 else rhi / 2
    else:
        v = math.sqrt(rlo * ulo) if rlo else ulo / 2
    sect = where.replace("*", "bottom")
    found = check(sect, name, "unit", v)
    assert found is not None and found[0] == "warning" and "unusual" in found[1], (v, found)


MISTAKES = [(w, n, f, what) for (w, n), p in sorted(PLAUSIBLE.items()) for f, what in p.mistakes]


@pytest.mark.parametrize("where, name, factor, what", MISTAKES, ids=[f"{w}.{n}-{f:g}" for w, n, f, _ in MISTAKES])
def test_each_listed_unit_mistake_is_named(where, name, factor, what):
    """Usual values typed in the unit of the mistake (value / factor) are refused or warned with the
    value that was probably meant, wherever the mistyped value is not itself usual."""
    p = PLAUSIBLE[(where, name)]
    ulo, uhi = p.usual
    lo, hi = (ulo or (uhi or 1.0) * 1e-3), (uhi or (ulo or 1.0) * 1e3)
    named = 0
    for i in range(13):
        meant = lo * (hi / lo) ** (i / 12) if lo > 0 else lo + (hi - lo) * i / 12
        found = check(where.replace("*", "bottom"), name, "unit", meant / factor)
        if found is not None:
            assert "did you mean" in found[1], found
            named += what in found[1]
    assert named > 0, f"no usual value of {name} typed as {what} is caught"


# ---------------------------------------------------------------- the common mistakes, through the command
EXE = [shutil.which("twofluid")] if shutil.which("twofluid") else [sys.executable, "-m", "twofluid.cli"]


def _layered_case(tmp_path, edit):
    text = subprocess.run([*EXE, "show", "liquefaction-layered-site"], capture_output=True, text=True,
                          check=True).stdout
    path = tmp_path / "site.toml"
    path.write_text(edit(text))
    return path


@pytest.mark.parametrize("key, typed, says", [
    ("unit_weight", "18.5", "did you mean 18500 (kN/m³ typed into an N/m³ key"),
    ("fines_content", "0.15", "did you mean 15 (a fraction typed into a per-cent key"),
])
def test_common_layer_mistakes_are_refused_by_the_command(tmp_path, key, typed, says):
    import re

    def edit(text):
        new, n = re.subn(rf"(?m)^{key}\s*=\s*[^#\n]*", f"{key} = {typed} ", text, count=1)
        if n == 0:  # the case does not give it: into the first [[layers]] entry
            new = text.replace("[[layers]]\n", f"[[layers]]\n{key} = {typed}\n", 1)
        return new
    path = _layered_case(tmp_path, edit)
    p = subprocess.run([*EXE, "run", str(path), "--out", str(tmp_path / "out")], capture_output=True, text=True)
    assert p.returncode == 2, p.stderr
    assert says in p.stderr and p.stderr.count("\n") == 1, p.stderr
    assert not (tmp_path / "out").exists()


def test_pga_in_metres_per_second_squared_is_refused_by_the_command(tmp_path):
    import re

    path = _layered_case(tmp_path, lambda t: re.sub(r"(?m)^pga_g\s*=\s*[^#\n]*", "pga_g = 2.45 ", t, count=1))
    p = subprocess.run([*EXE, "run", str(path)], capture_output=True, text=True, cwd=tmp_path)
    assert p.returncode == 2 and "did you mean 0.25 (m/s² typed into a key in g" in p.stderr, p.stderr


def test_a_particle_density_of_1e20_is_refused_not_a_silent_end():
    case = load_case("settling-illite")
    case["materials"]["particle_density"] = 1e20
    with pytest.raises(CaseError, match=r"particle_density: 1e\+20 kg/m³ is physically implausible"):
        revalidate(case, "c.toml")


def test_a_density_in_grams_per_cubic_centimetre_names_the_mistake():
    case = load_case("settling-illite")
    case["materials"]["particle_density"] = 2.65
    with pytest.raises(CaseError, match=r"did you mean 2650 \(g/cm³ or t/m³ typed into a kg/m³ key"):
        revalidate(case, "c.toml")


def test_an_unusual_value_warns_in_one_line_and_runs():
    case = load_case("settling-illite")
    case["materials"]["gravity"] = 1.0  # possible (a lighter world), unusual: one line, with the hint
    with pytest.warns(CaseWarning) as rec:
        S.validate({k: v for k, v in case.items() if not k.startswith("_")}, "c.toml")
    lines = [str(w.message) for w in rec if "gravity" in str(w.message)]
    assert len(lines) == 1 and "\n" not in lines[0] and "did you mean 9.81 (g typed into an m/s² key" in lines[0]


# ---------------------------------------------------------------- unknown keys, keys without effect
def test_an_unknown_key_suggests_the_nearest_one():
    case = load_case("liquefaction-layered-site")
    case["layers"][0]["unit_wieght"] = 18500.0
    with pytest.raises(CaseError, match=r"unit_wieght: unknown key; did you mean 'unit_weight'\?$"):
        revalidate(case, "c.toml")


def test_an_unknown_section_suggests_the_nearest_one():
    doc = {k: v for k, v in load_case("settling-illite").items() if not k.startswith("_")}
    doc["material"] = doc.pop("materials")
    with pytest.raises(CaseError, match=r"\[material\]: unknown section .* did you mean 'materials'\?"):
        S.validate(doc, "c.toml")


def test_distance_km_on_level_ground_warns_that_it_has_no_effect():
    doc = {k: v for k, v in load_case("liquefaction-layered-site").items() if not k.startswith("_")}
    assert doc["site"]["slope"] == 0.0
    doc["ground_motion"]["distance_km"] = 10.0
    with pytest.warns(CaseWarning, match=r"distance_km: ignored on level ground"):
        S.validate(doc, "c.toml")


def test_a_slopes_flow_keys_that_leave_no_two_windows_are_refused():
    """free_vibration + flow_max < 2 flow_window ran the whole computation and then ended with no
    summary (a TypeError); it is refused when the case is loaded."""
    case = load_case("sloping-site")
    case["shear_wave"].update(free_vibration=0.0, flow_max=0.0, flow_window=2.0)
    with pytest.raises(CaseError, match=r"\[shear_wave\] flow_max: .*two flow windows"):
        revalidate(case, "c.toml")
    case["shear_wave"].update(free_vibration=4.0)  # exactly two windows: valid
    revalidate(case, "c.toml")
