"""The initial bed of a 1D case as a process engineer gives it.

``[initial]`` sets the bed by its porosity (or ``state = "fluidized"``: the porosity at
which the inlet velocity at t = 0 holds a uniform bed, from the case's own drag law)
and by its height, its solids mass or its settled height at a packing porosity. A bed
given by its solids inventory has its surface placed exactly: the element it cuts holds
the solids of the part below it, so the inventory is the one asked for. A bed given by its
height fills whole elements (those whose centres lie below it), with a one-line warning
when that moves the surface: a cut element starts as a dilute layer out of balance on top
of the bed, which shifts t1 by about 9 % on the Slis bed at 90 elements.
"""
from __future__ import annotations

import warnings

import numpy as np
from ..scipy_kernels import brentq  # scipy.optimize's, without importing scipy.optimize (0.35 s)

from .schema import CaseError, CaseWarning

__all__ = ["volume_below", "height_of_volume", "bed_porosity", "fluidized_porosity", "initial_bed",
           "packed_porosity", "bed_figures", "equilibrium_warning", "flow_rate_inputs", "column_diameter",
           "richardson_zaki_1954_exponent", "L_MIN", "M3_H"]

L_MIN = 1e-3 / 60.0  # [m³/s] per L/min
M3_H = 1.0 / 3600.0  # [m³/s] per m³/h


def flow_rate_inputs(case: dict, source: str) -> None:
    """Convert a 1D case's process-engineering inputs to the model's, in place (at the edge).

    ``[mesh] diameter`` D [m] of a round column sets ``area`` = π D²/4 (and is then dropped: the
    resolved case holds the area). An inlet's ``flow_rates_l_min`` [L/min] or ``flow_rates_m3_h``
    [m³/h] become its ``velocities`` [m/s], the superficial velocity Q/A over the bottom
    cross-section A (the inlet's face), so the resolved case and everything after it hold SI
    velocities only. CaseError for a diameter with an ``area`` given too, a tapered column, or a
    flow rate beside velocities/porosities or on a boundary that is not an inlet.

    >>> case = {"mesh": {"diameter": 0.05, "area": 1.0, "area_top": -1.0},
    ...         "boundary": {"bottom": {"kind": "inlet", "times": [0.0], "velocities": [], "porosities": [],
    ...                                 "flow_rates_l_min": [2.0], "flow_rates_m3_h": []},
    ...                      "top": {"kind": "outlet", "velocities": [], "porosities": [],
    ...                              "flow_rates_l_min": [], "flow_rates_m3_h": []}}}
    >>> flow_rate_inputs(case, "bed.toml")
    >>> round(case["mesh"]["area"], 8), round(case["boundary"]["bottom"]["velocities"][0], 6)
    (0.0019635, 0.016977)
    """
    mesh = case["mesh"]
    d = mesh.get("diameter", -1.0)
    if d != -1.0:
        if not d > 0.0:
            raise CaseError(source, "[mesh] diameter", f"{d!r} must be > 0 [m] (the column's inner diameter), "
                            "or -1: not given")
        if mesh["area"] != 1.0 or mesh.get("area_top", -1.0) != -1.0:
            raise CaseError(source, "[mesh] diameter", "give the cross-section by one of diameter [m] (a round "
                            "column) or area/area_top [m²], not both")
        mesh["area"], mesh["diameter"] = float(np.pi * d * d / 4.0), -1.0
    for end, b in case["boundary"].items():
        given = [(k, f) for k, f in (("flow_rates_l_min", L_MIN), ("flow_rates_m3_h", M3_H)) if b.get(k)]
        if not given:
            continue
        key, factor = given[0]
        where = f"[boundary.{end}] {key}"
        if len(given) > 1 or b.get("velocities") or b.get("porosities"):
            raise CaseError(source, where, "give an inlet's schedule by one of velocities [m/s], porosities [-], "
                            "flow_rates_l_min [L/min] or flow_rates_m3_h [m³/h]")
        if b["kind"] != "inlet":
            raise CaseError(source, where, f"only an inlet takes a flow rate (kind = {b['kind']!r})")
        b["velocities"] = [float(q) * factor / mesh["area"] for q in b[key]]
        b[key] = []


def column_diameter(area: float) -> float:
    """Inner diameter [m] of a round column of cross-section ``area`` [m²]: sqrt(4 A/π).

    >>> round(column_diameter(np.pi * 0.05**2 / 4), 12)
    0.05
    """
    return float(np.sqrt(4.0 * area / np.pi))


def richardson_zaki_1954_exponent(re_t, d_over_D=0.0):
    """Richardson & Zaki's (1954) exponent k [-] of U = U_i n^k, with their wall-effect term d/D.

    Re_t = ρ_f U_t d/μ_f of one particle at its terminal velocity; d/D particle over column diameter:

    ========================  ============================
    Re_t ≤ 0.2                k = 4.65 + 19.5 d/D
    0.2 < Re_t ≤ 1            k = (4.35 + 17.5 d/D) Re_t^−0.03
    1 < Re_t ≤ 200            k = (4.45 + 18 d/D) Re_t^−0.1
    200 < Re_t ≤ 500          k = 4.45 Re_t^−0.1
    Re_t > 500                k = 2.39
    ========================  ============================

    (their equations 33, 37, 38, 39 and 34). The wall raises k: 0.5 mm glass beads in water
    (Re_t ≈ 40) in a 50 mm column have k = 3.20 where Khan & Richardson's (1989) correlation without
    the wall term (:func:`twofluid.closures.drag.khan_richardson_exponent`) gives 2.98.

    >>> round(float(richardson_zaki_1954_exponent(40.0, 0.01)), 2), round(float(richardson_zaki_1954_exponent(40.0)), 2)
    (3.2, 3.08)
    >>> [round(float(richardson_zaki_1954_exponent(r)), 3) for r in (0.1, 0.5, 300.0, 1000.0)]
    [4.65, 4.441, 2.516, 2.39]

    Reference: Richardson, J. F., Zaki, W. N. (1954). Sedimentation and fluidisation: part I.
    Trans. Inst. Chem. Eng. 32, 35–53.
    """
    re_t = np.asarray(re_t, dtype=float)
    w = np.asarray(d_over_D, dtype=float)
    return np.select([re_t <= 0.2, re_t <= 1.0, re_t <= 200.0, re_t <= 500.0],
                     [4.65 + 19.5 * w, (4.35 + 17.5 * w) * re_t ** -0.03, (4.45 + 18.0 * w) * re_t ** -0.1,
                      4.45 * re_t ** -0.1 + 0.0 * w], 2.39 + 0.0 * w)


def volume_below(mesh, h: float) -> float:
    """Column volume [m³] between the bottom and the height ``h`` [m] above it (area linear per element).

    >>> from twofluid.mesh.line import uniform_line
    >>> round(volume_below(uniform_line(2.0, 2, area=(1.0, 3.0)), 1.5), 12)  # 1.5 + (2 + 2.5)/2 · 0.5
    2.625
    """
    y = mesh.y - mesh.y[0]
    x = np.clip(h - y[:-1], 0.0, mesh.lengths)  # length of each element below h
    slope = mesh.area_slope
    return float((mesh.area[:-1] * x + 0.5 * slope * x * x).sum())


def height_of_volume(mesh, volume: float) -> float:
    """Height [m] above the bottom below which the column holds ``volume`` [m³] (its length if more)."""
    total = float(mesh.volumes.sum())
    length = float(mesh.y[-1] - mesh.y[0])
    if volume >= total:
        return length
    return float(brentq(lambda h: volume_below(mesh, h) - volume, 0.0, length, xtol=1e-15, rtol=1e-14))


def bed_porosity(mesh, n: float, h: float) -> np.ndarray:
    """Element porosities of a uniform bed at ``n`` up to ``h`` [m] with clear liquid above.

    The element cut by the surface holds the solids of its part below ``h``:
    1 − n_e = (1 − n) × (its volume below h)/(its volume).

    >>> from twofluid.mesh.line import uniform_line
    >>> [round(float(x), 12) for x in bed_porosity(uniform_line(1.0, 4), 0.6, 0.6)]
    [0.6, 0.6, 0.84, 1.0]
    """
    y = mesh.y - mesh.y[0]
    x = np.clip(h - y[:-1], 0.0, mesh.lengths)
    below = mesh.area[:-1] * x + 0.5 * mesh.area_slope * x * x
    frac = below / mesh.volumes
    frac = np.where(np.abs(frac - 1.0) < 1e-12, 1.0, np.where(frac < 1e-12, 0.0, frac))  # faces stay faces
    return 1.0 - (1.0 - n) * frac


def fluidized_porosity(clo, mat, u: float, source: str = "<case>") -> float:
    """Porosity [-] at which the superficial velocity ``u`` [m/s] holds a uniform bed (the case's drag law).

    Inverts :func:`~twofluid.closures.drag.steady_fluidization_velocity`, which grows with n
    from 0 to the terminal velocity U_t.
    """
    key = "[initial] state = 'fluidized'"

    def U(n):
        return clo.fluidization_velocity(n, mat)

    if not u > 0.0:
        raise CaseError(source, key, f"needs an upward inlet velocity at t = 0 (got {u:g} m/s)")
    lo, hi = 1e-3, 1.0 - 1e-9
    try:
        u_lo, u_hi = U(lo), U(hi)
    except ValueError as exc:
        raise CaseError(source, key, f"no fluidization velocity for these particles ({exc})") from None
    if not u_lo < u < u_hi:
        raise CaseError(source, key, f"the inlet velocity at t = 0 ({u:.4g} m/s) is outside the fluidized "
                        f"range {u_lo:.3g}–{u_hi:.4g} m/s of the drag law (up to the terminal velocity)")
    return float(brentq(lambda n: U(n) - u, lo, hi, xtol=1e-14, rtol=1e-13))


def packed_porosity(case: dict) -> float:
    """Porosity n_mf [-] of the case's packed bed: ``[initial] settled_porosity`` (0.4 unless given).

    The bed of a fluidization curve below minimum fluidization, and the porosity at which the
    minimum fluidization velocity U_mf is taken (:func:`bed_figures`).
    """
    return float(case["initial"].get("settled_porosity", 0.4))


def _bed_state(clo, mat, u: float, n_mf: float) -> float:
    """Porosity [-] of a uniform bed in the superficial velocity ``u`` [m/s]: packed at ``n_mf`` below
    the fluidization velocity there, else the porosity the drag law fluidizes at ``u``."""
    if u <= clo.fluidization_velocity(n_mf, mat):
        return n_mf
    return fluidized_porosity(clo, mat, u)


def bed_figures(mesh, case: dict, clo, mat, u0: float, u_end: float | None) -> dict:
    """What a process engineer checks first about a 1D bed, with definitions (summary.json "bed").

    U_mf: the superficial velocity at which the case's drag law at the packed porosity n_mf
    (:func:`packed_porosity`) carries the bed's buoyant weight (beside Wen & Yu's (1966)
    correlation); U_t: the terminal velocity of one particle with the same law (without the model's slip saturation); the initial
    porosity and height (:func:`initial_bed`); and, for the last inlet velocity ``u_end``
    [m/s], the uniform bed's porosity and height by Richardson & Zaki (U = U_t n^k, k of Khan &
    Richardson, U_t as above), by Richardson & Zaki's own 1954 correlation with the wall term
    (U = U_i n^k, k of :func:`richardson_zaki_1954_exponent` at d/D, log10 U_i = log10 U_t − d/D,
    their equation 41; D the diameter of a round column of the bottom cross-section,
    :func:`column_diameter`) and by the model's own equilibrium (the drag law).
    Heights [m] hold the initial solids volume over the column's cross-section.
    """
    from ..closures import drag as drag_laws

    n0, h0, n_el = initial_bed(mesh, case, clo, mat, u0, warn=False)
    solids = float(((1.0 - n_el) * mesh.volumes).sum())
    n_mf = packed_porosity(case)
    out = {"initial_porosity": n0, "initial_height_m": h0, "packed_porosity_n_mf": n_mf}
    if not mat.rho_s > mat.rho_f:
        return out
    ar = float(drag_laws.archimedes_number(mat.d, mat.rho_s, mat.rho_f, mat.mu_f, mat.g))
    k = float(drag_laws.khan_richardson_exponent(ar))
    try:
        u_mf = clo.fluidization_velocity(n_mf, mat)
        u_t = drag_laws.terminal_velocity(clo.drag, mat.d, mat.rho_s, mat.rho_f, mat.mu_f, mat.g,
                                          **clo.drag_params)
    except ValueError:
        return out
    d_over_D = float(mat.d) / column_diameter(float(mesh.area[0]))
    k54 = float(richardson_zaki_1954_exponent(mat.rho_f * u_t * mat.d / mat.mu_f, d_over_D))
    u_i = u_t * 10.0 ** -d_over_D
    out.update({
        "column_diameter_m": column_diameter(float(mesh.area[0])), "particle_to_column_diameter": d_over_D,
        "richardson_zaki_exponent_1954_wall": k54, "richardson_zaki_intercept_1954_wall_m_s": u_i,
        "U_mf_m_s": u_mf, "U_mf_wen_yu_m_s": drag_laws.wen_yu_minimum_fluidization_velocity(
            mat.d, mat.rho_s, mat.rho_f, mat.mu_f, mat.g),
        "U_t_m_s": u_t, "archimedes_number": ar, "richardson_zaki_exponent_khan_richardson": k,
        "definitions": (
            "U_mf: superficial velocity at which the case's drag law at the packed porosity n_mf "
            "([initial] settled_porosity) carries the buoyant weight of the bed; U_mf_wen_yu: Wen & Yu "
            "(1966); U_t: terminal velocity of one particle with the case's drag law; expanded bed at "
            "the last inlet velocity U: Richardson-Zaki n = (U/U_t)^(1/k), k of Khan & Richardson (1989); "
            "richardson_zaki_1954_wall: n = (U/U_i)^(1/k), k and U_i of Richardson & Zaki (1954) with the wall "
            "term d/D (D: a round column of the bottom cross-section); and the model's own uniform equilibrium (the drag law); packed at n_mf below U_mf; heights "
            "hold the initial solids volume")})
    if u_end is not None and u_end > 0.0:
        exp = {"inlet_velocity_m_s": u_end}
        n_rz = min(max((u_end / u_t) ** (1.0 / k), n_mf), 1.0)  # packed below U_t n_mf^k
        n_54 = min(max((u_end / u_i) ** (1.0 / k54), n_mf), 1.0)
        try:
            n_model = _bed_state(clo, mat, u_end, n_mf)
        except CaseError:  # carried away (above U_t)
            n_model = 1.0
        for name, n in (("richardson_zaki", n_rz), ("richardson_zaki_1954_wall", n_54), ("model", n_model)):
            exp[name] = {"porosity": n, "height_m": height_of_volume(mesh, solids / (1.0 - n)) if n < 1.0
                         else None}
        out["expanded"] = exp
    return out


def equilibrium_warning(case: dict, clo, mat, n: float, u0: float) -> str | None:
    """A warning line when a bed given by its porosity ``n`` starts out of equilibrium with the
    inlet velocity ``u0`` [m/s] at t = 0 (it then expands or contracts as the run starts), else None.

    A fluidized bed (n above the packed porosity) is in equilibrium where the drag law holds it at
    ``u0`` to 1 %; a packed bed (n ≤ n_mf + 0.01) where ``u0`` does not lift it.
    """
    if not (mat.rho_s > mat.rho_f and u0 > 0.0 and 0.0 < n < 1.0):
        return None
    try:
        u_n = clo.fluidization_velocity(n, mat)
    except ValueError:
        return None
    packed = n <= packed_porosity(case) + 0.01
    if (packed and u0 <= u_n * 1.01) or abs(u0 - u_n) <= 0.01 * u_n:
        return None
    src = case.get("_source", "<case>")
    what = "expands" if u0 > u_n else "contracts"
    return (f"{src}: [initial] porosity: the bed starts at porosity {n:.4g}, which the inlet velocity at t = 0 "
            f"({u0:.4g} m/s) does not hold (the drag law holds it at {u_n:.4g} m/s), so the bed {what} as the "
            "run starts; state = \"fluidized\" starts it in equilibrium with the inlet")


def initial_bed(mesh, case: dict, clo, mat, u0: float, warn: bool = True) -> tuple[float, float, np.ndarray]:
    """(bed porosity, bed height [m], element porosities) of the case's ``[initial]`` section.

    ``u0`` [m/s]: the inlet velocity into the column at t = 0. With ``state = "fluidized"`` the
    bed is the uniform bed that velocity holds: fluidized at the drag law's porosity above the
    minimum fluidization velocity, packed at ``settled_porosity`` below it. A bed given by its
    porosity that ``u0`` does not hold gets a warning (:func:`equilibrium_warning`) if ``warn``.
    """
    init, src = case["initial"], case.get("_source", "<case>")
    if init["state"] == "fluidized":
        n_mf = packed_porosity(case)
        packed = u0 > 0.0 and mat.rho_s > mat.rho_f and u0 <= clo.fluidization_velocity(n_mf, mat)
        n = n_mf if packed else fluidized_porosity(clo, mat, u0, src)
    else:
        n = init["porosity"]
        line = equilibrium_warning(case, clo, mat, n, u0) if warn else None
        if line is not None:
            warnings.warn(CaseWarning(line), stacklevel=3)
    length = float(mesh.y[-1] - mesh.y[0])
    if init["solids_mass"] > 0.0 or init["settled_height"] > 0.0:
        if init["solids_mass"] > 0.0:
            vs, key = init["solids_mass"] / mat.rho_s, "solids_mass"
        else:
            vs = (1.0 - init["settled_porosity"]) * volume_below(mesh, init["settled_height"])
            key = "settled_height"
        if vs > (1.0 - n) * float(mesh.volumes.sum()) * (1.0 + 1e-12):
            raise CaseError(src, f"[initial] {key}", f"the solids ({vs:.4g} m³) do not fit in the column at "
                            f"porosity {n:.4g} (room for {(1.0 - n) * mesh.volumes.sum():.4g} m³)")
        h = height_of_volume(mesh, vs / (1.0 - n))
        return n, h, bed_porosity(mesh, n, h)
    if init["bed_height"] <= 0:
        return n, length, np.full(mesh.n_elements, n)
    # a height fills the elements whose centres lie below it (the surface on an element face:
    # a cut element would start as a dilute layer out of balance on the bed), and says so
    h = init["bed_height"]
    inside = mesh.centres - mesh.y[0] < h
    used = float(mesh.y[int(inside.sum())] - mesh.y[0])
    if abs(used - h) > 1e-9 * max(h, 1e-3):
        warnings.warn(CaseWarning(
            f"{src}: [initial] bed_height: {h:g} m is not on an element face; the bed fills the elements "
            f"whose centres lie below it, up to {used:g} m (solids_mass or settled_height place the "
            "surface exactly)"), stacklevel=3)
    return n, used, np.where(inside, n, 1.0)
