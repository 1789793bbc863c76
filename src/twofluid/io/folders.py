"""Output folders and files: checked before computing, owned by the run that writes them.

- :func:`check_out_dir` / :func:`check_out_file` look at a path without touching it: an
  existing file where a folder should be (or the reverse), a path under a file, a name
  too long for the file system, a folder that cannot be written, a non-empty folder not
  written by twofluid. Each is a one-line :class:`~twofluid.casefile.schema.CaseError`.
- :class:`OutputFolder` claims a folder for one run (or one ensemble): creates it, takes a lock
  file (``.twofluid.lock`` with the process id: a second run into the same folder is refused;
  a lock left by a process that no longer exists is taken over), removes the files the
  folder's previous run recorded in ``.twofluid-run.json`` — only those that are still as
  that run left them (same size and modification time) — and then refuses, before anything
  runs, a folder that still holds an entry with the name of a twofluid output (a file of the
  user's, a folder, a symbolic link): nothing of the user's is overwritten or removed.
- Files are written only through :func:`create` and :func:`write_atomic`: never through a
  symbolic link (``O_NOFOLLOW``), recorded in the folder's manifest as they are made (a user's
  file added to the folder during a run is never recorded, so never removed later), and an error
  names the file.
- :func:`default_out_dir`: ``twofluid-out/<name>`` with ``[case] name`` made a plain folder
  name (``../../x`` cannot write outside ``twofluid-out``).
"""
from __future__ import annotations

import errno
import json
import os
import re
import time
import warnings
from pathlib import Path

from ..casefile.schema import CaseError, CaseWarning

__all__ = ["ERROR_LOG", "LOCK", "MANIFEST", "OutputFolder", "OutputWarning", "check_out_dir", "check_out_file",
           "create", "default_out_dir", "is_output_name", "record", "safe_name", "write_atomic", "write_error_log"]

LOCK = ".twofluid.lock"
MANIFEST = ".twofluid-run.json"
ERROR_LOG = "twofluid-error.log"  # the traceback of an internal error (a defect of twofluid)

#: the names twofluid writes into a run or ensemble folder (besides the patterns below)
OUTPUT_NAMES = frozenset({
    "case.resolved.toml", "summary.json", "profiles.csv", "probes.csv", "steps.csv", "elements.csv",
    "layers.csv", "ru_field.csv", "surface_motion.csv", "spectra.csv", "element_test.csv", "fields.pvd",
    "members.csv", "members.previous.csv", "ensemble.json", "porosity.png", "pressure.png", "heights.png",
    "bed_pressure_drop.png", "velocity.png", "profiles.png", "single_fluid.png", "profile.png", "ru_map.png",
    "spectra.png", "ru_histories.png", "settlement.png", "element_test.png", "fragility.png", "runs",
    "fluidization_curve.csv", "fluidization_curve.png", "csr_n.csv", "csr_n.png", ERROR_LOG, LOCK, MANIFEST})
_OUTPUT_PATTERNS = re.compile(r"(fields_\d{4,}\.vtu|(figure|histogram)_.*\.png|.*\.tmp|\.twofluid.*)")


class OutputWarning(CaseWarning):
    """An output folder's record could not be written (disk full): the message names the file."""


def is_output_name(name: str) -> bool:
    """Whether ``name`` is a name twofluid writes into an output folder.

    >>> is_output_name("summary.json"), is_output_name("fields_0003.vtu"), is_output_name("my.csv")
    (True, True, False)
    """
    return name in OUTPUT_NAMES or _OUTPUT_PATTERNS.fullmatch(name) is not None


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
    if not str(os.fspath(path)).strip():
        raise CaseError(repr(str(os.fspath(path))), what, "is empty: give a folder name")
    p = Path(path)
    if "\x00" in str(p):
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
    """True if folder ``p`` holds a twofluid run or ensemble (its manifest or lock file)."""
    return any((p / f).is_file() and not (p / f).is_symlink() for f in (MANIFEST, LOCK))


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
        kind = "an existing file" if p.is_file() else "not a folder (a device or other special file)"
        raise CaseError(str(p), what, f"is {kind}; give a folder")
    _check_parent(p, what)
    if own and p.is_dir() and any(p.iterdir()) and not owned(p):
        raise CaseError(str(p), what, "is not empty and holds no earlier twofluid run: give a new or empty "
                        "folder (a run removes the files its folder's previous run wrote, and only those)")
    return p


def check_out_file(path, what: str = "output file") -> Path:
    """``path`` as a file that can be written (nothing is created); CaseError otherwise."""
    p = _as_path(path, what)
    _check_names(p, what)
    if p.is_dir():
        raise CaseError(str(p), what, "is a folder, not a file")
    if p.is_symlink():
        raise CaseError(str(p), what, "is a symbolic link; twofluid does not write through links")
    _check_parent(p, what)
    if p.exists() and not os.access(p, os.W_OK):
        raise CaseError(str(p), what, "cannot be written: no write permission")
    return p


# ---------------------------------------------------------------- writing files
#: the folders claimed by this process: absolute path -> OutputFolder (for :func:`record`)
_CLAIMED: dict[str, "OutputFolder"] = {}
#: the folder this process claimed last (where :func:`write_error_log` puts a traceback)
_LAST: list = [None]


def record(path) -> None:
    """Note that twofluid wrote ``path``: if it lies in a claimed folder, the folder's manifest lists it."""
    folder = _CLAIMED.get(os.path.dirname(os.path.abspath(path)))
    if folder is not None:
        folder.add(os.path.basename(path))


def _named(exc: OSError, path) -> OSError:
    """``exc`` with the file's name in it (``[Errno 28] No space left on device: '…/summary.json'``)."""
    if exc.errno == errno.ELOOP:
        return OSError(errno.ELOOP, "is a symbolic link; twofluid does not write through links", str(path))
    if exc.filename is None:
        return OSError(exc.errno, exc.strerror or str(exc), str(path))
    return exc


def create(path, append: bool = False) -> int:
    """Open ``path`` for writing (truncated, or appended to) and return the file descriptor; never
    through a symbolic link. The file is recorded in its claimed folder's manifest.

    >>> import tempfile
    >>> d = Path(tempfile.mkdtemp())
    >>> os.symlink(d / "elsewhere", d / "link.csv")
    >>> create(d / "link.csv")
    Traceback (most recent call last):
    ...
    OSError: [Errno 40] is a symbolic link; twofluid does not write through links: '...link.csv'
    """
    flags = os.O_WRONLY | os.O_CREAT | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_CLOEXEC", 0)
    flags |= os.O_APPEND if append else os.O_TRUNC
    try:
        fd = os.open(path, flags, 0o644)
    except OSError as exc:
        raise _named(exc, path) from None
    record(path)
    return fd


def write_all(fd: int, data: bytes, path) -> None:
    """Write every byte of ``data`` to ``fd`` (a short write is continued); OSError naming ``path``."""
    view = memoryview(data)
    try:
        while view:
            view = view[os.write(fd, view):]
    except OSError as exc:
        raise _named(exc, path) from None


def write_atomic(path, data: bytes | str) -> None:
    """``path`` written whole or not at all: a temporary file next to it (never through a link) is
    written and renamed over it, so an older version is replaced only by a complete one and a full
    disk never leaves an empty or cut file. OSError naming ``path``."""
    path = Path(path)
    if isinstance(data, str):
        data = data.encode("utf-8")
    tmp = path.with_name(path.name + ".tmp")
    try:
        for p in (tmp, path):  # a link planted before or during the run is neither followed nor replaced
            if p.is_symlink():
                raise OSError(errno.ELOOP, "is a symbolic link; twofluid does not write through links", str(p))
        fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_TRUNC | getattr(os, "O_NOFOLLOW", 0), 0o644)
        try:
            write_all(fd, data, path)
        finally:
            os.close(fd)
        if path.is_symlink():
            raise OSError(errno.ELOOP, "is a symbolic link; twofluid does not write through links", str(path))
        record(path)  # before it appears: a run stopped right after still has it in its record
        os.replace(tmp, path)
    except OSError as exc:
        try:
            tmp.unlink(missing_ok=True)
        except OSError:
            pass
        raise _named(exc, path) from None
    record(path)


# ---------------------------------------------------------------- claiming a folder
def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (PermissionError, OSError):
        return True
    return True


def _stat(p: Path):
    """[size, mtime_ns] of a plain file (None for a link, a folder or nothing)."""
    try:
        st = p.lstat()
    except OSError:
        return None
    if not os.path.isfile(p) or p.is_symlink():
        return None
    return [st.st_size, st.st_mtime_ns]


class OutputFolder:
    """A run's claim on its output folder (see the module doc); a context manager.

    ``keep``: recorded names the claim leaves in place (an ensemble's ``members.csv``, which a rerun
    continues); ``keep_check(path)`` returns why such a file cannot be continued (or None).
    """

    def __init__(self, path: Path, keep=(), keep_check=None):
        self.path = Path(path)
        self.created = False
        self.keep, self.keep_check = frozenset(keep), keep_check
        self._written: dict[str, object] = {}
        self._abandoned = False
        self._key = os.path.abspath(self.path)
        self._started = 0

    def __enter__(self) -> "OutputFolder":
        p = self.path
        self.created = not p.exists()
        try:
            p.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise CaseError(str(p), "output folder", f"cannot be created ({exc.strerror or exc})") from None
        self._lock()
        try:
            self._refuse_leftovers()  # before anything is removed: a refused folder stays as it was
            self._clear()
            self._started = time.time_ns()
            self._written = {n: None for n in self.keep if (p / n).is_file()}
            _CLAIMED[self._key] = self
            self._save()
            _LAST[0] = self.path
        except BaseException:
            self.abandon()
            self.__exit__(None, None, None)
            raise
        return self

    def _lock(self) -> None:
        """The lock file, with this process's id, appears whole (a file of its own linked to the lock's
        name, which fails if it exists): a run stopped at any moment never leaves an empty lock."""
        lock = self.path / LOCK
        for _ in range(2):
            try:
                self._link_lock(lock)
            except FileExistsError:
                try:
                    pid = int(lock.read_text().split()[0]) if not lock.is_symlink() else -1
                except (OSError, ValueError, IndexError):
                    pid = -1
                if pid > 0 and _alive(pid):
                    raise CaseError(str(self.path), "output folder", f"is in use by another run (process {pid}; "
                                    f"lock file {LOCK}): give another folder, or wait") from None
                if lock.is_dir() and not lock.is_symlink():
                    raise CaseError(str(self.path), "output folder", f"holds a folder named {LOCK}; remove it")
                lock.unlink(missing_ok=True)  # left by a process that has gone
                continue
            except OSError as exc:
                raise CaseError(str(lock), "output folder", f"cannot be written ({exc.strerror or exc})") \
                    from None
            return
        raise CaseError(str(self.path), "output folder", f"lock file {LOCK} cannot be taken")

    @staticmethod
    def _link_lock(lock: Path) -> None:
        for e in lock.parent.glob(LOCK + ".*.tmp"):  # left by a process stopped while locking
            try:
                if not _alive(int(e.name[len(LOCK) + 1:-4])):
                    e.unlink(missing_ok=True)
            except (ValueError, OSError):
                pass
        tmp = lock.with_name(f"{LOCK}.{os.getpid()}.tmp")
        fd = os.open(tmp, os.O_CREAT | os.O_TRUNC | os.O_WRONLY | getattr(os, "O_NOFOLLOW", 0), 0o644)
        try:
            try:
                write_all(fd, f"{os.getpid()}\n".encode(), tmp)
            finally:
                os.close(fd)
            os.link(tmp, lock, follow_symlinks=False)
        finally:
            tmp.unlink(missing_ok=True)

    def _recorded(self) -> tuple[dict, int]:
        """{name: [size, mtime_ns] or None} of the previous run's manifest, and when that run began [ns]."""
        m = self.path / MANIFEST
        if not m.is_file() or m.is_symlink():
            return {}, 0
        try:
            doc = json.loads(m.read_text(encoding="utf-8"))
            files, started = doc["files"], int(doc.get("started_ns", 0))
        except (OSError, ValueError, KeyError, TypeError, AttributeError):
            return {}, 0
        if isinstance(files, list):  # the manifest of twofluid before 0.x: names only, written at the end
            when = m.stat().st_mtime_ns
            return {str(n): ["<=", when] for n in files}, 0
        return ({str(n): s for n, s in files.items()} if isinstance(files, dict) else {}), started

    def _clearable(self) -> list[str]:
        """The files the folder's previous run wrote and that are still as it left them."""
        p = self.path
        files, started = self._recorded()
        out = []
        for n, was in files.items():
            if "/" in n or "\\" in n or n in ("", ".", "..", LOCK, MANIFEST) or n in self.keep:
                continue
            now = _stat(p / n)  # None: a link, a folder or nothing: never removed
            if now is None or not is_output_name(n):
                continue
            if isinstance(was, list) and len(was) == 2 and was[0] == "<=":
                same = now[1] <= was[1]  # older manifest: unchanged since the run ended
            elif isinstance(was, list):
                same = now == was
            else:  # recorded while the run went (it was stopped): written since that run began
                same = started > 0 and now[1] >= started
            if same:
                out.append(n)
        return out

    def _clear(self) -> None:
        """Remove the files the folder's previous run wrote and that are still as it left them."""
        for n in self._clearable():
            (self.path / n).unlink(missing_ok=True)

    def _refuse_leftovers(self) -> None:
        """Before anything runs: no entry left with a name twofluid writes (it would be overwritten)."""
        recorded = set(self._recorded()[0])
        clearable = set(self._clearable())
        for e in sorted(self.path.iterdir(), key=lambda e: e.name):
            n = e.name
            if n in (LOCK, MANIFEST) or n in clearable or not is_output_name(n):
                if e.is_symlink() and n in (MANIFEST,):
                    raise CaseError(str(e), "output folder", "is a symbolic link; remove it")
                continue
            if n in self.keep and n in recorded and e.is_file() and not e.is_symlink():
                why = self.keep_check(e) if self.keep_check else None
                if why is None:
                    continue
                raise CaseError(str(e), "output folder", why)
            if n == "runs" and n in recorded and e.is_dir() and not e.is_symlink():
                continue
            kind = ("a symbolic link" if e.is_symlink() else "a folder" if e.is_dir() else
                    "a file this folder's earlier run did not write, or one changed since")
            raise CaseError(str(e), "output folder", f"is {kind}, and a run writes a file of that name here: "
                            "move it away, or give another folder")

    def add(self, name: str) -> None:
        """Record ``name`` as written by this run (the manifest on disk lists it from now on)."""
        if name in self._written or name in (LOCK, MANIFEST) or name.endswith(".tmp"):
            return
        self._written[name] = None
        try:
            self._save()
        except OSError:
            pass  # written again at the end; a full disk there is reported

    def _save(self, final: bool = False) -> None:
        # only what twofluid's writers recorded (create, write_atomic, record): a file the user puts
        # here during the run, even under an output's name, is never recorded, so never removed later
        files = {}
        for n in sorted(self._written):
            files[n] = _stat(self.path / n) if final else None
        doc = {"files": files, "started_ns": self._started}
        _write_manifest(self.path / MANIFEST, (json.dumps(doc, indent=1) + "\n").encode())

    def refresh(self) -> None:
        """Record the files again as they are now (after a file was rewritten once the folder was closed)."""
        try:
            self._save(final=True)
        except OSError as e:
            warnings.warn(OutputWarning(f"{self.path / MANIFEST}: cannot be written ({e.strerror or e})"),
                          stacklevel=2)

    def abandon(self) -> None:
        """The run did not start (bad input found late): leave the folder as it was found, if new."""
        self._abandoned = True

    def __exit__(self, *exc) -> None:
        p = self.path
        _CLAIMED.pop(self._key, None)
        try:
            if self._abandoned:
                if self.created:
                    (p / MANIFEST).unlink(missing_ok=True)
                    (p / LOCK).unlink(missing_ok=True)
                    if not any(p.iterdir()):
                        p.rmdir()
                return
            try:
                self._save(final=True)
            except OSError as e:
                warnings.warn(OutputWarning(f"{p / MANIFEST}: cannot be written ({e.strerror or e}); the record "
                                            "of this run's files is the one written while it ran"), stacklevel=2)
        except OSError:
            pass
        finally:
            (p / LOCK).unlink(missing_ok=True)


def _write_manifest(path: Path, data: bytes) -> None:
    tmp = path.with_name(path.name + ".tmp")
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_TRUNC | getattr(os, "O_NOFOLLOW", 0), 0o644)
    try:
        try:
            write_all(fd, data, path)
        finally:
            os.close(fd)
        os.replace(tmp, path)
    except OSError:
        tmp.unlink(missing_ok=True)
        raise


def write_error_log(text: str) -> Path:
    """Write ``text`` (the traceback of an internal error) to :data:`ERROR_LOG` in the folder this
    process claimed last, recorded in its manifest (the next run there removes it), or, where there
    is none, to a new file in the temporary folder; return the path. OSError if neither can be written."""
    folder = _LAST[0]
    if folder is not None and owned(folder):
        path = folder / ERROR_LOG
        try:
            fd = create(path)
            try:
                write_all(fd, text.encode("utf-8", "replace"), path)
            finally:
                os.close(fd)
            _add_to_manifest(folder, ERROR_LOG)
            return path
        except OSError:
            pass
    import tempfile

    fd, name = tempfile.mkstemp(prefix="twofluid-error-", suffix=".log")
    try:
        write_all(fd, text.encode("utf-8", "replace"), name)
    finally:
        os.close(fd)
    return Path(name)


def _add_to_manifest(folder: Path, name: str) -> None:
    """Add ``name`` as it is now to the manifest of ``folder`` (a folder no longer claimed)."""
    m = folder / MANIFEST
    doc = json.loads(m.read_text(encoding="utf-8"))
    if isinstance(doc.get("files"), dict):
        doc["files"][name] = _stat(folder / name)
        _write_manifest(m, (json.dumps(doc, indent=1) + "\n").encode())
