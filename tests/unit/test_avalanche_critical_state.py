"""What sets the immersed avalanche's two unmet onsets (φ0 = 0.571 and 0.578): the critical state.

The late plateau of φ0 = 0.568 fixes the steady viscous number I* through the steady flow alone
(u_s = I* Δρ g cos θ φ* h*²/(2 η_f), φ* = φ_eq(I*)), whatever friction law carries it: so the
steady solid fraction φ* = φ_c/(1 + √I*) is the data's and φ_c's, not the fit's. A creeping dense
layer looser than φ_c is held by its suction at φ ≈ φ_eq of its own rate, so its velocity is
(φ_c/φ0 − 1)² Δρ g cos θ φ0 h²/(2 η_f) to within its profile, whatever K, the permeability or the
nonlocal amplitude. These checks pin the diagnosis the validation's strict xfails state
(docs/avalanche.md, "What the unmet onsets need").
"""
import math

import numpy as np
import pytest

from twofluid.casefile.loader import load_case
from twofluid.runners.avalanche import layer_of
from twofluid.verification import pailha2008 as data

CASE = "immersed-avalanche"


def _case(**rheology):
    c = load_case(CASE)
    c["closures"]["granular_rheology"].update(rheology)
    return c


@pytest.mark.parametrize("i_0", [0.002, 0.004, 0.008])
def test_the_late_plateau_fixes_the_steady_fraction_above_0571_whatever_mu_s_and_i0(i_0):
    """Refitting μ_s on the plateau (the declared closed form) with I_0 halved or doubled leaves I*
    and φ* = φ_eq(I*) as they are, and φ* stays above 0.571: 0.571 is looser than the steady state
    under any admissible (μ_s, I_0), so it contracts first. φ* reaches 0.571 only at
    φ_c = 0.571 (1 + √I*) ≈ 0.5838."""
    ref = _case()
    _, iv_ref, ph_ref = data.steady_surface_velocity(ref, 0.568, mu_s=data.calibrate_mu_s(ref))
    case = _case(i_0=i_0)
    mu_s = data.calibrate_mu_s(case)
    v, iv, ph = data.steady_surface_velocity(case, 0.568, mu_s=mu_s)
    assert v == pytest.approx(data.plateau_velocity(0.568), rel=1e-5)
    assert iv == pytest.approx(iv_ref, rel=1e-4) and ph == pytest.approx(ph_ref, abs=1e-7)
    assert ph > 0.571 + 1e-3
    phi_c_needed = 0.571 * (1.0 + math.sqrt(iv))
    assert 0.583 < phi_c_needed < 0.5845 < ref["closures"]["granular_rheology"]["phi_c"]


def _creep(phi0, t, rheology=None, constant=None, amplitude=None, elements=12):
    c = _case(**(rheology or {}))
    if constant is not None:
        c["closures"]["permeability"]["constant"] = constant
    if amplitude is not None:
        c["closures"]["granular_rheology"]["amplitude"] = amplitude
    lay = layer_of(c, phi0, elements)
    return np.array([s.surface_velocity for s in lay.run(np.asarray(t, dtype=float), rtol=1e-7, max_step=2.0)])


def test_dense_creep_before_onset_is_set_by_phi_c_not_by_k_the_permeability_or_the_nonlocal_length():
    """φ0 = 0.578 at 5 and 10 s: the creep is within 30 % of the critical-state estimate
    (φ_c/φ0 − 1)² Δρ g cos θ φ0 h²/(2 η_f) (above it: the suction adds to P_s, and the layer has
    dilated a little since t = 0), and K = 4.09 against the fitted 9.97, Carman–Kozeny's
    C = 150 against 180 and the local law against the nonlocal one each move it by less than 10 %.
    The measured 0.10 mm/s is 35 % below the model's: only φ_c (or the φ_eq law) can close it."""
    c = _case()
    ma, la, rh = c["materials"], c["layer"], c["closures"]["granular_rheology"]
    phi0, t = 0.578, [0.0, 5.0, 10.0]
    w = (ma["particle_density"] - ma["liquid_density"]) * ma["gravity"] * math.cos(math.radians(la["slope_deg"]))
    estimate = (rh["phi_c"] / phi0 - 1.0) ** 2 * w * phi0 * la["thickness"] ** 2 / (2.0 * ma["liquid_viscosity"])
    ref = _creep(phi0, t)[1:]
    assert np.all(np.abs(ref / estimate - 1.0) <= 0.3)
    for other in (_creep(phi0, t, rheology={"k_dil": 4.09}), _creep(phi0, t, constant=150.0),
                  _creep(phi0, t, amplitude=0.0)):
        assert np.all(np.abs(other[1:] / ref - 1.0) <= 0.10), (other, ref)
    d = data.load(phi0)
    measured = np.interp(t[1:], d["v_t"], d["v"])
    assert np.all(ref >= 1.4 * measured)
