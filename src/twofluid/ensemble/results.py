"""The results of an ensemble: ``members.csv`` streamed row by row, and ``ensemble.json``.

One row per member: ``member`` (its index), ``hash`` (of its resolved case), ``status``
(completed or failed), ``reason``, ``wall_time_s`` and ``cpu_time_s`` (of the member's
process while it ran: less than the wall time when the CPU is shared), the varied parameters and the
collected figures. A figure that is a list or a table is written as JSON in its cell. Beside a
settlement a member reached, the ensemble also collects whether it is final and the predicted final
settlement (:func:`with_settlement_companions`), and ``ensemble.json`` says how many members' settlements
are final (:func:`figure_stats`).
Rows are flushed as members finish, so an interrupted ensemble keeps every finished row.
"""
from __future__ import annotations

import csv
import io
import json
import os
from pathlib import Path

import numpy as np

from ..io.folders import create, write_all, write_atomic
from ..io.results import plain

__all__ = ["ResultsTable", "figure_at", "unit_of", "figure_stats", "with_settlement_companions", "settlement_notes",
           "encode", "decode", "FIXED"]

FIXED = ["member", "hash", "status", "reason", "wall_time_s", "cpu_time_s"]

# unit of a figure from the end of its name (summary.json's naming habit), longest first
_SUFFIX_UNITS = [("_m3_s", "m³/s"), ("_m2_s", "m²/s"), ("_m_s2", "m/s²"), ("_m_s", "m/s"), ("_1_s", "1/s"),
                 ("_m3", "m³"), ("_kPa", "kPa"), ("_Pa", "Pa"), ("_percent_of_depth", "% of depth"),
                 ("_percent", "%"), ("_m", "m"), ("_s", "s"), ("_g", "g")]


def unit_of(path: str) -> str:
    """The unit of a figure from its dotted name; "-" when the name carries none.

    >>> unit_of("settlement_end_m"), unit_of("base_excess_pore_pressure.peak_Pa"), unit_of("t1_s")
    ('m', 'Pa', 's')
    >>> unit_of("solids_volume_m3.final"), unit_of("peak_r_u_top_element"), unit_of("porosity_error@5")
    ('m³', '-', '-')
    """
    if "@" in path:
        return "-" if path.startswith("porosity_error") else unit_of(path.split("@")[0])
    for part in reversed(path.split(".")):
        for suffix, unit in _SUFFIX_UNITS:
            if part.endswith(suffix):
                return unit
    return "-"


def figure_at(summary: dict, profiles: dict, path: str):
    """The figure ``path`` of one run: a dotted path into its summary (list entries 1-based), or ``profile.FIELD@T``
    (the element field at output time T [s]; ``@end``: the last profile) as a list.

    >>> figure_at({"a": {"b_m": 2.0}}, {}, "a.b_m")
    2.0
    >>> figure_at({}, {0.0: {"porosity": [0.5]}, 4.0: {"porosity": [0.4]}}, "profile.porosity@end")
    [0.4]
    >>> figure_at({"a": 1}, {}, "b") is None
    True
    >>> figure_at({"layers": [{"h_m": 1.0}, {"h_m": 2.0}]}, {}, "layers.2.h_m")
    2.0
    """
    if path.startswith("profile.") and "@" in path:
        name, when = path[len("profile."):].split("@", 1)
        if not profiles:
            return None
        times = sorted(profiles)
        t = times[-1] if when == "end" else next((s for s in times if abs(s - float(when)) <= 1e-9 * max(1.0, s)),
                                                 None)
        return None if t is None or name not in profiles[t] else plain(profiles[t][name])
    node = summary
    for part in path.split("."):
        if isinstance(node, list) and part.isdigit() and 1 <= int(part) <= len(node):
            node = node[int(part) - 1]  # an entry of a list, 1-based: layers.2.settlement_end_m
        elif isinstance(node, dict) and part in node:
            node = node[part]
        else:
            return None
    return plain(node)


def encode(v) -> str:
    """A cell: "" for None and non-finite numbers, numbers and strings as they are, lists and
    tables as JSON (non-finite entries null).

    >>> encode(float("nan")), encode([1.0, float("inf")]), encode(0.5), encode(True)
    ('', '[1.0,null]', '0.5', 'true')
    """
    if v is None:
        return ""
    if isinstance(v, (bool, np.bool_)):
        return "true" if v else "false"  # JSON's spelling: decoded back to a bool
    if isinstance(v, (list, dict)):
        return json.dumps(plain(v), separators=(",", ":"), allow_nan=False)
    if isinstance(v, (float, np.floating)):
        return repr(float(v)) if np.isfinite(v) else ""  # NaN, inf: an empty cell, as every output
    return str(v)


def decode(text: str):
    """Inverse of :func:`encode` (numbers, JSON, else the text).

    >>> decode(encode([1.0, None])), decode(encode(0.1)), decode(""), decode("x.AT2"), decode(encode(False))
    ([1.0, None], 0.1, None, 'x.AT2', False)
    """
    if text == "":
        return None
    try:
        return json.loads(text)
    except ValueError:
        return text


class ResultsTable:
    """``members.csv``: the rows kept from an earlier run of the same ensemble, then new rows.

    Opening it keeps the completed rows whose hash is a current member's (and that hold
    every collected figure) and moves any other earlier rows to ``members.previous.csv``.
    """

    def __init__(self, path: Path, params: list[str], figures: list[str], hashes: set[str]):
        self.path = Path(path)
        self.columns = FIXED + params + figures
        self.kept: dict[str, dict] = {}
        dropped = []
        if self.path.is_file():
            with open(self.path, newline="", encoding="utf-8") as fh:
                reader = csv.DictReader(fh)
                if not set(FIXED) <= set(reader.fieldnames or []):
                    from ..casefile.schema import CaseError

                    raise CaseError(str(self.path), "members table", "is not a members table of twofluid "
                                    f"(columns {', '.join(FIXED)} missing): move it away, or give another folder")
                has_all = set(figures) <= set(reader.fieldnames or [])
                for raw in reader:
                    if has_all and raw["status"] == "completed" and raw["hash"] in hashes:
                        self.kept[raw["hash"]] = raw
                    elif raw["status"] != "completed" or raw["hash"] in hashes:
                        continue  # a failed member or a figure not collected then: run again
                    else:
                        dropped.append(raw)
            if dropped:
                fh = io.StringIO()
                w = csv.DictWriter(fh, list(dropped[0]))
                w.writeheader()
                w.writerows(dropped)
                write_atomic(self.path.with_name("members.previous.csv"), fh.getvalue())
        fh = io.StringIO()
        w = csv.DictWriter(fh, self.columns, extrasaction="ignore")
        w.writeheader()
        w.writerows(self.kept.values())
        write_atomic(self.path, fh.getvalue())  # the kept rows first, atomically
        self._fd = create(self.path, append=True)
        self._end = os.fstat(self._fd).st_size
        self._buf = io.StringIO()
        self._w = csv.DictWriter(self._buf, self.columns, extrasaction="ignore")

    def kept_row(self, h: str) -> dict:
        """A kept row decoded (numbers and lists back from the text)."""
        raw = self.kept[h]
        return {k: (raw[k] if k in ("hash", "status", "reason") else decode(raw.get(k, ""))) for k in self.columns}

    def write(self, row: dict) -> None:
        """Append one row: one unbuffered write of the whole line (a Ctrl-C or SIGTERM, raised
        between Python operations, cannot leave half a row; on a full disk the file is cut back to
        its last whole row and the error, naming the file, raised)."""
        self._buf.seek(0)
        self._buf.truncate()
        self._w.writerow({k: encode(row.get(k)) for k in self.columns})
        data = self._buf.getvalue().encode("utf-8")
        try:
            write_all(self._fd, data, self.path)
        except OSError:
            try:
                os.ftruncate(self._fd, self._end)
            except OSError:
                pass
            raise
        self._end += len(data)

    def close(self) -> None:
        if self._fd is not None:
            fd, self._fd = self._fd, None
            os.close(fd)


FINAL_FLAG = "settlement_final"  # summary.json: whether the run's settlement is final


def _reached_settlement(path: str) -> bool:
    """A figure that is a settlement a run reached (not a final, predicted or simplified-procedure one,
    nor the one at the end of shaking)."""
    last = path.split(".")[-1]
    return ("settlement" in last and last.startswith("settlement") and "final" not in last
            and "simplified" not in path and "end_of_shaking" not in last)


def _final_of(path: str) -> str:
    """The predicted final settlement beside a reached one: ``layers.2.settlement_end_m`` →
    ``layers.2.predicted_final_settlement_m``; the column's own otherwise."""
    head = path.rsplit(".", 1)[0] + "." if "." in path else ""
    return head + "predicted_final_settlement_m" if head.startswith("layers.") else "predicted_final_settlement_m"


def with_settlement_companions(collect: list[str]) -> list[str]:
    """``collect`` with, after it, whether the settlement is final and the predicted final settlement for
    every collected settlement a run reached (none added twice).

    >>> with_settlement_companions(["settlement_end_m", "layers.2.settlement_end_m", "steps"])
    ['settlement_end_m', 'layers.2.settlement_end_m', 'steps', 'settlement_final', 'predicted_final_settlement_m', 'layers.2.predicted_final_settlement_m']
    >>> with_settlement_companions(["simplified_procedure.settlement_run_m"])
    ['simplified_procedure.settlement_run_m']
    """
    out = list(collect)
    for f in collect:
        if _reached_settlement(f):
            for c in (FINAL_FLAG, _final_of(f)):
                if c not in out:
                    out.append(c)
    return out


def settlement_notes(rows: list[dict], figures: list[str]) -> list[str]:
    """One line per collected settlement some completed run did not reach in full: which runs, the
    settlement reached and the predicted final one (the rows must hold the companions of
    :func:`with_settlement_companions`); one line saying they are final otherwise.

    >>> rows = [{"member": 0, "status": "completed", "settlement_end_m": 0.1, "settlement_final": True,
    ...          "predicted_final_settlement_m": 0.1},
    ...         {"member": 1, "status": "completed", "settlement_end_m": 0.05, "settlement_final": False,
    ...          "predicted_final_settlement_m": 0.12}]
    >>> print(settlement_notes(rows, ["settlement_end_m"])[0])
    settlement_end_m is partial in 1 of 2 runs (the run stopped before dissipation): member 1 0.05 m of a predicted final 0.12 m
    >>> settlement_notes(rows[:1], ["settlement_end_m"])
    ['settlement_end_m is final in every run']
    """
    out = []
    done = [r for r in rows if r["status"] == "completed"]
    for f in figures:
        if not _reached_settlement(f) or not done:
            continue
        part = [r for r in done if r.get(FINAL_FLAG) is False]
        if not part:
            out.append(f"{f} is final in every run")
            continue
        fin = _final_of(f)
        each = ", ".join(f"member {r.get('member')} {r.get(f):.3g} m of a predicted final {r.get(fin):.3g} m"
                         for r in part if isinstance(r.get(f), (int, float)) and isinstance(r.get(fin), (int, float)))
        out.append(f"{f} is partial in {len(part)} of {len(done)} runs (the run stopped before dissipation): {each}")
    return out


def figure_stats(rows: list[dict], figures: list[str]) -> dict:
    """{figure: {unit, count, min, mean, std, max}} over the completed members' scalar values; a
    true/false figure gives its count of true (``true``). Beside a settlement a run reached (when
    ``settlement_final`` was collected): ``final``, how many members' settlements are final, in words,
    ``members_final``, and ``predicted_final``, the statistics of the predicted final settlement; of a list-valued figure (a value per depth),
    the same per entry as lists (None where no member has one).

    >>> rows = [{"status": "completed", "h_m": 1.0}, {"status": "completed", "h_m": 3.0},
    ...         {"status": "failed", "h_m": None}]
    >>> figure_stats(rows, ["h_m"])
    {'h_m': {'unit': 'm', 'count': 2, 'min': 1.0, 'mean': 2.0, 'std': 1.0, 'max': 3.0}}
    >>> rows = [{"status": "completed", "settlement_end_m": a, "settlement_final": f,
    ...          "predicted_final_settlement_m": 0.2} for a, f in ((0.1, False), (0.2, True))]
    >>> st = figure_stats(rows, with_settlement_companions(["settlement_end_m"]))
    >>> st["settlement_end_m"]["final"], st["settlement_end_m"]["predicted_final"]["mean"]
    ('1 of 2 members final; the others stopped before dissipation (predicted final settlement: predicted_final_settlement_m)', 0.2)
    >>> st["settlement_final"]
    {'unit': '-', 'count': 2, 'true': 1}
    >>> figure_stats([{"status": "completed", "r": [1.0, 2.0]}, {"status": "completed", "r": [3.0, None]}], ["r"])
    {'r': {'unit': '-', 'count': 2, 'entries': 2, 'min': [1.0, 2.0], 'mean': [2.0, 2.0], 'std': [1.0, 0.0], 'max': [3.0, 2.0]}}
    """
    out = {}
    done = [r for r in rows if r["status"] == "completed"]
    for f in figures:
        lists = [r[f] for r in done if isinstance(r.get(f), list)]
        if lists and all(all(isinstance(x, (int, float)) and not isinstance(x, bool) or x is None for x in v)
                         for v in lists):  # a value per entry: the statistics of each entry over the members
            width = max(len(v) for v in lists)
            a = np.array([[np.nan if x is None else x for x in v] + [np.nan] * (width - len(v)) for v in lists], float)
            n = np.isfinite(a).sum(0)
            with np.errstate(all="ignore"):
                stats = {k: [float(x) if c else None for x, c in zip(fn(np.where(np.isfinite(a), a, fill), 0), n)]
                         for k, fn, fill in (("min", np.min, np.inf), ("max", np.max, -np.inf))}
                mean = np.nansum(a, 0) / np.maximum(n, 1)
                std = np.sqrt(np.nansum((a - mean) ** 2, 0) / np.maximum(n, 1))
            out[f] = {"unit": unit_of(f), "count": len(lists), "entries": width, "min": stats["min"],
                      "mean": [float(x) if c else None for x, c in zip(mean, n)],
                      "std": [float(x) if c else None for x, c in zip(std, n)], "max": stats["max"]}
            continue
        flags = [r[f] for r in done if isinstance(r.get(f), bool)]
        if flags:
            out[f] = {"unit": "-", "count": len(flags), "true": int(sum(flags))}
            continue
        out[f] = _stats(done, f)
        if _reached_settlement(f) and FINAL_FLAG in figures:
            final = [r.get(FINAL_FLAG) for r in done if isinstance(r.get(f), (int, float))]
            k = sum(x is True for x in final)
            out[f]["members_final"] = k
            out[f]["final"] = ("all members final" if k == len(final) else
                               f"{k} of {len(final)} members final; the others stopped before dissipation "
                               f"(predicted final settlement: {_final_of(f)})")
            out[f]["predicted_final"] = _stats(done, _final_of(f))
    return out


def _stats(rows: list[dict], f: str) -> dict:
    vals = np.array([r[f] for r in rows if isinstance(r.get(f), (int, float)) and not isinstance(r.get(f), bool)],
                    float)
    entry = {"unit": unit_of(f), "count": int(vals.size)}
    if vals.size:
        entry.update(min=float(vals.min()), mean=float(vals.mean()), std=float(vals.std()), max=float(vals.max()))
    return entry
