"""The viscometer's torque and apparent viscosity converge to the exact Couette values.

1. An annulus r_i = 20 mm, r_o = 50 mm with no ends (the top and bottom free of
   swirl traction, so u_θ is circular Couette flow everywhere): the torque from the
   swirl reactions converges to 4π μ ω L r_i² r_o²/(r_o² − r_i²) at second order.
2. The bundled viscometer's single-fluid check (spindle with a tip, vessel bottom,
   inflow): the apparent viscosity of the measuring section converges with the mesh
   and is within 2 % of the given viscosity; the whole spindle's torque carries the
   end effect (tip and the flow near it) that the guard lengths keep out.
"""
import numpy as np

from twofluid.casefile.loader import load_case
from twofluid.mesh.quad import rectangle
from twofluid.models.single_fluid import solve_stokes
from twofluid.models.spindle import couette_torque, spindle_torque
from twofluid.runners.flow_2d import build_mesh, single_fluid_check
from twofluid.verification.order import observed_order

R_I, R_O, L, MU, OMEGA = 0.02, 0.05, 0.06, 1.0, 10.0


def _couette_torque_error(nr: int) -> float:
    mesh = rectangle(R_I, R_O, 0.0, L, nr, 2 * nr, axisymmetric=True)
    meridional = {"r": 0.0, "z": 0.0}
    d = {"bottom": meridional, "top": meridional, "right": {**meridional, "theta": 0.0},
         "left": {**meridional, "theta": lambda x: OMEGA * x[:, 0]}}
    res = solve_stokes(mesh, MU, d, swirl=True)
    nodes = mesh.boundary_nodes("left")
    exact = couette_torque(MU, OMEGA, L, R_I, R_O)
    out = spindle_torque(mesh.points, nodes, res.reaction[nodes, 2], OMEGA)
    return out["torque_N_m"] / exact - 1.0


def test_torque_of_couette_flow_converges_at_second_order():
    h = [1.0 / n for n in (4, 8, 16)]
    err = [abs(_couette_torque_error(n)) for n in (4, 8, 16)]
    assert err[-1] < 1e-3
    assert observed_order(h, err).rate > 1.8


def test_single_fluid_apparent_viscosity_is_within_two_percent_and_converges(tmp_path):
    case = load_case("viscometer")
    errors, ends = [], []
    for f in (0.5, 1, 2):
        case["mesh"].update(nx=int(20 * f), ny=int(64 * f))
        v = single_fluid_check(case, build_mesh(case), tmp_path, plots=False)["viscometer"]
        errors.append(v["apparent_over_given_minus_1"])
        ends.append(v["whole_spindle_over_couette_of_wetted_side"])
    assert all(abs(e) < 0.02 for e in errors)
    d = np.abs(np.diff(errors))
    assert d[1] < d[0] / 2  # converging with the mesh (second order: ≈ 4)
    # the whole spindle reads high by its end effect, which the section leaves out
    assert min(ends) > 1.0 + 2 * max(abs(e) for e in errors)
