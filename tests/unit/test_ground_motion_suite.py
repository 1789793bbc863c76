"""The bundled ground-motion suite: the shipped records, their registry and provenance, the
``[ground_motion] polarity`` key, the liquefied-site record's warning and the five-motion ensemble."""
from __future__ import annotations

import csv
import warnings
from importlib import resources
from pathlib import Path

import numpy as np
import pytest

from twofluid.casefile import schema_liquefaction as sl
from twofluid.casefile.loader import case_text, load_case
from twofluid.casefile.schema import CaseError, CaseWarning, revalidate
from twofluid.cli import main
from twofluid.ensemble.members import members
from twofluid.ensemble.spec import load_ensemble, parse_ensemble
from twofluid.io import ground_motion as gm

FOLDER = Path(str(resources.files("twofluid") / "data" / "ground_motions"))

# (file, NPTS, DT [s], peak |a| [g]) as the shared data folder's README states them (computed there
# from the raw samples, three decimals): the reader must give the same within that rounding.
STATED = [
    ("RSN6_IMPVALL.I_I-ELC180-hor1.AT2", 5372, 0.01, 0.281),
    ("RSN1120_KOBE_TAK000.AT2", 4096, 0.01, 0.618),
    ("RSN779_LOMAP_LGP000.AT2", 5001, 0.005, 0.570),
    ("RSN1180_CHICHI_CHY002-N.AT2", 37500, 0.004, 0.137),
    ("RSN1762_HECTOR_ABY360.AT2", 3000, 0.02, 0.150),
    ("RSN8119_CCHURCH_PRPCS.AT2", 4001, 0.005, 0.596),
]
INPUTS = [name for name, b in gm.BUNDLED.items() if b.input_motion]


def _header(path: Path) -> list[str]:
    return path.read_text(errors="replace").splitlines()[:4]


@pytest.mark.parametrize("name, npts, dt, pga_g", STATED, ids=[s[0].split("_")[1] for s in STATED])
def test_each_shipped_record_loads_with_its_stated_size_step_and_peak(name, npts, dt, pga_g):
    m = gm.load(gm.bundled_record(name))
    assert m.npts == npts
    assert m.dt == pytest.approx(dt, rel=1e-12)
    assert m.time[-1] == pytest.approx((npts - 1) * dt, rel=1e-12)
    assert abs(m.pga_g - pga_g) <= 0.0005 + 1e-12  # the README rounds to three decimals
    # the header's NPTS and DT are the file's (the reader reads them; read here independently too)
    fields = _header(Path(m.source))[3].replace(",", " ").split()
    assert int(fields[fields.index("NPTS=") + 1]) == npts
    assert float(fields[fields.index("DT=") + 1]) == pytest.approx(dt, rel=1e-12)


def test_every_shipped_record_is_in_the_registry_and_every_entry_is_shipped():
    on_disk = sorted(p.relative_to(FOLDER).as_posix() for p in FOLDER.rglob("*") if p.suffix.lower() in (".at2", ".csv"))
    assert on_disk == sorted(b.path for b in gm.BUNDLED.values())
    # the five inputs lie in the folder itself; the liquefied-site record apart, in its subfolder
    assert sorted(INPUTS) == sorted(p.name for p in FOLDER.iterdir() if p.suffix.lower() == ".at2")
    assert len(INPUTS) == 5
    assert [b.path for b in gm.BUNDLED.values() if not b.input_motion] == ["liquefied-site/RSN8119_CCHURCH_PRPCS.AT2"]


@pytest.mark.parametrize("name", list(gm.BUNDLED))
def test_registry_matches_the_file_header_and_the_provenance_table(name):
    """The registry's station and component are those of the PEER header (line 2), and
    PROVENANCE.md gives each record a table row with the registry's M_w."""
    b = gm.BUNDLED[name]
    line2 = _header(gm.bundled_record(name))[1]
    assert b.station.split(" (")[0] in line2
    assert line2.rstrip().endswith(", " + b.component)
    rows = [r for r in (FOLDER / "PROVENANCE.md").read_text(encoding="utf-8").splitlines()
            if r.startswith(f"| `{b.path}`")]
    assert len(rows) == 1
    cells = [c.strip() for c in rows[0].split("|")]
    assert float(cells[4]) == b.magnitude


def test_bundled_names_resolve_and_an_unknown_name_lists_the_shipped_records():
    prpc = gm.bundled_record("RSN8119_CCHURCH_PRPCS.AT2")
    assert prpc == gm.bundled_record("liquefied-site/RSN8119_CCHURCH_PRPCS.AT2")
    assert prpc.parent.name == "liquefied-site"
    with pytest.raises(FileNotFoundError, match="RSN1120_KOBE_TAK000.AT2.*liquefied-site/RSN8119"):
        gm.bundled_record("RSN9999_NOWHERE.AT2")


def test_scale_to_pga_polarity_flips_the_sign_and_keeps_the_peak():
    m = gm.load(gm.bundled_record("RSN1120_KOBE_TAK000.AT2"))
    up, down = gm.scale_to_pga(m, 0.15), gm.scale_to_pga(m, 0.15, polarity=-1)
    assert np.array_equal(down.acceleration, -up.acceleration)
    assert down.pga_g == pytest.approx(0.15, rel=1e-12)
    for bad in (0, 2, -2, True):
        with pytest.raises(ValueError, match="polarity must be 1 or -1"):
            gm.scale_to_pga(m, 0.15, polarity=bad)


def _layered(tmp_path, motion_lines: str, name="site.toml") -> Path:
    """The bundled layered site with its [ground_motion] keys replaced by ``motion_lines``."""
    text = case_text("liquefaction-layered-site")
    head, rest = text.split("[ground_motion]\n", 1)
    tail = rest[rest.index("\n["):]
    path = tmp_path / name
    path.write_text(head + "[ground_motion]\n" + motion_lines + "\n" + tail, encoding="utf-8")
    return path


def test_polarity_reverses_the_motion_a_case_applies():
    case = load_case("liquefaction-layered-site")
    assert case["ground_motion"]["polarity"] == 1
    up = sl.load_motion(case, "layered")
    flipped = revalidate({**case, "ground_motion": {**case["ground_motion"], "polarity": -1}}, "layered")
    down = sl.load_motion(flipped, "layered")
    assert np.array_equal(down.acceleration, -up.acceleration)
    assert np.array_equal(down.time, up.time)


TINY = """[case]
name = "tiny"
model = "liquefaction_1d"
[materials]
liquid_density = 1000.0
liquid_viscosity = 1e-3
particle_density = 2650.0
[ground_motion]
file = "RSN1120_KOBE_TAK000.AT2"
pga_g = 0.1
duration = 5.2
polarity = {polarity}
[shear_wave]
step = 0.01
free_vibration = 0.0
[time]
end = 5.2
step = 0.02
[reconsolidation]
step = 0.02
[report]
depths = [1.0, 3.0]
[output]
plots = false
[[layers]]
name = "sand"
thickness = 4.0
elements = 4
particle_diameter = 8e-5
porosity = 0.44
"""


def test_a_run_with_polarity_minus_one_is_the_mirror_image_of_the_run_with_plus_one(tmp_path):
    """End to end: the rigid base's acceleration in probes.csv is the record, reversed by polarity;
    and a level column at rest with a shear law odd in γ and densification from |γ| is symmetric
    under u → −u, so accelerations and displacements change sign and r_u, σ′_v and settlement do
    not (exactly in exact arithmetic; every operation involved is sign-symmetric in IEEE arithmetic,
    1e-12 of the peak allows for nothing else)."""
    probes = {}
    for pol in (1, -1):
        path = tmp_path / f"tiny{pol}.toml"
        path.write_text(TINY.replace("{polarity}", str(pol)), encoding="utf-8")
        assert main(["run", str(path), "--out", str(tmp_path / f"out{pol}"), "--quiet"]) == 0
        with open(tmp_path / f"out{pol}" / "probes.csv", newline="") as f:
            rows = list(csv.DictReader(f))
        probes[pol] = {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}
    up, down = probes[1], probes[-1]
    assert np.max(np.abs(up["base_acceleration_m_s2"])) > 0.5  # m/s²: it shakes (0.1 g peak)
    np.testing.assert_array_equal(down["base_acceleration_m_s2"], -up["base_acceleration_m_s2"])
    assert np.max(up["r_u@3m"]) > 0.05  # pore pressure builds: the comparison below is not of zeros
    for key, a in up.items():
        b = down[key]
        odd = key in ("base_acceleration_m_s2", "surface_acceleration_m_s2", "surface_displacement_m")
        scale = max(np.max(np.abs(a)), 1e-300)
        assert np.max(np.abs((-b if odd else b) - a)) <= 1e-12 * scale, key


@pytest.mark.parametrize("value", ["0", "2", "-2", "1.0", '"-1"', "true"])
def test_bad_polarity_is_exit_2_with_one_line_and_nothing_written(tmp_path, capsys, value):
    path = _layered(tmp_path, f'file = "RSN1120_KOBE_TAK000.AT2"\npga_g = 0.15\npolarity = {value}')
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1, err
    assert str(path) in err and "[ground_motion] polarity" in err
    assert ("one of 1, -1" in err) or ("must be an integer" in err), err
    assert not out.exists()


def _case_warnings(path) -> list[str]:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        load_case(str(path))
    return [str(w.message) for w in caught if issubclass(w.category, CaseWarning)]


@pytest.mark.parametrize("given", ["liquefied-site/RSN8119_CCHURCH_PRPCS.AT2", "RSN8119_CCHURCH_PRPCS.AT2"])
def test_the_liquefied_site_record_as_an_input_is_warned_once(tmp_path, given):
    path = _layered(tmp_path, f'file = "{given}"\npga_g = 0.15\nmagnitude = 6.2')
    msgs = [m for m in _case_warnings(path) if "itself liquefied" in m]
    assert len(msgs) == 1 and "\n" not in msgs[0]
    assert msgs[0].startswith(f"{path}: [ground_motion] file: RSN8119_CCHURCH_PRPCS.AT2")
    assert "not an input motion" in msgs[0]


def test_the_liquefied_site_warning_names_a_copy_of_the_record_too_and_spares_the_inputs(tmp_path):
    copy = tmp_path / "RSN8119_CCHURCH_PRPCS.AT2"
    copy.write_bytes(gm.bundled_record("RSN8119_CCHURCH_PRPCS.AT2").read_bytes())
    assert any("itself liquefied" in m for m in _case_warnings(
        _layered(tmp_path, f'file = "{copy.name}"\npga_g = 0.15', "copy.toml")))
    for name in INPUTS:
        assert not any("itself liquefied" in m for m in _case_warnings(
            _layered(tmp_path, f'file = "{name}"\npga_g = 0.15', "input.toml")))
    # no shaking, no input: no warning
    assert not any("itself liquefied" in m for m in _case_warnings(
        _layered(tmp_path, f'file = "{copy.name}"\npga_g = 0.0', "still.toml")))


def test_the_liquefied_site_warning_is_one_line_on_the_console(tmp_path, capsys):
    path = _layered(tmp_path, 'file = "RSN8119_CCHURCH_PRPCS.AT2"\npga_g = 0.15\nmagnitude = 6.2')
    assert main(["simplified", str(path)]) == 0
    lines = [ln for ln in capsys.readouterr().err.splitlines() if "itself liquefied" in ln]
    assert len(lines) == 1 and lines[0].startswith("twofluid: warning: ")


def _arias_t95(name: str) -> float:
    m = gm.load(gm.bundled_record(name))
    ia = np.cumsum(m.acceleration ** 2)
    return float(m.time[np.searchsorted(ia / ia[-1], 0.95)])


def _five_motion_members(name: str, base: str, pga: float) -> list:
    """The members of the bundled five-motion ensemble ``name`` on case ``base``: ten, valid and
    distinct, each input record once per polarity at ``pga`` [g], on the compliant base, with the
    record's own M_w; ``pga`` None: each member's own."""
    spec = load_ensemble(name)
    assert spec.base["case"]["name"] == base
    ms = members(spec)
    assert len(ms) == 10 and not [m.error for m in ms if m.error]
    assert len({m.hash for m in ms}) == 10
    seen = set()
    for m in ms:
        g = m.case["ground_motion"]
        assert (pga is None or g["pga_g"] == pga) and m.case["shear_wave"]["base"] == "compliant"
        assert g["magnitude"] == gm.BUNDLED[g["file"]].magnitude  # the zipped magnitudes line up with the records
        seen.add((g["file"], g["polarity"]))
    assert seen == {(name, p) for name in INPUTS for p in (1, -1)}
    return ms


def test_the_five_motion_ensemble_validates_and_expands_to_ten_members():
    for m in _five_motion_members("layered-site-five-motions", "liquefaction-layered-site", 0.15):
        g = m.case["ground_motion"]
        assert gm.BUNDLED[g["file"]].input_motion
        # each record shakes through 95 % of its Arias intensity and no longer than it lasts
        assert _arias_t95(g["file"]) <= g["duration"] < _arias_t95(g["file"]) + 0.5


def test_the_sloping_five_motion_ensemble_expands_to_ten_members():
    """The sloping site under the five input records, both polarities (checked without running it)."""
    for m in _five_motion_members("sloping-site-five-motions", "sloping-site", None):
        assert m.case["site"]["slope"] == 3.0 and m.case["shear_wave"]["flow_velocity"] > 0.0


# R_rup [km] (PROVENANCE.md) and the earthquake's mechanism of each input record
SCENARIOS = {"RSN6_IMPVALL.I_I-ELC180-hor1.AT2": (6.1, "SS"), "RSN1120_KOBE_TAK000.AT2": (1.5, "SS"),
             "RSN779_LOMAP_LGP000.AT2": (3.9, "RS"), "RSN1180_CHICHI_CHY002-N.AT2": (25.0, "RS"),
             "RSN1762_HECTOR_ABY360.AT2": (43.0, "SS")}


def test_the_sloping_ensemble_states_each_earthquake_and_scales_to_bssa14():
    """Each member stands for its record's earthquake at the station's distance: distance_km is R_rup,
    and pga_g is BSSA14's median PGA there at V_s30 760 m/s (to the 3 figures written; pygmm where
    installed), a scale factor within 0.5-2 of the record's own PGA over the shaking."""
    try:
        import pygmm
    except ImportError:
        pygmm = None
    for m in _five_motion_members("sloping-site-five-motions", "sloping-site", None):
        g = m.case["ground_motion"]
        r, mech = SCENARIOS[g["file"]]
        assert g["distance_km"] == r
        rec = gm.load(gm.bundled_record(g["file"]))
        own = np.abs(rec.acceleration[rec.time <= g["duration"] + 1e-12]).max() / gm.G_STANDARD
        assert 0.5 <= g["pga_g"] / own <= 2.0
        if pygmm is not None:
            sc = pygmm.Scenario(mag=g["magnitude"], dist_jb=r, dist_rup=r, v_s30=760.0, mechanism=mech,
                                region="california")
            assert g["pga_g"] == float(f"{pygmm.BooreStewartSeyhanAtkinson2014(sc).pga:.3g}")


def test_the_input_folder_gives_the_five_inputs_and_not_the_liquefied_site_record():
    """An ensemble's [ground_motions] files = the bundled folder runs the input suite only."""
    spec = parse_ensemble({"ensemble": {"base": "liquefaction-layered-site", "collect": ["settlement_end_m"]},
                           "ground_motions": {"files": str(FOLDER) + "/"}}, "<test>", FOLDER)
    assert sorted(p.name for p in spec.motions["files"]) == sorted(INPUTS)


def test_a_bad_polarity_in_an_edited_case_is_a_case_error():
    case = load_case("liquefaction-layered-site")
    with pytest.raises(CaseError, match=r"^x: \[ground_motion\] polarity: 0 is not valid; valid: one of 1, -1$"):
        revalidate({**case, "ground_motion": {**case["ground_motion"], "polarity": 0}}, "x")
