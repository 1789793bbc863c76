"""Load a case by bundled name or path; validate before any computation."""
from __future__ import annotations

import re
import tomllib
from pathlib import Path

from .case import Case
from .schema import CaseError, validate

__all__ = ["bundled_cases", "case_text", "case_readme", "copyable", "load_case", "CaseError"]

def _cases():
    """The folder of the bundled cases: beside the package's modules where it is installed as files
    (as ``pip install`` does), else through importlib.resources (a zipped package: ~3–6 ms of
    imports with zipfile, which a run does not pay otherwise)."""
    folder = Path(__file__).resolve().parent.parent / "data" / "cases"
    if folder.is_dir():
        return folder
    from importlib import resources

    return resources.files("twofluid") / "data" / "cases"


def bundled_cases() -> dict[str, str]:
    """{name: description} of the cases shipped with the package."""
    out = {}
    for entry in sorted(_cases().iterdir(), key=lambda p: p.name):
        toml = entry / "case.toml"
        if toml.is_file():
            doc = tomllib.loads(toml.read_text(encoding="utf-8"))
            out[entry.name] = doc.get("case", {}).get("description", "")
    return out


def _locate(case) -> tuple[Path | object, str, str]:
    """(file, source label, default name) of a bundled case name or a case-file path."""
    import os

    if not isinstance(case, (str, os.PathLike)):
        raise CaseError("<api>", "case", f"must be a resolved case (dict), a bundled case name or a path to a "
                        f"TOML file, got {type(case).__name__}")
    path = Path(case)
    if path.suffix == ".toml" or path.exists() or os.sep in str(case):
        if path.is_dir():
            raise CaseError(str(path), "file", "is a folder, not a case file")
        if path.exists() and not path.is_file():
            raise CaseError(str(path), "file", "is not a case file (a device, pipe or other special file; "
                            "a case file is a TOML text file)")
        if not path.is_file():
            raise CaseError(str(path), "file", "does not exist")
        return path, str(path), path.stem[:100]
    bundled = _cases() / str(case) / "case.toml"
    if bundled.is_file():
        return bundled, f"{case} (bundled)", str(case)
    raise CaseError(str(case), "case", "is neither a TOML file nor a bundled case; bundled: "
                    + ", ".join(bundled_cases()))


def _read(loc, source: str, kind: str = "a case file") -> str:
    try:
        return loc.read_text(encoding="utf-8")
    except UnicodeDecodeError:
        raise CaseError(source, "file", f"is not UTF-8 text ({kind} is TOML)") from None
    except OSError as exc:
        raise CaseError(source, "file", f"cannot be read ({exc.strerror or exc})") from None


def read_toml(loc, source: str, kind: str = "a case file") -> dict:
    """The TOML document at ``loc`` (a path or a package resource); CaseError naming ``source``
    for a file that cannot be read, is not UTF-8 text or is not TOML."""
    try:
        return tomllib.loads(_read(loc, source, kind))
    except tomllib.TOMLDecodeError as exc:
        raise CaseError(source, "TOML syntax", str(exc)) from None


def case_text(case: str) -> str:
    """The TOML text of a bundled case or file."""
    loc, source, _ = _locate(case)
    return _read(loc, source)


def copyable(text: str) -> str:
    """Case text with its ``[case] name`` line commented out: a copy (``twofluid show X > my.toml``)
    then runs under its own file's name ("my"), not over the bundled case's output folder.

    >>> print(copyable('[case]\\nname = "x"\\nmodel = "two_fluid_1d"\\n'), end="")
    [case]
    # name = "x"   (commented out by `twofluid show`: a copy runs under its file's name)
    model = "two_fluid_1d"
    """
    out, section = [], ""
    for line in text.splitlines(keepends=True):
        st = line.strip()
        if st.startswith("["):
            section = st.split("#")[0].strip()
        if section == "[case]" and re.match(r"name\s*=", st):
            end = "\n" if line.endswith("\n") else ""
            line = f"# {line.rstrip()}   (commented out by `twofluid show`: a copy runs under its file's name){end}"
        out.append(line)
    return "".join(out)


def case_readme(case: str) -> str | None:
    """The README.md next to a bundled case or case file (None if there is none)."""
    loc, source, _ = _locate(case)
    readme = loc.parent / "README.md" if isinstance(loc, Path) else loc.parent.joinpath("README.md")
    return _read(readme, str(readme)) if readme.is_file() else None


def load_case(case: str) -> Case:
    """Parse and validate; returns the resolved case with ``_source`` set.

    The case is a :class:`~twofluid.casefile.case.Case` (a ``dict``) nested as the TOML file:
    ``[boundary.bottom] kind`` is ``case["boundary"]["bottom"]["kind"]``. The flat dotted
    spelling of version 0.1.0 (``case["boundary.bottom"]``) still works in this release, with a
    :class:`~twofluid.casefile.case.FlatKeyWarning` (a ``DeprecationWarning``).
    An empty or missing ``[case] name`` becomes the file's name without ``.toml`` (the
    bundled case's name), so a copied case runs under its own name.

    >>> case = load_case("settling-illite")
    >>> case["case"]["name"], case["boundary"]["bottom"]["kind"], case["closures"]["drag"]["law"]
    ('settling-illite', 'wall', 'gidaspow')
    """
    loc, source, name = _locate(case)
    doc = read_toml(loc, source)
    resolved = validate(doc, source, name=name)
    resolved["_source"] = source
    return resolved
