"""Fluidized beds as a process engineer sets them up; closures used outside their range; the 1D outputs."""
import warnings

import numpy as np
import pytest

from twofluid import postprocess as pp
from twofluid.casefile.bed import bed_porosity, fluidized_porosity, volume_below
from twofluid.casefile.builder import build
from twofluid.casefile.loader import load_case
from twofluid.casefile.schema import CaseError, CaseWarning, revalidate
from twofluid.closures import drag as dl
from twofluid.mesh.line import uniform_line
from twofluid.runners.common import run_case


def classic_fluidized_bed():
    """fluidized-bed-step as it was before its drag law changed: the bed by porosity (0.65) and height (0.7 m), the
    inlet by porosities (0.65 -> 0.716), Gidaspow's drag (the case now gives velocities, a settled
    height and the ergun_richardson_zaki law)."""
    c = load_case("fluidized-bed-step")
    c["closures"]["drag"].update(law="gidaspow", blend_width=0.02)
    c["initial"].update(state="uniform", porosity=0.65, bed_height=0.7, settled_height=-1.0)
    c["boundary"]["bottom"].update(porosities=[0.65, 0.716], velocities=[])
    return c


def bed(**initial):
    c = classic_fluidized_bed()
    c["initial"].update(initial)
    return c


def built(case):
    return build(revalidate(case, "test.toml"))


def test_bundled_1d_cases_raise_no_range_warning():
    for name in ("fluidized-bed-step", "settling-illite", "slis-step-change"):
        with warnings.catch_warnings():
            warnings.simplefilter("error", CaseWarning)
            build(load_case(name))


def test_stokes_drag_with_millimetre_glass_in_water_warns_with_the_key_and_range():
    c = bed()
    c["closures"]["drag"]["stokes"] = True
    c["materials"]["particle_diameter"] = 1e-3
    with pytest.warns(CaseWarning) as rec:
        b = built(c)
    lines = [str(w.message) for w in rec if "[closures.drag]" in str(w.message)]
    assert len(lines) == 1 and "\n" not in lines[0]
    assert "stokes = true" in lines[0] and "Reynolds numbers 0–1" in lines[0]
    m = b.model.mat
    u_t = m.d ** 2 * (m.rho_s - m.rho_f) * m.g / (18 * m.mu_f)  # Stokes' law, Re_t = ρ_f U_t d/μ_f ≈ 870
    assert f"Re = {m.rho_f * u_t * m.d / m.mu_f:.3g}" in lines[0]


def test_ergun_alone_at_a_fluidized_porosity_warns():
    c = bed(porosity=0.85)
    c["closures"]["drag"]["law"] = "ergun"
    c["boundary"]["bottom"]["porosities"] = [0.85, 0.86]
    with pytest.warns(CaseWarning, match=r"\[closures.drag\] law = 'ergun': valid for porosities 0–0.8"):
        built(c)


def test_fluidized_initial_state_takes_the_porosity_the_inlet_velocity_holds():
    c = bed(state="fluidized", porosity=-1.0)
    b = built(c)
    n = b.state.n[b.state.n < 1.0]
    # the inlet at t = 0 is the velocity that holds n = 0.65 (the schedule's first porosity)
    assert np.abs(n - 0.65).max() < 1e-9
    clo, mat = b.model.clo, b.model.mat
    u = dl.steady_fluidization_velocity(clo.saturated_drag, 0.7, mat.d, mat.rho_s, mat.rho_f, mat.mu_f, mat.g,
                                        **clo.drag_params)
    assert fluidized_porosity(clo, mat, u) == pytest.approx(0.7, abs=1e-10)


def test_fluidized_state_beyond_the_terminal_velocity_is_a_one_line_error():
    c = bed(state="fluidized", porosity=-1.0)
    c["boundary"]["bottom"].update(porosities=[], velocities=[1.0, 1.0])
    with pytest.raises(CaseError, match=r"\[initial\] state = 'fluidized'.*terminal velocity"):
        built(c)


def test_bed_given_by_solids_mass_or_settled_height_holds_that_inventory():
    for initial, volume in (({"solids_mass": 2600.0 * 0.24}, 0.24),
                            ({"settled_height": 0.4, "settled_porosity": 0.42}, 0.4 * 0.58)):
        b = built(bed(bed_height=-1.0, **initial))
        assert b.model.solids_volume(b.state) == pytest.approx(volume, rel=1e-12)
        n = b.state.n[b.state.n < 1.0]
        assert (n[:-1] == 0.65).all() and 0.65 <= n[-1] < 1.0  # the top one is cut by the surface


def test_bed_surface_is_placed_exactly_not_rounded_to_a_face():
    mesh = uniform_line(1.0, 100, area=(1.0, 1.5))
    n = bed_porosity(mesh, 0.6, 0.05404)
    solids = float(((1.0 - n) * mesh.volumes).sum())
    assert solids == pytest.approx(0.4 * volume_below(mesh, 0.05404), rel=1e-12)
    assert 0.6 < n[5] < 1.0 and (n[:5] == 0.6).all() and (n[6:] == 1.0).all()


@pytest.mark.parametrize("initial, key", [({"solids_mass": 600.0}, "bed_height/solids_mass"),
                                          ({"porosity": -1.0}, "[initial] porosity")])
def test_inconsistent_bed_keys_are_one_line_errors(initial, key):
    with pytest.raises(CaseError, match=key.replace("[", r"\[").replace("]", r"\]")):
        revalidate(bed(**initial), "test.toml")


def test_galerkin_solids_flux_with_a_free_surface_is_refused_at_load_time():
    c = load_case("settling-illite")
    c["numerics"]["solids_flux"] = "galerkin"
    with pytest.raises(CaseError, match=r"\[numerics\] solids_flux.*'upwind'"):
        revalidate(c, "test.toml")


def test_step_change_reports_t1_from_the_step_and_the_bed_pressure_drop(tmp_path):
    c = classic_fluidized_bed()
    c["case"]["model"] = "reduced_1d"
    c["mesh"]["elements"] = 50
    c["initial"]["bed_height"] = 0.3
    c["boundary"]["bottom"]["times"] = [2.0, 2.0]  # the step at t = 2 s
    c["time"].update(end=30.0, step=0.05)
    c["output"].update(times=[], probes=[], probe_interval=1.0)
    r = run_case(revalidate(c, "test.toml"), tmp_path)
    s = r.summary
    assert s["status"] == "completed" and s["step_time_s"] == 2.0
    assert s["t1_s"] == pytest.approx(pp.t1_from_history(r.history["t"], r.history["bed_height_m"]) - 2.0,
                                      abs=1e-12)
    assert s["porosity_range"][1] <= 1.0
    # a settled fluidized bed's pressure drop carries the buoyant weight of its solids, short of the
    # drag on the lower half of the first element (P is taken at its centre)
    dp, w = s["bed_pressure_drop_Pa"]["final"], s["bed_pressure_drop_Pa"]["buoyant_weight_per_area"]
    h = c["mesh"]["length"] / c["mesh"]["elements"]
    assert w * (1 - h / s["bed_height_final_m"]) < dp <= w * (1 + 1e-6)
    probes = np.genfromtxt(tmp_path / "probes.csv", delimiter=",", names=True)
    assert "bed_pressure_drop_Pa" in probes.dtype.names
    assert s["bed_height_theory_final_m"] == pytest.approx(0.3 * 0.35 / (1 - s["bed_porosity_theory_final"]))
    assert (tmp_path / "bed_pressure_drop.png").exists()


def test_bed_height_off_the_element_faces_says_where_the_surface_went():
    with pytest.warns(CaseWarning, match=r"\[initial\] bed_height: 0.7054 m is not on an element face.*"
                                         r"up to 0.71 m"):
        b = built(bed(bed_height=0.7054))
    assert (b.state.n[:71] == 0.65).all() and (b.state.n[71:] == 1.0).all()
    with warnings.catch_warnings():
        warnings.simplefilter("error", CaseWarning)
        built(bed(bed_height=0.7))  # on a face: no word


@pytest.mark.parametrize("element", ["1VW/0P/0n", "2VW/1P/0n"])
def test_bed_pressure_drop_per_step_equals_the_one_from_the_element_fields(element):
    """The runner's per-step pressure drop reads the lowest element's centre pressure alone; it is
    the same number as from the element fields (both elements: P0 and the linear, discontinuous P)."""
    from twofluid.runners.column_1d import bed_pressure_drop

    case = load_case("fluidized-bed-step")
    case["mesh"]["element"] = element
    b = build(revalidate(case, "<test>"))
    s = b.state.copy()
    s.P[:] = np.linspace(5e3, 1e2, s.P.size)  # any pressure field with distinct entries
    assert bed_pressure_drop(b.model, s) == bed_pressure_drop(b.model, s, b.model.element_fields(s))
