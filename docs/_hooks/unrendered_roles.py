"""MkDocs hook: a Sphinx role left as literal text on a page (``:func:`x```) fails the strict build.

``sphinx_roles.py`` turns the docstrings' roles into cross-references; this checks the result: any
``:func:``, ``:class:``, ``:meth:``, ``:mod:``, ``:data:``, ``:attr:``, ``:exc:`` or ``:obj:`` still
in a page's HTML (outside ``<pre>`` blocks, where a listing may quote one) is logged as a warning,
which ``mkdocs build --strict`` turns into a failure.
"""
from __future__ import annotations

import logging
import re

log = logging.getLogger("mkdocs.hooks.unrendered_roles")
ROLE = re.compile(r":(?:py:)?(?:func|class|meth|mod|data|attr|exc|obj|const):(?:`|<code>)")
PRE = re.compile(r"<pre\b.*?</pre>", re.S)


def on_page_content(html: str, page, **kwargs) -> str:
    found = ROLE.findall(PRE.sub("", html))
    if found:
        first = ROLE.search(PRE.sub("", html))
        text = PRE.sub("", html)
        log.warning(f"{page.file.src_path}: {len(found)} Sphinx role(s) shown as literal text, e.g. "
                    f"{text[first.start():first.start() + 60]!r}")
    return html
