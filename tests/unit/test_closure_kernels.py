"""The compiled closure laws (closures/kernels.py) against the registry's vectorised functions.

Both evaluate the same formula in the same order; they differ only in ``exp`` and ``pow``, which
the compiled loop takes from libm and NumPy from its SIMD routines (each within a few ulp of the
exact value). The largest amplification of such an error is the viscosity's double exponential
exp(exp(x)), by exp(x) < 5 on the fit's range, so the two agree to about 30 ulp; the bound here
is 64 ε relative. A wrong operand or coefficient in a compiled form is an O(1e-3) or larger
relative change at some of the thousands of points checked.

Where the laws have branches (the Re = 1000 switch of C_D, Gidaspow's switch and blend, clear
liquid n = 1, the |slip| saturation, the viscosity's blend and cap) the sampled points straddle
them, and NaN in gives the same pattern of NaN out.
"""
from __future__ import annotations

import numpy as np
import pytest

from twofluid.closures import drag, kernels, solids_pressure as sp
from twofluid.closures.viscosity import mooney_pringle, solid_viscosity
from twofluid.models.data_1d import Closures, Materials

TOL = 64 * np.finfo(float).eps
requires_numba = pytest.mark.skipif(kernels._compiled() is None, reason="numba not installed")
RNG = np.random.default_rng(2026)


def _close(fast, ref):
    both_nan = np.isnan(fast) & np.isnan(ref)
    assert (np.isnan(fast) == np.isnan(ref)).all()
    f, r = fast[~both_nan], ref[~both_nan]
    assert np.all(np.abs(f - r) <= TOL * np.abs(r)), np.max(np.abs(f - r) / np.maximum(np.abs(r), 1e-300))


def _points(size=3000):
    """Porosities over (0.2, 1] with exact clear liquid, the switch 0.6 and its blend edges, and one NaN."""
    n = RNG.uniform(0.2, 1.0, size)
    n[:7] = [1.0, 0.6, 0.58, 0.62, 0.6 - 1e-12, 0.2, np.nan]
    return n


def _materials(ne):
    """Liquid water, particles of one diameter per element (a layered site's), ``ne`` elements."""
    return Materials(1000.0, 1e-3, 2600.0, RNG.uniform(5e-5, 5e-3, ne))


@requires_numba
@pytest.mark.parametrize("law, params", [(drag.ergun, {}), (drag.wen_yu, {}),
                                         (drag.gidaspow, {"n_switch": 0.6, "blend_width": 0.0}),
                                         (drag.gidaspow, {"n_switch": 0.6, "blend_width": 0.02}),
                                         (drag.richardson_zaki, {"exponent": 2.7}),
                                         (drag.ergun_richardson_zaki, {"exponent": 3.4})],
                         ids=["ergun", "wen_yu", "gidaspow", "gidaspow-blend", "richardson_zaki",
                              "ergun_richardson_zaki"])
@pytest.mark.parametrize("stokes", [False, True])
@pytest.mark.parametrize("slip_max", [np.inf, 0.05])
def test_drag_per_solids_is_the_registry_law(law, params, stokes, slip_max):
    ne, reps = 500, 3
    mat = _materials(ne)
    clo = Closures(drag=law, drag_params={"stokes": stokes, **params}, slip_max=slip_max)
    laws = kernels.for_closures(clo, mat)
    assert laws is not None and laws.drag_law == law.__name__
    n = _points(ne * reps)
    slip = 10.0 ** RNG.uniform(-7, 1, n.size)  # Re from 1e-8 to beyond 1000 (the C_D switch), and saturated
    slip[7:10] = [0.0, 1e9, 0.05]
    stacked = Materials(1000.0, 1e-3, 2600.0, np.tile(mat.d_p, reps))  # as the models' _materials_times
    _close(laws.beta_per_solids(n, slip), clo.beta_per_solids(n, slip, stacked))


@requires_numba
@pytest.mark.parametrize("fluidized", [False, True])
@pytest.mark.parametrize("per_element", [False, True])
def test_solids_pressure_and_its_slope_are_the_registry_laws(fluidized, per_element):
    ne = 3000
    mat = _materials(ne) if per_element else Materials(1000.0, 1e-3, 2600.0, 3e-4)
    A = RNG.uniform(0.01, 0.2, ne) if per_element else 0.015
    p_ref = RNG.uniform(0.5, 2.0, ne) if per_element else 1.0
    clo = Closures(A=A, p_ref=p_ref, fluidized_pressure=sp.foscolo_gibilaro if fluidized else None,
                   fluidized_params={"coefficient": 3.2} if fluidized else {})
    laws = kernels.for_closures(clo, mat)
    n = _points(ne)
    n_bar = RNG.uniform(0.3, 0.6, ne)  # P_s from far below 1 Pa to the exp(700) cap
    ps, dps = laws.solids_pressure(n, n_bar)
    ref_ps, ref_dps = clo.solids_pressure(n, n_bar, mat, derivative=True)
    assert (ref_ps[1:6] > 0).all() and ref_ps[0] == (0.0 if not fluidized else ref_ps[0])
    _close(ps, ref_ps)
    _close(dps, ref_dps)


@requires_numba
@pytest.mark.parametrize("params", [{}, {"eps_blend": 0.1, "n_c": 0.45}])
def test_solid_and_mixture_viscosity_are_the_registry_laws(params):
    mat = Materials(1000.0, 1.3e-3, 2600.0, 1e-3)
    laws = kernels.for_closures(Closures(viscosity_params=params), mat)
    n = _points()
    n[7:10] = [1.0 - 1e-7, 1.0 - 2e-6, 0.4]  # the n = 1 limit, the blend, beyond the cap n_c
    _close(laws.solid_viscosity(n), solid_viscosity(n, mat.mu_f, **params))
    _close(laws.mixture_viscosity(n), mooney_pringle(n, mat.mu_f, **params))


def test_runs_the_compiled_forms_do_not_cover_get_none():
    mat = Materials(1000.0, 1e-3, 2600.0, 1e-3)
    assert kernels.for_closures(Closures(drag=lambda *a, **k: 0.0), mat) is None  # a law without one
    assert kernels.for_closures(Closures(drag_params={"n_switch": np.full(3, 0.6)}), mat) is None
    assert kernels.for_closures(Closures(viscosity_params={"k1": np.ones(3)}), mat) is None
    assert kernels.for_closures(Closures(), Materials(np.ones(3), 1e-3, 2600.0, 1e-3)) is None
    assert kernels.for_closures(Closures(drag=drag.wen_yu, drag_params={"n_switch": 0.6}), mat) is None


def test_the_numpy_path_calls_the_registry_laws():
    from twofluid.casefile.builder import build
    from twofluid.casefile.loader import load_case

    m = build(load_case("fluidized-bed-step")).model
    m.compiled = False
    assert m.compiled_laws() is None
    m.compiled, m.compiled_closures = None, False
    assert m.compiled_laws() is None
