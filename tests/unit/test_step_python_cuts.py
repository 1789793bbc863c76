"""The per-step Python cuts keep what they replace: the stepper's Step, the probes' element means from
kept indices, the prescribed values of the ends, the surface displacement's static part, the progress
count and the NaN of the median."""
import dataclasses
import pickle

import numpy as np
import pytest

from twofluid.casefile.builder import build
from twofluid.casefile.loader import load_case
from twofluid.postprocess import median
from twofluid.runners.common import _CountingBar, _NoBar
from twofluid.timestepping.backward_euler import Step


def test_step_is_a_frozen_dataclass_with_its_fields_in_order():
    s = Step(1.5, 0.1, 3, "state", 7)
    assert [f.name for f in dataclasses.fields(Step)] == list(vars(s))
    assert dataclasses.astuple(s) == (1.5, 0.1, 3, "state", 7, 0)
    assert s == Step(1.5, 0.1, 3, "state", 7, 0) and hash(s) == hash(Step(1.5, 0.1, 3, "state", 7, 0))
    assert s != Step(1.5, 0.1, 3, "state", 7, 1)
    with pytest.raises(dataclasses.FrozenInstanceError):
        s.t = 2.0
    assert dataclasses.replace(s, rejected=2) == Step(1.5, 0.1, 3, "state", 7, 2)
    assert pickle.loads(pickle.dumps(s)) == s
    assert Step(t=1.0, dt=0.5, iterations=1, state=None, n_steps=2, rejected=4).rejected == 4


def test_element_mean_at_a_read_only_index_array_is_the_plain_one_and_follows_the_mesh():
    m = build(load_case("fluidized-bed-step")).model
    rng = np.random.default_rng(5)
    V = rng.standard_normal(m.nv)
    at = np.array([3, 0, m.mesh.n_elements - 1, 3])
    plain = m.element_mean(V, at)
    ro = at.copy()
    ro.flags.writeable = False
    kept = m.element_mean(V, ro)
    assert kept.tobytes() == plain.tobytes()
    assert m.element_mean(2.0 * V, ro).tobytes() == m.element_mean(2.0 * V, at).tobytes()  # (from what it kept)
    assert m.__dict__["_mean_at"][0] is ro
    other = np.array([1, 2])
    other.flags.writeable = False
    assert m.element_mean(V, other).tobytes() == m.element_mean(V, np.array([1, 2])).tobytes()
    m.avg_weights = 2.0 * m.avg_weights  # other weights: made again
    assert m.element_mean(V, other).tobytes() == m.element_mean(V, np.array([1, 2])).tobytes()
    assert m.element_mean(V, [1, 2]).tobytes() == m.element_mean(V, np.array([1, 2])).tobytes()  # (a list too)


def test_the_ends_prescribed_values_follow_the_inlet_schedule_and_the_ends():
    m = build(load_case("fluidized-bed-step")).model
    for t in (0.0, 0.5, 3.0, 3.0, 100.0):
        idx, val = m.dirichlet(t)
        want = []
        for b, sign in ((m.bottom, 1.0), (m.top, -1.0)):
            if b.kind in ("inlet", "wall"):
                u = sign * b.velocity(t) if b.kind == "inlet" else 0.0
                want += [u, u]
        assert val.tolist() == want and val.dtype == float
        assert idx.tolist() == [0, m.nv]  # the bed's inlet at the bottom, an outlet at the top
    top = m.top
    m.top = dataclasses.replace(m.bottom, kind="wall")  # other ends: indices and values made again
    idx, val = m.dirichlet(7.0)
    assert idx.tolist() == [0, m.nv, m.nv - 1, 2 * m.nv - 1]
    assert val.tolist() == [m.bottom.velocity(7.0)] * 2 + [0.0, 0.0]
    m.top = top
    assert m.dirichlet(8.0)[0].tolist() == [0, m.nv]


def test_the_surface_displacement_follows_a_new_static_profile():
    from twofluid.runners.liquefaction import build_column

    b = build_column(load_case("liquefaction-elcentro"))
    col, s = b.column, b.state
    u = s.wave.u + np.linspace(0.0, 0.3, s.wave.u.size)
    s.wave.u = u
    assert col.surface_displacement(s) == float(u[-1] - u[0]) - float(col.u_static[-1] - col.u_static[0])
    col.u_static = np.linspace(0.0, 0.1, u.size)  # (replaced, as the sloping column's start replaces it)
    assert col.surface_displacement(s) == float(u[-1] - u[0]) - float(col.u_static[-1] - col.u_static[0])


def test_the_counting_bar_counts_its_updates_and_sums_the_bars_n():
    bar = _CountingBar(_NoBar())
    for dn in (0.1, 0.2, 0.3):
        bar.update(dn)
    assert bar.steps == 3 and bar.n == (0.0 + 0.1) + 0.2 + 0.3


def test_the_median_is_numpys_and_nan_with_a_nan():
    rng = np.random.default_rng(1)
    for size in (1, 2, 5, 6):
        x = rng.standard_normal(size)
        assert median(x) == float(np.median(x))
    assert np.isnan(median([])) and np.isnan(median([2.0, np.nan, 1.0]))
