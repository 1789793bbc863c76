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


def test_a_column_step_pairs_up_its_surface_samples_when_read():
    """ColumnStep keeps the shear sub-steps' samples as two lists (what the run's record keeps) and pairs them
    up into ``surface`` when that is read: the same step as one made with the pairs."""
    from twofluid.models.liquefaction_1d import ColumnStep

    t, a = [0.005, 0.01, 0.015], [0.25, -0.5, 1.0]
    lazy = ColumnStep("state", 0.015, 3, 2, -1e-9, samples=(t, a))
    made = ColumnStep("state", 0.015, 3, 2, -1e-9, ((0.005, 0.25), (0.01, -0.5), (0.015, 1.0)))
    assert lazy.samples == (t, a) and made.samples == (t, a)
    assert lazy == made and hash(lazy) == hash(made) and repr(lazy) == repr(made)
    assert lazy.surface == made.surface and lazy.surface is lazy.surface  # (made once)
    assert [f.name for f in dataclasses.fields(ColumnStep)][-1] == "surface"
    assert dataclasses.replace(lazy, dt=1.0).surface == made.surface
    assert pickle.loads(pickle.dumps(ColumnStep("state", 0.015, 3, 2, -1e-9, samples=(t, a)))) == made
    assert ColumnStep("s", 1.0, 0, 1, 0.0).surface == () and ColumnStep("s", 1.0, 0, 1, 0.0).samples == ([], [])
    with pytest.raises(AttributeError):
        lazy.other
    with pytest.raises(dataclasses.FrozenInstanceError):
        lazy.surface = ()


def test_the_kernel_samples_follow_the_newton_tests_table():
    """kernel_samples looks the model up again only where the table of runs changed since: a new record, a
    record popped, and a copy of the model (its own, empty, lookup) each give samples from the table."""
    import copy

    from twofluid.timestepping import newton

    class Model:
        pass

    m = Model()
    first = newton.kernel_samples(m)
    assert newton.kernel_samples(m) is first and first[4] is None  # (nothing changed: kept)
    rec = newton._Run()
    rec.samples.extend([(3, 0.5), (4, 0.25)])
    rec.steps = 5
    newton._RUNS[m] = rec  # the stepper's record replaced: taken
    got = newton.kernel_samples(m)
    assert got is not first and got[4] is rec and got[2].tolist() == [2, 5] and got[1][:2].tolist() == [0.5, 0.25]
    assert newton.kernel_samples(m) is got
    twin = copy.deepcopy(m)  # (a copy does not share the original's record)
    assert newton.kernel_samples(twin)[4] is None and newton.kernel_samples(m) is got
    newton._RUNS.pop(m)
    assert newton.kernel_samples(m)[4] is None


def test_the_damage_record_keeps_the_last_states_strains_as_a_copy_when_read():
    from types import SimpleNamespace

    from twofluid.closures import hysteretic as law
    from twofluid.runners.liquefaction_damage import DamageRecord

    par = np.zeros((3, law.NPARAM))
    col = SimpleNamespace(hysteretic=par, n_sat=2, shaking_end=1.0, wave=SimpleNamespace(h=np.ones(3)), u_static=None)
    rec = DamageRecord(col)
    assert rec.gamma_end.tolist() == [0.0, 0.0, 0.0]
    g = np.array([0.1, -0.2, 0.3])
    rec.record(SimpleNamespace(t=0.5, shear=np.zeros((3, law.NSTATE)), wave=SimpleNamespace(gamma=g)),
               np.zeros(2, bool), -1)
    end = rec.gamma_end
    assert end.tolist() == g.tolist() and end is not g
    end[0] = 9.0  # (a copy: the record keeps the state's own)
    assert rec.gamma_end.tolist() == g.tolist() and rec.columns(1)[-1] == -0.2


def test_the_records_surface_lists_hold_every_steps_samples():
    from twofluid.runners.liquefaction import _Recorder, build_column

    b = build_column(load_case("liquefaction-elcentro"))
    col, s = b.column, b.state
    rec = _Recorder(col, [1.0, 2.0], 0.95)
    rec.record(s, True)
    want_t, want_a = [], []
    for k, step in enumerate(col.run(s, 6 * b.dt, b.dt)):
        rec.record(step.state, False, step.samples)
        want_t += [p[0] for p in step.surface]
        want_a += [p[1] for p in step.surface]
        if k == 2:
            assert rec.surface_t == want_t and rec.surface_a == want_a  # (read while the run goes on)
    assert len(want_t) > 6 and rec.surface_t == want_t and rec.surface_a == want_a
    t, a = rec.surface_arrays()
    assert t.tolist() == want_t and a.tolist() == want_a
