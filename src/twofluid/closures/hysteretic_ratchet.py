"""The hysteretic law's strain after triggering: once triggered, the centre of the dilation zone γ_c
follows the mean strain of the half cycles, and the dilation weakens with how far it has moved
(module docstring of :mod:`twofluid.closures.hysteretic`, "Strain after triggering"). On level
ground the half cycles' mean strain stays at γ_c and nothing changes; on a slope it moves downslope
by each cycle's increment, so the element re-enters the zone every cycle and the strain keeps
accumulating. Scalar functions numba compiles with the law's kernel and that also run un-jitted.
"""
from __future__ import annotations

import math

from .hysteretic_layout import (NPARAM, NSTATE, P_GDR, P_GW, P_KC, S_GC, S_GC0, S_GREV, S_LIQ, S_RAT, S_T, S_TREV)


__all__ = ['start', 'follow_mean', 'dilation_strain']


GAMMA_TRIGGER = 0.03  # single-amplitude strain of the laboratory's liquefaction criterion [-]


def start(g, st, e):
    """Start the strain after triggering of element ``e`` at strain ``g`` once it has triggered:
    liquefied (D ≥ 1, ``S_LIQ``) or strained by the laboratory's 3 % from its centre, whichever
    comes first (the element test's two criteria); the drift of γ_c is measured from there,
    γ_c0 = γ_c. Before, nothing of this module acts."""
    if st[e, S_LIQ] > 0.0 or abs(g - st[e, S_GC]) >= GAMMA_TRIGGER:
        st[e, S_RAT] = 1.0
        st[e, S_GC0] = st[e, S_GC]


def follow_mean(g_rev, st, par, e):
    """A triggered element ``e`` reversed at ``g_rev`` (stress ratio τ/τ_max ``S_T``) after the
    half cycle from its previous reversal γ_p (``S_GREV``, ratio ``S_TREV``; neither yet updated):
    where the stress at ``g_rev`` is within the strength, |τ/τ_max| ≤ 1 (not held by dilation),
    γ_c moves towards the half cycle's mean strain γ_m = (g_rev + γ_p)/2 by the share κ w of the
    way, w = min(1, |Δ(τ/τ_max)|/2): a half cycle across the whole strength range counts fully, a
    small wiggle by its size. The stress at the reversal lies within the strength and so within the envelope max(τ_max, τ_d) wherever the centre is: the
    move changes no stress at the committed strain.

    >>> import numpy as np
    >>> st = np.zeros((1, NSTATE)); par = np.zeros((1, NPARAM)); par[0, P_KC] = 0.5
    >>> st[0, S_GREV] = 0.02; st[0, S_TREV] = -0.5   # half cycle 0.02 → 0.04
    >>> st[0, S_T] = 0.5; follow_mean(0.04, st, par, 0); round(float(st[0, S_GC]), 6)  # 0.5 · 0.5 · 0.03
    0.0075
    >>> st[0, S_T] = 1.4; follow_mean(0.05, st, par, 0); round(float(st[0, S_GC]), 6)  # on a dilation stop
    0.0075
    """
    k = par[e, P_KC]
    if k <= 0.0 or abs(st[e, S_T]) > 1.0:
        return
    gp = st[e, S_GREV]
    w = min(0.5 * abs(st[e, S_T] - st[e, S_TREV]), 1.0)
    st[e, S_GC] += k * w * (0.5 * (g_rev + gp) - st[e, S_GC])


def dilation_strain(st, par, e):
    """γ_dr [-] of element ``e``: the parameter's, and once triggered stretched by the centre's
    drift, γ_dr (1 + √(|γ_c − γ_c0| / γ_w)) (γ_w ≤ 0: not stretched)."""
    gdr = par[e, P_GDR]
    gw = par[e, P_GW]
    if st[e, S_RAT] <= 0.0 or gw <= 0.0:
        return gdr
    return gdr * (1.0 + math.sqrt(abs(st[e, S_GC] - st[e, S_GC0]) / gw))
