"""The upwind tests of the bed forces of the 1D two-component model (element ``1VW/0P/0n``).

:class:`UpwindBedForces` is the part of :class:`~twofluid.models.two_fluid_1d.TwoFluid1D` (and so
of the reduced model) that shifts each element's buoyant weight and drag towards one of its
vertices (upwind Petrov–Galerkin tests ψ = N ∓ αB): with the hat functions an odd–even porosity
mode stands in fluidized beds (docs/model.md). It lives apart from the model's equations
because it is one decision with its own analysis; it uses the model's mesh, materials,
closures and element matrices (``BN``, ``M``, ``src``, ``vdofs``, ``volumes``).
"""
from __future__ import annotations

import numpy as np

from . import full_kernel
from .data_1d import State

__all__ = ["UpwindBedForces"]

_CLEAR = 1e-6  # floor of 1 − n in the slip and the upwind flux ratio (clear liquid), for all 1D models


class UpwindBedForces:
    """The shift α of each element's bed forces and the upwind test integrals (mixin of the 1D models)."""

    def force_shift(self, n: np.ndarray, phi_n: np.ndarray, dps: np.ndarray) -> np.ndarray:
        """Shift α_e ∈ (−½, ½) of element e's bed forces towards its top vertex (``1VW/0P/0n``).

        The buoyant weight and the drag of the solids, φ = (1 − n)(ρ_s − ρ_f) g_y + βs/n
        per unit volume, balance the granular pressure gradient in a bed at rest,
        ∂P_s/∂y = φ. Tested with the hat functions, a vertex sees the mean of its two
        elements' φ: linearised about a uniform bed, the steady vertex balance
        P_s'(δ_i − δ_{i−1}) = h φ'(δ_{i−1} + δ_i)/2 propagates a porosity disturbance by
        λ = (2 + Pe)/(2 − Pe) per element, Pe = h φ'/P_s' (φ' = ∂φ/∂n at fixed V, W), which
        is negative for |Pe| > 2 and −1 as P_s' → 0: an odd–even porosity mode that the
        bed surface feeds and nothing damps (docs/model.md). The test functions
        ψ_bottom = N_bottom − α B, ψ_top = N_top + α B (B = 6ξ(1 − ξ); upwind
        Petrov–Galerkin, Christie et al. 1976) give the element's forces the shares
        (½ − α, ½ + α) instead, and λ = (1 + Pe w_t)/(1 − Pe w_b). With the share of the
        vertex against the wave w = min(½, 1/(2|Pe|)), λ = 2|Pe| + 1 > 0 when |Pe| > 1
        and the scheme is the Galerkin one where it is already monotone (|Pe| ≤ 1, e.g.
        every settled deposit, whose P_s' is large: there α = 0 exactly). Upwind is
        towards the top vertex when Pe > 0 (a fluidized bed: porosity waves rise), the
        bottom one when Pe < 0 (a deposit at rest, dilute settling). P_s' gets a floor of
        10⁻³ h |ρ_s − ρ_f| g so that α is continuous where φ' changes sign with P_s' = 0.
        Clear liquid (1 − n ≤ 10⁻⁶) keeps the Galerkin tests: it has no solids whose forces
        could be upwinded, and its drag only ties W to V, at every vertex alike.

        >>> from twofluid.casefile.builder import build
        >>> from twofluid.casefile.loader import load_case
        >>> m = build(load_case("fluidized-bed-step")).model
        >>> one = np.ones(m.mesh.n_elements)
        >>> float(m.force_shift(0.4 * one, 1.6e4 * one, -1e5 * one)[0])  # a deposit: Galerkin
        0.0
        >>> round(float(m.force_shift(0.716 * one, -2.9e4 * one, -4.3 * one)[0]), 4)  # fluidized: to the top
        0.4923
        """
        if self.BN is None or self.bed_forces == "galerkin":
            return np.zeros_like(n)
        h = self.mesh.lengths
        stiff = np.abs(dps) + 1e-3 * h * abs(self.mat.rho_s - self.mat.rho_f) * self.mat.g
        against = np.minimum(0.5, stiff / np.maximum(2.0 * h * np.abs(phi_n), 1e-300))
        alpha = np.where(phi_n < 0.0, 0.5 - against, against - 0.5)  # P_s' ≤ 0: Pe > 0 where φ' < 0
        return np.where(1.0 - n > _CLEAR, alpha, 0.0)  # clear liquid: no solids, the drag only ties V to W

    def psi_source(self, alpha: np.ndarray) -> np.ndarray:
        """∫ ψ_i dΩ (n_el, nl) of the upwind test functions with shift ``alpha``."""
        if self.BN is None:
            return self.src
        b = self.BN.sum(axis=1) * alpha
        return self.src + np.stack([-b, b], axis=1)

    def psi_mass(self, alpha: np.ndarray) -> np.ndarray:
        """∫ ψ_i N_j dΩ (n_el, nl, nl) of the upwind test functions with shift ``alpha``."""
        if self.BN is None:
            return self.M
        sig = np.array([-1.0, 1.0])
        return self.M + alpha[:, None, None] * sig[None, :, None] * self.BN[:, None, :]

    def bed_force_shift(self, s: State) -> np.ndarray:
        """:meth:`force_shift` at state ``s`` (the start of a step; cached for the step).

        Taken at the old state of each step, the shift is the same for every Picard
        iterate and for the full and the reduced model, and the Newton linearisation
        of the step is unchanged.
        """
        fields = (s.n, s.n_bar, s.V, s.W)
        c = getattr(self, "_shift_cache", None)
        if c is not None and c[0] is s and c[1] == s.t and all(np.array_equal(a, b) for a, b in zip(c[2], fields)):
            return c[3]
        alpha = self._force_shift_at(s)
        self._shift_cache = (s, s.t, tuple(np.array(x, copy=True) for x in fields), alpha)
        return alpha

    def _force_shift_at(self, s: State) -> np.ndarray:
        """:meth:`force_shift` at state ``s`` (uncached: :meth:`bed_force_shift`)."""
        n = s.n
        if self.BN is None or self.bed_forces == "galerkin":  # force_shift's Galerkin tests: α = 0
            return np.zeros_like(n)
        if self._full_kernels() is not None:
            alpha = full_kernel.force_shift(self, s)
            if alpha is not None:
                return alpha
        ne = n.size
        _, dps = self.solids_pressure(n, s.n_bar, derivative=True)
        dn = 1e-8 * np.where(n < 0.5, 1.0, -1.0)
        # the elements' drag totals Σ_i ∫ N_i β s dΩ (β from the element-mean slip) at n and n + δn,
        # both in one closure call
        x = np.concatenate((n, n + dn))
        vd = self.vdofs
        v, w = self.element_mean(s.V), self.element_mean(s.W)
        c = 1.0 - 2.0 * x
        q = c[:, None] * np.concatenate((s.V[vd], s.V[vd])) + np.concatenate((s.W[vd], s.W[vd]))
        s_abs = np.abs((c * np.concatenate((v, v)) + np.concatenate((w, w))) / (2.0 * x * np.maximum(1.0 - x, _CLEAR)))
        K = self.clo.beta_per_solids(x, s_abs, self._materials_times(2))
        M2 = self._M_twice
        if M2 is None:
            M2 = self._M_twice = np.concatenate((self.M, self.M))
        total = ((K / (2.0 * x * x))[:, None] * np.einsum("eij,ej->ei", M2, q)).sum(axis=1)
        phi_n = (total[ne:] - total[:ne]) / dn / self.volumes - (self.mat.rho_s - self.mat.rho_f) * self.g_y
        return self.force_shift(n, phi_n, dps)
