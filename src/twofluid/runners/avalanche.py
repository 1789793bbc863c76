"""The runner of model ``immersed_avalanche``: one layer per initial solid fraction (docs/avalanche.md).

Files (``<k>`` is φ0 × 1000, e.g. ``568``):

- ``history_<k>.csv`` — ``time_s``, ``surface_velocity_m_s`` (the top node), ``top_element_velocity_m_s``
  (the mean of the top element's nodes), ``base_excess_pressure_Pa`` (over hydrostatic along the
  true vertical), ``thickness_m``;
- ``profiles_<k>.csv`` — at the ``[output] times``, 0 and the end: ``time_s``, ``z_m`` (element
  centre above the base), ``velocity_m_s`` (there), ``solid_fraction``, ``excess_pressure_Pa``,
  ``skeleton_pressure_Pa``, ``shear_rate_1_s``, ``tan_psi``;
- ``summary.json`` — per φ0 the onset time (surface velocity first above 0.2 mm/s), the base
  pressure at 20 s, its extremum, the solids and liquid balances and, with ``[output] compare``,
  the measured values beside them (:mod:`twofluid.verification.pailha2008`); the parameters and,
  comparing, what the declared calibration says of μ_s and K (``calibration``: K at the bound of
  its search is stated as not determined); the
  time every member reached (``stopped_at_s``) and the accepted BDF steps (``steps``, per member and
  in all).
"""
from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from ..io.results import CsvStream, write_json, write_resolved_case
from ..io.folders import default_out_dir
from ..models.avalanche_1d import AvalancheLayer
from ..verification import pailha2008 as data
from .common import RunResult, run_guard

__all__ = ["run_avalanche", "layer_of", "member_times"]

_HIST = ["time_s", "surface_velocity_m_s", "top_element_velocity_m_s", "base_excess_pressure_Pa", "thickness_m"]
_PROF = ["time_s", "z_m", "velocity_m_s", "solid_fraction", "excess_pressure_Pa", "skeleton_pressure_Pa",
         "shear_rate_1_s", "tan_psi"]


def layer_of(case: dict, phi0: float, elements: int | None = None) -> AvalancheLayer:
    """The layer of ``case`` at initial solid fraction ``phi0`` (``elements`` overrides the case's)."""
    la, ma = case["layer"], case["materials"]
    rh = {k: v for k, v in case["closures"]["granular_rheology"].items() if k not in ("law", "amplitude")}
    nonlocal_ = case["closures"]["granular_rheology"]["law"] == "boyer_pailha_nonlocal"
    return AvalancheLayer(la["thickness"], elements or la["elements"], phi0, la["slope_deg"],
                          ma["particle_density"], ma["liquid_density"], ma["liquid_viscosity"],
                          ma["particle_diameter"], ma["gravity"], rheology=rh,
                          permeability_constant=case["closures"]["permeability"]["constant"],
                          modulus=la["skeleton_modulus"], top=la["top"], grading=la["grading"],
                          nonlocal_amplitude=case["closures"]["granular_rheology"]["amplitude"] if nonlocal_ else 0.0)


def member_times(case: dict, phi0: float) -> np.ndarray:
    """History and profile times [s] of one run: 0.1 s apart to 10 s, ``samples`` to the end, the
    profile times, 20 s and (comparing) the data's times."""
    end, n = case["time"]["end"], case["output"]["samples"]
    t = [np.linspace(0.0, min(10.0, end), 101), np.linspace(0.0, end, n), [end],
         [x for x in case["output"]["times"] if x <= end], [20.0] if end >= 20.0 else []]
    if case["output"]["compare"]:
        d = data.load(phi0)
        extra = np.concatenate([d["v_t"], d["p_t"]])
        t.append(extra[(extra > 0.0) & (extra <= end)])
    return np.unique(np.concatenate([np.asarray(x, dtype=float) for x in t]))


def _member(case, phi0, out, run, offset):
    lay = layer_of(case, phi0)
    k = int(round(phi0 * 1000))
    times = member_times(case, phi0)
    prof_t = {round(x, 9) for x in [0.0, case["time"]["end"], *case["output"]["times"]]}
    hist = CsvStream(out / f"history_{k}.csv", _HIST)
    prof = CsvStream(out / f"profiles_{k}.csv", _PROF)
    rows, profiles = [], {}
    max_step = case["time"]["step"]
    try:
        for s in lay.run(times, rtol=case["time"]["rtol"], max_step=max_step):
            row = [s.t, s.surface_velocity, 0.5 * (s.u[-1] + s.u[-2]), s.base_pressure, float(s.z[-1])]
            rows.append(row)
            hist.table(np.array([row]), ["%.10g"] + ["%.8g"] * 4)
            if round(s.t, 9) in prof_t:
                zc = 0.5 * (s.z[1:] + s.z[:-1])
                uc = 0.5 * (s.u[1:] + s.u[:-1])
                tab = np.column_stack([np.full(zc.size, s.t), zc, uc, s.phi, s.p, s.p_s, s.shear_rate, s.tan_psi])
                prof.table(tab, ["%.10g"] + ["%.8g"] * 7)
                profiles[s.t] = {"z": zc, "u": uc, "phi": s.phi.copy(), "p": s.p.copy()}
            run.bar.update(offset + s.t - run.bar.n)
            last = s
    finally:
        hist.close()
        prof.close()
    h = np.array(rows)
    hd = {"t": h[:, 0], "v": h[:, 1], "p": h[:, 3]}
    liquid0 = float(lay.y0[: lay.n].sum() - lay.m.sum())
    res = {"phi0": phi0, "onset_s": data.onset(hd["t"], hd["v"]),
           "base_pressure_20s_Pa": float(np.interp(20.0, hd["t"], hd["p"])) if hd["t"][-1] >= 20.0 else None,
           "base_pressure_min_Pa": float(hd["p"].min()), "base_pressure_max_Pa": float(hd["p"].max()),
           "surface_velocity_end_m_s": float(hd["v"][-1]), "thickness_end_m": float(last.z[-1]),
           "liquid_volume_change_m": float(np.sum(np.diff(last.z)) - lay.m.sum() - liquid0),
           "solids_volume_m": float(lay.m.sum()), "steps": int(lay.steps_taken)}
    if case["output"]["compare"]:
        res["data"] = data.metrics(phi0, hd)
    return res, hd, profiles


def run_avalanche(case: dict, out_dir=None, progress: bool = False) -> RunResult:
    """Run every φ0 of ``case`` (already validated) into ``out_dir``."""
    out = Path(out_dir or default_out_dir(case))
    out.mkdir(parents=True, exist_ok=True)
    write_resolved_case(out / "case.resolved.toml", case)
    fr = case["layer"]["solid_fractions"]
    wall0 = time.perf_counter()
    members, hists, profs = [], {}, {}
    with run_guard(case["time"]["end"] * len(fr), progress) as run:
        for i, phi0 in enumerate(fr):
            res, hd, pr = _member(case, phi0, out, run, i * case["time"]["end"])
            members.append(res)
            hists[phi0], profs[phi0] = hd, pr
    rh = case["closures"]["granular_rheology"]
    summary = {"case": case["case"]["name"], "status": run.status, "reason": run.reason,
               "wall_time_s": time.perf_counter() - wall0, "elements": case["layer"]["elements"],
               "stopped_at_s": float(min(h["t"][-1] for h in hists.values())) if hists else 0.0,
               "steps": int(sum(m["steps"] for m in members)),
               "members": members,
               "onset_definition": "surface velocity first above 0.2 mm/s after the first 0.1 s (the "
                                   "undrained adjustment to the sudden inclination)",
               "parameters": {**{k: v for k, v in rh.items()},
                              "permeability": f"Carman-Kozeny, C = {case['closures']['permeability']['constant']:g}",
                              "skeleton_modulus_Pa": case["layer"]["skeleton_modulus"]}}
    if case["output"]["compare"]:
        summary["calibration"] = data.calibration_status(case)
    write_json(out / "summary.json", summary)
    if case["output"]["plots"] and hists:
        from ..plots.avalanche import avalanche_figures

        avalanche_figures(out, hists, profs, case["output"]["compare"])
    return RunResult(run.status, out, summary, profiles=profs, history=hists)
