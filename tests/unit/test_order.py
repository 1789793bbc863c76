"""Tests of the observed-order fit (verification/order.py).

Tolerances: exact power laws recovered to 1e-12; a noisy power law (±2 %
multiplicative noise, fixed seed) to 0.05 in the rate.
"""

import numpy as np
import pytest

from twofluid.verification.order import observed_order, pairwise_orders


@pytest.mark.parametrize("p,C", [(1.0, 3.0), (2.0, 0.5), (1.5, 1e-3), (4.0, 7.0)])
def test_exact_power_law_is_recovered(p, C):
    h = 0.2 / 2.0 ** np.arange(5)
    res = observed_order(h, C * h**p)
    assert res.rate == pytest.approx(p, rel=1e-12)
    assert res.constant == pytest.approx(C, rel=1e-10)
    assert np.allclose(res.pairwise, p, rtol=1e-12)


def test_noisy_power_law_and_non_uniform_refinement():
    rng = np.random.default_rng(12345)
    h = np.array([0.1, 0.07, 0.04, 0.025, 0.011, 0.006])
    err = 2.0 * h**2 * (1 + 0.02 * rng.uniform(-1, 1, h.size))
    assert observed_order(h, err).rate == pytest.approx(2.0, abs=0.05)


def test_pairwise_shows_pre_asymptotic_levels():
    h = 0.1 / 2.0 ** np.arange(4)
    err = h**2 + 10 * h**3  # third-order pollution fades as h falls
    rates = pairwise_orders(h, err)
    assert np.all(np.diff(rates) < 0) and rates[-1] == pytest.approx(2.0, abs=0.2)
    assert rates[0] > 2.3


@pytest.mark.parametrize("h,err", [([0.1], [1.0]), ([0.1, 0.05], [1.0]), ([0.1, 0.05], [1.0, 0.0]),
                                   ([0.1, -0.05], [1.0, 0.5]), ([0.1, 0.1], [1.0, 0.5])])
def test_bad_input_raises(h, err):
    with pytest.raises(ValueError):
        observed_order(h, err)
