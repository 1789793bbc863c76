"""Single-fluid verification of the 2D / axisymmetric Q1–P0 discretisation (thesis 4.7.3, appendix 4.3).

Viscometer annulus (thesis 4.7.3): r_i = 20 mm, r_o = 50 mm, height 60 mm,
ρ = 1600 kg/m³, μ = 1 Pa·s, ω = 10 rad/s, mean axial velocity 0.1 m/s, gravity
(see :class:`twofluid.verification.annular.Viscometer`). Exact inlet profiles
(u_z Poiseuille, u_θ Couette), outlet u_r = 0 with natural σ_zz = σ_zθ = 0, so the
exact solution is fully developed everywhere; errors are relative L2 over the
whole annulus (2πr-weighted). Meshes: nr × 2nr square elements, nr = 4, 8, 16, 32.
"""

import numpy as np
import pytest

from twofluid.mesh.quad import rectangle
from twofluid.models.single_fluid import assemble_stokes, solve_stokes
from twofluid.verification.annular import (Viscometer, annulus_study, channel_pressure_check,
                                           checkerboard_amplitude, inf_sup_constant,
                                           sector_couette_study)

LEVELS = (4, 8, 16, 32)


@pytest.fixture(scope="module")
def study():
    return annulus_study(LEVELS)


def test_annulus_errors_below_two_percent_on_thesis_like_mesh(study):
    # 8 × 16 elements (8 across the gap) — the thesis reports 1.8 % (z) and 1.6 % (θ)
    i = LEVELS.index(8)
    assert study["err_uz"][i] < 0.02
    assert study["err_utheta"][i] < 0.02


def test_annulus_velocity_converges_at_second_order(study):
    for key in ("uz", "utheta"):
        assert study[f"order_{key}"].rate >= 1.8, key
        assert np.all(study[f"order_{key}"].pairwise >= 1.8), key
    # absolute caps on the finest mesh (32 × 64), about twice the measured value
    assert study["err_uz"][-1] < 2e-3
    assert study["err_utheta"][-1] < 8e-4


def test_annulus_pressure_converges_at_first_order(study):
    # P0 pressure against the exact (hydrostatic + viscous) linear pressure
    assert study["order_p"].rate >= 0.9
    assert study["err_p"][-1] < 1.5e-2


@pytest.mark.parametrize("kind", ["local", "global"])
def test_annulus_jump_stabilisations_also_converge(kind):
    s = annulus_study((8, 16, 32), stabilisation=kind)
    assert s["order_uz"].rate >= 1.8 and s["order_utheta"].rate >= 1.8
    assert s["err_uz"][-1] < 1e-2


def test_rest_state_is_hydrostatic():
    """No inflow, no rotation: the fluid stays at rest with p = ρ g (H − z) (hydrostatic consistency)."""
    c = Viscometer()
    m = c.mesh(8)
    wall = {"r": 0.0, "z": 0.0, "theta": 0.0}
    for kind in ("checkerboard", "local", "global"):
        res = solve_stokes(m, c.mu, {"inner": wall, "outer": wall, "bottom": wall, "top": {"r": 0.0}},
                           rho=c.rho, gravity=(0.0, -c.g), swirl=True, stabilisation=kind)
        assert np.abs(res.velocity).max() < 1e-12, kind
        zc = m.points[m.cells].mean(axis=1)[:, 1]
        assert np.allclose(res.pressure, c.rho * c.g * (c.height - zc), rtol=1e-10), kind


def test_planar_couette_sector_second_order():
    s = sector_couette_study(LEVELS)
    assert s["order_u"].rate >= 1.8
    assert s["err_u"][1] < 0.02 and s["err_u"][-1] < 5e-4
    # exact pressure is zero; the stabilised P0 pressure follows at O(h²) [Pa]
    assert s["p_rms"][-1] < 2e-3


def test_checkerboard_is_a_spurious_mode_without_stabilisation():
    """Plain Q1–P0: the checkerboard s = (−1)^(i+j) is invisible to the velocity (Bᵀ s = 0)."""
    nx, ny = 8, 4
    m = rectangle(0.0, 2.0, 0.0, 1.0, nx, ny)
    bc = {"top": {"x": 0, "y": 0}, "bottom": {"x": 0, "y": 0}, "left": {"x": 1.0, "y": 0},
          "right": {"y": 0}}                                   # traction outflow on the right
    s = assemble_stokes(m, 1.0, bc, stabilisation=None)
    nu, ne = s.n_velocity, s.n_elements
    free = np.setdiff1d(np.arange(nu), s.fixed)
    Bt = s.matrix[free][:, nu:nu + ne].toarray()
    i, j = np.meshgrid(np.arange(nx), np.arange(ny))
    cb = ((-1.0) ** (i + j)).ravel()
    assert np.abs(Bt @ cb).max() < 1e-12 * np.abs(Bt).max()
    # and the stabilised system does see it
    C = -assemble_stokes(m, 1.0, bc).matrix[nu:nu + ne, nu:nu + ne]
    assert cb @ (C @ cb) > 0.1 * np.abs(C).max()


@pytest.mark.parametrize("kind", ["checkerboard", "local", "global"])
def test_stabilised_inf_sup_constant_independent_of_h(kind):
    beta = [inf_sup_constant(n, kind)[1] for n in (4, 8, 16)]
    assert min(beta) > 0.4
    # halving h changes β_h by < 15 % (an O(h) loss, as in plain Q1–P0's next mode, halves it)
    assert beta[-1] > 0.85 * beta[-2]


def test_unstabilised_inf_sup_constant_vanishes():
    assert all(inf_sup_constant(n, None)[1] < 1e-6 for n in (4, 8))


def test_channel_pressure_free_of_checkerboard():
    """Planar Poiseuille channel: element pressures against the exact linear pressure."""
    drop = 4.0                                                  # exact p(0) − p(2) [Pa]
    cb = channel_pressure_check(8, "checkerboard")
    assert cb["amplitude"] < 1e-12 * drop and cb["max_error"] < 1e-10 * drop
    for kind in ("local", "global"):
        errs = [channel_pressure_check(n, kind) for n in (4, 8, 16)]
        assert all(e["amplitude"] < 1e-12 * drop for e in errs), kind
        assert errs[-1]["max_error"] < 0.1 * drop and errs[-1]["max_error"] < 0.5 * errs[0]["max_error"]
    # without stabilisation the checkerboard amplitude is whatever round-off makes it
    # (the mode is undetermined); it is many orders above the stabilised one, or splu fails
    plain = channel_pressure_check(8, None)
    assert plain["singular"] or plain["amplitude"] > 1e6 * max(cb["amplitude"], 1e-16)
    assert checkerboard_amplitude(np.array([1.0, -1.0, -1.0, 1.0]), 2, 2) == 1.0
