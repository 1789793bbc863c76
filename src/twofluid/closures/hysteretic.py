"""Hysteretic effective-stress shear law of saturated sand: the liquefaction column's default.

One element of soil under horizontal shear (strain γ, skeleton stress τ) whose effective
vertical stress P_s falls as pore pressure is generated. Written once, as scalar functions of
an element's row in a state array and a parameter array, in plain Python that numba compiles
(the column's kernel, :mod:`twofluid.models.hysteretic_kernel`) and that also runs un-jitted
(the element test, debugging). docs/liquefaction.md, "The hysteretic model", has the why.

The law is the composition of its mechanisms, one module each: the backbone and strength
(:mod:`.hysteretic_backbone`), the Masing/MRDF memory of reversal points
(:mod:`.hysteretic_memory`), the damage count and Seed–Booker generation (:mod:`.hysteretic_damage`),
the dilation zone of cyclic mobility (:mod:`.hysteretic_dilation`), the flow rule
(:mod:`.hysteretic_flow`) and the strain after triggering (:mod:`.hysteretic_ratchet`), over one layout of the state and parameter arrays
(:mod:`.hysteretic_layout`). This module composes them: the stress at a trial strain
(:func:`skeleton_stress`), the commit of a converged sub-step (:func:`commit`,
:func:`commit_generating`) and the states to start from; it re-exports every mechanism's functions,
so ``hysteretic.X`` names the whole law. A mechanism calls another through its module
(``_hb._gqh(...)``): the kernel's build compiles each function in its own module.

**Strength and stiffness.** The skeleton's strength and small-strain modulus follow the current
effective vertical stress, floored by the residual strength S_r:

    p = max(P_s, S_r / tan φ′),   τ_max = p tan φ′,   G_max = 218.8 K2max √(p / 1 kPa) kPa,

so γ_r = τ_max / G_max ∝ p^0.5 (Seed & Idriss 1970 for G_max; the floor acts on the shear law
only and never feeds back into P_s). Above the water table (crust) P_s and G_max are fixed.

**Backbone.** GQ/H (Groholski et al. 2016) in normalised form, x = |γ|/γ_r:

    τ/τ_max = 2x / (1 + x + √((1 + x)² − 4 θ x)),   θ = θ1 + θ2 θ4 x^θ5 / (θ3^θ5 + θ4 x^θ5),

θ = 0 is the hyperbola x/(1 + x) (Hardin & Drnevich), θ = 1 elastic–perfectly plastic.

**Unloading and reloading.** From the last open reversal point (γ_0, τ_0), moving in direction d:

    τ = τ_0 + d τ_max [F (2 f(x/2) − f(x)) + f(x)],   x = |γ − γ_0|/γ_r,  f the backbone ratio,

with F = p1 − p2 (1 − G(γ_m)/G_max)^p3 the MRDF factor of Phillips & Hashash (2009) at the
largest strain so far γ_m (F = 1: Masing's rule), moved towards Masing's F = 1 as the pore pressure
is generated: F + (1 − F) w, w = S((r_g − 0.8)/(r_cap − 0.8)) (:func:`masing_weight`), so a liquefied
element flows between its dilation stops on Masing's branches and the change of rule is a
continuous function of r_g, never a jump of the stress. Beyond ±γ_m in the direction of motion the
branch does not go past the backbone. Reversal stresses are stored as τ/τ_max, so when τ_max
shrinks they shrink with it (the mapping of Matasovic & Vucetic): no stress of an old reversal
ever exceeds the new strength.

The law remembers up to ``NSTACK`` = 16 open reversal points (extended Masing rules): when a
branch reaches the reversal point where the loop it belongs to began, the loop closes and the
stress continues on the outer branch it had left, so small inner cycles do not ratchet the stress.
The branch is an odd function of γ − γ_0, so the branch back from the last point meets the one
before exactly there (for Masing and MRDF alike, F being the same for both). Within a sub-step
the stress is the lower, in direction d, of the current branch and that outer branch (and, beyond
γ_m, the backbone): the two cross at the closure point, so the stress is continuous in γ and
Newton's iterates may pass the point freely; which points are open is decided from the committed
state and d alone. At a commit, a closed pair is dropped only once the outer branch is the lower
one at the committed strain, so dropping it never changes the stress; with a strength that changed
since the reversal (γ_r ∝ √P_s) the crossing moves slightly off the reversal point, continuously.
A reversal at the largest strain so far starts afresh; with the stack full, the innermost pair (the
smallest loop) is forgotten (16 points: a decaying free vibration nests a new loop at every
reversal, and 8 overflowed in the PySeismoSoil benchmark).

**Cyclic mobility.** Dilation of the skeleton stiffens it again once the strain leaves a zone
|γ − γ_c| ≤ γ_d around the centre of the cycles: the strength envelope is

    τ_env = max(τ_max, τ_d),   τ_d = σ′_v0 tan φ′ S((|γ − γ_c| − γ_d)/γ_dr),  S(r) = r²(3 − 2r) on [0, 1]
    (in sand that generates pore pressure only),

and when loading outwards beyond γ_d the stress gains the dilation stress gained since the
branch's origin γ_0, τ_d(γ) − τ_d(γ_0) (τ_d(γ) from inside the zone: additive, so it is continuous
at the onset, and at a reversal within the dilation zone too). Each candidate branch carries its
own gain: the current one from its reversal point, the outer branch its loop closes onto from that
branch's origin, and the backbone that caps them beyond the largest strain so far from γ_c (so the
cap is the envelope itself). Capped by the bare backbone τ_max Φ, a reversal at the peak of a
dilated excursion followed by reloading outwards (a wiggle, or a sub-step's chatter between
branches) dropped the stress from the envelope to about τ_max at once: a liquefied element on a
slope, which rides on the downslope side of the zone, so lost its dilation stop at every such
wiggle and ratcheted at its strength (24 % of strain in one element of the 3 % sloping site, which
element was set by the step). A branch from a reversal above τ_max (a dilated state) is widened by
κ = max(1, |d − τ_0/τ_max|/(1 + F)) in stress and strain, so that it still reaches d τ_max; a
liquefied element takes Masing's branches (F = 1) between its dilation stops. γ_c is the strain
the sand was consolidated at (0 on level ground, the static strain on a slope) and stays there
until the element triggers ("Strain after triggering");
γ_d = ``gamma_d0`` until the element liquefies (D ≥ 1), and from then on the zone widens with the
strain travelled inside it, d(γ_d²) = Δγ_d |dγ| for |γ − γ_c| < γ_d (Δγ_d = ``gamma_d_step``), up
to the limiting strain γ_lim(Dr) of Idriss & Boulanger (2008): a half cycle that crosses the zone
(2γ_d of strain) widens it by Δγ_d, however many wiggles or sub-steps it takes, and a wiggle widens
it by its own share of strain only. Counted per reversal instead, every 10–30 Hz wiggle of a
liquefied element widened the zone by a full step, so the strain it could reach depended on the
mesh and the step. The strain so grows cycle by cycle towards γ_lim, with nothing that jumps at
liquefaction: the zone neither moves nor widens in a step, so the stress is continuous there.
``gamma_dilation`` γ_dr = 10 %: uniform cycles at CSR = CRR ((N1)60cs = 10) reach a single-amplitude
strain of 3.8 % at r_u = 0.98 (Yoshimine et al. 2006: 3.5 % at FS = 1; the laboratory's 3 %), and
the dilation stop is soft enough that a liquefied layer does not pass on pulses of the drained
strength.

**Flow liquefaction.** Cyclic mobility is what a sand does when the shear it must carry after
liquefaction is below its residual strength: level ground (no static shear) or a gentle slope
(FS_post = S_r/|τ_s| > 1), where the strain ratchets cycle by cycle and dilation stops each half
cycle. A loose, contractive sand whose static shear exceeds its residual strength, |τ_s| > S_r
(FS_post < 1), suffers flow liquefaction instead: once it has liquefied nothing in its skeleton
holds the static shear, and dilation, which needs the stress to reverse through the phase
transformation, must not hold it either. So for such an element there is no dilation stress on
the side of its static shear (``tau_static`` τ_s, signed, set by the column where it applies the
static state; 0 on level ground, where nothing changes): loaded downslope beyond γ_d its stress is
the strength max(P_s tan φ′, S_r) plus, in the column, the rate (viscous) part, and it flows until
the excess pore pressure dissipates and P_s tan φ′ returns (the vertical two-fluid model does
that), or the run reports a flow slide. Upslope, against the static shear, its dilation is
unchanged. Without this rule the dilation envelope (σ′_v0 tan φ′ over γ_dr beyond γ_d) stopped a
5 % slope with FS_post = 0.86 within seconds of the shaking's end: a flow slide held by cyclic
mobility, which the static shear never reverses to engage.

**Strain after triggering.** Once the element has triggered (D ≥ 1, or 3 % of strain from γ_c),
γ_c follows the cycles: at each reversal whose stress is within the strength (not on a dilation
stop) it moves the share κ w of the way to the mean strain of the half cycle that ended there,
w = min(1, |Δ(τ/τ_max)|/2), and γ_dr grows with its drift, γ_dr (1 + √(|γ_c − γ_c0|/γ_w))
(:mod:`.hysteretic_ratchet`). On level ground the mean strain stays at γ_c; on a slope it moves
downslope by each cycle's increment, so the element crosses the zone every cycle and the strain
keeps accumulating instead of shaking down near 3 %. The move happens where the stress lies within
τ_max, so within the envelope wherever the centre is: no stress jumps.

**Pore-pressure generation.** Cyclic damage counted per half cycle of stress, the half cycles found
by rainflow counting as the history arrives (:func:`_count_damage`: a small wiggle within a large
half cycle closes as a small cycle of its own and leaves the large one whole), with stress and
strain amplitudes τ_a = |τ − τ_0|/2, γ_a = |γ − γ_0|/2 from the half cycle's start (τ_0, γ_0):

    dD = f_t(γ_a) / (2 N_L),   N_L = 15 (CRR / CSR)^(1/b),   CSR = τ_a / σ′_v0,
    f_t = clip((γ_a − γ_t)/γ_t, 0, 1),

CRR the field cyclic resistance at the element's σ′_v0 (M 7.5, K_σ applied) and b the slope of
the CSR–N curve, both from (N1)60cs (:func:`twofluid.models.hysteretic_sand.derive`); no damage
below the threshold strain γ_t. The generated excess pore-pressure ratio follows Seed & Booker
(1977), r_g = (2/π) arcsin(D^(1/(2α))), α = 0.7, capped at ``r_cap``. Each increase of r_g lowers
the effective stress by the same factor, P_s ← P_s (1 − r_g,new)/(1 − r_g,old), which for the
exponential granular pressure of the two-fluid model is the reference-porosity change

    n̄ ← n̄ + A (1 − n) ln((1 − r_g,new)/(1 − r_g,old)),

so in an undrained element r_u = r_g exactly, and with drainage the two-fluid equations move the
pressure as they do for any change of n̄. In the column the generation of a sub-step is counted at
the stress the element carries with the strength that generation leaves (:func:`commit_generating`,
a backward-Euler step of the generation): counted at the stress of the strength before it, one
strong half cycle could take r_g from 0.7 to 1 in a single sub-step and the stress (∝ τ_max) then
fell by half at the next, a jolt whose size the step set.

>>> import numpy as np
>>> round(gqh_ratio(1.0, 0.0, 0.0, 1.0, 1.0, 1.0), 6)  # hyperbola at x = 1
0.5
>>> round(gqh_ratio(0.5, 1.0, 0.0, 1.0, 1.0, 1.0), 6), round(gqh_ratio(3.0, 1.0, 0.0, 1.0, 1.0, 1.0), 6)
(0.5, 1.0)
>>> round(seed_booker(0.5, 0.7), 4)
0.4173
"""
from __future__ import annotations

import math

import numpy as np

from . import hysteretic_backbone as _hb
from . import hysteretic_damage as _hd
from . import hysteretic_dilation as _hz
from . import hysteretic_memory as _hm
from . import hysteretic_ratchet as _hr
# the mechanisms' functions, the law's public API and the kernel's helpers, under one name
from .hysteretic_backbone import (gqh_ratio, strength_modulus, _constants, _gqh, _gqh_w)  # noqa: F401
from .hysteretic_flow import (flows)  # noqa: F401
from .hysteretic_dilation import (_dil, _dilation, _env, _env_value, widen_zone)  # noqa: F401
from .hysteretic_memory import (_branch, _branch_value, masing_weight, _mrdf, _origin, _on, _on_value, _reversal_branch, _backbone, _backbone_value, _open_count, _open_point,
    _open_stress, direction, _close_loops)  # noqa: F401
from .hysteretic_damage import (seed_booker, half_cycle_damage, _count_damage, generated_ratio)  # noqa: F401
from .hysteretic_layout import *  # noqa: F401,F403  (every index of the state and parameter arrays)
from .hysteretic_layout import (NPARAM, NSTACK, NSTATE, P_ALPHA, P_B, P_CRR, P_GD0, P_GDR, P_GT, P_K2, P_LIQ, P_P1, P_RCAP, P_SIG0,
    P_SR, P_TANPHI, P_TAUS, P_TH1, P_TH2, P_TH3, P_TH4, P_TH5, Q_A, Q_B, Q_D, Q_FM, Q_GM, Q_GR, Q_N,
    Q_S, S_D, S_DIR, S_DPART, S_G, S_GC, S_GD, S_GM, S_GREV, S_LIQ, S_NREV, S_NSTK, S_RF, S_RFDIR,
    S_RFN, S_RG, S_STK, S_T, S_TAU, S_TLIQ, S_TREV, S_RAT, C_C3, C_LIQ, C_TDMAX, C_TH2, C_TH4, C_TH5)

__all__ = ["gqh_ratio", "seed_booker", "strength_modulus", "skeleton_stress", "direction", "masing_weight",
           "commit", "commit_counted", "commit_generating", "generated_ratio", "new_state", "static_state", "STATE_COLUMNS", "PARAM_COLUMNS", "KPA"]

#: the share of the scale of its stresses by which :func:`_outer_floor` lowers an outer branch's
#: stress: far above the round-off of evaluating it (about 1e-7 at worst), far below the stresses
OUTER_MARGIN = 1e-4


def _prepare(d, st, par, e, s, gr, c, fm):
    """What element ``e``'s committed state and the direction ``d`` fix for a sub-step with strength
    ``s`` [Pa] and reference strain ``gr`` (``Q_*``): the open reversal points (:func:`_open_count`)
    and the origins of the branches from them, the MRDF factor, the largest strain so far. ``fm``:
    the branches' F where the caller kept it (:func:`_mrdf` of the same state and ``gr``, from an
    earlier sub-step: the same number); < 0: not known, computed here."""
    n, rev = _hm._open_count(d, st, e)
    virgin = 1.0 if st[e, S_DIR] == 0.0 else 0.0
    if n == 0:
        return (d, s, gr, virgin, 0.0, 0.0, st[e, S_GM], 0.0, 0.0, 0.0, 0.0, 0.0, 0.0,
                0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    if fm < 0.0:
        fm = _hm._mrdf(st, par, e, gr, c)
    g0, t0 = _hm._open_point(n - 1, n, rev, st, e)
    a = _hm._origin(g0, t0, d, s, gr, fm, c)
    b = a
    if n >= 3:
        g1, t1 = _hm._open_point(n - 3, n, rev, st, e)
        b = _hm._origin(g1, t1, d, s, gr, fm, c)
    return (d, s, gr, virgin, float(n), fm, st[e, S_GM], a[0], a[1], a[2], a[3], a[4], a[5],
            b[0], b[1], b[2], b[3], b[4], b[5])


def _stress_below(g, q, c, a, floor):
    """(τ [Pa], dτ/dγ [Pa], floor [Pa]): :func:`skeleton_stress` at ``g`` from the prepared ``q``
    (:func:`_prepare`) and the constants ``c`` (:func:`_constants`), the derivative of the branch
    that sets it, and where the outer branch was evaluated the floor its stress there gives it from
    ``g`` on (:func:`_floor_of`; nan where it was not evaluated), given that
    the outer branch's stress, in direction d, is above ``floor`` [Pa] at every strain from ``a`` on
    in that direction (:func:`_outer_floor`, :func:`_floor_of`; ``floor`` −inf: nothing known, every
    branch evaluated): where ``g`` lies there and the current branch's stress is at or below the
    floor, the outer branch cannot be the lower one, and it is not evaluated. The same τ and dτ/dγ
    either way."""
    d = q[Q_D]
    s = q[Q_S]
    if q[Q_N] == 0.0:  # first loading, or a loop closed onto the backbone: the backbone
        tau, k = _hm._backbone(g, d, s, q[Q_GR], c)
        return tau, k, math.nan
    fm = q[Q_FM]
    # the current branch: _hm._on written out (one call fewer per evaluation, the same operations)
    phi, k = _hm._branch((g - q[Q_A]) / q[Q_A + 3], fm, c)
    tau, k = _hz._env(g, d, q[Q_A + 1] + q[Q_A + 2] * phi, q[Q_A + 2] * k / q[Q_A + 3], s, q[Q_A + 4], q[Q_A + 5], c)
    to = math.nan
    if q[Q_N] >= 3.0 and not (d * (g - a) >= 0.0 and d * tau <= floor):  # the outer branch the loop closes onto
        # (its stress alone first: its slope only where it is the lower, the same stress again)
        to = _hz._env_value(g, d, q[Q_B + 1] + q[Q_B + 2] * _hm._branch_value((g - q[Q_B]) / q[Q_B + 3], fm, c), s,
                            q[Q_B + 4], q[Q_B + 5], c)  # (_hm._on_value written out)
        if d * to < d * tau:
            tau, k = _hm._on(g, d, q[Q_B], q[Q_B + 1], q[Q_B + 2], q[Q_B + 3], q[Q_B + 4], q[Q_B + 5], s, fm, c)
        to = _floor_of(to, q, c)
    if d * g > q[Q_GM]:  # beyond the largest strain so far: not past the backbone (with its dilation)
        tb = _hm._backbone_value(g, d, s, q[Q_GR], c)
        if d * tau > d * tb:
            tau, k = _hm._backbone(g, d, s, q[Q_GR], c)
    return tau, k, to


def _stress_value(g, q, c, a, floor):
    """(τ [Pa], floor [Pa]): :func:`_stress_below`'s stress and floor alone: the same branches
    compared, each evaluated by the same operations without its slope (``_hm._on_value``), so the
    same numbers, for the evaluations whose slope nothing uses (a commit's stress)."""
    d = q[Q_D]
    s = q[Q_S]
    if q[Q_N] == 0.0:
        return _hm._backbone_value(g, d, s, q[Q_GR], c), math.nan
    fm = q[Q_FM]
    # the current branch: _hm._on_value written out (one call fewer, the same operations)
    phi = _hm._branch_value((g - q[Q_A]) / q[Q_A + 3], fm, c)
    tau = _hz._env_value(g, d, q[Q_A + 1] + q[Q_A + 2] * phi, s, q[Q_A + 4], q[Q_A + 5], c)
    to = math.nan
    if q[Q_N] >= 3.0 and not (d * (g - a) >= 0.0 and d * tau <= floor):
        to = _hz._env_value(g, d, q[Q_B + 1] + q[Q_B + 2] * _hm._branch_value((g - q[Q_B]) / q[Q_B + 3], fm, c), s,
                            q[Q_B + 4], q[Q_B + 5], c)  # (_hm._on_value written out)
        if d * to < d * tau:
            tau = to
        to = _floor_of(to, q, c)
    if d * g > q[Q_GM]:
        tb = _hm._backbone_value(g, d, s, q[Q_GR], c)
        if d * tau > d * tb:
            tau = tb
    return tau, to


def _outer_floor(g, q, c):
    """A floor, in direction d, of the stress [Pa] of the outer branch of the prepared ``q``
    (:func:`_prepare`, with three or more open points) at every strain from ``g`` on in direction d
    (for :func:`_stress_below`): d τ_o(g) less ``OUTER_MARGIN`` of the scale of the stresses that
    make it; −inf where that branch is not known to be monotone.

    The branch τ_0 + τ_max κ Φ((γ − γ_0)/(κ γ_r)), raised by the dilation gained since its origin and
    held within the envelope, is monotone in the direction of motion when Φ is: when F ∈ [0, 1]
    (Φ′ = F f′(y/2) + (1 − F) f′(y)) and the GQ/H ratio f rises with x, which it does when θ_τ does
    (θ2 θ4 θ5 ≥ 0, θ4 ≥ 0). The dilation gain, the envelope max(τ_max, τ_d) and the clamp to it are
    monotone in γ each. So the exact branch at any strain beyond ``g`` is at least the exact branch
    at ``g``, and the computed ones differ from the exact by round-off, far below the margin (the
    largest, where the root of the GQ/H form nears 0, about √ε of its terms)."""
    if _floor_of(0.0, q, c) == -math.inf:
        return -math.inf
    d = q[Q_D]
    to = _hm._on_value(g, d, q[Q_B], q[Q_B + 1], q[Q_B + 2], q[Q_B + 3], q[Q_B + 4], q[Q_B + 5], q[Q_S], q[Q_FM], c)
    return _floor_of(to, q, c)


def _floor_of(to, q, c):
    """The floor [Pa], in direction d, that the outer branch's stress ``to`` [Pa] at a strain gives
    it at every strain from there on in direction d (:func:`_outer_floor`, whose reasons hold at any
    strain the branch was evaluated at): d τ_o less ``OUTER_MARGIN`` of the scale of the stresses
    that make it; −inf where the branch of ``q`` is not known to be monotone."""
    fm = q[Q_FM]
    if q[Q_N] < 3.0 or not (0.0 <= fm <= 1.0) or c[C_TH4] < 0.0 or c[C_TH2] * c[C_TH5] < 0.0 or not c[C_C3] > 0.0:
        return -math.inf
    scale = q[Q_S] + abs(q[Q_B + 1]) + 2.0 * q[Q_B + 2] + (2.0 * c[C_TDMAX] if c[C_LIQ] > 0.0 else 0.0)
    return q[Q_D] * to - OUTER_MARGIN * scale


def _store(a, e, x):
    """Row ``e`` of the work array ``a`` ← the tuple ``x`` (the kernel's per-element ``c``, once per call)."""
    for k in range(len(x)):
        a[e, k] = x[k]


def _store_prepared(a, e, x):
    """Row ``e`` of the work array ``a`` ← the prepared tuple ``x`` (:func:`_prepare`), written out:
    compiled, :func:`_store`'s loop indexes the tuple at a run-time index, a jump over its 19 cases
    per value, and the kernel stores a prepared tuple per element and sub-step."""
    a[e, 0] = x[0]
    a[e, 1] = x[1]
    a[e, 2] = x[2]
    a[e, 3] = x[3]
    a[e, 4] = x[4]
    a[e, 5] = x[5]
    a[e, 6] = x[6]
    a[e, 7] = x[7]
    a[e, 8] = x[8]
    a[e, 9] = x[9]
    a[e, 10] = x[10]
    a[e, 11] = x[11]
    a[e, 12] = x[12]
    a[e, 13] = x[13]
    a[e, 14] = x[14]
    a[e, 15] = x[15]
    a[e, 16] = x[16]
    a[e, 17] = x[17]
    a[e, 18] = x[18]


def _constants_row(a, e):
    """The constants stored by :func:`_store` in row ``e`` of ``a``, as the tuple :func:`_constants` gave."""
    return (a[e, 0], a[e, 1], a[e, 2], a[e, 3], a[e, 4], a[e, 5], a[e, 6], a[e, 7], a[e, 8], a[e, 9],
            a[e, 10], a[e, 11], a[e, 12])


def _prepared_row(a, e):
    """The prepared tuple stored by :func:`_store` in row ``e`` of ``a``, as :func:`_prepare` gave it."""
    return (a[e, 0], a[e, 1], a[e, 2], a[e, 3], a[e, 4], a[e, 5], a[e, 6], a[e, 7], a[e, 8], a[e, 9],
            a[e, 10], a[e, 11], a[e, 12], a[e, 13], a[e, 14], a[e, 15], a[e, 16], a[e, 17], a[e, 18])


def skeleton_stress(g, d, st, par, e, s, gr):
    """Rate-independent skeleton stress [Pa] of element ``e`` at trial strain ``g`` reached by
    moving in direction ``d`` (±1, fixed over a sub-step's Newton iterations) from its committed
    state, with strength ``s`` [Pa] and reference strain ``gr`` = s/G_max [-].

    Which reversal points are open is decided from the committed state and ``d``
    (:func:`_open_count`), never from ``g``; the stress is then the lower, in direction ``d``, of
    the current branch, the outer branch its loop closes onto and (beyond the largest strain so
    far) the backbone: a continuous function of ``g``, whose branches cross at the closure point
    (exactly so under constant strength), so Newton's iterates may pass it freely. Each branch is
    an odd function of γ − γ_0, smooth through its origin, and carries the dilation gained since its
    own origin (the backbone since γ_c), so a wiggle at the peak of a dilated excursion reloads
    onto the envelope, not onto τ_max:

    >>> import numpy as np
    >>> par = np.zeros((1, NPARAM)); par[0, P_K2] = 30.0; par[0, P_TANPHI] = 0.745; par[0, P_SR] = 4.5e3
    >>> par[0, P_TH3:P_TH5 + 1] = 1.0; par[0, P_P1] = 1.0; par[0, P_GT] = 1e-4; par[0, P_CRR] = 0.1
    >>> par[0, P_B] = 0.3; par[0, P_SIG0] = 70e3; par[0, P_LIQ] = 1.0; par[0, P_GDR] = 0.1
    >>> par[0, P_ALPHA] = 0.7; par[0, P_RCAP] = 0.999; par[0, P_GD0] = 0.005; par[0, P_TAUS] = 3e3
    >>> st = new_state(1, par); gc = static_state(st, par, 0, 3e3, 70e3)
    >>> s, gm = _hb.strength_modulus(0.0, par, 0)  # liquefied: the residual strength S_r = 4.5 kPa
    >>> taus = []
    >>> for g in list(gc + np.linspace(0.001, 0.04, 40)) + [gc + 0.0399, gc + 0.0401]:  # out, back 0.01 %, out
    ...     d = _hm.direction(g, st, 0); tau = skeleton_stress(g, d, st, par, 0, s, s / gm)
    ...     _ = commit(g, d, tau, st, par, 0, s, 0.0, s / gm); taus.append(tau)
    >>> [round(float(x) / 1e3, 1) for x in taus[-3:]]  # kPa: at 4 %, after the wiggle, past 4 % again
    [14.7, 13.2, 14.8]
    """
    c = _hb._constants(st, par, e)
    return _stress_value(g, _prepare(d, st, par, e, s, gr, c, -1.0), c, g, -math.inf)[0]


def commit(g, d, tau, st, par, e, s, t, gr):
    """Commit the converged strain ``g``, reached in direction ``d``, and stress ``tau`` [Pa] of
    element ``e`` at time ``t`` [s], with the sub-step's reference strain ``gr`` [-]: reversals
    and loop closure, the largest strain, damage and liquefaction. Returns the total damage."""
    return _commit_counted(g, d, tau, tau, st, par, e, s, t, gr, _hb._constants(st, par, e), -1.0)


def commit_counted(g, d, tau, tau_count, st, par, e, s, t, gr):
    """:func:`commit` with the damage counted on ``tau_count`` [Pa] instead of the skeleton stress
    ``tau``: in the column, the shear stress the element carries, skeleton and rate (viscous) parts
    together, as the laboratory's CSR is the stress applied to the specimen, whatever part of it
    its rate carries."""
    return _commit_counted(g, d, tau, tau_count, st, par, e, s, t, gr, _hb._constants(st, par, e), -1.0)


def _commit_counted(g, d, tau, tau_count, st, par, e, s, t, gr, c, fm):
    """:func:`commit_counted` with the element's constants ``c`` (:func:`_constants`, γ_d as before
    the commit) and the branches' F ``fm`` (:func:`_mrdf` at ``gr``; < 0: not known, computed where
    needed) given. (The column's kernel writes the strain, τ/τ_max and counted stress itself where
    nothing else here would change, ``models.hysteretic_kernel._moves_on``: its tests are this
    function's, kept in step.)"""
    g_old = st[e, S_G]
    d_old = st[e, S_DIR]
    if par[e, P_LIQ] > 0.0:
        _hd._count_damage(g, tau_count, st, e, par[e, P_GT], par[e, P_SIG0], par[e, P_CRR], par[e, P_B])
    if d_old != 0.0 and d != d_old and st[e, S_RAT] > 0.0:  # strain after triggering: γ_c follows the mean
        _hr.follow_mean(g_old, st, par, e)
    if d_old != 0.0 and d != d_old:  # the strain reversed at g_old: a new branch
        n, _ = _hm._open_count(d, st, e)  # pushed: g_old, with the pairs it closes dropped
        st[e, S_STK + 2 * (n - 1)] = g_old
        st[e, S_STK + 2 * (n - 1) + 1] = st[e, S_T]
        st[e, S_NSTK] = n
        st[e, S_GREV] = g_old
        st[e, S_TREV] = st[e, S_T]
        st[e, S_NREV] += 1.0
    st[e, S_DIR] = d
    st[e, S_G] = g
    st[e, S_T] = tau / s
    st[e, S_TAU] = tau_count
    n = int(st[e, S_NSTK])
    if n > 0 and ((n >= 3 and d * (g - st[e, S_STK + 2 * (n - 2)]) >= 0.0) or d * g > st[e, S_GM]):
        # (only where a loop may close, the entry tests of _hm._close_loops, kept in step with them:
        # otherwise it changes nothing, and a call with the state arrays costs their reference counts)
        _hm._close_loops(g, d, st, par, e, s, gr, c, fm)
    if abs(g) > st[e, S_GM]:
        st[e, S_GM] = abs(g)
    if st[e, S_LIQ] > 0.0:  # cyclic mobility: the zone widens with the strain travelled inside it
        _hz.widen_zone(g_old, g, st, par, e)
    if par[e, P_LIQ] > 0.0 and st[e, S_LIQ] == 0.0 and st[e, S_D] + st[e, S_DPART] >= 1.0:
        st[e, S_LIQ] = 1.0
        st[e, S_TLIQ] = t
    if st[e, S_RAT] == 0.0 and par[e, P_LIQ] > 0.0:
        _hr.start(g, st, e)
    return st[e, S_D] + st[e, S_DPART]


def commit_generating(g, d, st, par, e, ps, t, save, tau_rate):
    """Commit the converged strain ``g`` (direction ``d``) of element ``e`` at effective vertical
    stress ``ps`` [Pa] (before this sub-step's generation) with the pore pressure it generates
    counted consistently: the stress that is committed and counted is the one the element carries
    with the strength that its own damage leaves. Returns the committed stress [Pa]; the generated
    ratio is then :func:`generated_ratio`, and P_s falls by q = (1 − r_new)/(1 − r_old).

    Counted explicitly, at the stress of the strength before the sub-step, a strong half cycle
    can raise r_g from 0.7 to 1 within one sub-step (damage ∝ CSR^(1/b), 1/b ≈ 10, and Seed–Booker's
    dr/dD is unbounded at D = 1), and the strength, and the stress with it (reversal stresses are
    stored as τ/τ_max), then drops by half at the next step: a jolt whose size is set by the step.
    Here the strength factor q solves q = (1 − r(D(τ(q))))/(1 − r_old), τ(q) the skeleton stress at
    ``g`` with the strength at q ps (the backward-Euler step of the generation; the right-hand side
    falls as q rises, so the root is unique and found by regula falsi between the explicit factor
    and 1): an element cannot count a stress that its own pore pressure has made it unable to carry.
    The strength so falls only as fast as the motion keeps loading the element, a rate the time
    step resolves. ``save``: a work row of NSTATE floats. ``tau_rate`` [Pa]: the rate (viscous) part
    of the element's stress this sub-step, counted with the skeleton's (:func:`commit_counted`)."""
    c = _hb._constants(st, par, e)
    s, gmx = _hb.strength_modulus(ps, par, e)
    gr = s / gmx
    q = _prepare(d, st, par, e, s, gr, c, -1.0)
    tau = _stress_value(g, q, c, g, -math.inf)[0]
    return _commit_generating(g, d, st, par, e, ps, t, save, tau_rate, c, tau, s, gr, q[Q_FM] if q[Q_N] > 0.0 else -1.0,
                              math.nan, math.nan)[0]


def _commit_generating(g, d, st, par, e, ps, t, save, tau_rate, c, tau, s, gr, fm, dk, rk):
    """:func:`commit_generating` with the element's constants ``c`` (:func:`_constants`) given, and
    the skeleton stress ``tau`` [Pa] at ``g`` of its branches prepared at ``ps`` (:func:`_prepare` in
    direction ``d`` with the strength ``s`` [Pa] and γ_r ``gr`` of :func:`strength_modulus` at ``ps``;
    :func:`_stress_value`) and their F ``fm`` (< 0: none, no open point); ``rk``: the generated ratio
    of the element's damage D + D_part = ``dk`` where the caller computed it before (nan: none), used
    where the damage is that again (``_hd._generated_ratio_known``: the same number). Returns (the
    committed stress [Pa], the generated ratio of the committed state, :func:`generated_ratio`, where
    it was computed on the way, and the damage it is of; nan, nan where not)."""
    r_old = st[e, S_RG]
    if par[e, P_LIQ] <= 0.0 or ps <= 0.0 or r_old >= par[e, P_RCAP]:
        _commit_counted(g, d, tau, tau + tau_rate, st, par, e, s, t, gr, c, fm)
        return tau, math.nan, math.nan
    at_floor = s <= par[e, P_SR] * (1.0 + 1e-12)  # the strength at its floor: no iteration, no state to restore
    if not at_floor:
        for k in range(NSTATE):
            save[k] = st[e, k]
    _commit_counted(g, d, tau, tau + tau_rate, st, par, e, s, t, gr, c, fm)
    alpha = par[e, P_ALPHA]
    cap = par[e, P_RCAP]
    dsum = st[e, S_D] + st[e, S_DPART]  # (generated_ratio's damage)
    r = _hd._generated_ratio_known(dsum, alpha, cap, dk, rk)
    q1 = (1.0 - r) / (1.0 - r_old)
    if q1 >= 1.0 - 1e-12 or at_floor:
        return tau, r, dsum  # no generation, or the strength already at its floor: the explicit count holds
    # φ(q) = q′(q) − q: φ(1) = q1 − 1 < 0, φ(q1) ≥ 0 (a lower strength, a lower stress, less damage)
    lo, hi = q1, 1.0
    f_hi = q1 - 1.0
    f_lo = 0.0
    q = q1
    side = 0
    for it in range(60):
        if it == 0:
            q = lo
        else:
            q = (lo * f_hi - hi * f_lo) / (f_hi - f_lo) if f_lo != f_hi else 0.5 * (lo + hi)
            if not (lo < q < hi):
                q = 0.5 * (lo + hi)
        for k in range(NSTATE):
            st[e, k] = save[k]
        s, gmx = _hb.strength_modulus(ps * q, par, e)
        gr = s / gmx
        qq = _prepare(d, st, par, e, s, gr, c, -1.0)
        tau = _stress_value(g, qq, c, g, -math.inf)[0]
        _commit_counted(g, d, tau, tau + tau_rate, st, par, e, s, t, gr, c, qq[Q_FM] if qq[Q_N] > 0.0 else -1.0)
        dk, rk = dsum, r
        dsum = st[e, S_D] + st[e, S_DPART]
        r = _hd._generated_ratio_known(dsum, alpha, cap, dk, rk)
        f = (1.0 - r) / (1.0 - r_old) - q
        if it == 0:
            if f <= 0.0:
                return tau, r, dsum  # not bracketed (a turning point of the count): the explicit factor
            f_lo = f
            continue
        if abs(f) <= 1e-15 * q or hi - lo <= 1e-15 * hi:  # to round-off: the root, not the path to it
            return tau, r, dsum
        if f > 0.0:
            lo, f_lo = q, f
            if side == 1:
                f_hi *= 0.5  # Illinois: the end that stays is halved
            side = 1
        else:
            hi, f_hi = q, f
            if side == -1:
                f_lo *= 0.5
            side = -1
    return tau, r, dsum


def new_state(n_elements: int, par=None) -> np.ndarray:
    """A virgin state array (no shear history) for ``n_elements`` elements; γ_d from ``par``.

    >>> new_state(2).shape
    (2, 101)
    """
    st = np.zeros((n_elements, NSTATE))
    st[:, S_TLIQ] = -1.0
    st[:, S_RFN] = 1.0  # the count starts at the unloaded state (τ, γ) = (0, 0)
    if par is not None:
        st[:, S_GD] = par[:, P_GD0]
    return st


def static_state(st, par, e, tau_static, ps):
    """Load element ``e`` of a virgin state monotonically on its backbone to the static shear
    stress ``tau_static`` [Pa] (a slope's, before any shaking) at effective vertical stress ``ps``
    [Pa]; returns the static strain γ_s [-], or nan where |τ_s| is at or above the strength.

    The element is left as if it had been loaded there (first loading, direction the sign of
    τ_s, largest strain |γ_s|), with the damage count's start, the last reversal and the centre of the
    cycles γ_c at the static point: the damage counts the cyclic amplitude from the static state,
    not the static stress itself, and dilation is measured from the strain the sand was
    consolidated at. γ_s solves τ_max Φ(γ/γ_r) = τ_s by bisection (the backbone without the
    dilation envelope, which is off at γ = γ_c).

    >>> import numpy as np
    >>> par = np.zeros((1, NPARAM)); par[0, P_K2] = 30.0; par[0, P_TANPHI] = 0.6
    >>> par[0, P_TH3:P_TH5 + 1] = 1.0; par[0, P_SIG0] = 100e3; par[0, P_GD0] = 0.005
    >>> st = new_state(1, par)
    >>> g = static_state(st, par, 0, 30e3, 100e3)   # τ/τ_max = 1/2 on the hyperbola: γ = γ_r
    >>> s, gm = _hb.strength_modulus(100e3, par, 0)
    >>> round(float(g / (s / gm)), 9), float(st[0, S_TAU]), bool(st[0, S_GC] == g)
    (1.0, 30000.0, True)
    """
    s, gmx = _hb.strength_modulus(ps, par, e)
    if tau_static == 0.0:
        return 0.0
    if not abs(tau_static) < s:
        return math.nan
    gr = s / gmx
    d = 1.0 if tau_static > 0.0 else -1.0
    th1, th2, th3, th4, th5 = par[e, P_TH1], par[e, P_TH2], par[e, P_TH3], par[e, P_TH4], par[e, P_TH5]
    target = abs(tau_static) / s
    lo, hi = 0.0, 1.0
    while _hb.gqh_ratio(hi, th1, th2, th3, th4, th5) < target:
        hi *= 2.0
        if hi > 1e12:
            return math.nan
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if mid == lo or mid == hi:
            break
        if _hb.gqh_ratio(mid, th1, th2, th3, th4, th5) < target:
            lo = mid
        else:
            hi = mid
    g = d * hi * gr
    tau = s * _hm._branch(g / gr, 0.0, _hb._constants(st, par, e))[0]
    st[e, S_G] = g
    st[e, S_T] = tau / s
    st[e, S_TAU] = tau
    st[e, S_DIR] = d
    st[e, S_GM] = abs(g)
    st[e, S_GREV] = g
    st[e, S_GC] = g
    st[e, S_RF] = tau  # the damage count starts at the static point
    st[e, S_RF + 1] = g
    st[e, S_RF + 2] = 0.0
    st[e, S_RFN] = 1.0
    st[e, S_RFDIR] = 0.0
    return g
