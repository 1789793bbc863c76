"""Reference-porosity laws (Byrne 1991; thesis ANN): byrne against the per-cycle law, ann against byrne."""
from __future__ import annotations

import json

import numpy as np
import pytest

from twofluid.closures import registry
from twofluid.closures import reference_porosity as rp
from twofluid.models.element_test import cyclic_simple_shear


def run_path(law, gammas, n_bar0=0.45, state=None, **params):
    """Drive a law along a strain path (one or more elements); return n̄ history and state."""
    gammas = np.asarray(gammas, dtype=float)
    state = state or rp.ShearState.zeros(gammas.shape[1:], gamma=gammas[0])
    n_bar = np.full(gammas.shape[1:], n_bar0)
    history = [n_bar]
    for prev, new in zip(gammas[:-1], gammas[1:]):
        n_bar, state = law(new - prev, new, n_bar, state, **params)
        history.append(n_bar)
    return np.array(history), state


def one_cycle(gamma_a, steps):
    """Strain path of one full cycle starting at the reversal point −γ_a."""
    return -gamma_a * np.cos(np.linspace(0.0, 2.0 * np.pi, steps + 1))


@pytest.mark.parametrize("gamma_a, eps0", [(1e-4, 0.0), (1e-3, 2e-3), (5e-3, 5e-2)])
def test_byrne_uniform_cycle_reproduces_per_cycle_law(gamma_a, eps0):
    c1, c2 = rp.byrne_constants(40.0)
    path = one_cycle(gamma_a, 4000)
    # history so far: strain came up to −γ_a (a reversal), ε_v already eps0
    state = rp.ShearState(np.array([eps0]), np.array([gamma_a]), np.array([-gamma_a]),
                          np.array([-1.0]), np.array([0.0]))
    _, end = run_path(rp.byrne, path[:, None], state=state, dr=40.0)
    deps = end.eps_v[0] - eps0
    assert end.path[0] == pytest.approx(4.0 * gamma_a, rel=1e-6)
    # the per-cycle law, with ε_v at the cycle's middle (ε_v moves within the cycle)
    mid = eps0 + 0.5 * deps
    assert deps == pytest.approx(c1 * gamma_a * np.exp(-c2 * mid / gamma_a), rel=0.01)
    # and the exact integral of dε_v = (C1/4) exp(−C2 ε_v/γ_a)|dγ| over |dγ| = 4γ_a
    exact = gamma_a / c2 * np.log(np.exp(c2 * eps0 / gamma_a) + c1 * c2)
    assert end.eps_v[0] == pytest.approx(exact, rel=1e-9)


def test_byrne_per_cycle_law_late_in_the_test():
    # once ε_v is large the within-cycle change is small: start-of-cycle value is enough
    c1, c2 = rp.byrne_constants(60.0)
    gamma_a, eps0 = 2e-3, 0.03
    state = rp.ShearState(np.array([eps0]), np.array([gamma_a]), np.array([-gamma_a]),
                          np.array([-1.0]), np.array([0.0]))
    _, end = run_path(rp.byrne, one_cycle(gamma_a, 2000)[:, None], state=state, dr=60.0)
    assert end.eps_v[0] - eps0 == pytest.approx(c1 * gamma_a * np.exp(-c2 * eps0 / gamma_a),
                                                rel=0.02)


def test_byrne_step_size_independent_and_dn_bar_law():
    path = 1e-3 * np.sin(np.linspace(0.0, 6 * np.pi, 601))
    fine = 1e-3 * np.sin(np.linspace(0.0, 6 * np.pi, 6001))
    nb, st = run_path(rp.byrne, path[:, None], dr=45.0)
    nb_f, st_f = run_path(rp.byrne, fine[:, None], dr=45.0)
    assert st.eps_v[0] == pytest.approx(st_f.eps_v[0], rel=2e-3)
    # dn̄ = −(1 − n̄) dε_v integrates to 1 − n̄ = (1 − n̄0) exp(ε_v)
    assert 1.0 - nb[-1, 0] == pytest.approx((1.0 - 0.45) * np.exp(st.eps_v[0]), rel=1e-12)


def test_byrne_peak_resets_at_reversal():
    # up to 2e-3, back down to 1e-3: the peak since the reversal is the turning point
    _, st = run_path(rp.byrne, np.array([0.0, 1e-3, 2e-3, 1.5e-3, 1e-3])[:, None])
    assert st.gamma_a[0] == pytest.approx(2e-3)
    assert st.direction[0] == -1.0
    # then up again past zero on the other side: reversal at 1e-3 then |γ| grows to 3e-3
    _, st = run_path(rp.byrne, np.array([0.0, 2e-3, 1e-3, -1e-3, 1e-3, 3e-3])[:, None])
    assert st.gamma_a[0] == pytest.approx(3e-3)


def test_n_bar_never_increases_and_vectorised():
    rng = np.random.default_rng(1)
    paths = np.cumsum(rng.normal(0.0, 2e-4, (500, 4)), axis=0)
    paths[:, 3] = 0.0  # an unsheared element keeps its n̄
    for law in (rp.byrne, rp.ann):
        hist, _ = run_path(law, paths)
        assert np.all(np.diff(hist, axis=0) <= 0.0)
        assert np.all(hist[-1, :3] < hist[0, :3])
        assert np.all(hist[:, 3] == 0.45)


def test_byrne_densifies_more_when_looser():
    path = (1e-3 * np.sin(np.linspace(0.0, 10 * np.pi, 1001)))[:, None]
    loose, _ = run_path(rp.byrne, path, dr=35.0)
    dense, _ = run_path(rp.byrne, path, dr=70.0)
    assert loose[-1, 0] < dense[-1, 0] < 0.45
    with pytest.raises(ValueError, match="Dr"):
        rp.byrne_constants(0.0)


def test_registered_under_one_interface():
    assert {"byrne", "ann"} <= set(registry.names("reference_porosity"))
    assert registry.get("reference_porosity", "byrne").params == {"dr": rp.DR_DEFAULT}


def test_default_weights_load_with_provenance():
    w = rp.load_weights()
    assert w.hidden_weights.shape == (3, 3)
    assert w.provenance["training_law"] == "byrne"
    assert "train_ann.py" in w.provenance["generated_by"]
    assert w.output["mode"] == "strain_scaled"


@pytest.mark.parametrize("gamma_a", [3e-4, 3e-3])
def test_ann_close_to_byrne_on_held_out_element_tests(gamma_a):
    held_out = rp.load_weights().provenance["held_out"]["strain_amplitudes"]
    assert gamma_a in held_out  # not in the training set
    kw = dict(gamma_amplitude=gamma_a, max_cycles=20, stop_at_liquefaction=False)
    ref = cyclic_simple_shear(**kw)
    net = cyclic_simple_shear(**kw, law="ann")
    change_ref = ref.n_bar[0, 0] - ref.n_bar[:, 0]
    change_net = net.n_bar[0, 0] - net.n_bar[:, 0]
    # the n̄ change after every full cycle within 15 % of byrne's
    every_cycle = slice(100, None, 100)
    assert np.allclose(change_net[every_cycle], change_ref[every_cycle], rtol=0.15, atol=0.0)


def test_ann_liquefies_element_like_byrne():
    kw = dict(gamma_amplitude=np.array([1e-3, 3e-3]), max_cycles=30)
    ref = cyclic_simple_shear(**kw)
    net = cyclic_simple_shear(**kw, law="ann")
    assert np.all(net.liquefied)
    assert np.allclose(net.cycles_to_liquefaction, ref.cycles_to_liquefaction, rtol=0.2)
    assert net.cycles_to_liquefaction[1] < net.cycles_to_liquefaction[0]


def _write(tmp_path, data, name="w.json"):
    path = tmp_path / name
    path.write_text(data if isinstance(data, str) else json.dumps(data))
    return path


def test_malformed_weights_give_clear_errors(tmp_path):
    good = rp.load_weights().to_json()
    bad_json = _write(tmp_path, "{ not json", "broken.json")
    with pytest.raises(rp.AnnWeightsError, match=r"broken\.json: not valid JSON \(line 1"):
        rp.load_weights(bad_json)
    for key, value, words in [("hidden_weights", [[1.0, 2.0]], "shape"),
                              ("input_min", ["a", 1, 2], "numbers"),
                              ("input_max", good["input_min"], "input_max"),
                              ("output", {"mode": "linear"}, "mode"),
                              ("output", {"mode": "absolute", "min": 0.5, "max": 0.4}, "max")]:
        broken = dict(good, **{key: value})
        path = _write(tmp_path, broken, f"{key}.json")
        with pytest.raises(rp.AnnWeightsError, match=words) as info:
            rp.load_weights(path)
        assert str(path) in str(info.value)
    missing = {k: v for k, v in good.items() if k != "output_bias"}
    with pytest.raises(rp.AnnWeightsError, match="missing key 'output_bias'"):
        rp.load_weights(_write(tmp_path, missing, "missing.json"))


def test_thesis_style_absolute_output(tmp_path):
    data = rp.load_weights().to_json()
    data["output"] = {"mode": "absolute", "min": 0.3, "max": 0.5}
    data["output_weights"] = [3.256640, 2.570816, 2.172821]  # thesis values
    data["output_bias"] = 1.8695
    w = rp.load_weights(_write(tmp_path, data))
    nb, _ = rp.ann(np.array([1e-4]), np.array([1e-4]), np.array([0.45]),
                   rp.ShearState.zeros(1), weights=w)
    # output sigmoid of at least 1.8695 (positive weights): n̄ in the upper part of [0.3, 0.5]
    assert 0.3 + 0.2 / (1.0 + np.exp(-1.8695)) <= nb[0] <= 0.5
