"""What an engineer reads from a liquefaction run, besides the time loop's own records.

- :func:`initial_consolidation_coefficient` — c_v of the initial state, per element;
- :func:`final_settlement` — the settlement the column will reach once the remaining excess pore
  pressure has dissipated, from the skeleton law at fixed n̄ (the constrained modulus, integrated);
  :func:`settlement_fields` — whether the settlement a run reached is final, beside the final one;
- :func:`sand_boil` — a quick surface after the shaking (when, how long, upward seepage);
- :func:`spectra` — 5 %-damped response spectra of the input and of the surface, and their ratio;
- :func:`simplified_rows` — the simplified procedure (Idriss & Boulanger 2008, 2014) on the same
  profile, per element of the column; :func:`dr_notes` — where its Dr is not the one entered, and why.

Depths are from the ground surface throughout.
"""
from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from ..geotech import response_spectrum, simplified_procedure
from ..postprocess import median
from .liquefaction_damage import DAMAGE_COLUMNS

__all__ = ["dr_notes", "initial_consolidation_coefficient", "final_settlement", "final_contributions", "settlement_fields",
           "FINAL_FRACTION", "sand_boil", "spectra", "simplified_rows", "simplified_method", "DEFAULT_PERIODS", "G"]

G = 9.80665  # standard gravity [m/s²]: accelerations reported in g
DEFAULT_PERIODS = np.logspace(np.log10(0.02), np.log10(5.0), 60)


def initial_consolidation_coefficient(col, excess_ratio: float = 0.0) -> np.ndarray:
    """c_v = k M/(ρ_f g) = n² M/β [m²/s] of the column's initial state, per saturated element.

    M = P_s (1 − n̄)/(A (1 − n)) is the constrained modulus (docs/liquefaction.md), β the drag at zero
    slip; all of the state the run starts from, rebuilt from what the run does not change: the
    initial porosity ``col.n0``, σ′_v0 ``col.sigma_v0``, P_s = (1 − r_u0) σ′_v0 (``excess_ratio``,
    ``[site] initial_excess_ratio``) and n̄ = 1 − (1 − n)(1 − A ln(P_s/p_ref)) (the column's
    ``initial_state``). So the value does not depend on how long the run went on.
    """
    from ..closures.solids_pressure import reference_porosity_for
    from ..verification.terzaghi import consolidation_coefficient

    v = col.v
    n0 = np.asarray(col.n0, dtype=float)
    ps = (1.0 - excess_ratio) * np.asarray(col.sigma_v0, dtype=float)
    n_bar = reference_porosity_for(n0, ps, v.clo.A, v.clo.p_ref)
    beta = v.clo.drag(n0, 0.0, v.mat.d, v.mat.rho_f, v.mat.mu_f, **v.clo.drag_params)
    return consolidation_coefficient(n0, n_bar, ps, v.clo.A, beta)


def final_settlement(col, s) -> tuple[float, np.ndarray]:
    """Settlement at full dissipation [m] and the per-element final porosity.

    The total vertical stress at an element does not change as it drains, so the excess pore
    pressure u_e = P − P_hydrostatic still in it ends up on the skeleton: P_s,final = P_s + u_e.
    With n̄ fixed after the shaking the skeleton law P_s = p_ref exp[(1/A)(1 − (1 − n̄)/(1 − n))]
    gives the final porosity n_f = 1 − (1 − n̄)/(1 − A ln(P_s,final/p_ref)) — the constrained
    modulus M = dP_s/dε_v = P_s (1 − n̄)/(A (1 − n)) integrated exactly, not linearised — and
    the final settlement Σ h (n0 − n_f)/(1 − n_f), the same measure as the run's.
    """
    v = s.vertical
    ps = col.granular_pressure(s)
    target = np.maximum(ps + col.excess_pressure(s), 1e-12 * np.maximum(col.sigma_v0, 1.0))
    clo = col.v.clo
    n_f = 1.0 - (1.0 - v.n_bar) / (1.0 - clo.A * np.log(target / clo.p_ref))
    h = col.v.mesh.lengths
    return float(np.sum(h * (col.n0 - n_f) / (1.0 - n_f))), n_f


def final_contributions(col, s) -> np.ndarray:
    """Each saturated element's share of :func:`final_settlement` [m]: h (n0 − n_f)/(1 − n_f)."""
    n_f = final_settlement(col, s)[1]
    return col.v.mesh.lengths * (col.n0 - n_f) / (1.0 - n_f)


#: a settlement is final once the excess pore pressure has dissipated (the run's criterion), or once the
#: run has reached this fraction of the final settlement (a run with no dissipation criterion)
FINAL_FRACTION = 0.99


def settlement_fields(reached_m: float, final_m: float, dissipated: bool, end_cap_s: float,
                      stopped_at_s: float) -> dict:
    """summary.json's statement of whether the reached settlement is final (docs/outputs.md).

    ``settlement_final``: the excess pore pressure has dissipated, or the run reached
    :data:`FINAL_FRACTION` of ``final_m`` (the settlement at full dissipation, :func:`final_settlement`);
    ``settlement_fraction_reached``: reached/final (1 where nothing is left to settle);
    ``predicted_final_settlement_m``: ``final_m``; ``end_cap_s``: the latest end ([time] end), which a run
    ends at only if the pore pressure has not dissipated by then; ``settlement_state``: one line.

    >>> f = settlement_fields(0.0737, 0.175, False, 3600.0, 3600.0)
    >>> f["settlement_final"], round(f["settlement_fraction_reached"], 3)
    (False, 0.421)
    >>> print(f["settlement_state"])
    partial: 7.37 cm reached, 42 % of the predicted final 17.5 cm (stopped at the 3600 s cap before dissipation)
    >>> print(settlement_fields(0.1, 0.1005, True, 86400.0, 812.0)["settlement_state"])
    final: 10 cm (the excess pore pressure dissipated at 812 s)
    """
    fraction = reached_m / final_m if final_m > 0.0 else 1.0
    final = bool(dissipated or fraction >= FINAL_FRACTION)
    if final:
        when = (f"the excess pore pressure dissipated at {stopped_at_s:.4g} s" if dissipated else
                f"{100.0 * fraction:.0f} % of the predicted final {100.0 * final_m:.3g} cm at {stopped_at_s:.4g} s")
        state = f"final: {100.0 * reached_m:.3g} cm ({when})"
    else:
        cap = (f"at the {end_cap_s:.6g} s cap" if stopped_at_s >= end_cap_s * (1.0 - 1e-9) else
               f"at {stopped_at_s:.6g} s, before the {end_cap_s:.6g} s cap,")
        state = (f"partial: {100.0 * reached_m:.3g} cm reached, {100.0 * fraction:.0f} % of the predicted final "
                 f"{100.0 * final_m:.3g} cm (stopped {cap} before dissipation)")
    return {"settlement_final": final, "settlement_fraction_reached": float(fraction),
            "predicted_final_settlement_m": float(final_m), "end_cap_s": float(end_cap_s),
            "settlement_state": state}


def sand_boil(t, ru_top, flux_top, shaking_end: float, ru_liq: float) -> dict:
    """A quick surface (r_u of the top saturated element above ``ru_liq``) after the shaking.

    ``t`` [s], ``ru_top`` [-] and ``flux_top`` (upward Darcy flux n (U_f − U_s) of the liquid at the
    water table [m/s]) are histories over the run's steps. Returns whether the surface went quick
    during the shaking, and after it: ``sand_boil`` (bool), its start and end [s], duration [s]
    (time spent quick) and the peak and mean upward seepage velocity while quick [m/s].

    >>> b = sand_boil([0, 1, 2, 3, 4], [0, 0.5, 0.99, 0.99, 0.2], [0, 1e-3, 2e-3, 4e-3, 1e-3], 1.5, 0.95)
    >>> b["sand_boil"], b["start_s"], b["duration_s"], b["peak_seepage_velocity_m_s"]
    (True, 2.0, 2.0, 0.004)
    """
    t, ru, q = (np.asarray(x, dtype=float) for x in (t, ru_top, flux_top))
    quick = ru > ru_liq
    during = quick & (t <= shaking_end + 1e-9)
    after = quick & (t > shaking_end + 1e-9)
    out = {"surface_liquefied_while_shaking": bool(during.any()),
           "peak_r_u_top_while_shaking": float(ru[t <= shaking_end + 1e-9].max()) if t.size else 0.0,
           "sand_boil": bool(after.any()), "start_s": None, "end_s": None, "duration_s": 0.0,
           "peak_seepage_velocity_m_s": None, "mean_seepage_velocity_m_s": None}
    if after.any():
        i = np.flatnonzero(after)
        dt = np.diff(t, prepend=t[0])
        out.update(start_s=float(t[i[0]]), end_s=float(t[i[-1]]), duration_s=float(dt[i].sum()),
                   peak_seepage_velocity_m_s=float(q[i].max()),
                   mean_seepage_velocity_m_s=float(np.sum(q[i] * dt[i]) / max(dt[i].sum(), 1e-300)))
    return out


def spectra(motion, surface_t, surface_a, periods=None, damping: float = 0.05) -> dict | None:
    """Response spectra [g] of the input record and of the surface's absolute acceleration.

    The input is the applied record (base or outcrop motion, m/s²) padded with zeros to the end
    of the surface history (the free vibration), the surface the sub-step history of the run.
    None without shaking.
    """
    if motion is None or len(surface_t) < 2:
        return None
    periods = DEFAULT_PERIODS if periods is None or len(periods) == 0 else np.asarray(periods, float)
    ts, a_s = np.asarray(surface_t, float), np.asarray(surface_a, float)
    dt_s = median(np.diff(ts))
    dt_in = float(motion.dt)
    n_in = max(motion.npts, int(round((ts[-1] - motion.time[0]) / dt_in)) + 1)
    a_in = np.zeros(n_in)
    a_in[:motion.npts] = motion.acceleration
    sa_in, _, _ = response_spectrum(a_in / G, dt_in, periods, damping)
    sa_s, _, _ = response_spectrum(np.concatenate([[0.0], a_s]) / G, dt_s, periods, damping)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(sa_in > 0.0, sa_s / np.where(sa_in > 0.0, sa_in, 1.0), np.nan)
    return {"period_s": periods, "Sa_input_g": sa_in, "Sa_surface_g": sa_s, "amplification": ratio,
            "damping": damping, "pga_input_g": float(np.abs(motion.acceleration).max() / G),
            "pga_surface_g": float(np.abs(a_s).max() / G),
            "period_of_peak_Sa_input_s": float(periods[np.argmax(sa_in)]),
            "period_of_peak_Sa_surface_s": float(periods[np.argmax(sa_s)])}


def profile_stresses(col, site, case: dict) -> dict:
    """Depth ranges, total and effective vertical stress at rest [Pa], Dr [%] and whether each
    element of the whole column (saturated, bottom first, then the crust) can liquefy."""
    ys = col.y_all
    H = col.ground_surface
    z_top, z_bot = H - ys[1:], H - ys[:-1]
    ns = col.n_sat
    layers = case["layers"]
    owner = np.concatenate([site.layer_of, site.crust_layer_of])
    u_hydro = np.concatenate([col.p_hydro - col.v.top.pressure, np.zeros(owner.size - ns)])
    sig_eff = np.empty(owner.size)
    sig_eff[:ns] = col.sigma_v0
    if owner.size > ns:  # the crust: σ′_v = σ_v = surcharge + weight above the centre
        sig_eff[ns:] = col.crust.sigma_v
    dr = np.array([layers[i]["relative_density"] for i in owner])
    liq = np.array([layers[i]["liquefiable"] for i in owner], dtype=bool)
    liq[ns:] = False
    n160 = np.array([layers[i].get("n160cs", 0.0) for i in owner], dtype=float)
    qc1n = np.array([layers[i].get("qc1ncs", 0.0) for i in owner], dtype=float)
    slope = np.array([layers[i].get("csr_n_slope", 0.0) for i in owner], dtype=float)
    return {"z_top_m": z_top, "z_bottom_m": z_bot, "sigma_v_Pa": sig_eff + u_hydro,
            "sigma_v_eff_Pa": sig_eff, "relative_density": dr, "liquefiable": liq, "layer_of": owner,
            "n160cs": n160, "qc1ncs": qc1n, "csr_n_slope": slope}


def dr_notes(case: dict, tolerance_percent: float = 0.5) -> list[str]:
    """One line per layer whose simplified-procedure Dr is not the ``relative_density`` it gives.

    The procedure takes a layer's penetration resistance where it gives one: with ``qc1ncs``,
    Dr = 100 (0.478 q_c1Ncs^0.264 − 1.063) (clipped to 5–100 %), else with ``n160cs``,
    Dr = 100 √((N1)60cs/46) (at most 100 %), and its table's Dr [%] column shows that Dr, not the
    entered one (which the hysteretic law does not use either then).

    >>> print(dr_notes({"layers": [{"name": "loose sand", "relative_density": 45.0, "n160cs": 12.0}]})[0])
    Dr of layer 'loose sand': 51 % from n160cs = 12 (Dr = 100 sqrt((N1)60cs/46)), not the relative_density of 45 % entered: the simplified procedure takes the penetration resistance where a layer gives one
    >>> dr_notes({"layers": [{"name": "x", "relative_density": 47.0, "n160cs": 0.0, "qc1ncs": 0.0}]})
    []
    """
    from ..geotech import correlations as co

    out = []
    for la in case["layers"]:
        q, n = la.get("qc1ncs", 0.0) or 0.0, la.get("n160cs", 0.0) or 0.0
        if q > 0.0:
            dr = float(np.clip(co.dr_from_qc1ncs(max(q, 1.0)), 5.0, 100.0))
            how = f"qc1ncs = {q:g} (Dr = 100 (0.478 q_c1Ncs^0.264 - 1.063))"
        elif n > 0.0:
            dr = float(min(co.dr_from_n160cs(n), 100.0))
            how = f"n160cs = {n:g} (Dr = 100 sqrt((N1)60cs/46))"
        else:
            continue
        if abs(dr - la["relative_density"]) > tolerance_percent:
            out.append(f"Dr of layer {la['name']!r}: {dr:.0f} % from {how}, not the relative_density of "
                       f"{la['relative_density']:g} % entered: the simplified procedure takes the penetration "
                       "resistance where a layer gives one")
    return out


def simplified_rows(col, site, case: dict, a_max_g: float, top_first: bool = False):
    """:func:`twofluid.geotech.simplified_procedure` per element of the column (crust: FS = inf),
    in the column's element order (saturated bottom first, then the crust), or from the ground
    surface down."""
    p = profile_stresses(col, site, case)
    if top_first:
        order = np.argsort(p["z_top_m"])
        p = {k: v[order] for k, v in p.items()}
    m = case["ground_motion"]["magnitude"]
    return simplified_procedure(p["z_top_m"], p["z_bottom_m"], p["sigma_v_Pa"], p["sigma_v_eff_Pa"],
                                p["relative_density"], p["liquefiable"], min(max(a_max_g, 0.0), 3.0), m,
                                n160cs=p["n160cs"], qc1ncs=p["qc1ncs"], csr_n_slope=p["csr_n_slope"])


def simplified_method(case: dict) -> str:
    """The summary's one-line statement of the simplified procedure, naming the penetration resistance
    its rows take: a layer's n160cs or qc1ncs where given, else (N1)60cs = 46 Dr².

    >>> simplified_method({"layers": [{"n160cs": 10.0, "qc1ncs": 0.0, "csr_n_slope": 0.0}]}).split("K_sigma, ")[1]
    'CRR from the layers n160cs; settlement: Ishihara & Yoshimine (1992)'
    """
    sources = []
    for la in case["layers"]:
        key = ("qc1ncs (CPT route of B&I 2014)" if la.get("qc1ncs", 0.0) > 0.0 else
               "n160cs" if la.get("n160cs", 0.0) > 0.0 else "(N1)60cs = 46 Dr^2")
        if key not in sources:
            sources.append(key)
    given = [k for k in sources if not k.startswith("(N1)")]
    crr = ("CRR from (N1)60cs = 46 Dr^2" if not given else
           "CRR from the layers " + " and ".join(given) + (", else (N1)60cs = 46 Dr^2" if len(given) < len(sources)
                                                            else ""))
    slope = ", MSF_max from a layer's csr_n_slope where given" if any(la.get("csr_n_slope", 0.0) > 0.0
                                                                       for la in case["layers"]) else ""
    return f"Idriss & Boulanger (2008, 2014): r_d, MSF, K_sigma, {crr}{slope}; settlement: Ishihara & Yoshimine (1992)"


ELEMENT_COLUMNS = ["depth_top_m", "depth_bottom_m", "depth_m", "layer", "saturated", "peak_r_u",
                   "time_first_liquefied_s", "peak_shear_strain", "max_settlement_contribution_m",
                   "settlement_contribution_end_m", "FS_simplified_run", "FS_simplified_input",
                   "eps_v_simplified_run", "FS_note", "settlement_contribution_final_m"] + DAMAGE_COLUMNS
#: the ``FS_note`` of a row whose FS is empty: the simplified procedure finds it cannot liquefy (not
#: liquefiable, above the water table, or no cyclic stress)
NOT_LIQUEFIABLE = "NL"


def _fs_note(*fs) -> str:
    """"NL" where a factor of safety is inf (the row cannot liquefy; written as an empty cell)."""
    return NOT_LIQUEFIABLE if any(x is not None and np.isinf(x) for x in fs) else ""


def _write_csv(path, header, rows):
    """A report table; None is an empty cell. A NaN is refused (NonFiniteOutput naming the file,
    the column and the row), never written; an inf (FS of a row that cannot liquefy,
    docs/simplified.md) is an empty cell, its reason in the row's ``FS_note`` column."""
    import csv
    import io

    from ..io.folders import create
    from ..io.results import NonFiniteOutput

    rows = [list(r) for r in rows]
    for i, r in enumerate(rows):
        for name, x in zip(header, r):
            if isinstance(x, float) and x != x:
                raise NonFiniteOutput(f"NaN in {Path(path).name}, column {name}, row {i + 1}: "
                                      "the report is not written with it")
    f = io.StringIO()
    w = csv.writer(f)
    w.writerow(header)
    for r in rows:
        w.writerow(["" if x is None or (isinstance(x, float) and np.isinf(x)) else
                    (f"{x:.8g}" if isinstance(x, float) else x) for x in r])
    with os.fdopen(create(path), "w", newline="", encoding="utf-8") as fh:
        fh.write(f.getvalue())


def _write_numbers(path, header, table) -> None:
    """:func:`_write_csv` of a table of floats (columns of one length), each row formatted by one
    ``%`` call; a NaN goes through :func:`_write_csv`, which refuses it naming where."""
    table = np.column_stack([np.asarray(c, dtype=float) for c in table])
    if np.isnan(table).any():
        return _write_csv(path, header, table.tolist())
    if np.isinf(table).any():
        return _write_csv(path, header, table.tolist())
    from ..io.folders import create

    fmt = ",".join(["%.8g"] * len(header)) + "\r\n"  # csv.writer's line end
    with os.fdopen(create(path), "w", newline="", encoding="utf-8") as f:
        f.write(",".join(header) + "\r\n" + "".join(fmt % tuple(r) for r in table.tolist()))


LAYER_COLUMNS = ["layer", "depth_top_m", "depth_bottom_m", "saturated", "liquefiable",
                 "hydraulic_conductivity_m_s", "peak_r_u", "time_first_liquefied_s", "liquefied_top_m",
                 "liquefied_bottom_m", "liquefied_thickness_m", "peak_shear_strain", "settlement_end_m",
                 "max_settlement_contribution_m", "FS_min_simplified_input", "FS_min_simplified_run",
                 "settlement_simplified_input_m", "settlement_simplified_run_m", "FS_note",
                 "predicted_final_settlement_m", "settlement_final"]


def write_tables(out, summary: dict, extra: dict, rec) -> None:
    """layers.csv (one row per layer; beside the settlement reached, the predicted final one and
    whether the run's settlement is final), elements.csv (one row per element of the column, depths
    from the ground surface, top first; beside the contribution reached, the final one), surface_motion.csv (absolute surface acceleration per
    shear sub-step) and spectra.csv (input and surface S_a and their ratio)."""
    rows = []
    for la in summary["layers"]:
        zone = la.get("liquefied_depth_range_m") or [None, None]
        rows.append([la["name"], la["depth_top_m"], la["depth_bottom_m"], "yes" if la["saturated"] else "no",
                     "yes" if la["liquefiable"] else "no", la.get("hydraulic_conductivity_m_s"),
                     la.get("peak_r_u"), la.get("time_first_liquefied_s"), zone[0], zone[1],
                     la.get("liquefied_thickness_m"), la["peak_shear_strain"], la.get("settlement_end_m", 0.0),
                     la.get("max_settlement_contribution_m", 0.0), la["simplified_min_FS_input"],
                     la["simplified_min_FS_run"], la["simplified_settlement_input_m"],
                     la["simplified_settlement_run_m"],
                     _fs_note(la["simplified_min_FS_input"], la["simplified_min_FS_run"]),
                     la.get("predicted_final_settlement_m", 0.0), "yes" if summary["settlement_final"] else "no"])
    _write_csv(out / "layers.csv", LAYER_COLUMNS, rows)
    run, inp = extra["simplified_run"], extra["simplified_input"]
    col = rec.col
    ns = col.n_sat
    names = extra["layer_names"]
    rows = []
    for e in np.argsort(run.depth_mid_m):
        wet = e < ns
        f = rec.first[e] if wet else np.nan
        rows.append([float(run.z_top_m[e]), float(run.z_bottom_m[e]), float(run.depth_mid_m[e]),
                     names[extra["owner"][e]], "yes" if wet else "no",
                     float(rec.peak[e]) if wet else None, float(f) if np.isfinite(f) else None,
                     float(rec.peak_strain[e]), float(rec.max_contribution[e]) if wet else 0.0,
                     float(rec.last_contribution[e]) if wet else 0.0,
                     float(run.FS[e]), float(inp.FS[e]), float(run.eps_v[e]),
                     _fs_note(float(run.FS[e]), float(inp.FS[e])),
                     float(extra["final_contribution"][e]) if wet else 0.0] + rec.damage.columns(int(e)))
    _write_csv(out / "elements.csv", ELEMENT_COLUMNS, rows)
    if rec.surface_t:
        _write_numbers(out / "surface_motion.csv", ["time_s", "surface_acceleration_m_s2"],
                       list(rec.surface_arrays()))
    spec = extra["spectra"]
    if spec is not None:
        _write_numbers(out / "spectra.csv", ["period_s", "Sa_input_g", "Sa_surface_g", "amplification"],
                       [spec["period_s"], spec["Sa_input_g"], spec["Sa_surface_g"], spec["amplification"]])
