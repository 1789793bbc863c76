"""The result writers' fast paths (one ``%`` format per row, one NumPy finiteness test per row
block) write what ``csv.writer`` with one ``_cell`` per value writes, and refuse what it refuses."""
from __future__ import annotations

import csv
import io

import numpy as np
import pytest

from twofluid.io.results import (CsvStream, NonFiniteOutput, ResultWriter, _cell, check_finite,
                                 read_table, reset_nonfinite)


def _reference(rows) -> str:
    buf = io.StringIO()
    w = csv.writer(buf)
    for r in rows:
        w.writerow([_cell(v) for v in r])
    return buf.getvalue()


def _values(rng, n):
    """Floats over the whole double range, signed zeros, integers and NumPy scalars."""
    x = rng.standard_normal(n) * 10.0 ** rng.integers(-320, 308, n)
    out = list(x)
    out[:4] = [0.0, -0.0, 1e-310, -1.7976931348623157e308]
    return out + [7, np.float64(0.1), np.float32(0.1), np.int64(-3), True]


def test_rows_of_numbers_text_none_and_nan_are_written_as_csv_writer_writes_them(tmp_path):
    rng = np.random.default_rng(1)
    rows = [_values(rng, 40) for _ in range(50)]
    rows += [["time_s", "a,b", 'q"uote'], [1.0, None, 2.0], [np.nan, 1.0], ["1.5", 2.0], [], [np.inf, -np.inf]]
    s = CsvStream(tmp_path / "t.csv", ["h"])
    s.rows(rows)
    s.close()
    assert (tmp_path / "t.csv").read_bytes() == _reference([["h"], *rows]).encode("utf-8")


def test_table_with_formats_and_empty_nan_cells(tmp_path):
    rng = np.random.default_rng(2)
    a = rng.standard_normal((30, 5)) * 10.0 ** rng.integers(-30, 30, (30, 5))
    a[3, 2] = np.nan
    formats = ["%.10g", "%.6g", "%.6g", "%.4g", "%.10g"]
    s = CsvStream(tmp_path / "t.csv", ["a", "b", "c", "d", "e"])
    s.table(a, formats)
    s.close()
    want = [["a", "b", "c", "d", "e"]] + [[f % x if x == x else None for f, x in zip(formats, row)]
                                          for row in a.tolist()]
    assert (tmp_path / "t.csv").read_bytes().decode("utf-8") == _reference(want)
    assert np.isnan(read_table(tmp_path / "t.csv")["c"][3])


@pytest.mark.parametrize("columns, undefined, bad", [
    ({"a": np.ones(3), "b": np.array([1.0, np.inf, 0.0])}, (), "column b, element 1"),
    ({"a": 1.0, "b": np.ones(4), "c": np.array([np.nan])}, (), "column c"),  # shapes do not stack
    ({"Us_x": np.array([np.nan, np.inf]), "p": np.ones(2)}, ("Us_",), "column Us_x, element 1"),
    ({"p": np.ones(2), "Us_x": np.array([np.nan, 1.0]), "q": np.array([0.0, np.nan])}, ("Us_",),
     "column q, element 1"),
    ({"a": None}, (), "column a"),
])
def test_check_finite_names_the_first_bad_value_whatever_the_shapes(columns, undefined, bad):
    reset_nonfinite()
    with pytest.raises(NonFiniteOutput, match=bad):
        check_finite("x.csv", 2.0, columns, undefined)
    assert check_finite("x.csv", 2.0, columns, undefined) is False  # after the first refusal: dropped
    reset_nonfinite()


def test_check_finite_passes_finite_columns_and_nan_where_undefined():
    reset_nonfinite()
    assert check_finite("x", 0.0, {"a": 1.0, "b": np.ones(3), "Us_c": np.array([np.nan, 2.0])}, ("Us_",))
    assert check_finite("x", 0.0, {})


def test_probe_row_writes_as_probe_and_refuses_the_same_rows(tmp_path):
    reset_nonfinite()
    cols = ["p", "Us_q", "r"]
    a = ResultWriter(tmp_path / "a", ["x"], cols)
    b = ResultWriter(tmp_path / "b", ["x"], cols)
    for t, row in enumerate([[1.5, 2.0, -3e-9], [0.0, np.nan, 1e300]]):
        a.probe(float(t), dict(zip(cols, row)))
        b.probe_row(float(t), row)
    with pytest.raises(NonFiniteOutput, match="column r"):
        b.probe_row(2.0, [1.0, 1.0, np.nan])
    with pytest.raises(NonFiniteOutput, match="column Us_q"):
        reset_nonfinite()
        b.probe_row(3.0, [1.0, np.inf, 1.0])
    a.close()
    b.close()
    assert (tmp_path / "a" / "probes.csv").read_bytes() == (tmp_path / "b" / "probes.csv").read_bytes()
    reset_nonfinite()
