"""The shear column's tridiagonal algebra, shared by its two sub-step kernels.

Linear elements with consistent mass: the mass, damping and tangent-stiffness matrices are
tridiagonal (a diagonal of the ne + 1 nodes and one off-diagonal of the ne elements), and a
Newmark step's Newton iterate solves J du = −r by Thomas elimination on the free nodes (the base
node is held on a rigid base). Scalar loops in plain Python that numba compiles into the kernels
that call them (:mod:`twofluid.models.hysteretic_kernel`, :mod:`twofluid.models.shear_kernel`).

>>> import numpy as np
>>> md, mo, m1 = np.zeros(3), np.zeros(2), np.zeros(3)
>>> consistent_mass(np.array([6.0, 6.0]), np.array([1.0, 1.0]), md, mo, m1)
>>> md.tolist(), mo.tolist(), m1.tolist()  # ρh/3 per node and element, ρh/6 between, M·1
([2.0, 4.0, 2.0], [1.0, 1.0], [3.0, 6.0, 3.0])
"""
from __future__ import annotations

import math

__all__ = ["consistent_mass", "damping_bands", "jacobian_bands", "thomas", "newmark_rates", "inertia_residual"]


def consistent_mass(rho, h, md, mo, m1):
    """Fill the diagonal ``md`` (ne + 1), off-diagonal ``mo`` (ne) and row sums ``m1`` = M 1 of the
    consistent mass of elements of density ``rho`` and length ``h`` [kg/m², per unit area]."""
    ne = h.size
    for j in range(ne + 1):
        md[j] = 0.0
    for e in range(ne):
        me = rho[e] * h[e]
        md[e] += me / 3.0
        md[e + 1] += me / 3.0
        mo[e] = me / 6.0
    for j in range(ne + 1):
        m1[j] = md[j]
    for e in range(ne):
        m1[e] += mo[e]
        m1[e + 1] += mo[e]


def damping_bands(md, mo, a0, impedance, visc, h, cd, co):
    """Fill the damping bands ``cd``, ``co``: mass-proportional a0 M, the elements' viscosity
    ``visc`` [Pa·s] on their strain rate, and the base dashpot ``impedance`` [Pa·s/m] at node 0."""
    ne = h.size
    for j in range(ne + 1):
        cd[j] = a0 * md[j]
    cd[0] += impedance
    for e in range(ne):
        ke = visc[e] / h[e]
        cd[e] += ke
        cd[e + 1] += ke
        co[e] = -ke + a0 * mo[e]


def jacobian_bands(md, mo, cd, co, kk, c0, c1, jd, jo):
    """J = c0 M + c1 C + K with the elements' tangent stiffness ``kk`` [Pa/m] (already over h)."""
    ne = kk.size
    for j in range(ne + 1):
        jd[j] = c0 * md[j] + c1 * cd[j]
    for e in range(ne):
        jd[e] += kk[e]
        jd[e + 1] += kk[e]
        jo[e] = c0 * mo[e] + c1 * co[e] - kk[e]


def thomas(jd, jo, res, first, cp, dp, du):
    """Solve the tridiagonal J du = −res on the nodes first..ne by Thomas elimination (J is
    diagonally dominant: the mass and damping terms); ``du`` below ``first`` is left alone."""
    ne = jo.size
    nv = ne + 1
    cp[first] = jo[first] / jd[first] if first < ne else 0.0
    dp[first] = -res[first] / jd[first]
    for j in range(first + 1, nv):
        den = jd[j] - jo[j - 1] * cp[j - 1]
        if j < ne:
            cp[j] = jo[j] / den
        dp[j] = (-res[j] - jo[j - 1] * dp[j - 1]) / den
    du[ne] = dp[ne]
    for j in range(ne - 1, first - 1, -1):
        du[j] = dp[j] - cp[j] * du[j + 1]


def newmark_rates(un, u, v, a, dt, beta, gamma, acc, vel):
    """Newmark's acceleration and velocity at the end of a step from the displacement ``un``:
    a′ = (u′ − u)/(β Δt²) − v/(β Δt) − (1/(2β) − 1) a, v′ = v + Δt ((1 − γ) a + γ a′)."""
    c0 = 1.0 / (beta * dt * dt)
    ca = 0.5 / beta - 1.0
    for j in range(un.size):
        acc[j] = c0 * (un[j] - u[j]) - (v[j] / (beta * dt) + ca * a[j])
        vel[j] = v[j] + dt * ((1.0 - gamma) * a[j] + gamma * acc[j])


def inertia_residual(md, mo, m1, cd, co, acc, vel, ag, res):
    """res = M a′ + C v′ + (M 1) a_g: the nodal residual before the elements' internal forces."""
    ne = mo.size
    for j in range(ne + 1):
        res[j] = md[j] * acc[j] + cd[j] * vel[j] + m1[j] * ag
    for e in range(ne):
        res[e] += mo[e] * acc[e + 1] + co[e] * vel[e + 1]
        res[e + 1] += mo[e] * acc[e] + co[e] * vel[e]


def newton_update(un, du, first, relax):
    """un += relax du on the free nodes (from ``first``): returns the largest |du| there and the
    largest |un| after the update, or (−1, 0) where du has a non-finite entry (un then partly
    updated: the caller abandons the iterate)."""
    dmax = 0.0
    for j in range(first, un.size):
        if not math.isfinite(du[j]):
            return -1.0, 0.0
        un[j] += relax * du[j]
        if abs(du[j]) > dmax:
            dmax = abs(du[j])
    umax = 0.0
    for j in range(un.size):
        if abs(un[j]) > umax:
            umax = abs(un[j])
    return dmax, umax


HELPERS = (consistent_mass, damping_bands, jacobian_bands, thomas, newmark_rates, inertia_residual,
           newton_update)
