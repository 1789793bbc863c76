"""The OpenSees PM4Sand column's inputs (benchmarks/pm4sand_column.py), checked without OpenSees:
the case and record it takes are twofluid's own (one reader: every bundled input record, whatever
its header's layout), its layers' densities and Dr, and the flow criterion it runs on after the
shaking."""
from __future__ import annotations

import importlib.util
import math
from pathlib import Path

import numpy as np
import pytest

from twofluid.casefile.loader import load_case
from twofluid.io import ground_motion as gm
from twofluid.io.results import write_resolved_case
from repo_scripts import load_script

BENCH = Path(__file__).resolve().parents[2] / "benchmarks"
INPUTS = [b.name for b in gm.BUNDLED.values() if b.input_motion]


@pytest.fixture(scope="module")
def col():
    return load_script("benchmarks/pm4sand_column.py")


def _case_file(tmp_path, record, duration, pga=0.2, polarity=1):
    c = load_case("sloping-site")
    c["ground_motion"].update(file=record, duration=duration, pga_g=pga, polarity=polarity)
    path = tmp_path / f"{Path(record).stem}-{polarity}.toml"
    write_resolved_case(path, c)
    return path


def test_the_module_imports_without_opensees(col):
    assert col.ops is None and col.peer is None  # loaded by load() at run time only


@pytest.mark.parametrize("record", INPUTS)
def test_every_bundled_input_record_is_read_as_twofluid_reads_it(col, tmp_path, record):
    # the NGA headers differ ("NPTS=   4096  DT=   .0100 SEC," has no comma after NPTS): all are read
    raw = gm.read_at2(gm.bundled_record(record))
    head = gm.bundled_record(record).read_text().splitlines()[3]
    assert str(raw.npts) in head
    duration = round(0.5 * raw.duration, 2)
    case, m = col.case_and_motion(_case_file(tmp_path, record, duration))
    assert m.dt == raw.dt and m.time[-1] <= duration + 1e-9 and m.time[-1] > duration - raw.dt - 1e-9
    assert np.max(np.abs(m.acceleration)) == pytest.approx(0.2 * gm.G_STANDARD, rel=1e-12)
    # cut, baseline-corrected (order 1), then scaled: twofluid's record, not the raw one scaled
    keep = raw.time <= duration + 1e-12
    cut = gm.GroundMotion(raw.time[keep], raw.acceleration[keep], raw.name, raw.source, raw.dt)
    expected = gm.scale_to_pga(gm.baseline_correct(cut, 1), 0.2).acceleration
    np.testing.assert_allclose(m.acceleration, expected, rtol=1e-12, atol=1e-12 * m.pga)
    naive = cut.acceleration * 0.2 * gm.G_STANDARD / cut.pga
    assert np.max(np.abs(m.acceleration - naive)) > 1e-6 * m.pga
    _, rev = col.case_and_motion(_case_file(tmp_path, record, duration, polarity=-1))
    np.testing.assert_array_equal(rev.acceleration, -m.acceleration)


def test_overrides_replace_the_case_keys(col, tmp_path):
    path = _case_file(tmp_path, "RSN1120_KOBE_TAK000.AT2", 8.0)
    case, m = col.case_and_motion(path, polarity=-1, pga=0.3, duration=4.0)
    g = case["ground_motion"]
    assert (g["polarity"], g["pga_g"], g["duration"]) == (-1, 0.3, 4.0)
    assert m.duration == pytest.approx(4.0) and m.pga_g == pytest.approx(0.3, rel=1e-12)


def test_layer_materials_follow_the_case(col):
    case = load_case("sloping-site")
    crust, loose, dense = col.layer_materials(case, 2.65)
    assert crust == (18000.0 / 1000.0 / 9.80665, 0.6, col.CRUST_DR, 1e-4)
    n = 0.44
    assert loose[0] == pytest.approx((1 - n) * 2.65 + n * 1.0) and loose[1] == pytest.approx(n / (1 - n))
    assert loose[2] == 36.1 and dense[2] == 80.0
    case["layers"][1].update(porosity=0.0, void_ratio=0.7)  # a layer given by its void ratio
    assert col.layer_materials(case, 2.65)[1][1] == pytest.approx(0.7)


def test_flow_criterion_is_the_window_mean_velocity(col):
    t = np.arange(0.05, 6.0001, 0.05)
    window, v_min = 2.0, 1e-5
    assert col.flowing(t[:30], 0.0 * t[:30], window, v_min)           # under 2 windows of samples: on
    assert col.flowing(t, 3e-5 * t, window, v_min)                     # creeping at 3e-5 m/s: on
    assert not col.flowing(t, 3e-6 * t, window, v_min)                 # 3e-6 m/s: stopped
    ring = 0.01 * np.sin(2 * math.pi * t / 0.5)                        # a ring-down, whole periods a window
    assert not col.flowing(t, 0.2 + ring, window, v_min)
    assert col.flowing(t, 0.2 + ring + 2e-5 * t, window, v_min)


def _ideal():
    return load_script("scripts/idealised_spreads.py")


def test_frozen_idealised_runs_are_the_scripts_columns():
    """Each frozen PM4Sand run of an idealised column ran the column, record, scale, duration and
    polarity that scripts/idealised_spreads.py builds (the twofluid runs beside it take the same file)."""
    import json

    ideal = _ideal()
    runs = json.loads((BENCH / "pm4sand_column_results.json").read_text())["runs"]
    frozen = {k: v for k, v in runs.items() if k.startswith("idealised ")}
    assert len(frozen) >= 4
    cols = {c[0]: c for c in ideal.COLUMNS}
    for key, run in frozen.items():
        name, label = key.split()[1].split("-", 1)
        _, s, t15, m, r, f15, _ = cols[name]
        record = next(x for x in ideal.RECORDS if x.split("_")[1] == label)
        assert run["record"] == record and run["polarity"] == int(key.split()[-1])
        assert run["shaking_s"] == pytest.approx(ideal.arias_t95(record), abs=1e-9)
        assert run["slope"] == pytest.approx(s / 100.0) and run["baseline_order"] == 1
        crust, layer, dense = run["materials"]
        assert layer["dr"] == pytest.approx(100.0 * math.sqrt(ideal.fines_corrected(8.0, f15) / 46.0), rel=1e-12)
        assert dense["dr"] == pytest.approx(100.0 * math.sqrt(29.0 / 46.0), rel=1e-12)
        assert layer["k"] == (1e-4 if f15 < 15.0 else 1e-5)
        sat = [p for p in run["profile"] if p["layer"] == "T15 layer"]
        assert sum(1 for _ in sat) * 0.25 == pytest.approx(t15)
        h = run["surface_displacement_history"]
        assert h["t_s"][-1] == pytest.approx(run["end_s"], abs=0.011)
        assert h["u_m"][-1] == pytest.approx(run["surface_displacement_end_m"], abs=1e-5)
        if importlib.util.find_spec("pygmm") is not None:
            assert run["pga_g"] == round(ideal.bssa14_pga(m, r), 4)
