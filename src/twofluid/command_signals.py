"""The command's signals and internal errors (for :mod:`twofluid.cli`; standard library only, imported
first): Ctrl-C and SIGTERM noted from the command module's import on and turned into exit statuses
130 and 143 with one line, and an unexpected exception turned into one line and a log file."""
import os
import signal
import sys

__all__ = ["Signals", "internal_error", "note_early"]


def _note_early(signum, frame):
    """SIGINT/SIGTERM before :func:`main` has started (the module's own import): noted, acted on by
    main as an interruption (exit 130/143, one line), never a traceback from an import."""
    _EARLY.append(signum)


_EARLY: list = []


def note_early() -> None:
    """In the command's process (the console script, or ``python -m twofluid.cli``), from now until
    :meth:`Signals.install`, a Ctrl-C or SIGTERM is noted rather than raised in the middle of an
    import. A program that imports the command line keeps its own handlers."""
    if os.path.basename(sys.argv[0] if sys.argv and sys.argv[0] else "") not in ("twofluid", "twofluid.exe",
                                                                                   "cli.py"):
        return
    try:
        if signal.getsignal(signal.SIGINT) is signal.default_int_handler:
            signal.signal(signal.SIGINT, _note_early)
        if signal.getsignal(signal.SIGTERM) is signal.SIG_DFL:
            signal.signal(signal.SIGTERM, _note_early)
    except ValueError:  # not the main thread
        pass


class Signals:
    """The command's own handlers of SIGINT and SIGTERM for its whole life (a run installs its own
    while it goes and restores these): both raise ``KeyboardInterrupt``, and which one came is noted,
    so a signal at any moment — during the imports, after the run — ends the command with one line
    and exit status 130 (SIGINT) or 143 (SIGTERM), never a traceback or a kill."""

    got: int | None = None

    @classmethod
    def handler(cls, signum, frame):
        cls.got = cls.got or signum
        raise KeyboardInterrupt

    handler.__func__.twofluid_handler = True

    @classmethod
    def install(cls):
        """Install the handlers; return the ones they replace (None where none was replaced)."""
        import signal

        cls.got = _EARLY[0] if _EARLY else None  # a signal noted as the module was imported
        cls._unraisable = sys.unraisablehook
        sys.unraisablehook = cls._unraisable_hook
        try:
            if signal.getsignal(signal.SIGINT) is _note_early:
                signal.signal(signal.SIGINT, signal.default_int_handler)
            if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:  # ignored on purpose (nohup, a background job)
                return None, signal.signal(signal.SIGTERM, cls.handler)
            return signal.signal(signal.SIGINT, cls.handler), signal.signal(signal.SIGTERM, cls.handler)
        except ValueError:  # not the main thread (main() called from a thread): Python's defaults stay
            return None

    @classmethod
    def late(cls) -> None:
        """The command's work is done (or it is saying that it was interrupted): a signal now exits at
        once with its status (130, 143), without a traceback from the interpreter's shutdown."""
        import signal

        def leave(signum, frame):
            cls.got = cls.got or signum
            try:
                os.write(2, b"twofluid: interrupted as it ended (its outputs are complete)\n")
            except OSError:
                pass
            cls.leave(143 if signum == signal.SIGTERM else 130)

        try:
            if signal.getsignal(signal.SIGINT) is not signal.SIG_IGN:
                signal.signal(signal.SIGINT, leave)
            signal.signal(signal.SIGTERM, leave)
        except ValueError:
            pass

    @staticmethod
    def leave(rc: int) -> None:
        """End the process with status ``rc`` now: the output flushed, logging shut down, no
        interpreter shutdown (every file of twofluid is closed by then)."""
        logging = sys.modules.get("logging")  # (not imported: no handler to flush, and not worth importing)

        for stream in (sys.stdout, sys.stderr):
            try:
                stream.flush()
            except (OSError, ValueError):
                pass
        try:
            if logging is not None:
                logging.shutdown()
        except Exception:  # noqa: BLE001 - leaving anyway
            pass
        os._exit(rc)

    _unraisable = None

    @classmethod
    def _unraisable_hook(cls, unraisable) -> None:
        """A KeyboardInterrupt raised where Python cannot propagate it (a weakref callback of the import
        system, a ``__del__``) is not printed as "Exception ignored …": the signal is noted (``got``)
        and acted on by :meth:`pending` and at the end of :func:`main`."""
        if isinstance(unraisable.exc_value, KeyboardInterrupt):
            return
        (cls._unraisable or sys.__unraisablehook__)(unraisable)

    @classmethod
    def pending(cls) -> None:
        """Raise the interruption of a signal noted but swallowed on the way (see above)."""
        if cls.got is not None:
            raise KeyboardInterrupt

    @classmethod
    def restore(cls, old) -> None:
        import signal

        if cls._unraisable is not None:
            sys.unraisablehook, cls._unraisable = cls._unraisable, None
        if old is not None:
            if old[0] is not None:
                signal.signal(signal.SIGINT, old[0])
            signal.signal(signal.SIGTERM, old[1])

    @classmethod
    def status(cls, reason: str = "", exc: BaseException | None = None) -> int:
        import signal

        common = sys.modules.get("twofluid.runners.common")  # not imported on purpose: this may run in a signal
        term = common is not None and isinstance(exc, common.Terminated)
        return 143 if cls.got == signal.SIGTERM or "SIGTERM" in reason or term else 130


def internal_error(exc: BaseException) -> int:
    """An exception twofluid did not expect (a defect of the program, not of the input): one line that
    names it and the file its traceback went to (the run folder's log, else a temporary file); status 1."""
    import traceback

    from .io.folders import write_error_log

    text = "".join(traceback.format_exception(type(exc), exc, exc.__traceback__))
    try:
        where = f"traceback in {write_error_log(text)}"
    except OSError as e:  # nowhere to write it: the traceback goes to stderr after the line
        where = f"traceback below (no log could be written: {e.strerror or e})"
    msg = str(exc).splitlines()[0][:200] if str(exc) else ""
    print(f"twofluid: internal error: {type(exc).__name__}{': ' + msg if msg else ''}; this is a defect of "
          f"twofluid, please report it; {where}", file=sys.stderr)
    if where.startswith("traceback below"):
        print(text, file=sys.stderr, end="")
    return 1
