"""The driver: runs an ensemble's members on ``dask.distributed`` and streams their rows.

A LocalCluster of ``workers`` processes with one thread each is started on this machine
unless ``scheduler`` names an existing cluster. The driver submits a bounded window of
members (a few per worker thread, at least 8), so its memory does not grow with the ensemble; a
worker runs :func:`run_member` in a temporary folder (or the member's kept folder) and
returns only the collected figures and its status. Members whose resolved case was
completed before (same hash, in ``members.csv``) are not run again.
"""
from __future__ import annotations

import itertools
import logging
import os
import signal
import sys
import tempfile
import threading
import time
from contextlib import contextmanager, nullcontext
from pathlib import Path

from tqdm import tqdm

from ..runners.common import sigterm_as_interrupt
from .results import ResultsTable, figure_at, figure_stats, with_settlement_companions

__all__ = ["run_member", "run_members", "run_ensemble", "cluster_client", "ensemble_out_dir", "check_workers",
           "check_scheduler", "ProgressLines"]


def run_member(case: dict, collect: list[str], run_dir: str | None = None) -> dict:
    """Run one member (on a worker); return {status, reason, wall_time_s, cpu_time_s, figures}.

    ``run_dir`` keeps the member's run folder; None runs it in a temporary folder that is
    removed. A failed step, an invalid case found while building, or any other error of the
    run is a failed member with its reason (one line), not an exception.

    >>> import twofluid
    >>> case = twofluid.load_case("settling-illite")
    >>> case["time"]["end"], case["output"]["times"], case["output"]["plots"] = 0.2, [0.2], False
    >>> res = run_member(case, ["steps", "nothing.here"])
    >>> res["status"], res["figures"]
    ('completed', {'steps': 2, 'nothing.here': None})
    >>> case["materials"]["particle_density"] = "heavy"   # an error of the member, not of the driver
    >>> res = run_member(case, ["steps"])
    >>> res["status"], res["reason"][:9]
    ('failed', 'CaseError')
    """
    from ..runners import run_case

    t0, c0 = time.perf_counter(), time.process_time()

    def go(out):
        res = run_case(case, out)
        figures = {c: figure_at(res.summary, res.profiles, c) for c in collect}
        return res.summary.get("status", res.status), str(res.summary.get("reason", "")), figures

    try:
        if run_dir:
            status, reason, figures = go(run_dir)
        else:
            with tempfile.TemporaryDirectory(prefix="twofluid-member-") as out:
                status, reason, figures = go(out)
    except Exception as exc:  # a member's failure must not stop the ensemble; its reason is kept
        status, reason, figures = "failed", f"{type(exc).__name__}: {exc}", {}
    reason = " ".join(reason.split())
    return {"status": status, "reason": reason, "wall_time_s": time.perf_counter() - t0,
            "cpu_time_s": time.process_time() - c0, "figures": figures}


@contextmanager
def cluster_client(workers: int | None = None, scheduler: str | None = None):
    """A ``distributed.Client``: to the cluster at ``scheduler``, or to a new LocalCluster of
    ``workers`` processes (default: the CPU count) with one thread each."""
    from distributed import Client, LocalCluster

    if scheduler:
        try:
            client = Client(scheduler, timeout="30s")
        except (OSError, TimeoutError, ValueError) as exc:
            from ..casefile.schema import CaseError

            raise CaseError("command line", "--scheduler", f"no Dask scheduler answered at {scheduler!r} "
                            f"({type(exc).__name__}: {' '.join(str(exc).split())[:200]}); valid: the address "
                            "a running scheduler prints, e.g. tcp://head-node:8786") from None
        try:
            yield client
        finally:
            client.close()
        return
    n = workers or os.cpu_count() or 1
    start = _ClusterStart()
    try:
        cluster = LocalCluster(n_workers=n, processes=True, threads_per_worker=1, dashboard_address=":0",
                               silence_logs=logging.ERROR)
    except BaseException:
        start.end()
        raise
    with cluster:
        start.end()  # a Ctrl-C or SIGTERM held during the start interrupts here, and the cluster is closed
        with Client(cluster) as client:
            yield client


class _ClusterStart:
    """Signals while a LocalCluster starts. Its worker processes start with SIGINT blocked (they inherit
    the signal mask): a Ctrl-C in the terminal reaches the whole process group, and only the driver
    should act on it, by closing the cluster. The driver's own Ctrl-C, and a SIGTERM, during the start
    are held, not lost: :meth:`end` delivers them once the cluster exists (it can then be closed), as
    ``KeyboardInterrupt`` and :class:`~twofluid.runners.common.Terminated`. (Where signal masks do not
    exist, SIGINT is ignored during the start instead.) Main thread only; elsewhere nothing changes."""

    def __init__(self):
        self.active = threading.current_thread() is threading.main_thread()
        self.noted: list[int] = []
        if not self.active:
            return
        note = lambda signum, frame: self.noted.append(signum)  # noqa: E731
        self.old_term = signal.signal(signal.SIGTERM, note)
        # noted, not raised, also where another thread of this process takes the signal
        ignored = signal.getsignal(signal.SIGINT) is signal.SIG_IGN
        self.old_int = None if ignored else signal.signal(signal.SIGINT, note)
        self.old_mask = None
        if hasattr(signal, "pthread_sigmask"):  # for the workers, which inherit the mask
            self.old_mask = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
        elif not ignored:
            signal.signal(signal.SIGINT, signal.SIG_IGN)

    def end(self) -> None:
        if not self.active:
            return
        self.active = False
        signal.signal(signal.SIGTERM, self.old_term)
        if self.old_int is not None:
            signal.signal(signal.SIGINT, self.old_int)
        if self.old_mask is not None:
            signal.pthread_sigmask(signal.SIG_SETMASK, self.old_mask)  # a Ctrl-C held meanwhile raises here
        if signal.SIGTERM in self.noted:
            from ..runners.common import Terminated

            raise Terminated()
        if self.noted:
            raise KeyboardInterrupt


class ProgressLines:
    """An ensemble's progress as one line on stderr at a steady pace (every ``every`` seconds, from a
    thread of its own, whether or not a member finished meanwhile): for output that is not a terminal
    (a batch job's log), where a progress bar cannot be drawn."""

    def __init__(self, name: str, total: int, every: float = 30.0, stream=None):
        self.name, self.total, self.every = name, total, every
        self.stream = stream
        self.done = self.failed = 0
        self._t0 = time.monotonic()
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name="twofluid-ensemble-progress", daemon=True)

    def start(self, done: int = 0) -> "ProgressLines":
        self.done = done
        self._thread.start()
        return self

    def line(self) -> str:
        return (f"twofluid: ensemble {self.name}: {self.done} of {self.total} members done"
                + (f" ({self.failed} failed)" if self.failed else "") + f", {time.monotonic() - self._t0:.0f} s elapsed")

    def _run(self) -> None:
        while not self._stop.wait(self.every):
            try:
                print(self.line(), file=self.stream or sys.stderr, flush=True)
            except (OSError, ValueError):
                pass

    def close(self) -> None:
        self._stop.set()


def check_scheduler(scheduler) -> str | None:
    """``scheduler`` as the address of a Dask scheduler (None: a local cluster); CaseError otherwise."""
    from ..casefile.schema import CaseError

    if scheduler is None:
        return None
    if not isinstance(scheduler, str) or not scheduler.strip():
        raise CaseError("<api>", "scheduler", f"{scheduler!r} is not valid; valid: the address a running Dask "
                        "scheduler prints (a string, e.g. 'tcp://head-node:8786'), or None for a local cluster")
    return scheduler


def _label(v):
    """A parameter as its table shows it: a record file by its name."""
    return Path(v).name if isinstance(v, str) and os.sep in v else v


def run_members(members, collect: list[str], out_dir, *, keep_runs: bool = False, workers: int | None = None,
                scheduler: str | None = None, progress: bool = False, client=None) -> tuple[list[dict], dict]:
    """Run ``members`` (see :mod:`.members`); return (rows in member order, run record).

    ``members.csv`` in ``out_dir`` gets a row as each member finishes. On Ctrl-C or SIGTERM
    the running members are cancelled, the record says ``interrupted`` and the
    ``KeyboardInterrupt`` propagates after the finished rows are written. ``progress``: True, a
    progress bar; "lines", a line every 30 s (:class:`ProgressLines`); False, nothing.
    """
    from distributed import as_completed

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    params = list(dict.fromkeys(k for m in members for k in m.params))
    table = ResultsTable(out / "members.csv", params, collect, {m.hash for m in members if m.hash})
    rows: dict[int, dict] = {}

    def row_of(m, status, reason, wall, figures, cpu=None):
        return {"member": m.index, "hash": m.hash, "status": status, "reason": reason, "wall_time_s": wall,
                "cpu_time_s": cpu,
                **{k: _label(v) for k, v in m.params.items()}, **{c: figures.get(c) for c in collect}}

    todo = []
    for m in members:
        if m.error:
            rows[m.index] = row_of(m, "failed", m.error, 0.0, {})
            table.write(rows[m.index])
        elif m.hash in table.kept:
            kept = table.kept_row(m.hash)
            rows[m.index] = row_of(m, "completed", "", kept["wall_time_s"], kept, kept["cpu_time_s"])
        else:
            todo.append(m)
    record = {"members": len(members), "kept_from_before": len(members) - len(todo) - sum(bool(m.error) for m in members),
              "invalid": sum(bool(m.error) for m in members), "ran": 0, "status": "completed"}
    bar = tqdm(total=len(members), initial=len(members) - len(todo), unit="member",
               disable=progress is not True, desc="members", dynamic_ncols=True)
    lines = (ProgressLines(Path(out).name, len(members)).start(len(members) - len(todo))
             if progress == "lines" else None)
    from .. import compiled

    # the members' kernels built once, here, before any worker starts (not once per worker)
    compiled.prepare([g for m in todo for g in compiled.groups_for(m.case)])
    t0 = time.perf_counter()
    try:
        with sigterm_as_interrupt(), (nullcontext(client) if client else cluster_client(workers, scheduler)) as cl:
            record["workers"] = len(cl.nthreads())
            pending = iter(todo)
            by_key, running = {}, {}
            failed = sum(r["status"] != "completed" for r in rows.values())

            def submit(m):
                run_dir = str(out / "runs" / f"member-{m.index:05d}-{m.hash[:12]}") if keep_runs else None
                f = cl.submit(run_member, m.case, collect, run_dir, key=f"member-{m.index}-{m.hash[:16]}",
                              pure=False)
                by_key[f.key], running[f.key] = m, f
                return f

            threads = {"n": sum(cl.nthreads().values()), "asked": time.monotonic()}

            def top_up():
                """Members in flight: 4 per worker thread (at least 8), as the cluster is now (a
                batch-system cluster may still be growing; asked at most every 2 s)."""
                if time.monotonic() - threads["asked"] > 2.0:
                    threads.update(n=sum(cl.nthreads().values()), asked=time.monotonic())
                window = max(8, 4 * threads["n"])
                return [submit(m) for m in itertools.islice(pending, max(window - len(running), 0))]

            queue = as_completed(top_up())
            try:
                for fut in queue:
                    m = by_key.pop(fut.key)
                    running.pop(fut.key)
                    try:
                        res = fut.result()
                    except Exception as exc:  # the worker died (KilledWorker) or the task could not run
                        res = {"status": "failed", "reason": " ".join(f"{type(exc).__name__}: {exc}".split()),
                               "wall_time_s": 0.0, "figures": {}}
                    fut.release()
                    if res["status"] != "interrupted":  # a member stopped by Ctrl-C runs again next time
                        rows[m.index] = row_of(m, res["status"], res["reason"], res["wall_time_s"], res["figures"],
                                               res.get("cpu_time_s"))
                        table.write(rows[m.index])
                        record["ran"] += 1
                        failed += res["status"] != "completed"
                    else:
                        record.setdefault("interrupted_members", []).append(m.index)
                    bar.update(1)
                    bar.set_postfix(failed=failed, refresh=False)
                    if lines is not None:
                        lines.done, lines.failed = lines.done + 1, failed
                    queue.update(top_up())
            except KeyboardInterrupt:
                record["status"] = "interrupted"
                cl.cancel(list(running.values()))
                raise
    finally:
        bar.close()
        if lines is not None:
            lines.close()
        table.close()
        record["wall_time_s"] = time.perf_counter() - t0
    return [rows[i] for i in sorted(rows)], record


def ensemble_out_dir(spec) -> Path:
    """``twofluid-out/<[ensemble] name>``, the name made a plain folder name (as a run's)."""
    from ..io.folders import safe_name

    return Path("twofluid-out") / safe_name(spec.name)


def check_workers(workers, what: str = "workers") -> int | None:
    """``workers`` as the number of worker processes (None: the CPU count); CaseError outside [1, 1024]."""
    from ..casefile.schema import CaseError

    if workers is None:
        return None
    if isinstance(workers, bool) or not isinstance(workers, int) or not 1 <= workers <= 1024:
        raise CaseError("<api>" if what == "workers" else "command line", what,
                        f"{workers!r} is not valid; valid: an integer in [1, 1024], or None for the CPU count")
    return workers


def _members_table_check(path: Path) -> str | None:
    """Why ``members.csv`` of an earlier ensemble cannot be continued (None: it can)."""
    from .results import FIXED

    try:
        with open(path, newline="", encoding="utf-8") as fh:
            head = fh.readline().strip().split(",")
    except (OSError, UnicodeDecodeError) as exc:
        return f"cannot be read ({exc})"
    if head[: len(FIXED)] != FIXED:
        return (f"is not a members table of twofluid (its header starts {','.join(head[:3])!r}, not "
                f"{','.join(FIXED[:3])!r}): move it away, or give another folder")
    return None


def run_ensemble(spec_or_path, out_dir=None, workers: int | None = None, scheduler: str | None = None,
                 progress: bool = False, plots: bool = True, client=None) -> list[dict]:
    """Run an ensemble (an :class:`~twofluid.ensemble.EnsembleSpec` or the path of its file).

    Writes ``members.csv``, ``ensemble.json`` and the plots to ``out_dir`` (default
    ``twofluid-out/<ensemble name>``, the name made a plain folder name) and returns the results
    table: one dict per member with ``member``, ``hash``, ``status``, ``reason``, ``wall_time_s``,
    the varied parameters and the collected figures. ``workers`` processes on this machine (an
    integer in [1, 1024]; None: the CPU count), or the cluster at ``scheduler`` (or an open
    ``distributed.Client``). The folder is checked and locked as a run's is (a second ensemble into
    it is refused; a rerun continues its ``members.csv``). Bad input is a :class:`~twofluid.CaseError`.

    >>> run_ensemble(42)
    Traceback (most recent call last):
    ...
    twofluid.casefile.schema.CaseError: <api>: ensemble: must be an EnsembleSpec or the path of an ensemble file, got int
    """
    from . import plots as ens_plots
    from .members import members as make_members
    from .spec import EnsembleSpec, load_ensemble
    from ..casefile.schema import CaseError
    from ..io.folders import OutputFolder, check_out_dir
    from ..io.results import write_json

    if isinstance(spec_or_path, EnsembleSpec):
        spec = spec_or_path
    elif isinstance(spec_or_path, (str, os.PathLike)) and str(os.fspath(spec_or_path)).strip():
        spec = load_ensemble(spec_or_path)
    else:
        raise CaseError("<api>", "ensemble", "must be an EnsembleSpec or the path of an ensemble file, got "
                        f"{type(spec_or_path).__name__}")
    workers = check_workers(workers)
    scheduler = check_scheduler(scheduler)
    out = check_out_dir(ensemble_out_dir(spec) if out_dir is None else out_dir, "ensemble output folder")
    ms = make_members(spec)
    collect = with_settlement_companions(spec.collect)  # beside a settlement: final or not, and the final one
    summary = {"ensemble": spec.name, "description": spec.description, "file": spec.source,
               "base_case": spec.base.get("_source", ""), "varied": spec.varied(), "collect": spec.collect,
               "scheduler": scheduler or "LocalCluster"}
    with OutputFolder(out, keep=("members.csv", "members.previous.csv", "runs"), keep_check=_members_table_check):
        try:
            rows, record = run_members(ms, collect, out, keep_runs=spec.keep_runs, workers=workers,
                                       scheduler=scheduler, progress=progress, client=client)
        except KeyboardInterrupt as exc:
            from ..runners.common import Terminated

            write_json(out / "ensemble.json", {**summary, "status": "interrupted",
                                               "reason": "terminated (SIGTERM)" if isinstance(exc, Terminated)
                                               else "interrupted by the user (Ctrl-C)",
                                               "note": "members.csv holds every member that finished; run the "
                                                       "same ensemble again to run the rest"})
            raise
        summary.update(record)
        summary["completed"] = sum(r["status"] == "completed" for r in rows)
        summary["failed"] = [{"member": r["member"], "reason": r["reason"]} for r in rows
                             if r["status"] != "completed"]
        summary["figures"] = figure_stats(rows, collect)
        if spec.fragility:
            summary["fragility"] = ens_plots.fragility_fits(rows, spec.fragility)
        write_json(out / "ensemble.json", summary)
        if plots:
            from ..io.folders import record

            figures = ens_plots.ensemble_plots(rows, spec, out, summary.get("fragility"))
            for p in figures:  # drawn by matplotlib: recorded here, as twofluid's own writers record theirs
                record(p)
            summary["plots"] = [p.name for p in figures]
            write_json(out / "ensemble.json", summary)
    return rows
