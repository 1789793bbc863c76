"""Run a ``liquefaction_1d`` case: build the layered column, shake it, let it reconsolidate until
the excess pore pressure has dissipated (or the end time), write results.

``run_liquefaction`` runs a case from the API; ``twofluid run`` calls ``run_validated`` for this
model (through :data:`twofluid.runners.common.RUNNERS`, which has validated the case);
``simplified_table`` is what ``twofluid simplified``
prints. The run folder holds (depths below the ground surface; columns in docs/outputs.md)

- ``case.resolved.toml`` — every key with the value used;
- ``probes.csv`` — time series: base and surface acceleration (absolute), surface settlement,
  base pore pressure, surface displacement relative to the base, seepage at the water table,
  and r_u and σ′_v at the ``[report] depths``;
- ``layers.csv``, ``elements.csv`` — per layer and per element of the column (crust included):
  peak r_u, first liquefaction, peak shear strain, settlement contribution, the simplified
  procedure's FS;
- ``surface_motion.csv``, ``spectra.csv`` — surface acceleration per shear sub-step, response
  spectra of input and surface and their ratio;
- ``ru_field.csv`` — r_u of every saturated element against time (the depth–time map);
- ``profiles.csv`` — element profiles at t = 0, the ``[output] times``, the end of
  the shaking and the end of the run;
- ``summary.json`` — per layer and per element results, liquefied depth range, surface and
  sand boil, settlement, dissipation (fraction of the final settlement), the simplified
  procedure, spectra, solids balance, wall time, status (completed / interrupted / failed,
  with ``stopped_at_s`` and the reason);
- ``profile.png``, ``ru_map.png``, ``spectra.png``, ``ru_histories.png``, ``settlement.png``; on a
  slope also ``lateral_displacement.png`` and ``surface_displacement.png`` (:mod:`twofluid.plots.slope`).

Inputs are checked before the folder is created: the case (again, if it is a dictionary
that may have been edited since loading) with the record, the ANN weights and the G/G_max
tables it names, read and validated (:mod:`twofluid.casefile.schema_liquefaction`); a bad one
is a CaseError and nothing is written. Once running, the per-step CSV rows are written in blocks
(at most a second old) and flushed on every way out of the time loop, so Ctrl-C, SIGTERM or a
failed step (including a non-finite shear step) leaves readable files with every row computed,
and ``summary.json`` is written whatever the outcome.
"""
from __future__ import annotations

import bisect
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..casefile import schema_liquefaction
from ..casefile.loader import load_case
from ..casefile.schema import CaseError, revalidate
from ..closures import drag as drag_laws
from ..closures.shear_modulus import seed_idriss_gmax
from ..geotech import filtering
from ..io import ground_motion as gm
from ..io.folders import default_out_dir
from ..io.results import (CsvStream, NonFiniteOutput, ResultWriter, check_finite, write_json,
                          write_resolved_case)
from ..models.liquefaction_1d import ColumnState, FlowStop, LiquefactionColumn, VerticalColumn
from ..models import record_kernel
from ..models.reduced_column import ReducedVerticalColumn
from ..models.two_fluid_1d import Boundary
from ..timestepping.backward_euler import PicardSettings, StepFailure
from . import liquefaction_report as report
from . import liquefaction_total_stress as total_stress
from .liquefaction_damage import DamageRecord
from .liquefaction_site import Site, crust_for, hysteretic_parameters, sand_for, site_arrays

__all__ = ["Built", "build_column", "run_liquefaction", "run_validated", "simplified_table", "PROFILE_COLUMNS"]

PROFILE_COLUMNS = ["depth_m", "y_m", "porosity", "reference_porosity", "P_Pa", "excess_P_Pa",
                   "sigma_v_eff_Pa", "sigma_v0_Pa", "r_u", "peak_r_u", "shear_strain",
                   "shear_stress_Pa", "hydraulic_conductivity_m_s"]


@dataclass
class Built:
    column: LiquefactionColumn
    state: ColumnState
    motion: gm.GroundMotion | None  # scaled record actually applied (None: no shaking)
    t_end: float
    dt: float
    dt_after: float
    site: Site


def _source(case: dict) -> str:
    return case.get("_source", "") or "<case>"


def validated(case: dict) -> dict:
    """``case`` (a resolved dict, possibly edited since loading) checked again through the schema,
    including the files it names; CaseError otherwise. Nothing is written."""
    source = _source(case)
    return revalidate(case, source)


def build_column(case: dict, reference: bool = False) -> Built:
    """Column, geostatic initial state and stepping of a resolved ``liquefaction_1d`` case.

    Reads the record, the ANN weights and the G/G_max tables (CaseError if they cannot be used);
    writes nothing. The vertical model is the reduced (W, n) formulation of the same discrete
    equations (:mod:`twofluid.models.reduced_column`) and the shear sub-steps run as a compiled
    kernel where numba is installed (:mod:`twofluid.models.shear_kernel`); ``reference=True``
    takes the full V, W, P, n model and the NumPy shear path instead (the reference the fast
    paths are tested against).
    """
    sw, st = case["shear_wave"], case["site"]
    source = _source(case)
    site = site_arrays(case)
    tm = case["time"]
    settings = PicardSettings(tol=tm["picard_tol"], max_iter=tm["picard_max_iter"],
                              dt_min=min(1e-7, tm["step"] * 1e-4))
    model = VerticalColumn if reference else ReducedVerticalColumn
    slope = st["slope"]
    cos_a = float(np.cos(np.arctan(slope / 100.0))) if slope > 0.0 else 1.0
    vertical = model(site.mesh, site.mat, site.clo, Boundary("wall"),
                     Boundary("outlet", pressure=st["water_table_pressure"]),
                     surcharge=(st["surcharge"] + site.crust_weight) * cos_a)
    sigma_v0 = vertical.settled_solids_pressure(site.porosity) + vertical.surcharge
    sand = sand_for(case, source, site, sigma_v0)
    crust = crust_for(case, source, site)
    motion = schema_liquefaction.load_motion(case, source)
    accel = None if motion is None else (lambda t, m=motion: float(gm.value_at(m, t)))
    accel_at = None if motion is None else gm.interpolator(motion)
    if motion is not None and slope > 0.0:  # the record's component along the slope (the normal one, sin α of it, is left out)
        accel = (lambda t, m=motion: cos_a * float(gm.value_at(m, t)))
        accel_at = (lambda t, m=motion: cos_a * gm.value_at(m, t))
    column = LiquefactionColumn(vertical, sand, accel, shaking_end=0.0 if motion is None else motion.duration,
                                shear_step=sw["step"], damping_ratio=sw["damping_ratio"],
                                damping_frequencies=tuple(sw["damping_frequencies"]),
                                free_vibration=sw["free_vibration"], settings=settings,
                                base_impedance=schema_liquefaction.base_impedance(case),
                                crust=crust, fast_shear=not reference,
                                base_acceleration_at=accel_at,
                                hysteretic=hysteretic_parameters(case, site, sigma_v0, crust,
                                                                 np.broadcast_to(sand.k2max, sigma_v0.shape)),
                                numerical_damping=sw["numerical_damping"], slope_percent=slope,
                                submerged=st["groundwater"] == "submerged",
                                flow=FlowStop(sw["flow_velocity"], sw["flow_window"], sw["flow_max"],
                                              sw["flow_step"]))
    if slope > 0.0:
        state = _sloping_start(case, source, column, site)
    else:
        state = column.initial_state(site.porosity, st["initial_excess_ratio"])
    nb = state.vertical.n_bar
    if not (np.all(np.isfinite(nb)) and np.all((nb > 0.0) & (nb < 1.0))
            and np.all(np.isfinite(column.sigma_v0)) and np.all(column.sigma_v0 > 0.0)):
        bad = int(np.flatnonzero(~((nb > 0.0) & (nb < 1.0)) | ~(column.sigma_v0 > 0.0))[0])
        i = int(site.layer_of[bad])
        la = case["layers"][i]
        raise CaseError(source, f"{schema_liquefaction.layer_label(case, i)} compressibility",
                        f"{la['compressibility']:g} with p_ref = {la['p_ref']:g} Pa gives an initial reference "
                        f"porosity outside (0, 1) ({nb[bad]:.4g}); lower A or p_ref")
    return Built(column, state, motion, tm["end"], tm["step"], case["reconsolidation"]["step"], site)


def _sloping_start(case: dict, source: str, column: LiquefactionColumn, site) -> ColumnState:
    """The static start of a sloping column: each element's CRR times K_α at its static shear ratio
    α = τ_s/σ′_v0 (:func:`twofluid.models.hysteretic_sand.apply_k_alpha`), then the static state
    (:meth:`LiquefactionColumn.initial_state`); CaseError naming the layer where the static shear
    exceeds the strength."""
    from ..closures import hysteretic as law
    from ..models.hysteretic_sand import apply_k_alpha

    par = column.hysteretic
    alpha = column.static_shear(site.porosity) / np.maximum(par[:, law.P_SIG0], 1e-300)
    column.hysteretic = np.ascontiguousarray(apply_k_alpha(par, alpha))
    try:
        return column.initial_state(site.porosity, case["site"]["initial_excess_ratio"])
    except ValueError as exc:
        e = int(str(exc).split()[1])
        owner = np.concatenate([site.layer_of, site.crust_layer_of])
        i = int(owner[e])
        raise CaseError(source, "[site] slope", f"{case['site']['slope']:g} % is too steep for "
                        f"{schema_liquefaction.layer_label(case, i)}: {str(exc).split(': ', 1)[1]}; valid "
                        "are slopes the site stands on before shaking") from None


def total_stress_column(case: dict, polarity: int | None = None) -> Built | None:
    """The built total-stress companion of ``case``: the same column with every layer
    ``liquefiable = false`` (n̄ held: no pore-pressure generation), nothing moving vertically
    (``LiquefactionColumn.shear_only``), the record with the sign ``polarity`` where given; None
    without shaking."""
    import copy

    if case["ground_motion"]["pga_g"] == 0.0:
        return None
    c = copy.deepcopy(case)
    for la in c["layers"]:
        la["liquefiable"] = False
    if polarity is not None:
        c["ground_motion"]["polarity"] = int(polarity)
    b = build_column(c)
    b.column.shear_only = True
    return b


class Surface(tuple):
    """(t [s], absolute surface acceleration [m/s²]) of the total-stress companion
    (:func:`total_stress_surface`); ``whole``: on a slope, where the wave ran in one call, every
    node's accelerations of that call (:class:`~twofluid.runners.liquefaction_total_stress.WholeWave`,
    the Newmark block's input for the same polarity where its steps give the same sub-steps), else None."""

    whole = None


def total_stress_surface(case: dict, one_call: bool = True, kernel=None):
    """(t [s], absolute surface acceleration [m/s²]) of the same column without pore-pressure
    generation (every layer ``liquefiable = false``: n̄ held, total stress), run to the end of the
    shear wave (a :class:`Surface`); None without shaking. Its low-passed peak is the a_max of the
    simplified procedure's "run" column, so that the procedure's CSR comes from the site's response
    as a total-stress analysis gives it, as the procedure's r_d assumes.

    Nothing moves vertically in such a run (``LiquefactionColumn.shear_only``), so the column's
    vertical steps only cut the shear wave into pieces. With ``one_call`` (the default) the whole
    shear wave is one call of the compiled sub-steps, where that gives the same sub-steps as the
    run's vertical steps (:func:`_whole_wave`): the same accelerations to far below Newton's
    tolerance (the sub-steps' times are summed differently, and the call stops Newton's iterations
    by their rate of contraction as well, ``one_call``'s ``quick``; tests/unit/test_total_stress_surface.py); on a slope that call
    keeps every node's acceleration (``Surface.whole``). Otherwise, or with ``one_call=False``, the
    column runs step by step as the two-fluid run does. ``kernel``: the hysteretic sub-steps' function
    (:func:`twofluid.models.hysteretic_kernel.runner`'s by default)."""
    b = total_stress_column(case)
    if b is None:
        return None
    col = b.column
    nodes = col.hysteretic is not None and col.body != 0.0
    whole = _whole_wave(b, nodes, kernel) if one_call else None
    if whole is not None:
        t, a = whole
        if not nodes:
            return Surface((t, a))
        out = Surface((t, np.ascontiguousarray(a[:, -1])))
        out.whole = total_stress.WholeWave(t, a, int(case["ground_motion"]["polarity"]))
        return out
    t, a = [], []
    for step in col.run(b.state, col.shear_end, b.dt, b.dt_after):
        for ti, ai in step.surface:
            t.append(ti)
            a.append(ai)
    return Surface((np.array(t), np.array(a)))


def _whole_wave(b: Built, nodes: bool = False, kernel=None):
    """The shear wave of a total-stress column (``b``, built with ``shear_only``) in one call of its
    sub-steps: (t, the surface's absolute acceleration, or with ``nodes`` every node's, bottom first,
    one row per sub-step); None where that would not repeat the sub-steps of its run
    (:func:`twofluid.runners.liquefaction_total_stress.plan`) or a sub-step would be halved (a Newton
    failure: the run halves that step only). The hysteretic law's sub-steps are called directly
    (:func:`~twofluid.runners.liquefaction_total_stress.one_call`), the thesis laws' as one step
    of the whole wave (``LiquefactionColumn.step``; surface only)."""
    col = b.column
    plan = total_stress.plan(col, b.state, b.dt)
    if plan is None:
        return None
    if col.hysteretic is not None:
        return total_stress.one_call(col, b.state, plan[0], nodes, kernel)
    col.shear_step = plan[1]
    try:
        step = col.step(b.state, col.shear_end)
    except StepFailure:
        return None
    if step.substeps != plan[0]:
        return None
    t, a = zip(*step.surface)
    return np.array(t), np.array(a)


def simplified_table(case, a_max_g: float | None = None):
    """The simplified procedure on the case's profile, per element, without running the column.

    ``a_max_g`` [g] is the peak ground-surface acceleration of the CSR; None: the input's
    (``[ground_motion] pga_g``). Returns a :class:`twofluid.geotech.SimplifiedResult`;
    CaseError for a bad case or ``a_max_g`` outside [0, 3] g.
    """
    case = load_case(case) if not isinstance(case, dict) else validated(case)
    if case["case"]["model"] != "liquefaction_1d":
        raise CaseError(_source(case), "[case] model", f"{case['case']['model']!r}: the simplified procedure "
                        "needs a liquefaction_1d case (a layered site)")
    if a_max_g is not None and not 0.0 <= a_max_g <= 3.0:
        raise CaseError(_source(case), "--a-max", f"{a_max_g:g} is outside the valid range [0, 3] [g]")
    b = build_column(case)
    a = case["ground_motion"]["pga_g"] if a_max_g is None else a_max_g
    return report.simplified_rows(b.column, b.site, case, a, top_first=True)


def hydraulic_conductivity(col: LiquefactionColumn, n) -> np.ndarray:
    """k = ρ_f g n²/β [m/s] with β at zero slip (docs/model.md, "Drag"), per element."""
    v = col.v
    beta = v.clo.drag(n, 0.0, v.mat.d, v.mat.rho_f, v.mat.mu_f, **v.clo.drag_params)
    return drag_laws.hydraulic_conductivity(beta, n, v.mat.rho_f, v.mat.g)


class _Recorder:
    """Histories kept in memory for the summary and the figures."""

    def __init__(self, col: LiquefactionColumn, depths, ru_liq: float):
        self.col, self.ru_liq = col, ru_liq
        ne = col.v.mesh.n_elements
        ys = col.v.mesh.y
        self.depths = list(depths)
        self.elem = [int(np.clip(np.searchsorted(ys, col.ground_surface - z, side="right") - 1, 0, ne - 1))
                     for z in depths]
        self.sig0_elem = col.sigma_v0[self.elem]  # σ′_v0 at the report depths [Pa]
        self.peak = np.full(ne, -np.inf)
        self.t_peak = np.zeros(ne)
        self.first = np.full(ne, np.nan)
        self.peak_strain = np.zeros(col.y_all.size - 1)
        self.max_contribution = np.zeros(ne)
        self.t, self.ru, self.sig, self.settle, self.pbase = [], [], [], [], []
        self.ru_top, self.flux_top = [], []
        self._surface_t, self._surface_a = [], []  # (:attr:`surface_t`, :attr:`surface_a`)
        self._surface_steps = []  # the steps' (times, accelerations) lists not yet in those lists
        self.field_t, self.field = [], []
        self.ever = np.zeros(ne, dtype=bool)
        self.damage = DamageRecord(col)  # CSR_eq15 snapshots and the residual strains
        # the per-step reductions in one compiled call (models.record_kernel; its plain Python without numba)
        self._step = record_kernel.compiled() or record_kernel.record_step
        self._elem = np.array(self.elem, dtype=np.int64)
        self._sig0_elem = _c(self.sig0_elem)
        self._ru_liq = float(ru_liq)
        self._liq = np.zeros(ne, dtype=bool)
        self._scalars = np.zeros(5)  # (with the lowest liquefied element: the damage record's)
        self.last_contribution = np.zeros(ne)  # (each record writes it whole: one array)
        self._sizes = (ne, self._elem.size)
        self._fixed, self._fixed_of = (), (None, None, None)  # the column's constant arrays as the kernel takes them
        self._last_ru = None  # the r_u of the last :meth:`record` (its report depths: self.ru[-1])

    def _constants(self) -> tuple:
        """(P_hydrostatic, σ′_v0, n0, element lengths) as contiguous float64, converted again only if
        the column holds other arrays (a new initial state)."""
        col = self.col
        was = self._fixed_of
        if col.p_hydro is not was[0] or col.sigma_v0 is not was[1] or col.n0 is not was[2]:
            of = self._fixed_of = (col.p_hydro, col.sigma_v0, col.n0)
            self._fixed = (*map(_c, of), _c(col.v.mesh.lengths))
        return self._fixed

    def record(self, s: ColumnState, field: bool, samples=((), ())):
        """Record the state ``s`` (``field``: its r_u row kept too; ``samples``: the step's (times, surface
        accelerations) lists, ``ColumnStep.samples``); returns its r_u."""
        col, v = self.col, s.vertical
        ne, k = self._sizes
        ru = np.empty(ne)
        ru_elem, sig_elem = np.empty(k), np.empty(k)
        done = col._ps  # (the split step's σ′_v of the state it made: P, n and σ′_v as the record takes them)
        if done is not None and done[0] is v:
            self.ps = ps = done[1]
            P, n = v.P, v.n
        else:
            self.ps = col.granular_pressure(s)  # the probes' σ′_v too
            P, n, ps = _c(v.P), _c(v.n), _c(self.ps)
        was = self._fixed_of  # (:meth:`_constants`, inline)
        fixed = self._fixed if col.p_hydro is was[0] and col.sigma_v0 is was[1] and col.n0 is was[2] else \
            self._constants()
        p_hydro, sigma_v0, n0, lengths = fixed
        settle, pbase, ru_top, flux_top, low = self._step(
            float(v.t), P, p_hydro, sigma_v0, n, n0, lengths, _c(s.wave.gamma), ps,
            self._elem, self._sig0_elem, self._ru_liq, float(v.V[-1]), float(v.W[-1]), self.peak, self.t_peak,
            self.first, self.ever, self._liq, self.peak_strain, self.max_contribution, ru, self.last_contribution,
            ru_elem, sig_elem, self._scalars).tolist()
        self.damage.record(s, self._liq, int(low))
        self.t.append(v.t)
        self.ru.append(ru_elem)
        self.sig.append(sig_elem)
        self.settle.append(settle)  # = col.settlement(s)
        self.pbase.append(pbase)
        self.ru_top.append(ru_top)
        self.flux_top.append(flux_top)  # = col.surface_seepage(s)
        if samples[0]:
            self._surface_steps.append(samples)
        if field:
            self.field_t.append(v.t)
            self.field.append(ru)
        self._last_ru = ru
        return ru

    @property
    def surface_t(self) -> list:
        """The times [s] of the surface's acceleration samples (the shear sub-steps' ends), a list that grows."""
        if self._surface_steps:
            self._surface_lists()
        return self._surface_t

    @property
    def surface_a(self) -> list:
        """The surface's absolute acceleration [m/s²] at :attr:`surface_t`, a list that grows."""
        if self._surface_steps:
            self._surface_lists()
        return self._surface_a

    def _surface_lists(self) -> None:
        """The steps' samples recorded since into :attr:`surface_t` and :attr:`surface_a`."""
        t, a = self._surface_t, self._surface_a
        for times, acc in self._surface_steps:
            t.extend(times)
            a.extend(acc)
        self._surface_steps.clear()

    def surface_arrays(self) -> tuple[np.ndarray, np.ndarray]:
        """(:attr:`surface_t`, :attr:`surface_a`) as float64 arrays, made once for the lists as they are
        (they only grow): the summary, its tables and the history read them several times."""
        kept = self.__dict__.get("_surface_arrays")
        if kept is None or kept[0] != len(self.surface_t) or kept[1] != len(self.surface_a):
            kept = self._surface_arrays = (len(self.surface_t), len(self.surface_a),
                                           np.array(self.surface_t, dtype=float), np.array(self.surface_a, dtype=float))
        return kept[2], kept[3]

    def probe_names(self) -> list[str]:
        """Columns of probes.csv after time_s (:meth:`probe_row`)."""
        return (["base_acceleration_m_s2", "surface_acceleration_m_s2", "surface_settlement_m",
                 "base_pore_pressure_Pa", "base_excess_pore_pressure_Pa", "surface_displacement_m",
                 "water_table_seepage_m_s"] + [f"r_u@{z:g}m" for z in self.depths]
                + [f"sigma_v_eff_Pa@{z:g}m" for z in self.depths])

    def probe_row(self, s: ColumnState, ru) -> list:
        """The probes of the state last recorded (:meth:`record`), in the order of :meth:`probe_names`,
        as a list of floats (what :meth:`ResultWriter.probe_row <twofluid.io.results.ResultWriter.probe_row>` takes fastest)."""
        col = self.col
        base, surface = col.accelerations(s)
        return [float(base), float(surface), self.settle[-1], float(s.vertical.P[0]), self.pbase[-1],
                col.surface_displacement(s), self.flux_top[-1],
                *(self.ru[-1] if ru is self._last_ru else ru[self._elem]).tolist(),  # (the record's r_u at the depths)
                *self.ps[self._elem].tolist()]


def _at_mark(marks: list, t: float) -> bool:
    """Whether ``t`` [s] is one of the sorted ``marks`` to 1e-9 relative (1e-9 s below 1 s): the two
    nearest marks either side only (one farther away is farther from ``t``: it could match only
    where marks lie within 1e-9 of each other)."""
    i = bisect.bisect_left(marks, t)
    for m in marks[max(i - 2, 0):i + 2]:
        if abs(t - m) < 1e-9 * max(1.0, m):
            return True
    return False


class _Marks:
    """:func:`_at_mark` for a run's growing times: ``low`` is below every time within the tolerance of a mark
    not yet passed (2e-9 relative, twice :func:`_at_mark`'s), so that a time ``t`` ≤ ``low`` is at none
    and only a time past it needs :meth:`at`."""

    def __init__(self, marks: list):
        self.marks = marks
        self._k = 0
        self.low = -np.inf
        self._next(-np.inf)

    def _next(self, t: float) -> None:
        marks, k = self.marks, self._k
        while k < len(marks) and marks[k] + 2e-9 * max(1.0, marks[k]) <= t:  # passed for good
            k += 1
        self._k = k
        self.low = marks[k] - 2e-9 * max(1.0, marks[k]) if k < len(marks) else np.inf

    def at(self, t: float) -> bool:
        """:func:`_at_mark` of ``t``, with the next ``low`` set for the times after it."""
        hit = _at_mark(self.marks, t)
        self._next(t)
        return hit


def _c(a) -> np.ndarray:
    """``a`` as the compiled record takes it: a C-contiguous float64 array (itself where it is one)."""
    return a if type(a) is np.ndarray and a.dtype == np.float64 and a.flags.c_contiguous else \
        np.ascontiguousarray(a, dtype=np.float64)


def _profile(col: LiquefactionColumn, s: ColumnState, peak) -> dict:
    v = s.vertical
    mesh = col.v.mesh
    ns = col.n_sat
    return {"depth_m": col.depth, "y_m": mesh.centres, "porosity": v.n, "reference_porosity": v.n_bar,
            "P_Pa": v.P, "excess_P_Pa": col.excess_pressure(s), "sigma_v_eff_Pa": col.granular_pressure(s),
            "sigma_v0_Pa": col.sigma_v0, "r_u": col.excess_ratio(s), "peak_r_u": peak.copy(),
            "shear_strain": s.wave.gamma[:ns], "shear_stress_Pa": s.wave.tau[:ns],
            "hydraulic_conductivity_m_s": hydraulic_conductivity(col, v.n)}


def _zone(mask, col) -> list | None:
    """[top depth, bottom depth] [m] below the ground surface spanned by the saturated elements in
    ``mask`` (None if empty)."""
    if not np.any(mask):
        return None
    y, H = col.v.mesh.y, col.ground_surface
    e = np.flatnonzero(mask)
    return [float(H - y[e.max() + 1]), float(H - y[e.min()])]


def run_liquefaction(case, out_dir=None, progress: bool = False, reference: bool = False):
    """Run a ``liquefaction_1d`` case (resolved dict, bundled name or TOML path); ``reference``: the
    full vertical model and the NumPy shear path (:func:`build_column`)."""
    case = load_case(case) if not isinstance(case, dict) else validated(case)
    return run_validated(case, out_dir, progress, reference)


def run_validated(case: dict, out_dir=None, progress: bool = False, reference: bool = False):
    """:func:`run_liquefaction` of a case just validated (what ``run_case`` calls: it has validated
    the case and checked the output folder)."""
    from .common import RunResult, run_guard

    # reads the record and weights: a bad one stops here, nothing written
    b = build_column(case, reference=True) if reference else build_column(case)
    name = case["case"]["name"]
    out = Path(out_dir or default_out_dir(case))
    out.mkdir(parents=True, exist_ok=True)
    write_resolved_case(out / "case.resolved.toml", case)
    col, state = b.column, b.state
    c_v0 = report.initial_consolidation_coefficient(col, case["site"]["initial_excess_ratio"])  # before the run softens A
    H = col.ground_surface
    rep = case["report"]
    depths = sorted(set(schema_liquefaction.report_depths(case)) | {H - y for y in case["output"]["probes"]})  # y above the base
    rec = _Recorder(col, depths, rep["ru_liquefied"])
    ru0 = rec.record(state, True)
    # rows every step: written in blocks (io.results), flushed at the loop's end and on every way out of it
    writer = ResultWriter(out, PROFILE_COLUMNS, rec.probe_names(), block=True)
    ffile = CsvStream(out / "ru_field.csv", ["time_s"] + [f"r_u@{z:.6g}m" for z in col.depth], block=True)
    field_formats = ["%.10g"] + ["%.6g"] * col.n_sat

    def write_field(s, ru):  # whole rows, finite values only (io.results)
        if check_finite("ru_field.csv", s.t, {"r_u": ru}):
            row = np.empty((1, ru.size + 1))  # (t, r_u...)
            row[0, 0] = s.t
            row[0, 1:] = ru
            ffile.table(row, field_formats)

    write_field(state, ru0)
    writer.probe_row(state.t, rec.probe_row(state, ru0))
    srec = None
    if col.body != 0.0:  # a sloping site: displacements, localisation, FS_post and the estimates
        from .liquefaction_slope import SlopeRecorder

        srec = SlopeRecorder(col, out)
        srec.record(state)
        srec.profile(state)
    out_times = sorted({*case["output"]["times"], col.shaking_end, b.t_end} - {0.0})
    out_times = [t for t in out_times if 0.0 < t <= b.t_end]
    profiles = {0.0: _profile(col, state, rec.peak)}
    writer.profile(0.0, profiles[0.0])
    solids0 = col.v.solids_volume(state.vertical)
    inflow = 0.0
    settle_shaking = 0.0 if col.shaking_end == 0.0 else None
    probe_interval, field_interval = case["output"]["probe_interval"], rep["field_interval"]
    next_probe, next_field = probe_interval, field_interval
    n_steps, n_sub, last, probed = 0, 0, state, True
    ru_done = case["reconsolidation"]["dissipated_r_u"]
    stop = None if ru_done == 0.0 else (lambda s: float(np.max(col.excess_ratio(s))) < ru_done)
    wall0 = time.perf_counter()
    near = _Marks(out_times)
    with run_guard(b.t_end, progress, writer, ffile, *(() if srec is None else (srec,))) as run:
        record, bar = rec.record, run.bar
        shown = bar.n  # (the bar's n, kept here as the bar sums it)
        for step in col.run(state, b.t_end, b.dt, b.dt_after, stops=out_times, stop=stop):
            s = last = step.state
            t = s.vertical.t
            n_steps += 1
            n_sub += step.substeps
            inflow += step.solids_inflow
            at_mark = t > near.low and near.at(t)
            field = t >= next_field - 1e-12 or at_mark
            ru = record(s, field, step.samples)
            if srec is not None:
                srec.record(s)
                if at_mark or abs(t - col.shear_end) < 1e-9 * max(1.0, t):
                    srec.profile(s)
            if field:
                write_field(s, ru)
                next_field = t + field_interval
            probed = False
            if t >= next_probe - 1e-12 or at_mark:
                writer.probe_row(t, rec.probe_row(s, ru))
                next_probe = t + probe_interval
                probed = True
            if settle_shaking is None and t >= col.shaking_end - 1e-9:
                settle_shaking = rec.settle[-1]
            if at_mark:
                profiles[round(t, 9)] = _profile(col, s, rec.peak)
                writer.profile(t, profiles[round(t, 9)])
            dn = t - shown
            bar.update(dn)
            shown += dn
        if run.status == "completed" and round(last.t, 9) not in profiles:  # ended by dissipation
            profiles[round(last.t, 9)] = _profile(col, last, rec.peak)
            writer.profile(last.t, profiles[round(last.t, 9)])
            if not probed:
                writer.probe_row(last.t, rec.probe_row(last, col.excess_ratio(last)))
        writer.flush()  # in the guard: a full disk here is a failed run, said in its summary
        ffile.flush()
    status, reason = run.status, run.reason
    wall = time.perf_counter() - wall0
    if round(last.t, 9) not in profiles:
        profiles[round(last.t, 9)] = _profile(col, last, rec.peak)
        writer.profile(last.t, profiles[round(last.t, 9)])  # the state it stopped at, in the file too
    if srec is not None:
        srec.profile(last)
        srec.close()
    total = None
    if status == "completed":  # the companion run informs the simplified table only
        try:
            total = total_stress_surface(case)
        except (StepFailure, FloatingPointError, ValueError):
            total = None
    summary, extra = _summary(case, b, rec, last, status, reason, n_steps, n_sub, wall, solids0, inflow,
                              settle_shaking, total, c_v0)
    summary["residual_strain"] = rec.damage.summary(col, last, summary["liquefied_thickness_m"], rec.peak_strain)
    if srec is not None:
        from .liquefaction_slope import slope_summary

        summary["slope"] = slope_summary(case, col, b.site, rec, srec, last, extra["simplified_run"],
                                         getattr(total, "whole", None))
    write_json(out / "summary.json", summary)
    try:
        report.write_tables(out, summary, extra, rec)
    except NonFiniteOutput as exc:  # a NaN in a report table: the run failed, said in its summary
        status = summary["status"] = "failed"
        summary["reason"] = str(exc)
        write_json(out / "summary.json", summary)
    if case["output"]["plots"]:
        from ..plots.liquefaction import liquefaction_plots

        liquefaction_plots(rec, col, out, name, rep["ru_liquefied"], case=case, summary=summary, extra=extra)
        if srec is not None:  # a sloping site: lateral_displacement.png, surface_displacement.png
            from ..plots.slope import slope_plots

            slope_plots(srec, col, out, name, summary["slope"])
    hist = {"t": np.array(rec.t), "r_u": np.array(rec.ru), "settlement_m": np.array(rec.settle),
            "base_excess_pore_pressure_Pa": np.array(rec.pbase),
            "field_t": np.array(rec.field_t), "field_r_u": np.array(rec.field),
            "surface_t": np.array(rec.surface_arrays()[0]), "surface_acceleration_m_s2": np.array(rec.surface_arrays()[1])}
    return RunResult(status, out, summary, profiles, hist)


def _summary(case, b, rec, last, status, reason, n_steps, n_sub, wall, solids0, inflow, settle_shaking,
             total=None, c_v=None):
    """summary.json, and the per-element and per-layer arrays behind the CSV tables and figures."""
    col, site = b.column, b.site
    mesh = col.v.mesh
    H = col.ground_surface
    n0 = col.n0
    k = hydraulic_conductivity(col, n0)
    if c_v is None:  # c_v of the initial state: only before the run (the reconsolidation softens A)
        c_v = report.initial_consolidation_coefficient(col, case["site"]["initial_excess_ratio"])
    solids = col.v.solids_volume(last.vertical)
    first = rec.first
    liq = np.isfinite(first)
    by_shaking = liq & (np.nan_to_num(first, nan=np.inf) < col.shear_end - 1e-9)
    after = liq & ~by_shaking
    t = np.array(rec.t)
    pb = np.array(rec.pbase)
    first_info = None
    if np.any(liq):
        t1 = float(np.nanmin(first))
        at = liq & (first <= t1 + 1e-12)
        first_info = {"time_s": t1, "depth_range_m": _zone(at, col), "depth_m": float(np.mean(col.depth[at]))}
    m = case["ground_motion"]
    c_base = col.wave.base_impedance
    if c_base is None:
        base = {"kind": "rigid", "record_is": "base motion"}
    else:  # α = ρ̄ V_s / (ρ_r V_r) of the bottom element at the initial G_max
        g0 = seed_idriss_gmax(col.sigma_v0[0], np.broadcast_to(col.sand.k2max, n0.shape)[0])
        rho0 = float(col.mixture_density(n0)[0])
        base = {"kind": "compliant", "record_is": "outcrop motion of the bedrock",
                "bedrock_impedance_Pa_s_m": c_base,
                "impedance_ratio_bottom_element": float(np.sqrt(rho0 * g0)) / c_base}
    # dissipation: the settlement the column will reach once the excess pore pressure is gone
    final_el = report.final_contributions(col, last)
    final = float(final_el.sum())
    ru_end = float(np.max(col.excess_ratio(last)))
    done = case["reconsolidation"]["dissipated_r_u"]
    dissipated = done > 0.0 and ru_end < done
    fraction = rec.settle[-1] / final if final > 0.0 else 1.0
    if status == "completed":
        reached = (f"max r_u = {ru_end:.3g}, {100.0 * fraction:.1f} % of the final settlement "
                   f"({100.0 * final:.3g} cm) reached")
        reason = (f"dissipated: max r_u = {ru_end:.3g} < {done:g} at t = {last.t:.6g} s" if dissipated else
                  f"stopped at the end time {b.t_end:g} s before dissipation: {reached}" if done > 0.0 else
                  f"stopped at the end time {b.t_end:g} s (no dissipation criterion): {reached}")
    boil = report.sand_boil(rec.t, rec.ru_top, rec.flux_top, col.shaking_end, rec.ru_liq)
    surface_t, surface_a = rec.surface_arrays()  # (the lists as arrays, once)
    spec = report.spectra(b.motion, surface_t, surface_a, case["report"]["spectrum_periods"],
                          case["report"]["spectrum_damping"])
    pga_in = 0.0 if b.motion is None else b.motion.pga / report.G
    pga_surf = 0.0 if not rec.surface_a else float(np.max(np.abs(surface_a))) / report.G
    pga_lp = sa_surf = None
    if len(rec.surface_a) > 2:
        pga_lp = filtering.low_passed_peak(surface_t, surface_a) / report.G
        sa_surf = {f"{p:g}": v / report.G for p, v in filtering.spectral_ordinates(surface_t, surface_a).items()}
    pga_ts = None if total is None or total[0].size < 3 else filtering.low_passed_peak(*total) / report.G
    a_run = pga_ts if pga_ts is not None else (pga_lp if pga_lp is not None else pga_surf)
    simp_run = report.simplified_rows(col, site, case, min(a_run, 3.0))
    simp_in = report.simplified_rows(col, site, case, pga_in)
    ns = col.n_sat
    layers = []
    owner_all = np.concatenate([site.layer_of, site.crust_layer_of])
    contrib_end = col.settlement_contributions(last)
    for i, la in enumerate(case["layers"]):
        e = np.flatnonzero(site.layer_of == i)
        ea = np.flatnonzero(owner_all == i)
        row = {"name": la["name"], "depth_top_m": float(site.depth_top[i]),
               "depth_bottom_m": float(site.depth_bottom[i]), "elements": int(ea.size),
               "saturated": bool(e.size), "liquefiable": bool(e.size) and la["liquefiable"],
               "peak_shear_strain": float(rec.peak_strain[ea].max()),
               "simplified_min_FS_run": float(simp_run.FS[ea].min()),
               "simplified_min_FS_input": float(simp_in.FS[ea].min()),
               "simplified_settlement_run_m": float(simp_run.settlement_m[ea].sum()),
               "simplified_settlement_input_m": float(simp_in.settlement_m[ea].sum())}
        if e.size:
            f = first[e]
            row.update(porosity=float(n0[e].mean()), particle_diameter_m=float(col.v.mat.d_p[e[0]]),
                       hydraulic_conductivity_m_s=float(k[e].mean()),
                       hydraulic_conductivity_given_m_s=la["hydraulic_conductivity"] or None,
                       sigma_v0_Pa=[float(col.sigma_v0[e].min()), float(col.sigma_v0[e].max())],
                       peak_r_u=float(rec.peak[e].max()),
                       time_first_liquefied_s=None if not np.any(np.isfinite(f)) else float(np.nanmin(f)),
                       liquefied_depth_range_m=_zone(np.isin(np.arange(ns), e) & rec.ever, col),
                       liquefied_thickness_m=float(mesh.lengths[e][rec.ever[e]].sum()),
                       settlement_end_m=float(contrib_end[e].sum()),
                       predicted_final_settlement_m=float(final_el[e].sum()),
                       max_settlement_contribution_m=float(rec.max_contribution[e].sum()))
        else:
            row.update(unit_weight_N_m3=la["unit_weight"])
        layers.append(row)
    zw = case["site"]["water_table_depth"]
    curves = {la["modulus_reduction"] for la in case["layers"]}
    s = {
        "case": case["case"]["name"], "status": status, "stopped_at_s": last.t, "reason": reason,
        "end_time_s": b.t_end, "wall_time_s": wall, "steps": n_steps, "shear_substeps": n_sub,
        "depths_are": "below the ground surface [m]",
        "site": {"depth_m": H, "water_table_depth_m": zw, "crust_weight_Pa": site.crust_weight,
                 "elements": int(col.y_all.size - 1), "saturated_elements": ns,
                 "sigma_v0_Pa": [float(col.sigma_v0.min()), float(col.sigma_v0.max())]},
        "layers": layers,
        "hydraulic_conductivity_m_s": float(k.mean()),
        "hydraulic_conductivity_definition": "k = rho_f g n^2 / beta at zero slip, initial porosity",
        "consolidation_coefficient_m2_s": {"top": float(c_v[-1]), "mid_depth": float(np.interp(
            zw + (H - zw) / 2, col.depth[::-1], c_v[::-1])), "base": float(c_v[0])},
        "shaking": {"record": m["file"], "pga_g": m["pga_g"], "magnitude": m["magnitude"],
                    "end_s": col.shaking_end, "shear_wave_end_s": col.shear_end,
                    "applied_pga_m_s2": None if b.motion is None else b.motion.pga, "base": base,
                    "peak_surface_acceleration_g": pga_surf,
                    "peak_surface_acceleration_low_passed_g": pga_lp,
                    "low_pass": f"zero-phase 4th-order Butterworth (a forward and backward pass's response, "
                                f"applied in the frequency domain), {filtering.CUTOFF_HZ:g} Hz, on the surface "
                                "motion resampled to the shear sub-step",
                    "surface_Sa_g": sa_surf, "surface_Sa_damping": 0.05,
                    "peak_surface_acceleration_total_stress_low_passed_g": pga_ts,
                    "modulus_reduction": curves.pop() if len(curves) == 1 else "per layer"},
        "r_u_definition": "(P - P_hydrostatic) / sigma'_v0 per saturated element; liquefied: r_u > "
                          f"{rec.ru_liq:g}",
        "by_depth": {"depth_m": col.depth, "peak_r_u": rec.peak, "time_of_peak_s": rec.t_peak,
                     "time_first_liquefied_s": [None if not np.isfinite(x) else float(x) for x in first]},
        "report_depths": {"depth_m": rec.depths, "element_depth_m": [float(col.depth[e]) for e in rec.elem],
                          "peak_r_u": [float(rec.peak[e]) for e in rec.elem],
                          "time_first_liquefied_s": [None if not np.isfinite(first[e]) else float(first[e])
                                                     for e in rec.elem]},
        "first_liquefaction": first_info,
        "liquefied_depth_range_m": _zone(rec.ever, col),
        "liquefied_thickness_m": float(mesh.lengths[rec.ever].sum()),
        "liquefied_depth_range_shaking_m": _zone(by_shaking, col),
        "liquefied_thickness_shaking_m": float(mesh.lengths[by_shaking].sum()),
        "liquefied_depth_range_after_shaking_m": _zone(after, col),
        "liquefied_thickness_after_shaking_m": float(mesh.lengths[after].sum()),
        "liquefied_by_definition": ("shaking: r_u > the threshold first reached while the shear wave runs "
                                    f"(t < {col.shear_end:g} s); after shaking: first reached later, by upward "
                                    "seepage from below (or, with the hysteretic model, the reconsolidation floor "
                                    "applied when the shear wave stops)"),
        "peak_r_u_top_element": float(rec.peak[-1]),
        "surface": boil,
        "settlement_end_of_shaking_m": settle_shaking,
        "settlement_end_m": rec.settle[-1],
        **report.settlement_fields(rec.settle[-1], final, dissipated, b.t_end, last.t),
        "settlement_end_percent_of_depth": 100.0 * rec.settle[-1] / H,
        "settlement_definition": "sum over saturated elements of h (n0 - n)/(1 - n): compression of the skeleton",
        "dissipation": {"dissipated": dissipated, "criterion_max_r_u": done, "max_r_u_end": ru_end,
                        "final_settlement_m": final, "fraction_of_final_settlement": fraction,
                        "final_settlement_definition": "the remaining excess pore pressure moved onto the "
                        "skeleton at fixed reference porosity (skeleton law integrated exactly)"},
        "simplified_procedure": {
            "method": report.simplified_method(case),
            "a_max_run_g": min(a_run, 3.0), "a_max_input_g": pga_in, "magnitude": m["magnitude"],
            "a_max_run_definition": ("low-passed peak surface acceleration of the same column in total stress "
                                     "(no pore-pressure generation)" if pga_ts is not None else
                                     "low-passed peak surface acceleration of this run (no total-stress run)"),
            "a_max_run_note": None if a_run <= 3.0 else f"the peak surface acceleration "
                              f"{a_run:.3g} g is above the procedure's range; evaluated at 3 g",
            "liquefied_depth_range_run_m": _fs_zone(simp_run, col),
            "liquefied_depth_range_input_m": _fs_zone(simp_in, col),
            "settlement_run_m": simp_run.total_settlement_m,
            "settlement_input_m": simp_in.total_settlement_m,
            "table_input": _rows_top_first(simp_in), "table_run": _rows_top_first(simp_run)},
        "base_excess_pore_pressure": {"peak_Pa": float(pb.max()), "time_of_peak_s": float(t[pb.argmax()]),
                                      "end_Pa": float(pb[-1])},
        "solids_volume_m3": {"initial": solids0, "final": solids, "inflow_top": inflow},
        "solids_volume_balance_error": (solids - solids0 - inflow) / solids0,
        "solids_volume_balance_error_definition":
            "(solids volume now - initial - solids that entered through the top face) / initial",
    }
    if spec is not None:
        s["spectra"] = {key: spec[key] for key in ("damping", "pga_input_g", "pga_surface_g",
                                                   "period_of_peak_Sa_input_s", "period_of_peak_Sa_surface_s")}
        s["spectra"]["max_amplification"] = float(np.nanmax(spec["amplification"]))
        s["spectra"]["period_of_max_amplification_s"] = float(spec["period_s"][np.nanargmax(spec["amplification"])])
    extra = {"simplified_run": simp_run, "simplified_input": simp_in, "spectra": spec,
             "owner": owner_all, "layer_names": [la["name"] for la in case["layers"]], "final_contribution": final_el}
    return s, extra


def _rows_top_first(res) -> list[dict]:
    """The simplified procedure's rows (labels with units; FS null where it cannot liquefy) from
    the ground surface down."""
    rows = res.to_rows()
    return [rows[i] for i in np.argsort(res.z_top_m)]


def _fs_zone(res, col) -> list | None:
    """Depth range [m] where the simplified procedure's FS < 1."""
    bad = res.FS < 1.0
    if not np.any(bad):
        return None
    return [float(res.z_top_m[bad].min()), float(res.z_bottom_m[bad].max())]
