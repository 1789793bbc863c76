"""Fuzz every bundled case: each mutation is either one clean line or a run with a status.

Every key of every section of each case's model (given in the case file or not) is set to
values of the wrong type, the wrong sign, 0, 1e308, 1e-300, 1e±30, NaN, ±inf, empty and odd lists;
each key and each section is also removed, and an unknown key added. Each mutated case is
validated as ``twofluid run`` validates it: it must either be refused with a
:class:`CaseError` of one line, or be accepted. A deterministic sample of the accepted ones
(the extreme values first) is then run for one time step through ``run_case``: it must
complete or fail with a status and a ``summary.json``, never raise anything else.

``TWOFLUID_FUZZ_FULL=1`` runs every accepted mutation instead of the sample and prints the
counts (the numbers quoted in the reliability notes).
"""
from __future__ import annotations

import copy
import json
import math
import os
import signal
import tomllib
import warnings
from collections import Counter

import pytest

from twofluid.casefile.loader import bundled_cases, case_text
from twofluid.casefile.schema import ARRAYS, FLOATS, CaseError, _model_schema, validate
from twofluid.runners.common import run_case

FULL = os.environ.get("TWOFLUID_FUZZ_FULL") == "1"
RUNS_PER_CASE = 3  # sampled runs per bundled case (CI); all with TWOFLUID_FUZZ_FULL=1
WALL_LIMIT = 20  # [s] per run: then it is stopped as by Ctrl-C (a status too: "interrupted")

NAN, INF = math.nan, math.inf
VALUES = {
    float: [-1.0, 0.0, 1e308, 1e-300, 1e30, 1e-30, NAN, INF, -INF, "text", True, [1.0]],
    int: [-1, 0, 10 ** 9, 1.5, "3", True],
    str: ["", "nonsense", 5, "../../escaped"],
    bool: ["yes", 1],
    FLOATS: [[], [NAN], [1e308], [-1.0], [1e-300], [1e30], "x", [[1.0]], [INF], [0.0, 0.0, 0.0]],
}
EXTREME = {repr(v) for v in (1e30, 1e-30, -1.0, 0.0, -1, 0, 10 ** 9, [1e30], [-1.0], [0.0, 0.0, 0.0])}
DELETE = object()


def _doc(name: str) -> dict:
    return tomllib.loads(case_text(name))


def _table(doc: dict, where: str, create: bool):
    node = doc
    for part in where.split("."):
        if part not in node:
            if not create:
                return None
            node[part] = {}
        node = node[part]
    return node


def _mutate(table, key: str, value) -> bool:
    """Set ``key`` to ``value``, or delete it (DELETE); False when there is nothing to delete."""
    if value is DELETE:
        if table is None or key not in table:
            return False
        del table[key]
    else:
        table[key] = value
    return True


def _shown(value) -> str:
    return "<deleted>" if value is DELETE else repr(value)


def mutations(name: str):
    """(label, mutated document) for one bundled case."""
    base = _doc(name)
    model = base["case"].get("model", "two_fluid_1d")
    schema = _model_schema(model)  # imports the model's schema module (which registers its arrays)
    yield from _array_mutations(name, base, model)
    for where, keys in schema.items():
        for key in keys:
            for value in [*VALUES[key.type], DELETE]:
                doc = copy.deepcopy(base)
                if _mutate(_table(doc, where, create=value is not DELETE), key.name, value):
                    yield f"{name}: [{where}] {key.name} = {_shown(value)}", doc
        doc = copy.deepcopy(base)
        table = _table(doc, where, create=True)
        table["no_such_key"] = 1.0
        yield f"{name}: [{where}] no_such_key = 1.0", doc
        parts = where.split(".")
        doc = copy.deepcopy(base)
        if where in ARRAYS.get(model, {}):
            continue
        parent = _table(doc, ".".join(parts[:-1]), create=False) if len(parts) > 1 else doc
        if parent is not None and parts[-1] in parent:
            del parent[parts[-1]]
            yield f"{name}: [{where}] <section deleted>", doc


def _array_mutations(name: str, base: dict, model: str):
    """The same for arrays of tables ([[layers]]): each key of the first entry, and no entry at all."""
    for array, keys in ARRAYS.get(model, {}).items():
        if not base.get(array):
            continue
        for key in keys:
            for value in [*VALUES[key.type], DELETE]:
                doc = copy.deepcopy(base)
                if _mutate(doc[array][0], key.name, value):
                    yield f"{name}: [[{array}]] 1 {key.name} = {_shown(value)}", doc
        doc = copy.deepcopy(base)
        doc[array] = []
        yield f"{name}: [[{array}]] <no entry>", doc


def _short(case: dict) -> dict:
    """One time step of the case (the mutation itself was validated as given)."""
    case = copy.deepcopy(case)
    t = case["time"]
    t["end"] = t["step"] = min(t["end"], t["step"])
    case["output"]["times"] = []
    case["output"]["plots"] = False
    if "reconsolidation" in case:
        case["reconsolidation"]["step"] = max(case["reconsolidation"]["step"], t["step"])
    if "shear_wave" in case:
        case["shear_wave"]["step"] = min(case["shear_wave"]["step"], t["step"])
    m = case.get("mesh", {})
    if m.get("kind") == "rectangle":  # 2D: a coarser mesh of the same geometry (cut, heights)
        m["nx"], m["ny"] = min(m["nx"], 10), min(m["ny"], 16)
    return case


def _validate(doc: dict, source: str):
    """("refused", message) or ("accepted", case): anything else propagates (a test failure)."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return "accepted", validate(doc, source, name="fuzz")
    except CaseError as exc:
        return "refused", str(exc)


def _stop(signum, frame):
    raise KeyboardInterrupt  # the wall limit: the run must stop as on Ctrl-C, with a status


def fuzz_case(name: str, tmp_path, runs: int | None) -> Counter:
    outcomes: Counter = Counter()
    accepted = []
    for label, doc in mutations(name):
        kind, value = _validate(doc, f"{name} (bundled)")
        if kind == "refused":
            assert "\n" not in value and value.startswith(f"{name} (bundled): "), (label, value)
            outcomes["refused with one line"] += 1
        else:
            accepted.append((label, value))
            outcomes["accepted"] += 1
    extreme = [a for a in accepted if a[0].rsplit(" = ", 1)[-1] in EXTREME]
    rest = [a for a in accepted if a not in extreme]
    sample = (extreme + rest) if runs is None else (extreme + rest)[:runs]
    for i, (label, case) in enumerate(sample):
        case["_source"] = f"{name} (bundled)"
        old = signal.signal(signal.SIGALRM, _stop)
        signal.alarm(WALL_LIMIT)
        try:
            res = run_case(_short(case), tmp_path / f"{name}-{i}")
        except CaseError as exc:  # the one-step version of the case is refused: also a clean line
            assert "\n" not in str(exc), (label, str(exc))
            outcomes["run refused with one line"] += 1
            continue
        finally:
            signal.alarm(0)
            signal.signal(signal.SIGALRM, old)
        assert res.status in ("completed", "failed", "interrupted"), (label, res.status)
        if res.status == "interrupted":  # only by the wall limit
            assert "Ctrl-C" in res.summary["reason"], (label, res.summary["reason"])
        summary = json.loads((res.out_dir / "summary.json").read_text())
        assert summary["status"] == res.status, label
        outcomes[f"run {res.status}"] += 1
    return outcomes


@pytest.mark.parametrize("name", sorted(bundled_cases()))
def test_every_mutation_is_one_clean_line_or_a_run_with_a_status(name, tmp_path):
    out = fuzz_case(name, tmp_path, None if FULL else RUNS_PER_CASE)
    assert out["refused with one line"] > 0
    if FULL:
        print(f"\n{name}: {sum(v for k, v in out.items() if k in ('refused with one line', 'accepted'))} "
              f"mutations: {dict(out)}")
