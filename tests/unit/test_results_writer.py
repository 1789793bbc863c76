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


# ---------------------------------------------------------------- rows written in blocks
def _rows(n):
    rng = np.random.default_rng(3)
    return [[float(i), *(rng.standard_normal(5) * 10.0 ** rng.integers(-30, 30, 5))] for i in range(n)]


def test_a_block_stream_writes_the_same_bytes_once_flushed_or_closed(tmp_path, monkeypatch):
    monkeypatch.setattr(CsvStream, "BLOCK_AGE", 1e9)  # kept by size alone, however slow the machine
    rows = _rows(50)
    one = CsvStream(tmp_path / "one.csv", ["t", "a", "b", "c", "d", "e"])
    blk = CsvStream(tmp_path / "blk.csv", ["t", "a", "b", "c", "d", "e"], block=True)
    header = (tmp_path / "blk.csv").read_bytes()
    assert header == b"t,a,b,c,d,e\r\n"  # the header at once
    for r in rows[:20]:
        one.rows([r])
        blk.line(r)
    assert (tmp_path / "blk.csv").read_bytes() == header  # kept in memory: well under a block
    blk.flush()
    assert (tmp_path / "blk.csv").read_bytes() == (tmp_path / "one.csv").read_bytes()
    for r in rows[20:]:
        one.rows([r])
        blk.rows([r]) if r[0] % 2 else blk.table(np.array([r]), ["%.10g"] * 6)
    blk.close()
    one.close()
    assert (tmp_path / "blk.csv").read_bytes() == (tmp_path / "one.csv").read_bytes()
    blk.line([99.0, 1.0, 2.0, 3.0, 4.0, 5.0])  # after close: re-opened, written at once
    assert (tmp_path / "blk.csv").read_bytes().endswith(b"99,1,2,3,4,5\r\n")


def test_a_block_stream_writes_a_full_block_and_rows_a_second_old(tmp_path, monkeypatch):
    blk = CsvStream(tmp_path / "blk.csv", ["t", "a", "b", "c", "d", "e"], block=True)
    monkeypatch.setattr(CsvStream, "BLOCK_CHARS", 200)
    rows = _rows(10)
    for r in rows:
        blk.line(r)
    written = (tmp_path / "blk.csv").read_bytes().count(b"\n") - 1
    assert 0 < written < 10  # the blocks that reached 200 characters, not the rest
    monkeypatch.setattr(CsvStream, "BLOCK_CHARS", 1 << 30)
    monkeypatch.setattr(CsvStream, "BLOCK_AGE", 0.0)
    blk.line(rows[0])
    assert (tmp_path / "blk.csv").read_bytes().count(b"\n") == 12  # a row as old as BLOCK_AGE: all written
    blk.close()


def test_a_block_that_does_not_fit_on_the_disk_leaves_the_rows_that_fit_whole(tmp_path, monkeypatch):
    import errno
    import os

    from twofluid.io import folders

    real = folders.write_all
    left = {"n": 14 + 3 * 9}  # the header and three rows of "1,2,3,4\r\n"

    def write_all(fd, data, path):
        grow = max(os.lseek(fd, 0, os.SEEK_CUR) + len(data) - os.fstat(fd).st_size, 0)
        if grow > left["n"]:
            raise OSError(errno.ENOSPC, "No space left on device", str(path))
        left["n"] -= grow
        real(fd, data, path)

    monkeypatch.setattr(folders, "write_all", write_all)
    blk = CsvStream(tmp_path / "blk.csv", ["time_s", "a,b"], block=True)
    for i in range(5):
        blk.line([1.0, 2.0, 3.0, 4.0])
    with pytest.raises(OSError, match="No space left"):
        blk.flush()
    assert (tmp_path / "blk.csv").read_bytes() == b'time_s,"a,b"\r\n' + b"1,2,3,4\r\n" * 3
    blk.close()  # nothing left to write


def test_probe_rows_in_blocks_are_the_rows_written_one_by_one(tmp_path):
    reset_nonfinite()
    cols = ["p", "Us_q", "r"]
    a = ResultWriter(tmp_path / "a", ["x"], cols)
    b = ResultWriter(tmp_path / "b", ["x"], cols, block=True)
    rows = [[1.5, 2.0, -3e-9], [0.0, np.nan, 1e300], [7, np.float64(0.1), np.float32(0.1)]]
    for t, row in enumerate(rows):
        a.probe_row(float(t), row)
        b.probe_row(float(t), np.array(row, dtype=float) if t == 0 else row)
    with pytest.raises(NonFiniteOutput, match="column r"):
        b.probe_row(9.0, np.array([1.0, 1.0, np.inf]))
    a.close()
    b.close()
    assert (tmp_path / "a" / "probes.csv").read_bytes() == (tmp_path / "b" / "probes.csv").read_bytes()
    assert (tmp_path / "b" / "probes.csv").read_bytes().count(b"\n") == 4
    reset_nonfinite()
