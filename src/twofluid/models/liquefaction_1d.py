"""1D earthquake liquefaction column: vertical two-component flow + horizontal shear wave.

Thesis sections 5.4–5.5; docs/model.md, "Liquefaction column". The vertical motion is the
full 1D two-component model
(:class:`~twofluid.models.two_fluid_1d.TwoFluid1D`, unknowns V, W, P, n, with the
reference porosity n̄ per element); the horizontal motion is the shear wave of
:class:`~twofluid.models.shear_column.ShearColumn`, driven by the
acceleration record a_g(t) (relative formulation, free top; rigid base by default,
where a_g is the base motion, or a compliant base — a Lysmer–Kuhlemeyer dashpot
c = ρ_r V_r — where a_g is the outcrop motion of the bedrock). They are
coupled through two state variables of each element:

* the granular pressure P_s(n, n̄) sets the small-strain shear modulus
  G_max = 218.8 K2max √(P_s/1 kPa) kPa (Seed & Idriss 1970 in SI), so G → 0 as the element
  liquefies;
* the shear-strain path densifies the skeleton: the reference-porosity law
  (``byrne``, Byrne 1991, or ``ann``, Pringle 2001 app. 3.1) lowers n̄, which lowers P_s at fixed n; the
  vertical equations then move the weight onto the liquid pressure (undrained
  response), drive the liquid to the drained top and let the column settle.

Operator splitting, per vertical step [t, t + Δt] (Lie splitting, first order in Δt):

1. shear sub-steps of ``shear_step`` over the step (Newmark average acceleration),
   each with G_max from P_s(n^t, n̄) — n̄ updated after every sub-step, n held at
   its value at t (undrained within the step);
2. the reference-porosity law applied to each sub-step's strain increment;
3. one backward-Euler step of the vertical model with the new n̄ (its own
   step-halving if the Picard iterations struggle).

The shear wave runs while the base shakes and for ``free_vibration`` seconds after
the record ends (the column rings down through its damping); on a slope it runs on while the
column still flows ("Flow after the shaking" below). After that the
horizontal motion is dropped and only the vertical model advances, with a step
growing by ×1.5 per step from the shaking step to ``reconsolidation_step``.

Strain seen by the densification law: |γ| is clipped at ``Sand.gamma_law_max``
(default 1 %) before the law sees it. The elastic backbone has no residual
strength, so once an element liquefies (G → 0) its strain runs away (tens of
per cent) while the base keeps shaking; Byrne's law, fitted to cyclic tests at
strains below about 1 %, would then make tens of per cent of volumetric strain.
With the cap, n cycles at the cap add at most ε_v = (γ_cap/C2) ln(1 + C1 C2 n),
2.8 % after 20 cycles for Dr = 47 % — the post-liquefaction volumetric strain of
Ishihara & Yoshimine (1992) for a loose clean sand (about 3 % at Dr ≈ 50 % once
the maximum shear strain exceeds a few per cent).

Solids flux: the Galerkin form (``solids_flux = "galerkin"``) of the vertical
model: the drained top face moves with the skeleton (small strain), as in the
Terzaghi check (:mod:`twofluid.verification.terzaghi_check`). The upwind form
would let the top element loosen as its solids settle away from the fixed top
face, so its averaged porosity (half soil, half clear water) would carry no
granular pressure and read as "liquefied". Surface settlement is then the
compression of the skeleton, s = Σ_e h_e (n0_e − n_e)/(1 − n_e) (Lagrangian
volumetric strain summed over the depth; it equals the solids that entered
through the top face divided by (1 − n) to second order).

Excess pore-pressure ratio per element: r_u = (P − P_hydrostatic)/σ′_v0, with
P_hydrostatic = p_top + ρ_f g (H − y) and σ′_v0 the initial granular pressure
(the buoyant weight above, plus any surcharge).

Layered sites: every :class:`Sand` parameter may be an array over the saturated elements
(each layer its own K2max, G/G_max, Dr, viscosity, law, liquefiable or not; the vertical
model's drag diameter, A and p_ref are arrays of its materials and closures). A
:class:`Crust` — the layers above the water table — sits on top of the saturated elements in
the shear column only: its mass and fixed G_max shear with the column, its weight reaches the
vertical model as the surcharge at the water table, and it has no pore pressure.

Infinite slope (``slope_percent`` S > 0, tan α = S/100; hysteretic law only): the column stands
normal to the ground surface (its y, thicknesses and depths are measured normal to the slope;
cos α > 0.999 up to S = 4.5 %), the vertical two-fluid model sees g cos α (the runner gives its
mesh the inclination α and multiplies the surcharge by cos α), and the shear wave, now along the
slope, carries a downslope body force. With slope-parallel seepage (the default) it is ρ̄ g sin α
of the *total* mixture weight: the water table is parallel to the ground surface and the
groundwater seeps parallel to the slope, so the pore pressure does not vary along the slope and
the seepage force carries the water's share of the driving weight (τ_s = σ_v sin α cos α with the
total σ_v). A submerged slope (``submerged``: under still open water, the water table at or above
the ground surface, no crust) is driven by its buoyant weight only, (ρ̄ − ρ_f) g sin α: the
hydrostatic pore pressure grows downslope by ρ_f g sin α per metre, which holds back the water's
share, and the water above the ground surface adds no shear: τ_s = g sin α Σ (ρ̄ − ρ_f) h =
σ′_v sin α cos α, so at rest τ_s/P_s = tan α in every saturated element, P_s = g cos α Σ (ρ̄ − ρ_f) h
the effective stress normal to the slope (σ′_v cos²α, σ′_v the vertical effective stress at the
vertical depth d/cos α of a normal depth d). The inertia keeps the total mass ρ̄ either way. On
a compliant base the bedrock carries the column's downslope weight as a static traction. The run starts from the static equilibrium
under that shear: each element is loaded monotonically on its backbone to τ_s
(:meth:`LiquefactionColumn.static_shear`, :func:`twofluid.closures.hysteretic.static_state`),
with its static strain, and the displacements reported are measured from that state
(:meth:`LiquefactionColumn.lateral_displacement`). Below its strength the skeleton's stress is the
rate-independent backbone with a finite tangent, and every rate term (η γ̇, Rayleigh) vanishes at
zero rate, so rest is an exact solution of the discrete equations: no regularisation of the
strength at zero rate is needed or used.

Flow after the shaking (a sloping column with a :class:`FlowStop`; level ground is unchanged): a
liquefied layer flows under the static shear, resisted by its strength and its rate-dependent
stress, and the shear wave must not be dropped while it does. After ``free_vibration`` seconds the
column checks, after every step, the mean downslope velocity of the surface relative to the base,
v̄ = (D̄(t − T, t) − D̄(t − 2T, t − T))/T with D̄ the time mean of the surface displacement over a
window T (:meth:`LiquefactionColumn.flow_velocity`: a ring-down oscillation averages out, a flow
does not), and drops the shear wave (with the reconsolidation floor) at the first step where
|v̄| < ``FlowStop.velocity``, or at ``FlowStop.max_after`` seconds after the record ends, said then
to be still flowing. The strength returns as the vertical model dissipates the excess pore
pressure (τ_max = P_s tan φ′ above the residual floor), so a flow that the residual strength cannot
hold (FS_post ≤ 1) slows and stops by itself. The record is zero then and the motion quasi-static
or viscous, so the step grows: the vertical step and the shear sub-step (one per vertical step)
grow by ×1.5 per step from the shaking step to ``FlowStop.step``; the sub-steps stay implicit
Newmark (unconditionally stable, the same β, γ), and the bound is checked by halving it
(docs/lateral-spreading.md). The surface acceleration samples (spectra, a_max) stop at
``free_vibration``.

Liquefied-soil viscosity: ``Sand.viscosity`` η_s (1 000 Pa·s by default; Chen et al. 2019
measured 0.8–1.7 kPa·s in falling-ball tests on liquefied soil) is added to the mixture
viscosity of the shear wave, Newtonian, or a power law η_s (|γ̇|/γ̇_ref)^(m − 1) capped at
:data:`VISCOSITY_MAX` when ``viscosity_exponent`` m < 1 (η_s from the previous sub-step's rate).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, fields
from typing import Callable, Iterator

import numpy as np

from ..closures import registry
from ..closures.reference_porosity import ShearState, byrne_constants
from ..closures.shear_modulus import seed_idriss_gmax
from ..closures.solids_pressure import reference_porosity_for
from ..closures.viscosity import mooney_pringle
from ..geotech.settlement import max_shear_strain
from ..timestepping.backward_euler import PicardSettings, StepFailure, integrate
from ..closures import hysteretic as _hyst_law
from . import column_split as _split
from . import record_rows as _record_rows
from . import hysteretic_kernel as _hyst_kernel
from . import shear_kernel as _shear_kernel
from .shear_column import NewmarkFailure, ShearColumn, WaveState, piecewise_reduction
from .two_fluid_1d import State, TwoFluid1D

__all__ = ["Sand", "Crust", "VerticalColumn", "ColumnState", "LiquefactionColumn", "ColumnStep",
           "FlowStop", "VISCOSITY_MAX"]

#: Largest liquefied-soil viscosity the shear wave takes [Pa·s] (the power law is capped here).
VISCOSITY_MAX = 1e5
_F8 = np.dtype(np.float64)


@dataclass(frozen=True)
class Sand:
    """Skeleton parameters of the saturated soil, scalars or arrays per saturated element (defaults:
    the calibrated loose sand of :class:`twofluid.models.element_test.LooseSand`)."""

    k2max: float | np.ndarray = 30.0  # Seed–Idriss modulus number [-]
    gamma_ref: float | np.ndarray = 1e-3  # hyperbolic reference strain [-]
    dr: float | np.ndarray = 47.0  # relative density [%] (byrne)
    law: str = "byrne"  # reference-porosity law (of every element unless law_groups)
    law_params: dict = field(default_factory=dict)  # extra arguments of the law (e.g. ann weights)
    reduction: Callable | None = None  # G/G_max(γ) (e.g. a tabulated curve); None: hyperbolic with gamma_ref
    gamma_law_max: float | np.ndarray = 0.01  # |γ| beyond this adds no densification [-] (module docstring)
    viscosity: float | np.ndarray = 1000.0  # liquefied-soil viscosity η_s in the shear wave [Pa·s]
    viscosity_exponent: float | np.ndarray = 1.0  # power-law flow index m (1: Newtonian) [-]
    viscosity_reference_rate: float | np.ndarray = 1.0  # rate at which η_s = viscosity [1/s]
    liquefiable: bool | np.ndarray = True  # False: n̄ held (no pore-pressure generation)
    law_groups: tuple = ()  # ((element mask, law name, params), ...) for layers with different laws

    def n_bar_law(self) -> Callable:
        """The densification law of every element: (dγ, γ, n̄, history) -> (n̄, history).

        Byrne's constants follow each element's Dr (C1 = 7600 Dr^−2.5); with ``law_groups`` each
        group's law is evaluated and its elements take its result; elements that are not
        ``liquefiable`` keep their n̄.
        """
        groups = self.law_groups or ((None, self.law, self.law_params),)
        funcs = []
        for mask, name, params in groups:
            func = registry.get("reference_porosity", name).func
            p = dict(params)
            if name == "byrne" and "c1" not in p:
                p["c1"] = self.byrne_c1()
            funcs.append((mask, func, p))
        liq = np.asarray(self.liquefiable, dtype=bool)

        def law(dg, g, nb, st):
            out_nb, out_st = None, None
            for mask, func, p in funcs:
                nb_k, st_k = func(dg, g, nb, st, **p)
                if mask is None:
                    out_nb, out_st = nb_k, st_k
                else:
                    out_nb = np.where(mask, nb_k, nb if out_nb is None else out_nb)
                    out_st = st_k if out_st is None else _select_history(mask, st_k, out_st)
            return np.where(liq, out_nb, nb), out_st
        return law

    def byrne_c1(self) -> np.ndarray:
        """Byrne's C1 of each element from its Dr (:func:`~twofluid.closures.reference_porosity.byrne_constants`)."""
        dr = np.asarray(self.dr, dtype=float)
        return np.array([byrne_constants(float(x))[0] for x in dr.ravel()]).reshape(dr.shape)

    def shear_viscosity(self, rate) -> np.ndarray:
        """η_s [Pa·s] at shear-strain rate ``rate`` [1/s]: constant (m = 1) or the power law
        η_s (|γ̇|/γ̇_ref)^(m − 1), at most :data:`VISCOSITY_MAX`."""
        m = np.asarray(self.viscosity_exponent, dtype=float)
        eta = np.broadcast_to(np.asarray(self.viscosity, dtype=float), np.shape(rate))
        if np.all(m == 1.0):
            return np.array(eta, dtype=float)
        x = np.maximum(np.abs(rate), 1e-12) / self.viscosity_reference_rate
        return np.minimum(eta * x ** (m - 1.0), VISCOSITY_MAX)


def _hyperbola(gamma_ref) -> Callable:
    """G/G_max = 1/(1 + |γ|/γ_ref) with γ_ref per element (the closure takes one γ_ref)."""
    r = np.asarray(gamma_ref, dtype=float)
    return lambda g: 1.0 / (1.0 + np.abs(g) / r)


def _select_history(mask, a: ShearState, b: ShearState) -> ShearState:
    """History with ``a`` where ``mask``, ``b`` elsewhere."""
    return ShearState(*(np.where(mask, getattr(a, f.name), getattr(b, f.name)) for f in fields(ShearState)))


@dataclass(frozen=True)
class FlowStop:
    """When the shear wave of a sloping column stops after the shaking (module docstring, "Flow after
    the shaking"): it runs ``free_vibration`` seconds after the record ends, then on while the
    window-mean surface velocity (:meth:`LiquefactionColumn.flow_velocity`) is at least ``velocity``
    [m/s] (0: stop at ``free_vibration``), at most ``max_after`` seconds after the record ends; while
    it flows after ``free_vibration`` the step (vertical step and shear sub-step) grows by ×1.5 per
    step from the shaking step to ``step`` [s]; ``window`` [s] is the averaging window."""

    velocity: float = 1e-5
    window: float = 2.0
    max_after: float = 600.0
    step: float = 0.1


@dataclass(frozen=True)
class Crust:
    """Layers above the water table, bottom element first: thickness h [m], density ρ = γ/g
    [kg/m³] and small-strain modulus G_max [Pa] per element (fixed: no pore pressure), the
    G/G_max curve (``reduction`` callable over the crust elements, or hyperbolic with
    ``gamma_ref``), and σ′_v at each element's centre [Pa] (surcharge plus the crust above; None:
    not given). Its weight is carried by the vertical model as a surcharge."""

    h: np.ndarray
    rho: np.ndarray
    g_max: np.ndarray
    gamma_ref: float | np.ndarray = 1e-3
    reduction: Callable | None = None
    sigma_v: np.ndarray | None = None


class VerticalColumn(TwoFluid1D):
    """:class:`TwoFluid1D` with a surcharge on the solids at the top face and a
    velocity floor in the Picard convergence measure.

    ``surcharge`` [Pa] is a load on the skeleton at the drained top (a fill or a
    foundation; also the way the Terzaghi test makes c_v uniform). ``velocity_floor``
    [m/s]: the Picard test divides velocity changes by max(|V|, |W|, floor). Near
    rest the iterates keep changing by 1e-11–1e-9 m/s (round-off, and the kink of
    Ergun's |U_f − U_s| term at zero slip), which never passes the relative
    tolerance against the default 1e-6 m/s floor; with 1e-2 m/s and the default
    tolerance 1e-7 the velocity test is absolute at 1e-9 m/s (0.2 µm over 180 s)
    until velocities exceed 1 cm/s. The porosity test (absolute) is unchanged.
    """

    def __init__(self, *args, surcharge: float = 0.0, velocity_floor: float = 1e-2, **kw):
        kw.setdefault("solids_flux", "galerkin")
        super().__init__(*args, **kw)
        self.surcharge, self.velocity_floor = float(surcharge), float(velocity_floor)

    def assemble(self, k, old, dt, t_new):
        S = super().assemble(k, old, dt, t_new)
        if self.surcharge:
            S.add_rhs("V", np.array([self.vert_node[-1]]),
                      np.array([-self.surcharge * self.vert_area[-1]]))
        return S


@dataclass
class ColumnState:
    """Vertical state (V, W, P, n, n̄), horizontal motion and shear history."""

    vertical: State
    wave: WaveState
    shear: ShearState | np.ndarray  # the thesis laws' history, or the hysteretic law's state array

    @property
    def t(self) -> float:
        return self.vertical.t


@dataclass(frozen=True, init=False)
class ColumnStep:
    state: ColumnState
    dt: float  # vertical step [s]
    substeps: int  # shear sub-steps in it
    iterations: int  # Picard iterations of the vertical step (last sub-step)
    solids_inflow: float  # solids volume that entered through the ends during the step [m³]
    surface: tuple  # (t [s], absolute surface acceleration [m/s²]) after each shear sub-step (default ())

    def __init__(self, state: ColumnState, dt: float, substeps: int, iterations: int, solids_inflow: float,
                 surface: tuple = (), samples: tuple | None = None):
        """``samples``: where given, the (times, accelerations) lists that ``surface`` pairs up, made when
        first read (:attr:`samples`: the lists as they are, which a run's record keeps)."""
        # (a frozen dataclass's own __init__ sets each field through object.__setattr__: 1 µs more a step)
        d = self.__dict__
        d["state"] = state
        d["dt"] = dt
        d["substeps"] = substeps
        d["iterations"] = iterations
        d["solids_inflow"] = solids_inflow
        if samples is None:
            d["surface"] = surface
        else:
            d["_samples"] = samples

    def __getattr__(self, name):  # (only where the instance has no such attribute: ``surface`` not made yet)
        raw = self.__dict__.get("_samples") if name == "surface" else None
        if raw is None:
            raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")
        pairs = self.__dict__["surface"] = tuple(zip(*raw))
        return pairs

    @property
    def samples(self) -> tuple[list, list]:
        """(times [s], absolute surface accelerations [m/s²]) of :attr:`surface`, as two lists (not to be written)."""
        raw = self.__dict__.get("_samples")
        if raw is not None:
            return raw
        pairs = self.surface
        return (list(p[0] for p in pairs), list(p[1] for p in pairs))


class LiquefactionColumn:
    """The coupled column (module docstring).

    Parameters
    ----------
    vertical : VerticalColumn — bottom must be a wall, top an outlet.
    sand : Sand
    base_acceleration : callable t [s] -> a_g [m/s²] (0 outside the record), or None: the base
        acceleration on a rigid base, the outcrop acceleration on a compliant one.
    shaking_end : time [s] when the record ends.
    shear_step : shear sub-step [s].
    damping_ratio, damping_frequencies : Rayleigh damping of the shear wave.
    free_vibration : seconds of shear wave after ``shaking_end`` (on a slope with ``flow``: at least).
    flow : :class:`FlowStop` — a sloping column's shear wave runs on while it flows (None: stop at
        ``free_vibration``; ignored on level ground).
    settings : Picard settings of the vertical steps.
    base_impedance : None (rigid base) or c = ρ_r V_r [Pa·s/m] of a compliant base
        (:class:`~twofluid.models.shear_column.ShearColumn`); the vertical model's base stays
        an impervious wall either way.
    fast_shear : the shear sub-steps by the compiled kernel (:mod:`~twofluid.models.shear_kernel`)
        where numba is installed and the case is one it covers; False: always the reference path.
    base_acceleration_at : the same motion as ``base_acceleration`` at an array of times [s] (e.g.
        ``np.interp`` of the record), so that the compiled path reads one vertical step's sub-steps
        in one call; None: ``base_acceleration`` time by time.
    """

    def __init__(self, vertical: VerticalColumn, sand: Sand = Sand(),
                 base_acceleration: Callable[[float], float] | None = None,
                 shaking_end: float = 0.0, shear_step: float = 0.005,
                 damping_ratio: float = 0.05, damping_frequencies=(1.0, 10.0),
                 free_vibration: float = 5.0, settings: PicardSettings = PicardSettings(),
                 base_impedance: float | None = None, crust: Crust | None = None,
                 fast_shear: bool = True, base_acceleration_at: Callable | None = None,
                 hysteretic: np.ndarray | None = None, numerical_damping: float = 0.0,
                 slope_percent: float = 0.0, flow: FlowStop | None = None, submerged: bool = False):
        if vertical.bottom.kind != "wall" or vertical.top.kind != "outlet":
            raise ValueError("the liquefaction column needs a wall at the bottom and an outlet at the top")
        self.v, self.sand, self.crust = vertical, sand, crust
        self.a_g = base_acceleration or (lambda t: 0.0)
        self.shaking_end = shaking_end if base_acceleration is not None else 0.0
        self.shear_end = self.shaking_end + (free_vibration if self.shaking_end > 0.0 else 0.0)
        self.shear_step, self.settings = shear_step, settings
        self.law = sand.n_bar_law()
        mat, mesh = vertical.mat, vertical.mesh
        ns = mesh.n_elements
        self.n_sat = ns
        y = mesh.y if crust is None else np.concatenate([mesh.y, mesh.y[-1] + np.cumsum(crust.h)])
        nt = y.size - 1
        self.y_all = y
        rho = np.full(nt, mat.rho_s)
        gamma_ref = np.broadcast_to(np.asarray(sand.gamma_ref, dtype=float), (ns,))
        reduction = sand.reduction
        if crust is not None:
            rho[ns:] = crust.rho
            g_crust = np.broadcast_to(np.asarray(crust.gamma_ref, dtype=float), (nt - ns,))
            if reduction is not None or crust.reduction is not None:
                reduction = piecewise_reduction(
                    [(slice(0, ns), reduction or _hyperbola(gamma_ref)),
                     (slice(ns, nt), crust.reduction or _hyperbola(g_crust))], nt)
            gamma_ref = np.concatenate([gamma_ref, g_crust])
        self.wave = ShearColumn(y, rho=rho, gamma_ref=gamma_ref, reduction=reduction,
                                damping_ratio=damping_ratio, damping_frequencies=damping_frequencies,
                                base_impedance=base_impedance)
        self.ground_surface = float(y[-1])
        self.depth = self.ground_surface - mesh.centres  # saturated element centres below the ground surface [m]
        self.depth_all = self.ground_surface - 0.5 * (y[1:] + y[:-1])  # every element of the shear column [m]
        self.p_hydro = vertical.top.pressure - mat.rho_f * vertical.g_y * (mesh.y[-1] - mesh.centres)
        self.sigma_v0 = None  # set by initial_state
        self.n0 = None
        self.a_g_at = base_acceleration_at if base_acceleration is not None else None
        # η_s of a Newtonian liquefied soil is fixed: computed once (None: the power law, per sub-step)
        self._eta_s = (None if np.any(np.asarray(sand.viscosity_exponent) != 1.0)
                       else sand.shear_viscosity(np.zeros(ns)))
        self._kernel = self._kernel_arguments() if fast_shear and hysteretic is None else None
        # the hysteretic law's (n_all, NPARAM) parameters, saturated elements first (None: thesis laws)
        # a copy: the column writes its static shear into it (P_TAUS)
        self.hysteretic = None if hysteretic is None else np.array(hysteretic, dtype=float, order="C")
        if self.hysteretic is not None and self.hysteretic.shape[0] != nt:
            raise ValueError(f"hysteretic parameters for {self.hysteretic.shape[0]} elements, the column has {nt}")
        self._ndot = np.zeros(ns)  # dn/dt of the last vertical step (the sub-steps' interpolation)
        self._dn = None  # (_ndot, a step's span, _ndot × span) made by the compiled split step (:func:`.column_split.split_step`)
        self._shear_next = None  # (a law state, its copy) made by the compiled split step, for the next sub-steps
        self._props = None  # (n, ρ, η): the wave properties at porosity n set by the compiled split step
        self._ps = None  # (vertical state, its σ′_v) made by the compiled split step
        # the record at the hysteretic sub-steps' times, read for many steps at once (None: step by step)
        self._rows = None
        self._h = shear_step  # the vertical step being made [s] (the next ones' likely step)
        self._a_last = (None, 0.0)  # (t, the record at t) of the last sub-step
        gam = 0.5 + float(numerical_damping)  # Newmark (β, γ) of the hysteretic sub-steps
        self.newmark = ((gam + 0.5) ** 2 / 4.0, gam)
        #: skip the vertical model (a total-stress run: no layer generates pore pressure, so the
        #: column stays in its geostatic state; :func:`twofluid.runners.liquefaction.total_stress_surface`)
        self.shear_only = False
        #: infinite slope (module docstring, "Infinite slope"): the downslope body force g sin α [m/s²]
        self.slope_percent = float(slope_percent)
        self.body = vertical.mat.g * math.sin(math.atan(self.slope_percent / 100.0))
        #: the density the saturated elements' driving weight leaves out [kg/m³]: ρ_f on a submerged
        #: slope (the buoyant weight drives), 0 with slope-parallel seepage (the total weight)
        self.rho_b = float(vertical.mat.rho_f) if submerged else 0.0
        if submerged and crust is not None:
            raise ValueError("a submerged slope has its water table at or above the ground surface: no crust")
        if self.body != 0.0 and self.hysteretic is None:
            raise ValueError("a sloping column needs the hysteretic shear law")
        self.u_static = np.zeros(nt + 1)  # the static displacement profile the run starts from [m]
        #: post-shaking flow on a slope (module docstring, "Flow after the shaking"): the shear wave runs
        #: at least to ``shear_end_min`` and on while the column still flows, at most to ``flow_end_max``
        self.shear_end_min = self.shear_end
        self.flow = flow if (flow is not None and flow.velocity > 0.0 and self.body != 0.0
                             and self.shaking_end > 0.0) else None
        self.flow_end_max = self.shear_end if self.flow is None else \
            self.shaking_end + max(free_vibration, self.flow.max_after)
        self.flow_velocity_end = None  # the window-mean surface velocity when the shear wave stopped [m/s]
        self.flow_stopped = None  # True: stopped by the criterion; False: at flow_end_max, still flowing
        self._flow_t, self._flow_d = [0.0], [0.0]  # (t, surface displacement) after each shear step

    # ------------------------------------------------------------ state
    def initial_state(self, porosity, excess_ratio: float = 0.0) -> ColumnState:
        """Geostatic state at rest (docs/model.md, "Liquefaction column").

        σ′_v0 is the discrete buoyant weight above each element (plus the surcharge);
        n̄ follows from P_s = (1 − r_u0) σ′_v0, i.e. n̄ = 1 − (1 − n)(1 − A ln(P_s/p_ref)),
        and P = P_hydrostatic + r_u0 σ′_v0 (the undrained, drag-dominated response to
        the drop of P_s; r_u0 > 0 imposes an excess pore pressure). With r_u0 = 0 the
        state is a discrete equilibrium of the vertical model.
        """
        v = self.v
        ne = v.mesh.n_elements
        n = np.broadcast_to(np.asarray(porosity, dtype=float), (ne,)).copy()
        sig0 = v.settled_solids_pressure(n) + v.surcharge
        n_bar = reference_porosity_for(n, (1.0 - excess_ratio) * sig0, v.clo.A, v.clo.p_ref)
        P = self.p_hydro + excess_ratio * sig0
        s = State(0.0, np.zeros(v.nv), np.zeros(v.nv), P, n, n_bar)
        self.sigma_v0, self.n0 = sig0, n.copy()
        if self.hysteretic is not None:
            st = _hyst_law.new_state(self.hysteretic.shape[0], self.hysteretic)
            if self.body == 0.0:
                return ColumnState(s, self.wave.rest(), st)
            return ColumnState(s, self._static_wave(n, self.v.solids_pressure(n, n_bar), st), st)
        return ColumnState(s, self.wave.rest(), ShearState.zeros(ne))

    def static_shear(self, n) -> np.ndarray:
        """Static shear stress of every shear-column element on a slope [Pa] (0 on level ground):
        τ_s = g sin α (Σ_above ρ h + ρ_e h_e/2), the downslope weight of the column above the
        element's centre with the mixture density ρ̄(n) of the saturated elements and the crust's
        — the total weight: the water table parallel to the ground surface with slope-parallel
        seepage; on a submerged slope ρ̄ − ρ_f, the buoyant weight (module docstring, "Infinite
        slope"). It is the discrete static equilibrium of the shear sub-steps (consistent mass and
        load: each node carries half of each element next to it)."""
        rho = np.array(self.wave.rho, dtype=float)
        rho[:self.n_sat] = self.mixture_density(np.asarray(n, dtype=float)) - self.rho_b
        w = rho * self.wave.h
        above = np.cumsum(w[::-1])[::-1] - w
        return self.body * (above + 0.5 * w)

    def _static_wave(self, n, ps, st) -> WaveState:
        """The static state on a slope: each element loaded monotonically on its backbone to its
        static shear (:func:`twofluid.closures.hysteretic.static_state`, ``st`` updated), the
        displacement the sum of the static strains from the base; ValueError naming the first
        element whose strength cannot carry it."""
        tau = self.static_shear(n)
        ne = tau.size
        gam = np.zeros(ne)
        for e in range(ne):
            p = float(ps[e]) if e < self.n_sat else 0.0
            gam[e] = _hyst_law.static_state(st, self.hysteretic, e, float(tau[e]), p)
            self.hysteretic[e, _hyst_law.P_TAUS] = tau[e]  # the law's flow-liquefaction rule reads it
            if not np.isfinite(gam[e]):
                s_e = _hyst_law.strength_modulus(p, self.hysteretic, e)[0]
                raise ValueError(f"element {e} (depth {self.depth_all[e]:.3g} m): the static shear "
                                 f"{tau[e]:.4g} Pa is at or above its strength {s_e:.4g} Pa (static FS "
                                 f"{s_e / tau[e]:.3f} <= 1)")
        u = np.concatenate([[0.0], np.cumsum(gam * self.wave.h)])
        self.u_static = u.copy()
        return WaveState(0.0, u, np.zeros(ne + 1), np.zeros(ne + 1), gam, tau)

    def lateral_displacement(self, s: ColumnState) -> np.ndarray:
        """Downslope displacement of every node of the shear column relative to the base, from the
        static state the run started at [m] (never baseline-corrected): u − u_base − (u_s − u_s,base)."""
        u = s.wave.u
        return (u - u[0]) - (self.u_static - self.u_static[0])

    # ------------------------------------------------------- diagnostics
    def granular_pressure(self, s: ColumnState) -> np.ndarray:
        """P_s = σ′_v per element [Pa]."""
        done = self._ps  # (the compiled split step's, for the state it made)
        if done is not None and done[0] is s.vertical:
            return done[1]
        return self.v.solids_pressure(s.vertical.n, s.vertical.n_bar)

    def excess_pressure(self, s: ColumnState) -> np.ndarray:
        """P − P_hydrostatic per element [Pa]."""
        return s.vertical.P - self.p_hydro

    def excess_ratio(self, s: ColumnState) -> np.ndarray:
        """r_u = (P − P_hydrostatic)/σ′_v0 per element [-]."""
        return self.excess_pressure(s) / self.sigma_v0

    def settlement(self, s: ColumnState) -> float:
        """Surface settlement [m] (positive down): Σ h (n0 − n)/(1 − n)."""
        return float(np.sum(self.settlement_contributions(s)))

    def settlement_contributions(self, s: ColumnState) -> np.ndarray:
        """Compression h (n0 − n)/(1 − n) of each saturated element [m] (the crust is rigid)."""
        n = s.vertical.n
        return self.v.mesh.lengths * (self.n0 - n) / (1.0 - n)

    def surface_seepage(self, s: ColumnState) -> float:
        """Upward Darcy flux of the liquid relative to the grains at the water table,
        n (U_f − U_s) [m/s], from the top node's V, W and the top element's n."""
        v = s.vertical
        n = v.n[-1]
        V, W = v.V[-1], v.W[-1]
        return float(0.5 * (V + W) - n * 0.5 * (V - W) / (1.0 - n))

    def surface_acceleration(self, s: ColumnState) -> float:
        """Absolute horizontal acceleration of the ground surface [m/s²] while the shear wave runs
        (else 0): the reference motion (record) plus the surface's acceleration relative to it."""
        return self.accelerations(s)[1]

    def accelerations(self, s: ColumnState) -> tuple[float, float]:
        """(:meth:`base_acceleration`, :meth:`surface_acceleration`) [m/s²], the record read once."""
        t, last = s.t, self._a_last
        a_in = (last[1] if last[0] == t else self.a_g(t)) if t <= self.shaking_end else 0.0
        running = s.t <= self.shear_end + 1e-12
        surface = a_in + float(s.wave.a[-1]) if running else 0.0
        if self.wave.base_impedance is None:
            return a_in, surface
        return (a_in + float(s.wave.a[0]) if running else 0.0), surface

    def shear_strain(self, s: ColumnState) -> np.ndarray:
        """Shear strain γ of every element of the shear column (crust included) [-]."""
        return s.wave.gamma

    def surface_displacement(self, s: ColumnState) -> float:
        """Horizontal (on a slope: downslope) displacement of the surface relative to the base [m],
        from the static state the run started at (:meth:`lateral_displacement`; level ground: 0)."""
        u0 = self.u_static
        kept = self.__dict__.get("_u_static_span")  # (the static part, kept while it is the same array)
        if kept is None or kept[0] is not u0:
            kept = self._u_static_span = (u0, float(u0[-1] - u0[0]))
        u = s.wave.u
        return float(u[-1] - u[0]) - kept[1]

    def base_acceleration(self, s: ColumnState) -> float:
        """Absolute horizontal acceleration of the base [m/s²] while the shear wave runs (else 0):
        the record on a rigid base; record (outcrop) + the base's relative acceleration on a
        compliant one."""
        return self.accelerations(s)[0]

    def mixture_density(self, n) -> np.ndarray:
        mat = self.v.mat
        return n * mat.rho_f + (1.0 - n) * mat.rho_s

    # ---------------------------------------------------------- stepping
    def _shear(self, s: ColumnState, t_new: float) -> tuple[WaveState, np.ndarray, ShearState, int, list]:
        """Shear sub-steps over [s.t, t_new]; returns wave, n̄, shear history, sub-steps and the
        (t, absolute surface acceleration) of each sub-step.

        The saturated elements (the first ``n_sat``) take G_max from P_s and densify under the
        law; the crust's G_max, density and (zero) liquefied-soil viscosity are fixed.
        """
        if self.hysteretic is not None:
            w, n_bar, hist, m, (times, acc) = self._shear_hysteretic(s, t_new)
            return w, n_bar, hist, m, tuple(zip(times, acc))
        v, wave, sand, ns = self.v, self.wave, self.sand, self.n_sat
        n = s.vertical.n
        mu_m = self._wave_properties(s)
        w, n_bar, hist = s.wave, s.vertical.n_bar, s.shear
        span = t_new - s.t
        m = max(1, math.ceil(span / self.shear_step - 1e-9))
        dt = span / m
        power = self._eta_s is None
        if not power and self._kernel is not None:  # Newtonian: η_s fixed
            fast = self._shear_compiled(s, w, n, n_bar, hist, m, dt)
            if fast is not None:
                return fast
        cap = sand.gamma_law_max
        g_crust = None if self.crust is None else self.crust.g_max
        surface = []
        for i in range(1, m + 1):
            t = s.t + i * dt
            g_max = seed_idriss_gmax(v.solids_pressure(n, n_bar), sand.k2max)
            if g_crust is not None:
                g_max = np.concatenate([g_max, g_crust])
            a_in = self.a_g(t)
            w = self._wave_step(w, dt, a_in, g_max)
            surface.append((t, (a_in if t <= self.shaking_end + 1e-12 else 0.0) + float(w.a[-1])))
            g_law = np.clip(w.gamma[:ns], -cap, cap)
            n_bar, hist = self.law(g_law - hist.gamma, g_law, n_bar, hist)
            if power:  # shear thinning: η_s from the rate of the last sub-step
                wave.eta[:ns] = mu_m + sand.shear_viscosity(np.diff(w.v[:ns + 1]) / wave.h[:ns])
        return w, n_bar, hist, m, surface

    def _wave_properties(self, s: ColumnState) -> np.ndarray:
        """Set the shear wave's density and viscosity of the saturated elements at the start of a
        step (η_s fixed, or from the strain rate at the start for a shear-thinning soil); returns
        the mixture viscosity μ_m [Pa·s]."""
        v, wave, sand, ns = self.v, self.wave, self.sand, self.n_sat
        n = s.vertical.n
        wave.rho[:ns] = self.mixture_density(n)
        laws = v.compiled_laws()
        mu_m = laws.mixture_viscosity(n) if laws is not None and not v.clo.viscosity_params \
            else mooney_pringle(n, v.mat.mu_f)
        if self._eta_s is None:
            wave.eta[:ns] = mu_m + sand.shear_viscosity(np.diff(s.wave.v[:ns + 1]) / wave.h[:ns])
        else:
            wave.eta[:ns] = mu_m + self._eta_s
        return mu_m

    def _record_at(self, times: np.ndarray) -> np.ndarray:
        """The base (or outcrop) acceleration at the sub-steps' ``times`` [s], as one array [m/s²]."""
        if self.a_g_at is None:
            return np.array([self.a_g(t) for t in times.tolist()], dtype=float)
        return np.ascontiguousarray(self.a_g_at(times), dtype=float)

    def _shear_hysteretic(self, s: ColumnState, t_new: float, strain: bool = True):
        """The sub-steps of :meth:`_shear` with the hysteretic law (:mod:`~twofluid.models.hysteretic_kernel`);
        a sub-step whose Newton iterations fail is retried at half the size (four times at most); returns as
        :meth:`_shear` does, but for the sub-steps' (times, absolute surface accelerations) as two lists.
        ``strain`` False: the new wave state's γ is an array left for the caller to write (the compiled split
        step writes it, :meth:`step`)."""
        vert = s.vertical
        n = vert.n
        fixed = self.__dict__.get("_hyst_fixed")
        if fixed is None:  # the kernel (or its plain Python), its fixed arguments, the saturated ρ and η: once per run
            wave, ns = self.wave, self.n_sat
            fixed = self._hyst_fixed = (_hyst_kernel.runner(), *self.hysteretic_arguments(), wave.rho[:ns],
                                        wave.eta[:ns], wave.h, {})
        run, mid, tail, rho_sat, eta_sat, h_wave, kept = fixed
        props = self._props
        if props is not None and props[0] is n:  # set by the compiled split step that made this state (its n
            rho_sat[...] = props[1]  # a C-contiguous float64 array)
            eta_sat[...] = props[2]
        else:
            n = np.ascontiguousarray(n, dtype=float)
            self._wave_properties(s)
        w = s.wave
        t0 = vert.t
        span = t_new - t0
        ndot, pred = self._ndot, self._dn  # (the split step's product for a step of this span, where it made it)
        dn = pred[2] if pred is not None and pred[0] is ndot and pred[1] == span else ndot * span
        m = max(1, math.ceil(span / (self.shear_step if self.flow is None else self._substep(t0)) - 1e-9))
        key, clo = self.__dict__.get("_skeleton_key"), self.v.clo  # (_skeleton_arrays's test, inline)
        A, p_ref = self._skeleton if key is not None and key[0] is clo.A and key[1] is clo.p_ref \
            else self._skeleton_arrays()
        shear, n_bar = s.shear, vert.n_bar
        copy_st = type(shear) is np.ndarray and shear.dtype is _F8  # (np.array(x, dtype=float) of others)
        copy_nb = type(n_bar) is np.ndarray and n_bar.dtype is _F8
        ready = self._shear_next  # (the split step's copy of this law state, where it made one)
        ready = ready[1] if ready is not None and ready[0] is shear else None
        self._shear_next = None
        for attempt in range(5):
            dt = span / m
            rows = self._rows
            if attempt == 0 and rows is not None and rows.at is self.a_g_at:  # (the record read for many steps at once)
                a_in = rows.rows(t0, m, dt, self._h)[1]
                times, end = rows.times, rows.end
            elif attempt == 0 and self.a_g_at is not None:
                self._rows = rows = _record_rows.RecordRows(self.a_g_at)
                a_in = rows.rows(t0, m, dt, self._h)[1]
                times, end = rows.times, rows.end
            else:
                times = t0 + np.arange(1.0, m + 1.0) * dt
                a_in = self._record_at(times)
                times, end = times.tolist(), float(a_in[-1])
            u, vel, acc = w.u.copy(), w.v.copy(), w.a.copy()
            st = ready if attempt == 0 and ready is not None else \
                shear.copy() if copy_st else np.array(shear, dtype=float)
            nb = n_bar.copy() if copy_nb else np.array(n_bar, dtype=float)
            surface = kept.get(m)  # (the surface's samples: written whole, read at once; one array for each m)
            if surface is None:
                surface = kept[m] = np.empty(m)
            tau = np.empty(h_wave.size)
            code = int(run(u, vel, acc, st, self.hysteretic, nb, n, dn, A, p_ref, *mid, t0, dt, a_in, self.shaking_end,
                           surface, tau, *tail))
            if code != 1:
                break
            m *= 2
        if code != 0:
            raise NewmarkFailure(f"shear step at t = {t_new:.6g} s: "
                                 + ("Newton did not converge" if code == 1 else "a non-finite value"))
        # (np.diff's arithmetic)
        out = WaveState(t_new, u, vel, acc, (u[1:] - u[:-1]) / h_wave if strain else np.empty(h_wave.size), tau)
        self._a_last = (times[-1], end)  # (the record at the step's end: :meth:`accelerations`)
        return out, nb, st, m, (times, surface.tolist())

    def hysteretic_arguments(self) -> tuple[tuple, tuple]:
        """The fixed arguments of the hysteretic sub-steps (:func:`twofluid.models.hysteretic_kernel._substeps`)
        that do not change over a run: those after ``p_ref`` up to ``t0`` (the wave's ρ, η and element
        lengths, which :meth:`_wave_properties` updates in place, the saturated count, the Rayleigh
        coefficients, the base, Newton's tolerance and iterations), and those after ``tau_out`` (Newmark's
        β and γ, the slope's body force and the density it leaves out, and ``quick`` 0: Newton's
        iterations to the tolerance, as the run takes them)."""
        wave = self.wave
        return ((wave.rho, wave.eta, wave.h, self.n_sat, wave.a0, wave.a1,
                 0.0 if wave.base_impedance is None else wave.base_impedance,
                 0 if wave.base_impedance is not None else 1, wave.tol, wave.max_iter),
                (self.newmark[0], self.newmark[1], float(self.body), float(self.rho_b), 0))

    def _skeleton_arrays(self) -> tuple[np.ndarray, np.ndarray]:
        """The skeleton law's A and p_ref per saturated element as the kernel takes them (contiguous
        float64), made again only when the closures hold another A or p_ref (the reconsolidation
        floor replaces them)."""
        clo, ns = self.v.clo, self.n_sat
        key = getattr(self, "_skeleton_key", None)
        if key is None or key[0] is not clo.A or key[1] is not clo.p_ref:
            full = lambda x: np.ascontiguousarray(np.broadcast_to(np.asarray(x, dtype=float), (ns,)))
            self._skeleton_key = (clo.A, clo.p_ref)
            self._skeleton = (full(clo.A), full(clo.p_ref))
        return self._skeleton

    def _flowing_phase(self, t: float) -> bool:
        """True once the shear wave runs past ``free_vibration`` because the column still flows."""
        return self.flow is not None and t >= self.shear_end_min - 1e-9 * max(1.0, t)

    def _substep(self, t: float) -> float:
        """The shear sub-step of a vertical step starting at ``t`` [s]: ``shear_step`` while the base
        shakes and during ``free_vibration``, then at most the flow step (:class:`FlowStop`)."""
        return max(self.shear_step, self.flow.step) if self._flowing_phase(t) else self.shear_step

    def flow_velocity(self, t: float) -> float | None:
        """The window-mean downslope velocity of the surface relative to the base at ``t`` [m/s]:
        (D̄(t − T, t) − D̄(t − 2T, t − T))/T, D̄ the time mean of the surface displacement over a window
        of T = ``flow.window`` seconds (linear between the steps). A ring-down oscillation of
        amplitude A and frequency f adds at most 2A/(π f T²) (each window mean moves by at most 2A/(2π f T)): the criterion sees the mean motion,
        not the oscillation. None until the history after the shaking spans 2T."""
        T = self.flow.window
        if t - 2.0 * T < self.shaking_end - 1e-9 * max(1.0, t):
            return None
        tt, dd = np.asarray(self._flow_t), np.asarray(self._flow_d)

        def mean(a, b):
            grid = np.concatenate([[a], tt[(tt > a) & (tt < b)], [b]])
            val = np.interp(grid, tt, dd)
            return float(np.sum(0.5 * (val[1:] + val[:-1]) * np.diff(grid))) / (b - a)

        return (mean(t - T, t) - mean(t - 2.0 * T, t - T)) / T

    def _flow_decide(self, t: float, wave: WaveState) -> None:
        """After a shear step ending at ``t``: record the surface displacement; from ``shear_end_min``
        on, keep the shear wave running while the column flows (:meth:`flow_velocity` ≥
        ``flow.velocity``), else stop it at ``t`` (``shear_end = t``)."""
        self._flow_t.append(t)
        self._flow_d.append(float(wave.u[-1] - wave.u[0]))
        keep = t - 2.0 * self.flow.window - 1.0  # trim the history to what the windows need
        if len(self._flow_t) > 4096 and self._flow_t[1024] < keep:
            del self._flow_t[:1024], self._flow_d[:1024]
        eps = 1e-9 * max(1.0, t)
        if t < self.shear_end_min - eps:
            return
        v = self.flow_velocity(t)
        self.flow_velocity_end = v
        moving = v is None or abs(v) >= self.flow.velocity
        if moving and t < self.flow_end_max - eps:
            self.shear_end = self.flow_end_max
        else:
            self.shear_end = t
            self.flow_stopped = not moving

    def reconsolidation_floor(self, s: ColumnState) -> np.ndarray:
        """The post-liquefaction volumetric strain floor of Ishihara & Yoshimine (1992), as fitted by
        Yoshimine et al. (2006), ε_v = 1.5 exp(−2.5 Dr) min(0.08, γ_max) per saturated element [-]
        (0 for elements that generate no pore pressure), with γ_max the larger of the element's own
        largest strain and the γ_max(FS, Dr) of Idriss & Boulanger (2008) at the factor of safety
        its cyclic loading implies, FS = D^−b (D its damage: the cycles it took over the cycles to
        liquefaction, b its CSR–N slope; docs/liquefaction.md says why)."""
        par, st, ns = self.hysteretic, s.shear, self.n_sat
        dr = par[:ns, _hyst_law.P_DR]
        damage = st[:ns, _hyst_law.S_D] + st[:ns, _hyst_law.S_DPART]
        fs = np.where(damage > 0.0, np.maximum(damage, 1e-300) ** -par[:ns, _hyst_law.P_B], np.inf)
        gamma = np.maximum(st[:ns, _hyst_law.S_GM], max_shear_strain(fs, dr))
        eps = 1.5 * np.exp(-2.5 * dr) * np.minimum(0.08, gamma)
        return np.where(par[:ns, _hyst_law.P_LIQ] > 0.0, eps, 0.0)

    def _apply_floor(self, s: ColumnState, n_bar: np.ndarray, st: np.ndarray) -> np.ndarray:
        """The reconsolidation floor, applied when the shear wave stops (a floor, not an addition).

        Each element will settle by the strain its drainage has made so far, ln((1 − n)/(1 − n0)),
        plus what its skeleton makes as P_s recovers from its present value P_end to σ′_v0, about
        A ln(σ′_v0/P_end). Where that total is below the floor, the skeleton's compressibility for
        that reloading is raised to A′ = (floor − drained)/ln(σ′_v0/P_end), with n̄ remapped so that
        P_s does not change: the strain then comes out of the two-fluid drainage as the excess pore
        pressure dissipates (it takes longer, as a softer skeleton must), without a jump of r_u. A′ is
        at most what keeps 1 − A′ ln(σ′_v0/p_ref) ≥ 1/2 (a positive skeleton law). An element that has
        already drained (r_u ≤ 0.05: no pore pressure left to drain), and what the capped A′ cannot
        make, take the rest as a drop of n̄, the only way left. ``st`` records the strain added;
        returns n̄."""
        ns, v = self.n_sat, self.v
        n = s.vertical.n
        floor = self.reconsolidation_floor(ColumnState(s.vertical, s.wave, st))
        drained = np.log((1.0 - n) / (1.0 - self.n0))
        p_end = np.maximum(v.solids_pressure(n, n_bar), 1e-300)
        A = np.array(np.broadcast_to(np.asarray(v.clo.A, dtype=float), (ns,)))
        p_ref = np.broadcast_to(np.asarray(v.clo.p_ref, dtype=float), (ns,))
        span = np.log(np.maximum(self.sigma_v0 / p_end, 1.0))
        need = floor - drained
        soft = (need > A * span) & (span > -np.log(0.95))  # r_u > 0.05 left: a softer reloading
        # A′ at most what keeps the law's 1 − A′ ln(P_s/p_ref) ≥ 1/2 at σ′_v0 (a positive skeleton)
        a_cap = 0.5 / np.log(np.maximum(self.sigma_v0 / p_ref, np.e))
        a_new = np.where(soft, np.minimum(need / np.where(soft, span, 1.0), np.maximum(a_cap, A)), A)
        nb = np.array(n_bar, dtype=float)
        # P_s(n, n̄′, A′) = P_s(n, n̄, A): 1 − n̄′ = (1 − n)(1 − A′ ln(P_end/p_ref))
        nb = np.where(soft, 1.0 - (1.0 - n) * (1.0 - a_new * np.log(p_end / p_ref)), nb)
        rest = np.maximum(need - a_new * span, 0.0)  # what the reloading cannot make: a drop of n̄
        nb = nb - (1.0 - nb) * np.expm1(rest)
        st[:ns, _hyst_law.S_EPS] += np.maximum(need - A * span, 0.0)
        if np.any(soft):
            from dataclasses import replace

            v.clo = replace(v.clo, A=a_new)
        return nb

    def _kernel_arguments(self):
        """The fixed arguments of the compiled shear kernel, or None where the case needs the
        reference path (module :mod:`~twofluid.models.shear_kernel`)."""
        sand, v, wave, ns = self.sand, self.v, self.wave, self.n_sat
        p = dict(sand.law_params)
        if (sand.law != "byrne" or sand.law_groups or sand.reduction is not None or set(p) - {"c1", "c2", "dr"}
                or (self.crust is not None and self.crust.reduction is not None)
                or getattr(wave, "gamma_ref", None) is None or v.clo.fluidized_pressure is not None
                or not _shear_kernel.available()):
            return None
        full = lambda x, k=ns: np.ascontiguousarray(np.broadcast_to(np.asarray(x, dtype=float), (k,)))
        c1 = full(p["c1"] if "c1" in p else sand.byrne_c1())
        c2 = full(p["c2"]) if "c2" in p else 0.4 / c1
        ne = wave.h.size
        g_crust = np.zeros(0) if self.crust is None else full(self.crust.g_max, ne - ns)
        return dict(run=_shear_kernel.compiled(), A=full(v.clo.A), p_ref=full(v.clo.p_ref), k2max=full(sand.k2max), g_crust=g_crust,
                    gamma_ref=full(wave.gamma_ref, ne), c1=c1, c2=c2,
                    liq=full(np.asarray(sand.liquefiable, dtype=float)), cap=full(sand.gamma_law_max),
                    first=0 if wave.base_impedance is not None else 1,
                    impedance=0.0 if wave.base_impedance is None else wave.base_impedance)

    def _shear_compiled(self, s, w, n, n_bar, hist, m, dt):
        """The sub-steps of :meth:`_shear` by the compiled kernel; None if it hands back (the caller
        then takes the reference path from the same start)."""
        k, wave = self._kernel, self.wave
        times = s.t + np.arange(1.0, m + 1.0) * dt  # as the reference path's s.t + i dt
        a_in = self._record_at(times)
        u, vel, acc, gam, tau = w.u.copy(), w.v.copy(), w.a.copy(), w.gamma.copy(), w.tau.copy()
        nb = np.array(n_bar, dtype=float)
        eps_v, g_a, g_h, dirn, path = (np.array(x, dtype=float) for x in
                                       (hist.eps_v, hist.gamma_a, hist.gamma, hist.direction, hist.path))
        surface = np.empty(m)
        code = k["run"](
            u, vel, acc, gam, tau, nb, eps_v, g_a, g_h, dirn, path, np.ascontiguousarray(n, dtype=float),
            k["A"], k["p_ref"], k["k2max"], k["g_crust"], wave.rho, wave.eta, wave.h, k["gamma_ref"], k["c1"],
            k["c2"], k["liq"], k["cap"], wave.a0, wave.a1, k["impedance"], k["first"], wave.tol, wave.max_iter,
            s.t, dt, a_in, self.shaking_end, surface)
        if code != 0:
            return None
        t_w = w.t
        for _ in range(m):  # the wave's clock, summed as the reference path sums it
            t_w = t_w + dt
        out = WaveState(t_w, u, vel, acc, gam, tau)
        return out, nb, ShearState(eps_v, g_a, g_h, dirn, path), m, list(zip(times.tolist(), surface.tolist()))

    def _wave_step(self, w, h, a_g, g_max, depth=0):
        if not (np.all(np.isfinite(g_max)) and np.isfinite(a_g)):  # halving cannot help
            return self.wave.step(w, h, a_g, g_max)  # raises NewmarkFailure naming the value
        try:
            return self.wave.step(w, h, a_g, g_max)
        except NewmarkFailure:
            if depth >= 4:
                raise
            a_mid = 0.5 * (a_g + self.a_g(w.t))  # linear base motion over the halves
            w = self._wave_step(w, 0.5 * h, a_mid, g_max, depth + 1)
            return self._wave_step(w, 0.5 * h, a_g, g_max, depth + 1)

    def step(self, s: ColumnState, dt: float) -> ColumnStep:
        """One split step of length ``dt`` [s] (module docstring); raises StepFailure."""
        v0 = s.vertical
        t0 = v0.t
        t_new = t0 + dt
        wave, n_bar, hist, m, surface, samples = s.wave, v0.n_bar, s.shear, 0, (), None
        hyst = self.hysteretic is not None
        # the vertical step and what follows it in one compiled call (:meth:`_split_step`) where it covers it
        fixed = self._split_args() if hyst and dt > 0.0 and not self.shear_only else None
        fused = fixed is not None
        check = False  # the finite test of the shear's results left to that call
        eps = 1e-9 * max(dt, 1e-12)  # (integrate's)
        fast = getattr(self.v, "fast_step", None)
        flow, end = self.flow, self.shear_end - 1e-12  # (the shear wave's end: only _flow_decide moves it)
        sheared = t0 < end
        defer = False  # the shear's γ left to the split step (tried below with the check)
        if sheared:
            self._h = dt
            defer = (fused and flow is None and not end <= t_new and type(v0) is State and fast is not None
                     and t0 < t_new - eps)
            try:
                if hyst:  # (the surface's samples as two lists: ColumnStep pairs them up where asked)
                    wave, n_bar, hist, m, samples = self._shear_hysteretic(s, t_new, not defer)
                else:
                    wave, n_bar, hist, m, surface = self._shear(s, t_new)
            except NewmarkFailure as exc:
                raise StepFailure(t0, dt, str(exc), s) from None
            # (not where the shear wave stops: the floor comes first; a flowing slope decides first)
            check = fused and flow is None and not end <= t_new
            if not check and not (np.isfinite(n_bar).all() and np.isfinite(wave.u).all()):
                raise self._not_finite(t0, dt, s)
            if flow is not None and not self.shear_only:
                if self._flowing_phase(t0):
                    surface, samples = (), None  # the surface motion (spectra, a_max) covers the shaking and free_vibration
                self._flow_decide(t_new, wave)
                end = self.shear_end - 1e-12
        floor = hyst and t0 < end <= t_new  # the shear wave stops
        if floor:
            n_bar = self._apply_floor(s, n_bar, hist)  # the reconsolidation floor
            fused = False
        if self.shear_only:  # a total-stress companion run: no pore pressure, nothing moves vertically
            vert = s.vertical.copy(t=t_new)
            return ColumnStep(ColumnState(vert, wave, hist), dt, m, 0, 0.0, tuple(surface), samples)
        its, inflow, made, split, joint = 0, 0.0, None, False, None
        h = min(dt, t_new - t0)  # the stepper's first try in one compiled call: integrate's first step to t_new
        h = t_new - t0 if t_new - t0 - h < 0.01 * dt else h
        tried = fused and sheared and type(v0) is State and fast is not None and t0 < t_new - eps
        if tried:  # n̄ the shear's own new array: the split step starts from v0 with it (no copy of v0 made)
            # (deferred: the hysteretic sub-steps' own law state, a C-contiguous float64 array, copied for the next)
            joint = self._split_step(v0, h, dt, wave.u, check, fixed, n_bar, wave.gamma if defer else None,
                                     hist if defer else None)
            if joint is None and defer:  # (the call did not make the step: γ as the shear gives it)
                u = wave.u
                wave.gamma = (u[1:] - u[:-1]) / self.wave.h
        if joint is None:
            # the stepper and the compiled step read the old arrays and write new ones: no copy needed
            vert = State(v0.t, v0.V, v0.W, v0.P, v0.n, n_bar) if type(v0) is State else v0.copy(n_bar=n_bar)
            if hasattr(self.v, "continue_from"):  # the reduced model's extrapolation history goes on
                self.v.continue_from(v0, vert)
            if not tried and fast is not None and vert.t < t_new - eps:
                if fused:
                    joint = self._split_step(vert, h, dt, wave.u, check, fixed)
                else:
                    made = fast(vert, h, self.settings)
                    if made is not None:
                        vert, its = made
                        inflow -= h * self.v.solids_outflow(vert)
        if joint is not None:  # (the split step's call made it: the vertical step and what follows it)
            made = joint
            vert, its, outflow = joint
            inflow -= h * outflow
            split = True
        if check and made is None and not (np.isfinite(n_bar).all() and np.isfinite(wave.u).all()):
            raise self._not_finite(t0, dt, s)
        if made is None or vert.t < t_new - eps:  # the stepper (all of the step, or the rest)
            split = False
            for st in integrate(self.v, vert, t_new, dt, settings=self.settings):  # (each try in one
                vert, its = st.state, st.iterations  # compiled call where it can be: the model's compiled_step)
                inflow -= st.dt * self.v.solids_outflow(vert)  # backward Euler: end-of-step flux
        if hyst and dt > 0.0 and not split:
            self._ndot = (vert.n - v0.n) / dt
            self._props = None
        return ColumnStep(ColumnState(vert, wave, hist), dt, m, its, inflow, tuple(surface), samples)

    @staticmethod
    def _not_finite(t0: float, dt: float, s: ColumnState) -> StepFailure:
        return StepFailure(t0, dt, "shear sub-steps gave a non-finite reference porosity or displacement", s)

    def _split_args(self):
        """The fixed arguments of the compiled split step, or None (:func:`.column_split.split_args`)."""
        hit = self.__dict__.get("_split")  # (split_args's own test of what it kept, here: once a step)
        if hit is not None and hit[0] is self.v.clo:
            return hit[1]
        return _split.split_args(self)

    #: the vertical step of ``h`` [s] from ``vert`` and what follows it in one compiled call, or None:
    #: :func:`.column_split.split_step` with the column as its first argument (a method, one call less a step)
    _split_step = _split.split_step

    def run(self, s: ColumnState, t_end: float, dt: float, dt_after: float | None = None,
            stops=(), stop: Callable[[ColumnState], bool] | None = None) -> Iterator[ColumnStep]:
        """Advance to ``t_end`` with step ``dt`` while the shear wave runs, then growing
        (×1.5 per step) to ``dt_after``; lands exactly on ``shear_end`` and ``stops``.

        ``stop(state)``, checked after every step once the shear wave has stopped, ends the run
        early (e.g. once the excess pore pressure has dissipated)."""
        dt_after = dt_after or dt
        fixed = sorted({x for x in (*stops, self.shaking_end, t_end) if s.t < x <= t_end})
        h = dt
        eps = 1e-9 * max(dt, 1e-12)
        flow_h = dt if self.flow is None else max(dt, self.flow.step)
        t = s.t
        k = 0  # fixed[k]: the first fixed mark after t (t only grows)
        while t < t_end - eps:
            # the next time to land on: the fixed marks and the shear wave's end, which a sloping column
            # that still flows moves on (:meth:`_flow_decide`)
            end = self.shear_end
            while not fixed[k] > t + eps:  # (t_end is one, after t)
                k += 1
            mark = fixed[k]
            if t + eps < end <= t_end and end < mark:
                mark = end
            if t < end - eps:  # the shear wave runs: the shaking step, growing while the column flows
                target = min(flow_h, 1.5 * h) if self.flow is not None and self._flowing_phase(t) else dt
            else:
                target = min(dt_after, 1.5 * h)
            h = target
            h_try = min(h, mark - t)
            if mark - t - h_try < 0.01 * dt:
                h_try = mark - t
            step = self.step(s, h_try)
            s = step.state
            yield step
            t = s.t
            if stop is not None and t >= self.shear_end - eps and stop(s):
                return
        if self.flow is not None and self.flow_stopped is None and self.shear_end > s.t + eps:
            self.shear_end = s.t  # a sloping column still shearing at t_end: its shear wave ends with the run
