"""K_α: the hysteretic element under a static shear bias against Idriss & Boulanger (2008).

Compared quantity: the model's CRR ratio CRR(α)/CRR(0), CRR the uniform-cycle CSR that liquefies
the element in 15 cycles (r_u ≥ 0.98, or a single-amplitude strain of 3 % counted from the static
strain), against K_α(α, ξ_R) of the correlation at the same Dr and p′. Tolerance ±15 %.
"""
import math

import numpy as np
import pytest

from twofluid.closures import hysteretic as law
from twofluid.geotech.correlations import k_alpha_ib2003
from twofluid.models import hysteretic_sand as hs
from twofluid.models.element_test_hysteretic import element_test, model_crr


@pytest.mark.parametrize("n160cs", [10.0, 20.0])
def test_k_alpha_reproduced_at_alpha_0_1(n160cs):
    ratio = model_crr(n160cs=n160cs, alpha=0.1) / model_crr(n160cs=n160cs)
    k_a = float(k_alpha_ib2003(0.1, 100.0 * math.sqrt(n160cs / 46.0), 100e3 * (1.0 + 2.0 * hs.K0) / 3.0))
    assert abs(ratio / k_a - 1.0) <= 0.15, (ratio, k_a)


def test_biased_test_starts_from_static_strain_and_rides_on_tau_s():
    r = element_test(csr=0.12, n160cs=10.0, alpha=0.1, max_cycles=40)
    assert r.gamma[0] > 0.0 and r.tau[0] == pytest.approx(0.1 * 100e3, rel=1e-9)
    # the stress cycles about τ_s: its mean over the first full cycle is the static stress
    k = 101
    assert np.mean(r.tau[1:k]) == pytest.approx(0.1 * 100e3, rel=1e-3)
    assert np.isfinite(r.cycles)


def test_static_state_refuses_a_stress_above_strength():
    par = hs.parameters(sigma_v0=[100e3], n160cs=10.0)
    st = law.new_state(1, par)
    assert math.isnan(law.static_state(st, par, 0, 100e3 * par[0, law.P_TANPHI] * 1.001, 100e3))
    assert st[0, law.S_G] == 0.0  # left untouched


def test_k_alpha_leaves_level_ground_and_crust_alone():
    par = hs.parameters(sigma_v0=[100e3, 50e3], n160cs=10.0, g_max_fixed=[0.0, 40e6])
    out = hs.apply_k_alpha(par, [0.0, 0.1])
    np.testing.assert_array_equal(out, par)


def test_biased_element_carries_its_static_shear_for_the_flow_rule(monkeypatch):
    """The element test gives the law its static shear (P_TAUS) as the column does, so the
    flow-liquefaction rule (no dilation on the side of a static shear above S_r) is the column's."""
    from twofluid.models import element_test_hysteretic as et

    seen = {}
    real = et.hk.element_cycles

    def spy(st, par, *args, **kw):
        seen["taus"] = float(par[0, law.P_TAUS])
        return real(st, par, *args, **kw)

    monkeypatch.setattr(et.hk, "element_cycles", spy)
    element_test(csr=0.12, n160cs=10.0, alpha=0.1, max_cycles=2)
    assert seen["taus"] == pytest.approx(0.1 * 100e3, rel=1e-12)
    element_test(csr=0.12, n160cs=10.0, max_cycles=2)
    assert seen["taus"] == 0.0
