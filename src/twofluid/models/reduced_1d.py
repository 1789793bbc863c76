"""The reduced-variable 1D model (SPEC 5.3): one nodal unknown W per Picard iteration.

It solves the same discrete equations as :class:`~twofluid.models.two_fluid_1d.TwoFluid1D`
with the ``1VW/0P/0n`` element, reorganised so that each Picard iterate is a
tridiagonal system in W alone:

- continuity: A V = c(t) at every vertex, c fixed by the inlet or wall end, so V
  is known;
- porosity (the same upwinded vertex solids flux, upwind ratio r frozen at the
  iterate): n_e = n_eᵗ + Δt [a (V − W)]_{e}^{e+1} / (2 Vol_e), a = A r, affine in W;
- momentum: at every vertex i with a free W the mixture row carries A_i [[P]]_i, and
  so does the liquid row, which the full model writes per unit liquid volume
  (tested with δW/n), so mixture − liquid is free of P (SPEC 5.3: solid − (1 − n)/n
  liquid). Substituting n(W) leaves a tridiagonal Jacobian.

The linearisation about iterate k is the full model's: drag Newton-linearised in
V, W (exact) and n (finite difference), P_s Taylor-expanded in n, μ_s and the 1/n
of the liquid inertia frozen. At convergence both models satisfy the same
residuals, so they agree to the Picard tolerance. P is recovered after each step
from the liquid rows, marching from the outlet: [[P]]_i = −L_i/A_i.

``surcharge`` [Pa] is a solids pressure applied on the top face (a load carried by
the skeleton only, drained liquid), used by the Terzaghi check.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.linalg import solve_banded

from ..closures.viscosity import solid_viscosity
from .two_fluid_1d import _CLEAR, State, TwoFluid1D

__all__ = ["Reduced1D", "ReducedSystem"]


@dataclass
class ReducedSystem:
    """One Picard iterate: banded Jacobian ``ab`` (3, nv), rhs, and the affine map n = b + G W."""

    ab: np.ndarray
    rhs: np.ndarray
    n_b: np.ndarray  # (ne,) porosity at W = 0
    g_bot: np.ndarray  # (ne,) ∂n_e/∂W_e
    g_top: np.ndarray  # (ne,) ∂n_e/∂W_{e+1}
    V: np.ndarray


class Reduced1D(TwoFluid1D):
    """Reduced-variable 1D model: W is the only unknown of the linear solves.

    Parameters are those of :class:`TwoFluid1D`; ``element`` must be ``"1VW/0P/0n"``,
    one end must be an inlet or a wall (it fixes c = A V), and ``surcharge`` [Pa]
    is an optional solids load on the top face.
    """

    def __init__(self, mesh, materials, closures, bottom, top, element="1VW/0P/0n",
                 solids_flux="upwind", surcharge: float = 0.0):
        if element != "1VW/0P/0n":
            raise ValueError(f"the reduced_1d model supports only the '1VW/0P/0n' element, got {element!r}; "
                             "use model = 'two_fluid_1d' for the quadratic element")
        if "outlet" == bottom.kind == top.kind:
            raise ValueError("the reduced_1d model needs an inlet or a wall at one end (it fixes A V)")
        super().__init__(mesh, materials, closures, bottom, top, element, solids_flux)
        self.surcharge = float(surcharge)
        ne = mesh.n_elements
        self._free = np.ones(ne + 1, bool)
        for b, v in ((bottom, 0), (top, ne)):
            self._free[v] = b.kind == "outlet"
        self._loc = np.arange(ne)[:, None] + np.arange(2)[None, :]  # vertex of (e, local)

    # ----------------------------------------------------------- pieces
    def mixture_flux(self, t: float) -> float:
        """c = A V [m³/s] fixed by the inlet (or wall) end at time t."""
        if self.bottom.kind != "outlet":
            return self.vert_area[0] * self.inlet_value(self.bottom, t, 1.0)
        return self.vert_area[-1] * self.inlet_value(self.top, t, -1.0)

    def _rows(self, V, W, n, old: State, dt: float, n_bar):
        """Element contributions (ne, 2) of the mixture and liquid rows without P, and their derivatives."""
        mat, clo, M, Kv, src = self.mat, self.clo, self.M, self.Kvis, self.src
        vd = self.vdofs
        rho_hat, d_rho = 0.5 * (mat.rho_s + mat.rho_f), 0.5 * (mat.rho_s - mat.rho_f)
        Ve, We = V[vd], W[vd]
        dV, dW = Ve - old.V[vd], We - old.W[vd]
        mv = lambda A, x: np.einsum("eij,ej->ei", A, x)  # noqa: E731
        # mixture, with −B0ᵀ P_s: A_bottom P_s at local 0, −A_top P_s at local 1
        ps, dps = self.solids_pressure(n, n_bar, derivative=True)
        sgn = np.array([1.0, -1.0])
        area = self.vert_area[self._loc]
        X = mv(M, rho_hat * dV - d_rho * dW) / dt + (sgn * area) * ps[:, None] \
            + ((mat.rho_s - mat.rho_f) * n[:, None] - mat.rho_s) * self.g_y * src
        XW = -d_rho / dt * M
        Xn = (mat.rho_s - mat.rho_f) * self.g_y * src + (sgn * area) * dps[:, None]
        # liquid, per unit liquid volume (1/n frozen at the iterate, as in the full model)
        inv_n = (1.0 / n)[:, None, None]
        L = 0.5 * mat.rho_f / dt * mv(inv_n * M, dV + dW) - mat.rho_f * self.g_y * src
        LW = 0.5 * mat.rho_f / dt * inv_n * M
        if clo.viscous:
            mu_s = solid_viscosity(n, mat.mu_f, **clo.viscosity_params)[:, None, None]
            X = X + mv(0.5 * (mat.mu_f + mu_s) * Kv, Ve) + mv(0.5 * (mat.mu_f - mu_s) * Kv, We)
            XW = XW + 0.5 * (mat.mu_f - mu_s) * Kv
            L = L + 0.5 * mat.mu_f * mv(inv_n * Kv, Ve + We)
            LW = LW + 0.5 * mat.mu_f * inv_n * Kv
        D0, Jq, Jn = self._drag_terms(n, Ve, We)
        return X, XW, Xn, L + D0, LW + Jq, Jn

    def _drag_terms(self, n, Ve, We):
        """Drag D = K M q/(2n²) (K = β/(1 − n), q = (1 − 2n)V + W) and its Jacobians.

        Same law and linearisation as the full model's ``_drag`` (exact in V, W
        through the element-mean slip; finite difference in n), with the three
        closure evaluations (at |s|, |s| + δs and n + δn) fused into one call.
        """
        w = self.avg_weights.T  # (ne, 2)
        dn = 1e-8 * np.where(n < 0.5, 1.0, -1.0)
        nn = np.concatenate([n, n + dn])
        q = (1.0 - 2.0 * nn)[:, None] * np.concatenate([Ve, Ve]) + np.concatenate([We, We])
        qbar = (q * np.concatenate([w, w])).sum(axis=1)
        s_abs = np.abs(qbar) / (2.0 * nn * np.maximum(1.0 - nn, _CLEAR))
        ne = n.size
        ds = 1e-6 * np.maximum(s_abs[:ne], 1e-6)
        K = self.clo.beta_per_solids(np.concatenate([nn, n]), np.concatenate([s_abs, s_abs[:ne] + ds]),
                                     self.mat)
        K0, Kn, Ks = K[:ne], K[ne:2 * ne], K[2 * ne:]
        Mq = np.einsum("eij,ej->ei", np.concatenate([self.M, self.M]), q)
        D0 = (K0 / (2.0 * n * n))[:, None] * Mq[:ne]
        Dn = (Kn / (2.0 * nn[ne:] ** 2))[:, None] * Mq[ne:]
        qb = qbar[:ne]
        gain = np.where(qb != 0.0, (Ks - K0) / ds * s_abs[:ne] / np.where(qb != 0.0, qb, 1.0), 0.0)
        Jq = (K0 / (2.0 * n * n))[:, None, None] * self.M \
            + (gain / (2.0 * n * n))[:, None, None] * Mq[:ne, :, None] * w[:, None, :]
        return D0, Jq, (Dn - D0) / dn[:, None]

    def _assemble_nodal(self, E: np.ndarray) -> np.ndarray:
        """Sum element contributions (ne, 2) at the vertices (linear element: node = vertex)."""
        out = np.zeros(self.nv)
        out[:-1] += E[:, 0]
        out[1:] += E[:, 1]
        return out

    # ---------------------------------------------------- stepper interface
    def assemble(self, k: State, old: State, dt: float, t_new: float) -> ReducedSystem:
        """Banded Newton system in W of one Picard iterate (module docstring)."""
        ne, node = self.mesh.n_elements, self.vert_node
        V = np.full(self.nv, self.mixture_flux(t_new)) / self.vert_area
        n = k.n
        X, XW, Xn, L, LW, Ln = self._rows(V, k.W, n, old, dt, k.n_bar)
        R = self._assemble_nodal(X - L)  # residual at iterate k
        self._liquid = (k.W[self.vdofs], n, L, LW, Ln)  # for the pressure of the step
        if self.top.kind == "outlet":
            R[-1] += self.surcharge * self.vert_area[-1]
        JW, Jn = XW - LW, Xn - Ln
        # porosity update with the upwind ratio frozen at the iterate
        F = 0.5 * (k.V[node] - k.W[node])
        r = self._upwind_ratio(n, F, getattr(self, "_below", None))[0] if self.solids_flux == "upwind" \
            else np.ones(ne + 1)
        a = self.vert_area * r
        c = dt / (2.0 * self.volumes)
        g_bot, g_top = c * a[:-1], -c * a[1:]
        n_b = old.n + c * (a[1:] * V[1:] - a[:-1] * V[:-1])
        G = np.stack([g_bot, g_top], axis=1)
        J = JW + Jn[:, :, None] * G[:, None, :]  # (ne, 2, 2): rows local vertex, cols local W
        rhs = -R + self._assemble_nodal(np.einsum("eij,ej->ei", JW, k.W[self.vdofs])) \
            - self._assemble_nodal(Jn * (n_b - n)[:, None])
        ab = np.zeros((3, self.nv))
        ab[1] = self._assemble_nodal(np.stack([J[:, 0, 0], J[:, 1, 1]], axis=1))
        ab[0, 1:] = J[:, 0, 1]  # row e, column e+1
        ab[2, :-1] = J[:, 1, 0]  # row e+1, column e
        return ReducedSystem(ab, rhs, n_b, g_bot, g_top, V)

    def solve(self, S: ReducedSystem, t: float) -> np.ndarray:
        """W from the banded solve (prescribed W at inlet/wall ends), then n; returns [V, W, n]."""
        ab, rhs = S.ab, S.rhs
        for v in np.nonzero(~self._free)[0]:
            w = S.V[v]  # inlet / wall: W = V
            if v > 0:  # column v in row v − 1; row v's lower entry
                rhs[v - 1] -= ab[0, v] * w
                ab[0, v] = ab[2, v - 1] = 0.0
            if v < self.nv - 1:  # column v in row v + 1; row v's upper entry
                rhs[v + 1] -= ab[2, v] * w
                ab[2, v] = ab[0, v + 1] = 0.0
            ab[1, v], rhs[v] = 1.0, w
        W = solve_banded((1, 1), ab, rhs, check_finite=False)
        n = S.n_b + S.g_bot * W[:-1] + S.g_top * W[1:]
        return np.concatenate([S.V, W, n])

    def pack(self, s: State) -> np.ndarray:
        return np.concatenate([s.V, s.W, s.n])

    def unpack(self, a: np.ndarray, like: State, t: float) -> State:
        nv = self.nv
        return like.copy(t=t, V=a[:nv], W=a[nv:2 * nv], n=a[2 * nv:])

    def end_step(self, old: State, new: State, dt: float) -> State:
        """Recover P [Pa] per element from the liquid rows linearised about the last iterate.

        That is the liquid equation the full model's P satisfies in its last solve.
        """
        Wk, nk, L, LW, Ln = self._liquid
        L = L + np.einsum("eij,ej->ei", LW, new.W[self.vdofs] - Wk) + Ln * (new.n - nk)[:, None]
        new.P = self._pressure_from(self._assemble_nodal(L))
        return new

    def recover_pressure(self, s: State, old: State, dt: float) -> np.ndarray:
        """Element pressures [Pa] of state ``s`` (after a step of ``dt`` from ``old``)."""
        return self._pressure_from(self._assemble_nodal(self._rows(s.V, s.W, s.n, old, dt, s.n_bar)[3]))

    def _pressure_from(self, L: np.ndarray) -> np.ndarray:
        """Element pressures [Pa] from [[P]]_i = −L_i/A_i and the outlet pressure."""
        jump = -L / self.vert_area  # P above − P below at vertex i
        if self.top.kind == "outlet":
            return self.top.pressure - np.cumsum(jump[1:][::-1])[::-1]
        return self.bottom.pressure + np.cumsum(jump[:-1])
