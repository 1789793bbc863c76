"""twofluid: finite element model of saturated granular material and liquid moving together.

The public facade. A script usually needs only these::

    >>> import twofluid
    >>> case = twofluid.load_case("settling-illite")   # bundled name or path to a TOML file
    >>> case["materials"]["particle_diameter"]
    6.25e-05

then ``twofluid.run_case(case, out_dir)`` to run it (results and summary as
``twofluid run`` writes them) or ``twofluid.build(case)`` for the model and
initial state to drive ``twofluid.integrate`` yourself.
"""
__version__ = "0.1.0"

from .casefile.builder import build
from .casefile.loader import bundled_cases, load_case
from .casefile.schema import CaseError
from .simulation import RunResult, run_case
from .timestepping.backward_euler import PicardSettings, StepFailure, integrate

__all__ = ["__version__", "build", "bundled_cases", "load_case", "CaseError", "RunResult", "run_case",
           "PicardSettings", "StepFailure", "integrate"]
