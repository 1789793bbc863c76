"""Key figures of a run, with their written definitions.

Bed surface height H(t) of a run (:func:`interface_height`, the runner's figures and plots):
scanning down from the top, k is the first element whose porosity falls below a threshold
(midway between clear liquid and the bed porosity); the solids of element k and of every
element above it are laid on the top face of the element below k, at that element's
porosity. In words: the interface lies inside the element where the porosity crosses the
threshold, at the height that element's solids fill at the bed's porosity. A uniform bed
with a partly filled top element (the state :func:`twofluid.casefile.bed.bed_porosity`
builds) has its surface exactly where it was built, and the height moves continuously and
in proportion to the solids as the front crosses an element, without the staircase a
whole-element position gives.

:func:`surface_height` is the earlier definition, kept unchanged for the Slis table and the
Kynch checks (frozen, so that their numbers change only with the drag law): the height where the element-centre porosity first falls
below the threshold, by linear interpolation between the two centres around the crossing.

t1 of a step change: the first time after which the bed surface stays within
``band`` (default 2 %) of the total change |H_end − H_0| of its final height.
Applied unchanged to the exact Kynch trajectory when comparing.

Settling interfaces: the top (clear liquid / suspension) interface is the bed
surface with threshold (1 + n0)/2; the sediment interface is the highest height
below it where the porosity falls below n0 − ``drop`` (default 0.01).
"""
from __future__ import annotations

import numpy as np

__all__ = ["median", "surface_height", "interface_height", "t1_from_history", "sediment_height"]


def median(values) -> float:
    """The median of ``values`` (NaN for none, and where one is NaN): ``np.median``'s value, taken from
    the sorted entries.

    ``np.median`` imports ``numpy.ma`` (~10–16 ms of a run's start-up) to check for NaN.

    >>> median([3.0, 1.0, 2.0]), median([4.0, 1.0, 2.0, 3.0]), median([1.0, float("nan"), 2.0])
    (2.0, 2.5, nan)
    """
    v = np.sort(np.asarray(values, dtype=float).ravel())
    m = v.size
    if not m or v[-1] != v[-1]:  # (the sort puts NaN last)
        return float("nan")
    return float(0.5 * (v[(m - 1) // 2] + v[m // 2]))


def surface_height(y: np.ndarray, n: np.ndarray, threshold: float, bottom: float = 0.0) -> float:
    """Height [m] (above ``bottom``) of the highest downward crossing of ``threshold``.

    >>> surface_height(np.array([0.5, 1.5, 2.5]), np.array([0.6, 0.6, 1.0]), 0.8)
    2.0
    >>> surface_height(np.array([0.5, 1.5]), np.array([1.0, 1.0]), 0.8)
    0.0
    """
    below = np.nonzero(n < threshold)[0]
    if below.size == 0:
        return 0.0
    j = below[-1]
    if j == len(n) - 1:
        return float(y[-1] + 0.5 * (y[-1] - y[-2]) - bottom) if len(y) > 1 else float(y[-1] - bottom)
    f = (threshold - n[j]) / (n[j + 1] - n[j])
    return float(y[j] + f * (y[j + 1] - y[j]) - bottom)


def interface_height(faces: np.ndarray, n: np.ndarray, threshold: float,
                     lengths: np.ndarray | None = None) -> float:
    """Height [m] above ``faces[0]`` of the bed surface interpolated within its element (module docstring).

    ``faces``: the element faces [m] (``n.size + 1`` of them, increasing); ``n``: element porosities;
    ``lengths``: ``faces[1:] - faces[:-1]`` if the caller has it (a run asks every step).
    0 when no element is below ``threshold``.

    >>> faces = np.array([0.0, 1.0, 2.0, 3.0])
    >>> interface_height(faces, np.array([0.6, 0.6, 0.9]), 0.8)   # the top element a quarter full
    2.25
    >>> interface_height(faces, np.array([0.6, 0.7, 1.0]), 0.8)   # element 1 three quarters full
    1.75
    >>> interface_height(faces, np.array([1.0, 1.0, 1.0]), 0.8)
    0.0
    """
    up = n[::-1] < threshold  # (called every step: the highest element below it by one argmax)
    j = int(up.argmax())
    if not up[j]:
        return 0.0
    k = n.size - 1 - j
    r = k - 1 if k > 0 else 0  # the element whose porosity the solids above are laid at
    dy = faces[k + 1:] - faces[k:-1] if lengths is None else lengths[k:]
    solids = float(np.dot(1.0 - np.minimum(n[k:], 1.0), dy))
    return float(faces[k] + solids / (1.0 - n[r]) - faces[0])


def sediment_height(y: np.ndarray, n: np.ndarray, n0: float, top: float, drop: float = 0.01,
                    bottom: float = 0.0) -> float:
    """Height [m] of the sediment interface below ``top`` (see module docstring)."""
    keep = (y - bottom) < top
    if not keep.any():
        return 0.0
    return surface_height(y[keep], n[keep], n0 - drop, bottom) if (n[keep] < n0 - drop).any() else 0.0


def t1_from_history(t: np.ndarray, h: np.ndarray, band: float = 0.02) -> float:
    """First time after which |h − h[-1]| ≤ band·|h[-1] − h[0]| holds to the end [s].

    >>> t = np.linspace(0, 10, 101); h = np.minimum(t, 5.0)
    >>> round(t1_from_history(t, h), 6)
    4.9
    """
    t, h = np.asarray(t), np.asarray(h)
    tol = band * abs(h[-1] - h[0])
    outside = np.nonzero(np.abs(h - h[-1]) > tol)[0]
    if outside.size == 0:
        return float(t[0])
    i = outside[-1]
    if i + 1 >= len(t):
        return float("nan")
    # interpolate the crossing of the band between samples i and i+1
    target = h[-1] + np.sign(h[i] - h[-1]) * tol
    f = (h[i] - target) / (h[i] - h[i + 1]) if h[i] != h[i + 1] else 1.0
    return float(t[i] + f * (t[i + 1] - t[i]))
