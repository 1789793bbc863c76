"""Step changes of a fluidized bed: front shapes (Kynch) and the two 1D elements (thesis fig. 4.2)."""
import numpy as np
import pytest

from twofluid.casefile.builder import build
from twofluid.casefile.loader import load_case
from twofluid.timestepping.backward_euler import integrate


def profiles(case, times):
    b = build(case)
    out = {}
    for step in integrate(b.model, b.state, max(times), case["time"]["step"], stops=times,
                          settings=b.settings):
        if any(abs(step.t - t) < 1e-9 for t in times):
            out[round(step.t, 9)] = step.state.n.copy()
    return b.model.mesh.centres, out


def front_width(y, n, n0, n1):
    """Elements between the heights where n passes 10 % and 90 % of the way from n1 (below) to n0."""
    below = y < 0.6  # stay clear of the bed surface
    f = (n[below] - n1) / (n0 - n1)
    i10 = np.nonzero(f > 0.1)[0][0]  # first element (from the bottom) still 10 % from n1
    i90 = np.nonzero(f > 0.9)[0][0]
    return int(i90 - i10)


def step_case(n0, n1, bed=0.7, end=20.0):
    c = load_case("fluidized-bed-step")
    c["initial"].update(porosity=n0, bed_height=bed)
    c["boundary.bottom"]["porosities"] = [n0, n1]
    c["time"]["end"] = end
    return c


def test_expansion_front_spreads_as_it_rises():
    y, p = profiles(step_case(0.65, 0.716), [5.0, 15.0])
    w5, w15 = front_width(y, p[5.0], 0.65, 0.716), front_width(y, p[15.0], 0.65, 0.716)
    assert w15 > w5 + 3  # a rarefaction fan widens in proportion to time
    assert w15 / w5 == pytest.approx(3.0, rel=0.35)


def test_contraction_front_stays_sharp():
    y, p = profiles(step_case(0.716, 0.65, bed=0.8), [5.0, 15.0])
    w5, w15 = (front_width(y, p[t], 0.716, 0.65) for t in (5.0, 15.0))
    assert w5 <= 3 and w15 <= 3  # a shock: a few elements wide ...
    assert w15 <= w5  # ... that does not widen as it rises


def test_both_1d_elements_give_nearly_the_same_porosity_profile():
    res = {}
    for el in ("1VW/0P/0n", "2VW/1P/0n"):
        c = step_case(0.65, 0.716, end=10.0)
        c["mesh"]["element"] = el
        y, p = profiles(c, [10.0])
        res[el] = p[10.0]
    a, b = res.values()
    h = y[1] - y[0]
    mid = 0.5 * (0.65 + 0.716)
    front = [y[np.nonzero(n > mid)[0][0]] for n in (a, b)]  # lowest element above mid-porosity
    assert abs(front[0] - front[1]) <= h
    assert np.mean(np.abs(a - b)) < 0.005
