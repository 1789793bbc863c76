"""The data of a 1D run of the two-component models: liquid and particle properties, the closure
choices, the two ends of the line, and the state (V, W, P, n, n̄) at a time.

Apart from :mod:`~twofluid.models.two_fluid_1d` (which re-exports them, their usual import) so
that the model's module holds the equations only.
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Callable

import numpy as np

from ..closures import drag as drag_laws
from ..closures.solids_pressure import exponential

__all__ = ["Materials", "Closures", "Boundary", "State"]


@dataclass(frozen=True)
class Materials:
    """Liquid and particle properties (SI)."""

    rho_f: float  # liquid density [kg/m³]
    mu_f: float  # liquid viscosity [Pa·s]
    rho_s: float  # particle density [kg/m³]
    d_p: float  # particle diameter [m]
    sphericity: float = 1.0  # ψ [-]; drag laws use d = ψ d_p
    g: float = 9.81  # |g| [m/s²]

    @property
    def d(self) -> float:
        return self.sphericity * self.d_p


@dataclass(frozen=True)
class Closures:
    """The closure choices of a run (functions from the registry with their parameters)."""

    drag: Callable = drag_laws.gidaspow
    drag_params: dict = field(default_factory=dict)
    A: float = 0.015  # solids-pressure compressibility [-]
    p_ref: float = 1.0  # [Pa]
    viscous: bool = True
    viscosity_params: dict = field(default_factory=dict)
    slip_max: float = np.inf  # [m/s] where the |slip| the law sees saturates (builder: slip_saturation × U_t)
    fluidized_pressure: Callable | None = None  # added to P_s, e.g. solids_pressure.foscolo_gibilaro
    fluidized_params: dict = field(default_factory=dict)

    def solids_pressure(self, n, n_bar, mat: Materials, derivative=False):
        """P_s(n, n̄) [Pa] (and ∂P_s/∂n): the exponential law plus the fluidized-bed term if chosen."""
        ps = exponential(n, n_bar, self.A, self.p_ref, derivative=derivative)
        if self.fluidized_pressure is None:
            return ps
        pe = self.fluidized_pressure(n, mat.d, mat.rho_s, mat.rho_f, mat.g, derivative=derivative,
                                     **self.fluidized_params)
        return (ps[0] + pe[0], ps[1] + pe[1]) if derivative else ps + pe

    def saturated_drag(self, n, slip, *args, **kw):
        """The drag law with this run's |slip| saturation (same signature as the laws)."""
        return self.drag(n, drag_laws.saturated_slip(slip, self.slip_max), *args, **kw)

    def fluidization_velocity(self, n: float, mat: Materials) -> float:
        """The superficial velocity [m/s] that holds a uniform bed of porosity ``n`` with this run's
        drag law (:func:`~twofluid.closures.drag.steady_fluidization_velocity`)."""
        return drag_laws.steady_fluidization_velocity(self.saturated_drag, n, mat.d, mat.rho_s, mat.rho_f,
                                                      mat.mu_f, mat.g, **self.drag_params)

    def beta_per_solids(self, n, slip, mat: Materials):
        return self.saturated_drag(n, slip, mat.d, mat.rho_f, mat.mu_f, per_solids=True, **self.drag_params)


@dataclass(frozen=True)
class Boundary:
    """One end of the line.

    kind: ``"inlet"`` (porous distributor: V = W = velocity(t)), ``"wall"``
    (V = W = 0) or ``"outlet"`` (prescribed liquid pressure [Pa]; solids may leave).
    """

    kind: str
    velocity: Callable[[float], float] | None = None  # superficial velocity into the domain [m/s]
    pressure: float = 0.0  # [Pa]


@dataclass
class State:
    """Fields at time t: V, W [m/s] nodal; P [Pa] (per element or nodal); n, n_bar per element."""

    t: float
    V: np.ndarray
    W: np.ndarray
    P: np.ndarray
    n: np.ndarray
    n_bar: np.ndarray

    def copy(self, **changes) -> "State":
        if type(self) is State and changes.keys() <= {"t"}:  # the stepper's copy of each step (the same)
            return State(changes.get("t", self.t), self.V.copy(), self.W.copy(), self.P.copy(), self.n.copy(),
                         self.n_bar.copy())
        s = replace(self, **{k: np.array(v, copy=True) if isinstance(v, np.ndarray) else v
                             for k, v in changes.items()})
        for k in ("V", "W", "P", "n", "n_bar"):
            if k not in changes:
                setattr(s, k, getattr(self, k).copy())
        return s


def _times(params: dict, n: int, reps: int) -> dict:
    """``params`` with every per-element array (size ``n``) repeated ``reps`` times (scalars kept)."""
    return {k: np.tile(v, reps) if np.ndim(v) and np.size(v) == n else v for k, v in params.items()}
