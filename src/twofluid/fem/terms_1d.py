"""Weak-form terms on 1D elements: small functions returning element arrays.

Each term takes :class:`~twofluid.fem.line.ElementValues` (whose ``JxW``
already carries the measure A(y)) and coefficients that are constant per
element (shape (n_el,)) or per quadrature point (n_el, nq). Matrices are
(n_el, n_test, n_trial); vectors (n_el, n_test).
"""
from __future__ import annotations

import numpy as np

from .line import ElementValues

__all__ = ["mass", "diffusion", "source", "divergence", "weighted_gradient"]


def _coef(c, ev: ElementValues) -> np.ndarray:
    c = np.asarray(c, dtype=float)
    if c.ndim == 1:
        c = c[:, None]
    return np.broadcast_to(c, ev.JxW.shape) * ev.JxW


def mass(ev: ElementValues, c=1.0) -> np.ndarray:
    """∫ c N_i N_j dΩ.

    >>> from twofluid.fem.line import element_values, LINE1
    >>> from twofluid.mesh.line import uniform_line
    >>> mass(element_values(uniform_line(1.0, 1), LINE1))[0].round(12).tolist()
    [[0.333333333333, 0.166666666667], [0.166666666667, 0.333333333333]]
    """
    return np.einsum("eq,qi,qj->eij", _coef(c, ev), ev.N, ev.N)


def diffusion(ev: ElementValues, c=1.0) -> np.ndarray:
    """∫ c dN_i/dy dN_j/dy dΩ."""
    return np.einsum("eq,eqi,eqj->eij", _coef(c, ev), ev.dN, ev.dN)


def source(ev: ElementValues, c=1.0) -> np.ndarray:
    """∫ c N_i dΩ."""
    return np.einsum("eq,qi->ei", _coef(c, ev), ev.N)


def divergence(ev: ElementValues, q: np.ndarray, c=1.0) -> np.ndarray:
    """∫ c q_a ∇·N_j dΩ for a pressure-like basis ``q`` (nq, n_q) -> (n_el, n_q, n_v).

    With q = 1 (constant per element) this is [A N_j] at the element ends.
    """
    return np.einsum("eq,qa,eqj->eaj", _coef(c, ev), q, ev.div)


def weighted_gradient(ev: ElementValues, dq: np.ndarray, c=1.0) -> np.ndarray:
    """∫ c N_i dq_a/dy dΩ for a pressure basis gradient ``dq`` (n_el, nq, n_q)."""
    return np.einsum("eq,qi,eqa->eia", _coef(c, ev), ev.N, dq)
