"""Exact annular flows and the 2D Q1–P0 verification study built on them.

Fully developed flow in the annulus r_i < r < r_o between a rotating inner
cylinder (angular speed ω) and a fixed outer wall (thesis appendix 4.3):

- axial Poiseuille flow under a uniform axial pressure gradient G = dp/dz [Pa/m]
  (the part of it not balancing gravity), μ (1/r) d/dr(r du_z/dr) = G::

      u_z(r) = G/(4μ) [ r² − r_i² − (r_o² − r_i²) ln(r/r_i) / ln(r_o/r_i) ]

  (the OCR of the appendix garbles the integration; this is the standard result,
  zero at both walls);
- Couette swirl, d/dr((1/r) d(r u_θ)/dr) = 0::

      u_θ(r) = ω/(r_i² − r_o²) (r r_i² − r_i² r_o² / r)

  the form written here: u_θ(r_i) = ω r_i, u_θ(r_o) = 0 (checked in the doctest), so
  the OCR dropped nothing here.

Both are exact solutions of the full Navier–Stokes equations too (convection only
adds the radial pressure ρ u_θ²/r), so dropping convection does not change them.

The study (:func:`annulus_study`) solves the axisymmetric single-fluid problem with
swirl on meshes refined three times and reports the relative L2 errors with the
observed order (:func:`twofluid.verification.order.observed_order`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from twofluid.fem.quad import QuadBasis
from twofluid.mesh.quad import QuadMesh, annular_sector, rectangle
from twofluid.verification.order import observed_order

__all__ = ["annular_poiseuille", "annular_poiseuille_gradient", "couette_swirl",
           "relative_l2_error", "Viscometer", "annulus_study", "convergence_table",
           "sector_couette_study", "sector_table",
           "checkerboard_amplitude", "inf_sup_constant", "channel_pressure_check",
           "checkerboard_table"]


def annular_poiseuille(r: ArrayLike, r_i: float, r_o: float, dpdz: float, mu: float) -> NDArray:
    """Axial velocity u_z(r) [m/s] of fully developed annular flow, G = dpdz [Pa/m].

    Examples
    --------
    >>> u = annular_poiseuille([1.0, 1.5, 2.0], 1.0, 2.0, -1.0, 1.0)
    >>> bool(abs(u[0]) < 1e-15 and abs(u[2]) < 1e-15 and u[1] > 0)
    True
    """
    r = np.asarray(r, dtype=float)
    lam = (r_o**2 - r_i**2) / np.log(r_o / r_i)
    return dpdz / (4.0 * mu) * (r**2 - r_i**2 - lam * np.log(r / r_i))


def annular_poiseuille_gradient(r_i: float, r_o: float, mu: float, u_mean: float) -> float:
    """Axial pressure gradient G [Pa/m] giving mean axial velocity ``u_mean`` [m/s].

    u_mean = Q / (π (r_o² − r_i²)) = −G/(8μ) [r_o² + r_i² − (r_o² − r_i²)/ln(r_o/r_i)].

    Examples
    --------
    >>> G = annular_poiseuille_gradient(1.0, 2.0, 1.0, 1.0)
    >>> r = np.linspace(1.0, 2.0, 200001)
    >>> u = annular_poiseuille(r, 1.0, 2.0, G, 1.0)
    >>> round(float(np.trapezoid(2 * np.pi * r * u, r) / (3 * np.pi)), 8)
    1.0
    """
    lam = (r_o**2 - r_i**2) / np.log(r_o / r_i)
    return -8.0 * mu * u_mean / (r_o**2 + r_i**2 - lam)


def couette_swirl(r: ArrayLike, r_i: float, r_o: float, omega: float) -> NDArray:
    """Swirl u_θ(r) [m/s] between an inner cylinder turning at ω [rad/s] and a fixed outer wall.

    Examples
    --------
    >>> u = couette_swirl([0.5, 2.0], 0.5, 2.0, 3.0)   # ω r_i at r_i, 0 at r_o
    >>> bool(np.allclose(u, [1.5, 0.0], rtol=0, atol=1e-15))
    True
    """
    r = np.asarray(r, dtype=float)
    return omega / (r_i**2 - r_o**2) * (r * r_i**2 - r_i**2 * r_o**2 / r)


def relative_l2_error(mesh: QuadMesh, nodal: NDArray, exact, order: int = 4) -> float:
    """‖u_h − u‖ / ‖u‖ in L2 over the mesh (2πr-weighted in axisymmetry).

    ``nodal`` (n_nodes,) is a Q1 field, ``exact`` a callable of coordinates (..., 2).
    """
    b = QuadBasis(mesh, order=order)
    ue = exact(b.x)
    return float(np.sqrt(b.integrate((b.interpolate(nodal) - ue) ** 2) / b.integrate(ue**2)))


@dataclass(frozen=True)
class Viscometer:
    """Annular gap of a rotating-cylinder viscometer with axial through-flow.

    Geometry chosen by the project (the thesis's fig. 4.8 gives no numbers): a
    Brookfield-like spindle r_i = 20 mm in a vessel r_o = 50 mm, a straight section
    of height 60 mm (two gap widths); the thesis's single test fluid ρ = 1600 kg/m³,
    μ = 1 Pa·s (thesis 4.7.3); inner cylinder at ω = 10 rad/s (0.2 m/s at the wall),
    mean axial velocity 0.1 m/s. Reynolds numbers ρ U (r_o − r_i)/μ ≈ 5 and 10.
    """

    r_i: float = 0.02
    r_o: float = 0.05
    height: float = 0.06
    rho: float = 1600.0
    mu: float = 1.0
    omega: float = 10.0
    u_mean: float = 0.1
    g: float = 9.81

    @property
    def dpdz(self) -> float:
        """Viscous part of the axial pressure gradient [Pa/m]."""
        return annular_poiseuille_gradient(self.r_i, self.r_o, self.mu, self.u_mean)

    def u_z(self, x: NDArray) -> NDArray:
        return annular_poiseuille(x[..., 0], self.r_i, self.r_o, self.dpdz, self.mu)

    def u_theta(self, x: NDArray) -> NDArray:
        return couette_swirl(x[..., 0], self.r_i, self.r_o, self.omega)

    def pressure(self, x: NDArray) -> NDArray:
        """Exact pressure [Pa], zero at the outlet z = height, hydrostatic head included."""
        return (self.dpdz - self.rho * self.g) * (x[..., 1] - self.height)

    def mesh(self, nr: int) -> QuadMesh:
        """nr elements across the gap, square elements (2 nr along the height)."""
        nz = int(round(nr * self.height / (self.r_o - self.r_i)))
        return rectangle(self.r_i, self.r_o, 0.0, self.height, nr, nz, axisymmetric=True)


def annulus_study(levels=(4, 8, 16, 32), case: Viscometer | None = None,
                  stabilisation: str | None = "auto", delta: float = 0.25) -> dict:
    """Solve the viscometer annulus on each level and measure the errors.

    Inlet (bottom): exact u_z, u_θ, u_r = 0; inner wall: no slip with u_θ = ω r_i;
    outer wall: no slip; outlet (top): u_r = 0, natural σ_zz = 0 and σ_zθ = 0
    (consistent with fully developed flow, p = 0 there). Gravity −g ẑ.

    Returns
    -------
    dict with arrays ``h`` [m], ``err_uz``, ``err_utheta``, ``err_p`` (relative L2 [-]),
    and ``order_uz``, ``order_utheta``, ``order_p`` (:class:`ObservedOrder`).
    """
    from twofluid.models.single_fluid import solve_stokes

    c = case if case is not None else Viscometer()
    h, e_z, e_t, e_p, nzs = [], [], [], [], []
    for nr in levels:
        m = c.mesh(nr)
        nzs.append(m.n_elements // nr)
        bc = {
            "outer": {"r": 0.0, "z": 0.0, "theta": 0.0},
            "inner": {"r": 0.0, "z": 0.0, "theta": c.omega * c.r_i},
            "bottom": {"r": 0.0, "z": c.u_z, "theta": c.u_theta},
            "top": {"r": 0.0},
        }
        res = solve_stokes(m, c.mu, bc, rho=c.rho, gravity=(0.0, -c.g), swirl=True,
                           stabilisation=stabilisation, delta=delta)
        h.append((c.r_o - c.r_i) / nr)
        e_z.append(relative_l2_error(m, res.velocity[:, 1], c.u_z))
        e_t.append(relative_l2_error(m, res.velocity[:, 2], c.u_theta))
        b = QuadBasis(m, order=4)
        pe = c.pressure(b.x)
        e_p.append(float(np.sqrt(b.integrate((res.pressure[:, None] - pe) ** 2) / b.integrate(pe**2))))
    out = {"levels": np.asarray(levels), "nz": np.asarray(nzs), "h": np.asarray(h),
           "err_uz": np.asarray(e_z),
           "err_utheta": np.asarray(e_t), "err_p": np.asarray(e_p)}
    for k in ("uz", "utheta", "p"):
        out[f"order_{k}"] = observed_order(out["h"], out[f"err_{k}"])
    return out


def convergence_table(study: dict | None = None) -> str:
    """Markdown table (h, relative L2 errors, pairwise orders) of :func:`annulus_study`."""
    s = study if study is not None else annulus_study()
    lines = ["| elements (r × z) | h [mm] | u_z error | rate | u_θ error | rate | p error | rate |",
             "|---|---|---|---|---|---|---|---|"]
    for i, nr in enumerate(s["levels"]):
        nz = s["nz"][i]
        rates = ["–" if i == 0 else f"{s[f'order_{k}'].pairwise[i - 1]:.2f}" for k in ("uz", "utheta", "p")]
        lines.append(f"| {nr} × {nz} | {1e3 * s['h'][i]:.3g} | {s['err_uz'][i]:.3e} | {rates[0]} "
                     f"| {s['err_utheta'][i]:.3e} | {rates[1]} | {s['err_p'][i]:.3e} | {rates[2]} |")
    lines.append(f"| least-squares order | | | {s['order_uz'].rate:.2f} | | "
                 f"{s['order_utheta'].rate:.2f} | | {s['order_p'].rate:.2f} |")
    return "\n".join(lines)


def sector_couette_study(levels=(4, 8, 16, 32), r_i: float = 0.02, r_o: float = 0.05,
                         omega: float = 10.0, mu: float = 1.0,
                         stabilisation: str | None = "auto") -> dict:
    """Planar Couette flow in a quarter ring (:func:`~twofluid.mesh.quad.annular_sector`).

    The in-plane velocity u = u_θ(r) (−sin θ, cos θ) with u_θ = :func:`couette_swirl`
    is an exact planar Stokes solution with constant pressure; it is prescribed on all
    four sides (enclosed: mean-zero pressure), nr elements across the gap and
    2 nr around. Returns ``h`` [m], relative L2 velocity error ``err_u`` [-],
    RMS pressure ``p_rms`` [Pa] (exact 0) and ``order_u``.
    """
    from twofluid.models.single_fluid import solve_stokes

    def exact(x):
        r, th = np.hypot(x[..., 0], x[..., 1]), np.arctan2(x[..., 1], x[..., 0])
        ut = couette_swirl(r, r_i, r_o, omega)
        return np.stack([-ut * np.sin(th), ut * np.cos(th)], axis=-1)

    h, err, prms = [], [], []
    for nr in levels:
        m = annular_sector(r_i, r_o, np.pi / 2, nr, 2 * nr)
        bc = {g: {"x": (lambda x: exact(x)[:, 0]), "y": (lambda x: exact(x)[:, 1])}
              for g in ("inner", "outer", "start", "end")}
        res = solve_stokes(m, mu, bc, stabilisation=stabilisation)
        b = QuadBasis(m, order=4)
        ue = exact(b.x)
        diff = b.interpolate(res.velocity) - ue
        err.append(float(np.sqrt(b.integrate((diff**2).sum(-1)) / b.integrate((ue**2).sum(-1)))))
        h.append((r_o - r_i) / nr)
        prms.append(float(np.sqrt(np.mean(res.pressure**2))))
    out = {"levels": np.asarray(levels), "h": np.asarray(h), "err_u": np.asarray(err),
           "p_rms": np.asarray(prms)}
    out["order_u"] = observed_order(out["h"], out["err_u"])
    return out


def sector_table(study: dict | None = None) -> str:
    """Markdown table of :func:`sector_couette_study`."""
    s = study if study is not None else sector_couette_study()
    lines = ["| elements (r × θ) | h [mm] | u error | rate | p RMS [Pa] |", "|---|---|---|---|---|"]
    for i, nr in enumerate(s["levels"]):
        rate = "–" if i == 0 else f"{s['order_u'].pairwise[i - 1]:.2f}"
        lines.append(f"| {nr} × {2 * nr} | {1e3 * s['h'][i]:.3g} | {s['err_u'][i]:.3e} | {rate} "
                     f"| {s['p_rms'][i]:.2e} |")
    lines.append(f"| least-squares order | | | {s['order_u'].rate:.2f} | |")
    return "\n".join(lines)


# --- Q1–P0 pressure stability (checkerboard) -----------------------------------------

def checkerboard_amplitude(p: NDArray, nx: int, ny: int) -> float:
    """Mean projection |⟨p, s⟩|/n_el of element pressures on the global checkerboard s = (−1)^(i+j).

    For the row-by-row element numbering of :func:`~twofluid.mesh.quad.rectangle` [Pa].
    """
    i, j = np.meshgrid(np.arange(nx), np.arange(ny))
    return float(abs(np.mean(((-1.0) ** (i + j)).ravel() * np.asarray(p))))


def inf_sup_constant(n: int, stabilisation: str | None, delta: float = 0.25,
                     grading: tuple | None = None) -> tuple[float, float]:
    """Discrete (stabilised) inf–sup constant of Q1–P0 on the enclosed unit square, n × n.

    Smallest two square roots of the generalised eigenvalues of
    (B K⁻¹ Bᵀ + C) q = λ M_p q (μ = 1, M_p the P0 mass matrix). The first belongs to
    the constant pressure (0 for enclosed flow); the second is the inf–sup constant
    β_h: 0 when a spurious (checkerboard) mode exists, bounded away from 0
    independently of h for a stable pair. Dense: keep n ≤ 32.
    """
    import scipy.linalg as sl
    import scipy.sparse.linalg as spla

    from twofluid.models.single_fluid import assemble_stokes

    m = rectangle(0.0, 1.0, 0.0, 1.0, n, n, grading=grading)
    wall = {"x": 0.0, "y": 0.0}
    s = assemble_stokes(m, 1.0, {k: wall for k in ("left", "right", "bottom", "top")},
                        stabilisation=stabilisation, delta=delta)
    A, nu, ne = s.matrix.tocsr(), s.n_velocity, s.n_elements
    free = np.setdiff1d(np.arange(nu), s.fixed)
    K = A[free][:, free].tocsc()
    B = A[nu:nu + ne][:, free].toarray()
    C = -A[nu:nu + ne, nu:nu + ne].toarray()
    S = B @ spla.splu(K).solve(B.T) + C
    lam = sl.eigh(S, np.diag(QuadBasis(m).dx.sum(axis=1)), eigvals_only=True,
                  subset_by_index=[0, 1])
    return tuple(float(v) for v in np.sqrt(np.clip(lam, 0.0, None)))


def channel_pressure_check(n: int, stabilisation: str | None, delta: float = 0.25) -> dict:
    """Planar Poiseuille channel [0, 2] × [0, 1] m, 2n × n elements, μ = 1 Pa·s.

    Inlet profile u = y(1 − y) m/s, no slip top and bottom, outlet u_y = 0 and
    σ_xx = 0: exact p = 2(2 − x) Pa. Returns the checkerboard amplitude of the
    element-pressure error and its maximum [Pa] (an unstabilised solve of this
    singular system may raise; then both are ``nan`` and ``singular`` is True).
    """
    from twofluid.models.single_fluid import solve_stokes

    m = rectangle(0.0, 2.0, 0.0, 1.0, 2 * n, n)
    prof = lambda x: x[:, 1] * (1.0 - x[:, 1])  # noqa: E731
    bc = {"top": {"x": 0, "y": 0}, "bottom": {"x": 0, "y": 0},
          "left": {"x": prof, "y": 0}, "right": {"y": 0}}
    try:
        res = solve_stokes(m, 1.0, bc, stabilisation=stabilisation, delta=delta)
    except RuntimeError:
        return {"amplitude": np.nan, "max_error": np.nan, "singular": True}
    xc = m.points[m.cells].mean(axis=1)
    err = res.pressure - 2.0 * (2.0 - xc[:, 0])
    u_err = float(np.abs(res.velocity[:, 0] - prof(m.points)).max())
    return {"amplitude": checkerboard_amplitude(err, 2 * n, n),
            "max_error": float(np.abs(err).max()), "u_max_error": u_err, "singular": False}


def checkerboard_table(levels=(4, 8, 16), kinds=(None, "checkerboard", "local", "global")) -> str:
    """Markdown tables of :func:`inf_sup_constant` and :func:`channel_pressure_check`."""
    lines = ["| stabilisation | " + " | ".join(f"β_h, {n}×{n}" for n in levels) + " |",
             "|---|" + "---|" * len(levels)]
    for k in kinds:
        lines.append(f"| {k} | " + " | ".join(f"{inf_sup_constant(n, k)[1]:.3g}" for n in levels) + " |")
    lines += ["", "| stabilisation | " + " | ".join(
        f"checkerboard amplitude / max p error / max u error [Pa, Pa, m/s], {2 * n}×{n}"
        for n in levels) + " |", "|---|" + "---|" * len(levels)]
    for k in kinds:
        cells = []
        for n in levels:
            r = channel_pressure_check(n, k)
            cells.append("singular" if r["singular"] else
                         f"{r['amplitude']:.2e} / {r['max_error']:.2e} / {r['u_max_error']:.2e}")
        lines.append(f"| {k} | " + " | ".join(cells) + " |")
    return "\n".join(lines)
