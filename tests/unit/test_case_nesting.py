"""The resolved case nests as its TOML file: ``case["boundary"]["bottom"]``.

The flat dotted section keys that ``load_case`` returned until 0.1.0 (``case["boundary.bottom"]``)
still read, test and write the nested section for one release, each access with one
``FlatKeyWarning`` (a ``DeprecationWarning``) that names the nested spelling; the package itself
never uses them (pyproject.toml turns the warning into an error for the whole suite, and
``test_the_package_source_has_no_flat_section_lookups`` checks the code that only runs in workers).
"""
from __future__ import annotations

import copy
import hashlib
import json
import pickle
import re
import tomllib
import warnings
from pathlib import Path

import pytest

import twofluid
from twofluid.casefile.case import Case, FlatKeyWarning, nest, section, sections
from twofluid.casefile.loader import bundled_cases, case_text, load_case
from twofluid.casefile.schema import CaseError, effective, revalidate
from twofluid.ensemble.members import apply, case_hash, locate
from twofluid.io.results import write_resolved_case

SRC = Path(twofluid.__file__).resolve().parent
CASES = sorted(bundled_cases())


def _flat_accesses(action):
    """The FlatKeyWarnings that ``action()`` raises (every one recorded), and its result."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = action()
    return [w for w in caught if issubclass(w.category, FlatKeyWarning)], result


@pytest.mark.parametrize("name", CASES)
def test_load_case_returns_the_toml_nesting(name):
    case = load_case(name)
    assert isinstance(case, Case) and isinstance(case, dict)
    text = tomllib.loads(case_text(name))
    assert not [k for k in case if "." in k]  # no flat dotted section name at the top
    for where, table in text.items():  # every section of the file sits where TOML puts it
        if isinstance(table, dict):
            for key, value in sections({where: table}).items():
                assert section(case, key) is not None, key
                for k, v in value.items():
                    assert section(case, key)[k] == v, (key, k)


@pytest.mark.parametrize("name", [n for n in CASES if 'model = "liquefaction_1d"' not in case_text(n)
                                  and 'model = "immersed_avalanche"' not in case_text(n)])
def test_resolved_case_round_trip_is_nested_toml(name, tmp_path):
    """case.resolved.toml is written with TOML's nested tables ([closures.drag], never a quoted
    ["closures.drag"]) and loads back to the same resolved case."""
    case = load_case(name)
    path = tmp_path / "case.resolved.toml"
    write_resolved_case(path, case)
    text = path.read_text(encoding="utf-8")
    assert '["' not in text and "[closures.drag]" in text and re.search(r"^\[boundary\.\w+\]$", text, re.M)
    doc = tomllib.loads(text)
    assert set(doc["closures"]) >= {"drag"} and "closures.drag" not in doc
    assert doc == {k: v for k, v in effective(case).items() if not k.startswith("_")}
    again = load_case(path)
    assert {k: v for k, v in again.items() if k != "_source"} == {k: v for k, v in case.items() if k != "_source"}


def test_liquefaction_resolved_case_is_nested(tmp_path):
    case = load_case("liquefaction-elcentro")
    path = tmp_path / "case.resolved.toml"
    write_resolved_case(path, case)
    doc = tomllib.loads(path.read_text(encoding="utf-8"))
    assert doc["closures"]["drag"] == effective(case)["closures"]["drag"]
    assert doc["closures"]["drag"]["law"] == case["closures"]["drag"]["law"]
    assert len(doc["layers"]) == len(case["layers"])


@pytest.mark.parametrize("name", [n for n in CASES if 'model = "liquefaction_1d"' in case_text(n)])
def test_liquefaction_resolved_case_reloads_silently(name, tmp_path):
    """A liquefaction run's case.resolved.toml, loaded again, gives the same case and none of the
    warnings of keys that have no effect (a layer's gamma_ref under the hysteretic model, a crust's
    relative_density, the flow keys on level ground): the keys it writes are those that act."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        case = load_case(name)
    path = tmp_path / "case.resolved.toml"
    write_resolved_case(path, case)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        again = load_case(path)
    thesis = 'model = "thesis"' in case_text(name)
    messages = [str(w.message) for w in caught if not (thesis and '"thesis"' in str(w.message))]
    assert messages == []
    assert {k: v for k, v in again.items() if k != "_source"} == {k: v for k, v in case.items() if k != "_source"}


def test_resolved_case_keeps_a_crusts_relative_density(tmp_path):
    """Under the hysteretic model a crust's relative_density sets its friction angle and backbone: the
    resolved case keeps it, so that the case loaded again runs the same crust."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        case = load_case("liquefaction-layered-site")
    crust = next(la for la in case["layers"] if la["name"] == "crust")
    crust["relative_density"] = 85.0
    path = tmp_path / "case.resolved.toml"
    write_resolved_case(path, case)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        again = load_case(path)
    assert next(la for la in again["layers"] if la["name"] == "crust")["relative_density"] == 85.0


def test_nested_and_flat_input_give_the_same_case():
    nested = load_case("fluidized-bed-step")
    flat = {k: v for k, v in sections(nested).items()}  # the dict of version 0.1.0
    assert "closures.drag" in flat and "boundary.bottom" in flat
    warned, again = _flat_accesses(lambda: revalidate(flat, "old.toml"))
    assert again == nested
    assert len(warned) == 1  # one warning per case given, naming the nested form
    assert warned[0].filename == __file__  # the line that gave the case (shown by default in a script)
    assert 'case["closures"]["drag"]' in str(warned[0].message) and "[closures.drag]" in str(warned[0].message)
    both = copy.deepcopy(flat)
    both["closures"] = {"drag": nested["closures"]["drag"]}
    with pytest.raises(CaseError, match=r"\[closures.drag\]: given twice"):
        _flat_accesses(lambda: revalidate(both, "both.toml"))


def test_flat_access_reads_tests_and_writes_the_nested_section_with_one_warning_each():
    case = load_case("fluidized-bed-step")
    bottom = case["boundary"]["bottom"]
    checks = [
        (lambda: case["boundary.bottom"], bottom),
        (lambda: "boundary.bottom" in case, True),
        (lambda: "boundary.left" in case, False),
        (lambda: case.get("boundary.bottom"), bottom),
        (lambda: case.get("boundary.left", 7), 7),
        (lambda: case["closures.drag"]["law"], case["closures"]["drag"]["law"]),
    ]
    for action, expected in checks:
        warned, got = _flat_accesses(action)
        assert got == expected
        assert len(warned) == 1
        message = str(warned[0].message)
        assert "deprecated" in message and "case[" in message
        assert re.search(r'use case\["(boundary|closures)"\]\["\w+"\]', message)
        assert warned[0].filename == __file__  # the user's line, not the package's
    warned, _ = _flat_accesses(lambda: case["closures.drag"].update(law="ergun"))  # write through a read
    assert len(warned) == 1 and case["closures"]["drag"]["law"] == "ergun"
    new = {**bottom, "kind": "wall"}

    def assign():
        case["boundary.bottom"] = new

    warned, _ = _flat_accesses(assign)
    assert len(warned) == 1 and 'case["boundary"]["bottom"]' in str(warned[0].message)
    assert case["boundary"]["bottom"] is new and "boundary.bottom" not in dict.keys(case)
    warned, _ = _flat_accesses(lambda: case.update({"closures.drag": {"law": "wen_yu"}}, time=case["time"]))
    assert len(warned) == 1 and warned[0].filename == __file__ and case["closures"]["drag"] == {"law": "wen_yu"}
    with pytest.raises(KeyError):
        _flat_accesses(lambda: case["boundary.left"])
    warned, popped = _flat_accesses(lambda: case.pop("boundary.top"))
    assert len(warned) == 1 and "top" not in case["boundary"] and popped["kind"] == "outlet"


def test_nested_access_raises_no_warning():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        case = load_case("settling-illite")
        case["closures"]["drag"]["law"], case.get("boundary"), "boundary" in case
        case["time"]["step"] *= 0.5
        revalidate(case, "x")


def test_a_flat_access_is_shown_by_default_in_a_script():
    """Python shows a DeprecationWarning by default where __main__ triggers it: a user's script."""
    import os
    import subprocess
    import sys

    code = ("import twofluid\nc = twofluid.load_case('settling-illite')\nc['closures.drag']\n"
            "c['closures.drag']\n")  # the second access is on another line: two lines of warning
    env = {k: v for k, v in os.environ.items() if k != "PYTHONWARNINGS"}  # Python's default filters
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120, env=env)
    assert p.returncode == 0, p.stderr
    lines = [ln for ln in p.stderr.splitlines() if "FlatKeyWarning" in ln]
    assert len(lines) == 2 and 'use case["closures"]["drag"]' in lines[0]


def test_a_case_survives_copy_pickle_and_json_as_a_nested_case():
    case = load_case("slis-step-change")
    for other in (copy.deepcopy(case), pickle.loads(pickle.dumps(case)), copy.copy(case)):
        assert type(other) is Case and other == case
        warned, got = _flat_accesses(lambda: other["boundary.bottom"])
        assert got == case["boundary"]["bottom"] and len(warned) == 1
    assert json.loads(json.dumps(case)) == case


def test_member_hashes_are_those_of_the_flat_case():
    """The sha256 of a member's case is computed on the dotted section names (the flat form of
    0.1.0), so the hashes in an older members.csv still match and a resumed ensemble reuses them."""
    case = load_case("fluidized-bed-step")
    flat = {"case": case["case"], "materials": case["materials"], "time": case["time"], "output": case["output"],
            "mesh": case["mesh"], "initial": case["initial"], "numerics": case["numerics"],
            **{f"closures.{k}": v for k, v in case["closures"].items()},
            **{f"boundary.{k}": v for k, v in case["boundary"].items()}}
    old = hashlib.sha256(json.dumps(flat, sort_keys=True, separators=(",", ":")).encode()).hexdigest()
    assert case_hash(case) == old
    changed = apply(case, {"closures.drag.law": "ergun"})
    assert case_hash(changed) != old and changed["closures"]["drag"]["law"] == "ergun"
    assert case["closures"]["drag"]["law"] != "ergun"  # apply copies


def test_ensemble_paths_walk_the_nesting():
    case = load_case("liquefaction-elcentro")
    node, name = locate(case, "closures.drag.slip_saturation")
    assert node is case["closures"]["drag"] and name == "slip_saturation"
    node, name = locate(case, "layers.1.relative_density")
    assert node is case["layers"][0]
    with pytest.raises(LookupError, match=r"no section \[closures.dragg\].*valid sections: .*closures.drag"):
        locate(case, "closures.dragg.law")
    with pytest.raises(LookupError, match="names a section"):
        locate(case, "closures.drag")
    with pytest.raises(LookupError, match=r"no key 'lw' in \[closures.drag\]"):
        locate(case, "closures.drag.lw")


def test_nest_and_sections_are_inverse():
    case = load_case("viscometer")
    assert nest(sections(case)) == case
    assert sections(nest(sections(case))) == sections(case)


_FLAT = re.compile(r"""(?:\b[a-z_][a-z_0-9]*\[f?["'](?:closures|boundary)\.|\.(?:get|pop|setdefault)\(f?["'](?:closures|"""
                   r"""boundary)\.|["'](?:closures|boundary)\.\w+["']\s+(?:not\s+)?in\s)""")


def test_the_package_source_has_no_flat_section_lookups():
    """The ensemble's Dask workers run in other processes, where the suite's error filter does not
    reach: no module looks a section up by its flat name (SCHEMA["closures.drag"], the schema's
    own names, is not a case; casefile/case.py, which answers the flat names, is left out)."""
    found = [f"{p.relative_to(SRC)}:{i}: {line.strip()}" for p in SRC.rglob("*.py") if p.name != "case.py"
             for i, line in enumerate(p.read_text(encoding="utf-8").splitlines(), 1)
             if _FLAT.search(line) and ">>>" not in line and "``" not in line and "..." not in line[:12]]
    assert found == []
    assert _FLAT.search('b = case["boundary.bottom"]') and _FLAT.search('if "closures.drag" in case:')
    assert _FLAT.search("case.get('boundary.bottom', {})") and _FLAT.search('x = c[f"boundary.{name}"]')
    assert not _FLAT.search('SCHEMA["closures.drag"]') and not _FLAT.search('case["closures"]["drag"]')
