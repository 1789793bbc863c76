"""Output folders and files: checked before computing, owned by the run that writes them.

- :func:`check_out_dir` / :func:`check_out_file` look at a path without touching it: an
  existing file where a folder should be (or the reverse), a path under a file, a name
  too long for the file system, a folder that cannot be written, a non-empty folder not
  written by twofluid. Each is a one-line :class:`~twofluid.casefile.schema.CaseError`.
- :class:`OutputFolder` claims a folder for one run: creates it, takes a lock file
  (``.twofluid.lock`` with the process id: a second run into the same folder is refused;
  a lock left by a process that no longer exists is taken over), removes the files the
  folder's previous run listed in ``.twofluid-run.json`` (so no PNG or CSV of an earlier
  run survives) and, at the end, lists the files this run wrote there.
- :func:`default_out_dir`: ``twofluid-out/<name>`` with ``[case] name`` made a plain folder
  name (``../../x`` cannot write outside ``twofluid-out``).
"""
from __future__ import annotations

import json
import os
import re
from pathlib import Path

from ..casefile.schema import CaseError

__all__ = ["LOCK", "MANIFEST", "OutputFolder", "check_out_dir", "check_out_file", "default_out_dir", "safe_name"]

LOCK = ".twofluid.lock"
MANIFEST = ".twofluid-run.json"
#: what runs of twofluid before the manifest wrote (a folder holding case.resolved.toml)
_LEGACY = ("case.resolved.toml", "summary.json", "*.csv", "*.png", "fields_*.vtu", "fields.pvd")


def safe_name(name: str) -> str:
    """``name`` as one plain folder name: letters, digits, ``.``, ``_``, ``-``; at most 100 characters.

    >>> safe_name("../../escaped"), safe_name("my bed (2)"), safe_name("..")
    ('escaped', 'my_bed_2', 'case')
    """
    s = re.sub(r"[^A-Za-z0-9._-]+", "_", str(name)).strip("._")
    s = re.sub(r"\.{2,}", ".", s)
    return s[:100] or "case"


def default_out_dir(case: dict) -> Path:
    """``twofluid-out/<[case] name>`` with the name made safe (:func:`safe_name`)."""
    return Path("twofluid-out") / safe_name(case["case"]["name"])


def _as_path(path, what: str) -> Path:
    if not isinstance(path, (str, os.PathLike)):
        raise CaseError("<api>", what, f"must be a path (str or os.PathLike), got {type(path).__name__}")
    p = Path(path)
    if "\x00" in str(p) or not str(p):
        raise CaseError(repr(str(path)), what, "is not a valid path")
    return p


def _check_names(p: Path, what: str) -> None:
    try:
        limit = os.pathconf(_existing_ancestor(p), "PC_NAME_MAX")
    except (OSError, ValueError, AttributeError):
        limit = 255
    for part in p.parts:
        if len(os.fsencode(part)) > limit:
            raise CaseError(str(p)[:80] + "…", what, f"a name in the path is longer than the file system "
                            f"allows ({len(os.fsencode(part))} > {limit} bytes)")
    if len(os.fsencode(str(p.absolute()))) >= 4096:
        raise CaseError(str(p)[:80] + "…", what, "the path is longer than the file system allows")


def _existing_ancestor(p: Path) -> Path:
    q = p.absolute()
    while not q.exists() and q != q.parent:
        q = q.parent
    return q


def _check_parent(p: Path, what: str) -> None:
    anc = _existing_ancestor(p if p.is_dir() else p.parent)  # an existing file is checked by its folder
    if not anc.is_dir():
        raise CaseError(str(p), what, f"lies under {anc}, which is a file, not a folder")
    if not os.access(anc, os.W_OK | os.X_OK):
        raise CaseError(str(p), what, f"cannot be written: no write permission in {anc}")


def owned(p: Path) -> bool:
    """True if folder ``p`` holds a twofluid run (its manifest or lock, or a resolved case)."""
    return any((p / f).is_file() for f in (MANIFEST, LOCK, "case.resolved.toml"))


def check_out_dir(path, what: str = "output folder", own: bool = True) -> Path:
    """``path`` as a folder a run may write into (nothing is created); CaseError otherwise.
    ``own``: the folder must also be new, empty or hold an earlier twofluid run.

    >>> import tempfile
    >>> f = Path(tempfile.mkdtemp()) / "a-file"
    >>> _ = f.write_text("x")
    >>> check_out_dir(f / "run")
    Traceback (most recent call last):
    ...
    twofluid.casefile.schema.CaseError: ...run: output folder: lies under ...a-file, which is a file, not a folder
    """
    p = _as_path(path, what)
    _check_names(p, what)
    if p.exists() and not p.is_dir():
        raise CaseError(str(p), what, "is an existing file, not a folder")
    _check_parent(p, what)
    if own and p.is_dir() and any(p.iterdir()) and not owned(p):
        raise CaseError(str(p), what, "is not empty and holds no earlier twofluid run: give a new or empty "
                        "folder (a run removes the files of the folder's previous run, and only those)")
    return p


def check_out_file(path, what: str = "output file") -> Path:
    """``path`` as a file that can be written (nothing is created); CaseError otherwise."""
    p = _as_path(path, what)
    _check_names(p, what)
    if p.is_dir():
        raise CaseError(str(p), what, "is a folder, not a file")
    _check_parent(p, what)
    if p.exists() and not os.access(p, os.W_OK):
        raise CaseError(str(p), what, "cannot be written: no write permission")
    return p


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (PermissionError, OSError):
        return True
    return True


class OutputFolder:
    """A run's claim on its output folder (see the module doc); a context manager."""

    def __init__(self, path: Path):
        self.path = Path(path)
        self.created = False
        self._keep: set[str] = set()

    def __enter__(self) -> "OutputFolder":
        p = self.path
        self.created = not p.exists()
        try:
            p.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise CaseError(str(p), "output folder", f"cannot be created ({exc.strerror or exc})") from None
        self._lock()
        self._clear()
        self._keep = {e.name for e in p.iterdir()} - {LOCK, MANIFEST}  # the user's own files
        return self

    def _lock(self) -> None:
        lock = self.path / LOCK
        for _ in range(2):
            try:
                fd = os.open(lock, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644)
            except FileExistsError:
                try:
                    pid = int(lock.read_text().split()[0])
                except (OSError, ValueError, IndexError):
                    pid = -1
                if pid > 0 and _alive(pid):
                    raise CaseError(str(self.path), "output folder", f"is in use by another run (process {pid}; "
                                    f"lock file {LOCK}): give another folder, or wait") from None
                lock.unlink(missing_ok=True)  # left by a process that has gone
                continue
            except OSError as exc:
                raise CaseError(str(self.path), "output folder", f"cannot be written ({exc.strerror or exc})") \
                    from None
            with os.fdopen(fd, "w") as f:
                f.write(f"{os.getpid()}\n")
            return
        raise CaseError(str(self.path), "output folder", f"lock file {LOCK} cannot be taken")

    def _clear(self) -> None:
        p = self.path
        names: list[str] = []
        if (p / MANIFEST).is_file():
            try:
                names = [str(n) for n in json.loads((p / MANIFEST).read_text(encoding="utf-8"))["files"]]
            except (OSError, ValueError, KeyError, TypeError):
                names = []
        elif (p / "case.resolved.toml").is_file():
            names = sorted({f.name for pat in _LEGACY for f in p.glob(pat)})
        for n in names:
            f = p / n
            if "/" in n or "\\" in n or n in ("", ".", "..", LOCK) or not f.is_file():
                continue  # only plain files of this folder
            f.unlink(missing_ok=True)
        (p / MANIFEST).unlink(missing_ok=True)

    def abandon(self) -> None:
        """The run did not start (bad input found late): leave the folder as it was found, if new."""
        self._keep = None

    def __exit__(self, *exc) -> None:
        p = self.path
        try:
            if self._keep is None:
                (p / LOCK).unlink(missing_ok=True)
                if self.created and not any(p.iterdir()):
                    p.rmdir()
                return
            files = sorted(e.name for e in p.iterdir() if e.is_file() and e.name not in self._keep
                           and e.name not in (LOCK, MANIFEST))
            (p / MANIFEST).write_text(json.dumps({"files": files}, indent=1) + "\n", encoding="utf-8")
        except OSError:
            pass
        finally:
            (p / LOCK).unlink(missing_ok=True)
