"""The bundled Slis et al. (1959) case: the twelve rows of thesis table 5.2 (also in `twofluid verify`)."""
import numpy as np
import pytest

from twofluid import postprocess as pp
from twofluid.casefile.loader import load_case
from twofluid.verification.runs import run_history
from twofluid.verification.slis import load_slis_table
from twofluid.verification.slis_check import slis_case, slis_markdown, slis_t1, slis_table, t1_reach


def test_bundled_case_is_row_one():
    case, row = load_case("slis-step-change"), load_slis_table()[0]
    assert case["case"]["model"] == "reduced_1d" and case["initial"]["bed_height"] == 0.27
    assert case["materials"]["particle_diameter"] == row.d
    assert case["boundary"]["bottom"]["porosities"] == [row.n0, row.n1]


def test_no_slip_cap_of_its_own():
    """The model saturates the slip itself (3 U_t); the check must not wrap the drag law."""
    import twofluid.verification.slis_check as sc

    assert not hasattr(sc, "capped_drag")


def test_t1_reach_is_first_entry_into_band():
    t = np.arange(6.0)
    h = np.array([0.0, 0.5, 1.0, 1.0, 1.1, 1.0])
    assert t1_reach(t, h, band=0.02) == 2.0
    assert pp.t1_from_history(t, h, band=0.02) > 4.0  # the excursion at t = 4 counts for t1


def test_markdown_reports_unfinished_rows():
    row = {"row": 5, "d_mm": 5.0, "n0": 0.66, "n1": 0.85, "t1_exp": 18.0, "t1_thesis": 15.0,
           "t1_twofluid": float("nan"), "t1_reach": float("nan"), "err_thesis": -1 / 6,
           "err_twofluid": float("nan"), "note": "not finished: stopped"}
    text = slis_markdown([row])
    assert "not finished" in text and "| – | – | – |" in text


@pytest.fixture(scope="module")
def table():
    return slis_table()


def test_all_twelve_rows_finish_with_a_mean_error_near_the_thesis(table):
    """Mean |t1 − t1_exp|/t1_exp below 30 %: measured 20.3 %; thesis FEA 20.4 %, Kynch (same law) 21.6 %.

    This bound guards what the model reaches; the gate of `twofluid verify` is relative (at most the
    thesis FEA's mean error, and ≤ 10 % with the particle amount fitted leaving each row out:
    tests/unit/test_slis_gate.py), since the rows follow the experiment's unknown bed heights
    (README of the case, "Why the worst rows are late").
    """
    assert all(np.isfinite(r["t1_twofluid"]) for r in table), slis_markdown(table)
    mae = np.mean([abs(r["err_twofluid"]) for r in table])
    assert mae < 0.30, slis_markdown(table)


@pytest.mark.parametrize("i", [0, 3, 6, 11])
def test_rows_end_in_a_uniform_bed_at_n1(i):
    """Expansions (1, 4) and contractions (7, 12): the new steady state is the row's n1 everywhere."""
    row = load_slis_table()[i]
    case = slis_case(row)
    thr = 0.5 * (1.0 + max(row.n0, row.n1))
    h = run_history(case, {"h": lambda m, s: pp.surface_height(m.mesh.centres, s.n, thr, m.mesh.y[0])},
                    wall_limit=120.0)
    m, n = h.model, h.final.n
    bed = n[m.mesh.centres < 0.8 * 0.27 * (1 - row.n0) / (1 - row.n1)]  # below the surface zone
    assert np.max(np.abs(bed - row.n1)) < 0.005  # uniform: no porosity waves, no odd–even pattern
    H0 = h.values["h"][0]  # the measured surface (0.27 m up to the threshold's interpolation)
    H1 = H0 * (1 - row.n0) / (1 - row.n1)  # solids conserved: a uniform bed at n1
    assert abs(h.values["h"][-1] - H1) < 0.02 * H0


def test_t1_holds_under_refinement_with_the_bed_elasticity():
    """Row 4 (4 mm, 0.62 → 0.73): without the Foscolo–Gibilaro term t1 went 25.0 → 8.3 s at 90 → 180
    elements; with it 7.46 → 7.45 s at 180 elements and Δt/4 (measured)."""
    row = load_slis_table()[3]
    t1 = [slis_t1(slis_case(row, elements=el, dt=dt)) for el, dt in ((90, 0.1), (180, 0.025))]
    assert abs(t1[1] - t1[0]) < 0.07 * t1[0], t1
