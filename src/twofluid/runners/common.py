"""What every runner shares: the result record, the guard of the time loop, the dispatch.

Each runner (``column_1d``, ``flow_2d``, ``liquefaction``) has the same shape:
build the model from the resolved case, consume its generator of steps inside
:func:`run_guard`, write the summary, make the plots.
"""
from __future__ import annotations

import importlib
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..casefile.loader import load_case
from ..timestepping.backward_euler import StepFailure

__all__ = ["RunResult", "RunGuard", "run_case", "run_guard", "RUNNERS"]


@dataclass
class RunResult:
    status: str  # completed | interrupted | failed
    out_dir: Path
    summary: dict
    profiles: dict = field(default_factory=dict)  # t -> element fields
    history: dict = field(default_factory=dict)  # name -> array over steps


class _NoBar:
    """The progress bar's interface when there is none (no tqdm import for a quiet run)."""

    n = 0.0

    def update(self, dn: float) -> None:
        self.n += dn

    def reset(self, total=None) -> None:
        self.n = 0.0

    def close(self) -> None:
        pass


def _bar(t_end: float, progress: bool):
    if not progress:
        return _NoBar()
    from tqdm import tqdm

    return tqdm(total=t_end, unit="s", leave=False,
                bar_format="{l_bar}{bar}| t = {n:.4g}/{total:.4g} s simulated [{elapsed}<{remaining}]")


@dataclass
class RunGuard:
    """What :func:`run_guard` found: status, reason and the progress bar (tqdm) to update."""

    bar: object
    status: str = "completed"
    reason: str = ""


# Errors of the numerics (not of the program) that end a run as "failed" with a summary:
# SuperLU's "Factor is exactly singular" is a RuntimeError; NotImplementedError and
# RecursionError are RuntimeErrors of the program and propagate.
_NUMERICAL_ERRORS = (FloatingPointError, OverflowError, np.linalg.LinAlgError, RuntimeError)
_PROGRAM_ERRORS = (NotImplementedError, RecursionError)


@contextmanager
def run_guard(t_end: float, progress: bool, *closing):
    """Context of a run's time loop: progress bar, Ctrl-C and failed steps.

    A ``KeyboardInterrupt``, a :class:`StepFailure` or a numerical error
    (floating-point overflow, ``LinAlgError``, a ``RuntimeError`` such as a singular
    factorisation) inside the block ends the loop, not the program: the guard records status ``interrupted`` or ``failed``
    with the reason, closes the bar and every object in ``closing`` (result
    writers), and the runner goes on to write its summary from what it has.
    """
    run = RunGuard(_bar(t_end, progress))
    try:
        yield run
    except KeyboardInterrupt:
        run.status, run.reason = "interrupted", "interrupted by the user (Ctrl-C)"
    except StepFailure as exc:
        run.status, run.reason = "failed", str(exc)
    except _NUMERICAL_ERRORS as exc:  # e.g. SuperLU "Factor is exactly singular", overflow
        if isinstance(exc, _PROGRAM_ERRORS):
            raise
        run.status, run.reason = "failed", f"{type(exc).__name__}: {exc}"
    finally:
        run.bar.close()
        for c in closing:
            c.close()


# The runner of each model: "module:function", imported on use.
RUNNERS = {"two_fluid_1d": "twofluid.runners.column_1d:run_1d",
           "reduced_1d": "twofluid.runners.column_1d:run_1d",
           "two_fluid_2d": "twofluid.runners.flow_2d:run_2d",
           "liquefaction_1d": "twofluid.runners.liquefaction:run_liquefaction"}


def run_case(case, out_dir=None, progress: bool = False, plots: bool | None = None) -> RunResult:
    """Run ``case`` (resolved dict, bundled name or TOML path); write results to ``out_dir``.

    ``plots``: True/False overrides the case's ``[output] plots`` (None keeps it).
    """
    if not isinstance(case, dict):
        case = load_case(case)
    if plots is not None:
        case = {**case, "output": {**case["output"], "plots": bool(plots)}}
    mod, func = RUNNERS[case["case"]["model"]].split(":")
    return getattr(importlib.import_module(mod), func)(case, out_dir, progress=progress)


