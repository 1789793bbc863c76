"""Drag laws that expand beds as Richardson–Zaki, hold the packed branch (Ergun) and U_mf
(Wen & Yu); beds set by velocity; the fluidization curve; the interface height within its element."""
import warnings

import numpy as np
import pytest

from twofluid import postprocess as pp
from twofluid.casefile.bed import bed_figures, equilibrium_warning
from twofluid.casefile.builder import build
from twofluid.casefile.loader import load_case
from twofluid.casefile.schema import CaseWarning
from twofluid.closures import drag as D
from twofluid.closures import registry
from twofluid.verification import expansion_check as ec


@pytest.mark.parametrize("name", ["richardson_zaki", "ergun_richardson_zaki"])
def test_new_laws_are_finite_positive_and_vectorised(name):
    law = registry.get("drag", name).func
    n = np.array([0.36, 0.45, 0.47, 0.6, 0.9, 1.0])
    for stokes in (False, True):
        b = law(n, 0.01, 1e-3, 1000.0, 1e-3, stokes=stokes, exponent=2.6)
        k = law(n, 0.01, 1e-3, 1000.0, 1e-3, stokes=stokes, exponent=2.6, per_solids=True)
        assert np.all(np.isfinite(k)) and np.all(k > 0) and b[-1] == 0.0


def test_richardson_zaki_law_holds_a_uniform_bed_at_the_rz_velocity():
    # independent check: U = U_t n^k with U_t from Dallavalle's C_D solved here by bisection
    d, rs, rf, mu, k = 5e-4, 2600.0, 1000.0, 1e-3, 3.1
    lo, hi = 1e-6, 1.0
    for _ in range(200):
        u = 0.5 * (lo + hi)
        re = rf * u * d / mu
        cd = (0.63 + 4.8 / np.sqrt(re)) ** 2
        lo, hi = (u, hi) if cd * rf * u * u < 4.0 / 3.0 * d * (rs - rf) * 9.81 else (lo, u)
    for n in (0.45, 0.6, 0.8):
        u = D.steady_fluidization_velocity(D.richardson_zaki, n, d, rs, rf, mu, exponent=k)
        assert u == pytest.approx(lo * n ** k, rel=1e-9)


def test_expansion_within_5_percent_of_richardson_zaki_over_re_t():
    rows = ec.expansion_rows()
    assert len(rows) == 10 and all(r["pass"] for r in rows), [r for r in rows if not r["pass"]]


def test_default_law_packed_branch_is_ergun_and_u_mf_within_wen_yu_band():
    assert all(r["pass"] for r in ec.packed_rows())
    assert all(r["pass"] for r in ec.minimum_fluidization_rows())


def test_default_law_fluidization_velocity_grows_through_its_transition():
    d = ec.diameter_for(10.0, "ergun_richardson_zaki")
    p = ec._params("ergun_richardson_zaki", d)
    u = [D.steady_fluidization_velocity(D.ergun_richardson_zaki, n, d, 2600.0, 998.2, 1.002e-3, **p)
         for n in np.linspace(0.40, 0.55, 61)]
    assert np.all(np.diff(u) > 0)


def test_khan_richardson_exponent_limits():
    assert float(D.khan_richardson_exponent(1e-12)) == pytest.approx(4.8, abs=1e-6)
    assert float(D.khan_richardson_exponent(1e20)) == pytest.approx(2.4, abs=1e-3)


def test_interface_height_is_exact_for_a_built_bed_and_continuous_as_a_front_crosses():
    from twofluid.casefile.bed import bed_porosity
    from twofluid.mesh.line import uniform_line

    mesh = uniform_line(1.0, 50)
    hs = np.linspace(0.3, 0.5, 201)
    got = [pp.interface_height(mesh.y, bed_porosity(mesh, 0.6, h), 0.8) for h in hs]
    np.testing.assert_allclose(got, hs, atol=1e-12)  # the staircase of whole elements is gone


@pytest.fixture(scope="module")
def bundled():
    c = load_case("fluidized-bed-step")
    return c, build(c)


def test_bundled_bed_is_set_by_velocity_and_starts_in_equilibrium(bundled):
    c, b = bundled
    assert c["boundary"]["bottom"]["velocities"] and not c["boundary"]["bottom"]["porosities"]
    m = b.model
    n0 = b.state.n[0]
    assert m.clo.fluidization_velocity(n0, m.mat) == pytest.approx(c["boundary"]["bottom"]["velocities"][0], rel=1e-9)


def test_bed_figures_give_u_mf_u_t_and_expanded_beds(bundled):
    c, b = bundled
    m = b.model
    f = bed_figures(m.mesh, c, m.clo, m.mat, b.inlet_velocities[0], b.inlet_velocities[-1])
    assert f["U_mf_m_s"] < b.inlet_velocities[0] < f["U_t_m_s"]
    assert abs(f["U_mf_m_s"] / f["U_mf_wen_yu_m_s"] - 1.0) < 0.3
    e = f["expanded"]
    assert e["model"]["height_m"] == pytest.approx(e["richardson_zaki"]["height_m"], rel=0.05)
    assert f["initial_height_m"] < e["model"]["height_m"] < c["mesh"]["length"]


def test_edited_bed_out_of_equilibrium_is_warned_about(bundled):
    c, b = bundled
    m = b.model
    assert equilibrium_warning(c, m.clo, m.mat, 0.7, 8e-3) is not None  # 8 mm/s holds 0.63, not 0.7
    assert equilibrium_warning(c, m.clo, m.mat, float(b.state.n[0]), 8e-3) is None
    assert equilibrium_warning(c, m.clo, m.mat, 0.4, 0.5e-3) is None  # packed below U_mf: at rest
    case = load_case("fluidized-bed-step")
    case["initial"].update(state="uniform", porosity=0.7)
    with pytest.warns(CaseWarning, match="does not hold"):
        build(case)


def test_packed_bed_set_by_velocity_lands_on_the_model_and_rz_heights():
    """A bed packed at 0.4 in an inlet velocity that fluidizes it: the run's final interface height
    against the model's own uniform equilibrium (0.5 %) and Richardson–Zaki (5 %)."""
    from twofluid.runners import run_case

    case = load_case("fluidized-bed-step")
    case["case"].update(model="reduced_1d", study="general")
    case["initial"].update(state="uniform", porosity=0.4)
    case["boundary"]["bottom"].update(times=[0.0], velocities=[6e-3])
    case["time"].update(end=80.0, step=0.05)
    case["output"].update(times=[], probes=[], plots=False)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CaseWarning)  # the packed start is out of equilibrium, on purpose
        res = run_case(case)
    s = res.summary
    assert s["status"] == "completed"
    h = res.tables["probes.csv"]["bed_height_m"][-1]
    e = s["bed"]["expanded"]
    assert h == pytest.approx(e["model"]["height_m"], rel=0.005)
    assert h == pytest.approx(e["richardson_zaki"]["height_m"], rel=0.05)


def test_fluidization_curve_plateau_is_the_buoyant_weight(tmp_path):
    from twofluid.fluidization_curve import COLUMNS, fluidization_curve, write_curve

    curve = fluidization_curve(load_case("fluidized-bed-step"), points=30)
    rows = curve["rows"]
    assert [r["U_m_s"] for r in rows] == sorted((r["U_m_s"] for r in rows), reverse=True)
    w = curve["figures"]["buoyant_weight_per_area_Pa"]
    fl = [r for r in rows if r["state"] == "fluidized"]
    pk = [r for r in rows if r["state"] == "packed"]
    assert fl and pk
    for r in fl:
        assert r["bed_pressure_drop_Pa"] == pytest.approx(w, rel=0.01)
    for r in pk:  # below U_mf the packed bed's drag is Ergun's at n_mf
        assert r["bed_pressure_drop_Pa"] == pytest.approx(r["ergun_pressure_drop_packed_Pa"], rel=0.01)
        assert r["bed_pressure_drop_Pa"] < w * 1.0001
    assert max(r["porosity"] for r in rows) <= 0.9 + 1e-9
    paths = write_curve(curve, tmp_path, plot=True)
    header = paths[0].read_text().splitlines()[0].split(",")
    assert tuple(header) == COLUMNS and paths[1].stat().st_size > 0


def test_fluidization_curve_cli(tmp_path, capsys):
    from twofluid.cli import main

    assert main(["fluidization-curve", "fluidized-bed-step", "--out", str(tmp_path / "fc"), "--points", "12",
                 "--no-plots"]) == 0
    assert (tmp_path / "fc" / "fluidization_curve.csv").exists()
    assert "U_mf" in capsys.readouterr().out
    assert main(["fluidization-curve", "settling-illite", "--out", str(tmp_path / "x")]) == 2
