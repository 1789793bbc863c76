"""Terzaghi check: a preloaded deposit gets a further load on its drained top.

Deposit: sand-like spheres (d = 0.2 mm, ρ_s = 2650 kg/m³) in water, n = 0.4, 1 m
deep, 100 elements, impervious wall at the bottom, drained outlet at the top,
Kozeny–Carman drag (Ergun, Stokes limit), P_s exponential with A = 0.015, no
viscous stress. It starts at rest under a surcharge q0 = 1 MPa on the solids at
the top (n̄ per element such that P_s carries q0 plus the buoyant weight above;
the self-weight, 10 kPa, makes c_v vary by 1 % over the depth), and at t = 0 the
surcharge rises by Δq = 10 kPa (1 %, so P_s is effectively linear). The solids flux
is the Galerkin one (``solids_flux = "galerkin"``): the loaded top face moves with
the skeleton (small strain), whereas the upwind flux would take the solids that
the top element sends down from the clear liquid "above" the fixed outlet (none),
so the top of the deposit would loosen instead of consolidating.

The average degree of consolidation from the computed pore pressure,
U = 1 − ∫(P − P⁰) dy / (Δq H) with P⁰ the pressure before loading, is compared
with Terzaghi's U(T_v), T_v = c_v t/H², c_v the depth average of
:func:`~twofluid.verification.terzaghi.consolidation_coefficient` at the state
half-way through the load (P_s + Δq/2). Relative error, tolerance 2 %.

The surcharge (a solids pressure on the top face, drained liquid) is an option of
:class:`~twofluid.models.reduced_1d.Reduced1D`; for the full model this module
adds it through :class:`LoadedTwoFluid1D` (one traction term in the mixture row).
"""
from __future__ import annotations

import numpy as np

from ..closures.solids_pressure import reference_porosity_for
from ..models.reduced_1d import Reduced1D
from ..models.two_fluid_1d import TwoFluid1D
from . import terzaghi
from ..casefile.builder import build
from .runs import case_from, run_history

__all__ = ["LoadedTwoFluid1D", "consolidation_rows", "TOL"]

TOL = 0.02
T_V = (0.05, 0.1, 0.2, 0.5, 1.0)


class LoadedTwoFluid1D(TwoFluid1D):
    """The full 1D model with a solids surcharge [Pa] on the top face (drained liquid)."""

    def __init__(self, *args, surcharge: float = 0.0, **kw):
        super().__init__(*args, **kw)
        self.surcharge = float(surcharge)

    def assemble(self, k, old, dt, t_new):
        S = super().assemble(k, old, dt, t_new)
        S.add_rhs("V", np.array([self.vert_node[-1]]), np.array([-self.surcharge * self.vert_area[-1]]))
        return S


def consolidation_rows(elements: int = 100, q0: float = 1e6, dq: float = 1e4, n: float = 0.4,
                       H: float = 1.0, dT: float = 1e-3, model: str = "reduced_1d") -> list[dict]:
    """Run the loaded deposit and compare U(T_v) at :data:`T_V` (module docstring)."""
    A = 0.015
    case = case_from({
        "case": {"name": "terzaghi", "model": "two_fluid_1d"},
        "materials": {"liquid_density": 1000.0, "liquid_viscosity": 1e-3, "particle_density": 2650.0,
                      "particle_diameter": 2e-4},
        "closures": {"drag": {"law": "ergun", "stokes": True},
                     "solids_pressure": {"compressibility": A}, "viscosity": {"law": "none"}},
        "mesh": {"length": H, "elements": elements},
        "initial": {"porosity": n},
        "boundary": {"bottom": {"kind": "wall"}, "top": {"kind": "outlet"}},
        "numerics": {"solids_flux": "galerkin"},
        "time": {"end": 1.0, "step": 1.0}})
    b = build(case)
    m0 = b.model
    ps0 = m0.settled_solids_pressure(b.state.n) + q0
    state = b.state.copy(n_bar=reference_porosity_for(b.state.n, ps0, A, m0.clo.p_ref))
    beta = m0.clo.drag(state.n, 0.0, m0.mat.d, m0.mat.rho_f, m0.mat.mu_f, **m0.clo.drag_params)
    mid_nbar = reference_porosity_for(state.n, ps0 + 0.5 * dq, A, m0.clo.p_ref)
    c_v = float(np.mean(terzaghi.consolidation_coefficient(state.n, mid_nbar, ps0 + 0.5 * dq, A, beta)))
    args = (m0.mesh, m0.mat, m0.clo, m0.bottom, m0.top)
    kw = {"solids_flux": "galerkin"}
    if model == "reduced_1d":
        m = Reduced1D(*args, surcharge=q0 + dq, **kw)
        P0 = m.recover_pressure(state, state, 1.0)
    else:
        m = LoadedTwoFluid1D(*args, surcharge=q0 + dq, **kw)
        P0 = m0.top.pressure - m0.mat.rho_f * m0.g_y * (H - m0.mesh.centres)  # discrete hydrostatic
    state = state.copy(P=P0)
    t_scale = H * H / c_v
    stops = [T * t_scale for T in T_V]
    vol = m.volumes
    case["time"].update(end=stops[-1], step=dT * t_scale)
    h = run_history(case, {"U": lambda mm, s: 1.0 - float(((s.P - P0) * vol).sum()) / (dq * vol.sum())},
                    state=state, model=m, t_end=stops[-1], stops=stops)
    rows = []
    for T, ts in zip(T_V, stops):
        i = int(np.argmin(np.abs(h.t - ts)))
        ref = float(terzaghi.average_degree(T))
        err = abs(h.values["U"][i] - ref) / ref
        rows.append({"check": f"Terzaghi consolidation ({'reduced' if model == 'reduced_1d' else 'full'} model)",
                     "quantity": f"U(T_v = {T:g})", "unit": "-", "reference": ref,
                     "computed": float(h.values["U"][i]), "error": err, "tolerance": TOL,
                     "error_kind": "relative", "pass": bool(err <= TOL)})
    return rows
