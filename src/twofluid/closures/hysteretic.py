"""Hysteretic effective-stress shear law of saturated sand: the liquefaction column's default.

One element of soil under horizontal shear (strain γ, skeleton stress τ) whose effective
vertical stress P_s falls as pore pressure is generated. Written once, as scalar functions of
an element's row in a state array and a parameter array, in plain Python that numba compiles
(the column's kernel, :mod:`twofluid.models.hysteretic_kernel`) and that also runs un-jitted
(the element test, debugging). docs/liquefaction.md, "The hysteretic model", has the why.

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
the sand was consolidated at (0 on level ground, the static strain on a slope) and stays there;
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

from . import backbones as _bb

__all__ = ["gqh_ratio", "seed_booker", "strength_modulus", "skeleton_stress", "direction", "masing_weight",
           "commit", "commit_counted", "commit_generating", "generated_ratio", "new_state", "static_state", "STATE_COLUMNS", "PARAM_COLUMNS", "KPA"]

KPA = 1000.0

# ---- columns of the per-element state array (float64, one row per element)
S_G = 0  # committed shear strain γ [-]
S_T = 1  # committed skeleton stress over τ_max at commit, τ/τ_max [-]
S_TAU = 2  # stress the damage count took at the last commit (the skeleton's; in the column plus its rate part) [Pa]
S_GREV = 3  # strain at the last reversal [-]
S_DIR = 4  # direction of the last strain increment (−1, 0, +1)
S_NREV = 5  # number of reversals so far
S_GM = 6  # largest |γ| so far [-]
S_D = 7  # damage of the completed half cycles [-]
S_DPART = 8  # damage of the current half cycle so far [-]
S_RG = 9  # generated excess pore-pressure ratio applied so far [-]
S_EPS = 10  # volumetric strain made through n̄ so far, ln((1 − n̄)/(1 − n̄0)) [-]
S_LIQ = 11  # 1 once the element has liquefied (D ≥ 1)
S_GC = 12  # centre of the cycles γ_c [-]
S_GD = 13  # half-width of the zone without dilation γ_d [-]
S_TLIQ = 14  # time of liquefaction [s] (−1: not yet)
S_RFDIR = 15  # direction of the last change of the stress, for the damage count (−1, 0, +1)
S_RFN = 16  # number of turning points on the damage count's stack (≥ 1: its start)
S_RF = 17  # the stack: RF_SIZE rows of (τ [Pa], γ [-], damage of the half cycle that ended there)
RF_SIZE = 16  # turning points kept by the damage count (rainflow); the oldest is dropped beyond
S_NSTK = S_RF + 3 * RF_SIZE  # number of open strain-reversal points of the stress–strain law (0: on the backbone)
S_STK = S_NSTK + 1  # those points, oldest first: (γ_k [-], τ_k/τ_max [-]) at S_STK + 2k, S_STK + 2k + 1
NSTACK = 16  # open reversal points kept (module docstring, "Unloading and reloading")
R_MASING = 0.8  # generated ratio from which the loops turn from MRDF's towards Masing's (:func:`masing_weight`)
NSTATE = S_STK + 2 * NSTACK
STATE_COLUMNS = (("gamma", "tau_ratio", "tau", "gamma_rev", "direction",
                  "reversals", "gamma_max", "damage", "damage_part", "r_generated", "eps_v",
                  "liquefied", "gamma_centre", "gamma_d", "t_liquefied", "count_direction", "count_points")
                 + tuple(f"{q}_{j}" for j in range(RF_SIZE) for q in ("count_tau", "count_gamma", "count_damage"))
                 + ("open_reversals",) + tuple(f"{q}_open_{k}" for k in range(NSTACK) for q in ("gamma", "tau_ratio")))

# ---- columns of the per-element parameter array
P_K2 = 0  # Seed–Idriss K2max [-]
P_TANPHI = 1  # tan φ′ [-]
P_SR = 2  # residual strength S_r [Pa]
P_TH1, P_TH2, P_TH3, P_TH4, P_TH5 = 3, 4, 5, 6, 7  # GQ/H θ1..θ5 [-]
P_P1, P_P2, P_P3 = 8, 9, 10  # MRDF p1..p3 [-]
P_CRR = 11  # field CRR at σ′_v0 (M 7.5, K_σ) [-]
P_B = 12  # slope b of CSR ∝ N^−b [-]
P_GT = 13  # threshold strain γ_t [-]
P_GLIM = 14  # limiting strain γ_lim [-]
P_SIG0 = 15  # σ′_v0 [Pa]
P_LIQ = 16  # 1: generates pore pressure (saturated, liquefiable)
P_GDR = 17  # strain over which dilation restores the strength, γ_dr [-]
P_GMAXFIX = 18  # > 0: fixed G_max [Pa] (crust)
P_PSFIX = 19  # fixed effective vertical stress [Pa] (crust)
P_DR = 20  # relative density Dr [-] (fraction, for the reconsolidation floor)
P_ALPHA = 21  # Seed–Booker α [-]
P_RCAP = 22  # largest generated ratio r_cap [-]
P_DGD = 23  # widening of γ_d per liquefied half cycle [-]
P_GD0 = 24  # γ_d before liquefaction [-]
P_TAUS = 25  # static shear stress τ_s of a slope [Pa] (signed, downslope > 0; 0 on level ground)
NPARAM = 26
PARAM_COLUMNS = ("k2max", "tan_phi", "residual_strength", "theta1", "theta2", "theta3", "theta4",
                 "theta5", "p1", "p2", "p3", "crr", "b", "gamma_threshold", "gamma_lim", "sigma_v0",
                 "liquefiable", "gamma_dilation", "g_max_fixed", "p_s_fixed", "dr", "alpha", "r_cap",
                 "gamma_d_step", "gamma_d0", "tau_static")


def gqh_ratio(x, th1, th2, th3, th4, th5):
    """τ/τ_max of the GQ/H backbone at normalised strain x = |γ|/γ_r ≥ 0 [-] (module docstring;
    :func:`twofluid.closures.backbones.gqh_core`, 0 at x ≤ 0).

    >>> round(gqh_ratio(0.0, 0.0, 0.0, 1.0, 1.0, 1.0), 6)
    0.0
    """
    if x <= 0.0:
        return 0.0
    return _bb.gqh_core(x, th1, th2, th3, th4, th5)


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


def strength_modulus(ps, par, e):
    """(τ_max [Pa], G_max [Pa]) of element ``e`` at effective vertical stress ``ps`` [Pa]."""
    tanphi = par[e, P_TANPHI]
    if par[e, P_GMAXFIX] > 0.0:
        return max(par[e, P_PSFIX] * tanphi, par[e, P_SR]), par[e, P_GMAXFIX]
    p = max(ps, par[e, P_SR] / tanphi, 1e-3)
    return p * tanphi, 218.8 * KPA * par[e, P_K2] * math.sqrt(p / KPA)


# ---- the law at a trial strain, written as scalar functions of two tuples of floats: the
# element's constants over a sub-step (:func:`_constants`) and what its committed state and direction
# fix for a sub-step's Newton iterations (:func:`_prepare`). The compiled kernel keeps both per element
# and evaluates the stress many times per sub-step without recomputing them (the MRDF factor, θ3^θ5,
# the branches' origins) and without passing arrays (each array argument of a compiled call costs a
# reference count); :func:`skeleton_stress` is the same two steps in one call.
# Each returns the stress and its derivative dτ/dγ together (one power and one root per backbone
# evaluation serve both), the derivative of the branch that sets the stress: Newton's stiffness.
C_TH1, C_TH2, C_C3, C_TH4, C_TH5 = 0, 1, 2, 3, 4  # GQ/H θ1, θ2, θ3^θ5, θ4, θ5
C_LIQ, C_TAUS, C_SR, C_GDR, C_TDMAX = 5, 6, 7, 8, 9  # P_LIQ, τ_s, S_r, γ_dr, σ′_v0 tan φ′
C_GC, C_GD = 10, 11  # γ_c, γ_d (state)
C_H5 = 12  # 2^−θ5: θ4 (x/2)^θ5 = θ4 x^θ5 2^−θ5 (one power for a branch's f(x) and f(x/2))
NCONST = 13
Q_D, Q_S, Q_GR, Q_VIRGIN, Q_N, Q_FM, Q_GM = 0, 1, 2, 3, 4, 5, 6  # d, τ_max, γ_r, no direction yet, open points, F, γ_m
Q_A = 7  # the current branch's origin: (γ_0, τ_0 [Pa], τ_max κ, κ γ_r, γ_0 − γ_c, τ_d(γ_0 − γ_c)), 6 floats
Q_B = 13  # the outer branch's origin (n ≥ 3), the same 6 floats
NPREP = 19


def _constants(st, par, e):
    """Constants of element ``e`` for the scalar functions of the law (``C_*``): GQ/H θ1, θ2,
    θ3^θ5, θ4, θ5; whether it dilates (P_LIQ), τ_s, S_r, γ_dr, σ′_v0 tan φ′; γ_c and γ_d; 2^−θ5."""
    th5 = par[e, P_TH5]
    return (par[e, P_TH1], par[e, P_TH2], par[e, P_TH3] ** th5, par[e, P_TH4], th5, par[e, P_LIQ],
            par[e, P_TAUS], par[e, P_SR], par[e, P_GDR], par[e, P_SIG0] * par[e, P_TANPHI],
            st[e, S_GC], st[e, S_GD], 0.5 ** th5)


def _gqh(x, c):
    """(:func:`gqh_ratio`, its slope d/dx) at x ≥ 0 with the constants ``c`` (:func:`_constants`)."""
    if x <= 0.0:
        return 0.0, 1.0
    return _bb.gqh_core_slope_c(x, c[C_TH1], c[C_TH2], c[C_C3], c[C_TH4], c[C_TH5])


def _dil(ex, c):
    """(τ_d ≥ 0 [Pa], dτ_d/dγ [Pa]): the dilation stress at ``ex`` = γ − γ_c from the centre of the
    cycles (0 inside the zone |ex| ≤ γ_d, in sand that generates no pore pressure, and on the side of
    a static shear τ_s that exceeds the residual strength S_r: flow liquefaction, module docstring
    "Flow liquefaction"); ``c`` the element's constants."""
    over = abs(ex) - c[C_GD]
    if over <= 0.0 or c[C_LIQ] <= 0.0:
        return 0.0, 0.0
    ts = c[C_TAUS]
    if ts * ex > 0.0 and abs(ts) > c[C_SR]:
        return 0.0, 0.0  # flow liquefaction: no dilation on the side of a static shear above S_r
    r = over / c[C_GDR]
    if r >= 1.0:
        return c[C_TDMAX] * 1.0, 0.0  # capped
    k = c[C_TDMAX] * 6.0 * r * (1.0 - r) / c[C_GDR]  # smooth onset: S(r) = r²(3 − 2r)
    return c[C_TDMAX] * (r * r * (3.0 - 2.0 * r)), (k if ex > 0.0 else -k)


def _dilation(ex, st, par, e):
    """Dilation stress τ_d ≥ 0 [Pa] of element ``e`` at ``ex`` = γ − γ_c (:func:`_dil`)."""
    return _dil(ex, _constants(st, par, e))[0]


def _env(g, d, tau, k, s, ex0, td0, c):
    """(τ [Pa], dτ/dγ [Pa]): ``tau`` (slope ``k``) limited by the strength envelope max(τ_max, τ_d),
    and raised by the dilation stress gained since the branch's origin γ_0 (``ex0`` = γ_0 − γ_c,
    ``td0`` = τ_d there) when loading outwards beyond γ_d (module docstring, "Cyclic mobility"):
    τ_d(γ) − τ_d(γ_0) where the origin lies beyond γ_d on the same side, so a branch that turns back
    outwards within the dilation zone starts from its reversal stress, not from τ_d above it (a jump
    at the reversal)."""
    upper = s
    ku = 0.0
    lower = -s
    kl = 0.0
    ex = g - c[C_GC]
    td, kd = _dil(ex, c)
    if td > 0.0:
        gain = td
        if ex0 * ex > 0.0:
            gain = td - td0
        if ex > 0.0:
            if td > upper:
                upper = td
                ku = kd
            if d > 0.0 and gain > 0.0:
                tau += gain
                k += kd
        else:
            if -td < lower:
                lower = -td
                kl = -kd
            if d < 0.0 and gain > 0.0:
                tau -= gain
                k -= kd
    if tau > upper:
        tau = upper
        k = ku
    if tau < lower:
        tau = lower
        k = kl
    return tau, k


def _branch(y, fm, c):
    """(Φ(y), dΦ/dy): Φ = F (2 f(y/2) − f(y)) + f(y), odd in y = (γ − γ_0)/γ_r, a Masing/MRDF branch
    over τ_max (F = 0: the backbone f, F = 1: Masing's 2 f(y/2)); ``c`` the element's constants."""
    x = abs(y)
    if fm == 0.0:
        phi, k = _gqh(x, c)
    elif fm == 1.0:
        f2, k = _gqh(0.5 * x, c)
        phi = 2.0 * f2
    elif x > 0.0:  # f(x) and f(x/2) from one power
        w = c[C_TH4] * x ** c[C_TH5]
        f1, k1 = _bb.gqh_slope_w(x, w, c[C_TH1], c[C_TH2], c[C_C3], c[C_TH5])
        f2, k2 = _bb.gqh_slope_w(0.5 * x, w * c[C_H5], c[C_TH1], c[C_TH2], c[C_C3], c[C_TH5])
        phi = fm * (2.0 * f2 - f1) + f1
        k = fm * (k2 - k1) + k1
    else:
        phi, k = 0.0, 1.0
    return (phi if y >= 0.0 else -phi), k


def masing_weight(st, par, e):
    """Weight w ∈ [0, 1] of Masing's rule in the unloading–reloading factor of element ``e``: 0 up to
    a generated ratio r_g = ``R_MASING``, then S((r_g − R_MASING)/(r_cap − R_MASING)), S(x) = x²(3 − 2x),
    1 at r_cap (module docstring, "Unloading and reloading"). A continuous function of r_g, so the
    loops turn from the intact skeleton's into Masing's as the pore pressure is generated, never in
    a jump.

    >>> import numpy as np
    >>> par = np.zeros((1, NPARAM)); par[0, P_RCAP] = 0.999; st = np.zeros((1, NSTATE))
    >>> st[0, S_RG] = 0.5; a = masing_weight(st, par, 0); st[0, S_RG] = 0.999
    >>> a, masing_weight(st, par, 0)
    (0.0, 1.0)
    """
    x = (st[e, S_RG] - R_MASING) / (par[e, P_RCAP] - R_MASING)
    if x <= 0.0:
        return 0.0
    if x >= 1.0:
        return 1.0
    return x * x * (3.0 - 2.0 * x)


def _mrdf(st, par, e, gr, c):
    """F of the unloading–reloading branches of element ``e`` (1: Masing): MRDF's factor at the
    largest strain so far, moved towards Masing's F = 1 by :func:`masing_weight` as the pore pressure
    is generated (a liquefied element flows between its dilation stops on Masing branches)."""
    f = par[e, P_P1]
    if par[e, P_P2] != 0.0:
        xm = st[e, S_GM] / gr
        red = 1.0
        if xm > 0.0:
            red = _gqh(xm, c)[0] / xm
        f = par[e, P_P1] - par[e, P_P2] * max(1.0 - red, 0.0) ** par[e, P_P3]
    if par[e, P_LIQ] > 0.0:
        w = masing_weight(st, par, e)
        if w > 0.0:
            f = f + (1.0 - f) * w
    return f


def _origin(g0, t0, d, s, gr, fm, c):
    """What the branch in direction ``d`` from the reversal (``g0``, ``t0`` τ/τ_max) needs of its
    origin, once per sub-step: (γ_0, τ_0 [Pa], τ_max κ [Pa], κ γ_r, γ_0 − γ_c, τ_d(γ_0 − γ_c) [Pa]).

    From a stress the dilation carried above τ_max the branch is wider (κ > 1), so that it still
    reaches the strength the other way (asymptote d τ_max)."""
    kappa = max(1.0, abs(d - t0) / (1.0 + fm)) if abs(t0) > 1.0 else 1.0
    ex0 = g0 - c[C_GC]
    return g0, t0 * s, s * kappa, kappa * gr, ex0, _dil(ex0, c)[0]


def _on(g, d, g0, ts0, sk, kg, ex0, td0, s, fm, c):
    """(τ [Pa], dτ/dγ [Pa]) at ``g`` of the branch in direction ``d`` from the origin (``g0``,
    ``ts0``, ``sk``, ``kg``, ``ex0``, ``td0``: :func:`_origin`) within the strength envelope, with the
    dilation gained since the origin."""
    phi, k = _branch((g - g0) / kg, fm, c)
    return _env(g, d, ts0 + sk * phi, sk * k / kg, s, ex0, td0, c)


def _reversal_branch(g, d, g0, t0, s, gr, fm, c):
    """Stress [Pa] at ``g`` of the branch from the reversal (``g0``, ``t0`` τ/τ_max) in direction
    ``d`` within the strength envelope, with the dilation gained since ``g0``."""
    o = _origin(g0, t0, d, s, gr, fm, c)
    return _on(g, d, o[0], o[1], o[2], o[3], o[4], o[5], s, fm, c)[0]


def _backbone(g, d, s, gr, c):
    """(τ [Pa], dτ/dγ [Pa]) of the backbone at ``g`` within the strength envelope, with the dilation
    gained since the centre of the cycles γ_c (the cap beyond the largest strain so far)."""
    phi, k = _branch(g / gr, 0.0, c)
    return _env(g, d, s * phi, s * k / gr, s, 0.0, 0.0, c)


def _open_count(d, st, e):
    """Open reversal points of element ``e`` while it moves in direction ``d`` from its committed
    state, and whether the last of them is the committed point itself (a reversal now, pushed at
    the commit): a function of the committed state and ``d`` only, fixed over Newton's iterations.

    At a reversal the pairs whose loop the branch just left had already closed (its strain passed
    their target) are dropped, and so is the innermost pair when the stack is full; a reversal at
    the largest strain so far starts afresh."""
    n = int(st[e, S_NSTK])
    d_old = st[e, S_DIR]
    if d_old == 0.0 or d == d_old:
        return n, False
    gc = st[e, S_G]
    if abs(gc) >= st[e, S_GM]:
        return 1, True
    while n >= 2 and d_old * (gc - st[e, S_STK + 2 * (n - 2)]) >= 0.0:
        n -= 2
    if n >= NSTACK:
        n -= 2
    return n + 1, True


def _open_point(k, n, rev, st, e):
    """(γ, τ/τ_max) of open reversal point ``k`` of ``n`` (:func:`_open_count`)."""
    if rev and k == n - 1:
        return st[e, S_G], st[e, S_T]
    return st[e, S_STK + 2 * k], st[e, S_STK + 2 * k + 1]


def _open_stress(g, d, n, rev, st, e, s, gr, fm, c):
    """The lower (in direction ``d``) of the branch from the last open reversal point and the outer
    branch that its loop closes onto (the one from the point before its target), before the
    backbone cap and the envelope [Pa]."""
    g0, t0 = _open_point(n - 1, n, rev, st, e)
    tau = _reversal_branch(g, d, g0, t0, s, gr, fm, c)
    if n >= 3:
        g1, t1 = _open_point(n - 3, n, rev, st, e)
        to = _reversal_branch(g, d, g1, t1, s, gr, fm, c)
        if d * to < d * tau:
            tau = to
    return tau


def direction(g, st, e):
    """Direction (±1) of a strain increment to ``g`` from the committed strain (the last one's if 0)."""
    dg = g - st[e, S_G]
    if dg > 0.0:
        return 1.0
    if dg < 0.0:
        return -1.0
    return st[e, S_DIR] if st[e, S_DIR] != 0.0 else 1.0


def _prepare(d, st, par, e, s, gr, c):
    """What element ``e``'s committed state and the direction ``d`` fix for a sub-step with strength
    ``s`` [Pa] and reference strain ``gr`` (``Q_*``): the open reversal points (:func:`_open_count`)
    and the origins of the branches from them, the MRDF factor, the largest strain so far."""
    n, rev = _open_count(d, st, e)
    virgin = 1.0 if st[e, S_DIR] == 0.0 else 0.0
    if n == 0:
        return (d, s, gr, virgin, 0.0, 0.0, st[e, S_GM], 0.0, 0.0, 0.0, 0.0, 0.0, 0.0,
                0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    fm = _mrdf(st, par, e, gr, c)
    g0, t0 = _open_point(n - 1, n, rev, st, e)
    a = _origin(g0, t0, d, s, gr, fm, c)
    b = a
    if n >= 3:
        g1, t1 = _open_point(n - 3, n, rev, st, e)
        b = _origin(g1, t1, d, s, gr, fm, c)
    return (d, s, gr, virgin, float(n), fm, st[e, S_GM], a[0], a[1], a[2], a[3], a[4], a[5],
            b[0], b[1], b[2], b[3], b[4], b[5])


def _stress(g, q, c):
    """(τ [Pa], dτ/dγ [Pa]): :func:`skeleton_stress` at ``g`` from the prepared ``q``
    (:func:`_prepare`) and the constants ``c`` (:func:`_constants`), and the derivative of the
    branch that sets it."""
    d = q[Q_D]
    s = q[Q_S]
    if q[Q_N] == 0.0:  # first loading, or a loop closed onto the backbone: the backbone
        return _backbone(g, d, s, q[Q_GR], c)
    fm = q[Q_FM]
    tau, k = _on(g, d, q[Q_A], q[Q_A + 1], q[Q_A + 2], q[Q_A + 3], q[Q_A + 4], q[Q_A + 5], s, fm, c)
    if q[Q_N] >= 3.0:  # the outer branch the current loop closes onto
        to, ko = _on(g, d, q[Q_B], q[Q_B + 1], q[Q_B + 2], q[Q_B + 3], q[Q_B + 4], q[Q_B + 5], s, fm, c)
        if d * to < d * tau:
            tau = to
            k = ko
    if d * g > q[Q_GM]:  # beyond the largest strain so far: not past the backbone (with its dilation)
        tb, kb = _backbone(g, d, s, q[Q_GR], c)
        if d * tau > d * tb:
            tau = tb
            k = kb
    return tau, k


def _store(a, e, x):
    """Row ``e`` of the work array ``a`` ← the tuple ``x`` (the kernel's per-element ``c``, ``q``)."""
    for k in range(len(x)):
        a[e, k] = x[k]


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
    >>> s, gm = strength_modulus(0.0, par, 0)  # liquefied: the residual strength S_r = 4.5 kPa
    >>> taus = []
    >>> for g in list(gc + np.linspace(0.001, 0.04, 40)) + [gc + 0.0399, gc + 0.0401]:  # out, back 0.01 %, out
    ...     d = direction(g, st, 0); tau = skeleton_stress(g, d, st, par, 0, s, s / gm)
    ...     _ = commit(g, d, tau, st, par, 0, s, 0.0, s / gm); taus.append(tau)
    >>> [round(float(x) / 1e3, 1) for x in taus[-3:]]  # kPa: at 4 %, after the wiggle, past 4 % again
    [14.7, 13.2, 14.8]
    """
    c = _constants(st, par, e)
    return _stress(g, _prepare(d, st, par, e, s, gr, c), c)[0]


def _close_loops(g, d, st, par, e, s, gr, c, fm):
    """Loop closure at the committed strain ``g`` (direction ``d``; the stack already holds this
    sub-step's reversal): drops the innermost open pair once ``g`` has passed its target and the
    outer branch is the active one there, and every point once the backbone is (beyond the largest
    strain so far). Only what no longer sets the stress at ``g`` is dropped, so the stress there is
    unchanged: closing a loop is never a jump. ``c``: the element's constants (:func:`_constants`);
    ``fm``: the branches' F (:func:`_mrdf`, the same before and after the commit's push), < 0 where
    not known yet."""
    n = int(st[e, S_NSTK])
    if n == 0:
        return
    if fm < 0.0:
        fm = _mrdf(st, par, e, gr, c)
    while n >= 3 and d * (g - st[e, S_STK + 2 * (n - 2)]) >= 0.0:
        gi, go = st[e, S_STK + 2 * (n - 1)], st[e, S_STK + 2 * (n - 3)]
        ti = _reversal_branch(g, d, gi, st[e, S_STK + 2 * (n - 1) + 1], s, gr, fm, c)
        to = _reversal_branch(g, d, go, st[e, S_STK + 2 * (n - 3) + 1], s, gr, fm, c)
        if d * ti < d * to:
            break
        n -= 2
    if d * g > st[e, S_GM]:
        tb = _backbone(g, d, s, gr, c)[0]
        if d * tb <= d * _open_stress(g, d, n, False, st, e, s, gr, fm, c):
            n = 0
    st[e, S_NSTK] = n


def half_cycle_damage(ta, ga, par, e):
    """Damage of a half cycle of stress amplitude ``ta`` [Pa] and strain amplitude ``ga`` [-]."""
    gt = par[e, P_GT]
    ft = (ga - gt) / gt
    if ft <= 0.0 or ta <= 0.0:
        return 0.0
    if ft > 1.0:
        ft = 1.0
    csr = ta / par[e, P_SIG0]
    return ft / 30.0 * (csr / par[e, P_CRR]) ** (1.0 / par[e, P_B])


def _count_damage(g, tau, st, par, e):
    """Count the damage of element ``e`` at its new stress ``tau`` [Pa] and strain ``g``, before
    they are committed: half cycles of stress found by rainflow counting (ASTM E1049's three-point
    rule, applied as the history arrives), each weighted by :func:`half_cycle_damage`.

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
    dd = half_cycle_damage(0.5 * abs(tau - st[e, S_RF + 3 * k]), 0.5 * abs(g - st[e, S_RF + 3 * k + 1]), par, e)
    if closed or dd > st[e, S_DPART]:
        st[e, S_DPART] = dd


def commit(g, d, tau, st, par, e, s, t, gr):
    """Commit the converged strain ``g``, reached in direction ``d``, and stress ``tau`` [Pa] of
    element ``e`` at time ``t`` [s], with the sub-step's reference strain ``gr`` [-]: reversals
    and loop closure, the largest strain, damage and liquefaction. Returns the total damage."""
    return _commit_counted(g, d, tau, tau, st, par, e, s, t, gr, _constants(st, par, e), -1.0)


def commit_counted(g, d, tau, tau_count, st, par, e, s, t, gr):
    """:func:`commit` with the damage counted on ``tau_count`` [Pa] instead of the skeleton stress
    ``tau``: in the column, the shear stress the element carries, skeleton and rate (viscous) parts
    together, as the laboratory's CSR is the stress applied to the specimen, whatever part of it
    its rate carries."""
    return _commit_counted(g, d, tau, tau_count, st, par, e, s, t, gr, _constants(st, par, e), -1.0)


def _commit_counted(g, d, tau, tau_count, st, par, e, s, t, gr, c, fm):
    """:func:`commit_counted` with the element's constants ``c`` (:func:`_constants`, γ_d as before
    the commit) and the branches' F ``fm`` (:func:`_mrdf` at ``gr``; < 0: not known, computed where
    needed) given."""
    g_old = st[e, S_G]
    d_old = st[e, S_DIR]
    if par[e, P_LIQ] > 0.0:
        _count_damage(g, tau_count, st, par, e)
    if d_old != 0.0 and d != d_old:  # the strain reversed at g_old: a new branch
        n, _ = _open_count(d, st, e)  # pushed: g_old, with the pairs it closes dropped
        st[e, S_STK + 2 * (n - 1)] = g_old
        st[e, S_STK + 2 * (n - 1) + 1] = st[e, S_T]
        st[e, S_NSTK] = n
        st[e, S_GREV] = g_old
        st[e, S_NREV] += 1.0
    st[e, S_DIR] = d
    st[e, S_G] = g
    st[e, S_T] = tau / s
    st[e, S_TAU] = tau_count
    _close_loops(g, d, st, par, e, s, gr, c, fm)
    if abs(g) > st[e, S_GM]:
        st[e, S_GM] = abs(g)
    if st[e, S_LIQ] > 0.0:  # cyclic mobility: the zone widens with the strain travelled inside it
        gc = st[e, S_GC]
        gd = st[e, S_GD]
        inside = min(max(g_old, g), gc + gd) - max(min(g_old, g), gc - gd)
        if inside > 0.0 and gd < par[e, P_GLIM]:
            st[e, S_GD] = min(par[e, P_GLIM], math.sqrt(gd * gd + par[e, P_DGD] * inside))
    if par[e, P_LIQ] > 0.0 and st[e, S_LIQ] == 0.0 and st[e, S_D] + st[e, S_DPART] >= 1.0:
        st[e, S_LIQ] = 1.0
        st[e, S_TLIQ] = t
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
    return _commit_generating(g, d, st, par, e, ps, t, save, tau_rate, _constants(st, par, e))


def _commit_generating(g, d, st, par, e, ps, t, save, tau_rate, c):
    """:func:`commit_generating` with the element's constants ``c`` (:func:`_constants`) given."""
    s, gmx = strength_modulus(ps, par, e)
    gr = s / gmx
    q = _prepare(d, st, par, e, s, gr, c)
    tau = _stress(g, q, c)[0]
    fm = q[Q_FM] if q[Q_N] > 0.0 else -1.0
    r_old = st[e, S_RG]
    if par[e, P_LIQ] <= 0.0 or ps <= 0.0 or r_old >= par[e, P_RCAP]:
        _commit_counted(g, d, tau, tau + tau_rate, st, par, e, s, t, gr, c, fm)
        return tau
    for k in range(NSTATE):
        save[k] = st[e, k]
    _commit_counted(g, d, tau, tau + tau_rate, st, par, e, s, t, gr, c, fm)
    q1 = (1.0 - generated_ratio(st, par, e)) / (1.0 - r_old)
    if q1 >= 1.0 - 1e-12 or s <= par[e, P_SR] * (1.0 + 1e-12):
        return tau  # no generation, or the strength already at its floor: the explicit count holds
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
        s, gmx = strength_modulus(ps * q, par, e)
        gr = s / gmx
        qq = _prepare(d, st, par, e, s, gr, c)
        tau = _stress(g, qq, c)[0]
        _commit_counted(g, d, tau, tau + tau_rate, st, par, e, s, t, gr, c, qq[Q_FM] if qq[Q_N] > 0.0 else -1.0)
        f = (1.0 - generated_ratio(st, par, e)) / (1.0 - r_old) - q
        if it == 0:
            if f <= 0.0:
                return tau  # not bracketed (a turning point of the count): the explicit factor
            f_lo = f
            continue
        if abs(f) <= 1e-15 * q or hi - lo <= 1e-15 * hi:  # to round-off: the root, not the path to it
            return tau
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
    return tau


def generated_ratio(st, par, e):
    """r_g of element ``e`` from its damage (Seed–Booker, capped at r_cap) [-]."""
    r = seed_booker(st[e, S_D] + st[e, S_DPART], par[e, P_ALPHA])
    cap = par[e, P_RCAP]
    return r if r < cap else cap


def new_state(n_elements: int, par=None) -> np.ndarray:
    """A virgin state array (no shear history) for ``n_elements`` elements; γ_d from ``par``.

    >>> new_state(2).shape
    (2, 98)
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
    >>> s, gm = strength_modulus(100e3, par, 0)
    >>> round(float(g / (s / gm)), 9), float(st[0, S_TAU]), bool(st[0, S_GC] == g)
    (1.0, 30000.0, True)
    """
    s, gmx = strength_modulus(ps, par, e)
    if tau_static == 0.0:
        return 0.0
    if not abs(tau_static) < s:
        return math.nan
    gr = s / gmx
    d = 1.0 if tau_static > 0.0 else -1.0
    th1, th2, th3, th4, th5 = par[e, P_TH1], par[e, P_TH2], par[e, P_TH3], par[e, P_TH4], par[e, P_TH5]
    target = abs(tau_static) / s
    lo, hi = 0.0, 1.0
    while gqh_ratio(hi, th1, th2, th3, th4, th5) < target:
        hi *= 2.0
        if hi > 1e12:
            return math.nan
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if mid == lo or mid == hi:
            break
        if gqh_ratio(mid, th1, th2, th3, th4, th5) < target:
            lo = mid
        else:
            hi = mid
    g = d * hi * gr
    tau = s * _branch(g / gr, 0.0, _constants(st, par, e))[0]
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
