"""The vertical model of the liquefaction column on the reduced (W, n) formulation.

:class:`~twofluid.models.liquefaction_1d.VerticalColumn` is the full 1D two-component model
(V, W, P, n) with the ``1VW/0P/0n`` element, an impervious wall at the base and a drained
top. There continuity makes A V = 0 at every vertex, so V ≡ 0 is known, and the reduced model
(:class:`~twofluid.models.reduced_1d.Reduced1D`, Pringle 2001 sec. 4.6.2) solves the same
discrete equations with W and n as the only unknowns of one banded (pentadiagonal) system per
iterate, the pressure recovered from the liquid rows after the step. Its iterates are Newton
iterates (μ_s and 1/n linearised as well) starting from an extrapolation of the last
converged steps, so a step converges in about one iterate where the full model's Picard loop
takes two to three; at convergence both satisfy the same residuals, so the column's results
agree to the Picard tolerance (``tests/unit/test_liquefaction_fast.py``).

What the column adds to the reduced model is the velocity floor of the Picard test (see
:class:`~twofluid.models.liquefaction_1d.VerticalColumn`) and the carrying of the
extrapolation table across the column's split steps, whose vertical state is a fresh copy
with the new reference porosity.
"""
from __future__ import annotations

from .reduced_1d import Reduced1D
from .two_fluid_1d import State

__all__ = ["ReducedVerticalColumn"]


class ReducedVerticalColumn(Reduced1D):
    """Reduced (W, n) vertical model of the liquefaction column (module docstring).

    Parameters are those of :class:`~twofluid.models.liquefaction_1d.VerticalColumn`:
    ``surcharge`` [Pa] on the skeleton at the drained top, ``velocity_floor`` [m/s] of the
    Picard test; the solids flux defaults to the Galerkin form.
    """

    # the iterates are Newton's: the stepper may accept one on its predicted error (timestepping.newton)
    newton_iterates = True

    def __init__(self, mesh, materials, closures, *args, surcharge: float = 0.0,
                 velocity_floor: float = 1e-2, **kw):
        kw.setdefault("solids_flux", "galerkin")
        super().__init__(mesh, materials, closures, *args, surcharge=surcharge, **kw)
        self.velocity_floor = float(velocity_floor)

    def continue_from(self, previous: State, start: State) -> None:
        """``start`` (a copy of the converged ``previous`` with a new n̄) continues its steps: the
        extrapolated first iterate keeps the history of the steps before."""
        ex = self._extrap
        if ex.state is previous:
            ex.state = start
