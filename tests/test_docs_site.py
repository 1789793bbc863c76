"""The documentation site (mkdocs.yml, docs/) builds in strict mode: a broken link, a page left
out of the navigation, a broken cross-reference, a Sphinx role left as literal text or a docstring
the API reference cannot render fails the suite (and so CI, which runs the suite). The tools are in
the ``test`` extra; the tests skip only where they are not installed."""
from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
ROLE = re.compile(r":(?:func|class|meth|mod|data|attr|exc|obj):(?:`|<code>)")


def _tools():
    pytest.importorskip("mkdocs")
    pytest.importorskip("mkdocstrings")
    pytest.importorskip("material")
    if not (ROOT / "mkdocs.yml").is_file():
        pytest.skip("not a source checkout (no mkdocs.yml)")


def _build(config: Path, site: Path, cwd: Path) -> subprocess.CompletedProcess:
    """``mkdocs build --strict``, not ``--quiet``: quiet drops the warnings strict mode counts."""
    env = dict(os.environ, NO_MKDOCS_2_WARNING="1")
    return subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "-f", str(config),
                           "-d", str(site)], capture_output=True, text=True, env=env, cwd=cwd)


def test_the_docs_site_builds_strictly_with_the_docstrings_roles_as_links(tmp_path):
    _tools()
    p = _build(ROOT / "mkdocs.yml", tmp_path / "site", tmp_path)
    assert p.returncode == 0, p.stderr[-4000:]
    assert (tmp_path / "site" / "index.html").is_file()
    assert (tmp_path / "site" / "fluidized-beds" / "index.html").is_file()
    pages = {f: f.read_text(encoding="utf-8") for f in (tmp_path / "site" / "api").rglob("index.html")}
    assert (tmp_path / "site" / "api" / "models" / "index.html") in pages
    assert not [f for f, html in pages.items() if ROLE.search(html)]
    links = sum(html.count('class="autorefs autorefs-internal"') for html in pages.values())
    assert links > 50  # the docstrings' :func:/:class: roles, now links (115 roles were literal text)
    models = pages[tmp_path / "site" / "api" / "models" / "index.html"]
    assert 'href="#twofluid.models.two_fluid_1d.TwoFluid1D"' in models


def test_a_role_left_as_literal_text_fails_the_strict_build(tmp_path):
    _tools()
    docs = tmp_path / "docs"
    docs.mkdir()
    (docs / "index.md").write_text("# Roles\n\nRun it with :func:`twofluid.run_case`.\n", encoding="utf-8")
    config = tmp_path / "mkdocs.yml"
    config.write_text(f"site_name: roles\ndocs_dir: {docs}\nstrict: true\nhooks:\n"
                      f"  - {ROOT / 'docs' / '_hooks' / 'unrendered_roles.py'}\n", encoding="utf-8")
    p = _build(config, tmp_path / "site", tmp_path)
    assert p.returncode != 0 and "Sphinx role" in p.stderr and "index.md" in p.stderr
    (docs / "index.md").write_text("# Roles\n\nRun it with `twofluid.run_case`.\n", encoding="utf-8")
    p = _build(config, tmp_path / "site", tmp_path)
    assert p.returncode == 0, p.stderr[-2000:]
