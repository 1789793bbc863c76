"""Lognormal fragility curves fitted by maximum likelihood (Baker 2015).

P(failure | x) = Φ(ln(x/θ)/β): θ is the median capacity (the intensity, e.g. the PGA
[g], at which half the members fail) and β the dispersion of ln capacity. Each member
is one Bernoulli trial at its intensity x_i with outcome y_i ∈ {0, 1}; θ and β maximise
Σ y_i ln Φ(z_i) + (1 − y_i) ln(1 − Φ(z_i)), z_i = ln(x_i/θ)/β (Baker 2015, "Efficient
analytical fragility function fitting using dynamic structural analysis", eq. 11).
"""
from __future__ import annotations

import numpy as np
from scipy import optimize, stats

__all__ = ["fit_lognormal_fragility", "fragility_by_level"]


def fit_lognormal_fragility(x, failed) -> dict:
    """MLE (θ, β) of a lognormal fragility curve from intensities ``x`` (> 0) and outcomes.

    The MLE exists only when the outcomes overlap in x: with no failure, only failures, or
    every failure above every survivor (perfect separation, β → 0) no (θ, β) is returned,
    but ``note`` says why and ``bounds`` brackets θ.

    Members whose failures follow Φ(ln(x/0.15)/0.5) (1000 at each of 5 levels, the count of
    failures rounded) give back θ = 0.15 g and β = 0.5:

    >>> levels = np.array([0.05, 0.1, 0.15, 0.2, 0.4])
    >>> k = np.round(1000 * stats.norm.cdf(np.log(levels / 0.15) / 0.5)).astype(int)
    >>> x = np.repeat(levels, 1000)
    >>> y = np.concatenate([np.arange(1000) < ki for ki in k])
    >>> fit = fit_lognormal_fragility(x, y)
    >>> round(fit["theta"], 3), round(fit["beta"], 2)
    (0.15, 0.5)
    >>> fit_lognormal_fragility([0.1, 0.2], [False, True])["note"]
    'perfectly separated: every member up to 0.1 survives and every one from 0.2 fails (beta -> 0)'
    """
    x = np.asarray(x, float)
    y = np.asarray(failed, bool)
    out = {"theta": None, "beta": None, "n": int(x.size), "failures": int(y.sum()),
           "bounds": [float(x.min()), float(x.max())] if x.size else None}
    if not y.any():
        return {**out, "note": "no member fails: theta is above the largest intensity"}
    if y.all():
        return {**out, "note": "every member fails: theta is below the smallest intensity"}
    lo_fail, hi_safe = x[y].min(), x[~y].max()
    if lo_fail > hi_safe:
        return {**out, "bounds": [float(hi_safe), float(lo_fail)],
                "note": f"perfectly separated: every member up to {hi_safe:g} survives and every one from "
                        f"{lo_fail:g} fails (beta -> 0)"}
    lnx = np.log(x)

    def nll(p):
        z = (lnx - p[0]) / np.exp(p[1])
        return -(stats.norm.logcdf(z[y]).sum() + stats.norm.logsf(z[~y]).sum())

    start = np.array([np.log(np.sqrt(lo_fail * hi_safe)), np.log(max(lnx.std(), 0.1))])
    res = optimize.minimize(nll, start, method="Nelder-Mead", options={"xatol": 1e-8, "fatol": 1e-10})
    return {**out, "theta": float(np.exp(res.x[0])), "beta": float(np.exp(res.x[1])),
            "log_likelihood": float(-res.fun), "note": "maximum likelihood"}


def fragility_by_level(x, failed) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(intensity levels, members at each, fraction failed at each).

    >>> fragility_by_level([0.1, 0.1, 0.2], [0, 1, 1])
    (array([0.1, 0.2]), array([2, 1]), array([0.5, 1. ]))
    """
    x = np.asarray(x, float)
    y = np.asarray(failed, float)
    levels, inv, counts = np.unique(x, return_inverse=True, return_counts=True)
    return levels, counts, np.bincount(inv, weights=y) / counts
