"""What a rotating-cylinder viscometer measures: the torque on its spindle and the apparent viscosity.

The spindle is a rotating wall (angular speed ω about the axis) of an axisymmetric
mesh with swirl; its side is the cylinder r = r_i, the vessel wall r = r_o. The
torque is the moment about the axis of the swirl (θ) reactions of the momentum
equation at the spindle's nodes, T = Σ_a r_a R_θ,a: the variationally consistent
value of ∫ r τ_rθ dA over the wetted surface (of ∫ r τ_zθ dA on a flat tip), which
converges at the rate of the energy, faster than the stress of the elements next to
the wall. It is the torque the spindle exerts on the contents over the full
circumference (the 2πr measure), in N·m, positive in the sense of ω: at a steady
speed, the motor torque.

End effects: the torque on the whole wetted surface exceeds the Couette torque of an
infinitely long cylinder of the same wetted length (the tip and the stress near it).
As in a guard-ring viscometer, the apparent viscosity is read from a measuring section
of the side only, one gap width r_o − r_i away from both ends of the wetted side
(the tip and the top), where the flow is the Couette flow of the annulus:

    μ_app = T_section (r_o² − r_i²) / (4π ω L r_i² r_o²),   L the section's length.

The reactions of the section's end nodes count half (the trapezoidal share of their
edges), so the section length is exact for a uniform wall stress.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["couette_torque", "couette_viscosity", "SpindleSection", "spindle_section", "spindle_torque",
           "mixture_swirl_reaction", "swirl_without_circulation"]


def couette_torque(mu: float, omega: float, length: float, r_i: float, r_o: float) -> float:
    """Torque [N·m] on an inner cylinder of length ``length`` [m] turning at ω in an annulus.

    T = 4π μ ω L r_i² r_o² / (r_o² − r_i²) (circular Couette flow, outer wall at rest).

    Examples
    --------
    >>> T = couette_torque(1.0, 10.0, 0.06, 0.02, 0.05)
    >>> round(T * 1e3, 4)   # mN·m
    3.5904
    >>> # τ_rθ at r_i times the wetted area times r_i
    >>> tau = 2 * 1.0 * 10.0 * 0.05**2 / (0.05**2 - 0.02**2)
    >>> bool(abs(tau * 2 * np.pi * 0.02 * 0.06 * 0.02 - T) < 1e-15)
    True
    """
    return 4.0 * np.pi * mu * omega * length * r_i ** 2 * r_o ** 2 / (r_o ** 2 - r_i ** 2)


def couette_viscosity(r_edges, mu) -> float:
    """The viscosity [Pa·s] a Couette viscometer reads from layers of viscosity ``mu`` between ``r_edges``.

    Torque is the same through every cylinder r (steady swirl), so the layers act in
    series with the weight 1/r³: μ_eq = (r_i⁻² − r_o⁻²) / Σ_j (r_j⁻² − r_j+1⁻²)/μ_j.

    Examples
    --------
    >>> couette_viscosity([0.02, 0.03, 0.05], [2.0, 2.0])
    2.0
    >>> bool(couette_viscosity([0.02, 0.03, 0.05], [1.0, 3.0]) < 2.0)   # the inner layer weighs most
    True
    """
    r = np.asarray(r_edges, dtype=float)
    w = r[:-1] ** -2 - r[1:] ** -2
    return float(w.sum() / (w / np.asarray(mu, dtype=float)).sum())


@dataclass(frozen=True)
class SpindleSection:
    """Geometry of a spindle: radius, wetted side [z_lo, z_hi], measuring section [z_a, z_b] (m)."""

    r_i: float
    r_o: float
    z_lo: float
    z_hi: float
    z_a: float
    z_b: float

    @property
    def length(self) -> float:
        return self.z_b - self.z_a


def spindle_section(points: np.ndarray, nodes: np.ndarray, z_top: float | None = None) -> SpindleSection:
    """The spindle of the nodes ``nodes`` (a rotating wall) on a mesh with node coordinates ``points``.

    r_i is the largest radius of the spindle's nodes, r_o the largest of the mesh; the
    wetted side runs from the side's lowest node to its highest, or to ``z_top`` [m]
    (e.g. the surface of a bed) if lower. The measuring section is the wetted side with
    one gap width r_o − r_i cut off at each end (the middle third of the wetted side if
    it is shorter than three gap widths), its ends moved inward to the nearest nodes.
    """
    p = points[nodes]
    r_i, r_o = float(p[:, 0].max()), float(points[:, 0].max())
    side = p[np.abs(p[:, 0] - r_i) <= 1e-9 * r_o, 1]
    z_lo, z_hi = float(side.min()), float(side.max())
    if z_top is not None:
        z_hi = min(z_hi, float(z_top))
    if z_hi <= z_lo:
        raise ValueError(f"the spindle's side (from z = {z_lo:g} m) is not wetted (top {z_hi:g} m)")
    guard = r_o - r_i
    if z_hi - z_lo < 3.0 * guard:
        guard = (z_hi - z_lo) / 3.0
    # the section ends on nodes of the side (inward), so the trapezoidal end weights are exact
    zs = np.unique(side)
    z_a = float(zs[np.searchsorted(zs, z_lo + guard - 1e-9 * r_o)])
    z_b = float(zs[np.searchsorted(zs, z_hi - guard + 1e-9 * r_o, side="right") - 1])
    return SpindleSection(r_i, r_o, z_lo, z_hi, z_a, z_b)


def spindle_torque(points: np.ndarray, nodes: np.ndarray, reaction_theta: np.ndarray,
                   omega: float, geometry: SpindleSection | None = None) -> dict:
    """Torques on the spindle [N·m] and the apparent viscosity [Pa·s] from them.

    ``reaction_theta`` holds the swirl reactions R_θ [N] of the spindle's ``nodes``.
    Returns the torque on the whole wetted surface, on the flat tip (nodes below the
    side, the corner excluded), on the measuring section, the Couette torques per unit
    viscosity of the section and of the wetted side, and μ_app from the section.

    Examples
    --------
    >>> pts = np.array([[0.02, z] for z in np.linspace(0.0, 0.12, 13)] + [[0.05, 0.0]])
    >>> nodes = np.arange(13)
    >>> tau = 2 * 1.0 * 10.0 * 0.05**2 / (0.05**2 - 0.02**2)   # Couette wall stress, μ = 1
    >>> R = np.full(13, tau * 2 * np.pi * 0.02 * 0.01); R[[0, -1]] /= 2
    >>> out = spindle_torque(pts, nodes, R, 10.0)
    >>> round(out["apparent_viscosity_Pa_s"], 12)
    1.0
    """
    g = geometry or spindle_section(points, nodes)
    p = points[nodes]
    moment = p[:, 0] * reaction_theta
    tol = 1e-9 * g.r_o
    on_side = np.abs(p[:, 0] - g.r_i) <= tol
    in_sec = on_side & (p[:, 1] >= g.z_a - tol) & (p[:, 1] <= g.z_b + tol)
    ends = in_sec & ((np.abs(p[:, 1] - g.z_a) <= tol) | (np.abs(p[:, 1] - g.z_b) <= tol))
    weight = np.where(ends, 0.5, 1.0) * in_sec
    t_sec = float((weight * moment).sum())
    per_mu = couette_torque(1.0, omega, g.length, g.r_i, g.r_o)
    per_mu_side = couette_torque(1.0, omega, g.z_hi - g.z_lo, g.r_i, g.r_o)
    total = float(moment.sum())
    return {"torque_N_m": total, "tip_torque_N_m": float(moment[~on_side].sum()),
            "section_torque_N_m": t_sec,
            "section_m": [g.z_a, g.z_b], "wetted_side_m": [g.z_lo, g.z_hi],
            "r_inner_m": g.r_i, "r_outer_m": g.r_o, "omega_rad_s": omega,
            "apparent_viscosity_Pa_s": t_sec / per_mu if omega else float("nan"),
            "whole_spindle_over_couette_of_wetted_side": total / (per_mu_side * t_sec / per_mu)
            if t_sec else float("nan")}


def mixture_swirl_reaction(model, state) -> np.ndarray:
    """Swirl reactions [N] of the mixture momentum rows of a :class:`TwoFluid2D`, per node.

    The steady part of the θ rows: τ_m = (μ_f + μ_s)/2 τ(V) + (μ_f − μ_s)/2 τ(W) = μ_f τ(nU_f)
    + μ_s τ((1 − n)U_s) (pressures and gravity have no swirl component, drag acts in the
    liquid rows only), so at a steady state it is the whole reaction of those rows: the
    torque of the spindle on the mixture, liquid and solids together.
    """
    from ..closures.viscosity import solid_viscosity

    n, mat, clo = state.n, model.mat, model.clo
    mu_s = solid_viscosity(n, mat.mu_f, **clo.viscosity_params) if clo.viscous else np.zeros(model.ne)
    mu_f = mat.mu_f if clo.viscous else 0.0
    vd = model.vd
    el = np.einsum("eij,ej->ei", model.K1, (0.5 * (mu_f + mu_s))[:, None] * state.V[vd]
                   + (0.5 * (mu_f - mu_s))[:, None] * state.W[vd])
    r = np.zeros(model.nv)
    np.add.at(r, vd, el)
    return r.reshape(model.nc, model.nn).T[:, 2]


def swirl_without_circulation(model, state, iterations: int = 20, tol: float = 1e-10):
    """The swirl of ``state``'s porosity field with the meridional velocities suppressed.

    V and W in the (r, z) plane are set to zero and only the swirl rows (mixture and
    liquid) are solved, steady (Δt → ∞), with the porosity, the pressure and the
    rotating walls' swirl as in ``state``; the drag coefficient, which depends on the
    magnitude of the whole slip, is iterated to ``tol`` (Picard). Returns the new state.
    What remains of the torque is that of the porosity field alone; the difference to
    ``state``'s torque is the share of the meridional circulation.
    """
    import scipy.sparse.linalg as spla

    nn, nv = model.nn, model.nv
    theta = np.concatenate([np.arange(2 * nn, 3 * nn), nv + np.arange(2 * nn, 3 * nn)])
    k = state.copy(V=state.V.copy(), W=state.W.copy())
    k.V[:2 * nn] = 0.0
    k.W[:2 * nn] = 0.0
    idx = model.dirichlet(state.t)[0]
    fixed = np.zeros(model.size, dtype=bool)
    fixed[idx] = True
    free = theta[~fixed[theta]]
    pinned = theta[fixed[theta]]
    for _ in range(iterations):
        A, b = model.assemble(k, k, 1e12, state.t)  # Δt → ∞: the steady rows
        x = model.pack(k)
        x[idx] = model.dirichlet(state.t)[1]  # the rotating wall's W_θ from the nodal porosity
        rest = np.ones(model.size, dtype=bool)
        rest[free] = False
        rhs = b[free] - A[free][:, rest] @ x[rest]
        new = spla.spsolve(A[free][:, free].tocsc(), rhs)
        change = float(np.abs(new - x[free]).max()) / max(float(np.abs(x[theta]).max()), 1e-30)
        x[free] = new
        k = model.unpack(x, k, state.t)
        if change < tol:
            break
    return k
