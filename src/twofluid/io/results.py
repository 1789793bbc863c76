"""Writers for a run's output folder: resolved case, profiles, probes, summary.

A plain stream writes every row as it comes, so an interrupted or failed run leaves
readable CSV files; ``summary.json`` is written at the end whatever the outcome
(with ``status`` "completed", "interrupted" or "failed" and where it stopped). A stream
opened with ``block=True`` (a run that writes a row every step) keeps its rows in memory and
writes them in blocks: at 64 KiB, after a second, on :meth:`CsvStream.flush` and on
:meth:`CsvStream.close` (which the run's guard calls on every way out of the time loop:
completed, failed, Ctrl-C, SIGTERM), so the file is the same, byte for byte, and what a stopped
run had computed is still written (a process killed outright, SIGKILL or out of memory, loses
the rows of the block not yet written: at most a second of them).

Two guards sit here, at the one place every output passes through:

- *finite values*: a NaN or inf in a row raises :class:`NonFiniteOutput` (a
  ``FloatingPointError``, which ends a run as "failed" with the column, the time and
  the element in the reason) and nothing of that row is written. Columns that are
  undefined by definition (U_s in clear liquid) are declared ``undefined`` and written
  as empty cells. After the first such failure of a run, further non-finite rows (the
  runner writing its last state) are dropped silently: the reason is already recorded.
- *whole rows*: a row (or the rows of one profile) is formatted first and written with
  one call; if the disk is full the file is cut back to its last complete row, so a
  reader never meets half a row.
"""
from __future__ import annotations

import contextvars
import csv
import io
import json
import math
import os
import time
from pathlib import Path

import numpy as np
import tomli_w

__all__ = ["plain", "ResultWriter", "CsvStream", "NonFiniteOutput", "write_resolved_case", "write_json", "read_table",
           "check_finite", "reset_nonfinite"]

#: set once a run's writer has refused a non-finite row (the run has failed with that reason)
_REFUSED: contextvars.ContextVar[bool] = contextvars.ContextVar("twofluid_nonfinite_refused", default=False)


class NonFiniteOutput(FloatingPointError):
    """A NaN or inf about to be written: the run fails, naming the output, column, time and element."""


def reset_nonfinite() -> None:
    """Start of a run: no non-finite row refused yet (called by ``run_guard``)."""
    _REFUSED.set(False)


def check_finite(what: str, t: float, columns: dict[str, np.ndarray], undefined=(), element_name="element") \
        -> bool:
    """True if every value of ``columns`` is finite (NaN allowed in columns starting with a prefix in
    ``undefined``); otherwise raise :class:`NonFiniteOutput` naming the first bad value — or, after a
    first refusal in this run, return False (the row is dropped).

    >>> check_finite("probes.csv", 1.0, {"a": np.array([1.0])})
    True
    """
    undefined = tuple(undefined)
    if _all_finite(columns, undefined):  # the usual case: one NumPy test for the whole row block
        return True
    for name, values in columns.items():  # name the first bad value
        v = np.asarray(values, dtype=float)
        ok = np.isfinite(v)
        if undefined and name.startswith(undefined):
            ok |= np.isnan(v)
        if ok.all():
            continue
        if _REFUSED.get():
            return False
        _REFUSED.set(True)
        flat = np.flatnonzero(~ok.ravel())[0]
        where = f", {element_name} {int(np.unravel_index(flat, v.shape)[0])}" if v.ndim >= 1 and v.size > 1 else ""
        raise NonFiniteOutput(f"non-finite value {v.ravel()[flat]!r} in {what}, column {name}{where}, "
                              f"at t = {t:.10g} s (the step that reached it): the run stops rather than "
                              "write it")
    return True


def _all_finite(columns: dict, undefined: tuple) -> bool:
    """Whether every value is finite (or NaN in an ``undefined`` column), tested on the columns stacked
    into one array; False also where they do not stack (columns of different shapes): the caller then
    tests them one by one."""
    if undefined:
        strict = [v for k, v in columns.items() if not k.startswith(undefined)]
        loose = [v for k, v in columns.items() if k.startswith(undefined)]
    else:
        strict, loose = list(columns.values()), ()
    try:
        if not np.isfinite(np.array(strict, dtype=float)).all():
            return False
        return not (loose and np.isinf(np.array(loose, dtype=float)).any())
    except (ValueError, TypeError):
        return False


def _cell(v) -> str:
    if v is None:
        return ""
    if isinstance(v, str):
        return v
    v = float(v)
    return "" if np.isnan(v) else f"{v:.10g}"


_FORMATS: dict[int, str] = {}


def _line(r) -> str | None:
    """The CSV line of a row of numbers (each as ``_cell`` writes it), formatted by one ``%`` call;
    None where the row holds anything else (text, None) or is one NaN: ``csv.writer`` takes it then."""
    n = len(r)
    fmt = _FORMATS.get(n)
    if fmt is None:
        fmt = _FORMATS[n] = ",".join(["%.10g"] * n) + "\r\n"  # csv.writer's line end
    try:
        text = fmt % tuple(r)
    except TypeError:  # text or None: %g takes numbers only
        return None
    if "nan" in text:  # NaN is an empty cell (csv.writer's line, but for a lone empty cell, which it quotes)
        return ",".join("" if x != x else "%.10g" % x for x in r) + "\r\n" if n > 1 else None
    return text


class CsvStream:
    """A CSV file written whole rows at a time (see the module doc), re-opened for appending if
    written after :meth:`close` (the runner's last state after an interruption).

    The file is written unbuffered through its descriptor (:func:`~twofluid.io.folders.create`: never
    through a symbolic link): every row is flushed anyway (``block=True``: every block, see the
    module doc), and with no buffer of its own a write that fails (disk full, file-size limit)
    leaves nothing pending that a later close or flush could add after the file has been cut back
    to its last complete row."""

    #: a block stream writes its rows once they reach this many characters, or are this old [s]
    BLOCK_CHARS, BLOCK_AGE = 65536, 1.0

    def __init__(self, path: Path, header: list[str], block: bool = False):
        from .folders import create

        self.path = Path(path)
        self._fd = create(self.path)
        self._end = 0  # bytes in the file: the end of its last complete row
        self._block = False
        self._pending, self._chars, self._since = [], 0, 0.0  # rows not yet written (block mode)
        self.rows([[str(h) for h in header]])  # the header at once
        self._block = block

    def line(self, row) -> None:
        """Write one row of numbers (a list of floats; NaN as an empty cell): :meth:`rows` of one row."""
        text = _line(row)
        if text is None:
            return self.rows([row])
        self._write(text)

    def rows(self, rows) -> None:
        """Write ``rows`` (sequences of numbers, text or None; NaN and None as empty cells)."""
        buf = io.StringIO()
        w = None
        for r in rows:
            line = _line(r)
            if line is not None:
                buf.write(line)
                continue
            if w is None:
                w = csv.writer(buf)
            w.writerow([_cell(v) for v in r])
        self._write(buf.getvalue())

    def table(self, values: np.ndarray, formats: list[str]) -> None:
        """Write the rows of the 2D float array ``values``, column j formatted by the printf format
        ``formats[j]`` (e.g. ``"%.6g"``); NaN cells empty. The caller has checked the values
        (:func:`check_finite`)."""
        fmt = ",".join(formats) + "\r\n"
        out = []
        for row in np.atleast_2d(values).tolist():
            text = fmt % tuple(row)
            if "nan" in text:
                text = ",".join("" if x != x else f % x for f, x in zip(formats, row)) + "\r\n"
            out.append(text)
        self._write("".join(out))

    def _write(self, text: str) -> None:
        if self._block and self._fd is not None:  # kept, written in blocks (after close: at once)
            if not self._pending:
                self._since = time.monotonic()
            self._pending.append(text)
            self._chars += len(text)
            if self._chars >= self.BLOCK_CHARS or time.monotonic() - self._since >= self.BLOCK_AGE:
                self.flush()
            return
        self._put(text)

    def flush(self) -> None:
        """Write the rows kept in memory (block mode). If the disk fills, as many whole rows as fit
        are written (the file cut back to its last complete row) and the error is raised."""
        if self._pending:
            self._put(self._pending)

    def _put(self, pieces) -> None:
        """Write ``pieces`` (text: whole rows each) with one call; if that fails (disk full), the file
        is cut back to its last complete row, as many pieces as fit are written one by one, and the
        file is closed and the error raised."""
        from .folders import create, write_all

        if self._fd is None:
            self._fd = create(self.path, append=True)
            self._end = os.fstat(self._fd).st_size
        data = (pieces if type(pieces) is str else "".join(pieces)).encode("utf-8")
        good = self._end
        if pieces is self._pending:  # off the queue only now, text made: the window in which a signal's
            self._pending, self._chars = [], 0  # exception (Ctrl-C, SIGTERM) would lose them is a few instructions
        try:
            write_all(self._fd, data, self.path)
        except OSError as exc:  # disk full: cut back to the last complete row, then report it
            error = exc
            try:
                os.ftruncate(self._fd, good)
                if type(pieces) is not str and len(pieces) > 1:  # a block: the rows that fit
                    os.lseek(self._fd, good, os.SEEK_SET)
                    for text in pieces:
                        one = text.encode("utf-8")
                        try:
                            write_all(self._fd, one, self.path)
                        except OSError as exc2:
                            error = exc2
                            os.ftruncate(self._fd, good)
                            break
                        good += len(one)
                    self._end = good
            except OSError:
                pass
            self.close()
            raise error from None
        self._end = good + len(data)

    def close(self) -> None:
        """Write what is kept (:meth:`flush`) and close the file; a later row re-opens it."""
        try:
            if self._fd is not None:
                self.flush()
        finally:
            if self._fd is not None:
                fd, self._fd = self._fd, None
                os.close(fd)


def write_resolved_case(path: Path, case: dict) -> None:
    """The fully resolved case (every key that acts, defaults filled) as TOML, re-loadable as a case."""
    from ..casefile.schema import effective

    doc = {where: table for where, table in effective(case).items() if not where.startswith("_")}  # nested
    from .folders import write_atomic

    source = " ".join(str(case.get("_source", "?")).split())  # one comment line, whatever the source
    header = f"# Resolved case: every key with its value used in this run.\n# Source: {source}\n"
    write_atomic(path, header + tomli_w.dumps(doc))


def plain(v):
    """JSON-ready: numpy arrays and scalars as lists and numbers, NaN/inf as None ("not computed").

    >>> plain({"a": np.array([1.0, np.nan]), "b": np.int64(2), "c": np.True_})
    {'a': [1.0, None], 'b': 2, 'c': True}
    """
    if isinstance(v, dict):
        return {k: plain(x) for k, x in v.items()}
    if isinstance(v, (list, tuple, np.ndarray)):
        return [plain(x) for x in v]
    if isinstance(v, (np.floating, float)):
        return None if not np.isfinite(v) else float(v)
    if isinstance(v, np.integer):
        return int(v)
    if isinstance(v, np.bool_):
        return bool(v)
    return v


def write_json(path: Path, data: dict) -> None:
    """``data`` as JSON; non-finite numbers become null ("not computed"). Written whole or not at all
    (:func:`~twofluid.io.folders.write_atomic`), so an older summary is replaced only by a complete
    one; an error (disk full) names the file."""
    from .folders import write_atomic

    write_atomic(path, json.dumps(plain(data), indent=2, allow_nan=False) + "\n")


def read_table(path: Path) -> dict[str, np.ndarray]:
    """A CSV file written here as {column: array} (numbers as floats, empty cells NaN).

    >>> import tempfile
    >>> p = Path(tempfile.mkdtemp()) / "t.csv"
    >>> s = CsvStream(p, ["time_s", "a"]); s.rows([[0.0, 1.5], [1.0, None]]); s.close()
    >>> read_table(p)["a"]
    array([1.5, nan])
    """
    with open(path, newline="", encoding="utf-8") as f:
        rows = list(csv.reader(f))
    if not rows:
        return {}
    head, body = rows[0], rows[1:]
    out = {}
    for i, name in enumerate(head):
        col = [r[i] if i < len(r) else "" for r in body]
        try:
            out[name] = np.array([float(c) if c != "" else np.nan for c in col])
        except ValueError:
            out[name] = np.array(col, dtype=object)
    return out


class ResultWriter:
    """Streams profiles (long format) and probe time series into CSV files.

    ``undefined``: column-name prefixes whose values may be undefined (NaN, written as an empty
    cell): U_s in clear liquid. Every other value must be finite (:func:`check_finite`).
    """

    def __init__(self, out_dir: Path, profile_columns: list[str], probe_columns: list[str],
                 undefined=("Us_",), block: bool = False):
        self.out = Path(out_dir)
        self.out.mkdir(parents=True, exist_ok=True)
        self._p = CsvStream(self.out / "profiles.csv", ["time_s"] + profile_columns, block=block)
        self._q = CsvStream(self.out / "probes.csv", ["time_s"] + probe_columns, block=block)
        self.profile_columns, self.probe_columns = profile_columns, probe_columns
        self.undefined = tuple(undefined)
        self._strict = [not c.startswith(self.undefined) for c in probe_columns]  # must be finite (probe_row)
        self._fmt = ",".join(["%.10g"] * (len(probe_columns) + 1)) + "\r\n"  # csv.writer's line end

    def profile(self, t: float, fields: dict[str, np.ndarray]) -> None:
        cols = {c: np.asarray(fields[c], dtype=float) for c in self.profile_columns}
        if not check_finite("profiles.csv", t, cols, self.undefined):
            return
        table = np.column_stack([np.full(len(cols[self.profile_columns[0]]), float(t)), *cols.values()])
        self._p.table(table, ["%.10g"] * table.shape[1])

    def probe(self, t: float, values: dict[str, float]) -> None:
        cols = {c: values[c] for c in self.probe_columns}
        if not check_finite("probes.csv", t, cols, self.undefined):
            return
        self._q.rows([[t, *cols.values()]])

    def probe_row(self, t: float, values) -> None:
        """:meth:`probe` with the values (numbers) as a sequence in the order of ``probe_columns``."""
        row = [float(t), *(values.tolist() if type(values) is np.ndarray else map(float, values))]  # floats
        text = self._fmt % tuple(row)
        if "n" in text:  # "nan" or "inf" (a finite number has no n): finite or NaN where it may be undefined
            for x, must in zip(row[1:], self._strict):
                if not (math.isfinite(x) or (x != x and not must)):
                    return self.probe(t, dict(zip(self.probe_columns, row[1:])))  # names the bad value, or drops the row
            return self._q.line(row)
        self._q._write(text)

    def flush(self) -> None:
        """Write the rows kept in memory (``block=True``): :meth:`CsvStream.flush`."""
        self._p.flush()
        self._q.flush()

    def close(self) -> None:
        try:
            self._p.close()
        finally:
            self._q.close()
