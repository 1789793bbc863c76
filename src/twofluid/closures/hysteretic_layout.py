"""The hysteretic law's arrays (:mod:`twofluid.closures.hysteretic`): the columns of the per-element
state (``S_*``) and parameter (``P_*``) arrays, and of the tuples its scalar functions pass (the
constants ``C_*`` of a sub-step and the prepared ``Q_*`` of a sub-step's Newton iterations).
One place for every index, so that each mechanism module reads the same layout.
"""
from __future__ import annotations

__all__ = ['KPA', 'S_G', 'S_T', 'S_TAU', 'S_GREV', 'S_DIR', 'S_NREV', 'S_GM', 'S_D', 'S_DPART', 'S_RG', 'S_EPS', 'S_LIQ', 'S_GC', 'S_GD', 'S_GC0', 'S_TREV', 'S_RAT', 'S_TLIQ', 'S_RFDIR', 'S_RFN', 'S_RF', 'RF_SIZE', 'S_NSTK', 'S_STK', 'NSTACK', 'R_MASING', 'NSTATE', 'STATE_COLUMNS', 'P_K2', 'P_TANPHI', 'P_SR', 'P_TH1', 'P_TH2', 'P_TH3', 'P_TH4', 'P_TH5', 'P_P1', 'P_P2', 'P_P3', 'P_CRR', 'P_B', 'P_GT', 'P_GLIM', 'P_SIG0', 'P_LIQ', 'P_GDR', 'P_GMAXFIX', 'P_PSFIX', 'P_DR', 'P_ALPHA', 'P_RCAP', 'P_DGD', 'P_GD0', 'P_TAUS', 'P_KC', 'P_GW', 'NPARAM', 'PARAM_COLUMNS', 'C_TH1', 'C_TH2', 'C_C3', 'C_TH4', 'C_TH5', 'C_LIQ', 'C_TAUS', 'C_SR', 'C_GDR', 'C_TDMAX', 'C_GC', 'C_GD', 'C_H5', 'NCONST', 'Q_D', 'Q_S', 'Q_GR', 'Q_VIRGIN', 'Q_N', 'Q_FM', 'Q_GM', 'Q_A', 'Q_B', 'NPREP']

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
S_GC0 = S_STK + 2 * NSTACK  # centre of the cycles when the element triggered γ_c0 [-]
S_TREV = S_GC0 + 1  # τ/τ_max at the last reversal [-]
S_RAT = S_GC0 + 2  # 1 once the strain after triggering has started (:mod:`.hysteretic_ratchet`)
NSTATE = S_GC0 + 3
STATE_COLUMNS = (("gamma", "tau_ratio", "tau", "gamma_rev", "direction",
                  "reversals", "gamma_max", "damage", "damage_part", "r_generated", "eps_v",
                  "liquefied", "gamma_centre", "gamma_d", "t_liquefied", "count_direction", "count_points")
                 + tuple(f"{q}_{j}" for j in range(RF_SIZE) for q in ("count_tau", "count_gamma", "count_damage"))
                 + ("open_reversals",) + tuple(f"{q}_open_{k}" for k in range(NSTACK) for q in ("gamma", "tau_ratio"))
                 + ("gamma_centre_triggered", "tau_ratio_rev", "triggered"))

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
P_KC = 26  # share κ of the way γ_c moves to the last half cycle's mean strain once liquefied [-] (0: fixed)
P_GW = 27  # centre drift γ_w over which γ_dr doubles (weakening of the dilation) [-]
NPARAM = 28
PARAM_COLUMNS = ("k2max", "tan_phi", "residual_strength", "theta1", "theta2", "theta3", "theta4",
                 "theta5", "p1", "p2", "p3", "crr", "b", "gamma_threshold", "gamma_lim", "sigma_v0",
                 "liquefiable", "gamma_dilation", "g_max_fixed", "p_s_fixed", "dr", "alpha", "r_cap",
                 "gamma_d_step", "gamma_d0", "tau_static", "k_centre", "gamma_weakening")


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
