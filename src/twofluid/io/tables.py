"""Small numeric tables in CSV-like text (ground-motion records, G/G_max curves).

Blank lines and text after ``#`` are ignored; fields are separated by commas,
semicolons or white space; the first data line is a header if its first field is
not a number. Errors name the 1-based line.
"""
from __future__ import annotations

import re

__all__ = ["TableError", "read_columns"]


class TableError(ValueError):
    """A malformed row; ``line`` is its 1-based number, ``what`` says what is wrong."""

    def __init__(self, line: int, what: str):
        super().__init__(f"line {line}: {what}")
        self.line, self.what = line, what


def read_columns(text: str, n: int) -> list[tuple[int, list[float]]]:
    """(line number, ``n`` values) of every data row of ``text``.

    >>> read_columns("t, a  # a header\\n0, 1\\n\\n0.1; 2.5\\n", 2)
    [(2, [0.0, 1.0]), (4, [0.1, 2.5])]
    >>> read_columns("0, 1, 2\\n", 2)
    Traceback (most recent call last):
    ...
    twofluid.io.tables.TableError: line 1: 3 value(s) in '0, 1, 2'; expected 2 columns
    """
    rows = []
    seen_data = False
    for number, raw in enumerate(text.splitlines(), start=1):
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        fields = [f for f in re.split(r"[,;\s]+", line) if f]
        if not seen_data:
            seen_data = True
            try:
                float(fields[0])
            except ValueError:
                continue  # header line
        if len(fields) != n:
            raise TableError(number, f"{len(fields)} value(s) in {line!r}; expected {n} columns")
        try:
            rows.append((number, [float(f) for f in fields]))
        except ValueError:
            raise TableError(number, f"non-numeric value in {line!r}") from None
    return rows
