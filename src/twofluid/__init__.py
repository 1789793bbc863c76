"""twofluid: finite element model of saturated granular material and liquid moving together.

The public facade. A script usually needs only these::

    >>> import twofluid
    >>> case = twofluid.load_case("settling-illite")   # bundled name or path to a TOML file
    >>> case["materials"]["particle_diameter"]
    6.25e-05

then ``twofluid.run_case(case, out_dir)`` to run it (results and summary as
``twofluid run`` writes them; ``out_dir=None`` keeps them in memory only, in
``RunResult.tables``) or ``twofluid.build(case)`` for the model and
initial state to drive ``twofluid.integrate`` yourself; ``twofluid.run_ensemble(path)``
runs an ensemble file's members on Dask and returns their results table. An edited case
is validated again by ``run_case`` exactly as a case file (``CaseError``).
"""
__version__ = "0.1.0"

_EXPORTS = {
    "build": "twofluid.casefile.builder",
    "bundled_cases": "twofluid.casefile.loader",
    "load_case": "twofluid.casefile.loader",
    "CaseError": "twofluid.casefile.schema",
    "RunResult": "twofluid.runners",
    "run_case": "twofluid.runners",
    "run_ensemble": "twofluid.ensemble",
    "PicardSettings": "twofluid.timestepping.backward_euler",
    "StepFailure": "twofluid.timestepping.backward_euler",
    "integrate": "twofluid.timestepping.backward_euler",
}
__all__ = ["__version__", *_EXPORTS]


def __dir__() -> list[str]:
    """The public names (tab completion), imported lazily by :func:`__getattr__`."""
    return sorted({*globals(), *__all__})


def __getattr__(name: str):
    """Import the facade's names on first use (keeps ``python -m twofluid.<module>`` clean)."""
    if name in _EXPORTS:
        import importlib

        return getattr(importlib.import_module(_EXPORTS[name]), name)
    raise AttributeError(f"module 'twofluid' has no attribute {name!r}")
