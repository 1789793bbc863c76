"""The shear sub-steps of the liquefaction column with the hysteretic law, written once.

One vertical step's shear sub-steps: Newmark average acceleration (β = 1/4, γ = 1/2) on linear
elements with consistent mass (:mod:`twofluid.models.shear_column` has the equations and the
compliant base), Newton iterations on the element stresses of
:mod:`twofluid.closures.hysteretic` with each element's branch (its direction of motion) fixed
and what that branch needs of the committed state prepared once per sub-step
(``closures.hysteretic._prepare``: its reversal points, MRDF factor, origins), the stiffness the
analytic slope dτ/dγ of the branch that sets each element's stress, evaluated with the stress,
then a check of each branch against the direction the converged strain moved (the sub-step is
solved again where one was wrong: an element whose motion reversed within the sub-step is not
committed on its loading branch), then each element's commit (reversals, damage) and the
pore-pressure generation as a change of n̄, counted at the stress the generation leaves
(:func:`twofluid.closures.hysteretic.commit_generating`) on the element's whole shear stress. The small-strain viscous floor is Rayleigh damping:
mass-proportional a0 ρ̄ u̇ and stiffness-proportional a1 G_max(P_s) γ̇ with the *current*
small-strain modulus (not the tangent, which is zero while the skeleton yields, and not the
initial one, which would keep a viscous strength after liquefaction), plus the liquefied-soil
and mixture viscosity η γ̇.

The porosity of the saturated elements moves linearly over the vertical step from ``n`` by
``dn`` (the previous step's change: the vertical model's drainage, extrapolated), so P_s — and
with it the strength — changes smoothly from sub-step to sub-step instead of jumping at every
vertical step. An element whose P_s cannot change over the call (:func:`_fixed_strength`: above the
water table, or saturated with ``dn`` = 0 and no generation, as in the total-stress companion run)
has its strength, G_max and viscosity computed at the first sub-step only, and with every element
so the damping bands too; each element's MRDF factor is kept while what it depends on (γ_m, γ_r,
r_g) is the same (:func:`_kept_factor`). Both give the same numbers, bit for bit, as computing them
at every sub-step. So does the outer branch an element's loop closes onto (three or more open
reversal points) left unevaluated while the current branch lies far below it in the direction of
motion: the branch is monotone there, so its stress at the committed strain, less a margin far above
round-off (``closures.hysteretic._outer_floor``), is a floor of it for the sub-step's strains
(:func:`_keep_floor`, ``closures.hysteretic._stress_below``). The branches of each element are
prepared once per sub-step, and again only for the elements whose direction the check after Newton's
iterations reversed, inline in the sub-step's loop: a helper function called per element and
sub-step with the kernel's work arrays cost a reference count of each array per call. They are
prepared again only where what they depend on changed (:func:`_prepared_same`: no reversal pushed
since, the same open points, largest strain, r_g, strength, γ_r and γ_d): in total stress most
elements move on along the same branches for many sub-steps. A commit's stress, and an outer branch
until it proves the lower, are evaluated without their slopes (``closures.hysteretic._stress_value``
and the law's ``*_value`` functions: the same operations, so the same numbers); an outer branch
evaluated at a Newton iterate or a commit gives a floor from that strain on as well
(:func:`_keep_seen`, :func:`_floor_for`); a commit that only moves the strain (no damage to count, no
reversal, no loop that may close, within γ_m: :func:`_moves_on`) writes those three numbers in place;
and the commit with generation hands back the generated ratio it computed, not computed again, and
is handed each element's last one with the damage it is of (``keep``), used again where a commit
leaves the damage as it was (``closures.hysteretic_damage._generated_ratio_known``: the same number).

The total-stress companion's call (its last argument ``quick`` 1) stops Newton's iterations as well
once the next update, at the rate the last two contracted by, would be within the tolerance
(:func:`_contracted`): the same solution to far below the tolerance, without the update that only
confirms it; the two-fluid run's calls (``quick`` 0) iterate as before, to the bit.

The same source runs compiled (:func:`compiled`, numba, built ahead of time by
:mod:`twofluid.compiled`) and as plain Python (``TWOFLUID_DISABLE_JIT=1`` or
:func:`substeps` with ``jit=False``), which is slow but steps through in a debugger.

>>> import numpy as np
>>> callable(compiled()) or compiled() is None
True
"""
from __future__ import annotations

import math

import numpy as np

from ..closures import hysteretic as _law
from ..closures import hysteretic_backbone as _hb, hysteretic_damage as _hd, hysteretic_dilation as _hz, hysteretic_flow as _hf, hysteretic_memory as _hm, hysteretic_ratchet as _hr
from . import newmark_bands as _nb
from ..closures.hysteretic import P_LIQ, P_SIG0, S_DIR, S_EPS, S_G, S_GC, S_GD, S_GM, S_LIQ, S_NREV, S_NSTK, S_RG, S_STK, S_T, S_TAU

__all__ = ["substeps", "element_cycles", "compiled", "SIGNATURE"]

_MAX_EXPONENT = 700.0
_NKEY = 10  # what an outer branch's floor depends on (_keep_floor)
_NPKEY = 8  # what an element's prepared branches depend on (_prepared_key)


def _substeps(u, v, a, st, par, nb, n, dn, A, p_ref, rho, eta, h, ns, a0, a1, impedance, first,
              tol, max_iter, t0, dt, a_in, shaking_end, surface, tau_out, nm_beta, nm_gamma, body, rho_b, quick):
    """Advance len(a_in) sub-steps in place; returns 0, 1 (Newton did not converge: halve the
    sub-step) or 2 (a non-finite value). ``surface`` [m/s²]: the absolute acceleration (record while
    it shakes plus the node's relative acceleration) of the surface node after each sub-step (size
    m = len(a_in)), or of every node, bottom first, sub-step after sub-step (size m·(ne + 1)). ``body`` [m/s²]: the downslope body force per unit mass
    of an infinite slope, g sin α (0 on level ground; :func:`_body_force`); ``rho_b`` [kg/m³]: the
    density the saturated elements' driving weight leaves out (ρ_f under still open water, a
    submerged slope: the buoyant weight drives; 0 with slope-parallel seepage: the total weight).
    ``quick``: 0, Newton's iterations to the tolerance (the two-fluid run); 1 (the total-stress
    companion, :func:`twofluid.runners.liquefaction_total_stress.one_call`), stopped as well once the
    next update, at the last rate of contraction of this branch's iterations, would be within the
    tolerance (:func:`_contracted`), where both updates are Newton's own (the first four iterations:
    from the fifth the slope is the chord between the last two iterates, whose rate is another
    method's): the same solution to far below the tolerance, in fewer evaluations of the law."""
    ne = h.size
    nv = ne + 1
    m = a_in.size
    md = np.zeros(nv)
    mo = np.empty(ne)
    m1 = np.empty(nv)
    _nb.consistent_mass(rho, h, md, mo, m1)
    s = np.empty(ne)
    gr = np.empty(ne)
    gm = np.empty(ne)
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
    nn = np.empty(ne)
    visc = np.empty(ne)
    dirn = np.empty(ne)
    g_prev = np.empty(ne)
    t_prev = np.empty(ne)
    psv = np.zeros(ne)
    flips = np.zeros(ne, dtype=np.int64)
    save = np.empty(st.shape[1])
    fixed = np.zeros(ne)  # 1: P_s cannot change over the call (:func:`_fixed_strength`)
    keep = np.empty((ne, 6))  # (γ_m, γ_r, r_g) of each element's last F (_mrdf; nan: none yet), and F;
    # then the damage D + D_part whose generated ratio its last commit computed (nan: none yet), and that ratio
    redo = np.zeros(ne, dtype=np.int64)  # 1: the element's branches to prepare before the next Newton sweep
    cst = np.empty((ne, _law.NCONST))  # each element's constants and its prepared branches for the
    prep = np.empty((ne, _law.NPREP))  # sub-step's Newton iterations (closures.hysteretic._prepare)
    cert = np.empty((ne, 5 + _NKEY))  # each element's outer-branch floors (_keep_floor, _keep_seen)
    pkey = np.empty((ne, _NPKEY))  # what each element's prepared branches were made from (_prepared_same)
    c0 = 1.0 / (nm_beta * dt * dt)
    cc1 = nm_gamma / (nm_beta * dt)
    ca = 0.5 / nm_beta - 1.0
    for e in range(ne):  # the law's constants of each element (γ_d refreshed at each commit)
        _law._store(cst, e, _hb._constants(st, par, e))
        keep[e, 0] = math.nan
        pkey[e, 0] = math.nan
        keep[e, 4] = math.nan
        cert[e, 1] = -math.inf
        cert[e, 3] = math.nan
        cert[e, 3 + _NKEY] = math.nan
        cert[e, 4 + _NKEY] = -math.inf
    # an element whose P_s cannot change over the call (above the water table, or neither drained
    # nor generating) has the same strength, G_max and viscosity at every sub-step: computed at the
    # first only, the same numbers; with every element so, the damping bands too
    all_fixed = _fixed_strength(par, dn, ns, fixed)
    for i in range(m):
        t = t0 + (i + 1) * dt
        frac = (i + 1.0) / m
        if i == 0 or not all_fixed:
            for e in range(ne):
                if i > 0 and fixed[e] > 0.0:
                    continue
                ps = 0.0
                if e < ns:
                    nn[e] = n[e] + frac * dn[e]
                    one_m = 1.0 - nn[e]
                    if one_m > 0.0:
                        ps = p_ref[e] * math.exp(min((1.0 - (1.0 - nb[e]) / one_m) / A[e], _MAX_EXPONENT))
                psv[e] = ps
                se, ge = _hb.strength_modulus(ps, par, e)
                if not (math.isfinite(se) and math.isfinite(ge) and ge > 0.0 and se > 0.0):
                    return 2
                s[e] = se
                gm[e] = ge
                gr[e] = se / ge
                visc[e] = eta[e] + a1 * gm[e]
        ag = a_in[i]
        if not math.isfinite(ag):
            return 2
        if i == 0 or not all_fixed:
            _nb.damping_bands(md, mo, a0, impedance, visc, h, cd, co)
        for j in range(nv):
            un[j] = u[j] + dt * v[j] + 0.5 * dt * dt * a[j]
        if first == 1:
            un[0] = 0.0
        for e in range(ne):  # each element's branch, fixed for the iterations: the predictor's
            # (a predicted motion within round-off, 1e-9 γ_r, keeps the last direction: no reversal)
            dgp = (un[e + 1] - un[e]) / h[e] - st[e, 0]
            if abs(dgp) <= 1e-9 * gr[e] and st[e, S_DIR] != 0.0:
                dirn[e] = st[e, S_DIR]
            else:
                dirn[e] = _hm.direction((un[e + 1] - un[e]) / h[e], st, e)
        d_last = math.inf  # the last Newton update (quick: for the rate of contraction; inf: none yet)
        for e in range(ne):
            flips[e] = 0
            redo[e] = 1
        converged = False
        changed = 0
        for sweep in range(5):
            # Newton's iterations with each element's branch fixed; then each element's branch is
            # checked against the direction its converged strain actually moved: an element whose
            # predictor pointed one way while the motion reversed would otherwise be committed on the
            # wrong branch (held at its yield stress while it unloads), and the next sub-step would
            # correct it, step after step: a chatter between branches at the sub-step's period.
            # First the branches of the elements whose direction is new (all, at the first sweep)
            # are prepared (closures.hysteretic._prepare) into ``prep``, with the MRDF factor F kept
            # from the last time it was computed where what it depends on is the same (γ_m, γ_r and
            # r_g, the parameters being fixed: the same number, without its powers), and with three
            # or more open points the outer branch's floor into ``cert`` (_keep_floor)
            for e in range(ne):
                if redo[e] == 0:
                    continue
                redo[e] = 0
                # (the row of ``prep`` read where its tuple is not needed: the same numbers, without
                # loading both tuples for the elements whose branches are kept)
                same = _prepared_same(pkey, e, dirn[e], st, s[e], gr[e], cst[e, _law.C_GD])
                if not same:  # (same: the row is what _prepare would give)
                    c = _law._constants_row(cst, e)
                    fm = _kept_factor(keep, e, st[e, S_GM], gr[e], st[e, S_RG])
                    q = _law._prepare(dirn[e], st, par, e, s[e], gr[e], c, fm)
                    _law._store_prepared(prep, e, q)
                    _prepared_key(pkey, e, dirn[e], st, s[e], gr[e], c[_law.C_GD])
                if prep[e, _law.Q_N] > 0.0:
                    keep[e, 0] = st[e, S_GM]
                    keep[e, 1] = gr[e]
                    keep[e, 2] = st[e, S_RG]
                    keep[e, 3] = prep[e, _law.Q_FM]
                if prep[e, _law.Q_N] >= 3.0 and not (same and _floor_fresh(cert, e, dirn[e] * st[e, S_T] * s[e], dirn[e], st[e, S_G])):
                    _keep_floor(_law._prepared_row(prep, e), _law._constants_row(cst, e), st[e, S_G], st[e, S_T], cert, e)
                    # (the same branch's floor, fresh: kept as it is)
            if sweep == 4 or (sweep > 0 and changed == 0):
                break
            converged = False
            relax = 1.0
            for it in range(max_iter):
                if it == 25:
                    relax = 0.5  # still alternating: damped
                _nb.newmark_rates(un, u, v, a, dt, nm_beta, nm_gamma, acc, vel)
                _nb.inertia_residual(md, mo, m1, cd, co, acc, vel, ag, res)
                if body != 0.0:
                    _body_force(m1, body, first, res, h, ns, rho_b)
                for e in range(ne):
                    g = (un[e + 1] - un[e]) / h[e]
                    c = _law._constants_row(cst, e)
                    q = _law._prepared_row(prep, e)
                    a_e, f_e = _floor_for(cert, e, q[_law.Q_D], g)
                    te, ke, fo = _law._stress_below(g, q, c, a_e, f_e)  # the stress, its branch's slope
                    if fo == fo:  # the outer branch evaluated: a floor from here on
                        _keep_seen(cert, e, g, fo)
                    res[e] -= te
                    res[e + 1] += te
                    if it >= 4 and abs(g - g_prev[e]) > 1e-12 * gr[e]:
                        # the chord between the last two iterates: iterates that alternate across a kink
                        # of the strength envelope converge like regula falsi instead of cycling
                        ke = (te - t_prev[e]) / (g - g_prev[e])
                    kk[e] = (ke if ke > 0.0 else 0.0) / h[e]
                    g_prev[e] = g
                    t_prev[e] = te
                _nb.jacobian_bands(md, mo, cd, co, kk, c0, cc1, jd, jo)
                _nb.thomas(jd, jo, res, first, cp, dp, du)  # J du = −res on the free nodes
                dmax, umax = _nb.newton_update(un, du, first, relax)
                if dmax < 0.0:
                    return 2
                # (quick: the rate only between two of Newton's own updates, before the chord's from it = 4)
                if dmax <= tol * max(umax, 1e-9) or (quick == 1 and it < 4 and _contracted(dmax, d_last, tol * max(umax, 1e-9))):
                    converged = True
                    break
                d_last = dmax
            if not converged:
                break
            d_last = math.inf  # (a new branch: no rate known)
            changed = 0
            for e in range(ne):
                dg = (un[e + 1] - un[e]) / h[e] - st[e, 0]  # from the committed strain (column S_G)
                # (a motion above round-off, 1e-9 γ_r, far below any strain increment of shaking)
                if dg * dirn[e] >= 0.0:
                    continue
                if st[e, S_DIR] == 0.0 and abs(dg + st[e, 0] - st[e, S_GC]) <= st[e, S_GD]:
                    dirn[e] = -dirn[e]  # not moved before, on the backbone: the same stress either way
                elif abs(dg) > 1e-9 * gr[e] and flips[e] == 0:
                    dirn[e] = -dirn[e]
                    flips[e] = 1  # once: an element at its reversal point keeps the second choice
                    changed += 1
                else:
                    continue
                redo[e] = 1
        if not converged:
            return 1
        _nb.newmark_rates(un, u, v, a, dt, nm_beta, nm_gamma, acc, vel)
        for e in range(ne):
            g = (un[e + 1] - un[e]) / h[e]
            virgin = st[e, S_DIR] == 0.0 and g == st[e, 0]
            tv = visc[e] * ((vel[e + 1] - vel[e]) / h[e])  # the rate part of the stress (η + a1 G_max) γ̇
            c = _law._constants_row(cst, e)
            q = _law._prepared_row(prep, e)
            r_gen = math.nan
            a_e, f_e = _floor_for(cert, e, q[_law.Q_D], g)
            te, fo = _law._stress_value(g, q, c, a_e, f_e)
            if fo == fo:  # the outer branch evaluated at the committed strain: a floor from here on
                _keep_seen(cert, e, g, fo)
            fm_e = q[_law.Q_FM] if q[_law.Q_N] > 0.0 else -1.0
            if e < ns and par[e, P_LIQ] > 0.0:  # the generation counted at the stress it leaves
                te, r_gen, d_gen = _law._commit_generating(g, dirn[e], st, par, e, psv[e], t, save, tv, c, te, q[_law.Q_S],
                                                           q[_law.Q_GR], fm_e, keep[e, 4], keep[e, 5])
            elif _moves_on(g, dirn[e], st, par, e):  # what _law._commit_counted does here, alone
                st[e, S_G] = g
                st[e, S_T] = te / s[e]
                st[e, S_TAU] = te
            else:
                _law._commit_counted(g, dirn[e], te, te, st, par, e, s[e], t, gr[e], c, fm_e)
            cst[e, _law.C_GD] = st[e, S_GD]
            tau_out[e] = te + tv
            if virgin:  # not moved yet: no direction, so the first motion sets it (either sign alike)
                st[e, S_DIR] = 0.0
            if e < ns and par[e, P_LIQ] > 0.0:
                r_old = st[e, S_RG]
                if r_gen == r_gen:  # (the commit's, where it made it: kept for the next commit's)
                    r_new = r_gen
                    keep[e, 4] = d_gen
                    keep[e, 5] = r_gen
                else:
                    r_new = _hd.generated_ratio(st, par, e)
                if r_new > r_old:
                    nb_old = nb[e]
                    nb[e] = nb_old + A[e] * (1.0 - nn[e]) * math.log((1.0 - r_new) / (1.0 - r_old))
                    st[e, S_EPS] += math.log((1.0 - nb[e]) / (1.0 - nb_old))
                    st[e, S_RG] = r_new
        for j in range(nv):
            u[j] = un[j]
            v[j] = vel[j]
            a[j] = acc[j]
        if surface.size == m:
            surface[i] = (ag if t <= shaking_end + 1e-12 else 0.0) + a[ne]
        else:  # every node's, bottom first (``surface`` of m·(ne + 1))
            for j in range(nv):
                surface[i * nv + j] = (ag if t <= shaking_end + 1e-12 else 0.0) + a[j]
    return 0


def _contracted(d, d_last, tol):
    """Whether Newton's iterations may stop after an update of size ``d`` that followed one of
    ``d_last`` with the same branches (the quick iterations of :func:`_substeps`): the updates contract
    (rate r = d/d_last < 1; ``d_last`` inf: no update before, no rate) and what the rest of them would
    add at that rate, d r/(1 − r), is within ``tol``. Newton's iterations contract faster than that
    (quadratically), so the solution is within ``tol`` of theirs.

    >>> _contracted(1.5e-8, 4e-4, 1e-10), _contracted(1.5e-8, 4e-4, 1e-13), _contracted(1e-20, float("inf"), 1.0)
    (True, False, False)
    """
    return d < d_last < math.inf and d * d <= tol * (d_last - d)


def _fixed_strength(par, dn, ns, fixed):
    """Mark in ``fixed`` (1) the elements whose P_s cannot change over a call of :func:`_substeps`: those
    above the water table (from ``ns`` on: P_s = 0) and the saturated ones that neither drain
    (``dn`` = 0: the porosity n + frac·0 = n at every sub-step) nor generate pore pressure
    (``P_LIQ`` = 0: n̄ held); returns whether every element is."""
    every = True
    for e in range(fixed.size):
        fixed[e] = 1.0 if e >= ns or (dn[e] == 0.0 and not par[e, P_LIQ] > 0.0) else 0.0
        if fixed[e] == 0.0:
            every = False
    return every


def _kept_factor(keep, e, gm, gr, rg):
    """Element ``e``'s MRDF factor F kept in row ``e`` of ``keep`` ((γ_m, γ_r, r_g) of its last
    computation, then F) where it was computed for the largest strain ``gm``, γ_r ``gr`` and generated
    ratio ``rg`` given (the parameters being fixed, the same number); −1 (to compute) otherwise."""
    if keep[e, 0] == gm and keep[e, 1] == gr and keep[e, 2] == rg:
        return keep[e, 3]
    return -1.0


def _prepared_key(pkey, e, d, st, s, gr, gd):
    """Keep in row ``e`` of ``pkey`` what element ``e``'s branches were just prepared from (direction
    ``d``, its committed state, strength ``s``, γ_r ``gr``, γ_d ``gd``) for :func:`_prepared_same`;
    nan (never the same) where the element reverses (``d`` other than its last direction: the committed
    point is then an open point of its own)."""
    pkey[e, 0] = d if st[e, S_DIR] == d else math.nan
    pkey[e, 1] = st[e, S_NSTK]
    pkey[e, 2] = st[e, S_NREV]
    pkey[e, 3] = st[e, S_GM]
    pkey[e, 4] = st[e, S_RG]
    pkey[e, 5] = s
    pkey[e, 6] = gr
    pkey[e, 7] = gd


def _prepared_same(pkey, e, d, st, s, gr, gd):
    """Whether element ``e``'s prepared branches (its row of the kernel's ``prep``) are what
    ``closures.hysteretic._prepare`` would make now, in direction ``d`` with strength ``s``, γ_r ``gr``
    and γ_d ``gd``: made in the same direction as the element kept moving in (no reversal then or
    now), with the same open points (their count, and no reversal pushed since: the reversal count is
    the same), the same largest strain and generated ratio (the MRDF factor), strength, γ_r and γ_d
    (the branches' origins and dilation). What else ``_prepare`` reads is fixed over the call.
    (Written with ``&``, not ``and``: without branches, numba's reference-count pruning removes the
    count of ``pkey`` and ``st`` that each call would otherwise take in and out, per element and
    sub-step; with short-circuit branches it does not. The same for :func:`_moves_on`.)"""
    return ((pkey[e, 0] == d) & (st[e, S_DIR] == d) & (pkey[e, 1] == st[e, S_NSTK]) & (pkey[e, 2] == st[e, S_NREV])
            & (pkey[e, 3] == st[e, S_GM]) & (pkey[e, 4] == st[e, S_RG]) & (pkey[e, 5] == s) & (pkey[e, 6] == gr)
            & (pkey[e, 7] == gd))


def _keep_floor(q, c, g, t, cert, e):
    """Keep in row ``e`` of ``cert`` the floor of the outer branch of the prepared ``q`` (three or
    more open points; ``closures.hysteretic._outer_floor``: the strain it holds from, the floor, the
    room the committed stress left below it, then what the branch depends on: d, τ_max, F, γ_d, its
    origin), with which the Newton iterations leave that branch unevaluated while the current one is
    the lower by far (``_stress_below``: the same numbers). Kept while the branch is the same and the
    element has not moved back from it; made again at the committed strain ``g`` (τ/τ_max ``t``) once
    the committed stress has used half its room."""
    d = q[_law.Q_D]
    tc = d * t * q[_law.Q_S]  # the committed stress, in direction d
    same = (cert[e, 3] == d and cert[e, 4] == q[_law.Q_S] and cert[e, 5] == q[_law.Q_FM]
            and cert[e, 6] == c[_law.C_GD])
    for k in range(6):
        if cert[e, 7 + k] != q[_law.Q_B + k]:
            same = False
    if same and _floor_fresh(cert, e, tc, d, g):
        return
    if not same:  # another branch: the floor _keep_seen kept was its own
        cert[e, 3 + _NKEY] = math.nan
        cert[e, 4 + _NKEY] = -math.inf
    f = _law._outer_floor(g, q, c)
    cert[e, 0] = g
    cert[e, 1] = f
    cert[e, 2] = f - tc
    cert[e, 3] = d
    cert[e, 4] = q[_law.Q_S]
    cert[e, 5] = q[_law.Q_FM]
    cert[e, 6] = c[_law.C_GD]
    for k in range(6):
        cert[e, 7 + k] = q[_law.Q_B + k]


def _moves_on(g, d, st, par, e):
    """Whether committing element ``e`` at ``g`` in direction ``d`` (``closures.hysteretic._commit_counted``)
    changes only its strain, τ/τ_max and counted stress: no damage to count (it generates no pore
    pressure), no reversal (``d`` its last direction), no loop that may close (fewer than three open
    points, or ``g`` short of the innermost one's target) and within γ_m (no backbone to reach, γ_m
    the same), no zone to widen (not liquefied). The tests of ``_commit_counted``, kept in step with it
    (without branches, as :func:`_prepared_same`: the innermost target is read whatever ``n``)."""
    n = st[e, S_NSTK]
    inner = st[e, S_STK + 2 * (int(n) - 2)]  # (the innermost target where n ≥ 3; read, not used, otherwise)
    return ((d == st[e, S_DIR]) & (not (par[e, P_LIQ] > 0.0)) & (st[e, S_LIQ] == 0.0) & (abs(g) <= st[e, S_GM])
            & ((n < 3.0) | (d * (g - inner) < 0.0)))


def _floor_fresh(cert, e, tc, d, g):
    """Whether the floor kept in row ``e`` of ``cert`` (:func:`_keep_floor`) holds at the committed
    strain ``g`` (direction ``d``) and the committed stress ``tc`` (in direction d) has used less than
    half the room it left: then it is kept as it is."""
    return d * (g - cert[e, 0]) >= 0.0 and (cert[e, 2] <= 0.0 or tc <= cert[e, 1] - 0.5 * cert[e, 2])


def _keep_seen(cert, e, g, f):
    """Keep in row ``e`` of ``cert`` (after :func:`_keep_floor`'s columns) the floor ``f`` [Pa] that
    the outer branch's stress evaluated at the strain ``g`` of a Newton iterate or a commit gives it
    from ``g`` on in direction d (``closures.hysteretic._stress_below``, ``_floor_of``: the branch is
    monotone there, as from the committed strain): the iterates of the next sub-steps lie near and
    mostly beyond it, where the committed strain's floor has gone stale. The branch is the one
    :func:`_keep_floor` keeps (made again, these columns are reset)."""
    cert[e, 3 + _NKEY] = g
    cert[e, 4 + _NKEY] = f


def _floor_for(cert, e, d, g):
    """(a, floor) for ``closures.hysteretic._stress_below`` at strain ``g`` in direction ``d``: of the
    two floors kept in row ``e`` of ``cert`` (the committed strain's, :func:`_keep_floor`, and the last
    evaluated one's, :func:`_keep_seen`), the higher of those that hold at ``g``."""
    a1 = cert[e, 3 + _NKEY]
    f1 = cert[e, 4 + _NKEY]
    if d * (g - a1) >= 0.0 and (f1 > cert[e, 1] or not d * (g - cert[e, 0]) >= 0.0):
        return a1, f1
    return cert[e, 0], cert[e, 1]


def _body_force(m1, body, first, res, h, ns, rho_b):
    """Subtract the slope's downslope weight (M 1) b, b = g sin α [m/s²], from the nodal residual;
    with ``rho_b`` > 0 (a submerged slope) the saturated elements (the first ``ns``) drive with
    (ρ − ρ_b) only, the consistent load ∫ N (ρ − ρ_b) b of each (half to each node), while their
    inertia keeps ρ. On a compliant base (``first`` = 0) the bedrock carries the column's whole
    downslope weight as a static traction at the base node (its dashpot acts on the motion only),
    so that the static state is an equilibrium on either base."""
    total = 0.0
    for j in range(m1.size):
        res[j] -= m1[j] * body
        total += m1[j]
    if rho_b != 0.0:
        for e in range(ns):
            half = 0.5 * rho_b * h[e]
            res[e] += half * body
            res[e + 1] += half * body
            total -= 2.0 * half
    if first == 0:
        res[0] += total * body


def _element_cycles(st, par, mode, amplitude, steps_per_cycle, max_cycles, ru_liq, gamma_liq,
                    out_g, out_tau, out_ru, bias):
    """Undrained cyclic simple shear of element 0 of ``st``/``par``: uniform cycles of stress
    (mode 0, τ = amplitude σ′_v0 sin 2πt) or strain (mode 1, γ = amplitude sin 2πt), t in cycles;
    undrained, so P_s = σ′_v0 (1 − r_g). Fills out_* per step (len steps_per_cycle·max_cycles + 1)
    and returns the cycles to the first r_u ≥ ``ru_liq`` or |γ − γ_s| ≥ ``gamma_liq`` (−1: none;
    the steps after it are not run). Stress control finds γ by bisection on the skeleton stress; a
    stress the skeleton cannot carry within |γ| ≤ 1 counts as liquefaction. ``bias``: a static
    shear stress ratio τ_s/σ′_v0 the cycles ride on (stress control: τ = (bias + amplitude sin 2πt)
    σ′_v0); the element must then start from its static state (γ_s, τ_s), e.g. by
    :func:`twofluid.closures.hysteretic.static_state`, and strain control cycles about γ_s."""
    sig0 = par[0, P_SIG0]
    nsteps = steps_per_cycle * max_cycles
    g_s = st[0, 0]  # the static strain the test starts from (0 without a bias)
    out_g[0] = g_s
    out_tau[0] = st[0, 2]
    out_ru[0] = 0.0
    for k in range(1, nsteps + 1):
        t = k / steps_per_cycle
        r = st[0, S_RG]
        s, gmx = _hb.strength_modulus(sig0 * (1.0 - r), par, 0)
        gr = s / gmx
        g_old = st[0, 0]
        if mode == 1:
            g = g_s + amplitude * math.sin(2.0 * math.pi * t)
            d = _hm.direction(g, st, 0)
            tau = _law.skeleton_stress(g, d, st, par, 0, s, gr)
        else:
            target = (bias + amplitude * math.sin(2.0 * math.pi * t)) * sig0
            d = 1.0 if target > st[0, 1] * s else -1.0  # from the committed stress τ/τ_max · τ_max
            lo = g_old
            step = 1e-6
            hi = g_old + d * step
            found = False
            while abs(hi) <= 1.0:
                th = _law.skeleton_stress(hi, d, st, par, 0, s, gr)
                if d * (th - target) >= 0.0:
                    found = True
                    break
                lo = hi
                step *= 2.0
                hi = g_old + d * step
            if not found:
                return t
            for _ in range(80):
                mid = 0.5 * (lo + hi)
                tm = _law.skeleton_stress(mid, d, st, par, 0, s, gr)
                if d * (tm - target) >= 0.0:
                    hi = mid
                else:
                    lo = mid
            g = hi
            tau = _law.skeleton_stress(g, d, st, par, 0, s, gr)
        _law.commit(g, d, tau, st, par, 0, s, t, gr)
        st[0, S_RG] = _hd.generated_ratio(st, par, 0)
        out_g[k] = g
        out_tau[k] = tau
        out_ru[k] = st[0, S_RG]
        if st[0, S_RG] >= ru_liq or abs(g - g_s) >= gamma_liq:
            return t
    return -1.0


#: argument types for the ahead-of-time build (C-contiguous float64 arrays, floats, integers)
SIGNATURE = ("i8(f8[::1], f8[::1], f8[::1], f8[:, ::1], f8[:, ::1], f8[::1], f8[::1], f8[::1], f8[::1], "
             "f8[::1], f8[::1], f8[::1], f8[::1], i8, f8, f8, f8, i8, f8, i8, f8, f8, f8[::1], f8, "
             "f8[::1], f8[::1], f8, f8, f8, f8, i8)")
_HELPERS = _nb.HELPERS + (_body_force, _contracted, _fixed_strength, _kept_factor, _prepared_key, _prepared_same, _keep_floor, _floor_fresh, _keep_seen, _floor_for, _moves_on, _hb._bb.gqh_core, _hb._bb.gqh_core_c, _hb._bb.gqh_core_slope_c, _hb._bb.gqh_slope_w, _law.gqh_ratio, _law.strength_modulus,
                          _law._constants, _law._gqh, _law._gqh_w, _law._dil, _law._env, _law._env_value, _law.masing_weight, _hm._masing_weight_of, _hm._mrdf_of, _hd._half_cycle_damage_of, _hd._generated_ratio_of, _hd._generated_ratio_known, _hb._strength_modulus_of,
                          _law._branch, _law._branch_value, _hm._branch_of, _hm._branch_value_of, _hb._gqh_value_w, _law._mrdf, _law._origin, _law._on, _law._on_value, _law._reversal_branch, _law._backbone, _law._backbone_value,
                          _law._open_count, _law._open_point, _law._open_stress, _law.direction, _law._prepare,
                          _law._stress_below, _law._stress_value, _law._outer_floor, _law._floor_of, _law._store, _law._store_prepared, _law._constants_row, _law._prepared_row,
                          _law.skeleton_stress, _law._close_loops,
                          _law.half_cycle_damage, _law._count_damage, _law.commit, _law.commit_counted,
                          _law._commit_counted, _law.seed_booker, _law.generated_ratio, _law.commit_generating,
                          _law._commit_generating, _hf.flows, _hz.widen_zone,
                          _hr.start, _hr.follow_mean, _hr.dilation_strain)

ELEMENT_SIGNATURE = "f8(f8[:, ::1], f8[:, ::1], i8, f8, i8, i8, f8, f8, f8[::1], f8[::1], f8[::1], f8)"

_COMPILED = None
_TRIED = False


def compiled():
    """The compiled kernel (arguments as :func:`_substeps`, arrays C-contiguous), or None where
    it cannot be compiled or ``TWOFLUID_DISABLE_JIT`` is set (then :func:`substeps` runs the
    plain Python)."""
    global _COMPILED, _TRIED
    from ..compiled import group, jit_disabled

    if jit_disabled():
        return None
    if not _TRIED:
        _TRIED = True

        _COMPILED = group("hysteretic", {"substeps": (_substeps, SIGNATURE),
                                         "element_cycles": (_element_cycles, ELEMENT_SIGNATURE)},
                          helpers=_HELPERS)
    return None if _COMPILED is None else _COMPILED["substeps"]


def element_cycles(*args, jit: bool = True, bias: float = 0.0) -> float:
    """Run the element test (arguments as :func:`_element_cycles` but ``bias``, the static shear
    ratio, a keyword: 0 by default), compiled where possible."""
    args = args + (float(bias),)
    if jit and compiled() is not None:
        return float(_COMPILED["element_cycles"](*args))
    return float(_element_cycles(*args))


def runner():
    """The sub-steps' function to call for a whole run, resolved once (the compiled kernel, or
    :func:`_substeps` where :func:`compiled` gives None): arguments as :func:`_substeps`, ``body`` and
    ``rho_b`` (as :func:`substeps` takes them) as floats and ``quick`` as an integer last; returns the
    code as :func:`substeps` does once passed to ``int``.

    >>> runner() in (compiled(), _substeps)
    True
    """
    k = compiled()
    return _substeps if k is None else k


def substeps(*args, jit: bool = True, body: float = 0.0, rho_b: float = 0.0, quick: int = 0) -> int:
    """Run the sub-steps (arguments as :func:`_substeps` but ``body``, the slope's g sin α [m/s²],
    ``rho_b``, the density its saturated elements' driving weight leaves out [kg/m³], and ``quick``,
    keywords: 0 on level ground and with slope-parallel seepage, and Newton's iterations as the
    two-fluid run takes them), compiled where possible."""
    args = args + (float(body), float(rho_b), int(quick))
    k = compiled() if jit else None
    return int(k(*args)) if k is not None else int(_substeps(*args))
