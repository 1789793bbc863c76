"""Cyclic simple-shear element test (Byrne 1991 densification; the calibration of docs/liquefaction.md)."""
from __future__ import annotations

import json
from dataclasses import replace

import numpy as np
import pytest

from twofluid.closures.solids_pressure import exponential
from twofluid.models.element_test import (DEFAULT_SAND, cyclic_simple_shear,
                                          run_element_test)


def test_undrained_element_liquefies():
    r = cyclic_simple_shear(gamma_amplitude=2e-3, max_cycles=20)
    assert r.liquefied[0]
    assert r.r_u[-1, 0] >= 0.95
    # undrained: porosity never moves, P_s follows n̄ through the pressure law
    assert np.all(r.porosity == DEFAULT_SAND.porosity)
    assert np.allclose(r.p_s, exponential(r.porosity, r.n_bar, DEFAULT_SAND.A), rtol=1e-12)
    assert r.p_s[0, 0] == pytest.approx(100e3, rel=1e-12)
    assert np.all(np.diff(r.p_s[:, 0]) <= 0.0)


def test_drained_element_builds_no_excess_pressure():
    r = cyclic_simple_shear(gamma_amplitude=2e-3, max_cycles=10, drained=True)
    assert not r.liquefied[0]
    assert np.allclose(r.r_u, 0.0, atol=1e-12)
    # the skeleton still densifies: n̄ and n fall together
    assert r.n_bar[-1, 0] < r.n_bar[0, 0]
    assert r.porosity[-1, 0] < r.porosity[0, 0]
    assert np.allclose(exponential(r.porosity, r.n_bar, DEFAULT_SAND.A), 100e3, rtol=1e-9)


def test_cycles_fall_as_strain_amplitude_grows():
    r = cyclic_simple_shear(gamma_amplitude=np.array([6e-4, 1e-3, 2e-3, 5e-3]), max_cycles=80)
    n = r.cycles_to_liquefaction
    assert np.all(np.isfinite(n))
    assert np.all(np.diff(n) < 0.0)


def test_cycles_fall_as_relative_density_falls():
    counts = [cyclic_simple_shear(gamma_amplitude=1e-3, max_cycles=80,
                                  sand=replace(DEFAULT_SAND, dr=dr)).cycles_to_liquefaction[0]
              for dr in (60.0, 47.0, 35.0)]
    assert np.all(np.isfinite(counts[1:]))
    assert counts[0] > counts[1] > counts[2]


def test_calibrated_sand_liquefies_in_about_15_cycles():
    r = cyclic_simple_shear(csr=0.12, sigma_v0=100e3, max_cycles=40)
    assert 12.0 <= r.cycles_to_liquefaction[0] <= 18.0
    # and the count is a converged property of the model, not of the time step
    coarse = cyclic_simple_shear(csr=0.12, max_cycles=40, steps_per_cycle=50)
    assert coarse.cycles_to_liquefaction[0] == pytest.approx(r.cycles_to_liquefaction[0], rel=0.03)


def test_stress_controlled_loading_follows_the_backbone():
    r = cyclic_simple_shear(csr=np.array([0.10, 0.15]), max_cycles=60)
    # τ is the prescribed sinusoid until liquefaction
    assert np.allclose(r.tau[:, 0], 0.10 * 100e3 * np.sin(2 * np.pi * r.cycles), atol=1e-6)
    # γ from τ = G_max(P_s) γ/(1 + |γ|/γ_ref) with P_s of the previous step
    gmax = 218.8e3 * 30.0 * np.sqrt(r.p_s[:-1, 0] / 1e3)
    expect = r.tau[1:, 0] / (gmax - np.abs(r.tau[1:, 0]) / 1e-3)
    live = np.abs(r.gamma[1:, 0]) < 0.1
    assert np.allclose(r.gamma[1:, 0][live], expect[live], rtol=1e-9, atol=1e-15)
    # a larger stress ratio liquefies sooner
    assert r.cycles_to_liquefaction[1] < r.cycles_to_liquefaction[0]


def test_run_element_test_writes_outputs(tmp_path):
    r = run_element_test(gamma_amplitude=3e-3, max_cycles=5, out_dir=tmp_path)
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["liquefied"] is True
    assert summary["cycles_to_liquefaction"] == pytest.approx(r.cycles_to_liquefaction[0])
    table = np.loadtxt(tmp_path / "element_test.csv", delimiter=",", skiprows=1)
    assert table.shape == (r.cycles.size, 7)
    assert np.allclose(table[:, 6], r.r_u[:, 0], atol=1e-8)
    assert (tmp_path / "element_test.png").stat().st_size > 10_000


def test_bad_arguments():
    with pytest.raises(ValueError, match="exactly one"):
        cyclic_simple_shear(csr=0.1, gamma_amplitude=1e-3)
    with pytest.raises(ValueError, match="exactly one"):
        cyclic_simple_shear()
