"""The idealised set's protocol (scripts/idealised_spreads.py), checked without running a column:
the fines correction, the columns' profile, the grid's ranges and roles, the record choice; and its
written case files (--write-cases): each loads, without a warning, to the very column the script runs,
so that twofluid and the OpenSees PM4Sand column (benchmarks/pm4sand_column.py) run one column,
record, scale, duration and polarity."""
import math
import warnings

import pytest

from twofluid.casefile.case import sections
from twofluid.casefile.loader import load_case
from twofluid.runners.liquefaction import validated
from repo_scripts import load_script



@pytest.fixture(scope="module")
def ideal():
    return load_script("scripts/idealised_spreads.py")


def test_fines_correction_is_idriss_boulanger(ideal):
    # Δ(N1)60 = exp(1.63 + 9.7/(FC + 0.01) − (15.7/(FC + 0.01))²): about 0 at 5 %, 5.37 at 30 %, 5.5 at 35 %
    assert ideal.fines_corrected(8.0, 5.0) == pytest.approx(8.0, abs=0.01)
    assert ideal.fines_corrected(8.0, 30.0) == pytest.approx(8.0 + math.exp(1.63 + 9.7 / 30.01 - (15.7 / 30.01) ** 2),
                                                            rel=1e-12)
    assert 13.3 < ideal.fines_corrected(8.0, 30.0) < 13.5
    assert ideal.fines_corrected(8.0, 35.0) == pytest.approx(13.5, abs=0.1)


def test_the_grid_spans_the_protocol(ideal):
    cols = ideal.COLUMNS
    assert len(cols) >= 12 and len({c[0] for c in cols}) == len(cols)
    assert {c[1] for c in cols} == {0.5, 1.0, 2.0, 3.0, 4.0}
    assert {c[2] for c in cols} == {1.5, 3.0, 6.0, 10.0}
    assert all(6.4 <= c[3] <= 7.7 and 1.0 <= c[4] <= 30.0 for c in cols)
    assert {c[5] for c in cols} == {5.0, 30.0}
    assert sum(c[6] == "control" for c in cols) >= 2 and sum(c[6] == "near-flow" for c in cols) >= 2


def test_a_column_is_the_protocol_profile(ideal):
    c = validated(ideal.column_case(2.0, 6.0, 7.0, 10.0, 30.0, "RSN6_IMPVALL.I_I-ELC180-hor1.AT2", 0.3, -1))
    crust, t15, dense = c["layers"]
    assert crust["thickness"] == 1.5 and crust["unit_weight"] == 18000.0 and c["site"]["water_table_depth"] == 1.5
    assert t15["thickness"] == 6.0 and t15["n160cs"] == pytest.approx(ideal.fines_corrected(8.0, 30.0))
    assert t15["hydraulic_conductivity"] == 1e-5 and t15["fines_content"] == 30.0
    assert dense["thickness"] == 5.0 and dense["n160cs"] == 29.0 and dense["hydraulic_conductivity"] == 1e-4
    assert c["shear_wave"]["base"] == "compliant" and c["shear_wave"]["bedrock_shear_velocity"] == 760.0
    g = c["ground_motion"]
    assert (g["magnitude"], g["distance_km"], g["polarity"], g["pga_g"]) == (7.0, 10.0, -1, 0.3)
    assert g["duration"] == ideal.arias_t95("RSN6_IMPVALL.I_I-ELC180-hor1.AT2") == 26.4
    assert validated(ideal.column_case(1.0, 3.0, 7.0, 10.0, 5.0))["layers"][1]["hydraulic_conductivity"] == 1e-4


def test_records_nearest_in_m_and_r_within_the_scale_range(ideal):
    pytest.importorskip("pygmm")
    mot = ideal.motions(6.95, 6.1)  # Imperial Valley at El Centro's distance: El Centro itself first
    assert mot[0][0] == "RSN6_IMPVALL.I_I-ELC180-hor1.AT2" and mot[0][3] == 0.0
    assert len(mot) == 2 and mot[0][3] <= mot[1][3]
    for m, r in ((7.0, 15.0), (6.4, 30.0)):
        for name, pga, factor, d in ideal.motions(m, r):
            assert 0.5 <= factor <= 2.0 and pga == ideal.bssa14_pga(m, r)


ELC = "RSN6_IMPVALL.I_I-ELC180-hor1.AT2"


@pytest.mark.parametrize("col", [(4.0, 6.0, 7.0, 8.0, 5.0, -1), (3.0, 3.0, 7.0, 5.0, 30.0, 1)])
def test_a_written_case_loads_to_the_column_the_script_runs(ideal, tmp_path, col):
    s, t15, m, r, f15, pol = col
    c = ideal.column_case(s, t15, m, r, f15, ELC, 0.2671, pol)
    path = ideal.write_case(c, tmp_path / "sub" / "col.toml")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        loaded = load_case(str(path))
    assert [str(w.message) for w in caught] == []
    want, got = sections(validated(c)), sections(loaded)
    keys = {k for k in set(want) | set(got) if not k.startswith("_") and k != "case"}
    assert keys and {k for k in keys if want.get(k) != got.get(k)} == set()
    assert loaded["case"]["name"] == "col"  # runs under its own file's name
    g = loaded["ground_motion"]
    assert (g["file"], g["pga_g"], g["polarity"], g["duration"]) == (ELC, 0.2671, pol, ideal.arias_t95(ELC))
    assert loaded["layers"][1]["thickness"] == t15 and loaded["site"]["slope"] == s


def test_run_names_say_column_record_and_polarity(ideal):
    assert ideal.run_name("n11", ELC, 1) == "n11-IMPVALL.I-p"
    assert ideal.run_name("c03", "RSN1120_KOBE_TAK000.AT2", -1) == "c03-KOBE-m"


def test_write_cases_writes_each_picked_run_and_runs_nothing(ideal, tmp_path, capsys):
    pytest.importorskip("pygmm")
    out = tmp_path / "runs"
    assert ideal.main(["--columns", "3", "--records", "1", "--write-cases", str(tmp_path / "cases"),
                       "--out", str(out)]) == 0
    written = sorted(p.name for p in (tmp_path / "cases").iterdir())
    assert written == ["c03-IMPVALL.I-m.toml", "c03-IMPVALL.I-p.toml"]
    assert not out.exists()  # no run, no table
    assert load_case(str(tmp_path / "cases" / "c03-IMPVALL.I-m.toml"))["ground_motion"]["polarity"] == -1
