"""docs/lateral-spreading.md: its worked example runs and prints what the page shows."""
import contextlib
import io
import re
from pathlib import Path


def test_worked_example_matches_the_page():
    doc = (Path(__file__).resolve().parents[2] / "docs" / "lateral-spreading.md").read_text(encoding="utf-8")
    block = doc.split("<!-- example:", 1)[1]
    code = re.search(r"```python\n(.*?)```", block, re.S).group(1)
    shown = re.search(r"```text\n(.*?)```", block, re.S).group(1)
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(code, "lateral-spreading.md", "exec"), {})
    assert out.getvalue() == shown
