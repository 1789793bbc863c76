"""The shear sub-steps of one vertical step of the liquefaction column as one compiled kernel.

Same arithmetic as the reference path (:meth:`LiquefactionColumn._shear` calling
:meth:`ShearColumn.step` and the ``byrne`` law per sub-step): per sub-step G_max from
P_s(n, n̄) (Seed & Idriss 1970, the exponential law of Pringle 2001 eq. 4.30), Newmark
average acceleration with Newton iterations on the hyperbolic backbone, then Byrne's (1991)
densification of n̄ on the clipped strain. Only the tridiagonal solve differs: a Thomas
elimination here, LAPACK's banded LU with partial pivoting there (the Newmark matrix is
diagonally dominant, so both are backward stable and agree to round-off).

Compiled with numba when it is installed (the ``fast`` extra), ahead of time into a cached
extension module (:mod:`twofluid.compiled`: the first run on a machine builds it, later runs
import it without importing numba), or by ``numba.njit(cache=True)`` where that module cannot be
built; without numba the column keeps the reference path, whose cost is the Python and NumPy
call overhead on arrays of 20–80 entries (docs/benchmarks.md).
The kernel covers the common case — hyperbolic G/G_max (per-element reference strain),
Byrne's law, Newtonian liquefied-soil viscosity, the exponential P_s without a
fluidized-bed term — and reports anything else it meets (a Newton failure, a non-finite
value) so that the caller repeats the step on the reference path, which halves or raises.

>>> import numpy as np
>>> ok = available()  # numba installed?
>>> isinstance(ok, bool)
True
"""
from __future__ import annotations

import math

import numpy as np

from . import newmark_bands as _nb

__all__ = ["available", "compiled", "shear_substeps"]

_MAX_EXPONENT = 700.0  # as closures.solids_pressure
_KPA = 1000.0  # as closures.shear_modulus


def _substeps(u, v, a, gamma, tau, nb, eps_v, gamma_a, hist_g, direction, path,  # state (in/out)
              n, A, p_ref, k2max, g_crust, rho, eta, h, gamma_ref, c1, c2, liq, cap,
              a0, a1, impedance, first, tol, max_iter, t0, dt, a_in, shaking_end, surface):
    """Advance len(a_in) sub-steps in place; returns 0, or 1 where the reference path must take over."""
    ne = h.size
    ns = n.size
    nv = ne + 1
    m = a_in.size
    md = np.zeros(nv)
    mo = np.empty(ne)
    m1 = np.empty(nv)  # M 1
    _nb.consistent_mass(rho, h, md, mo, m1)
    visc = np.empty(ne)
    gmax = np.empty(ne)
    cd = np.empty(nv)
    co = np.empty(ne)
    un = np.empty(nv)
    acc = np.empty(nv)
    vel = np.empty(nv)
    res = np.empty(nv)
    jd = np.empty(nv)
    jo = np.empty(ne)
    kk = np.empty(ne)
    cp = np.empty(nv)
    dp = np.empty(nv)
    du = np.zeros(nv)
    gt0 = np.empty(ne)
    c0 = 1.0 / (0.25 * dt * dt)
    cc1 = 0.5 / (0.25 * dt)
    for i in range(m):
        t = t0 + (i + 1) * dt
        # G_max from P_s(n, n̄) of the saturated elements; the crust's is fixed
        for e in range(ns):
            one_m = 1.0 - n[e]
            if one_m > 0.0:
                ps = p_ref[e] * math.exp(min((1.0 - (1.0 - nb[e]) / one_m) / A[e], _MAX_EXPONENT))
            else:
                ps = 0.0
            gmax[e] = 218.8 * _KPA * k2max[e] * math.sqrt(max(ps, 0.0) / _KPA)
        for e in range(ns, ne):
            gmax[e] = g_crust[e - ns]
        for e in range(ne):
            if not (math.isfinite(gmax[e]) and gmax[e] >= 0.0):
                return 1
        ag = a_in[i]
        if not math.isfinite(ag):
            return 1
        # damping bands with the tangent modulus at the start of the step
        for e in range(ne):
            x = 1.0 + abs(gamma[e]) / gamma_ref[e]
            gt0[e] = 1.0 / (x * x)
        for e in range(ne):
            visc[e] = eta[e] + a1 * gmax[e] * gt0[e]
        _nb.damping_bands(md, mo, a0, impedance, visc, h, cd, co)
        for j in range(nv):
            un[j] = u[j] + dt * v[j] + 0.5 * dt * dt * a[j]
        if first == 1:
            un[0] = 0.0
        converged = False
        for _ in range(max_iter):
            _nb.newmark_rates(un, u, v, a, dt, 0.25, 0.5, acc, vel)
            _nb.inertia_residual(md, mo, m1, cd, co, acc, vel, ag, res)
            for e in range(ne):
                g = (un[e + 1] - un[e]) / h[e]
                x = 1.0 + abs(g) / gamma_ref[e]
                te = gmax[e] * (g / x)
                res[e] -= te
                res[e + 1] += te
                kk[e] = gmax[e] * (1.0 / (x * x)) / h[e]
            _nb.jacobian_bands(md, mo, cd, co, kk, c0, cc1, jd, jo)
            _nb.thomas(jd, jo, res, first, cp, dp, du)  # J du = −res on the free nodes
            dmax, umax = _nb.newton_update(un, du, first, 1.0)
            if dmax < 0.0:
                return 1
            if dmax <= tol * max(umax, 1e-9):
                converged = True
                break
        if not converged:
            return 1
        _nb.newmark_rates(un, u, v, a, dt, 0.25, 0.5, acc, vel)
        for e in range(ne):
            g = (un[e + 1] - un[e]) / h[e]
            x = 1.0 + abs(g) / gamma_ref[e]
            gamma[e] = g
            tau[e] = gmax[e] * (g / x) + (eta[e] + a1 * gmax[e] * gt0[e]) * ((vel[e + 1] - vel[e]) / h[e])
        for j in range(nv):
            u[j] = un[j]
            v[j] = vel[j]
            a[j] = acc[j]
        surface[i] = (ag if t <= shaking_end + 1e-12 else 0.0) + a[ne]
        # Byrne's densification on the clipped strain of the saturated elements
        for e in range(ns):
            gl = min(max(gamma[e], -cap[e]), cap[e])
            dg = gl - hist_g[e]
            sgn = 1.0 if dg > 0.0 else (-1.0 if dg < 0.0 else 0.0)
            if sgn != 0.0 and direction[e] != 0.0 and sgn != direction[e]:
                peak = abs(gl - dg)
            else:
                peak = gamma_a[e]
            peak = max(peak, abs(gl))
            step = abs(dg)
            if peak > 0.0 and step > 0.0:
                growth = 0.25 * c1[e] * c2[e] * (step / peak) * math.exp(-c2[e] * eps_v[e] / peak)
                deps = peak / c2[e] * math.log1p(growth)
            else:
                deps = 0.0
            if liq[e]:
                nb[e] = nb[e] - (1.0 - nb[e]) * math.expm1(deps)
            eps_v[e] += deps
            gamma_a[e] = peak
            hist_g[e] = gl
            if sgn != 0.0:
                direction[e] = sgn
            path[e] += step
    return 0


_COMPILED = None
_TRIED = False
#: the kernel's argument types (C-contiguous float64 arrays, floats, integers) for the ahead-of-time build
SIGNATURE = "i8(" + ", ".join(["f8[::1]"] * 24 + ["f8", "f8", "f8", "i8", "f8", "i8", "f8", "f8", "f8[::1]",
                                                  "f8", "f8[::1]"]) + ")"


def available() -> bool:
    """Whether the compiled kernel can be used (numba installed, or its module already built)."""
    return _kernel() is not None


def _kernel():
    global _COMPILED, _TRIED
    if not _TRIED:
        _TRIED = True
        from ..compiled import group

        out = group("shear_substeps", {"shear_substeps": (_substeps, SIGNATURE)}, helpers=_nb.HELPERS)
        _COMPILED = None if out is None else out["shear_substeps"]
    return _COMPILED


def compiled():
    """The compiled kernel (taking the arguments of ``_substeps``, arrays C-contiguous), or None
    where numba is not installed. The caller holds it, so that a call is the dispatch alone."""
    return _kernel()


def shear_substeps(*args) -> int:
    """Run the compiled kernel (arguments as ``_substeps``); 1 if it is not available."""
    k = _kernel()
    if k is None:
        return 1
    return int(k(*args))
