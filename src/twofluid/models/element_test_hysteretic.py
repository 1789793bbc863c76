"""Element tests of the hysteretic law: undrained cyclic simple shear and its CSR–N curve.

One element of :mod:`twofluid.closures.hysteretic` under uniform cycles (K0 = 0.5, σ′_v0 given,
undrained, so P_s = σ′_v0 (1 − r_u)), run by the compiled kernel of
:mod:`twofluid.models.hysteretic_kernel`. Liquefaction is the first of r_u ≥ 0.98 or a
single-amplitude strain γ ≥ 3 %. Under a static shear stress (``alpha`` = τ_s/σ′_v0 > 0, a slope's)
the element is first loaded on its backbone to τ_s (:func:`twofluid.closures.hysteretic.static_state`),
its CRR carries K_α (:func:`twofluid.models.hysteretic_sand.apply_k_alpha`), the cycles ride on τ_s,
τ = (α + CSR sin 2πt) σ′_v0, and the strain criterion counts from the static strain:
|γ − γ_s| ≥ 3 %. :func:`model_crr` is the CSR that liquefies the element in 15 cycles, so
``model_crr(alpha=a) / model_crr()`` is the model's K_α. :func:`csr_n_curve` sets the model's cycles to liquefaction
beside the correlation it is calibrated to, N = 15 (CRR/CSR)^(1/b) with CRR = CRR_M7.5 K_σ and b
from Boulanger & Idriss's b(MSF_max) (:mod:`twofluid.models.hysteretic_sand`).

>>> r = element_test(csr=0.13, n160cs=10.0)
>>> round(r.cycles, 1), round(r.correlation_cycles, 1)
(9.2, 9.2)
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..closures import hysteretic as law
from ..geotech.correlations import CSR_N_SLOPE_RANGE
from . import hysteretic_kernel as hk
from . import hysteretic_sand as hs

__all__ = ["HystereticElementTest", "element_test", "csr_n_curve", "model_crr", "N_TARGETS"]

#: cycles at which :func:`csr_n_curve` evaluates the correlation's CSR
N_TARGETS = (3.0, 5.0, 10.0, 15.0, 30.0, 50.0)


@dataclass(frozen=True)
class HystereticElementTest:
    """One test: ``cycles`` to liquefaction (nan: none within the test), histories per step
    (``t`` [cycles], ``gamma`` [-], ``tau`` [Pa], ``r_u`` [-]), the soil's ``crr`` and ``b``, and the
    correlation's cycles at the applied CSR (nan under strain control)."""

    cycles: float
    correlation_cycles: float
    crr: float
    b: float
    t: np.ndarray
    gamma: np.ndarray
    tau: np.ndarray
    r_u: np.ndarray


def element_test(*, csr=None, gamma_amplitude=None, sigma_v0=100e3, n160cs=None, qc1ncs=None, dr=None,
                 k2max=30.0, friction_angle=None, max_cycles=100, steps_per_cycle=100,
                 alpha=0.0, csr_n_slope=None) -> HystereticElementTest:
    """Undrained cyclic simple shear at ``csr`` (stress control) or ``gamma_amplitude`` (strain
    control) of a soil given by (N1)60cs, q_c1Ncs or Dr [%] (default Dr 47 %) at σ′_v0 [Pa], on a
    static shear stress ratio ``alpha`` = τ_s/σ′_v0 ≥ 0 (module docstring); ``csr_n_slope`` in
    [0.05, 0.6] replaces the CSR–N slope b of Boulanger & Idriss's b(MSF_max)."""
    if (csr is None) == (gamma_amplitude is None):
        raise ValueError("element_test: give one of csr or gamma_amplitude")
    lo, hi = CSR_N_SLOPE_RANGE
    if csr_n_slope is not None and not lo <= csr_n_slope <= hi:
        raise ValueError(f"element_test: csr_n_slope = {csr_n_slope:g} is outside the valid range [{lo:g}, {hi:g}]")
    if dr is None and n160cs is None and qc1ncs is None:
        dr = 47.0
    par = hs.parameters(sigma_v0=[sigma_v0], n160cs=n160cs, qc1ncs=qc1ncs, dr=dr, k2max=k2max,
                        friction_angle=friction_angle, csr_n_slope=csr_n_slope)
    if not 0.0 <= alpha < 1.0:
        raise ValueError(f"element_test: alpha = {alpha:g} is outside the valid range [0, 1)")
    st = law.new_state(1, par)
    if alpha > 0.0:
        par = hs.apply_k_alpha(par, alpha)
        par[0, law.P_TAUS] = alpha * sigma_v0  # as the column sets it: the flow-liquefaction rule reads it
        if not abs(law.static_state(st, par, 0, alpha * sigma_v0, sigma_v0)) < 1.0:
            raise ValueError(f"element_test: alpha = {alpha:g} is at or above the strength ratio "
                             f"tan phi' = {par[0, law.P_TANPHI]:.3g}")
    size = int(steps_per_cycle) * int(max_cycles) + 1
    g, tau, ru = np.zeros(size), np.zeros(size), np.zeros(size)
    mode, amp = (0, float(csr)) if csr is not None else (1, float(gamma_amplitude))
    n = hk.element_cycles(st, par, mode, amp, int(steps_per_cycle), int(max_cycles), 0.98, 0.03, g, tau, ru,
                          bias=float(alpha))
    last = size if n < 0 else int(round(n * steps_per_cycle)) + 1
    crr, b = float(par[0, law.P_CRR]), float(par[0, law.P_B])
    corr = 15.0 * (crr / csr) ** (1.0 / b) if csr is not None else float("nan")
    t = np.arange(size) / steps_per_cycle
    return HystereticElementTest(float(n) if n >= 0 else float("nan"), corr, crr, b, t[:last], g[:last],
                                 tau[:last], ru[:last])


def csr_n_curve(*, sigma_v0=100e3, n_targets=N_TARGETS, **soil) -> list[dict]:
    """Rows {csr, cycles_model, cycles_correlation, csr_error} at the CSR the correlation gives for
    each of ``n_targets`` cycles; ``csr_error`` = (N_model/N_target)^b − 1, the relative change of
    CSR that would move the correlation to the model's N (the measure of the ±15 % criterion).

    >>> rows = csr_n_curve(n160cs=10.0, n_targets=(15.0,))
    >>> abs(rows[0]["csr_error"]) < 0.05
    True
    """
    base = element_test(csr=0.1, sigma_v0=sigma_v0, max_cycles=1, **soil)
    rows = []
    for nt in n_targets:
        csr = base.crr * (15.0 / nt) ** base.b
        r = element_test(csr=csr, sigma_v0=sigma_v0, max_cycles=int(max(3 * nt, 10)), **soil)
        err = (r.cycles / nt) ** base.b - 1.0 if np.isfinite(r.cycles) else float("nan")
        rows.append({"csr": float(csr), "cycles_model": r.cycles, "cycles_correlation": float(nt),
                     "csr_error": float(err)})
    return rows


def model_crr(*, n_cycles=15.0, sigma_v0=100e3, alpha=0.0, steps_per_cycle=100, **soil) -> float:
    """The model's cyclic resistance: the CSR [-] at which the element liquefies (module docstring's
    criterion) in ``n_cycles`` uniform cycles, on a static shear ratio ``alpha``; found by bisection
    on log CSR to 0.1 % (the cycles to liquefaction fall as the CSR rises).

    >>> r0, r1 = model_crr(n160cs=10.0), model_crr(n160cs=10.0, alpha=0.1)
    >>> 0.85 < (r1 / r0) / 0.9493 < 1.15   # K_α of Idriss & Boulanger (2008) at α = 0.1
    True
    """
    def cycles(csr):
        r = element_test(csr=csr, sigma_v0=sigma_v0, alpha=alpha, steps_per_cycle=steps_per_cycle,
                         max_cycles=int(max(3 * n_cycles, 10)), **soil)
        return r.cycles if np.isfinite(r.cycles) else np.inf

    first = element_test(csr=0.1, sigma_v0=sigma_v0, alpha=alpha, max_cycles=1, **soil)
    lo = hi = first.crr * (15.0 / n_cycles) ** first.b
    while cycles(lo) <= n_cycles:
        lo *= 0.7
    while cycles(hi) > n_cycles:
        hi *= 1.4
    while hi / lo > 1.001:
        mid = (lo * hi) ** 0.5
        if cycles(mid) > n_cycles:
            lo = mid
        else:
            hi = mid
    return float((lo * hi) ** 0.5)
