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


def level_height(y, n, n0, n1, frac):
    """Height where n, rising from n1 (below) to n0 (above), passes the fraction ``frac``.

    Linear interpolation between element centres, on the highest crossing below
    0.6 m (clear of the bed surface).
    """
    below = y < 0.6
    f = (n[below] - n1) / (n0 - n1)
    i = np.nonzero((f[:-1] < frac) & (f[1:] >= frac))[0][-1]
    return y[i] + (frac - f[i]) / (f[i + 1] - f[i]) * (y[i + 1] - y[i])


def front_width(y, n, n0, n1):
    """Distance [m] between the heights where n passes 10 % and 90 % of the way from n1 to n0."""
    return level_height(y, n, n0, n1, 0.9) - level_height(y, n, n0, n1, 0.1)


def step_case(n0, n1, bed=0.7, end=20.0):
    c = load_case("fluidized-bed-step")  # (its inlet is given by velocities, its bed by a settled height)
    c["initial"].update(state="uniform", porosity=n0, bed_height=bed, settled_height=-1.0)
    c["boundary"]["bottom"].update(porosities=[n0, n1], velocities=[])
    c["time"]["end"] = end
    return c


def kynch_fan_spreading(case, n0, n1):
    """Rate [m/s] at which the 10 %–90 % levels of an expansion fan separate (Kynch theory).

    Solids flux F(n) = (1 − n)(j − U(n)) at total flux j = U(n1), with U(n) the
    steady fluidization velocity of the case's own drag law; a porosity level
    travels up at −dF/dn.
    """
    from twofluid.closures import drag as dl

    m = build(case).model
    clo, mat = m.clo, m.mat

    def law(n, s, *a, **k):
        return clo.drag(n, dl.saturated_slip(s, clo.slip_max), *a, **k)

    def U(n):
        return dl.steady_fluidization_velocity(law, n, mat.d, mat.rho_s, mat.rho_f, mat.mu_f, mat.g,
                                               **clo.drag_params)

    j = U(n1)

    def speed(n, e=1e-6):
        F = lambda x: (1 - x) * (j - U(x))  # noqa: E731
        return -(F(n + e) - F(n - e)) / (2 * e)

    return speed(n1 + 0.9 * (n0 - n1)) - speed(n1 + 0.1 * (n0 - n1))


def test_expansion_front_spreads_as_it_rises():
    c = step_case(0.65, 0.716)
    y, p = profiles(c, [5.0, 15.0])
    w5, w15 = front_width(y, p[5.0], 0.65, 0.716), front_width(y, p[15.0], 0.65, 0.716)
    # a rarefaction fan widens at least at the kinematic-wave rate (numerical diffusion only adds)
    assert w15 - w5 >= 0.8 * kynch_fan_spreading(c, 0.65, 0.716) * 10.0


def test_contraction_front_stays_sharp():
    y, p = profiles(step_case(0.716, 0.65, bed=0.8), [5.0, 15.0])
    h = y[1] - y[0]
    w5, w15 = (front_width(y, p[t], 0.716, 0.65) for t in (5.0, 15.0))
    rise = level_height(y, p[15.0], 0.716, 0.65, 0.5) - level_height(y, p[5.0], 0.716, 0.65, 0.5)
    assert rise > 10 * h  # the shock travelled ten elements ...
    assert w15 < 4 * h  # ... and is still a few elements wide,
    assert w15 / w5 < np.sqrt(3.0)  # widening slower than any diffusive front (∝ √t) would


def test_both_1d_elements_give_nearly_the_same_porosity_profile():
    res = {}
    for el in ("1VW/0P/0n", "2VW/1P/0n"):
        c = step_case(0.65, 0.716, end=10.0)
        c["mesh"]["element"] = el
        y, p = profiles(c, [10.0])
        res[el] = p[10.0]
    a, b = res.values()
    h = y[1] - y[0]
    front = [level_height(y, n, 0.65, 0.716, 0.5) for n in (a, b)]  # middle of the expansion fan
    assert abs(front[0] - front[1]) <= h
    assert np.mean(np.abs(a - b)) < 0.005


@pytest.mark.parametrize("elements", [100, 200])
def test_expanded_bed_settles_uniform_without_odd_even_wiggle(elements):
    """After the expansion the bed is uniform: no element-to-element porosity jump above 2e-3.

    Galerkin (hat-function) tests of the element-wise bed forces let an odd–even porosity
    mode stand in the bed behind its surface (jumps of 0.03 before the upwind tests of
    ``TwoFluid1D.force_shift``; docs/model.md). Checked with the reduced model (the same
    discrete equations) on a 0.35 m bed, settled at 40 s (t1 ≈ 20 s).
    """
    c = step_case(0.65, 0.716, bed=0.35, end=40.0)
    c["case"]["model"] = "reduced_1d"
    c["mesh"]["elements"] = elements
    y, p = profiles(c, [40.0])
    n = p[40.0]
    surface = int(np.nonzero(n < 0.5 * (1.0 + 0.716))[0][-1])  # the last bed element
    inside = n[:surface]  # the last one, just below the partly filled surface element, balances it
    assert np.abs(np.diff(inside)).max() < 2e-3
    assert np.abs(inside - 0.716).max() < 2e-3
