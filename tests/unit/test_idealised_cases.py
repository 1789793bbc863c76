"""The idealised set's written case files (scripts/idealised_spreads.py --write-cases): each loads,
without a warning, to the very column the script runs, so that twofluid and the OpenSees PM4Sand
column (benchmarks/pm4sand_column.py) run one column, record, scale, duration and polarity."""
from __future__ import annotations

import importlib.util
import warnings
from pathlib import Path

import pytest

from twofluid.casefile.case import sections
from twofluid.casefile.loader import load_case
from twofluid.runners.liquefaction import validated

PATH = Path(__file__).resolve().parents[2] / "scripts" / "idealised_spreads.py"
ELC = "RSN6_IMPVALL.I_I-ELC180-hor1.AT2"


@pytest.fixture(scope="module")
def ideal():
    spec = importlib.util.spec_from_file_location("idealised_spreads", PATH)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


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
