r"""Solidification of a liquefied sand column (Scott 1986), for the two-fluid model's closures.

Setting (y upward, impervious base at y = 0, drained top)
----------------------------------------------------------
A column of height H of fully liquefied sand: uniform porosity n_l, zero effective
stress (r_u = 1 everywhere), nothing shaking. The grains settle through the liquid;
a solidified layer builds up from the base; the top of the sand descends. Scott
(1986) treats the grains as rigid (the solidified sand at one porosity n_s) and finds
a front rising linearly in time and a surface settling linearly in time until they
meet; he then adds the consolidation of the accreting layer (Gibson 1958), which
makes the measured excess pore pressure lag the rigid-grain prediction. Below, the
rigid-grain theory is generalised to the granular pressure of the model (a
compressible skeleton), with the skeleton drained (in equilibrium) at all times;
the rigid case is its limit A → 0.

1. The liquefied zone (suspension). V = n U_f + (1 − n) U_s = 0 everywhere (continuity
   with an impervious base), so the slip is s = U_f − U_s = −U_s/n. Inertia and viscous
   stresses dropped, u = P − P_hydrostatic the excess pore pressure, Δγ = (ρ_s − ρ_f) g:
   liquid  −n ∂u/∂y = β s;  mixture  ∂u/∂y = −(1 − n) Δγ − ∂P_s/∂y.
   With P_s uniform (n and n̄ uniform) the excess pore pressure carries the buoyant
   weight, ∂u/∂y = −(1 − n_l) Δγ, and the grains settle at

       v_s = −U_s = n s,   β(n_l, s) s = n_l (1 − n_l) Δγ,

   i.e. v_s = k (1 − n_l)(ρ_s − ρ_f)/ρ_f with k = ρ_f g n²/β the hydraulic conductivity
   of docs/model.md; for Kozeny–Carman (the Stokes Ergun law, constant 150)
   v_s = n_l³ Δγ d²/(150 μ_f (1 − n_l)). The top of the sand descends at v_s.
2. The solidified layer (deposit), drained: no relative flow, so u is uniform in it
   (equal to the buoyant weight of the suspension above it) and the skeleton carries
   its own buoyant weight: with m the solids volume per unit area measured down from
   the deposit's top, σ = P_s = P_l + Δγ m, where P_l = P_s(n_l, n̄) (the liquefied
   state's own, vanishingly small, granular pressure). The exponential law
   P_s = p_ref exp[(1/A)(1 − (1 − n̄)/(1 − n))] gives the porosity there,
   (1 − n̄)/(1 − n) = 1 − A ln(σ/p_ref): n = n_l at the deposit's top, denser below.
3. Thickness of a deposit whose base carries σ_M (dy = dm/(1 − n)):

       Z(σ_M) = [F(σ)]_{P_l}^{σ_M} / ((1 − n̄) Δγ),   F(σ) = σ (1 + A − A ln(σ/p_ref)).

4. Mass balance across the front. Solids cross the deposit's top, rising at ẏ_f, from a
   suspension falling at v_s: dM/dt = (1 − n_l)(v_s + ẏ_f), M = (σ_M − P_l)/Δγ, and
   ẏ_f = Z′ dM/dt with Z′ = 1/(1 − n_b), n_b the porosity at the deposit's base (adding
   solids on top compresses every layer below; the self-similar profile in m makes it
   the same as adding them at the bottom). Hence
   dM/dt = (1 − n_l) v_s (1 − n_b)/(n_l − n_b), and with c = (1 − n_l)/(1 − n̄),

       t(σ_M) = [G(σ)]_{P_l}^{σ_M} / (Δγ (1 − n_l) v_s),   G(σ) = (1 − c) σ + c A σ (ln(σ/p_ref) − 1).

   The front is y_f(t) = Z(σ_M(t)), σ_M the inverse of t(σ_M) (monotone). The top of the
   sand is at h(t) = H − v_s t, the surface settlement S(t) = v_s t, until the front
   meets it at t_end = t(σ_end), σ_end = P_l + Δγ (1 − n_l) H (all solids deposited);
   then S_end = H − Z(σ_end), and the drained deposit is at rest. The excess pore
   pressure at the base is the buoyant weight of the suspension,
   u_b(t) = Δγ (1 − n_l) H + P_l − σ_M(t), falling to zero at t_end.
5. Rigid grains (A → 0, Scott 1986): P_l → 0, n_b = n̄ everywhere, and everything is
   linear in time: ẏ_f = v_f = (1 − n_l) v_s/(n_l − n̄) (the shock speed of Kynch 1952),
   t_end = H/(v_s + v_f) = H (n_l − n̄)/((1 − n̄) v_s), S_end = H (n_l − n̄)/(1 − n̄),
   u_b = Δγ (1 − n_l)(H − (v_s + v_f) t).

Fixed surface (small strain). The liquefaction column (:mod:`twofluid.models.liquefaction_1d`)
keeps its drained top at the top of the mesh (the Galerkin solids flux: solids enter
through it as the skeleton settles) and reports the settlement as the compression of the
skeleton, S_ss = Σ h_e (n0 − n_e)/(1 − n_e). Its front rises by the same law (item 4 does not
involve the surface) but only stops at the top of the mesh, where Z(σ_M) = H, and

    S_ss(t) = Z(σ_M) − c [K(σ)]_{P_l}^{σ_M} / ((1 − n̄) Δγ),
    K(σ) = σ − 2Aσ(L − 1) + A²σ(L² − 2L + 2),  L = ln(σ/p_ref).

For rigid grains S_ss = c v_s t: the rate is c = (1 − n_l)/(1 − n̄) of the true one and the
time to solidify 1/c as long, while the final settlement is the same (a geometrically
linear description's error, of the order of the strain (n_l − n̄)/(1 − n̄)).

Assumptions: 1D, incompressible phases, inertia and viscous stresses negligible (creeping
settlement), drag from the model's law, P_s the exponential law with one n̄ and A, the
deposit drained. The last is exact only as A → 0: the deposit's consolidation
coefficient c_v = k M/(ρ_f g) with M ≈ σ/A, and the ratio of its consolidation time to
its deposition time is the consolidation number Λ = A (1 − n_l)/(n_l − n̄) (Gibson's
m²t/c_v, here independent of time). For finite Λ the model's excess pore pressure lags
u_b — Scott's centrifuge observation — by a fraction of the initial u that vanishes
linearly with A.

References
----------
Scott, R. F. (1986). Solidification and consolidation of a liquefied sand column. *Soils
and Foundations* 26(4), 23–31.
Gibson, R. E. (1958). The progress of consolidation in a clay layer increasing in thickness
with time. *Géotechnique* 8(4), 171–182.
Kynch, G. J. (1952). A theory of sedimentation. *Trans. Faraday Soc.* 48, 166–176.
Pringle (2001), thesis eqs. 3.41–3.54 (the exponential granular pressure).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["ScottColumn", "kozeny_carman_settling_velocity", "settling_velocity"]

Array = NDArray[np.float64]


def kozeny_carman_settling_velocity(n: ArrayLike, d: float, rho_s: float, rho_f: float, mu_f: float,
                                    g: float = 9.81) -> Array:
    """Settling velocity v_s [m/s] of a uniform liquefied sand with the Kozeny–Carman drag
    β = 150 (1 − n)² μ_f/(n d²) (the Stokes Ergun law): v_s = n³ (ρ_s − ρ_f) g d²/(150 μ_f (1 − n)).

    n porosity [-], d drag diameter [m], rho_s, rho_f [kg/m³], mu_f [Pa·s], g [m/s²].

    >>> round(float(kozeny_carman_settling_velocity(0.46, 2e-4, 2650.0, 1000.0, 1e-3)), 9)
    0.000778039
    """
    n = np.asarray(n, dtype=float)
    return n**3 * (rho_s - rho_f) * g * d * d / (150.0 * mu_f * (1.0 - n))


def settling_velocity(n: float, beta: Callable[[float, float], float], rho_s: float, rho_f: float,
                      g: float = 9.81) -> float:
    """Settling velocity v_s = n s [m/s] of a uniform liquefied sand for a drag law ``beta(n, |s|)``
    [N·s/m⁴]: the root of β(n, s) s = n (1 − n)(ρ_s − ρ_f) g (module docstring, item 1).

    >>> kc = lambda n, s: 150.0 * (1 - n) ** 2 * 1e-3 / (n * 4e-8)
    >>> round(settling_velocity(0.46, kc, 2650.0, 1000.0) * 1e3, 6)
    0.778039
    """
    from ..scipy_kernels import brentq

    load = n * (1.0 - n) * (rho_s - rho_f) * g
    f = lambda s: beta(n, s) * s - load  # noqa: E731  increasing in s for every registered law
    hi = load / beta(n, 0.0)
    while f(hi) < 0.0:
        hi *= 2.0
    return n * brentq(f, 0.0, hi, xtol=1e-30, rtol=1e-15)


def _xlnx(x: Array, p: float) -> Array:
    """x ln(x/p), 0 at x = 0."""
    x = np.asarray(x, dtype=float)
    return np.where(x > 0.0, x * np.log(np.where(x > 0.0, x, 1.0) / p), 0.0)


@dataclass(frozen=True)
class ScottColumn:
    """Drained solidification of a liquefied column (module docstring); A = 0: Scott's rigid grains.

    Parameters: ``height`` H [m], ``porosity`` n_l of the liquefied sand, ``reference_porosity``
    n̄ (< n_l) and ``compressibility`` A ≥ 0 of the granular pressure, ``p_ref`` [Pa],
    ``settling_velocity`` v_s [m/s], ``buoyant_unit_weight`` Δγ = (ρ_s − ρ_f) g [N/m³].

    >>> c = ScottColumn(1.0, 0.46, 0.42, 0.0, 1e-3, 16186.5)  # rigid grains
    >>> round(c.front_speed_rigid, 6), round(c.end_time, 3), round(c.final_settlement, 6)
    (0.0135, 68.966, 0.068966)
    >>> bool(np.isclose(c.front(30.0), 0.0135 * 30.0)), bool(np.isclose(c.settlement(30.0), 0.03))
    (True, True)
    """

    height: float
    porosity: float
    reference_porosity: float
    compressibility: float
    settling_velocity: float
    buoyant_unit_weight: float
    p_ref: float = 1.0

    def __post_init__(self):
        nl, nb, A = self.porosity, self.reference_porosity, self.compressibility
        if not (0.0 < nb < nl < 1.0):
            raise ValueError(f"need 0 < reference porosity ({nb}) < liquefied porosity ({nl}) < 1")
        if A < 0.0 or self.settling_velocity <= 0.0 or self.buoyant_unit_weight <= 0.0 or self.height <= 0.0:
            raise ValueError("need A >= 0 and positive H, v_s and (rho_s - rho_f) g")

    # ----------------------------------------------------------- constants
    @property
    def liquefied_pressure(self) -> float:
        """P_l = P_s(n_l, n̄) [Pa] (0 for rigid grains; underflows to 0 for small A)."""
        A, nl, nb = self.compressibility, self.porosity, self.reference_porosity
        return 0.0 if A == 0.0 else self.p_ref * float(np.exp(-(nl - nb) / (A * (1.0 - nl))))

    @property
    def c(self) -> float:
        """(1 − n_l)/(1 − n̄) [-]."""
        return (1.0 - self.porosity) / (1.0 - self.reference_porosity)

    @property
    def base_stress_end(self) -> float:
        """σ_end = P_l + Δγ (1 − n_l) H [Pa], the granular pressure at the base once all has settled."""
        return self.liquefied_pressure + self.buoyant_unit_weight * (1.0 - self.porosity) * self.height

    @property
    def consolidation_number(self) -> float:
        """Λ = A (1 − n_l)/(n_l − n̄) [-]: consolidation time / deposition time of the deposit."""
        return self.compressibility * (1.0 - self.porosity) / (self.porosity - self.reference_porosity)

    @property
    def front_speed_rigid(self) -> float:
        """Scott's (rigid-grain) front speed v_f = (1 − n_l) v_s/(n_l − n̄) [m/s]."""
        return (1.0 - self.porosity) * self.settling_velocity / (self.porosity - self.reference_porosity)

    # ------------------------------------------------------------ profiles
    def porosity_at(self, sigma: ArrayLike) -> Array:
        """Drained porosity under granular pressure σ [Pa]: (1 − n̄)/(1 − n) = 1 − A ln(σ/p_ref).

        >>> c = ScottColumn(1.0, 0.46, 0.42, 1e-3, 1e-3, 16186.5)
        >>> round(float(c.porosity_at(c.liquefied_pressure)), 12), round(float(c.porosity_at(1e4)), 5)
        (0.46, 0.41461)
        """
        s = np.asarray(sigma, dtype=float)
        return 1.0 - (1.0 - self.reference_porosity) / (1.0 - self.compressibility * np.log(s / self.p_ref))

    def _F(self, s):
        A = self.compressibility
        return np.asarray(s, dtype=float) * (1.0 + A) - A * _xlnx(s, self.p_ref)

    def _G(self, s):
        A, c = self.compressibility, self.c
        s = np.asarray(s, dtype=float)
        return (1.0 - c) * s + c * A * (_xlnx(s, self.p_ref) - s)

    def _K(self, s):
        A, p = self.compressibility, self.p_ref
        s = np.asarray(s, dtype=float)
        L = np.log(np.where(s > 0.0, s, 1.0) / p)
        return np.where(s > 0.0, s - 2.0 * A * s * (L - 1.0) + A * A * s * (L * L - 2.0 * L + 2.0), 0.0)

    def thickness(self, sigma: ArrayLike) -> Array:
        """Z(σ_M) [m]: thickness of the drained deposit whose base carries σ_M [Pa] (item 3)."""
        k = 1.0 / ((1.0 - self.reference_porosity) * self.buoyant_unit_weight)
        return (self._F(sigma) - self._F(self.liquefied_pressure)) * k

    def time_of(self, sigma: ArrayLike) -> Array:
        """t(σ_M) [s]: when the deposit's base carries σ_M [Pa] (item 4)."""
        k = 1.0 / (self.buoyant_unit_weight * (1.0 - self.porosity) * self.settling_velocity)
        return (self._G(sigma) - self._G(self.liquefied_pressure)) * k

    @property
    def end_time(self) -> float:
        """t_end [s]: the front meets the descending top of the sand."""
        return float(self.time_of(self.base_stress_end))

    def base_stress(self, t: ArrayLike, limit: float | None = None) -> Array:
        """σ_M(t) [Pa], the inverse of :meth:`time_of` (bisection to round-off), held at ``limit``
        (default σ_end) once reached."""
        top = self.base_stress_end if limit is None else float(limit)
        t = np.asarray(t, dtype=float)
        lo, hi = np.full(t.shape, self.liquefied_pressure), np.full(t.shape, top)
        t_top = float(self.time_of(top))
        for _ in range(200):  # halvings: the bracket falls below round-off of σ long before
            mid = 0.5 * (lo + hi)
            late = self.time_of(mid) < t
            lo, hi = np.where(late, mid, lo), np.where(late, hi, mid)
        return np.where(t >= t_top, top, np.where(t <= 0.0, self.liquefied_pressure, 0.5 * (lo + hi)))

    # ---------------------------------------------------------- observables
    def level_stress(self, level: float) -> float:
        """Granular pressure [Pa] at which the drained deposit has porosity ``level`` (n̄ ≤ level ≤ n_l);
        0 for rigid grains."""
        A = self.compressibility
        if A == 0.0:
            return 0.0
        return self.p_ref * float(np.exp((1.0 - (1.0 - self.reference_porosity) / (1.0 - level)) / A))

    def front(self, t: ArrayLike, level: float | None = None, limit: float | None = None) -> Array:
        """Height [m] of the porosity ``level`` (default (n_l + n̄)/2) in the deposit at time t [s]:
        Z(σ_M) − Z(σ_level); NaN while σ_M < σ_level. At level n_l it is the deposit's top Z(σ_M).

        >>> c = ScottColumn(1.0, 0.46, 0.42, 3e-4, 7.78e-4, 16186.5)
        >>> round(float(c.front(0.5 * c.end_time)), 4), round(float(c.settlement(0.5 * c.end_time)), 5)
        (0.4657, 0.03561)
        """
        level = 0.5 * (self.porosity + self.reference_porosity) if level is None else level
        sig = self.base_stress(t, limit)
        s_l = self.level_stress(level)
        out = self.thickness(sig) - self.thickness(s_l)
        return np.where(sig >= s_l, out, np.nan)

    def surface(self, t: ArrayLike) -> Array:
        """Height of the top of the sand [m]: H − v_s min(t, t_end)."""
        t = np.asarray(t, dtype=float)
        return self.height - self.settlement(t)

    def settlement(self, t: ArrayLike) -> Array:
        """Surface settlement S(t) [m] (down positive): v_s t until t_end, then S_end."""
        t = np.clip(np.asarray(t, dtype=float), 0.0, self.end_time)
        return self.settling_velocity * t

    @property
    def final_settlement(self) -> float:
        """S_end = H − Z(σ_end) [m] (rigid grains: H (n_l − n̄)/(1 − n̄))."""
        return float(self.height - self.thickness(self.base_stress_end))

    def base_excess_pressure(self, t: ArrayLike) -> Array:
        """u_b(t) = Δγ (1 − n_l) H + P_l − σ_M(t) [Pa]: the drained excess pore pressure at the base."""
        return self.base_stress_end - self.base_stress(t)

    # ---------------------------------------------- fixed surface (small strain)
    @property
    def fixed_surface_stress_end(self) -> float:
        """σ_M [Pa] at which the deposit fills the column (Z = H): the fixed-surface column's end."""
        lo, hi = self.liquefied_pressure, 2.0 * self.base_stress_end
        while self.thickness(hi) < self.height:
            hi *= 2.0
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if self.thickness(mid) < self.height else (lo, mid)
        return 0.5 * (lo + hi)

    @property
    def fixed_surface_end_time(self) -> float:
        """Time [s] at which the fixed-surface column has solidified (rigid: t_end/c)."""
        return float(self.time_of(self.fixed_surface_stress_end))

    def fixed_surface_front(self, t: ArrayLike, level: float | None = None) -> Array:
        """:meth:`front` of the fixed-surface column (it rises until Z = H)."""
        return self.front(t, level, limit=self.fixed_surface_stress_end)

    def fixed_surface_settlement(self, t: ArrayLike) -> Array:
        """S_ss(t) [m]: the compression Σ h (n_l − n)/(1 − n) of the fixed-surface column (module
        docstring; rigid grains: c v_s t).

        >>> c = ScottColumn(1.0, 0.46, 0.42, 0.0, 1e-3, 16186.5)
        >>> round(float(c.fixed_surface_settlement(30.0)), 6), round(c.fixed_surface_end_time, 3)
        (0.027931, 74.074)
        """
        sig = self.base_stress(t, limit=self.fixed_surface_stress_end)
        k = self.c / ((1.0 - self.reference_porosity) * self.buoyant_unit_weight)
        return self.thickness(sig) - k * (self._K(sig) - self._K(self.liquefied_pressure))
