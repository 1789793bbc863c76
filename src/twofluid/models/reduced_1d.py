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

Speed (the reason for the model): each iterate costs one fused drag-law call,
the viscosity and P_s, a handful of vectorised 2×2 element operations and one
LAPACK tridiagonal solve (``dgtsv``); the mixture-minus-liquid rows are formed in
one pass, and the liquid rows (for P) only once per step. The first iterate of a
step starts from the linear extrapolation of the last two converged steps
(W and n; V is known exactly), which saves about one Picard iteration per step;
the converged state is the same to the Picard tolerance.

``surcharge`` [Pa] is a solids pressure applied on the top face (a load carried by
the skeleton only, drained liquid), used by the Terzaghi check.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.linalg.lapack import dgtsv

from ..closures.viscosity import solid_viscosity
from .two_fluid_1d import _CLEAR, State, TwoFluid1D

__all__ = ["Reduced1D", "ReducedSystem"]


@dataclass
class ReducedSystem:
    """One Picard iterate: tridiagonal Jacobian ``ab`` = (lower, diag, upper), rhs, and the affine map n = b + G W."""

    ab: tuple
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
        # constant pieces of the mixture-minus-liquid rows: −B0ᵀ P_s and the buoyant weight
        self._ps_area = np.array([1.0, -1.0]) * self.vert_area[self._loc]
        self._g_src = (materials.rho_s - materials.rho_f) * self.g_y * self.src
        self._w2 = np.concatenate([self.avg_weights.T, self.avg_weights.T])
        self._M2 = np.concatenate([self.M, self.M])
        self._V_of_t = (None, None)  # (t, nodal V) cache
        self._history = None  # the last two converged (t, W, n), for the extrapolated first iterate

    # ----------------------------------------------------------- pieces
    def mixture_flux(self, t: float) -> float:
        """c = A V [m³/s] fixed by the inlet (or wall) end at time t."""
        if self.bottom.kind != "outlet":
            return self.vert_area[0] * self.inlet_value(self.bottom, t, 1.0)
        return self.vert_area[-1] * self.inlet_value(self.top, t, -1.0)

    def _rows(self, V, W, n, old: State, dt: float, n_bar):
        """Mixture minus liquid rows (ne, 2) without P, ∂/∂W (ne, 2, 2), ∂/∂n (ne, 2), and the drag terms.

        Mixture (tested with δV): M(ρ̂ ΔV − Δρ ΔW)/Δt − B0ᵀ P_s − ρ̄ g_y ∫N + viscous;
        liquid (tested with δW/n): ρ_f M(ΔV + ΔW)/(2nΔt) − ρ_f g_y ∫N + μ_f Kv(V + W)/(2n) + D.
        """
        mat = self.mat
        vd = self.vdofs
        Ve, We = V[vd], W[vd]
        dV, dW = Ve - old.V[vd], We - old.W[vd]
        ps, dps = self.solids_pressure(n, n_bar, derivative=True)
        h = (0.5 * mat.rho_f / dt) / n  # liquid inertia per unit liquid volume
        a_v = (0.5 * (mat.rho_s + mat.rho_f) / dt - h)[:, None]
        a_w = (-0.5 * (mat.rho_s - mat.rho_f) / dt - h)[:, None]
        D0, Jq, Jdn = self._drag_terms(n, Ve, We)
        x = a_v * dV + a_w * dW  # M is applied once to inertia and drag together
        R = self._mv(self.M, x) - D0 + self._ps_area * ps[:, None] \
            + self._g_src * (n[:, None] - 1.0)
        JW = (a_w[:, :, None] * self.M) - Jq
        Jn = self._g_src + self._ps_area * dps[:, None] - Jdn
        if self.clo.viscous:
            mu_s = solid_viscosity(n, mat.mu_f, **self.clo.viscosity_params)
            m_l = 0.5 * mat.mu_f / n
            c_v = (0.5 * (mat.mu_f + mu_s) - m_l)[:, None]
            c_w = (0.5 * (mat.mu_f - mu_s) - m_l)[:, None]
            R = R + self._mv(self.Kvis, c_v * Ve + c_w * We)
            JW = JW + c_w[:, :, None] * self.Kvis
        return R, JW, Jn, (D0, Jq, Jdn)

    def _liquid_rows(self, V, W, n, old: State, dt: float, drag):
        """Liquid rows (ne, 2) without P, tested with δW/n, and ∂/∂W, ∂/∂n (``drag`` from :meth:`_drag_terms`)."""
        mat = self.mat
        vd = self.vdofs
        Ve, We = V[vd], W[vd]
        D0, Jq, Jdn = drag
        h = ((0.5 * mat.rho_f / dt) / n)[:, None]
        L = self._mv(self.M, h * (Ve - old.V[vd] + We - old.W[vd])) - mat.rho_f * self.g_y * self.src + D0
        LW = h[:, :, None] * self.M + Jq
        if self.clo.viscous:
            m_l = (0.5 * mat.mu_f / n)[:, None]
            L = L + self._mv(self.Kvis, m_l * (Ve + We))
            LW = LW + m_l[:, :, None] * self.Kvis
        return L, LW, Jdn

    @staticmethod
    def _mv(A, x):
        """Element matrices (ne, 2, 2) times element vectors (ne, 2)."""
        return A[:, :, 0] * x[:, :1] + A[:, :, 1] * x[:, 1:]

    def _drag_terms(self, n, Ve, We):
        """Drag D = K M q/(2n²) (K = β/(1 − n), q = (1 − 2n)V + W) and its Jacobians.

        Same law and linearisation as the full model's ``_drag`` (exact in V, W
        through the element-mean slip; finite difference in n), with the three
        closure evaluations (at |s|, |s| + δs and n + δn) fused into one call.
        """
        ne = n.size
        w = self._w2[:ne]  # (ne, 2) averaging weights
        dn = np.where(n < 0.5, 1e-8, -1e-8)
        nn = np.concatenate([n, n + dn])
        q = (1.0 - 2.0 * nn)[:, None] * np.concatenate([Ve, Ve]) + np.concatenate([We, We])
        qbar = (q * self._w2).sum(axis=1)
        s_abs = np.abs(qbar) / (2.0 * nn * np.maximum(1.0 - nn, _CLEAR))
        ds = 1e-6 * np.maximum(s_abs[:ne], 1e-6)
        K = self.clo.beta_per_solids(np.concatenate([nn, n]), np.concatenate([s_abs, s_abs[:ne] + ds]),
                                     self.mat)
        K0, Kn, Ks = K[:ne], K[ne:2 * ne], K[2 * ne:]
        Mq = self._mv(self._M2, q)
        k0 = K0 / (2.0 * n * n)
        D0 = k0[:, None] * Mq[:ne]
        Dn = (Kn / (2.0 * nn[ne:] ** 2))[:, None] * Mq[ne:]
        qb = qbar[:ne]
        nz = qb != 0.0
        gain = np.where(nz, (Ks - K0) / ds * s_abs[:ne] / np.where(nz, qb, 1.0), 0.0) / (2.0 * n * n)
        Jq = k0[:, None, None] * self.M + gain[:, None, None] * Mq[:ne, :, None] * w[:, None, :]
        return D0, Jq, (Dn - D0) / dn[:, None]

    def _assemble_nodal(self, E: np.ndarray) -> np.ndarray:
        """Sum element contributions (ne, 2) at the vertices (linear element: node = vertex)."""
        out = np.zeros(self.nv)
        out[:-1] += E[:, 0]
        out[1:] += E[:, 1]
        return out

    def _mixture_velocity(self, t: float) -> np.ndarray:
        """Nodal V [m/s] = c(t)/A (cached per time level)."""
        if self._V_of_t[0] != t:
            self._V_of_t = (t, np.full(self.nv, self.mixture_flux(t)) / self.vert_area)
        return self._V_of_t[1]

    # ---------------------------------------------------- stepper interface
    def begin_iteration(self, it: int, k: State) -> None:
        """Picard hook: extrapolated first iterate, then the full model's upwind-side choice.

        At the first iteration of a step from the last converged state, W and n
        start from the line through the last two converged steps (n kept inside
        the range the two steps span, widened by their change) and V from c(t)/A.
        """
        if it == 1 and self._history is not None:
            (t0, W0, n0), (t1, W1, n1) = self._history
            if t1 > t0 and k.t > t1 and np.array_equal(k.W, W1) and np.array_equal(k.n, n1):
                f = min((k.t - t1) / (t1 - t0), 2.0)
                k.V[:] = self._mixture_velocity(k.t)
                k.W[:] = W1 + f * (W1 - W0)
                n_new = n1 + f * (n1 - n0)
                lo, hi = np.minimum(n0, n1), np.maximum(n0, n1)
                k.n[:] = np.clip(n_new, lo - (hi - lo), np.minimum(hi + (hi - lo), 1.0))
        super().begin_iteration(it, k)

    def assemble(self, k: State, old: State, dt: float, t_new: float) -> ReducedSystem:
        """Tridiagonal Newton system in W of one Picard iterate (module docstring)."""
        ne, node = self.mesh.n_elements, self.vert_node
        V = self._mixture_velocity(t_new)
        n = k.n
        X, JW, Jn, drag = self._rows(V, k.W, n, old, dt, k.n_bar)
        R = self._assemble_nodal(X)  # residual at iterate k
        self._last_iterate = (k.W, n, drag, old, dt)  # for the pressure of the step
        if self.top.kind == "outlet":
            R[-1] += self.surcharge * self.vert_area[-1]
        # porosity update with the upwind ratio frozen at the iterate
        F = 0.5 * (k.V[node] - k.W[node])
        r = self._upwind_ratio(n, F, getattr(self, "_below", None))[0] if self.solids_flux == "upwind" \
            else np.ones(ne + 1)
        a = self.vert_area * r
        c = dt / (2.0 * self.volumes)
        g_bot, g_top = c * a[:-1], -c * a[1:]
        n_b = old.n + c * (a[1:] * V[1:] - a[:-1] * V[:-1])
        # J = JW + Jn ⊗ (g_bot, g_top): rows local vertex, cols local W
        J00 = JW[:, 0, 0] + Jn[:, 0] * g_bot
        J01 = JW[:, 0, 1] + Jn[:, 0] * g_top
        J10 = JW[:, 1, 0] + Jn[:, 1] * g_bot
        J11 = JW[:, 1, 1] + Jn[:, 1] * g_top
        We = k.W[self.vdofs]
        rhs = -R + self._assemble_nodal(self._mv(JW, We) - Jn * (n_b - n)[:, None])
        diag = np.zeros(self.nv)
        diag[:-1] += J00
        diag[1:] += J11
        return ReducedSystem((J10.copy(), diag, J01.copy()), rhs, n_b, g_bot, g_top, V)

    def solve(self, S: ReducedSystem, t: float) -> np.ndarray:
        """W from the tridiagonal solve (prescribed W at inlet/wall ends), then n; returns [V, W, n]."""
        lower, diag, upper = S.ab  # lower[i]: row i+1, col i; upper[i]: row i, col i+1
        rhs = S.rhs
        last = self.nv - 1
        for v in np.nonzero(~self._free)[0]:
            w = S.V[v]  # inlet / wall: W = V
            if v > 0:  # column v in row v − 1; row v's lower entry
                rhs[v - 1] -= upper[v - 1] * w
                upper[v - 1] = lower[v - 1] = 0.0
            if v < last:  # column v in row v + 1; row v's upper entry
                rhs[v + 1] -= lower[v] * w
                lower[v] = upper[v] = 0.0
            diag[v], rhs[v] = 1.0, w
        W = dgtsv(lower, diag, upper, rhs, 1, 1, 1, 1)[3]
        n = S.n_b + S.g_bot * W[:-1] + S.g_top * W[1:]
        return np.concatenate([S.V, W, n])

    def pack(self, s: State) -> np.ndarray:
        return np.concatenate([s.V, s.W, s.n])

    def unpack(self, a: np.ndarray, like: State, t: float) -> State:
        nv = self.nv
        if type(like) is State:  # the cheap path: V, W, n are fresh slices of the solve's output
            return State(t, a[:nv], a[nv:2 * nv], like.P.copy(), a[2 * nv:], like.n_bar.copy())
        return like.copy(t=t, V=a[:nv], W=a[nv:2 * nv], n=a[2 * nv:])

    def end_step(self, old: State, new: State, dt: float) -> State:
        """Recover P [Pa] per element from the liquid rows linearised about the last iterate.

        That is the liquid equation the full model's P satisfies in its last solve.
        """
        Wk, nk, drag, old_k, dt_k = self._last_iterate
        L, LW, Ln = self._liquid_rows(new.V, Wk, nk, old_k, dt_k, drag)
        L = L + self._mv(LW, new.W[self.vdofs] - Wk[self.vdofs]) + Ln * (new.n - nk)[:, None]
        new.P = self._pressure_from(self._assemble_nodal(L))
        prev = self._history[1] if self._history is not None else (old.t, old.W.copy(), old.n.copy())
        if prev[0] != old.t or not np.array_equal(prev[1], old.W):
            prev = (old.t, old.W.copy(), old.n.copy())
        self._history = (prev, (new.t, new.W.copy(), new.n.copy()))
        return new

    def recover_pressure(self, s: State, old: State, dt: float) -> np.ndarray:
        """Element pressures [Pa] of state ``s`` (after a step of ``dt`` from ``old``)."""
        drag = self._drag_terms(s.n, s.V[self.vdofs], s.W[self.vdofs])
        return self._pressure_from(self._assemble_nodal(self._liquid_rows(s.V, s.W, s.n, old, dt, drag)[0]))

    def _pressure_from(self, L: np.ndarray) -> np.ndarray:
        """Element pressures [Pa] from [[P]]_i = −L_i/A_i and the outlet pressure."""
        jump = -L / self.vert_area  # P above − P below at vertex i
        if self.top.kind == "outlet":
            return self.top.pressure - np.cumsum(jump[1:][::-1])[::-1]
        return self.bottom.pressure + np.cumsum(jump[:-1])
