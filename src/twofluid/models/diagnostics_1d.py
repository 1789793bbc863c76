"""What a user reads off a 1D state: solids volume and outflow, the settled granular pressure, the
element fields (mixin of the 1D models).

Apart from :mod:`~twofluid.models.two_fluid_1d` so that the model's module holds the equations;
these use its mesh, materials, closures and vertex weights (``volumes``, ``vert_node``,
``w_below``, ``w_above``, ``vert_area``, ``solids_flux``, ``element_mean``, ``solids_pressure``).
"""
from __future__ import annotations

import numpy as np

from .bed_forces_1d import _CLEAR
from .data_1d import State

__all__ = ["LineDiagnostics"]


class LineDiagnostics:
    """Diagnostics of a 1D state (mixin of :class:`~twofluid.models.two_fluid_1d.TwoFluid1D`)."""

    def solids_volume(self, s: State) -> float:
        """∫ (1 − n) dΩ [m³]."""
        return float(((1.0 - s.n) * self.volumes).sum())

    def solids_outflow(self, s: State) -> float:
        """Rate [m³/s] at which solids leave through the ends (upwinded as in the porosity equation)."""
        node = self.vert_node
        ends = (0, -1)
        F = [0.5 * (float(s.V[node[v]]) - float(s.W[node[v]])) for v in ends]
        if self.solids_flux == "upwind":  # :meth:`_upwind_ratio` at the two ends only (same arithmetic)
            n = s.n
            wb, wa = self.w_below, self.w_above
            for i, (v, nb, na) in enumerate(((0, 1.0, float(n[0])), (-1, float(n[-1]), 1.0))):
                nf = (wb[v] * nb + wa[v] * na) / (wb[v] + wa[v])
                one_f = 1.0 - nf
                r = (1.0 - (nb if F[i] >= 0.0 else na)) * (1.0 / one_f if one_f > _CLEAR else 0.0)
                F[i] = F[i] * r
        return float(F[1] * self.vert_area[-1] - F[0] * self.vert_area[0])

    def settled_solids_pressure(self, n: np.ndarray) -> np.ndarray:
        """P_s per element [Pa] that makes porosity ``n`` a discrete equilibrium at rest.

        Marches the mixture-minus-liquid balance at each vertex from the top
        (P_s = 0 above the column): A_i [[P_s]] = g_y (ρ_s − ρ_f) Σ_e (1 − n_e) ∫_e N_i dΩ.
        """
        ne = self.mesh.n_elements
        d_rho = self.mat.rho_s - self.mat.rho_f
        i = np.arange(1, ne + 1)  # vertices above each element
        n_above = np.append(n, 1.0)[i]
        load = (1.0 - n[i - 1]) * self.w_below[i] + (1.0 - n_above) * self.w_above[i]
        jump = -self.g_y * d_rho * load / self.vert_area[i]  # P_s below − P_s above
        return np.cumsum(jump[::-1])[::-1]

    def element_fields(self, s: State, at: np.ndarray | None = None) -> dict[str, np.ndarray]:
        """Per-element values at the centres: the fields a user looks at (SI units); with ``at`` (an integer array of element
        indices) the same values at those elements only (the probes': the same operations on fewer entries).

        U_s is undefined in clear liquid (n = 1) and given as NaN there.
        """
        n, nb, P = s.n, s.n_bar, s.P if self.p_order == 0 else 0.5 * (s.P[0::2] + s.P[1::2])
        if at is None:
            y = self.mesh.centres
        else:
            ym = self.mesh.y
            n, P, y = n[at], P[at], 0.5 * (ym[at + 1] + ym[at])  # the mesh's centres there
            nb = nb[at] if np.ndim(nb) else nb
        v, w = self.element_mean(s.V, at), self.element_mean(s.W, at)
        one_m = 1.0 - n
        with np.errstate(divide="ignore", invalid="ignore"):
            us = np.where(one_m > _CLEAR, (v - w) / (2.0 * one_m), np.nan)
        return {"y_m": y, "porosity": n, "reference_porosity": nb,
                "P_Pa": P, "Ps_Pa": self.solids_pressure(n, nb), "V_m_s": v, "W_m_s": w,
                "Uf_m_s": (v + w) / (2.0 * n), "Us_m_s": us}
