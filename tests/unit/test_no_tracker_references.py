"""No reference to the issue tracker in the package, the docs, the case READMEs or the tests' names.

A reader has the code and its documentation, not the tracker: the word "issue" with a tracker
number, in a sentence or in a test file's name, tells them nothing. Code and docs say the reason itself, and a test is named after what it tests.
This greps the source tree (``src/``: code, case files and their READMEs, data notes), ``docs/``,
``README.md``, and every test's file name, function name and docstring text.
"""
from __future__ import annotations

import ast
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
TRACKER = re.compile(r"(?<![a-z])issues?[ _-]?#?\d+", re.I)
TEXT = {".py", ".md", ".toml", ".txt", ".csv", ".yml", ".yaml", ".json", ".cfg", ".ini"}


def _files(*roots: str):
    for root in roots:
        for p in (ROOT / root).rglob("*"):
            if p.is_file() and p.suffix in TEXT and "__pycache__" not in p.parts:
                yield p


def test_the_pattern_finds_what_it_must():
    word = "issue"  # the examples built here, so that this file holds no reference itself
    for text in (f"{word} 24", f"{word.title()} 4, part 1", f"test_{word}23_units.py", f"({word} 22)", f"{word}-21",
                 f"{word}s #3"):
        assert TRACKER.search(text), text
    for text in ("the warnings it issues", "tissue 4", "issued 3 times"):
        assert not TRACKER.search(text), text


def test_no_tracker_reference_in_src_docs_or_readme():
    found = []
    for p in [*_files("src", "docs"), ROOT / "README.md"]:
        for i, line in enumerate(p.read_text(encoding="utf-8", errors="replace").splitlines(), 1):
            if TRACKER.search(line):
                found.append(f"{p.relative_to(ROOT)}:{i}: {line.strip()[:100]}")
    assert not found, "\n".join(found)


def test_tests_are_named_after_what_they_test():
    found = []
    for p in (ROOT / "tests").rglob("*.py"):
        if TRACKER.search(p.name):
            found.append(str(p.relative_to(ROOT)))
        tree = ast.parse(p.read_text(encoding="utf-8"))
        for node in ast.walk(tree):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
                if TRACKER.search(node.name) or re.match(r"test_\d+_", node.name):
                    found.append(f"{p.relative_to(ROOT)}: {node.name}")
            if isinstance(node, (ast.Module, ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
                doc = ast.get_docstring(node) or ""
                if TRACKER.search(doc):
                    found.append(f"{p.relative_to(ROOT)}: docstring of {getattr(node, 'name', 'the module')}")
    assert not found, "\n".join(found)
