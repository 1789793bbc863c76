"""Layered sites (``[[layers]]``, a water table below the surface, a crust), dissipation, sand boils,
spectra and the simplified procedure beside the two-fluid result.

The runs use the bundled ``liquefaction-layered-site`` at a coarse mesh (0.5 m in the loose sand,
1 m elsewhere) and 4 s of shaking: a few seconds each.

Tolerances: the geostatic state is exact in the discrete model (1e-12 relative for σ′_v, the
rest test |r_u| < 1e-6 as for the one-layer column); a given k comes back through the equivalent
diameter to round-off (asserted 1e-9; 1 % would do); the final settlement predicted by a run
stopped early is an exact integration of the skeleton law but ignores the densification that is
already over and the drainage path, so it is compared with the dissipated run to 3 %.
"""
from __future__ import annotations

import json

import numpy as np
import pytest

from twofluid.casefile.loader import load_case
from twofluid.cli import main
from twofluid.models.liquefaction_1d import VISCOSITY_MAX, Sand
from twofluid.runners import liquefaction_report as report
from twofluid.runners.liquefaction import build_column, hydraulic_conductivity, run_liquefaction

CASE = "liquefaction-layered-site"


def _coarse(changes=None):
    c = load_case(CASE)
    sizes = {"crust": 1.0, "loose sand": 0.5, "dense sand": 1.0}
    for la in c["layers"]:
        la["element_size"] = sizes[la["name"]]
    c["ground_motion"]["duration"] = 4.0
    c["shear_wave"]["free_vibration"] = 2.0
    c["output"].update(plots=False, times=[], probes=[1.0])  # 1 m above the base: 14 m deep
    for (section, key), value in (changes or {}).items():
        c[section][key] = value
    return c


@pytest.fixture(scope="module")
def layered(tmp_path_factory):
    return run_liquefaction(_coarse(), tmp_path_factory.mktemp("site") / "run")


def test_loose_over_dense_liquefies_in_the_loose_layer_only(layered):
    s = layered.summary
    assert s["status"] == "completed"
    loose, dense = s["layers"][1], s["layers"][2]
    assert loose["name"] == "loose sand" and dense["name"] == "dense sand"
    top, bottom = s["liquefied_depth_range_m"]
    assert 2.0 <= top < bottom <= 8.0  # depths from the ground surface
    assert loose["liquefied_thickness_m"] > 0.0 and loose["peak_r_u"] > 0.95
    assert dense["liquefied_thickness_m"] == 0.0 and dense["peak_r_u"] < 0.95
    assert s["layers"][0]["saturated"] is False and "peak_r_u" not in s["layers"][0]
    # the crust shears with the column
    assert s["layers"][0]["peak_shear_strain"] > 0.0


def test_water_table_at_depth_is_an_exact_equilibrium_carrying_the_crust(tmp_path):
    c = _coarse()
    c["ground_motion"]["pga_g"] = 0.0
    c["time"]["end"] = 2.0
    b = build_column(c)
    col, st = b.column, b.state
    ma = c["materials"]
    g = ma["gravity"]
    crust = c["layers"][0]["unit_weight"] * c["layers"][0]["thickness"]
    n = st.vertical.n
    h = col.v.mesh.lengths
    unit = (1.0 - n) * (ma["particle_density"] - ma["liquid_density"]) * g
    below = np.cumsum((unit * h)[::-1])[::-1] - 0.5 * unit * h  # buoyant weight above each centre
    np.testing.assert_allclose(col.sigma_v0, crust + below, rtol=1e-12)
    depth_below_wt = col.depth - c["site"]["water_table_depth"]
    np.testing.assert_allclose(st.vertical.P, ma["liquid_density"] * g * depth_below_wt, rtol=1e-12)
    r = run_liquefaction(c, tmp_path / "rest")
    assert r.status == "completed"
    assert np.max(np.abs(r.history["r_u"])) < 1e-6
    assert abs(r.summary["settlement_end_m"]) < 1e-9


@pytest.mark.parametrize("k", [1e-5, 1e-4, 3e-3])
def test_given_hydraulic_conductivity_is_reported_back(k):
    c = _coarse()
    for la in c["layers"][1:]:
        la["hydraulic_conductivity"] = k
    b = build_column(c)
    col = b.column
    got = hydraulic_conductivity(col, col.n0)
    np.testing.assert_allclose(got, k, rtol=1e-9)
    # Kozeny–Carman: the Ergun (Gidaspow below its switch) equivalent diameter
    ma = c["materials"]
    n = col.n0
    d = np.sqrt(150.0 * ma["liquid_viscosity"] * (1 - n) ** 2 * k / (ma["liquid_density"] * ma["gravity"] * n**3))
    np.testing.assert_allclose(col.v.mat.d, d, rtol=1e-9)


def test_given_conductivity_in_the_summary(layered):
    for la in layered.summary["layers"][1:]:
        assert la["hydraulic_conductivity_m_s"] == pytest.approx(la["hydraulic_conductivity_given_m_s"], rel=0.01)


def test_run_stopped_early_predicts_its_final_settlement(layered, tmp_path):
    """A run stopped at its end time says so and how far it got; its predicted final settlement is
    what the dissipated run reaches."""
    full = layered.summary
    assert full["dissipation"]["dissipated"] and full["reason"].startswith("dissipated")
    assert full["stopped_at_s"] < full["end_time_s"]
    early = run_liquefaction(_coarse({("time", "end"): 20.0}), tmp_path / "early").summary
    d = early["dissipation"]
    assert early["status"] == "completed" and not d["dissipated"]
    assert early["reason"].startswith("stopped at the end time 20 s before dissipation")
    assert 0.0 < d["fraction_of_final_settlement"] < 0.99
    assert d["final_settlement_m"] == pytest.approx(full["settlement_end_m"], rel=0.03)


def test_outputs_with_depths_from_the_ground_surface(layered):
    out = layered.out_dir
    import csv

    rows = list(csv.DictReader(open(out / "elements.csv")))
    s = layered.summary
    assert len(rows) == s["site"]["elements"]
    z = [float(r["depth_m"]) for r in rows]
    assert z == sorted(z) and z[0] < 2.0 < z[-1] < 15.0
    crust = [r for r in rows if r["layer"] == "crust"]
    assert crust and all(r["saturated"] == "no" and r["peak_r_u"] == "" for r in crust)
    assert all(float(r["FS_simplified_input"]) > 0.0 for r in rows if r["saturated"] == "yes")
    lay = list(csv.DictReader(open(out / "layers.csv")))
    assert [r["layer"] for r in lay] == ["crust", "loose sand", "dense sand"]
    assert float(lay[1]["liquefied_thickness_m"]) == pytest.approx(s["layers"][1]["liquefied_thickness_m"])
    assert lay[0]["peak_r_u"] == "" and lay[0]["FS_min_simplified_input"] == "" and lay[0]["FS_note"] == "NL"
    spec = list(csv.DictReader(open(out / "spectra.csv")))
    assert set(spec[0]) == {"period_s", "Sa_input_g", "Sa_surface_g", "amplification"}
    probes = list(csv.DictReader(open(out / "probes.csv")))
    assert "r_u@14m" in probes[0] and "r_u@2.5m" in probes[0]
    motion = np.loadtxt(out / "surface_motion.csv", delimiter=",", skiprows=1)
    assert np.max(np.abs(motion[:, 1])) / report.G == pytest.approx(s["shaking"]["peak_surface_acceleration_g"])
    assert json.loads((out / "summary.json").read_text())["simplified_procedure"]["magnitude"] == 6.95


def test_simplified_procedure_beside_the_run(layered):
    """With the input's PGA (0.2 g) the simplified procedure liquefies the loose layer, not the dense
    one nor the crust; its settlement is reported next to the two-fluid one."""
    s = layered.summary["simplified_procedure"]
    top, bottom = s["liquefied_depth_range_input_m"]
    assert 2.0 <= top < bottom <= 8.0
    assert s["a_max_input_g"] == pytest.approx(0.2)
    assert s["settlement_input_m"] > 0.0
    layers = layered.summary["layers"]
    assert layers[0]["simplified_min_FS_input"] == float("inf")
    assert layers[2]["simplified_min_FS_input"] > 1.0 > layers[1]["simplified_min_FS_input"]
    table = s["table_input"]
    assert len(table) == layered.summary["site"]["elements"]
    assert table[0]["z_mid [m]"] < table[-1]["z_mid [m]"]  # from the ground surface down
    assert table[0]["FS [-]"] == float("inf")  # the crust


def test_spectra_of_a_scaled_copy_give_its_ratio():
    """spectra(): a surface motion that is twice the input (on the same samples) has amplification 2
    at every period; the input is padded with zeros to the surface history's length."""
    from twofluid.io.ground_motion import GroundMotion

    dt = 0.01
    t = np.arange(0.0, 5.0 + dt / 2, dt)
    a = 0.5 * np.sin(2 * np.pi * 1.5 * t) * np.exp(-0.3 * t)
    m = GroundMotion(t, a, "sine", "test", dt)
    ts = np.concatenate([t[1:], t[-1] + dt * np.arange(1, 200)])
    surf = np.concatenate([2.0 * a[1:], np.zeros(199)])
    sp = report.spectra(m, ts, surf, [0.1, 0.5, 1.0, 2.0])
    np.testing.assert_allclose(sp["amplification"], 2.0, rtol=1e-9)
    assert sp["pga_input_g"] == pytest.approx(0.5 * np.max(np.abs(np.sin(2 * np.pi * 1.5 * t) * np.exp(-0.3 * t)))
                                              / report.G)


def test_power_law_viscosity():
    s = Sand(viscosity=np.array([1000.0, 1000.0]), viscosity_exponent=np.array([1.0, 0.5]),
             viscosity_reference_rate=2.0)
    eta = s.shear_viscosity(np.array([8.0, 8.0]))
    np.testing.assert_allclose(eta, [1000.0, 500.0], rtol=1e-12)  # 1000 (8/2)^(-1/2)
    assert s.shear_viscosity(np.array([0.0, 0.0]))[1] == VISCOSITY_MAX  # capped at rest
    assert Sand().shear_viscosity(np.zeros(3)).tolist() == [1000.0] * 3  # the default, Newtonian


def test_power_law_case_runs(tmp_path):
    c = _coarse({("ground_motion", "duration"): 1.0, ("time", "end"): 2.0})
    c["layers"][1].update(viscosity_law="power_law", viscosity_exponent=0.6, viscosity_reference_rate=0.1)
    assert run_liquefaction(c, tmp_path / "pl").status == "completed"


def test_simplified_command_prints_the_table(capsys):
    assert main(["simplified", CASE, "--a-max", "0.2"]) == 0
    out = capsys.readouterr().out.strip().splitlines()
    b = build_column(load_case(CASE))
    assert len(out) == 2 + b.column.y_all.size - 1  # header, one row per element, the total
    assert out[1].split()[0] == "0.25" and out[1].split()[-3] == "-"  # the crust cannot liquefy
    assert "a_max = 0.200 g, M = 6.95" in out[-1]


def _site_text(site=None, layers=None, **sections):
    base = {"case": {"name": "s", "model": "liquefaction_1d"},
            "materials": {"liquid_density": 1000.0, "liquid_viscosity": 1e-3, "particle_density": 2650.0},
            "site": {"water_table_depth": 1.0, **(site or {})},
            "ground_motion": {"pga_g": 0.0}, "time": {"end": 1.0, "step": 0.02},
            "report": {"depths": [2.0]}, **sections}
    if layers is None:
        layers = [{"name": "crust", "thickness": 1.0, "unit_weight": 18000.0},
                  {"name": "sand", "thickness": 4.0, "hydraulic_conductivity": 1e-4, "porosity": 0.44}]
    lines = []
    for sec, keys in base.items():
        lines.append(f"[{sec}]")
        lines += [f"{k} = {json.dumps(v)}" for k, v in keys.items()]
    for la in layers:
        lines.append("[[layers]]")
        lines += [f"{k} = {json.dumps(v)}" for k, v in la.items()]
    return "\n".join(lines) + "\n"


CRUST = {"name": "crust", "thickness": 1.0, "unit_weight": 18000.0}
SAND = {"name": "sand", "thickness": 4.0, "hydraulic_conductivity": 1e-4, "porosity": 0.44}
BAD = [  # (site, layers, sections, words)
    (None, [], {}, ["[[layers]]", "at least one layer"]),
    ({"depth": 6.0}, None, {}, ["[site] depth", "add up to 5 m"]),
    ({"water_table_depth": 5.0}, None, {}, ["[site] water_table_depth", "at or below the base", "[0, 5)"]),
    ({"water_table_depth": 2.0}, None, {}, ["[site] water_table_depth", "inside [layers 2 'sand']",
                                           "layer boundary"]),
    (None, [CRUST, {**SAND, "element_size": 5.0}], {}, ["[layers 2 'sand'] element_size", "(0, 4]"]),
    (None, [{**CRUST, "unit_weight": 0.0}, SAND], {}, ["[layers 1 'crust'] unit_weight", "(0, 30000]"]),
    (None, [CRUST, {**SAND, "unit_weight": 19000.0}], {}, ["[layers 2 'sand'] unit_weight", "above the water"]),
    (None, [CRUST, {**SAND, "particle_diameter": 1e-4}], {}, ["[layers 2 'sand'] particle_diameter",
                                                              "exactly one", "both given"]),
    (None, [CRUST, {**SAND, "hydraulic_conductivity": 0.0}], {}, ["[layers 2 'sand'] particle_diameter",
                                                                  "(0, 10] m/s"]),
    (None, [CRUST, {**SAND, "hydraulic_conductivity": 20.0}], {}, ["[layers 2 'sand'] hydraulic_conductivity",
                                                                   "[0, 10]"]),
    (None, [CRUST, {**SAND, "void_ratio": 0.8}], {}, ["[layers 2 'sand'] porosity", "both given"]),
    (None, [CRUST, {**SAND, "porosity": 0.1}], {}, ["[layers 2 'sand'] porosity", "[0.2, 0.7]"]),
    (None, [CRUST, {**SAND, "porosity": 0.0, "void_ratio": 0.2}], {}, ["[layers 2 'sand'] void_ratio",
                                                                      "[0.25, 2.33]"]),
    (None, [CRUST, {**SAND, "name": "crust"}], {}, ["name", "more than one layer"]),
    (None, [CRUST, {**SAND, "thickness": -1.0}], {}, ["[layers 2 'sand'] thickness", "(0, 1000]"]),
    (None, [CRUST, {**SAND, "viscosity_law": "bingham"}], {}, ["[layers 2 'sand'] viscosity_law", "'power_law'"]),
    (None, [CRUST, {**SAND, "viscosity_law": "power_law", "viscosity_exponent": 0.0}], {},
     ["[layers 2 'sand'] viscosity_exponent", "(0, 1]"]),
    (None, [CRUST, {**SAND, "viscosity": 1e6}], {}, ["[layers 2 'sand'] viscosity", "[0, 100000]"]),
    (None, [CRUST, {**SAND, "shear_wave_velocity": -5.0}], {}, ["[layers 2 'sand'] shear_wave_velocity",
                                                                "[0, 3000]"]),
    (None, [CRUST, {**SAND, "liquefiable": "yes"}], {}, ["[layers 2 'sand'] liquefiable", "true or false"]),
    (None, [CRUST, {**SAND, "compressibility": 0.5}], {}, ["[layers 2 'sand'] compressibility", "valid: A <"]),
    (None, [CRUST, {"thickness": 4.0}], {}, ["[layers 2] name", "missing"]),
    (None, None, {"ground_motion": {"pga_g": 0.0, "magnitude": 4.0}}, ["[ground_motion] magnitude", "[5, 9]"]),
    (None, None, {"reconsolidation": {"dissipated_r_u": 0.9}}, ["[reconsolidation] dissipated_r_u", "[0, 0.5]"]),
    (None, None, {"report": {"depths": [0.5]}}, ["[report] depths", "outside [1, 5] m"]),
    ({"water_table_depth": -1.0}, None, {}, ["[site] water_table_depth", "[0, 1000]"]),
    ({"depth": -2.0}, None, {}, ["[site] depth", "[0, 1000]"]),
    (None, [CRUST, {**SAND, "elements": -1}], {}, ["[layers 2 'sand'] elements", "[0, 5000]"]),
    (None, [CRUST, {**SAND, "element_size": 0.0}], {}, ["[layers 2 'sand'] element_size", "(0, 1000]"]),
    (None, [CRUST, {**SAND, "viscosity_law": "power_law", "viscosity_reference_rate": 0.0}], {},
     ["[layers 2 'sand'] viscosity_reference_rate", "(0, 1000]"]),
    (None, None, {"report": {"depths": [2.0], "spectrum_damping": 0.5}}, ["[report] spectrum_damping", "[0, 0.5)"]),
    (None, [CRUST, {**SAND, "csr_n_slope": 0.01}], {}, ["[layers 2 'sand'] csr_n_slope", "[0.05, 0.6]"]),
    (None, [CRUST, {**SAND, "csr_n_slope": 0.7}], {}, ["[layers 2 'sand'] csr_n_slope", "0.6"]),
    (None, None, {"report": {"depths": [2.0], "spectrum_periods": [0.5, 0.1]}},
     ["[report] spectrum_periods", "increasing"]),
]


@pytest.mark.parametrize("site, layers, sections, words", BAD)
def test_bad_site_is_exit_2_and_one_line(tmp_path, capsys, site, layers, sections, words):
    path = tmp_path / "site.toml"
    path.write_text(_site_text(site, layers, **sections))
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "Traceback" not in err and str(path) in err, err
    for w in words:
        assert w in err, err
    assert not out.exists()


def test_unknown_array_of_tables(tmp_path, capsys):
    path = tmp_path / "site.toml"
    path.write_text(_site_text() + "[[colours]]\nname = \"red\"\n")
    assert main(["run", str(path), "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert "[[colours]]" in err and "[[layers]]" in err


def test_valid_site_text_runs(tmp_path):
    path = tmp_path / "site.toml"
    path.write_text(_site_text())
    assert main(["run", str(path), "--out", str(tmp_path / "o"), "--quiet"]) == 0


def test_saturated_keys_on_the_crust_are_a_warning(tmp_path):
    from twofluid.casefile.schema import CaseWarning

    path = tmp_path / "site.toml"
    path.write_text(_site_text(layers=[{**CRUST, "porosity": 0.4}, SAND]))
    with pytest.warns(CaseWarning, match=r"\[layers 1 'crust'\] porosity: ignored above the water table"):
        load_case(str(path))


def test_layers_keep_their_own_laws():
    """Per element: a non-liquefiable layer keeps n̄; law groups give each layer its own law."""
    from twofluid.closures.reference_porosity import ShearState, byrne, ann

    mask = np.array([True, True, False, False])
    s = Sand(dr=np.array([47.0, 47.0, 80.0, 80.0]), liquefiable=np.array([True, False, True, True]),
             law_groups=((mask, "byrne", {}), (~mask, "ann", {})))
    law = s.n_bar_law()
    nb0 = np.full(4, 0.5)
    dg = np.full(4, 1e-3)
    nb, _ = law(dg, dg, nb0, ShearState.zeros(4))
    ref_b, _ = byrne(dg, dg, nb0, ShearState.zeros(4), c1=7600.0 * s.dr ** -2.5)
    ref_a, _ = ann(dg, dg, nb0, ShearState.zeros(4))
    assert nb[0] == ref_b[0] < 0.5  # byrne, Dr 47 %
    assert nb[1] == 0.5  # not liquefiable: n̄ held
    np.testing.assert_array_equal(nb[2:], ref_a[2:])  # the ann layer


def test_shear_wave_velocity_sets_g_max_at_rest():
    c = _coarse()
    c["layers"][0]["shear_wave_velocity"] = 150.0  # crust
    c["layers"][2]["shear_wave_velocity"] = 250.0  # dense sand
    b = build_column(c)
    col = b.column
    from twofluid.closures.shear_modulus import seed_idriss_gmax

    g_sat = seed_idriss_gmax(col.sigma_v0, col.sand.k2max)
    rho = col.mixture_density(col.n0)
    dense = b.site.layer_of == 2
    np.testing.assert_allclose(g_sat[dense], rho[dense] * 250.0**2, rtol=1e-12)
    np.testing.assert_allclose(col.crust.g_max, 18000.0 / 9.81 * 150.0**2, rtol=1e-12)
    loose = b.site.layer_of == 1  # k2max = 30 there
    np.testing.assert_allclose(g_sat[loose], seed_idriss_gmax(col.sigma_v0[loose], 30.0), rtol=1e-12)


def test_one_tabulated_layer_among_hyperbolic_ones():
    c = _coarse()
    c["layers"][2].update(modulus_reduction="tabulated", reduction_strains=[1e-5, 1e-3, 1e-2],
                          reduction_ratios=[1.0, 0.3, 0.1])
    b = build_column(c)
    col = b.column
    nt = col.y_all.size - 1
    ratio = col.wave.backbone(np.full(nt, 1e-3))[0] / 1e-3  # τ/(G_max γ) = G/G_max
    dense = np.concatenate([b.site.layer_of == 2, np.zeros(nt - col.n_sat, bool)])
    np.testing.assert_allclose(ratio[dense], 0.3, rtol=1e-12)
    np.testing.assert_allclose(ratio[~dense], 0.5, rtol=1e-12)  # the hyperbola at γ = γ_ref


def test_the_status_line_says_a_run_stopped_early(tmp_path, capsys):
    """An imposed excess pore pressure that has not dissipated by the end time: `twofluid run`
    prints why the completed run ended, with the fraction of the final settlement reached."""
    path = tmp_path / "site.toml"
    path.write_text(_site_text(site={"initial_excess_ratio": 0.5}, time={"end": 0.5, "step": 0.02}))
    assert main(["run", str(path), "--out", str(tmp_path / "o"), "--quiet"]) == 0
    out = capsys.readouterr().out
    assert "completed at t = 0.5 s" in out
    assert "stopped at the end time 0.5 s before dissipation: max r_u = " in out
    assert "% of the final settlement" in out


def test_summary_separates_shaking_from_seepage_and_low_passes_the_surface(layered):
    """The liquefied range by shaking and after it (seepage or the
    reconsolidation floor) partition the elements that ever reached r_u > 0.95; the low-passed
    surface PGA is at most the raw one times the filter's overshoot; the simplified procedure's run a_max is the low-passed peak
    of the total-stress companion run; Sa at 0.1-1 s is given."""
    s = layered.summary
    total = s["liquefied_thickness_m"]
    assert s["liquefied_thickness_shaking_m"] + s["liquefied_thickness_after_shaking_m"] == pytest.approx(total)
    sh = s["shaking"]
    # a zero-phase low-pass is a convolution, so its peak is at most the raw peak times the L1 norm
    # of its impulse response (the filter's overshoot), not the raw peak
    from twofluid.geotech.filtering import low_pass

    ts_ = np.asarray(layered.history["surface_t"])
    dt = float(np.median(np.diff(ts_)))
    tt = np.arange(0.0, 20.0, dt)
    impulse = np.zeros(tt.size)
    impulse[tt.size // 2] = 1.0
    l1 = float(np.sum(np.abs(low_pass(tt, impulse)[1])))
    assert 0.0 < sh["peak_surface_acceleration_low_passed_g"] <= sh["peak_surface_acceleration_g"] * l1
    ts = sh["peak_surface_acceleration_total_stress_low_passed_g"]
    assert ts is not None and s["simplified_procedure"]["a_max_run_g"] == pytest.approx(ts)
    assert "total stress" in s["simplified_procedure"]["a_max_run_definition"]
    assert sorted(float(k) for k in sh["surface_Sa_g"]) == [0.1, 0.2, 0.3, 0.5, 1.0]
    assert all(v > 0.0 for v in sh["surface_Sa_g"].values())


def test_total_stress_companion_generates_no_pore_pressure():
    """The companion run holds n̄ (every layer liquefiable = false): its column never leaves the
    geostatic state, and its surface motion is that of a column whose strength and stiffness follow
    the initial effective stress."""
    from twofluid.runners.liquefaction import total_stress_surface

    c = _coarse()
    t, a = total_stress_surface(c)
    assert t.size > 100 and np.all(np.diff(t) > 0.0) and np.all(np.isfinite(a))
    assert t[-1] == pytest.approx(c["ground_motion"]["duration"] + c["shear_wave"]["free_vibration"])
