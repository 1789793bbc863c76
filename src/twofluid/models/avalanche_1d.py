"""A saturated granular layer on a submerged incline: shear with dilatancy coupled to drainage.

The layer (thickness h normal to the plane, inclined at θ, under still liquid) is resolved in z,
normal to the plane, from an impermeable no-slip base (z = 0) to a drained free surface, with
N elements that move with the solids (Lagrangian: element e holds the solid volume m_e per unit
area for ever, so the solids are conserved exactly and its thickness is Δz_e = m_e/φ_e).

**Vertical two-fluid balance** (normal to the plane; the solids and the liquid each in
equilibrium, velocities ~µm/s so inertia is negligible). Summed, the excess pore pressure
p (over hydrostatic along the true vertical, which on an infinite slope under still liquid is
hydrostatic along z with ρ_f g cos θ) and the skeleton pressure P_s carry the **buoyant** weight:
P_s + p = W(z) = (ρ_s − ρ_f) g cos θ ∫_z^h φ dz. The liquid's own balance with the Darcy drag
gives its flux relative to the solids, q = −(k/η_f) ∂p/∂z, with k from
:func:`~twofluid.closures.granular_rheology.carman_kozeny`; the liquid volume of each element
changes by what flows through its faces, dΔz_e/dt = q_(e−½) − q_(e+½), with q = 0 at the base
and p = 0 at the surface (or q = 0 there: an undrained layer).

**Skeleton** (the reference solid fraction φ̄, the solids' counterpart of the two-fluid model's
n̄ = 1 − φ̄): P_s = M (φ − φ̄). M [Pa] is the tangent modulus of a Hertzian packing of glass
beads at the layer's 10–40 Pa (3–5e7 Pa); the consolidation time η_f h²/(k M) ~ 2 ms is far
below every time of the flow, so M sets none of its own (tests vary it tenfold).

**Shear** (downslope, quasi-static: ρ ∂u/∂t is ~1e-3 of the buoyant weight's gradient): the
shear stress is the buoyant weight's downslope part, τ(z) = (ρ_s − ρ_f) g sin θ ∫_z^h φ dz, and
the rheology (:func:`~twofluid.closures.granular_rheology.boyer_pailha`) gives the shear rate,
τ/P_s = μ(I_v) + tan ψ with I_v = η_f γ̇/P_s; u(0) = 0 and u = ∫ γ̇ dz. The liquid viscosity
enters only through μ(I_v) (its I_v term). **Dilatancy** moves the reference:
Dφ̄/Dt = −φ γ̇ tan ψ, so a dilating layer lowers P_s (the liquid pressure drops and draws liquid
in), a contracting one loads the liquid.

Unknowns per element: Δz_e and φ̄_e; φ, P_s, p, γ̇ and u follow. Both are integrated by
scipy's BDF with a banded Jacobian; its steps are a generator (:meth:`AvalancheLayer.steps`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import BDF
from scipy.sparse import diags

from ..closures.granular_rheology import RHEOLOGY_DEFAULTS, carman_kozeny, nonlocal_shear_rate, phi_eq, viscous_number

__all__ = ["AvalancheLayer", "LayerState", "SKELETON_MODULUS_PA"]

#: tangent modulus [Pa] of a Hertzian glass-bead packing at 10–40 Pa (module docstring)
SKELETON_MODULUS_PA = 4e7


@dataclass
class LayerState:
    """Fields at time t [s]: element centres (bottom first) unless said; SI units."""

    t: float
    z: np.ndarray  # node heights above the base [m] (N + 1)
    u: np.ndarray  # downslope velocity at the nodes [m/s] (N + 1)
    phi: np.ndarray  # solid fraction [-]
    phi_bar: np.ndarray  # reference solid fraction [-]
    p: np.ndarray  # excess pore pressure [Pa]
    p_s: np.ndarray  # skeleton pressure [Pa]
    shear_rate: np.ndarray  # [1/s]
    tan_psi: np.ndarray  # [-]

    @property
    def surface_velocity(self) -> float:
        return float(self.u[-1])

    @property
    def base_pressure(self) -> float:
        """Excess pore pressure at the base [Pa] (the bottom centre value, ∂p/∂z = 0 there)."""
        return float(self.p[0])


class AvalancheLayer:
    """The layer of the module docstring.

    ``thickness`` h [m] at solid fraction ``phi0`` (uniform), ``elements`` N, ``slope_deg`` θ,
    densities ρ_s, ρ_f [kg/m³], dynamic viscosity ``eta_f`` [Pa·s], bead diameter ``d`` [m],
    ``gravity`` [m/s²]; ``rheology`` the parameters of ``boyer_pailha``; ``permeability_constant``
    C of Carman–Kozeny; ``modulus`` M [Pa]; ``top`` "drained" (p = 0) or "closed" (q = 0);
    ``grading`` the ratio of the top element's thickness at the start to the base element's, the
    thicknesses in geometric progression between (1: uniform; above 1 the elements are thinnest at
    the base, where a dense layer's shear band forms). The ratio is fixed as N changes, so doubling
    N about halves every element. ``nonlocal_amplitude`` A > 0 makes the rheology nonlocal
    (:func:`~twofluid.closures.granular_rheology.nonlocal_shear_rate`: a flowing zone fluidises its
    neighbours over ξ = A d/√|μ − μ_y|); 0 keeps it local.
    """

    def __init__(self, thickness: float, elements: int, phi0, slope_deg: float, rho_s: float, rho_f: float,
                 eta_f: float, d: float, gravity: float = 9.81, rheology: dict | None = None,
                 permeability_constant: float = 180.0, modulus: float = SKELETON_MODULUS_PA,
                 top: str = "drained", grading: float = 1.0, nonlocal_amplitude: float = 0.0):
        n = int(elements)
        phi0 = np.broadcast_to(np.asarray(phi0, dtype=float), (n,)).copy()
        self.n, self.eta, self.d = n, float(eta_f), float(d)
        self.rh = {**RHEOLOGY_DEFAULTS, **(rheology or {})}
        self.amplitude = float(nonlocal_amplitude)
        self.c_k, self.modulus, self.closed = float(permeability_constant), float(modulus), top == "closed"
        th = math.radians(slope_deg)
        widths = float(grading) ** (np.arange(n) / (n - 1))
        self.m = phi0 * float(thickness) * widths / widths.sum()  # solid volume per unit area of each element [m]
        above = np.concatenate([np.cumsum(self.m[::-1])[::-1][1:], [0.0]]) + 0.5 * self.m
        buoyant = (rho_s - rho_f) * gravity
        self.load = buoyant * math.cos(th) * above  # P_s + p at the centres [Pa]
        self.tau = buoyant * math.sin(th) * above  # shear stress at the centres [Pa]
        self.phi0 = phi0
        # P_s carries the whole load at the start: p = 0 (hydrostatic)
        self.y0 = np.concatenate([self.m / phi0, phi0 - self.load / self.modulus])

    # -- fields -----------------------------------------------------------------------------------
    def _split(self, y):
        dz, phib = y[: self.n], y[self.n:]
        phi = self.m / dz
        p_s = self.modulus * (phi - phib)
        return dz, phib, phi, p_s, self.load - p_s

    def _shear(self, phi, p_s, dz):
        ps = np.maximum(p_s, 1e-9 * self.load[0])  # a liquefied element keeps the viscous limit τ = η_f γ̇
        if self.amplitude > 0.0:
            gd = nonlocal_shear_rate(self.tau / ps, phi, ps, dz, self.eta, self.d, self.amplitude, **self.rh)
            iv = self.eta * gd / ps
        else:
            iv = viscous_number(self.tau / ps, phi, **self.rh)
            gd = iv * ps / self.eta
        tan_psi = self.rh["k_dil"] * (phi - phi_eq(iv, self.rh["phi_c"]))
        return gd, tan_psi

    def rhs(self, t, y):
        """d(Δz, φ̄)/dt of the module docstring."""
        dz, phib, phi, p_s, p = self._split(y)
        k = carman_kozeny(phi, self.d, self.c_k) / self.eta  # k/η_f per element
        q = np.zeros(self.n + 1)
        # interior faces: resistances of the two half elements in series
        r = 0.5 * dz[:-1] / k[:-1] + 0.5 * dz[1:] / k[1:]
        q[1:-1] = -(p[1:] - p[:-1]) / r
        if not self.closed:
            q[-1] = p[-1] / (0.5 * dz[-1] / k[-1])  # to p = 0 at the surface
        gd, tan_psi = self._shear(phi, p_s, dz)
        return np.concatenate([q[:-1] - q[1:], -phi * gd * tan_psi])

    def state(self, t: float, y) -> LayerState:
        dz, phib, phi, p_s, p = self._split(np.asarray(y, dtype=float))
        gd, tan_psi = self._shear(phi, p_s, dz)
        z = np.concatenate([[0.0], np.cumsum(dz)])
        u = np.concatenate([[0.0], np.cumsum(gd * dz)])
        return LayerState(float(t), z, u, phi, phib, p, p_s, gd, tan_psi)

    def jac_sparsity(self):
        n = self.n
        band = diags([1, 1, 1], [-1, 0, 1], shape=(n, n), dtype=float).toarray()
        eye = np.eye(n) if self.amplitude <= 0.0 else np.ones((n, n))  # nonlocal: every element's rate
        return np.block([[band, band], [eye, eye]])

    # -- time loop --------------------------------------------------------------------------------
    def steps(self, t_end: float, rtol: float = 1e-7, max_step: float = math.inf, first_step: float = 1e-4):
        """Generator of (t, y) after every accepted BDF step, from (0, y0) to ``t_end`` [s].

        Tolerances are absolute on what the output needs: 1e-12 of φ (4e-5 Pa of pressure at the
        default M) on Δz through its solid volume, 1e-12 on φ̄.
        """
        atol = np.concatenate([1e-12 * self.m / self.phi0**2, np.full(self.n, 1e-12)])
        solver = BDF(self.rhs, 0.0, self.y0.copy(), float(t_end), rtol=rtol, atol=atol,
                     max_step=max_step, first_step=min(first_step, float(t_end)), jac_sparsity=self.jac_sparsity())
        yield 0.0, self.y0.copy(), None
        while solver.status == "running":
            msg = solver.step()
            if solver.status == "failed":
                raise RuntimeError(f"avalanche layer: the BDF step failed at t = {solver.t:.6g} s ({msg})")
            yield solver.t, solver.y.copy(), solver.dense_output()

    def run(self, times, rtol: float = 1e-7, max_step: float = math.inf) -> list[LayerState]:
        """States at ``times`` [s] (increasing, ≥ 0), interpolated in the BDF steps; the number of
        accepted steps is left in ``steps_taken``."""
        times = np.asarray(times, dtype=float)
        out, i = [], 0
        self.steps_taken = 0  # accepted BDF steps of the last run
        for t, y, dense in self.steps(float(times[-1]), rtol=rtol, max_step=max_step):
            self.steps_taken += dense is not None
            while i < times.size and times[i] <= t + 1e-12 * max(1.0, t):
                yi = y if dense is None or times[i] >= t else dense(times[i])
                out.append(self.state(times[i], yi))
                i += 1
        return out
