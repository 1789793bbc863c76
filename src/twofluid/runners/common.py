"""What every runner shares: the result record, the guard of the time loop, the dispatch.

Each runner (``column_1d``, ``flow_2d``, ``liquefaction``) has the same shape:
build the model from the resolved case, consume its generator of steps inside
:func:`run_guard`, write the summary, make the plots. :func:`run_case` puts around it
what does not depend on the model, in this order: validate the case (a dict exactly as
a case file), check the output folder (:mod:`.output`), claim it (lock, clear the files
of its previous run), run with SIGTERM handled like Ctrl-C, and turn an interruption
or failure outside the time loop into a summary with a status.
"""
from __future__ import annotations

import contextvars
import errno
import importlib
import json
import os
import shutil
import signal
import sys
import time
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..casefile.loader import load_case
from ..casefile.schema import CaseError, revalidate
from ..io.results import NonFiniteOutput, read_table, reset_nonfinite, write_json
from ..timestepping.backward_euler import StepFailure
from ..io.folders import OutputFolder, check_out_dir, default_out_dir

__all__ = ["RunResult", "RunGuard", "LineProgress", "Terminated", "run_case", "run_guard", "validated_case", "RUNNERS"]


@dataclass
class RunResult:
    """What a run returns.

    ``out_dir`` is the folder written (None for a run kept in memory); ``summary`` is
    ``summary.json``; ``tables`` holds every CSV file of the run as {file name: {column:
    array}} (filled for in-memory runs, ``out_dir=None``, whose files are not kept);
    ``profiles`` and ``history`` are what the runner kept in memory.
    """

    status: str  # completed | interrupted | failed
    out_dir: Path | None
    summary: dict
    profiles: dict = field(default_factory=dict)  # t -> element fields
    history: dict = field(default_factory=dict)  # name -> array over steps
    tables: dict = field(default_factory=dict)  # "profiles.csv" -> {column: array}


class _NoBar:
    """The progress bar's interface when there is none (no tqdm import for a quiet run)."""

    n = 0.0

    def update(self, dn: float) -> None:
        self.n += dn

    def reset(self, total=None) -> None:
        self.n = 0.0

    def close(self) -> None:
        pass


class LineProgress:
    """Progress as plain lines on stderr, for output that is not a terminal (a batch job's log, a
    notebook): one line at least every 10 % of the simulated time and at least every 30 s of wall time
    (never more often than every 10 % or 30 s), from 5 s into the run on (a short run prints none).
    The progress bar's interface (``update``, ``reset``, ``close``, ``n``, ``bar_format``)."""

    STEP, EVERY_S, QUIET_S = 0.1, 30.0, 5.0

    def __init__(self, total: float | None, stream=None, clock=time.monotonic):
        import sys

        self.stream = stream if stream is not None else sys.stderr
        self.clock = clock
        self.bar_format = ""
        self.n = 0.0
        self._t0 = clock()
        self.reset(total)

    def reset(self, total=None) -> None:
        self.total, self.n = total, 0.0
        self._last_at, self._last_n = self.clock(), 0.0

    def update(self, dn: float) -> None:
        self.n += dn
        now = self.clock()
        if now - self._t0 < self.QUIET_S:
            return
        frac = (self.n / self.total) if self.total else None
        due = now - self._last_at >= self.EVERY_S
        if frac is not None and int(frac / self.STEP + 1e-9) > int(self._last_n / self.total / self.STEP + 1e-9):
            due = True
        if due:
            self._say(now, frac)

    def _say(self, now: float, frac) -> None:
        wall = now - self._t0
        what = (f"t = {self.n:.4g} of {self.total:.4g} s simulated ({100 * frac:.0f} %)" if frac is not None
                else f"step {self.n:.0f}")
        try:
            print(f"twofluid: {what}, {wall:.0f} s elapsed", file=self.stream, flush=True)
        except (OSError, ValueError):
            pass
        self._last_at, self._last_n = now, self.n

    def close(self) -> None:
        pass


def _bar(t_end: float, progress):
    if not progress:
        return _NoBar()
    if progress == "lines":
        return LineProgress(t_end)
    from tqdm import tqdm

    return tqdm(total=t_end, unit="s", leave=False,
                bar_format="{l_bar}{bar}| t = {n:.4g}/{total:.4g} s simulated [{elapsed}<{remaining}]")


@dataclass
class RunGuard:
    """What :func:`run_guard` found: status, reason and the progress bar (tqdm) to update."""

    bar: object
    status: str = "completed"
    reason: str = ""


class Terminated(KeyboardInterrupt):
    """SIGTERM (what ``kill`` and batch schedulers send), handled like Ctrl-C."""


# Errors of the numerics (not of the program) that end a run as "failed" with a summary:
# SuperLU's "Factor is exactly singular" is a RuntimeError; NotImplementedError and
# RecursionError are RuntimeErrors of the program and propagate. OSError: an output that
# cannot be written any more (disk full) ends the run with what was written.
_NUMERICAL_ERRORS = (FloatingPointError, OverflowError, ZeroDivisionError, np.linalg.LinAlgError,
                     RuntimeError, OSError)
_PROGRAM_ERRORS = (NotImplementedError, RecursionError)
#: where a run is: "set-up", "time loop" or "summary and plots"
_PHASE: contextvars.ContextVar[str] = contextvars.ContextVar("twofluid_run_phase", default="set-up")
#: (time reached [s], steps taken) when the time loop ended: what a summary written after a stop in the
#: "summary and plots" phase reports (the CSV files reach that time)
_REACHED: contextvars.ContextVar[tuple | None] = contextvars.ContextVar("twofluid_run_reached", default=None)
#: bytes of the summary.json a run reserves when it starts (see :func:`_reserve_summary`)
SUMMARY_RESERVE = 64 * 1024


class _CountingBar:
    """The progress bar, counting its updates (one per step) for :data:`_REACHED`."""

    def __init__(self, bar):
        object.__setattr__(self, "_bar", bar)
        object.__setattr__(self, "steps", 0)

    def update(self, dn: float) -> None:
        self.__dict__["steps"] += 1  # (its own count: not the bar's attribute, see __setattr__)
        self._bar.update(dn)

    def reset(self, total=None) -> None:  # pseudo-time restarts (flow_2d): the steps go on counting
        self._bar.reset(total=total)

    def __getattr__(self, name):
        return getattr(self._bar, name)

    def __setattr__(self, name, value) -> None:
        setattr(self._bar, name, value)


def _interrupt_reason(exc: BaseException) -> str:
    return "terminated (SIGTERM)" if isinstance(exc, Terminated) else "interrupted by the user (Ctrl-C)"


@contextmanager
def run_guard(t_end: float, progress: bool, *closing):
    """Context of a run's time loop: progress bar, Ctrl-C and SIGTERM, failed steps.

    A ``KeyboardInterrupt`` (also SIGTERM inside :func:`run_case`), a :class:`StepFailure`,
    a non-finite output (:class:`~twofluid.io.results.NonFiniteOutput`), an output that
    cannot be written or a numerical error (floating-point overflow, ``LinAlgError``, a
    ``RuntimeError`` such as a singular factorisation) inside the block ends the loop, not
    the program: the guard records status ``interrupted`` or ``failed``
    with the reason, closes the bar and every object in ``closing`` (result
    writers), and the runner goes on to write its summary from what it has.
    """
    run = RunGuard(_CountingBar(_bar(t_end, progress)))
    reset_nonfinite()
    _PHASE.set("time loop")
    _REACHED.set(None)
    try:
        yield run
    except KeyboardInterrupt as exc:
        run.status, run.reason = "interrupted", _interrupt_reason(exc)
    except StepFailure as exc:
        run.status, run.reason = "failed", str(exc)
    except _NUMERICAL_ERRORS as exc:  # e.g. SuperLU "Factor is exactly singular", overflow
        if isinstance(exc, _PROGRAM_ERRORS):
            raise
        text = str(exc) if isinstance(exc, NonFiniteOutput) else f"{type(exc).__name__}: {exc}"
        run.status, run.reason = "failed", text
    finally:
        _PHASE.set("summary and plots")
        _REACHED.set((float(run.bar.n), int(run.bar.steps)))
        run.bar.close()
        for c in closing:
            try:
                c.close()
            except OSError:
                pass


# The runner of each model: "module:function", imported on use; called with a case that
# run_case has just validated (the liquefaction runner's inner function does not validate it again).
RUNNERS = {"two_fluid_1d": "twofluid.runners.column_1d:run_1d",
           "reduced_1d": "twofluid.runners.column_1d:run_1d",
           "two_fluid_2d": "twofluid.runners.flow_2d:run_2d",
           "liquefaction_1d": "twofluid.runners.liquefaction:run_validated",
           "immersed_avalanche": "twofluid.runners.avalanche:run_avalanche"}


def validated_case(case) -> dict:
    """``case`` (resolved or edited dict, bundled name or TOML path) checked through the schema.

    A dict is validated exactly as a case file is (the same :class:`CaseError` lines, with
    the file it was loaded from as the source, ``<api>`` for a dict made in code).

    >>> validated_case({"case": {"name": "x", "modle": "reduced_1d"}})
    Traceback (most recent call last):
    ...
    twofluid.casefile.schema.CaseError: <api>: [case] modle: unknown key; did you mean 'model'? (valid keys: description, model, name, study)
    """
    if isinstance(case, dict):
        return revalidate(case, str(case.get("_source", "<api>")))
    return load_case(case)


@contextmanager
def sigterm_as_interrupt():
    """SIGTERM raises :class:`Terminated` (and SIGINT ``KeyboardInterrupt``, where Python's own
    handler is in place) while a run is going; main thread only: signal handlers cannot be set
    elsewhere, e.g. in a worker thread of an ensemble (None is yielded there).

    Yields a dict: ``got`` is the first signal received (or None). Once the caller sets
    ``finishing`` (the run has ended and is writing its last record), a signal is only noted, not
    raised, so that the caller can say in the summary that the run was interrupted as it ended."""
    threading = sys.modules.get("threading")  # not imported: no thread but the main one (and ~2 ms saved)
    if threading is not None and threading.current_thread() is not threading.main_thread():
        yield None
        return
    state = {"got": None, "finishing": False}

    def handler(signum, frame):
        if state["got"] is None:
            state["got"] = signum
        if state["finishing"]:
            return
        raise Terminated() if signum == signal.SIGTERM else KeyboardInterrupt()

    old = signal.signal(signal.SIGTERM, handler)
    old_int = signal.getsignal(signal.SIGINT)
    own_int = old_int is signal.default_int_handler or getattr(old_int, "twofluid_handler", False)
    if own_int:
        signal.signal(signal.SIGINT, handler)
    try:
        yield state
    finally:
        signal.signal(signal.SIGTERM, old)
        if own_int:
            signal.signal(signal.SIGINT, old_int)


def _interrupted_as_it_ended(res: RunResult, out: Path, signum: int) -> RunResult:
    """A signal that came as the run was ending: the summary says so (status interrupted), whatever
    the run had written; the files of the run are complete."""
    reason = "terminated (SIGTERM)" if signum == signal.SIGTERM else "interrupted by the user (Ctrl-C)"
    summary = dict(res.summary)
    before = f"{summary.get('status', res.status)}" + (f", {summary['reason']}" if summary.get("reason") else "")
    summary["status"] = "interrupted"
    summary["reason"] = f"{reason} as the run ended; its outputs are complete ({before})"
    if (out / "summary.json").is_file():
        _write_summary(out / "summary.json", summary)
    res.status, res.summary = "interrupted", summary
    return res


def _reserve_summary(out: Path, case: dict) -> None:
    """``summary.json`` written as the run starts: status "running", padded to :data:`SUMMARY_RESERVE`
    bytes (2 kB, room for the short summary, where the disk or the file-size limit does not allow
    that). A run killed outright leaves it saying so; a disk that fills up later still holds these
    bytes, where the final summary (or a short one) is written in place (:func:`_write_summary`). A
    disk too full for even the short one: the run goes on without (its end says if the summary
    cannot be written)."""
    doc = {"case": case["case"]["name"], "status": "running", "stopped_at_s": None, "steps": None,
           "reason": "the run was going when this was written: if no run is going, its process was killed "
                     "before it could write a summary", "end_time_s": case["time"]["end"]}
    data = json.dumps(doc, indent=2) + "\n"
    from ..io.folders import write_atomic

    for size in (SUMMARY_RESERVE, 2048):
        try:
            write_atomic(out / "summary.json", data + " " * max(size - len(data), 0))
            return
        except OSError as exc:
            if exc.errno not in (errno.ENOSPC, getattr(errno, "EDQUOT", errno.ENOSPC), errno.EFBIG):
                raise


def _is_reserved(path: Path) -> bool:
    """Whether ``path`` is still the summary :func:`_reserve_summary` wrote (no summary of the run yet)."""
    try:
        with open(path, "rb") as fh:
            return b'"status": "running"' in fh.read(400)
    except OSError:
        return False


def _write_summary(path: Path, summary: dict) -> None:
    """``summary`` as ``path``; on a full disk, written in place over the bytes the file already has
    (those reserved when the run started, or the summary written before), shortened to the key figures
    where it does not fit. OSError if even that cannot be written."""
    try:
        write_json(path, summary)
        return
    except OSError as exc:
        if exc.errno not in (errno.ENOSPC, getattr(errno, "EDQUOT", errno.ENOSPC), errno.EFBIG):
            raise
        full = exc
    from ..io.folders import write_all
    from ..io.results import plain

    short = {k: summary.get(k) for k in ("case", "status", "reason", "stopped_at_s", "end_time_s", "steps",
                                        "wall_time_s")}
    short["note"] = "the disk was full: this is the summary shortened to what fitted"
    try:
        fd = os.open(path, os.O_WRONLY | getattr(os, "O_NOFOLLOW", 0))
    except OSError:
        raise full from None
    try:
        size = os.fstat(fd).st_size
        for doc in (summary, short):
            data = (json.dumps(plain(doc), indent=2, allow_nan=False) + "\n").encode()
            if len(data) <= size:
                write_all(fd, data + b" " * (size - len(data)), path)  # no new block: the file's own bytes
                return
        raise full
    finally:
        os.close(fd)


def _outside_loop(case: dict, out: Path, status: str, reason: str, wall: float) -> dict:
    """Summary of a run interrupted or failed outside its time loop (see :func:`run_case`)."""
    path = out / "summary.json"
    phase = _PHASE.get()
    reached = _REACHED.get()
    if path.is_file() and phase == "summary and plots" and not _is_reserved(path):  # the plots were going
        summary = json.loads(path.read_text(encoding="utf-8"))
        summary["reason"] = (f"{reason} while making the plots; the time loop had ended "
                             f"({summary.get('status')}, {summary.get('reason') or 'no reason given'})")
        summary["status"] = status
    elif phase == "summary and plots" and reached is not None:  # the loop ended; its summary was not written
        summary = {"case": case["case"]["name"], "status": status, "stopped_at_s": reached[0],
                   "reason": f"{reason} while writing the summary and plots; the time loop had ended at t = "
                             f"{reached[0]:.6g} s (the CSV files reach it)",
                   "end_time_s": case["time"]["end"], "wall_time_s": wall, "steps": reached[1]}
    else:
        summary = {"case": case["case"]["name"], "status": status, "stopped_at_s": 0.0,
                   "reason": f"{reason} during the {phase}" + (", before the first step" if phase == "set-up"
                                                                else ""),
                   "end_time_s": case["time"]["end"], "wall_time_s": wall, "steps": 0}
    _write_summary(path, summary)
    return summary


def _run_claimed(runner, case: dict, out: Path, progress: bool, folder, sig, wall0: float) -> RunResult:
    """The runner in its claimed folder: an interruption or failure outside its time loop is a
    summary that says so; from its end on, a signal is only noted (``sig``)."""
    token = _PHASE.set("set-up")
    reached = _REACHED.set(None)
    try:
        _reserve_summary(out, case)
        return runner(case, out, progress=progress)
    except KeyboardInterrupt as exc:
        summary = _outside_loop(case, out, "interrupted", _interrupt_reason(exc), time.perf_counter() - wall0)
        return RunResult("interrupted", out, summary)
    except CaseError:
        if _is_reserved(out / "summary.json"):
            (out / "summary.json").unlink(missing_ok=True)
        folder.abandon()
        raise
    except (StepFailure, *_NUMERICAL_ERRORS) as exc:
        if isinstance(exc, _PROGRAM_ERRORS):
            raise
        text = str(exc) if isinstance(exc, (NonFiniteOutput, StepFailure)) else f"{type(exc).__name__}: {exc}"
        summary = _outside_loop(case, out, "failed", text, time.perf_counter() - wall0)
        return RunResult("failed", out, summary)
    finally:
        _PHASE.reset(token)
        _REACHED.reset(reached)
        if sig is not None:
            sig["finishing"] = True  # from here a signal is noted, not raised


def run_case(case, out_dir=None, progress: bool = False, plots: bool | None = None) -> RunResult:
    """Run ``case`` (resolved or edited dict, bundled name or TOML path).

    ``out_dir``: the folder for the results (created; it must be new, empty or hold an earlier
    run, whose files are removed first), or a function of the validated case that gives it
    (e.g. :func:`~twofluid.io.folders.default_out_dir`); None keeps the results in memory only: no file is
    kept, the CSV tables are in ``RunResult.tables`` and no plots are made. The case is
    validated before anything is written (:func:`validated_case`); bad input is a
    :class:`CaseError`. A run interrupted (Ctrl-C, SIGTERM) or failed, in the time loop or
    outside it, returns with status ``interrupted`` or ``failed`` and a summary saying where.
    ``plots``: True/False overrides the case's ``[output] plots`` (None keeps it).

    >>> import twofluid
    >>> case = twofluid.load_case("settling-illite")
    >>> case["time"]["end"], case["output"]["times"] = case["time"]["step"], []
    >>> res = twofluid.run_case(case)          # in memory: nothing written
    >>> res.status, res.out_dir, sorted(res.tables)
    ('completed', None, ['probes.csv', 'profiles.csv'])
    """
    case = validated_case(case)
    if plots is not None:
        case = {**case, "output": {**case["output"], "plots": bool(plots)}}
    if callable(out_dir):  # the folder follows from the validated case (the CLI's default_out_dir)
        out_dir = out_dir(case)
    memory = out_dir is None
    if memory:
        case = {**case, "output": {**case["output"], "plots": False}}
        import tempfile  # here: only a run kept in memory needs it

        out = Path(tempfile.mkdtemp(prefix="twofluid-"))
    else:
        out = check_out_dir(out_dir)
    mod, func = RUNNERS[case["case"]["model"]].split(":")
    runner = getattr(importlib.import_module(mod), func)
    from .. import compiled

    compiled.prepare(compiled.groups_for(case))  # the kernels this run needs, built once (one line)
    wall0 = time.perf_counter()
    try:
        with sigterm_as_interrupt() as sig:
            with OutputFolder(out) as folder:
                res = _run_claimed(runner, case, out, progress, folder, sig, wall0)
                if sig is not None and sig["got"] is not None and res.status != "interrupted":
                    res = _interrupted_as_it_ended(res, out, sig["got"])
            if sig is not None and sig["got"] is not None and res.status != "interrupted":
                res = _interrupted_as_it_ended(res, out, sig["got"])  # it came as the folder was closed
                folder.refresh()
        if memory:
            res.tables = {p.name: read_table(p) for p in sorted(out.glob("*.csv"))}
            res.out_dir = None
    finally:
        if memory:
            shutil.rmtree(out, ignore_errors=True)
    return res


__all__ += ["default_out_dir"]
