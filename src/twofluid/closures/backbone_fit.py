"""Fit a GQ/H backbone and MRDF damping to target curves and a shear strength (Groholski et al. 2016).

Given a target table (γ, G/G_max, D) — Darendeli, Menq or measured — the small-strain modulus
G_max and the strength τ_max, :func:`fit_gqh` returns θ1…θ5 of the GQ/H backbone
(:mod:`.backbones`) with γ_r = τ_max/G_max, and p1…p3 of the MRDF damping reduction, so that

- the backbone's secant G/G_max follows the target where the target is reliable (by default
  γ ≤ 1e-2, weighted to the small strains), and
- its stress reaches τ_max at large strain (3–10 % by default), which the modified hyperbola
  of the target does not do (its implied strength is G_max γ_r, a third of P_s tan φ′ or less);
- the damping D = D_min + F(γ) D_Masing(γ) follows the target D(γ): F from the fitted MRDF,
  D_Masing of the fitted backbone, D_min (the small-strain value of the table, supplied by the
  model as a viscous floor: the hysteresis gives none there).

θ4 is fixed at 1 (only θ3^θ5/θ4 enters θ_τ); θ_τ ≤ 1 is built in (θ2 = (1 − θ1) u, 0 ≤ u ≤ 1),
and a penalty keeps the tangent below G_max. The fit is a bounded least squares
(scipy.optimize.least_squares) from a few starting points; the best is kept.

**Stress dependence.** The parameters are fitted once, at a reference stress. At another P_s the
model keeps θ and p and scales G_max ∝ P_s^0.5, τ_max = P_s tan φ′ (or the residual strength),
so γ_r = τ_max/G_max ∝ P_s^0.5 (:meth:`GQHFit.scaled`). The target curves shift less:
Darendeli's γ_r ∝ σ′_m^0.35, Menq's ∝ σ′_m^(0.5 C_u^−0.15) (0.47 at C_u = 1.5); the
difference this makes at 25 and 400 kPa is tabulated in docs/dynamic-curves.md.

**Limitation.** θ_τ(x) rises monotonically from θ1 to θ1 + θ2, so the backbone's G/G_max falls
at most like a hyperbola in x at small strain. Darendeli's curve (a = 0.919) falls faster
between 1e-5 and 1e-3 relative to γ_r = τ_max/G_max, and no θ matches it to 0.03 there while
reaching τ_max by 3 % strain at 25 and 100 kPa (best minimax error 0.034–0.035; 0.030 at
400 kPa). Menq's curves (a = 0.80–0.92 with a larger γ_r) are matched to 0.005–0.011.

>>> import numpy as np
>>> from twofluid.closures.dynamic_curves import menq, menq_damping
>>> g = np.logspace(-6, -2, 25)
>>> fit = fit_gqh(g, menq(g, 100e3), menq_damping(g, 100e3), tau_max=65e3, g_max=65e6)
>>> bool(np.max(np.abs(fit.modulus_reduction(g[g <= 1e-3]) - menq(g[g <= 1e-3], 100e3))) < 0.03)
True
"""
from __future__ import annotations

import dataclasses

import numpy as np
from scipy.optimize import least_squares

from . import backbones as bb

__all__ = ["GQHFit", "fit_gqh", "fit_mrdf"]


@dataclasses.dataclass(frozen=True)
class GQHFit:
    """A fitted GQ/H backbone with MRDF damping.

    theta : (θ1, θ2, θ3, θ4, θ5) [-]; mrdf : (p1, p2, p3) [-]; g_max [Pa]; tau_max [Pa];
    d_min [-] the small-strain damping the model adds as a viscous floor.
    """

    theta: tuple
    mrdf: tuple
    g_max: float
    tau_max: float
    d_min: float

    @property
    def gamma_r(self) -> float:
        """Reference strain γ_r = τ_max/G_max [-]."""
        return self.tau_max / self.g_max

    def backbone(self, gamma):
        """Backbone stress τ(γ) [Pa]."""
        return bb.gqh_backbone(gamma, self.g_max, self.tau_max, self.theta)

    def modulus_reduction(self, gamma):
        """Secant G/G_max at strain amplitudes γ [-]."""
        return bb.gqh_modulus_reduction(gamma, self.gamma_r, self.theta)

    def masing_damping(self, gamma):
        """Masing damping of the backbone [-] at amplitudes γ > 0."""
        return bb.gqh_masing_damping(gamma, self.gamma_r, self.theta)

    def damping(self, gamma):
        """Damping D = D_min + F(γ) D_Masing(γ) [-] of strain-controlled loops of amplitude γ > 0."""
        f = bb.mrdf_factor(self.modulus_reduction(gamma), *self.mrdf)
        return self.d_min + f * self.masing_damping(gamma)

    def scaled(self, stress_ratio: float, strength: float | None = None) -> "GQHFit":
        """The same curve at P_s = stress_ratio · P_s,ref: G_max ∝ P_s^0.5, τ_max ∝ P_s (or
        ``strength`` [Pa] if given, e.g. max(P_s tan φ′, S_r)); θ, p and D_min unchanged."""
        tau = self.tau_max * stress_ratio if strength is None else strength
        return dataclasses.replace(self, g_max=self.g_max * stress_ratio ** 0.5, tau_max=tau)


def _theta(p):
    t1, u, log_t3, t5 = p
    return (t1, (1.0 - t1) * u, float(np.exp(log_t3)), 1.0, t5)


def fit_gqh(strains, g_ratio, damping, tau_max: float, g_max: float, *, d_min: float | None = None,
            fit_strain_max: float = 1e-2, strength_strains=(0.03, 0.1)) -> GQHFit:
    """Fit GQ/H θ's to a G/G_max table and τ_max, then MRDF p's to the damping table.

    Parameters
    ----------
    strains, g_ratio, damping : array_like
        Target table: strain amplitudes γ [-] (> 0, increasing), G/G_max [-] in (0, 1],
        damping ratio D [-] (a fraction). Interpolated nowhere: the points are the residuals.
    tau_max, g_max : float
        Shear strength and small-strain modulus [Pa], > 0, at the stress of the table.
    d_min : float, optional
        Small-strain damping [-]; default the table's damping at its smallest strain.
    fit_strain_max : float
        Largest table strain [-] the G/G_max residuals use.
    strength_strains : (float, float)
        Strain range [-] where the backbone stress should be τ_max.

    Raises
    ------
    ValueError
        A table that is not 1-D of equal lengths with positive increasing strains, G/G_max
        outside (0, 1] or damping outside [0, 1), or τ_max, G_max ≤ 0.
    """
    g = np.asarray(strains, dtype=float)
    r = np.asarray(g_ratio, dtype=float)
    d = np.asarray(damping, dtype=float)
    if g.ndim != 1 or r.shape != g.shape or d.shape != g.shape or g.size < 3:
        raise ValueError("fit_gqh: strains, g_ratio and damping must be 1-D of one length >= 3")
    if not (np.all(g > 0) and np.all(np.diff(g) > 0)):
        raise ValueError("fit_gqh: strains must be > 0 and strictly increasing (fractions, not %)")
    if not (np.all(r > 0) and np.all(r <= 1)) or not (np.all(d >= 0) and np.all(d < 1)):
        raise ValueError("fit_gqh: G/G_max must be in (0, 1] and damping in [0, 1) (fractions, not %)")
    if not (tau_max > 0 and g_max > 0):
        raise ValueError(f"fit_gqh: tau_max and g_max must be > 0 [Pa], got {tau_max}, {g_max}")
    gamma_r = tau_max / g_max
    sel = g <= fit_strain_max
    gf, rf = g[sel], r[sel]
    # weight the small strains: the G/G_max residual is what the loops are checked against
    w = 1.0 + 0.5 * (np.log10(fit_strain_max) - np.log10(gf)) / 4.0
    gs = np.logspace(np.log10(strength_strains[0]), np.log10(strength_strains[1]), 5)
    xs = np.logspace(-4, np.log10(gs[-1] / gamma_r), 60)    # tangent check grid

    def residual(p):
        th = _theta(p)
        res_g = w * (bb.gqh_modulus_reduction(gf, gamma_r, th) - rf)
        res_s = bb.gqh_core(gs / gamma_r, *th) - 1.0
        stiff = np.maximum(bb.gqh_slope_core(xs, *th) - 1.0, 0.0)
        return np.concatenate((res_g, res_s, 10.0 * stiff))

    lo = [-50.0, 0.0, np.log(1e-3), 0.1]
    hi = [1.0, 1.0, np.log(1e4), 5.0]
    best = None
    for t1 in (-1.0, -4.0, -12.0):
        for u in (0.6, 0.95):
            for t3 in (1.0, 10.0, 100.0):
                for t5 in (0.8, 2.0):
                    sol = least_squares(residual, [t1, u, np.log(t3), t5], bounds=(lo, hi), xtol=1e-12,
                                        ftol=1e-12, gtol=1e-12, max_nfev=400)
                    if best is None or sol.cost < best.cost:
                        best = sol
    theta = _theta(best.x)
    if d_min is None:
        d_min = float(d[0])
    fit = GQHFit(theta, (1.0, 0.0, 1.0), float(g_max), float(tau_max), float(d_min))
    return dataclasses.replace(fit, mrdf=fit_mrdf(fit, g, d))


def fit_mrdf(fit: GQHFit, strains, damping) -> tuple:
    """MRDF (p1, p2, p3) so that D_min + F(γ) D_Masing(γ) follows the target damping [-].

    The residuals are scaled by the tolerance the loops are checked to, max(0.1 D, 0.005), so
    the fit balances relative error at large damping and absolute error at small damping.
    Bounds 0 ≤ p1 ≤ 1 (no loop stiffer than G_max on unloading), p2 = p1 v with 0 ≤ v ≤ 1 (F ≥ 0),
    0.05 ≤ p3 ≤ 20.
    """
    g = np.asarray(strains, dtype=float)
    d = np.asarray(damping, dtype=float)
    dm = fit.masing_damping(g)
    gr = fit.modulus_reduction(g)
    scale = np.maximum(0.1 * d, 0.005)

    def residual(p):
        f = bb.mrdf_factor(gr, p[0], p[0] * p[1], p[2])
        return (fit.d_min + f * dm - d) / scale

    best = None
    for p1 in (1.0, 0.8):
        for p3 in (0.5, 1.0, 3.0):
            sol = least_squares(residual, [p1, 0.5, p3], bounds=([0.0, 0.0, 0.05], [1.0, 1.0, 20.0]),
                                xtol=1e-12, ftol=1e-12, gtol=1e-12, max_nfev=400)
            if best is None or sol.cost < best.cost:
                best = sol
    p1, v, p3 = best.x
    return (float(p1), float(p1 * v), float(p3))
