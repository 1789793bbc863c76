"""Horizontal shear wave in a level soil column, Newmark average acceleration (docs/model.md).

Relative formulation: u(y, t) is the horizontal displacement of the column
relative to a rigid reference motion with acceleration a_g(t), ρ̄ the mixture
density (liquid and grains move together horizontally in level ground):

    ρ̄ ∂²u/∂t² = ∂τ/∂y − ρ̄ a_g(t),   τ(H, t) = 0 (free top)
    τ = G_max (G/G_max)(γ) γ + η ∂γ/∂t,   γ = ∂u/∂y

and at the base either

* a **rigid base** (default): u(0, t) = 0, a_g is the base acceleration; or
* a **compliant base** (``base_impedance`` c = ρ_r V_r, Lysmer–Kuhlemeyer): a_g is
  the *outcrop* acceleration of the bedrock (the motion of its free surface, twice
  the incident wave) and the base node carries the dashpot traction −c ∂u/∂t(0, t).

Compliant base, derivation (docs/liquefaction.md has it in full). In absolute
displacement U the elastic bedrock below y = 0 carries an upgoing incident wave
f(t − y/V_r) and a downgoing reflected one g(t + y/V_r); its stress at y = 0 is
τ_r = ρ_r V_r (g′ − f′) and its velocity U̇_b = f′ + g′, so τ_r = c (U̇_b − 2 f′).
The outcrop motion (free rock surface, τ = 0 there) is U_o = 2 f, hence the base
traction on the column −τ_r = −c U̇_b + c U̇_o. With U = u + U_o (reference motion =
outcrop motion, a_g = Ü_o) the two U̇_o terms cancel: the relative equations are the
rigid-base ones with the base node free and the dashpot −c u̇(0) alone. The input
stays an acceleration record; no velocity of the record is needed.

Linear elements (γ constant per element), consistent mass, so one step solves a
tridiagonal system. The elastic part is the secant backbone of the modulus
reduction curve (non-linear elastic, no hysteresis), with G_max per element
given by the caller (it follows the granular pressure). The viscous part is
η = μ_m + a1 G_t (mixture viscosity plus the stiffness term of Rayleigh damping,
G_t the current tangent modulus), plus the mass term a0 ρ̄ ∂u/∂t; (a0, a1) give
the damping ratio ξ at two frequencies. The stiffness term uses the tangent
modulus so that a liquefied element (G → 0) does not keep a viscous strength it
no longer has.

Time stepping: Newmark with β = 1/4, γ = 1/2 (average acceleration): second
order and free of numerical damping (a linear undamped column keeps its energy
exactly), unconditionally stable. The non-linear backbone is solved by Newton
iterations in each step; the damping matrix is evaluated at the start of the step.

>>> import numpy as np
>>> col = ShearColumn(np.linspace(0.0, 10.0, 11), rho=np.full(10, 2000.0))
>>> s = col.rest()
>>> s = col.step(s, 0.01, 1.0, g_max=np.full(10, 50e6))  # base accelerates at 1 m/s²
>>> bool(s.u[-1] < 0.0), float(s.u[0])  # the column lags behind the base
(True, 0.0)
>>> soft = ShearColumn(np.linspace(0.0, 10.0, 11), rho=np.full(10, 2000.0), base_impedance=2400 * 760.0)
>>> s = soft.step(soft.rest(), 0.01, 1.0, g_max=np.full(10, 50e6))  # outcrop accelerates at 1 m/s²
>>> bool(s.u[0] < 0.0)  # the base node now lags behind the outcrop too
True
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

__all__ = ["WaveState", "ShearColumn", "rayleigh_coefficients", "NewmarkFailure",
           "layer_amplification", "piecewise_reduction"]

BETA, GAMMA = 0.25, 0.5  # average acceleration


def _solve_banded(*args):
    """``scipy.linalg.solve_banded``, imported on first use: the compiled shear path
    (:mod:`~twofluid.models.shear_kernel`) needs no ``scipy.linalg``, which costs 0.2–0.35 s to import."""
    from scipy.linalg import solve_banded

    return solve_banded(*args)


class NewmarkFailure(RuntimeError):
    """The Newton iterations of a shear step did not converge."""


@dataclass
class WaveState:
    """Horizontal motion relative to the base at time t: nodal u [m], v [m/s], a [m/s²].

    ``gamma`` is the element shear strain [-], ``tau`` the element shear stress [Pa].
    """

    t: float
    u: np.ndarray
    v: np.ndarray
    a: np.ndarray
    gamma: np.ndarray
    tau: np.ndarray


def rayleigh_coefficients(ratio: float, f1: float, f2: float) -> tuple[float, float]:
    """(a0 [1/s], a1 [s]) of Rayleigh damping with damping ratio ``ratio`` at f1 and f2 [Hz].

    ξ(ω) = a0/(2ω) + a1 ω/2.

    >>> a0, a1 = rayleigh_coefficients(0.05, 1.0, 10.0)
    >>> w = 2 * np.pi * np.array([1.0, 10.0])
    >>> [round(float(x), 6) for x in a0 / (2 * w) + a1 * w / 2]
    [0.05, 0.05]
    """
    w1, w2 = 2.0 * np.pi * f1, 2.0 * np.pi * f2
    return 2.0 * ratio * w1 * w2 / (w1 + w2), 2.0 * ratio / (w1 + w2)


def layer_amplification(frequency, H: float, rho: float, g: float, base_impedance: float | None = None,
                        eta: float = 0.0):
    """Exact steady-state amplification |U(H)|/|U_o| of a uniform linear layer [-].

    A layer of thickness ``H`` [m], density ``rho`` [kg/m³], shear modulus ``g`` [Pa] and
    Kelvin–Voigt viscosity ``eta`` [Pa·s] (complex modulus G* = G + iωη) on an elastic
    half-space of impedance ``base_impedance`` c = ρ_r V_r [Pa·s/m] (None: rigid base),
    shaken harmonically at ``frequency`` [Hz]: surface motion over outcrop motion (over
    the base motion for a rigid base),

        A(ω) = 1/|cos(k* H) + i α* sin(k* H)|,   k* = ω √(ρ/G*),   α* = √(ρ G*)/c

    (Kramer 1996, Geotechnical Earthquake Engineering, ch. 7; α* = 0 on a rigid base).
    Without viscosity this is 1/√(cos²(kH) + α² sin²(kH)) with α = ρ V_s/(ρ_r V_r).

    >>> f1 = np.sqrt(50e6 / 2000.0) / 40.0  # first resonance, kH = π/2
    >>> round(float(layer_amplification(f1, 10.0, 2000.0, 50e6, 2000.0 * 158.11388 / 0.5)), 6)  # 1/α
    2.0
    >>> round(float(layer_amplification(f1 / 2, 10.0, 2000.0, 50e6)), 6)  # 1/cos(π/4)
    1.414214
    """
    w = 2.0 * np.pi * np.asarray(frequency, dtype=float)
    g_star = g + 1j * w * eta
    k = w * np.sqrt(rho / g_star)
    alpha = 0.0 if base_impedance is None else np.sqrt(rho * g_star) / base_impedance
    return 1.0 / np.abs(np.cos(k * H) + 1j * alpha * np.sin(k * H))


def piecewise_reduction(parts, n_elements: int) -> Callable[[np.ndarray], np.ndarray]:
    """One G/G_max(γ) over a column whose layers have their own curves.

    ``parts`` is a list of (element slice or index array, curve); each curve maps the strains of
    its elements to G/G_max. The result takes the (n_elements,) strains of the whole column.

    >>> f = piecewise_reduction([(slice(0, 2), lambda g: 1 / (1 + abs(g) / 1e-3)),
    ...                          (slice(2, 3), lambda g: np.ones_like(g))], 3)
    >>> f(np.array([1e-3, 0.0, 5.0])).tolist()
    [0.5, 1.0, 1.0]
    """
    def curve(gamma):
        gamma = np.asarray(gamma, dtype=float)
        out = np.empty(n_elements)
        for idx, f in parts:
            out[idx] = f(gamma[idx])
        return out
    return curve


def _hyperbolic_backbone(gamma_ref: float):
    def backbone(g):
        x = 1.0 + np.abs(g) / gamma_ref
        return g / x, 1.0 / (x * x)  # τ/G_max and dτ/dγ / G_max
    return backbone


def _generic_backbone(reduction: Callable):
    def backbone(g):
        d = 1e-6 * np.maximum(np.abs(g), 1e-7)
        tau = reduction(g) * g
        tangent = ((g + d) * reduction(g + d) - (g - d) * reduction(g - d)) / (2.0 * d)
        return tau, np.maximum(tangent, 0.0)
    return backbone


class ShearColumn:
    """Newmark (average acceleration) shear column; see the module docstring.

    Parameters
    ----------
    y : (ne + 1,) vertex heights [m] from the base up.
    rho : (ne,) mixture density per element [kg/m³] (may be updated: attribute ``rho``).
    gamma_ref : reference strain of the hyperbolic G/G_max curve [-] (ignored if ``reduction``).
    reduction : optional G/G_max(γ) function (e.g. a tabulated curve); ``None``: hyperbolic;
        ``"linear"``: G = G_max (constant modulus).
    damping_ratio, damping_frequencies : Rayleigh damping ξ [-] at two frequencies [Hz].
    viscosity : (ne,) or scalar mixture viscosity μ_m [Pa·s] (attribute ``eta``).
    newton_tol : relative change of u that ends the Newton iterations [-].
    base_impedance : None (rigid base, u(0) = 0, ``a_g`` is the base acceleration) or
        c = ρ_r V_r > 0 [Pa·s/m] of a compliant base: ``a_g`` is the outcrop acceleration,
        u is relative to the outcrop motion and the base node has the dashpot −c u̇(0).
    """

    def __init__(self, y, rho, gamma_ref: float = 1e-3, reduction=None,
                 damping_ratio: float = 0.0, damping_frequencies=(1.0, 10.0),
                 viscosity=0.0, newton_tol: float = 1e-10, max_iter: int = 40,
                 base_impedance: float | None = None):
        self.y = np.asarray(y, dtype=float)
        self.h = np.diff(self.y)
        ne = self.h.size
        self.rho = np.broadcast_to(np.asarray(rho, dtype=float), (ne,)).copy()
        self.eta = np.broadcast_to(np.asarray(viscosity, dtype=float), (ne,)).copy()
        if reduction == "linear":
            self.backbone = lambda g: (np.asarray(g, float), np.ones_like(g, dtype=float))
        elif reduction is None:
            self.backbone = _hyperbolic_backbone(gamma_ref)
            self.gamma_ref = gamma_ref  # the compiled shear kernel evaluates this backbone itself
        else:
            self.backbone = _generic_backbone(reduction)
        if damping_ratio > 0.0:
            self.a0, self.a1 = rayleigh_coefficients(damping_ratio, *damping_frequencies)
        else:
            self.a0, self.a1 = 0.0, 0.0
        self.tol, self.max_iter = newton_tol, max_iter
        if base_impedance is not None and not (np.isfinite(base_impedance) and base_impedance > 0.0):
            raise ValueError(f"base_impedance must be a finite c = rho_r V_r > 0, got {base_impedance}")
        self.base_impedance = None if base_impedance is None else float(base_impedance)

    # ----------------------------------------------------------- matrices
    def rest(self, t: float = 0.0) -> WaveState:
        z = np.zeros(self.h.size + 1)
        return WaveState(t, z.copy(), z.copy(), z.copy(), np.zeros(self.h.size), np.zeros(self.h.size))

    def _mass_bands(self):
        """Consistent mass: diagonal (ne+1,) and off-diagonal (ne,) [kg/m²]."""
        m = self.rho * self.h
        diag = np.zeros(self.h.size + 1)
        diag[:-1] += m / 3.0
        diag[1:] += m / 3.0
        return diag, m / 6.0

    def _bar_bands(self, k):
        """Bands of Σ k_e [[1, −1], [−1, 1]] for element values k (ne,)."""
        diag = np.zeros(k.size + 1)
        diag[:-1] += k
        diag[1:] += k
        return diag, -k

    @staticmethod
    def _matvec(diag, off, x):
        out = diag * x
        out[:-1] += off * x[1:]
        out[1:] += off * x[:-1]
        return out

    def internal_force(self, tau):
        """f_i = ∫ ∂N_i/∂y τ dy: −τ_e at the bottom node of element e, +τ_e at its top node."""
        f = np.zeros(tau.size + 1)
        f[:-1] -= tau
        f[1:] += tau
        return f

    def energy(self, s: WaveState, g_max) -> float:
        """Kinetic + strain energy per unit area [J/m²] (linear elastic part only)."""
        md, mo = self._mass_bands()
        kin = 0.5 * float(s.v @ self._matvec(md, mo, s.v))
        return kin + 0.5 * float(np.sum(np.asarray(g_max) * s.gamma ** 2 * self.h))

    def dashpot_work(self, old: WaveState, new: WaveState) -> float:
        """Energy the base dashpot takes out over the step old → new [J/m²] (0 on a rigid base).

        Average acceleration is the trapezoidal rule, so the discrete energy balance is
        exact: E(new) − E(old) = −Δt c v̄_b² (+ the work of the load and of the other damping),
        with v̄_b the mean of the base velocities at the two ends of the step.
        """
        if self.base_impedance is None:
            return 0.0
        vb = 0.5 * (old.v[0] + new.v[0])
        return (new.t - old.t) * self.base_impedance * vb * vb

    def at_equilibrium(self, s: WaveState, a_g: float, g_max) -> WaveState:
        """``s`` with the acceleration that satisfies the equation of motion at s.t [m/s²].

        Newmark needs a consistent start: M a = −ρ̄ a_g (M 1) − C v − f_int(u), at the free
        nodes (all of them on a compliant base, the base node is held on a rigid one).
        """
        g_max = np.broadcast_to(np.asarray(g_max, dtype=float), self.h.shape)
        gamma = np.diff(s.u) / self.h
        md, mo = self._mass_bands()
        tau_n, gt = self.backbone(gamma)
        cd, co = self._damping_bands(g_max, gt)
        rhs = (-self._matvec(md, mo, np.ones_like(md)) * a_g - self._matvec(cd, co, s.v)
               - self.internal_force(g_max * tau_n))
        first = 0 if self.base_impedance is not None else 1
        ab = np.zeros((3, md.size - first))
        ab[0, 1:] = mo[first:]
        ab[1] = md[first:]
        ab[2, :-1] = mo[first:]
        a = np.zeros_like(md)
        a[first:] = _solve_banded((1, 1), ab, rhs[first:])
        return WaveState(s.t, s.u.copy(), s.v.copy(), a, gamma, s.tau.copy())

    def _damping_bands(self, g_max, gt0):
        """Bands of C: viscosity + Rayleigh (tangent stiffness, mass), + the base dashpot."""
        md, mo = self._mass_bands()
        cd, co = self._bar_bands((self.eta + self.a1 * g_max * gt0) / self.h)
        cd, co = cd + self.a0 * md, co + self.a0 * mo
        if self.base_impedance is not None:
            cd[0] += self.base_impedance
        return cd, co

    # --------------------------------------------------------------- step
    def step(self, s: WaveState, dt: float, a_g: float, g_max) -> WaveState:
        """Advance by ``dt`` [s] with base acceleration ``a_g`` [m/s²] at the end of the step
        (the outcrop acceleration on a compliant base).

        ``g_max`` (ne,) is the small-strain modulus per element [Pa] during the step.
        Raises :class:`NewmarkFailure` if Newton does not converge or meets a
        non-finite value (inputs, iterates or the tridiagonal solve).
        """
        g_max = np.broadcast_to(np.asarray(g_max, dtype=float), self.h.shape)
        t_new = s.t + dt
        for what, x in (("G_max", g_max), ("mixture density", self.rho), ("viscosity", self.eta),
                        ("base acceleration", a_g), ("state", s.u), ("state", s.v), ("state", s.a)):
            if not np.all(np.isfinite(x)):
                raise NewmarkFailure(f"shear step at t = {t_new:.6g} s: non-finite {what}")
        if np.any(g_max < 0.0) or np.any(self.rho <= 0.0):
            raise NewmarkFailure(f"shear step at t = {t_new:.6g} s: negative G_max or density <= 0")
        md, mo = self._mass_bands()
        _, gt0 = self.backbone(s.gamma)
        cd, co = self._damping_bands(g_max, gt0)
        first = 0 if self.base_impedance is not None else 1  # first free node (base held if rigid)
        c0, c1 = 1.0 / (BETA * dt * dt), GAMMA / (BETA * dt)
        # a1 = c0 (u1 − u0) − pa, v1 = v0 + dt((1 − γ) a0 + γ a1)
        pa = s.v / (BETA * dt) + (0.5 / BETA - 1.0) * s.a
        force = -self._matvec(md, mo, np.ones_like(md)) * a_g
        u = s.u + dt * s.v + 0.5 * dt * dt * s.a  # predictor
        if first:
            u[0] = 0.0
        for _ in range(self.max_iter):
            acc = c0 * (u - s.u) - pa
            vel = s.v + dt * ((1.0 - GAMMA) * s.a + GAMMA * acc)
            gamma = np.diff(u) / self.h
            tau_n, gt = self.backbone(gamma)
            tau = g_max * tau_n  # elastic part; the viscous part is the C v term
            res = (self._matvec(md, mo, acc) + self._matvec(cd, co, vel) + self.internal_force(tau)
                   - force)
            kd, ko = self._bar_bands(g_max * gt / self.h)
            jd = c0 * md + c1 * cd + kd
            jo = c0 * mo + c1 * co + ko
            ab = np.zeros((3, jd.size - first))  # free nodes first..ne
            ab[0, 1:] = jo[first:]
            ab[1] = jd[first:]
            ab[2, :-1] = jo[first:]
            try:
                du = _solve_banded((1, 1), ab, -res[first:])
            except (ValueError, np.linalg.LinAlgError) as exc:  # non-finite or singular system
                raise NewmarkFailure(f"shear step at t = {t_new:.6g} s: {exc}") from None
            if not np.all(np.isfinite(du)):
                raise NewmarkFailure(f"shear step at t = {t_new:.6g} s: Newton update is not finite")
            u[first:] += du
            if np.max(np.abs(du)) <= self.tol * max(np.max(np.abs(u)), 1e-9):
                break
        else:
            raise NewmarkFailure(f"shear step at t = {t_new:.6g} s: Newton did not converge "
                                 f"in {self.max_iter} iterations")
        acc = c0 * (u - s.u) - pa
        vel = s.v + dt * ((1.0 - GAMMA) * s.a + GAMMA * acc)
        gamma = np.diff(u) / self.h
        tau_n, gt = self.backbone(gamma)
        rate = np.diff(vel) / self.h
        tau = g_max * tau_n + (self.eta + self.a1 * g_max * gt0) * rate
        return WaveState(s.t + dt, u, vel, acc, gamma, tau)
