"""The ensemble file: what a study runs, read and checked before anything runs.

An ensemble file is TOML::

    [ensemble]
    name = "elcentro-pga-sweep"
    base = "liquefaction-elcentro"      # bundled case or a case file (relative to this file)
    collect = ["settlement_end_m", "report_depths.peak_r_u"]
    keep_runs = false

    [set]                               # the same change in every member
    "time.end" = 30.0

    [grid]                              # every combination of these lists
    "layers.1.particle_diameter" = [0.5e-3, 0.8e-3]

    [zip]                               # lists taken side by side (all one length)
    "layers.1.porosity" = [0.46, 0.44]
    "layers.1.relative_density" = [40.0, 47.0]

    [sample]                            # Monte Carlo: `count` draws with `seed`
    seed = 1
    count = 20
    "layers.1.gamma_ref" = { distribution = "lognormal", median = 1e-3, log_std = 0.3 }

    [ground_motions]                    # each record (folder, glob or list) at each PGA
    files = "motions/*.AT2"
    pga_g = [0.05, 0.1, 0.2]

    [fragility]                         # P(figure >= threshold) against the PGA, per depth
    figure = "report_depths.peak_r_u"
    threshold = 0.95
    labels = "report_depths.depth_m"

Keys of the case are dotted, ``section.key`` (``closures.drag.law``; ``layers.2.porosity``
for an entry of an array of tables, counted from 1): the engine works on any resolved case.
The blocks that are present multiply: members are the product of the grid, the zipped
lists, the samples and the records × PGAs (see
:mod:`twofluid.ensemble.members`).
"""
from __future__ import annotations

import glob
import math
from dataclasses import dataclass, field
from pathlib import Path

from ..casefile.loader import load_case, read_toml
from ..casefile.schema import CaseError, _nearest

__all__ = ["EnsembleSpec", "load_ensemble", "parse_ensemble", "DISTRIBUTIONS"]

# name -> (parameters, check of the parameters: None if valid, else what is valid)
DISTRIBUTIONS = {
    "uniform": (("low", "high"), lambda p: None if p["low"] < p["high"] else "low < high"),
    "normal": (("mean", "std"), lambda p: None if p["std"] > 0 else "std > 0"),
    "lognormal": (("median", "log_std"),
                  lambda p: None if p["median"] > 0 and p["log_std"] > 0 else "median > 0 and log_std > 0"),
    "truncnorm": (("mean", "std", "low", "high"),
                  lambda p: None if p["std"] > 0 and p["low"] < p["high"] else "std > 0 and low < high"),
}
_SECTIONS = {"ensemble", "set", "grid", "zip", "sample", "ground_motions", "fragility"}
_ENSEMBLE_KEYS = {"name", "description", "base", "collect", "keep_runs"}


@dataclass
class EnsembleSpec:
    """A checked ensemble description (what :func:`parse_ensemble` returns)."""

    name: str
    base: dict  # the resolved base case
    source: str  # the ensemble file (or "<ensemble>")
    collect: list[str]
    keep_runs: bool = False
    description: str = ""
    set: dict = field(default_factory=dict)  # dotted key -> value
    grid: dict = field(default_factory=dict)  # dotted key -> list
    zip: dict = field(default_factory=dict)  # dotted key -> list (one length)
    sample: dict = field(default_factory=dict)  # {"seed", "count", "distributions": {key: {...}}}
    motions: dict = field(default_factory=dict)  # {"files": [Path], "pga_g": list | None, "file_key", "pga_key"}
    fragility: dict = field(default_factory=dict)  # {"figure", "threshold", "labels", "intensity"}

    def varied(self) -> dict[str, str]:
        """{dotted key: how it varies} of every key that changes between members."""
        out = {k: "grid" for k in self.grid} | {k: "zip" for k in self.zip}
        out |= {k: "sample" for k in self.sample.get("distributions", {})}
        if self.motions:
            out[self.motions["file_key"]] = "record"
            if self.motions["pga_g"] is not None:
                out[self.motions["pga_key"]] = "pga"
        return out


def _flat(table: dict, prefix: str = "", leaf=lambda v: not isinstance(v, dict)) -> dict:
    """{"a": {"b": 1}} -> {"a.b": 1}: quoted ("a.b" = 1) and nested keys read alike."""
    out = {}
    for k, v in table.items():
        key = f"{prefix}.{k}" if prefix else k
        out.update({key: v} if leaf(v) else _flat(v, key, leaf))
    return out


def _case_key(base: dict, source: str, where: str, key: str) -> None:
    """Check that a dotted key names a value of the base case (CaseError naming what is valid)."""
    from .members import locate

    try:
        locate(base, key)
    except LookupError as exc:
        raise CaseError(source, f"[{where}] {key}", f"{exc} (of the base case)") from None


def _number(source: str, where: str, v, positive: bool = False) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or (positive and v <= 0):
        raise CaseError(source, where, f"must be a finite number{' > 0' if positive else ''}, got {v!r}")
    return float(v)


def _lists(source: str, where: str, table: dict, base: dict) -> dict:
    out = {}
    for key, values in _flat(table).items():
        _case_key(base, source, where, key)
        if not isinstance(values, list) or not values:
            raise CaseError(source, f"[{where}] {key}", f"must be a non-empty list of values, got {values!r}")
        out[key] = values
    return out


def _sample(source: str, table: dict, base: dict) -> dict:
    seed, count = table.get("seed"), table.get("count")
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise CaseError(source, "[sample] seed", f"must be an integer >= 0 (the same seed gives the same "
                        f"samples), got {seed!r}")
    if isinstance(count, bool) or not isinstance(count, int) or not 1 <= count <= MAX_MEMBERS:
        raise CaseError(source, "[sample] count", f"must be an integer in [1, {MAX_MEMBERS}], got {count!r}")
    dists = _flat({k: v for k, v in table.items() if k not in ("seed", "count")},
                  leaf=lambda v: not isinstance(v, dict) or "distribution" in v)
    if not dists:
        raise CaseError(source, "[sample]", "no distributions; give e.g. \"layers.1.relative_density\" = "
                        "{ distribution = \"normal\", mean = 47.0, std = 5.0 }")
    out = {}
    for key, d in dists.items():
        where = f"[sample] {key}"
        _case_key(base, source, "sample", key)
        if not isinstance(d, dict) or d.get("distribution") not in DISTRIBUTIONS:
            raise CaseError(source, where, f"must be a table with distribution = one of "
                            f"{', '.join(DISTRIBUTIONS)}, got {d!r}")
        names, check = DISTRIBUTIONS[d["distribution"]]
        extra = set(d) - set(names) - {"distribution"}
        if extra or set(names) - set(d):
            raise CaseError(source, where, f"a {d['distribution']} distribution takes exactly "
                            f"{', '.join(names)}; got {', '.join(sorted(set(d) - {'distribution'}))}")
        p = {n: _number(source, f"{where} {n}", d[n]) for n in names}
        bad = check(p)
        if bad:
            raise CaseError(source, where, f"invalid {d['distribution']} parameters {p}; valid: {bad}")
        out[key] = {"distribution": d["distribution"], **p}
    return {"seed": seed, "count": count, "distributions": out}


def _record_files(source: str, spec, folder: Path) -> list[Path]:
    """The records of ``files``: a folder (its .AT2 and .csv files), a glob, or a list of paths."""
    items = spec if isinstance(spec, list) else [spec]
    if not items or not all(isinstance(s, str) and s for s in items):
        raise CaseError(source, "[ground_motions] files", f"must be a folder, a glob or a list of files, got {spec!r}")
    files: list[Path] = []
    for s in items:
        p = Path(s) if Path(s).is_absolute() else folder / s
        if p.is_dir():
            found = sorted(q for q in p.iterdir() if q.suffix.lower() in (".at2", ".csv"))
        elif any(c in s for c in "*?["):
            found = sorted(Path(q) for q in glob.glob(str(p)))
        else:
            found = [p] if p.is_file() else []
        if not found:
            raise CaseError(source, "[ground_motions] files", f"{s!r} matches no record file "
                            f"(looked in {p}); valid: a folder of .AT2/.csv files, a glob or file paths")
        files += [q.resolve() for q in found]
    return files


def _motions(source: str, table: dict, base: dict, folder: Path) -> dict:
    extra = set(table) - {"files", "pga_g", "file_key", "pga_key"}
    if extra:
        raise CaseError(source, f"[ground_motions] {sorted(extra)[0]}", "unknown key; " + _nearest(
            sorted(extra)[0], ("files", "pga_g", "file_key", "pga_key"), "keys"))
    file_key = table.get("file_key", "ground_motion.file")
    pga_key = table.get("pga_key", "ground_motion.pga_g")
    _case_key(base, source, "ground_motions", file_key)
    pga = table.get("pga_g")
    if pga is not None:
        _case_key(base, source, "ground_motions", pga_key)
        if not isinstance(pga, list) or not pga:
            raise CaseError(source, "[ground_motions] pga_g", f"must be a non-empty list of peak accelerations "
                            f"[g], got {pga!r}")
        pga = [_number(source, "[ground_motions] pga_g", v, positive=True) for v in pga]
    files = _record_files(source, table.get("files"), folder)
    return {"files": files, "pga_g": pga, "file_key": file_key, "pga_key": pga_key}


def _fragility(source: str, table: dict, spec: EnsembleSpec) -> dict:
    extra = set(table) - {"figure", "threshold", "labels", "intensity"}
    if extra:
        raise CaseError(source, f"[fragility] {sorted(extra)[0]}", "unknown key; " + _nearest(
            sorted(extra)[0], ("figure", "threshold", "labels", "intensity"), "keys"))
    fig = table.get("figure")
    if fig not in spec.collect:
        raise CaseError(source, "[fragility] figure", f"{fig!r} must be one of the collected figures "
                        f"([ensemble] collect: {', '.join(spec.collect)})")
    labels = table.get("labels", "")
    if labels and labels not in spec.collect:
        raise CaseError(source, "[fragility] labels", f"{labels!r} must be one of the collected figures")
    intensity = table.get("intensity", spec.motions.get("pga_key", ""))
    if intensity not in spec.varied():
        raise CaseError(source, "[fragility] intensity", f"{intensity!r} must be a varied key "
                        f"({', '.join(spec.varied()) or 'none varies'})")
    thr = _number(source, "[fragility] threshold", table.get("threshold"))
    return {"figure": fig, "threshold": thr, "labels": labels, "intensity": intensity}


def _check_set(spec: EnsembleSpec) -> None:
    """A bad ``[set]`` would fail every member: it is an error of the ensemble file."""
    from ..casefile.schema import revalidate
    from .members import apply

    try:
        revalidate(apply(spec.base, spec.set), spec.base.get("_source", spec.source))
    except CaseError as exc:
        raise CaseError(spec.source, "[set]", f"makes the base case invalid: {exc}") from None
    except (TypeError, ValueError) as exc:
        raise CaseError(spec.source, "[set]", f"makes the base case invalid: {exc}") from None


#: the most members an ensemble may have (counted before any member is made: each holds its case)
MAX_MEMBERS = 100_000


def member_count(spec: EnsembleSpec) -> int:
    """The number of members: the product of the blocks' sizes, computed without expanding them.

    >>> member_count(EnsembleSpec("e", {}, "e.toml", ["x"], grid={"a": [1, 2, 3], "b": [1, 2]}))
    6
    """
    n = math.prod(len(v) for v in spec.grid.values())
    if spec.zip:
        n *= len(next(iter(spec.zip.values())))
    if spec.sample:
        n *= spec.sample["count"]
    if spec.motions:
        n *= len(spec.motions["files"]) * (len(spec.motions["pga_g"]) if spec.motions["pga_g"] else 1)
    return n


def _check_count(spec: EnsembleSpec) -> None:
    n = member_count(spec)
    if n > MAX_MEMBERS:
        sizes = [f"[grid] {' × '.join(str(len(v)) for v in spec.grid.values())}" if spec.grid else "",
                 f"[zip] {len(next(iter(spec.zip.values())))}" if spec.zip else "",
                 f"[sample] {spec.sample['count']}" if spec.sample else "",
                 f"[ground_motions] {len(spec.motions['files'])} records × {len(spec.motions['pga_g'] or [0])} "
                 "PGAs" if spec.motions else ""]
        raise CaseError(spec.source, "[grid]" if spec.grid else "[ensemble]",
                        f"gives {n:.3g} members ({' × '.join(x for x in sizes if x)}), more than the "
                        f"{MAX_MEMBERS} an ensemble may have; split it into several ensembles")


def parse_ensemble(doc: dict, source: str = "<ensemble>", folder: Path | None = None) -> EnsembleSpec:
    """Check an ensemble document (the parsed TOML); return the :class:`EnsembleSpec`.

    Raises :class:`~twofluid.CaseError` naming ``source``, the key and what is valid.

    >>> spec = parse_ensemble({"ensemble": {"base": "settling-illite", "collect": ["porosity_range"]},
    ...                        "grid": {"materials.particle_diameter": [6e-5, 7e-5]}})
    >>> spec.varied()
    {'materials.particle_diameter': 'grid'}
    >>> parse_ensemble({"ensemble": {"base": "settling-illite", "collect": []}})
    Traceback (most recent call last):
    ...
    twofluid.casefile.schema.CaseError: <ensemble>: [ensemble] collect: must be a non-empty list of dotted paths into summary.json, e.g. ["settlement_end_m"], got []
    """
    folder = folder or Path.cwd()
    for s in doc:
        if s not in _SECTIONS:
            raise CaseError(source, f"[{s}]", "unknown section; " + _nearest(s, _SECTIONS, "sections"))
    ens = doc.get("ensemble", {})
    for k in ens:
        if k not in _ENSEMBLE_KEYS:
            raise CaseError(source, f"[ensemble] {k}", "unknown key; " + _nearest(k, _ENSEMBLE_KEYS, "keys"))
    base_name = ens.get("base")
    if not isinstance(base_name, str) or not base_name:
        raise CaseError(source, "[ensemble] base", "missing: a bundled case name or a case file path")
    local = folder / base_name
    base = load_case(str(local) if local.is_file() else base_name)
    collect = ens.get("collect")
    if not isinstance(collect, list) or not collect or not all(isinstance(c, str) and c for c in collect):
        raise CaseError(source, "[ensemble] collect", "must be a non-empty list of dotted paths into "
                        f"summary.json, e.g. [\"settlement_end_m\"], got {collect!r}")
    keep = ens.get("keep_runs", False)
    if not isinstance(keep, bool):
        raise CaseError(source, "[ensemble] keep_runs", f"must be true or false, got {keep!r}")
    spec = EnsembleSpec(name=str(ens.get("name", Path(source).stem)), base=base, source=source,
                        collect=list(collect), keep_runs=keep, description=str(ens.get("description", "")))
    spec.set = _flat(doc.get("set", {}))
    for key in spec.set:
        _case_key(base, source, "set", key)
    _check_set(spec)
    spec.grid = _lists(source, "grid", doc.get("grid", {}), base)
    spec.zip = _lists(source, "zip", doc.get("zip", {}), base)
    if len({len(v) for v in spec.zip.values()}) > 1:
        lengths = ", ".join(f"{k}: {len(v)}" for k, v in spec.zip.items())
        raise CaseError(source, "[zip]", f"the lists must have one length; got {lengths}")
    if "sample" in doc:
        spec.sample = _sample(source, doc["sample"], base)
    if "ground_motions" in doc:
        spec.motions = _motions(source, doc["ground_motions"], base, folder)
    keys = [*spec.grid, *spec.zip, *spec.sample.get("distributions", {}),
            *([spec.motions["file_key"]] if spec.motions else []),
            *([spec.motions["pga_key"]] if spec.motions.get("pga_g") else [])]
    twice = sorted({k for k in keys if keys.count(k) > 1} | (set(keys) & set(spec.set)))
    if twice:
        raise CaseError(source, twice[0], "is given in more than one of [set], [grid], [zip], [sample], "
                        "[ground_motions]; give each key once")
    if not keys:
        raise CaseError(source, "[grid]", "nothing varies: give [grid], [zip], [sample] or [ground_motions]")
    _check_count(spec)
    if "fragility" in doc:
        spec.fragility = _fragility(source, doc["fragility"], spec)
    return spec


def load_ensemble(path: str | Path) -> EnsembleSpec:
    """Read and check an ensemble file (a path, or the name of a bundled example).

    >>> load_ensemble("elcentro-pga-sweep").varied()
    {'layers.1.relative_density': 'sample', 'ground_motion.file': 'record', 'ground_motion.pga_g': 'pga'}
    """
    from importlib import resources

    p = Path(path)
    if not p.is_file():
        bundled = resources.files("twofluid") / "data" / "ensembles" / f"{path}.toml"
        if not bundled.is_file():
            raise CaseError(str(path), "file", "is neither an ensemble file nor a bundled example ensemble")
        p = Path(str(bundled))
    source = str(p)
    doc = read_toml(p, source, kind="an ensemble file")
    return parse_ensemble(doc, source, p.parent)
