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
        c = self._outflow_ends()
        V, W = s.V, s.W
        F0 = 0.5 * (float(V[c[0]]) - float(W[c[0]]))
        F1 = 0.5 * (float(V[c[1]]) - float(W[c[1]]))
        if c[2]:  # :meth:`_upwind_ratio` at the two ends only (same arithmetic)
            wb0, wa0, wb1, wa1 = c[5:9]
            n0, n1 = float(s.n[0]), float(s.n[-1])
            one_f = 1.0 - (wb0 * 1.0 + wa0 * n0) / (wb0 + wa0)  # bottom: clear liquid below
            F0 = F0 * ((1.0 - (1.0 if F0 >= 0.0 else n0)) * (1.0 / one_f if one_f > _CLEAR else 0.0))
            one_f = 1.0 - (wb1 * n1 + wa1 * 1.0) / (wb1 + wa1)  # top: clear liquid above
            F1 = F1 * ((1.0 - (n1 if F1 >= 0.0 else 1.0)) * (1.0 / one_f if one_f > _CLEAR else 0.0))
        return float(F1 * c[4] - F0 * c[3])

    def _outflow_ends(self) -> tuple:
        """(bottom node, top node, upwind, bottom area, top area, the vertex weights w_below, w_above at
        the bottom and at the top) of :meth:`solids_outflow`, as Python numbers, kept while the model's
        arrays are the same objects."""
        wb, wa, area, node = self.w_below, self.w_above, self.vert_area, self.vert_node
        c = self.__dict__.get("_outflow_c")
        if c is None or c[0] is not wb or c[1] is not wa or c[2] is not area or c[3] is not node \
                or c[4] != self.solids_flux:
            ends = (int(node[0]), int(node[-1]), self.solids_flux == "upwind", float(area[0]), float(area[-1]),
                    float(wb[0]), float(wa[0]), float(wb[-1]), float(wa[-1]))
            c = self._outflow_c = (wb, wa, area, node, self.solids_flux, ends)
        return c[5]

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
