"""Griffe extension: the docstrings' Sphinx roles (``:func:`x```, ``:class:`~a.b.C```) as cross-references.

The package's docstrings use Sphinx's roles (numpydoc style); mkdocstrings reads Markdown and would
show them as literal text. When the package is loaded for the API reference, each role becomes a
mkdocstrings cross-reference ``[title][full.path]`` where its target is an object the reference
renders (a page of ``docs/api/`` names it or a module above it, it is public and has a docstring),
and inline code otherwise (a private helper, another package's object). The target is resolved as
Sphinx does: a full path as it is; ``~`` shows the last component only; a leading ``.`` or a bare
name is looked up from the docstring's own scope outwards (class, module, package, the module's
imports), then as a suffix of any path in the package. A cross-reference autorefs cannot resolve
is a warning, so the strict build fails on it; ``unrendered_roles.py`` fails it on any role left.
"""
from __future__ import annotations

import re
from pathlib import Path

import griffe

ROLE = re.compile(r":(?:py:)?(func|class|meth|mod|data|attr|exc|obj|const):`(~?)([^`<>]+?)`")
_API = Path(__file__).resolve().parents[1] / "api"


def _rendered_roots() -> list[str]:
    roots = []
    for page in sorted(_API.glob("*.md")):
        roots += re.findall(r"^:::\s+(\S+)", page.read_text(encoding="utf-8"), re.M)
    return roots


class SphinxRoles(griffe.Extension):
    """Rewrite the roles of every docstring of the package once it is loaded."""

    def __init__(self) -> None:
        super().__init__()
        self.roots = _rendered_roots()

    def on_package(self, *, pkg: griffe.Module, **kwargs) -> None:
        self.pkg = pkg
        self.index: dict[str, griffe.Object] = {}
        self._collect(pkg)
        for obj in list(self.index.values()):
            if obj.docstring is not None and ":" in obj.docstring.value:
                obj.docstring.value = ROLE.sub(lambda m, o=obj: self._ref(m, o), obj.docstring.value)

    # ------------------------------------------------------------------
    def _collect(self, obj) -> None:
        self.index[obj.path] = obj
        for member in obj.members.values():
            if not member.is_alias:
                self._collect(member)

    def _rendered(self, path: str) -> bool:
        obj = self.index.get(path)
        if obj is None or (obj.docstring is None and not obj.is_module):
            return False
        for root in self.roots:
            if path == root:
                return True
            if path.startswith(root + "."):
                rest = path[len(root) + 1:].split(".")
                if any(part.startswith("_") for part in rest):
                    return False
                parent = path.rsplit(".", 1)[0]  # each level down must be rendered too
                return parent == root or self._rendered(parent)
        return False

    def _in_scope(self, name: str, obj) -> str | None:
        head, _, rest = name.partition(".")
        scope = obj
        while scope is not None:
            member = scope.members.get(head) if hasattr(scope, "members") else None
            if member is not None:  # an import's target path needs no resolution (it may be another package)
                base = member.target_path if member.is_alias else member.path
                return f"{base}.{rest}" if rest else base
            scope = scope.parent
        return None

    def _follow(self, name: str) -> str | None:
        """The defining path of ``name`` given through the package's re-exports (``twofluid.CaseError``)."""
        head, _, rest = name.partition(".")
        if head != self.pkg.name or not rest:
            return None
        try:
            target = self.pkg[rest]
            return target.final_target.path if target.is_alias else target.path
        except Exception:  # not in the package, or an alias to another package
            return None

    def _resolve(self, name: str, obj) -> str | None:
        name = name.strip()
        if name in self.index:
            return name
        followed = self._follow(name)
        if followed in self.index:
            return followed
        bare = name.lstrip(".")
        found = self._in_scope(bare, obj)
        if found is not None and found in self.index:
            return found
        hits = [p for p in self.index if p.endswith("." + bare)]
        if hits:  # the nearest to the docstring's module
            here = obj.module.path
            return max(hits, key=lambda p: (len(_common(p, here)), -len(p)))
        last = [p for p in self.index if p.endswith("." + bare.rsplit(".", 1)[-1])]
        if "." in bare and len(last) == 1:  # a re-export griffe cannot see (the facade's lazy names)
            return last[0]
        return found

    def _ref(self, m: re.Match, obj) -> str:
        short, name = m.group(2) == "~", m.group(3).strip()
        path = self._resolve(name, obj)
        shown = (path or name).rsplit(".", 1)[-1] if short else name.lstrip(".")
        if m.group(1) in ("func", "meth") and not shown.endswith(")"):
            shown += "()"
        if path is not None and self._rendered(path):
            return f"[`{shown}`][{path}]"
        return f"`{shown}`"


def _common(a: str, b: str) -> list[str]:
    out = []
    for x, y in zip(a.split("."), b.split(".")):
        if x != y:
            break
        out.append(x)
    return out
