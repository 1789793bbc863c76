"""Members of an ensemble: the parameter sets, their resolved cases and their hashes.

The blocks of an ensemble multiply: every grid combination × every zipped position ×
every sample × every record at every PGA (a block that is absent counts once). Each
member's case is the base case with ``[set]`` and the member's parameters applied,
then checked again through the case schema: a combination the schema rejects becomes
a member that has failed before running, with the schema's one-line reason.
"""
from __future__ import annotations

import copy
import hashlib
import itertools
import json
from dataclasses import dataclass

import numpy as np
from scipy import stats

from ..casefile.case import is_group, sections
from ..casefile.schema import CaseError, revalidate

__all__ = ["Member", "members", "samples", "case_hash", "apply", "locate"]


@dataclass
class Member:
    """One member: its index, its parameters (dotted key -> value), its case and hash."""

    index: int
    params: dict
    case: dict | None  # the resolved case (None when it is invalid)
    hash: str  # sha256 of the resolved case ("" when invalid)
    error: str = ""  # why the case is invalid


def case_hash(case: dict) -> str:
    """sha256 of the resolved case as stable JSON (sorted keys; the ``_`` entries left out).

    The sections are hashed by their dotted names (:func:`~twofluid.casefile.case.sections`), so
    a nested case hashes as the flat case of version 0.1.0 did: an ensemble started then resumes.

    >>> case_hash({"a": {"x": 1.0}, "_source": "f.toml"}) == case_hash({"a": {"x": 1.0}})
    True
    >>> case_hash({"a": {"x": 1.0}}) == case_hash({"a": {"x": 1.0 + 1e-15}})
    False
    >>> case_hash({"closures": {"drag": {"law": "ergun"}}}) == case_hash({"closures.drag": {"law": "ergun"}})
    True
    """
    doc = {k: v for k, v in sections(case).items() if not k.startswith("_")}
    text = json.dumps(doc, sort_keys=True, separators=(",", ":"), allow_nan=False)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def _as_base_type(old, value):
    """A drawn float for an integer key is rounded (``mesh.elements``); numpy scalars become Python."""
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(old, int) and not isinstance(old, bool) and isinstance(value, float) and value.is_integer():
        return int(value)
    return value


def locate(case: dict, key: str) -> tuple:
    """(container, name or index) of the dotted ``key`` in a resolved case; LookupError saying
    what is valid. The path follows the case's nesting (``closures.drag.law``:
    ``case["closures"]["drag"]["law"]``); an entry of an array of tables is its 1-based position
    (``layers.2.relative_density``: the second layer from the top).

    >>> case = {"closures": {"drag": {"law": "ergun"}}, "layers": [{"porosity": 0.4}, {"porosity": 0.38}]}
    >>> locate(case, "closures.drag.law")
    ({'law': 'ergun'}, 'law')
    >>> locate(case, "layers.2.porosity")
    ({'porosity': 0.38}, 'porosity')
    >>> locate(case, "layers.3.porosity")
    Traceback (most recent call last):
    ...
    LookupError: [[layers]] has 2 entries: give layers.1 .. layers.2
    >>> locate(case, "closures.dragg.law")
    Traceback (most recent call last):
    ...
    LookupError: no section [closures.dragg] in the case; valid sections: closures.drag, layers
    """
    parts = key.split(".")
    node, where, in_section = case, "", False
    for j, p in enumerate(parts):
        if isinstance(node, list):
            if not (p.isdigit() and 1 <= int(p) <= len(node)):
                raise LookupError(f"[[{where}]] has {len(node)} entries: give {where}.1 .. {where}.{len(node)}")
            p = int(p) - 1
        elif not isinstance(node, dict) or not dict.__contains__(node, p):
            if not in_section:  # the case or a table of sections (closures): the section is unknown
                valid = ", ".join(s for s in sections(case) if not s.startswith("_"))
                missing = ".".join(parts[:max(j + 1, len(parts) - 1)])
                raise LookupError(f"no section [{missing}] in the case; valid sections: {valid}")
            valid = ", ".join(node) if isinstance(node, dict) else "none (it is a value)"
            raise LookupError(f"no key {p!r} in [{where}]; valid: {valid}")
        if j == len(parts) - 1:
            if in_section:
                return node, p
            break
        node = dict.__getitem__(node, p) if isinstance(node, dict) else node[p]
        where = f"{where}.{parts[j]}" if where else parts[j]
        in_section = in_section or isinstance(node, list) or not is_group(node)
    raise LookupError(f"{key!r} names a section, not a key")


def apply(case: dict, changes: dict) -> dict:
    """A copy of ``case`` with each dotted key (:func:`locate`) set to its value (not re-checked).

    >>> apply({"time": {"end": 1.0}}, {"time.end": 2.0})
    {'time': {'end': 2.0}}
    """
    out = copy.deepcopy(case)
    for key, value in changes.items():
        node, name = locate(out, key)
        node[name] = _as_base_type(node[name], value)
    return out


def samples(sample: dict) -> dict[str, np.ndarray]:
    """{dotted key: ``count`` draws} of a ``[sample]`` block; the same seed gives the same draws.

    The keys draw in the order given, from one ``numpy.random.default_rng(seed)``.

    >>> s = {"seed": 3, "count": 4, "distributions": {"x": {"distribution": "uniform", "low": 1.0, "high": 2.0}}}
    >>> a, b = samples(s)["x"], samples(s)["x"]
    >>> bool((a == b).all() and (a >= 1).all() and (a <= 2).all())
    True
    """
    rng = np.random.default_rng(sample["seed"])
    out = {}
    for key, d in sample["distributions"].items():
        kind = d["distribution"]
        if kind == "uniform":
            dist = stats.uniform(loc=d["low"], scale=d["high"] - d["low"])
        elif kind == "normal":
            dist = stats.norm(loc=d["mean"], scale=d["std"])
        elif kind == "lognormal":  # ln X ~ N(ln median, log_std)
            dist = stats.lognorm(s=d["log_std"], scale=d["median"])
        else:
            a, b = (d["low"] - d["mean"]) / d["std"], (d["high"] - d["mean"]) / d["std"]
            dist = stats.truncnorm(a, b, loc=d["mean"], scale=d["std"])
        out[key] = dist.rvs(size=sample["count"], random_state=rng)
    return out


def _blocks(spec) -> list[list[dict]]:
    """Each block as its list of {dotted key: value} choices (the blocks multiply)."""
    blocks = []
    if spec.grid:
        keys = list(spec.grid)
        blocks.append([dict(zip(keys, combo)) for combo in itertools.product(*spec.grid.values())])
    if spec.zip:
        keys = list(spec.zip)
        blocks.append([dict(zip(keys, row)) for row in zip(*spec.zip.values())])
    if spec.sample:
        drawn = samples(spec.sample)
        blocks.append([{k: float(v[i]) for k, v in drawn.items()} for i in range(spec.sample["count"])])
    if spec.motions:
        m = spec.motions
        pgas = m["pga_g"] if m["pga_g"] is not None else [None]
        blocks.append([{m["file_key"]: str(f), **({m["pga_key"]: p} if p is not None else {})}
                       for f in m["files"] for p in pgas])
    return blocks


def members(spec) -> list[Member]:
    """Every member of ``spec`` with its resolved, re-checked case (invalid ones carry the reason)."""
    base = apply(spec.base, spec.set)
    if not spec.keep_runs:
        base["output"]["plots"] = False  # nobody looks at a discarded member's figures
    out = []
    for i, combo in enumerate(itertools.product(*_blocks(spec))):
        params = {k: v for block in combo for k, v in block.items()}
        try:
            case = revalidate(apply(base, params), base.get("_source", spec.source))
            out.append(Member(i, params, case, case_hash(case)))
        except CaseError as exc:
            out.append(Member(i, params, None, "", f"invalid case: {exc}"))
        except (TypeError, ValueError) as exc:  # e.g. a list given for a number: the schema's check
            out.append(Member(i, params, None, "", f"invalid case: {type(exc).__name__}: {exc}"))
    return out
