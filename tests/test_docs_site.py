"""The documentation site (mkdocs.yml, docs/) builds in strict mode: a broken link, a page left
out of the navigation, a broken cross-reference or a docstring the API reference cannot render
fails the suite (and so CI, which runs the suite). The tools are in the ``test`` extra; the test
skips only where they are not installed."""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent


def test_the_docs_site_builds_strictly(tmp_path):
    pytest.importorskip("mkdocs")
    pytest.importorskip("mkdocstrings")
    pytest.importorskip("material")
    if not (ROOT / "mkdocs.yml").is_file():
        pytest.skip("not a source checkout (no mkdocs.yml)")
    env = dict(os.environ, NO_MKDOCS_2_WARNING="1")
    p = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "--quiet", "-f", str(ROOT / "mkdocs.yml"),
                        "-d", str(tmp_path / "site")], capture_output=True, text=True, env=env, cwd=tmp_path)
    assert p.returncode == 0, p.stderr[-4000:]
    assert (tmp_path / "site" / "index.html").is_file()
    assert (tmp_path / "site" / "api" / "models" / "index.html").is_file()
