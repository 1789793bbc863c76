"""Writers for a run's output folder: resolved case, profiles, probes, summary.

Every row is flushed as it is written, so an interrupted or failed run leaves
readable CSV files; ``summary.json`` is written at the end whatever the outcome
(with ``status`` "completed", "interrupted" or "failed" and where it stopped).
"""
from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import tomli_w

__all__ = ["ResultWriter", "write_resolved_case", "write_json"]


def write_resolved_case(path: Path, case: dict) -> None:
    """The fully resolved case (every key that acts, defaults filled) as TOML, re-loadable as a case."""
    from ..casefile.schema import effective

    doc: dict = {}
    for where, table in effective(case).items():
        if where.startswith("_"):
            continue
        node = doc
        parts = where.split(".")
        for p in parts[:-1]:
            node = node.setdefault(p, {})
        node[parts[-1]] = table
    header = f"# Resolved case: every key with its value used in this run.\n# Source: {case.get('_source', '?')}\n"
    path.write_text(header + tomli_w.dumps(doc), encoding="utf-8")


def write_json(path: Path, data: dict) -> None:
    def clean(v):
        if isinstance(v, dict):
            return {k: clean(x) for k, x in v.items()}
        if isinstance(v, (list, tuple, np.ndarray)):
            return [clean(x) for x in v]
        if isinstance(v, (np.floating, float)):
            return None if not np.isfinite(v) else float(v)
        if isinstance(v, np.integer):
            return int(v)
        return v

    path.write_text(json.dumps(clean(data), indent=2) + "\n", encoding="utf-8")


class ResultWriter:
    """Streams profiles (long format) and probe time series into CSV files."""

    def __init__(self, out_dir: Path, profile_columns: list[str], probe_columns: list[str]):
        self.out = Path(out_dir)
        self.out.mkdir(parents=True, exist_ok=True)
        self._pf = open(self.out / "profiles.csv", "w", newline="", encoding="utf-8")
        self._qf = open(self.out / "probes.csv", "w", newline="", encoding="utf-8")
        self._p = csv.writer(self._pf)
        self._q = csv.writer(self._qf)
        self._p.writerow(["time_s"] + profile_columns)
        self._q.writerow(["time_s"] + probe_columns)
        self.profile_columns, self.probe_columns = profile_columns, probe_columns

    def profile(self, t: float, fields: dict[str, np.ndarray]) -> None:
        cols = np.column_stack([fields[c] for c in self.profile_columns])
        for row in cols:
            self._p.writerow([f"{t:.10g}"] + [f"{v:.10g}" for v in row])
        self._pf.flush()

    def probe(self, t: float, values: dict[str, float]) -> None:
        self._q.writerow([f"{t:.10g}"] + [f"{values[c]:.10g}" for c in self.probe_columns])
        self._qf.flush()

    def close(self) -> None:
        self._pf.close()
        self._qf.close()
