"""Line meshes for 1D columns: vertices along the line, cross-section area, inclination.

The coordinate y runs along the line from the ``bottom`` end (y = y[0]) to the
``top`` end. The line makes the angle ``inclination_rad`` with the upward
vertical, so gravity along the line is −g cos θ. The cross-section area A(y)
[m²] is linear between vertices and is the measure weight: ∫ f dΩ = ∫ f A dy.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["LineMesh", "uniform_line"]


@dataclass(frozen=True)
class LineMesh:
    """A 1D mesh of ``n_elements`` two-vertex elements.

    Parameters
    ----------
    y : (n_el + 1,) vertex coordinates along the line [m], strictly increasing.
    area : (n_el + 1,) cross-section area at the vertices [m²], positive.
    inclination_rad : angle of the line to the upward vertical [rad].

    >>> m = uniform_line(1.0, 4)
    >>> m.n_elements, float(m.volumes.sum())
    (4, 1.0)
    """

    y: np.ndarray
    area: np.ndarray
    inclination_rad: float = 0.0

    def __post_init__(self):
        if np.any(np.diff(self.y) <= 0.0):
            raise ValueError("vertex coordinates must increase strictly")
        if np.any(self.area <= 0.0):
            raise ValueError("cross-section area must be positive")

    @property
    def n_elements(self) -> int:
        return len(self.y) - 1

    @property
    def lengths(self) -> np.ndarray:
        """Element lengths h [m]."""
        return np.diff(self.y)

    @property
    def centres(self) -> np.ndarray:
        return 0.5 * (self.y[1:] + self.y[:-1])

    @property
    def volumes(self) -> np.ndarray:
        """Element volumes ∫ A dy [m³] (A linear along each element)."""
        return self.lengths * 0.5 * (self.area[1:] + self.area[:-1])

    @property
    def area_slope(self) -> np.ndarray:
        """dA/dy per element [m]."""
        return np.diff(self.area) / self.lengths

    def area_at(self, e: np.ndarray, xi: np.ndarray) -> np.ndarray:
        """A at local coordinate ξ ∈ [0, 1] of elements ``e`` -> (len(e), len(ξ))."""
        a0, a1 = self.area[e][:, None], self.area[e + 1][:, None]
        return a0 + (a1 - a0) * xi[None, :]

    def gravity_along(self, g: float) -> float:
        """Component of gravity along the line (positive upward) [m/s²]."""
        return -g * float(np.cos(self.inclination_rad))

    @property
    def boundary_vertex(self) -> dict[str, int]:
        return {"bottom": 0, "top": self.n_elements}


def uniform_line(length: float, n_elements: int, area=1.0, inclination_rad: float = 0.0,
                 y0: float = 0.0) -> LineMesh:
    """Equal elements over ``[y0, y0 + length]``.

    ``area`` [m²] is a constant, a pair (bottom, top) for a linear taper, or a
    callable A(y).

    >>> m = uniform_line(2.0, 2, area=(1.0, 3.0))
    >>> m.area.tolist(), m.volumes.tolist()
    ([1.0, 2.0, 3.0], [1.5, 2.5])
    """
    y = y0 + np.linspace(0.0, length, n_elements + 1)
    if callable(area):
        a = np.asarray(area(y), dtype=float) * np.ones_like(y)
    elif np.ndim(area) == 1 and len(area) == 2:
        a = np.interp(y, [y[0], y[-1]], area)
    else:
        a = np.full_like(y, float(area))
    return LineMesh(y, a, inclination_rad)
