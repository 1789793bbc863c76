"""Sensitivity studies (thesis tables 5.3 and 5.6): change one parameter at a time, report figures.

``twofluid sensitivity CASE --vary particle.diameter liquid.viscosity --by 10%`` runs
the base case and one case per parameter with the value multiplied by (1 + by), all as
members of one ensemble on Dask (:mod:`twofluid.ensemble.engine`), and reports each
figure with its unit for each change. Any model runs; the default figures are

- ``t1`` [s] for a 1D ``study = "step_change"``: the run summary's ``t1_s`` (2 % band,
  surface at (1 + max inlet porosity)/2);
- ``porosity_error@T`` [-] for the other 1D studies (T = end time) and 2D cases
  (``@end``: the last state): the mean over the elements of |n_perturbed − n_base| at T,
  the thesis's "mean porosity error" between the perturbed and base profiles;
- ``settlement_end_m``, ``liquefied_thickness_m``, ``peak_r_u_top_element`` for a
  ``liquefaction_1d`` case.

Any dotted path into summary.json is a figure too (``--figure base_excess_pore_pressure.peak_Pa``).
A change that moves other inputs is said in the report: varying ``initial.porosity``
moves the inlet's first porosity with it (the bed starts at rest), and a change of the
particles or liquid with inlet *porosities* changes the inlet *velocities* that
fluidize them (and, in a liquefaction case, the hydraulic conductivity).
"""
from __future__ import annotations

import csv
import re
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .casefile.case import sections
from .casefile.loader import load_case
from .casefile.schema import CaseError, revalidate
from .ensemble.members import Member, case_hash
from .ensemble.results import settlement_notes, unit_of, with_settlement_companions

__all__ = ["ALIASES", "parse_change", "default_figures", "sensitivity_study", "Sensitivity"]

ALIASES = {
    "particle.diameter": "materials.particle_diameter", "particle.density": "materials.particle_density",
    "particle.sphericity": "materials.sphericity", "liquid.density": "materials.liquid_density",
    "liquid.viscosity": "materials.liquid_viscosity", "compressibility": "closures.solids_pressure.compressibility",
    "reference_porosity": "closures.solids_pressure.reference_porosity", "porosity": "initial.porosity",
}
_LIQUEFACTION = ["settlement_end_m", "liquefied_thickness_m", "peak_r_u_top_element"]
_DERIVED_SUMMARY = {"hydraulic_conductivity_m_s": "hydraulic conductivity"}  # inputs a run reports


def parse_change(param: str, by: str) -> tuple[str, str, float]:
    """(section, key, fraction) from ``"particle.diameter"``, ``"10%"`` (or ``"0.1"``).

    >>> parse_change("particle.diameter", "10%")
    ('materials', 'particle_diameter', 0.1)
    >>> parse_change("closures.drag.n_switch", "-5%")
    ('closures.drag', 'n_switch', -0.05)
    """
    full = ALIASES.get(param, param)
    section, _, key = full.rpartition(".")
    if not section:
        raise CaseError("<sensitivity>", param, "give a parameter as section.key, e.g. materials.particle_diameter")
    b = by.strip()
    try:
        frac = float(b[:-1]) / 100.0 if b.endswith("%") else float(b)
    except ValueError:
        frac = float("nan")
    if not (np.isfinite(frac) and frac > -1.0):
        raise CaseError("<sensitivity>", "--by", f"{by!r} is not a valid change; valid: a number > -1 or "
                        "a percentage > -100 %, e.g. 10% or -0.05")
    return section, key, frac


def default_figures(case: dict) -> list[str]:
    """The figures a study of ``case`` reports when none is asked for.

    >>> default_figures(load_case("liquefaction-elcentro"))
    ['settlement_end_m', 'liquefied_thickness_m', 'peak_r_u_top_element']
    >>> default_figures(load_case("settling-illite"))
    ['porosity_error@300']
    """
    model = case["case"]["model"]
    if model == "liquefaction_1d":
        return list(_LIQUEFACTION)
    if model == "two_fluid_2d":
        return ["porosity_error@end"]
    return ["t1"] if case["case"].get("study") == "step_change" else [f"porosity_error@{case['time']['end']:g}"]


def _check_figure(figure: str, case: dict, source: str) -> str:
    """The summary path (or profile path) a figure is collected as; CaseError before any run."""
    if figure == "t1":
        if case["case"].get("study") != "step_change":
            raise CaseError(source, "--figure", "t1 needs a case with [case] study = \"step_change\"; "
                            "use porosity_error@T or a summary figure for this one")
        return "t1_s"
    if figure.startswith("porosity_error@"):
        when = figure.split("@", 1)[1]
        end = case["time"]["end"]
        if when != "end":
            try:
                T = float(when)
            except ValueError:
                T = float("nan")
            if not 0.0 < T <= end:
                raise CaseError(source, "--figure", f"{figure!r}: the time must be a number in (0, {end:g}] s "
                                "(the case's end time) or 'end'")
        return f"profile.porosity@{when}"
    if re.fullmatch(r"[A-Za-z_]\w*(\.\w+)*", figure):
        return figure
    raise CaseError(source, "--figure", f"unknown key figure {figure!r}; valid: t1, porosity_error@T or a "
                    "dotted path into summary.json, e.g. settlement_end_m")


def _linked(case: dict, section: str, key: str) -> dict:
    """Keys moved with a change of [section] key: the inlet's first porosity follows the bed's."""
    if section == "initial" and key == "porosity" and case.get("boundary", {}).get("bottom", {}).get("porosities"):
        por = case["boundary"]["bottom"]["porosities"]
        return {"boundary.bottom.porosities": [case[section][key]] + list(por[1:])}
    return {}


def _inlet_velocities(case: dict) -> dict[str, list]:
    """{section: inlet velocities [m/s]} of the inlets given by porosities (1D and 2D)."""
    from .casefile.builder import closures, inlet_velocities, materials

    out = {}
    for where, b in sections(case).items():
        if where.startswith("boundary") and isinstance(b, dict) and b.get("kind") == "inlet" and b.get("porosities"):
            try:
                mat = materials(case)
                out[where] = [float(v) for v in inlet_velocities(b, closures(case, mat), mat)]
            except (KeyError, ValueError, ArithmeticError):  # an inlet the helper cannot resolve: not reported
                continue
    return out


def _perturbed(base: dict, source: str, section: str, key: str, frac: float) -> tuple[dict, float, dict]:
    """(the case with [section] key times 1 + frac, re-validated; the base value; the linked changes)."""
    import copy

    from .ensemble.members import locate

    case = copy.deepcopy(base)
    try:
        node, name = locate(case, f"{section}.{key}")
    except LookupError as exc:
        raise CaseError(source, f"[{section}] {key}", f"no such parameter in this case (--vary): {exc}") from None
    v0 = node[name]
    if isinstance(v0, bool) or not isinstance(v0, (int, float)):
        raise CaseError(source, f"[{section}] {key}", f"is not a number ({v0!r}): it cannot be varied")
    value = v0 * (1.0 + frac)
    node[name] = int(round(value)) if isinstance(v0, int) else value
    links = _linked(case, section, key)
    for k, v in links.items():
        node, name = locate(case, k)
        node[name] = v
    try:
        return revalidate(case, source), v0, links
    except CaseError as exc:
        detail = str(exc)[len(f"{exc.source}: {exc.key}: "):]
        raise CaseError(exc.source, exc.key, f"{detail} (after the change {100 * frac:+g} % of "
                        f"[{section}] {key} = {v0:g})") from None


@dataclass
class Sensitivity:
    """Rows of a study: one per (parameter, figure) with the base and changed values."""

    case: str
    figures: list
    base: dict  # figure -> base value
    rows: list = field(default_factory=list)
    notes: list = field(default_factory=list)  # "changing X also changes Y"

    def markdown(self) -> str:
        lines = [f"Sensitivity of case {self.case}", "",
                 "| parameter | base value | changed value | change | figure [unit] | base | changed | "
                 "change of figure |", "|---|---|---|---|---|---|---|---|"]
        for r in self.rows:
            fmt = (lambda v: "n/a" if v is None else f"{v:.5g}")
            rel = r["figure_change"]
            rel = "n/a" if rel is None else (f"{rel:.4g} (mean abs.)" if r["figure"].startswith("porosity_error")
                                             else f"{100 * rel:+.2f} %")
            lines.append(f"| {r['parameter']} | {r['base_value']:.5g} | {r['value']:.5g} | {100 * r['fraction']:+g} % "
                         f"| {r['figure']} [{r['unit']}] | {fmt(r['figure_base'])} | {fmt(r['figure_value'])} | {rel} |")
        lines += [""] + [f"- {n}" for n in self.notes] if self.notes else []
        return "\n".join(lines)

    def write_csv(self, path) -> None:
        cols = ["parameter", "base_value", "value", "fraction", "figure", "unit", "figure_base", "figure_value",
                "figure_change", "status", "also_changes"]
        with open(path, "w", newline="", encoding="utf-8") as fh:
            w = csv.DictWriter(fh, cols, extrasaction="ignore")
            w.writeheader()
            w.writerows(self.rows)


def _also_changes(base: dict, case: dict, links: dict, base_row: dict, row: dict) -> list[str]:
    def text(v):
        return "[" + ", ".join(f"{x:.6g}" for x in v) + "]" if isinstance(v, list) else f"{v:.6g}"

    out = [f"[{k.rpartition('.')[0]}] {k.rpartition('.')[2]} = {text(v)}" for k, v in links.items()]
    vb, vc = _inlet_velocities(base), _inlet_velocities(case)
    for where in vc:
        if where in vb and not np.allclose(vb[where], vc[where], rtol=1e-12, atol=0.0):
            out.append(f"[{where}] inlet velocities {', '.join(f'{v:.4g}' for v in vb[where])} -> "
                       f"{', '.join(f'{v:.4g}' for v in vc[where])} m/s")
    for key, name in _DERIVED_SUMMARY.items():
        b, c = base_row.get(key), row.get(key)
        if isinstance(b, (int, float)) and isinstance(c, (int, float)) and not np.isclose(b, c, rtol=1e-12, atol=0):
            out.append(f"{name} {b:.4g} -> {c:.4g} {unit_of(key)}")
    return out


def sensitivity_study(case_name: str, changes: list[tuple[str, str, float]], figure=None,
                      csv_path: str | Path | None = None, workers: int | None = None, scheduler: str | None = None,
                      out_dir: str | Path | None = None, progress: bool = False, client=None) -> Sensitivity:
    """Run the base case and one changed case per entry of ``changes`` on the ensemble engine.

    ``figure``: a figure name or a list of them (default :func:`default_figures`). Every change
    is checked (a known key, a number, a valid changed case) before anything runs. With
    ``out_dir`` the members' table is kept there (and a rerun reuses completed members).
    """
    from .ensemble.engine import run_members
    from .ensemble.members import locate

    base = load_case(case_name)
    source = base.get("_source", case_name)
    base["output"]["plots"] = False
    figures = [figure] if isinstance(figure, str) else list(figure or default_figures(base))
    paths = {f: _check_figure(f, base, source) for f in figures}
    times = {float(p.split("@")[1]) for p in paths.values() if p.startswith("profile.") and not p.endswith("@end")}
    if times:  # the run stops at the figure's time, with a profile there (as the thesis's error)
        base["time"]["end"] = max(times)
        base["output"]["times"] = sorted(times | {t for t in base["output"]["times"] if t <= max(times)})
        base = revalidate(base, source)
    cases = [_perturbed(base, source, s, k, f) for s, k, f in changes]
    members = [Member(0, {}, base, case_hash(base))]
    members += [Member(i + 1, {"parameter": f"{s}.{k}", "fraction": f}, c, case_hash(c))
                for i, ((s, k, f), (c, _, _)) in enumerate(zip(changes, cases))]
    collect = list(dict.fromkeys([*with_settlement_companions(list(paths.values())), *_DERIVED_SUMMARY]))
    with tempfile.TemporaryDirectory(prefix="twofluid-sensitivity-") as tmp:
        rows, _ = run_members(members, collect, out_dir or tmp, workers=workers, scheduler=scheduler,
                              progress=progress, client=client)
    b = rows[0]
    res = Sensitivity(base["case"]["name"], figures, {})
    if b["status"] != "completed":
        res.notes.append(f"the base case did not complete: {b['reason']}")
    for f in figures:
        res.base[f] = 0.0 if f.startswith("porosity_error") else b.get(paths[f])
    for (s, k, frac), (case, v0, links), row in zip(changes, cases, rows[1:]):
        also = _also_changes(base, case, links, b, row)
        if also:
            res.notes.append(f"changing [{s}] {k} by {100 * frac:+g} % also changes " + "; ".join(also))
        if row["status"] != "completed":
            res.notes.append(f"[{s}] {k} {100 * frac:+g} %: the run {row['status']}: {row['reason']}")
        for f in figures:
            val, f0 = row.get(paths[f]), res.base[f]
            if f.startswith("porosity_error"):
                n, n0 = row.get(paths[f]), b.get(paths[f])
                val = float(np.mean(np.abs(np.asarray(n) - np.asarray(n0)))) if n and n0 else None
                change = val
            else:
                change = (val - f0) / f0 if isinstance(val, (int, float)) and isinstance(f0, (int, float)) \
                    and f0 != 0 else None
            node, name = locate(case, f"{s}.{k}")
            res.rows.append({"parameter": f"{s}.{k}", "base_value": v0, "value": node[name], "fraction": frac,
                             "figure": f, "unit": unit_of(paths[f]), "figure_base": f0,
                             "figure_value": val, "figure_change": change, "status": row["status"],
                             "also_changes": "; ".join(also)})
    res.notes += settlement_notes(rows, [paths[f] for f in figures])
    if csv_path:
        res.write_csv(csv_path)
    return res
