"""The viscometer's reading of a 2D run: torque on the spindle and the apparent viscosity from it.

For an axisymmetric case with swirl and a turning ``rotating_wall`` (the spindle):
:func:`single_fluid` for the ``[single_fluid]`` check (given viscosity against the
reading) and :func:`mixture` for the two-fluid state (reading against the Mooney–Pringle
fit at the bed's porosity, and the share of the meridional circulation). The numerics
are in :mod:`twofluid.models.spindle`.
"""
from __future__ import annotations

import numpy as np

from ..casefile.schema_2d import BOUNDARY_NAMES

__all__ = ["spindle", "single_fluid", "mixture"]


def spindle(case: dict):
    """(mesh group, ω) of the first turning rotating wall of an axisymmetric case with swirl, or None."""
    if not (case["mesh"]["axisymmetric"] and case["mesh"]["swirl"]):
        return None
    for name in BOUNDARY_NAMES:
        b = case["boundary"][name]
        if b["kind"] == "rotating_wall" and b["omega"] != 0.0:
            return b["group"] or name, b["omega"]
    return None


_TORQUE_DEFINITION = (
    "torque the spindle (the rotating wall) exerts on the contents over its whole circumference [N·m], "
    "positive with ω: the moment about the axis of the swirl reactions at its nodes (the consistent "
    "value of ∫ r τ_rθ dA over the wetted side plus ∫ r τ_zθ dA over the tip); tip_torque: the tip's "
    "share. The apparent viscosity is the Couette relation T = 4π μ ω L r_i² r_o²/(r_o² − r_i²) "
    "applied to the torque on a measuring section of the side (section_m, one gap width from the "
    "tip and from the top, as a guard-ring viscometer: end effects excluded); "
    "whole_spindle_over_couette_of_wetted_side is the end effect a plain reading would carry")


#: porosity above which a row of the gap counts as clear liquid (the bed's surface is below it)
CLEAR_ROW = 0.95


def _bed_surface(mesh, n, nodes, vol) -> float | None:
    """Bottom of the lowest element row of the gap (r > r_i, above the spindle's lowest side node)
    whose volume-mean porosity exceeds CLEAR_ROW, or None (the bed fills the gap)."""
    xy = mesh.points[mesh.cells]
    r_i = mesh.points[nodes, 0].max()
    z_side = mesh.points[nodes][np.abs(mesh.points[nodes, 0] - r_i) <= 1e-9 * r_i, 1].min()
    gap = (xy[:, :, 0].min(axis=1) >= r_i - 1e-12) & (xy[:, :, 1].min(axis=1) >= z_side - 1e-12)
    z0 = np.round(xy[:, :, 1].min(axis=1), 12)
    rows = np.unique(z0[gap])
    for z in rows:
        e = gap & (z0 == z)
        if (n[e] * vol[e]).sum() / vol[e].sum() > CLEAR_ROW:
            return float(z)
    return None


def single_fluid(mesh, res, found, mu: float) -> dict:
    """Torque on the spindle and apparent viscosity of the single-fluid Stokes solution ``res``."""
    from ..models.spindle import spindle_torque

    group, omega = found
    nodes = mesh.boundary_nodes(group)
    out = spindle_torque(mesh.points, nodes, res.reaction[nodes, 2], omega)
    out["given_viscosity_Pa_s"] = mu
    out["apparent_over_given_minus_1"] = out["apparent_viscosity_Pa_s"] / mu - 1.0
    out["definition"] = _TORQUE_DEFINITION
    return out


def mixture(case: dict, model, state) -> dict | None:
    """What the viscometer reads on the mixture: torque, apparent viscosity, Mooney, circulation's share.

    The apparent viscosity of the measuring section is compared with the Mooney–Pringle
    mixture viscosity at the section's mean porosity and with the viscosity a Couette
    viscometer would read from the section's porosity layers (Mooney per element,
    arithmetic mean along z per radial column, the 1/r³ series rule across).
    The meridional circulation's share of the torque: the torque minus that of the same
    porosity field with the meridional velocities suppressed
    (:func:`~twofluid.models.spindle.swirl_without_circulation`), over the torque.
    """
    from ..closures.viscosity import mooney_pringle
    from ..models.spindle import (couette_viscosity, mixture_swirl_reaction, spindle_section, spindle_torque,
                                  swirl_without_circulation)

    found = spindle(case)
    if found is None or not model.clo.viscous:
        return None
    group, omega = found
    mesh = model.mesh
    nodes = mesh.boundary_nodes(group)
    xy = mesh.points[mesh.cells]
    r_lo, r_hi = xy[:, :, 0].min(axis=1), xy[:, :, 0].max(axis=1)
    zc = xy[:, :, 1].mean(axis=1)
    surface = _bed_surface(mesh, state.n, nodes, model.vol)
    geo = spindle_section(mesh.points, nodes, surface)
    out = spindle_torque(mesh.points, nodes, mixture_swirl_reaction(model, state)[nodes], omega, geo)
    calm = swirl_without_circulation(model, state)
    still = spindle_torque(mesh.points, nodes, mixture_swirl_reaction(model, calm)[nodes], omega, geo)
    sec = (r_lo >= geo.r_i - 1e-12) & (zc > geo.z_a) & (zc < geo.z_b)
    if not sec.any():
        raise ValueError(f"no elements in the measuring section z = {geo.z_a:g}–{geo.z_b:g} m")
    mu_el = mooney_pringle(state.n, model.mat.mu_f, **model.clo.viscosity_params)
    edges = np.unique(np.round(np.concatenate([r_lo[sec], r_hi[sec]]), 12))
    col = np.searchsorted(edges, np.round(r_lo[sec], 12))
    mu_col = np.bincount(col, weights=mu_el[sec] * model.vol[sec], minlength=edges.size - 1) \
        / np.bincount(col, weights=model.vol[sec], minlength=edges.size - 1)
    n_mean = float((state.n[sec] * model.vol[sec]).sum() / model.vol[sec].sum())
    mu_mean = float(mooney_pringle(n_mean, model.mat.mu_f, **model.clo.viscosity_params))
    mu_layers = couette_viscosity(edges, mu_col)
    out.update({
        "section_porosity_mean": n_mean,
        "section_porosity_range": [float(state.n[sec].min()), float(state.n[sec].max())],
        "mooney_viscosity_at_mean_porosity_Pa_s": mu_mean,
        "mooney_viscosity_of_section_layers_Pa_s": mu_layers,
        "apparent_over_mooney_at_mean_porosity": out["apparent_viscosity_Pa_s"] / mu_mean,
        "apparent_over_mooney_of_layers": out["apparent_viscosity_Pa_s"] / mu_layers,
        "without_meridional_flow": {"torque_N_m": still["torque_N_m"],
                                    "section_torque_N_m": still["section_torque_N_m"],
                                    "apparent_viscosity_Pa_s": still["apparent_viscosity_Pa_s"]},
        "circulation_share_of_torque": 1.0 - still["torque_N_m"] / out["torque_N_m"],
        "circulation_share_of_section_torque": 1.0 - still["section_torque_N_m"] / out["section_torque_N_m"],
        "bed_surface_m": surface,
        "definition": _TORQUE_DEFINITION + ". Mixture: the wetted side ends at the bed's surface in the gap "
        f"(bottom of the lowest row with mean porosity above {CLEAR_ROW}); the steady reaction of the "
        "mixture's swirl rows (liquid and solids stresses together); Mooney–Pringle viscosity at the section's mean porosity "
        "(volume weighted) and the reading of its porosity layers (Mooney per element, mean along z, "
        "1/r³ series rule across the gap); circulation share = 1 − torque of the same porosity field "
        "with the meridional velocities suppressed (swirl rows solved alone, steady) / torque",
    })
    return out
