"""Observed order of convergence from a mesh-refinement study.

A discretisation of order p has error ``err ≈ C h^p`` for small mesh size h, so
``log err = log C + p log h``; the observed order is the slope of that line.
Fitting all levels by least squares (rather than only the last pair) is less
sensitive to one noisy level; the per-pair rates show whether the study is in
the asymptotic range (they should approach a common value as h falls).

References
----------
Roache, P. J. (1998). *Verification and Validation in Computational Science and
Engineering*, Hermosa, ch. 5.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["ObservedOrder", "observed_order", "pairwise_orders"]


class ObservedOrder(NamedTuple):
    """Result of :func:`observed_order`.

    Attributes
    ----------
    rate : float
        Least-squares slope p of log(err) against log(h) [-].
    constant : float
        Fitted C in err ≈ C h^p [units of err / units of h^p].
    pairwise : numpy.ndarray
        Rate between consecutive levels, length ``len(h) - 1`` [-].
    """

    rate: float
    constant: float
    pairwise: NDArray[np.float64]


def _validated(h: ArrayLike, err: ArrayLike) -> tuple[NDArray, NDArray]:
    h_arr = np.asarray(h, dtype=float).ravel()
    e_arr = np.asarray(err, dtype=float).ravel()
    if h_arr.shape != e_arr.shape:
        raise ValueError(f"h and err differ in length: {h_arr.size} vs {e_arr.size}")
    if h_arr.size < 2:
        raise ValueError("need at least two refinement levels")
    if np.any(~np.isfinite(h_arr)) or np.any(h_arr <= 0.0):
        raise ValueError("mesh sizes h must be finite and positive")
    if np.any(~np.isfinite(e_arr)) or np.any(e_arr <= 0.0):
        raise ValueError("errors must be finite and positive (log of zero error)")
    if np.unique(h_arr).size != h_arr.size:
        raise ValueError("mesh sizes h must be distinct")
    return h_arr, e_arr


def pairwise_orders(h: ArrayLike, err: ArrayLike) -> NDArray[np.float64]:
    """Rate between consecutive refinement levels.

    ``p_i = log(err_{i+1}/err_i) / log(h_{i+1}/h_i)`` [-].

    Parameters
    ----------
    h : array_like
        Mesh sizes [m] (any consistent length unit), in the order of the study.
    err : array_like
        Error norms at those sizes (any unit).

    Returns
    -------
    numpy.ndarray
        ``len(h) - 1`` rates [-].

    Examples
    --------
    >>> pairwise_orders([0.1, 0.05, 0.025], [1e-2, 2.5e-3, 6.25e-4])
    array([2., 2.])
    """
    h_arr, e_arr = _validated(h, err)
    return np.diff(np.log(e_arr)) / np.diff(np.log(h_arr))


def observed_order(h: ArrayLike, err: ArrayLike) -> ObservedOrder:
    """Least-squares observed order of convergence.

    Fits ``log err = log C + p log h`` over all levels.

    Parameters
    ----------
    h : array_like
        Mesh sizes (or time steps) [m or s], at least two distinct positive values.
    err : array_like
        Positive error norms at those sizes (any unit).

    Returns
    -------
    ObservedOrder
        ``rate`` p [-], ``constant`` C, and ``pairwise`` rates [-].

    Raises
    ------
    ValueError
        If lengths differ, fewer than two levels, or any h or err is not positive.

    Examples
    --------
    >>> res = observed_order([0.1, 0.05, 0.025], [3e-3, 7.5e-4, 1.875e-4])
    >>> round(res.rate, 12), round(res.constant, 12)
    (2.0, 0.3)
    """
    h_arr, e_arr = _validated(h, err)
    slope, intercept = np.polyfit(np.log(h_arr), np.log(e_arr), 1)
    return ObservedOrder(
        rate=float(slope),
        constant=float(np.exp(intercept)),
        pairwise=np.diff(np.log(e_arr)) / np.diff(np.log(h_arr)),
    )
