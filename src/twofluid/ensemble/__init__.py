"""Ensembles of runs on Dask: suites of ground motions, PGA sweeps, Monte Carlo, sensitivity.

``twofluid ensemble FILE --out DIR`` and :func:`run_ensemble` read an ensemble file
(:mod:`.spec`), make its members (:mod:`.members`), run them on ``dask.distributed``
(:mod:`.engine`) and write ``members.csv``, ``ensemble.json`` (:mod:`.results`) and the
plots (:mod:`.plots`). See docs/ensembles.md.
"""
from .engine import run_ensemble, run_members
from .spec import EnsembleSpec, load_ensemble, parse_ensemble

__all__ = ["run_ensemble", "run_members", "EnsembleSpec", "load_ensemble", "parse_ensemble"]
