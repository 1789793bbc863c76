"""The Slis et al. (1959) step changes with the bed height normalised: (H(t) − H1)/(H2 − H1) against t/t1.

H1 is the bed surface's height before the step, H2 its height at the end of the run, t1 the run's
own t1 (:func:`twofluid.postprocess.t1_from_history`). In Kynch's kinematic-wave theory this curve
does not depend on the initial bed height: every front moves at a speed fixed by n0, n1 and the
equilibrium law, so a taller bed stretches the trajectory in height and time alike. The curve thus
compares twofluid with theory without the experiment's bed heights, which neither the paper's
reachable sources nor the thesis give.

Kynch's curve with a general equilibrium law U = u_eq(n) (:func:`kynch_normalised_height`): a
contraction (n1 < n0) moves the surface at the constant speed u_eq(n1) − u_eq(n0) until the shock
from the distributor meets it, so the curve is t/t1. An expansion moves it at that speed until the
fastest characteristic of the fan, of speed c(n0), reaches it at t* = H1 (1 − n0)/g(n0); inside the fan the surface sits where g(n_h) = H1 (1 − n0)/t, with
g(n) = (1 − n)² u_eq'(n) (the solids below the surface are conserved), at height c(n_h) t, with
c(n) = u_eq(n1) − u_eq(n) + (1 − n) u_eq'(n). With u_eq = U_t n^k this is
:func:`twofluid.verification.kynch.bed_height`.
"""
from __future__ import annotations

from typing import Callable

import numpy as np

__all__ = ["TAU", "kynch_normalised_height", "normalised_samples", "normalised_markdown"]

#: t/t1 at which the curves are compared (1: the band of t1 around the final height)
TAU = (0.25, 0.5, 0.75, 1.0)


def kynch_normalised_height(tau, n0: float, n1: float, u_eq: Callable[[float], float],
                            dn: float = 1e-6) -> np.ndarray:
    """Kynch's (H(t) − H1)/(H2 − H1) at t/t1 = ``tau`` (module docstring); H0-free by construction.

    ``u_eq``: the equilibrium superficial velocity [m/s] of a uniform bed of porosity n; its
    derivative by central differences of step ``dn``. With Richardson–Zaki it matches
    :func:`twofluid.verification.kynch.bed_height`:

    >>> from twofluid.verification.kynch import bed_height, step_change_t1
    >>> tau = np.array([0.2, 0.6, 0.9, 1.0, 1.3])
    >>> t1 = float(step_change_t1(0.5, 0.6, 1.0, 1.0, 2.0))
    >>> ref = (bed_height(tau * t1, 0.5, 0.6, 1.0, 1.0, 2.0) - 1.0) / 0.25
    >>> bool(np.allclose(kynch_normalised_height(tau, 0.5, 0.6, lambda n: n**2), ref, atol=1e-6))
    True
    >>> kynch_normalised_height([0.5, 2.0], 0.6, 0.5, lambda n: n**2).tolist()  # contraction
    [0.5, 1.0]
    """
    tau = np.clip(np.asarray(tau, float), 0.0, None)
    if n1 <= n0:
        return np.minimum(tau, 1.0)
    du = lambda n: (u_eq(n + dn) - u_eq(n - dn)) / (2.0 * dn)  # noqa: E731
    g = lambda n: (1.0 - n) ** 2 * du(n)  # noqa: E731
    c = lambda n: u_eq(n1) - u_eq(n) + (1.0 - n) * du(n)  # noqa: E731
    h1, s = 1.0, (1.0 - n0)  # any H1: the curve does not depend on it
    h2 = h1 * s / (1.0 - n1)
    t1 = h2 / c(n1)
    t_star = h1 * s / g(n0)
    out = []
    for t in tau * t1:
        if t <= t_star:
            h = h1 + (u_eq(n1) - u_eq(n0)) * t
        elif t >= t1:
            h = h2
        else:  # bisection for g(n_h) = H1 (1 − n0)/t, g decreasing from n0 to n1
            a, b = n0, n1
            for _ in range(60):
                m = 0.5 * (a + b)
                a, b = (m, b) if g(m) > h1 * s / t else (a, m)
            h = c(0.5 * (a + b)) * t
        out.append((h - h1) / (h2 - h1))
    return np.array(out)


def normalised_samples(t, h, t1: float, tau=TAU) -> list[float]:
    """(h − h[0])/(h[-1] − h[0]) of a history, interpolated at t/t1 = ``tau`` (NaN where t1 is not finite).

    >>> normalised_samples([0, 1, 2, 3, 4], [0.0, 1.0, 2.0, 2.0, 2.0], 2.0, (0.5, 1.0))
    [0.5, 1.0]
    """
    t, h = np.asarray(t, float), np.asarray(h, float)
    if not np.isfinite(t1) or h[-1] == h[0]:
        return [float("nan")] * len(tau)
    return [float(v) for v in (np.interp(np.asarray(tau) * t1, t, h) - h[0]) / (h[-1] - h[0])]


def normalised_markdown(table: list[dict], inventory: list[dict] | None = None) -> str:
    """Table of the normalised curves at :data:`TAU`: twofluid from the thesis's bed height, twofluid from
    the fitted amount of particles (``inventory``, another H0), Kynch with the case's drag law; below it
    the largest difference between each pair over all rows and sampled times."""
    def fmt(v):
        return " / ".join("–" if not np.isfinite(x) else f"{x:.2f}" for x in v)

    taus = " / ".join(f"{x:g}" for x in TAU)
    inv = {r["row"]: r for r in inventory or []}
    lines = [f"| row | n0 → n1 | twofluid, H0 = thesis's [at t/t1 = {taus}] | twofluid, H0 from the fitted "
             "amount of particles | Kynch, same law (any H0) |", "|---|---|---|---|---|"]
    diffs: dict = {"thesis's H0 − Kynch": [], "fitted H0 − Kynch": [], "thesis's H0 − fitted H0": []}
    for r in table:
        a, k = np.array(r.get("h_norm", [np.nan] * len(TAU))), np.array(r["h_norm_kynch"])
        b = np.array(inv[r["row"]]["h_norm"]) if r["row"] in inv else np.full(len(TAU), np.nan)
        h0b = f" (H0 = {inv[r['row']]['H0']:.2f} m)" if r["row"] in inv else ""
        lines.append(f"| {r['row']} | {r['n0']:g} → {r['n1']:g} | {fmt(a)} | {fmt(b)}{h0b} | {fmt(k)} |")
        for key, (x, y) in zip(diffs, ((a, k), (b, k), (a, b))):
            diffs[key] += list(np.abs(x - y)[np.isfinite(x - y)])
    lines += ["", "Largest difference of the normalised height over the rows and times: "
              + "; ".join(f"{key} {max(v):.3f}" if v else f"{key} –" for key, v in diffs.items()) + "."]
    return "\n".join(lines)
