"""The bundled Slis et al. (1959) case: a fast subset of the twelve rows (all run in `twofluid verify`)."""
import numpy as np
import pytest

from twofluid.casefile.loader import load_case
from twofluid.verification.runs import run_history
from twofluid.verification.slis import load_slis_table
from twofluid.verification.slis_check import capped_drag, slis_case, slis_model, slis_t1


def test_bundled_case_is_row_one():
    case, row = load_case("slis-step-change"), load_slis_table()[0]
    assert case["case"]["model"] == "reduced_1d" and case["initial"]["bed_height"] == 0.275
    assert case["materials"]["particle_diameter"] == row.d
    assert case["boundary.bottom"]["porosities"] == [row.n0, row.n1]


def test_slip_cap_only_touches_large_slips():
    law = lambda n, s, *a, **k: s  # noqa: E731
    assert np.array_equal(capped_drag(law, 0.2)(0.5, np.array([0.1, 0.3])), [0.1, 0.2])


@pytest.mark.parametrize("i", [0, 3])
def test_expansion_rows(i):
    """t1 within 25 % of the experiment (the thesis's own mean error is 20 %); the bed ends at n1."""
    row = load_slis_table()[i]
    case = slis_case(row)
    t1 = slis_t1(case)
    assert abs(t1 - row.t1_exp) / row.t1_exp < 0.25
    m, s = slis_model(case)
    n = run_history(case, {}, state=s, model=m).final.n
    bed = n[m.mesh.centres < 0.5 * 0.275 * (1 - row.n0) / (1 - row.n1)]
    assert abs(np.median(bed) - row.n1) < 0.005  # the new steady state is the row's n1
