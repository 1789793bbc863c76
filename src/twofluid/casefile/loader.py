"""Load a case by bundled name or path; validate before any computation."""
from __future__ import annotations

import tomllib
from importlib import resources
from pathlib import Path

from .schema import CaseError, validate

__all__ = ["bundled_cases", "case_text", "load_case", "CaseError"]

_CASES = resources.files("twofluid") / "data" / "cases"


def bundled_cases() -> dict[str, str]:
    """{name: description} of the cases shipped with the package."""
    out = {}
    for entry in sorted(_CASES.iterdir(), key=lambda p: p.name):
        toml = entry / "case.toml"
        if toml.is_file():
            doc = tomllib.loads(toml.read_text(encoding="utf-8"))
            out[entry.name] = doc.get("case", {}).get("description", "")
    return out


def _locate(case: str):
    path = Path(case)
    if path.suffix == ".toml" or path.exists():
        if not path.is_file():
            raise CaseError(str(path), "file", "does not exist")
        return path
    bundled = _CASES / case / "case.toml"
    if bundled.is_file():
        return bundled
    raise CaseError(case, "case", "is neither a TOML file nor a bundled case; bundled: "
                    + ", ".join(bundled_cases()))


def case_text(case: str) -> str:
    """The TOML text of a bundled case or file."""
    return _locate(case).read_text(encoding="utf-8")


def load_case(case: str) -> dict:
    """Parse and validate; returns the resolved case with ``_source`` set."""
    loc = _locate(case)
    source = str(loc) if isinstance(loc, Path) else f"{case} (bundled)"
    try:
        doc = tomllib.loads(loc.read_text(encoding="utf-8"))
    except tomllib.TOMLDecodeError as exc:
        raise CaseError(source, "TOML syntax", str(exc)) from None
    except UnicodeDecodeError:
        raise CaseError(source, "file", "is not UTF-8 text") from None
    resolved = validate(doc, source)
    resolved["_source"] = source
    return resolved
