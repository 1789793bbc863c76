"""Turn a resolved case into a model, an initial state and run settings."""
from __future__ import annotations

import bisect
import warnings
from dataclasses import dataclass, replace

import numpy as np

from ..closures import drag as drag_laws
from ..closures.registry import get
from ..closures.solids_pressure import reference_porosity_for
from ..mesh.line import uniform_line
from ..models.two_fluid_1d import Boundary, Closures, Materials, State, TwoFluid1D
from ..timestepping.backward_euler import PicardSettings
from .bed import initial_bed
from .case import section
from .validity import drag_validity_warnings

__all__ = ["Schedule", "Built", "build"]


@dataclass(frozen=True)
class Schedule:
    """Piecewise-linear function of time; a repeated time is a step (right value after it).

    >>> s = Schedule((0.0, 0.0, 10.0), (1.0, 2.0, 4.0))
    >>> s(-1.0), s(0.0), s(1e-9) > 1.99, s(5.0), s(20.0)
    (1.0, 1.0, True, 3.0, 4.0)
    """

    times: tuple
    values: tuple

    def __call__(self, t: float) -> float:
        ts, vs = self.times, self.values  # scalar work on tuples: called at every step and iterate
        i = bisect.bisect_left(ts, t)
        if i == 0:
            return float(vs[0])
        if i >= len(ts):
            return float(vs[-1])
        # ts[i-1] < t <= ts[i]; with a step at ts[i] the left value holds up to it
        t0, t1 = ts[i - 1], ts[i]
        return float(vs[i - 1] + (vs[i] - vs[i - 1]) * (t - t0) / (t1 - t0))


@dataclass
class Built:
    model: TwoFluid1D
    state: State
    t_end: float
    dt: float
    settings: PicardSettings
    inlet_velocities: tuple  # resolved inlet schedule [m/s] (for the summary)


def materials(case: dict) -> Materials:
    """The ``[materials]`` section as :class:`Materials` (SI)."""
    ma = case["materials"]
    return Materials(rho_f=ma["liquid_density"], mu_f=ma["liquid_viscosity"], rho_s=ma["particle_density"],
                     d_p=ma["particle_diameter"], sphericity=ma["sphericity"], g=ma["gravity"])


def closures(case: dict, mat: Materials, pressure_section: str = "closures.solids_pressure") -> Closures:
    """The case's closures, with the drag law's |slip| saturation (``[closures.drag] slip_saturation``).

    ``pressure_section`` is the section holding ``compressibility`` and ``p_ref`` of P_s, by its
    schema name (``"closures.solids_pressure"``: ``case["closures"]["solids_pressure"]``).
    """
    clo = _closures(case, pressure_section)
    if "exponent" in clo.drag_params and clo.drag_params["exponent"] == 0.0:  # Khan & Richardson's k
        ar = drag_laws.archimedes_number(mat.d, mat.rho_s, mat.rho_f, mat.mu_f, mat.g)
        clo = replace(clo, drag_params={**clo.drag_params,
                                        "exponent": float(drag_laws.khan_richardson_exponent(max(float(ar), 0.0)))})
    return replace(clo, slip_max=drag_laws.slip_limit(
        clo.drag, case["closures"]["drag"]["slip_saturation"], mat.d, mat.rho_s, mat.rho_f, mat.mu_f, mat.g,
        **clo.drag_params))


def inlet_velocities(b: dict, clo: Closures, mat: Materials) -> tuple[float, ...]:
    """An inlet's schedule values [m/s]: its ``velocities``, or the superficial velocities that
    fluidize a uniform bed at each of its ``porosities`` with the model's drag law."""
    if not b["porosities"]:
        return tuple(b["velocities"])
    return tuple(clo.fluidization_velocity(n, mat) for n in b["porosities"])


def _closures(case: dict, pressure_section: str) -> Closures:
    d = case["closures"]["drag"]
    law = get("drag", d["law"]).func
    params = {"stokes": d["stokes"]}
    if d["law"] == "gidaspow":
        params.update(n_switch=d["n_switch"], blend_width=d["blend_width"])
    if d["law"] in ("richardson_zaki", "ergun_richardson_zaki"):
        params["exponent"] = d["exponent"]  # 0: Khan & Richardson's, set by closures()
    sp = section(case, pressure_section)
    fluidized, fparams = None, {}
    if sp.get("fluidized", "none") != "none":
        fluidized = get("fluidized_pressure", sp["fluidized"]).func
        fparams = {"coefficient": sp["fluidized_coefficient"]}
    return Closures(drag=law, drag_params=params, A=sp["compressibility"], p_ref=sp["p_ref"],
                    viscous=case["closures"]["viscosity"]["law"] != "none",
                    fluidized_pressure=fluidized, fluidized_params=fparams)


def _boundary(b: dict, clo: Closures, mat: Materials) -> tuple[Boundary, tuple]:
    if b["kind"] != "inlet":
        return Boundary(b["kind"], pressure=b["pressure"]), ()
    vel = inlet_velocities(b, clo, mat)
    return Boundary("inlet", velocity=Schedule(tuple(b["times"]), vel)), vel


def build(case: dict) -> Built:
    m = case["mesh"]
    area = m["area"] if m["area_top"] == -1.0 else (m["area"], m["area_top"])
    mesh = uniform_line(m["length"], m["elements"], area=area,
                        inclination_rad=np.deg2rad(m["inclination_deg"]))
    mat = materials(case)
    clo = closures(case, mat)
    bottom, vb = _boundary(case["boundary"]["bottom"], clo, mat)
    top, vt = _boundary(case["boundary"]["top"], clo, mat)
    drag_validity_warnings(case, clo, mat, vb + vt)
    cls = TwoFluid1D
    if case["case"]["model"] == "reduced_1d":
        from ..models.reduced_1d import Reduced1D as cls
    model = cls(mesh, mat, clo, bottom, top, element=m["element"],
                solids_flux=case["numerics"]["solids_flux"])
    state = initial_state(model, case)
    tm = case["time"]
    settings = PicardSettings(tol=tm["picard_tol"], max_iter=tm["picard_max_iter"],
                              dt_min=min(1e-7, tm["step"] * 1e-4))
    return Built(model, state, tm["end"], tm["step"], settings, vb or vt)


def settled_reference_porosity(n_bar: np.ndarray, n: np.ndarray, ps: np.ndarray, clo: Closures,
                               mat: Materials) -> None:
    """Set ``n_bar`` in place where the solids carry ``ps`` [Pa] at porosity ``n`` (a deposit at rest).

    The exponential law carries ``ps`` minus the fluidized-bed term, if the case has one. Where
    that term alone reaches ``ps`` (elements near the bed surface, which carry little weight) no
    n̄ puts the element at rest: the exponential part is then given 1e-6 p_ref (n̄ continuous in
    the remainder, P_s as close to rest as it can be) and a
    :class:`~twofluid.casefile.schema.CaseWarning` says how many elements.
    """
    from .schema import CaseWarning

    bed = n < 1.0
    rest = ps
    if clo.fluidized_pressure is not None:
        rest = ps - clo.fluidized_pressure(n, mat.d, mat.rho_s, mat.rho_f, mat.g, **clo.fluidized_params)
        over = bed & (rest <= 0.0) & (ps > 0.0)
        if over.any():
            warnings.warn(CaseWarning(
                f"[initial] state = 'settled': in {int(over.sum())} of {int(bed.sum())} bed elements the "
                "fluidized-bed pressure P_e reaches the weight they carry, so they cannot start at rest; "
                "a finer mesh near the bed surface or fluidized = 'none' avoids it"), stacklevel=2)
        rest = np.where(ps > 0.0, np.maximum(rest, 1e-6 * clo.p_ref), rest)
    solid = bed & (rest > 0.0)
    n_bar[solid] = reference_porosity_for(n[solid], rest[solid], clo.A, clo.p_ref)


def initial_state(model: TwoFluid1D, case: dict) -> State:
    """Uniform bed (clear liquid above its surface, :func:`~twofluid.casefile.bed.initial_bed`) at rest
    in the initial inflow."""
    init = case["initial"]
    mesh = model.mesh
    u = 0.0
    if model.bottom.kind == "inlet":
        u = model.bottom.velocity(0.0)
    elif model.top.kind == "inlet":
        u = -model.top.velocity(0.0)
    _, _, n = initial_bed(mesh, case, model.clo, model.mat, u)
    n_bar = np.full(mesh.n_elements, case["closures"]["solids_pressure"]["reference_porosity"])
    if init["state"] == "settled":
        settled_reference_porosity(n_bar, n, model.settled_solids_pressure(n), model.clo, model.mat)
    P = np.zeros(model.np)
    return State(0.0, np.full(model.nv, u), np.full(model.nv, u), P, n, n_bar)
