"""MkDocs hook: doctest blocks (``>>>`` lines and their output) in docstrings render as Python code.

The project's docstrings carry doctests in their prose as well as in numpydoc ``Examples``
sections; Markdown would read ``x["end"]`` in such a line as a link reference (a broken
cross-reference in the strict build). This registers a Markdown preprocessor, before
mkdocstrings reads the Markdown configuration, that fences each block of lines starting with
``>>>`` (with the lines up to the next blank one, the expected output).
"""
from __future__ import annotations

import re

from markdown import Extension
from markdown.preprocessors import Preprocessor
from mkdocs.plugins import event_priority

_PROMPT = re.compile(r"^(\s*)>>> ")


class _Fence(Preprocessor):
    def run(self, lines):
        out, i, fenced = [], 0, False
        while i < len(lines):
            line = lines[i]
            if line.lstrip().startswith("```"):
                fenced = not fenced
            m = None if fenced else _PROMPT.match(line)
            if m is None:
                out.append(line)
                i += 1
                continue
            indent = m.group(1)
            block = []
            while i < len(lines) and lines[i].strip():
                block.append(lines[i][len(indent):] if lines[i].startswith(indent) else lines[i].lstrip())
                i += 1
            out += ["", indent + "```python", *(indent + b for b in block), indent + "```", ""]
        return out


class DoctestBlocks(Extension):
    def extendMarkdown(self, md):
        md.preprocessors.register(_Fence(md), "twofluid_doctests", 40)


@event_priority(100)  # before mkdocstrings copies the Markdown extensions
def on_config(config):
    config.markdown_extensions.append(DoctestBlocks())
    return config
