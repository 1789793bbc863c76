"""The resolved case as the TOML file nests it: ``case["boundary"]["bottom"]["kind"]``.

A case file's dotted section names (``[closures.drag]``, ``[boundary.bottom]``) are tables
inside tables in TOML, and :func:`~twofluid.casefile.loader.load_case` returns them so:
``case["closures"]["drag"]``. The schema names each section by its dotted name, and
:func:`sections` gives that flat view for code that walks the sections by schema name.

Until version 0.1.0, ``load_case`` returned the sections under flat dotted keys
(``case["closures.drag"]``). A :class:`Case` still answers them for one more release, with a
:class:`FlatKeyWarning` (a ``DeprecationWarning``) that names the nested spelling.
"""
from __future__ import annotations

import os
import sys
import warnings
from pathlib import Path

__all__ = ["Case", "FlatKeyWarning", "nest", "sections", "section", "nested_spelling", "is_group"]


class FlatKeyWarning(DeprecationWarning):
    """A case section looked up by its flat dotted name (``case["closures.drag"]``): it still
    works in this release and is removed in the next; the nesting of the TOML file replaces it
    (``case["closures"]["drag"]``)."""


def nested_spelling(key: str) -> str:
    """The nested Python spelling of a flat dotted section name.

    >>> print(nested_spelling("boundary.bottom"))
    case["boundary"]["bottom"]
    """
    return "case" + "".join(f"[{p!r}]" for p in key.split(".")).replace("'", '"')


def _warn(key: str, stacklevel: int = 3) -> None:
    """One warning for a flat access, attributed to the line that made it (``Case`` method: 3)."""
    warnings.warn(FlatKeyWarning(
        f'twofluid: case["{key}"]: flat dotted section keys are deprecated and will be removed in the '
        f"next release; use {nested_spelling(key)}, the nesting of the TOML file"), stacklevel=stacklevel)


_PACKAGE = str(Path(__file__).resolve().parent.parent) + os.sep


def caller_stacklevel() -> int:
    """The ``stacklevel`` of the innermost frame outside the twofluid package, for a warning about
    what the caller gave: Python shows a ``DeprecationWarning`` by default only where it is
    attributed to ``__main__`` (a script, a notebook), not to the package's own modules."""
    frame, level = sys._getframe(1), 1
    while frame is not None and str(Path(frame.f_code.co_filename).resolve()).startswith(_PACKAGE):
        frame, level = frame.f_back, level + 1
    return level


def _is_flat(case: dict, key) -> bool:
    return isinstance(key, str) and "." in key and not dict.__contains__(case, key)


class Case(dict):
    """A resolved case: a ``dict`` of sections nested as in the TOML file.

    Flat dotted section names (the form of version 0.1.0) still read, test, write and delete
    the nested section, each time with one :class:`FlatKeyWarning` naming the nested form.

    >>> c = Case({"closures": {"drag": {"law": "ergun"}}})
    >>> c["closures"]["drag"]["law"]
    'ergun'
    >>> import warnings
    >>> with warnings.catch_warnings(record=True) as w:
    ...     warnings.simplefilter("always")
    ...     c["closures.drag"]["law"], "closures.drag" in c
    ('ergun', True)
    >>> print(w[0].message)  # doctest: +ELLIPSIS
    twofluid: case["closures.drag"]: ... use case["closures"]["drag"], the nesting of the TOML file
    """

    __slots__ = ()

    def _parent(self, key: str, create: bool = False) -> tuple[dict | None, str]:
        """(the table holding the last part of a dotted ``key``, that part); None if a part is missing."""
        *path, last = key.split(".")
        node = self
        for p in path:
            nxt = dict.get(node, p) if isinstance(node, dict) else None
            if not isinstance(nxt, dict):
                if not (create and nxt is None and isinstance(node, dict)):
                    return None, last
                nxt = dict.setdefault(node, p, {})
            node = nxt
        return node, last

    def __getitem__(self, key):
        if _is_flat(self, key):
            _warn(key)
            node, last = self._parent(key)
            if node is None or last not in node:
                raise KeyError(key)
            return node[last]
        return dict.__getitem__(self, key)

    def __setitem__(self, key, value) -> None:
        if _is_flat(self, key):
            _warn(key)
            node, last = self._parent(key, create=True)
            if node is None:
                raise KeyError(f"{key}: {key.rpartition('.')[0]} is not a table of sections")
            node[last] = value
            return
        dict.__setitem__(self, key, value)

    def __delitem__(self, key) -> None:
        if _is_flat(self, key):
            _warn(key)
            node, last = self._parent(key)
            if node is None or last not in node:
                raise KeyError(key)
            del node[last]
            return
        dict.__delitem__(self, key)

    def __contains__(self, key) -> bool:
        if _is_flat(self, key):
            _warn(key)
            node, last = self._parent(key)
            return node is not None and last in node
        return dict.__contains__(self, key)

    def get(self, key, default=None):
        if _is_flat(self, key):
            _warn(key)
            node, last = self._parent(key)
            return default if node is None else node.get(last, default)
        return dict.get(self, key, default)

    def pop(self, key, *default):
        if _is_flat(self, key):
            _warn(key)
            node, last = self._parent(key)
            if node is None or last not in node:
                if default:
                    return default[0]
                raise KeyError(key)
            return node.pop(last)
        return dict.pop(self, key, *default)

    def setdefault(self, key, default=None):
        if _is_flat(self, key):
            _warn(key)
            node, last = self._parent(key, create=True)
            if node is None:
                raise KeyError(f"{key}: {key.rpartition('.')[0]} is not a table of sections")
            return node.setdefault(last, default)
        return dict.setdefault(self, key, default)

    def update(self, other=(), /, **kw) -> None:
        for key, value in dict(other, **kw).items():
            if _is_flat(self, key):
                _warn(key, stacklevel=4)
                node, last = self._parent(key, create=True)
                if node is None:
                    raise KeyError(f"{key}: {key.rpartition('.')[0]} is not a table of sections")
                node[last] = value
            else:
                dict.__setitem__(self, key, value)

    def __reduce__(self):  # pickled (Dask workers) and deep-copied as a Case, nested
        return (Case, (dict(self),))

    def __reduce_ex__(self, protocol):
        return self.__reduce__()


def is_group(value) -> bool:
    """A table of sections (``closures``: every entry a table), not a section of keys.

    >>> is_group({"drag": {"law": "ergun"}}), is_group({"end": 1.0}), is_group({})
    (True, False, False)
    """
    return isinstance(value, dict) and bool(value) and all(isinstance(v, dict) for v in value.values())


def sections(case: dict) -> dict:
    """{dotted section name: table} of a case, nested or flat (the schema's names); arrays of
    tables and the ``_`` entries as they are. Raises no :class:`FlatKeyWarning`.

    >>> sections({"closures": {"drag": {"law": "ergun"}}, "time": {"end": 1.0}, "_source": "x"})
    {'closures.drag': {'law': 'ergun'}, 'time': {'end': 1.0}, '_source': 'x'}
    """
    out: dict = {}

    def walk(prefix: str, table: dict) -> None:
        for k, v in dict.items(table):
            name = f"{prefix}.{k}" if prefix else k
            if is_group(v) and not (isinstance(k, str) and k.startswith("_")):
                walk(name, v)
            else:
                out[name] = v

    walk("", case)
    return out


def nest(flat: dict) -> Case:
    """A :class:`Case` of ``flat`` with each dotted section name made tables in tables.

    >>> nest({"closures.drag": {"law": "ergun"}, "time": {"end": 1.0}})
    {'closures': {'drag': {'law': 'ergun'}}, 'time': {'end': 1.0}}
    """
    out = Case()
    for where, table in dict.items(flat):
        if isinstance(where, str) and "." in where and not where.startswith("_"):
            *path, last = where.split(".")
            node = out
            for p in path:
                node = dict.setdefault(node, p, {})
            node[last] = table
        else:
            dict.__setitem__(out, where, table)
    return out


def section(case: dict, where: str, default=None):
    """The section ``where`` (a schema name, e.g. ``"closures.drag"``) of a nested case, or ``default``.

    >>> section({"closures": {"drag": {"law": "ergun"}}}, "closures.drag")
    {'law': 'ergun'}
    >>> section({"time": {"end": 1.0}}, "closures.drag") is None
    True
    """
    node = case
    for p in where.split("."):
        if not isinstance(node, dict) or not dict.__contains__(node, p):
            return default
        node = dict.__getitem__(node, p)
    return node
