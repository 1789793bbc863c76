"""Sensitivity studies (thesis tables 5.3 and 5.6): change one parameter at a time, report the key figure.

``twofluid sensitivity CASE --vary particle.diameter liquid.viscosity --by 10%`` runs
the base case and one case per parameter with the value multiplied by (1 + by),
and reports the case's key figure for each:

- ``t1`` [s] (default for ``study = "step_change"``): the run summary's t1
  (:func:`twofluid.postprocess.t1_from_history`, 2 % band, surface at
  (1 + max inlet porosity)/2);
- ``porosity_error@T`` (default for other studies, T = end time): the mean over the
  elements of |n_perturbed − n_base| at time T [s], the thesis's "mean porosity
  error" between the perturbed and base profiles.
"""
from __future__ import annotations

import csv
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from . import postprocess as pp
from .casefile.loader import load_case
from .casefile.schema import CaseError, revalidate

__all__ = ["ALIASES", "parse_change", "key_figure", "sensitivity_study", "Sensitivity"]

ALIASES = {
    "particle.diameter": "materials.particle_diameter", "particle.density": "materials.particle_density",
    "particle.sphericity": "materials.sphericity", "liquid.density": "materials.liquid_density",
    "liquid.viscosity": "materials.liquid_viscosity", "compressibility": "closures.solids_pressure.compressibility",
    "reference_porosity": "closures.solids_pressure.reference_porosity", "porosity": "initial.porosity",
}


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


def _figure_time(figure: str, case: dict, source: str) -> None:
    """Check ``figure`` before any run (CaseError naming --figure and what is valid)."""
    model = case["case"]["model"]
    if model not in ("two_fluid_1d", "reduced_1d"):
        raise CaseError(source, "[case] model", f"{model!r}: sensitivity studies run the 1D column models; "
                        "valid: 'two_fluid_1d', 'reduced_1d'")
    if figure == "t1":
        if case["case"]["study"] != "step_change":
            raise CaseError(source, "--figure", "t1 needs a case with [case] study = \"step_change\"; "
                            "use porosity_error@T for this one")
        return
    if figure.startswith("porosity_error@"):
        try:
            T = float(figure.split("@", 1)[1])
        except ValueError:
            T = float("nan")
        end = case["time"]["end"]
        if not 0.0 < T <= end:
            raise CaseError(source, "--figure", f"{figure!r}: the time must be a number in (0, {end:g}] s "
                            "(the case's end time)")
        return
    raise CaseError(source, "--figure", f"unknown key figure {figure!r}; valid: t1 or porosity_error@T")


def _revalidated(case: dict, source: str, where: str, frac: float) -> dict:
    """The perturbed case checked again through the schema (ranges and cross-key checks)."""
    try:
        return revalidate(case, source)
    except CaseError as exc:
        detail = str(exc)[len(f"{exc.source}: {exc.key}: "):]
        raise CaseError(exc.source, exc.key, f"{detail} (after the change {100 * frac:+g} % of {where})") \
            from None


def _perturbed(case_name: str, section: str, key: str, frac: float) -> tuple[dict, float]:
    """(the case with [section] key multiplied by 1 + frac and re-validated, base value)."""
    case = load_case(case_name)
    source = case.get("_source", case_name)
    case["output"]["plots"] = False
    if section not in case or key not in case[section]:
        raise CaseError(source, f"[{section}] {key}", "no such parameter in this case (--vary)")
    v0 = case[section][key]
    if isinstance(v0, bool) or not isinstance(v0, (int, float)):
        raise CaseError(source, f"[{section}] {key}", f"is not a number ({v0!r}): it cannot be varied")
    value = v0 * (1.0 + frac)
    case[section][key] = int(round(value)) if isinstance(v0, int) else value
    if section == "initial" and key == "porosity" and case["boundary.bottom"]["porosities"]:
        por = case["boundary.bottom"]["porosities"]
        case["boundary.bottom"]["porosities"] = [case[section][key]] + list(por[1:])
    return _revalidated(case, source, f"[{section}] {key} = {v0:g}", frac), v0


def key_figure(case: dict, figure: str, base_n: np.ndarray | None = None) -> tuple[float, np.ndarray]:
    """(value of ``figure``, porosity profile at the figure's time) of one run."""
    from .verification.runs import run_history

    if figure == "t1":
        thr = 0.5 * (1.0 + max(case["boundary.bottom"]["porosities"] or [case["initial"]["porosity"]]))
        h = run_history(case, {"h": lambda m, s: pp.surface_height(m.mesh.centres, s.n, thr, m.mesh.y[0])})
        return pp.t1_from_history(h.t, h.values["h"]), h.final.n
    if figure.startswith("porosity_error@"):
        T = float(figure.split("@", 1)[1])
        h = run_history(case, {}, t_end=T)
        n = h.final.n
        return (float(np.mean(np.abs(n - base_n))) if base_n is not None else 0.0), n
    raise CaseError("<sensitivity>", "--figure", f"unknown key figure {figure!r} (t1 or porosity_error@T)")


@dataclass
class Sensitivity:
    """Rows of a study: parameter, values, figure base/perturbed and its relative change."""

    case: str
    figure: str
    base: float
    rows: list = field(default_factory=list)

    def markdown(self) -> str:
        lines = [f"Sensitivity of {self.figure} for case {self.case} (base: {self.base:.5g})", "",
                 "| parameter | base value | changed value | change | figure | change of figure |",
                 "|---|---|---|---|---|---|"]
        for r in self.rows:
            rel = f"{100 * r['figure_change']:+.2f} %" if self.figure == "t1" else f"{r['figure']:.4g}"
            lines.append(f"| {r['parameter']} | {r['base_value']:.5g} | {r['value']:.5g} | "
                         f"{100 * r['fraction']:+g} % | {r['figure']:.5g} | {rel} |")
        return "\n".join(lines)

    def write_csv(self, path) -> None:
        with open(path, "w", newline="", encoding="utf-8") as fh:
            w = csv.DictWriter(fh, ["parameter", "base_value", "value", "fraction", "figure_base", "figure",
                                    "figure_change"])
            w.writeheader()
            for r in self.rows:
                w.writerow({**r, "figure_base": self.base})


def sensitivity_study(case_name: str, changes: list[tuple[str, str, float]], figure: str | None = None,
                      csv_path: str | Path | None = None) -> Sensitivity:
    """Run the base case and one perturbed case per change (module docstring)."""
    base = load_case(case_name)
    base["output"]["plots"] = False
    if figure is None:
        figure = "t1" if base["case"]["study"] == "step_change" else f"porosity_error@{base['time']['end']:g}"
    _figure_time(figure, base, base.get("_source", case_name))
    # every change checked (known key, a number, perturbed value valid) before anything runs
    cases = [(section, key, frac, *_perturbed(case_name, section, key, frac)) for section, key, frac in changes]
    f0, n0 = key_figure(base, figure)
    res = Sensitivity(base["case"]["name"], figure, f0)
    for section, key, frac, case, v0 in cases:
        f, _ = key_figure(case, figure, n0)
        change = (f - f0) / f0 if figure == "t1" else f
        res.rows.append({"parameter": f"{section}.{key}", "base_value": v0, "value": case[section][key],
                         "fraction": frac, "figure": f, "figure_change": change})
    if csv_path:
        res.write_csv(csv_path)
    return res
