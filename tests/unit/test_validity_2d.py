"""A 2D case outside its drag law's validity gets the same one-line warning as a 1D case."""
import warnings

import twofluid
from twofluid.casefile.schema import CaseWarning
from twofluid.runners.flow_2d import build_2d


def _warnings(case):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        build_2d(case)
    return [str(w.message) for w in caught if issubclass(w.category, CaseWarning)]


def test_bundled_2d_cases_are_inside_their_drag_laws_range():
    for name in ("pipe-flow", "viscometer"):
        assert _warnings(twofluid.load_case(name)) == []


def test_stokes_limit_at_an_inlet_reynolds_number_of_18_is_warned_naming_the_key():
    case = twofluid.load_case("pipe-flow")
    case["closures"]["drag"]["stokes"] = True  # 403 µm glass in the 0.077 m/s feed: Re ≈ 18
    msgs = _warnings(case)
    assert len(msgs) == 1 and "[closures.drag] law = 'gidaspow', stokes = true" in msgs[0]
    assert "Reynolds numbers 0–1" in msgs[0] and "\n" not in msgs[0]
