"""The hysteretic law's damage count: half cycles of stress found by rainflow counting, each worth
f_t/(2 N_L), N_L = 15 (CRR/CSR)^(1/b), and the generated excess pore-pressure ratio of Seed &
Booker (module docstring of :mod:`twofluid.closures.hysteretic`, "Pore-pressure generation").
Scalar functions numba compiles with the law's kernel and that also run un-jitted.
"""
from __future__ import annotations

import math

from .hysteretic_layout import (P_ALPHA, P_B, P_CRR, P_GT, P_RCAP, P_SIG0, RF_SIZE, S_D, S_DPART, S_G, S_RF, S_RFDIR, S_RFN, S_TAU)

__all__ = ['seed_booker', 'half_cycle_damage', 'generated_ratio']


def seed_booker(damage, alpha):
    """Seed & Booker (1977) r_u = (2/π) arcsin(D^(1/(2α))) for damage D = N/N_L ≥ 0 (1 at D ≥ 1).

    >>> seed_booker(0.0, 0.7), seed_booker(2.0, 0.7)
    (0.0, 1.0)
    """
    if damage <= 0.0:
        return 0.0
    if damage >= 1.0:
        return 1.0
    return 2.0 / math.pi * math.asin(damage ** (0.5 / alpha))


def half_cycle_damage(ta, ga, par, e):
    """Damage of a half cycle of stress amplitude ``ta`` [Pa] and strain amplitude ``ga`` [-]."""
    return _half_cycle_damage_of(ta, ga, par[e, P_GT], par[e, P_SIG0], par[e, P_CRR], par[e, P_B])


def _half_cycle_damage_of(ta, ga, gt, sig0, crr, b):
    """:func:`half_cycle_damage` from the element's γ_t, σ′_v0, CRR and b given (no array in a function
    that branches: compiled, each array such a function takes costs a reference count in and out)."""
    ft = (ga - gt) / gt
    if ft <= 0.0 or ta <= 0.0:
        return 0.0
    if ft > 1.0:
        ft = 1.0
    csr = ta / sig0
    return ft / 30.0 * (csr / crr) ** (1.0 / b)


def _count_damage(g, tau, st, e, gt, sig0, crr, b):
    """Count the damage of element ``e`` at its new stress ``tau`` [Pa] and strain ``g``, before
    they are committed: half cycles of stress found by rainflow counting (ASTM E1049's three-point
    rule, applied as the history arrives), each weighted by :func:`half_cycle_damage` (of the
    element's γ_t ``gt``, σ′_v0 ``sig0`` [Pa], CRR ``crr`` and b ``b``, given as floats: compiled, the
    parameter array would cost a reference count in and out per call).

    The stack holds the stress turning points still open. A turning point of the stress ends the
    current half cycle, whose damage is then counted, and is pushed. When the stress goes past the
    turning point before the last one, the inner pair closes a full cycle: its second half is
    counted, its damage equal to the first's, and the outer half cycle resumes from its own start,
    so the damage already counted for that half cycle up to the inner turning point is withdrawn;
    the partial damage is then measured from there. A small wiggle within a large half cycle so
    costs the large one nothing, as it costs a specimen nothing in the laboratory: counted from the
    last reversal alone, each wiggle would split the half cycle, and with damage ∝ CSR^(1/b),
    1/b ≈ 10 for loose sand, that would remove almost all of its damage."""
    k = int(st[e, S_RFN]) - 1
    t_old = st[e, S_TAU]
    dt = tau - t_old
    dnew = 1.0 if dt > 0.0 else (-1.0 if dt < 0.0 else 0.0)
    dold = st[e, S_RFDIR]
    if dold != 0.0 and dnew != 0.0 and dnew != dold:  # the stress turned at the committed point
        h = st[e, S_DPART]
        st[e, S_D] += h
        st[e, S_DPART] = 0.0
        if k == RF_SIZE - 1:  # full: the oldest turning point goes (its half cycles stay counted)
            for j in range(RF_SIZE - 1):
                for q in range(3):
                    st[e, S_RF + 3 * j + q] = st[e, S_RF + 3 * (j + 1) + q]
            k -= 1
        k += 1
        st[e, S_RF + 3 * k] = t_old
        st[e, S_RF + 3 * k + 1] = st[e, S_G]
        st[e, S_RF + 3 * k + 2] = h
    if dnew != 0.0:
        st[e, S_RFDIR] = dnew
    closed = False
    while k >= 1 and abs(tau - st[e, S_RF + 3 * k]) >= abs(st[e, S_RF + 3 * k] - st[e, S_RF + 3 * (k - 1)]):
        if k == 1:  # past the start: the first half cycle stays counted, and the start goes
            for q in range(3):
                st[e, S_RF + q] = st[e, S_RF + 3 + q]
            st[e, S_RF + 2] = 0.0
            k = 0
        else:  # the inner cycle closes; the outer half cycle resumes from its start
            st[e, S_D] += st[e, S_RF + 3 * k + 2] - st[e, S_RF + 3 * (k - 1) + 2]
            k -= 2
        closed = True
    st[e, S_RFN] = k + 1
    dd = _half_cycle_damage_of(0.5 * abs(tau - st[e, S_RF + 3 * k]), 0.5 * abs(g - st[e, S_RF + 3 * k + 1]), gt, sig0, crr, b)
    if closed or dd > st[e, S_DPART]:
        st[e, S_DPART] = dd


def generated_ratio(st, par, e):
    """r_g of element ``e`` from its damage (Seed–Booker, capped at r_cap) [-]."""
    return _generated_ratio_of(st[e, S_D] + st[e, S_DPART], par[e, P_ALPHA], par[e, P_RCAP])


def _generated_ratio_of(damage, alpha, cap):
    """:func:`generated_ratio` from the damage, α and r_cap given (no array in a function that branches)."""
    r = seed_booker(damage, alpha)
    return r if r < cap else cap


def _generated_ratio_known(damage, alpha, cap, dk, rk):
    """:func:`_generated_ratio_of` the ``damage`` given, or ``rk`` where ``damage`` is ``dk`` and ``rk``
    is the ratio computed of ``dk`` before (with the same α and r_cap): the same number, without its
    power and arcsine. The column's commits keep each element's last one, as most sub-steps leave
    the damage as it was (no half cycle grows beyond the threshold strain).

    >>> r = _generated_ratio_of(0.3, 0.7, 0.999)
    >>> _generated_ratio_known(0.3, 0.7, 0.999, 0.3, r) == r, _generated_ratio_known(0.3, 0.7, 0.999, 0.2, -1.0) == r
    (True, True)
    """
    if damage == dk:
        return rk
    return _generated_ratio_of(damage, alpha, cap)
