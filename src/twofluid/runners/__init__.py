"""Runners: how a run of each model happens (build -> steps -> consumers -> summary).

``run_case`` dispatches on ``[case] model`` to ``column_1d.run_1d``,
``flow_2d.run_2d`` or ``liquefaction.run_validated``.
"""
from .common import RunGuard, RunResult, run_case, run_guard

__all__ = ["RunGuard", "RunResult", "run_case", "run_guard"]
