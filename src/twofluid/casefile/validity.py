"""Warnings for a 1D or 2D case whose initial or inlet state lies outside its drag law's validity.

Each drag law in the registry states the porosity and particle Reynolds number
range where it holds (:class:`~twofluid.closures.registry.Closure`, and for its
Stokes limit ``stokes = true`` a Reynolds number below 1). A case is checked at
the states it sets up: the porosity of the initial bed and of the inlet schedule,
the particle Reynolds number Re = ρ_f U d/μ_f of a bed at rest in each inlet
velocity U (there n|U_f − U_s| = U), and that of a single particle settling at
its terminal velocity U_t, which any particle reaches once it is alone (above a
bed surface, in a settling column). Each breach is one
:class:`~twofluid.casefile.schema.CaseWarning` naming the key and the range; the
run goes on.
"""
from __future__ import annotations

import warnings

from ..closures import drag as drag_laws
from ..closures.registry import get
from .schema import CaseWarning

__all__ = ["drag_validity_warnings"]


def drag_validity_warnings(case: dict, clo, mat, inlet_velocities, porosities=None) -> list[str]:
    """The warning lines for ``case`` (and issue them as CaseWarning); ``[]`` when all is in range.

    ``clo``, ``mat``: the case's :class:`Closures` and :class:`Materials`; ``inlet_velocities``:
    the resolved inlet schedule [m/s]; ``porosities``: the porosities the case starts or feeds a
    bed at (default: those of a 1D case's ``[initial]`` and end boundaries).

    >>> from twofluid.casefile.loader import load_case
    >>> from twofluid.casefile.builder import build
    >>> c = load_case("fluidized-bed-step")
    >>> b = build(c)
    >>> drag_validity_warnings(c, b.model.clo, b.model.mat, b.inlet_velocities)
    []
    """
    d = case["closures"]["drag"]
    law = get("drag", d["law"])
    src = case.get("_source", "<case>")
    key = f"[closures.drag] law = {d['law']!r}" + (", stokes = true" if d["stokes"] else "")
    out = []
    lo, hi = law.porosity_range
    if porosities is None:
        porosities = [case["initial"]["porosity"]] if case["initial"]["state"] != "fluidized" else []
        for end in ("bottom", "top"):
            porosities += case["boundary"][end]["porosities"]
    bad = [n for n in porosities if not lo <= n <= hi]
    if bad:
        out.append(f"{src}: {key}: valid for porosities {lo:g}–{hi:g}, but the case starts or feeds "
                   f"a bed at {', '.join(f'{n:g}' for n in bad)}")
    re_lo, re_hi = law.valid_reynolds(d["stokes"])
    to_re = mat.rho_f * mat.d / mat.mu_f
    states = [(abs(u) * to_re, f"a bed in the inlet velocity {abs(u):.3g} m/s") for u in inlet_velocities]
    try:
        u_t = drag_laws.terminal_velocity(clo.saturated_drag, mat.d, mat.rho_s, mat.rho_f, mat.mu_f, mat.g,
                                          **clo.drag_params)
        states.append((u_t * to_re, f"a single particle settling at U_t = {u_t:.3g} m/s"))
    except ValueError:  # no dilute limit (Ergun alone) or particles that do not sink
        pass
    worst = max(states, default=None, key=lambda s: s[0])
    if worst is not None and not re_lo <= worst[0] <= re_hi:
        fix = "; set stokes = false" if d["stokes"] else ""
        out.append(f"{src}: {key}: valid for particle Reynolds numbers {re_lo:g}–{re_hi:g}, but "
                   f"{worst[1]} has Re = {worst[0]:.3g}{fix}")
    for line in out:
        warnings.warn(CaseWarning(line), stacklevel=3)
    return out
