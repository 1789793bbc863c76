"""Cyclic simple shear of one soil element: the liquefaction element test.

The element is a point of the 1D liquefaction column (docs/model.md, "Liquefaction column") without flow:

* **undrained** — the porosity n is constant; as the reference porosity n̄ falls
  (Byrne 1991) the granular pressure P_s(n, n̄) = p_ref exp[(1/A)(1 − (1 − n̄)/(1 − n))]
  falls and the excess pore pressure ratio r_u = 1 − P_s/σ′_v0 rises;
* **drained** — the liquid leaves freely: P_s stays at σ′_v0 and n follows n̄
  (1 − n = (1 − n̄)/(1 − A ln(σ′_v0/p_ref))), so r_u stays 0.

Loading, with time t counted in cycles (one cycle per unit time):

* strain-controlled: γ = γ_a sin 2πt;
* stress-controlled: τ = CSR σ′_v0 sin 2πt, γ from τ = G_max(P_s) (G/G_max)(γ) γ
  with P_s of the previous step; when |τ| exceeds the strength the backbone can
  give, the strain runs away, which also counts as liquefaction.

The initial state has P_s = σ′_v0: n̄0 = 1 − (1 − n)(1 − A ln(σ′_v0/p_ref)).
Liquefaction is the first time r_u ≥ ``ru_liquefied`` (0.95) or the strain runs away;
the number of cycles to liquefaction is that time [cycles].

>>> r = cyclic_simple_shear(csr=0.12, max_cycles=40)
>>> round(float(r.cycles_to_liquefaction[0]), 2), bool(r.r_u[-1, 0] >= 0.95)
(15.94, True)
"""
from __future__ import annotations

import io

from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import Callable

import numpy as np

from ..closures import registry
from ..closures.reference_porosity import ShearState
from ..closures.shear_modulus import hyperbolic, seed_idriss_gmax, strain_from_stress
from ..closures.solids_pressure import exponential, reference_porosity_for

__all__ = ["LooseSand", "DEFAULT_SAND", "ElementTestResult", "cyclic_simple_shear",
           "run_element_test", "OPTION_RANGES", "check_options"]


@dataclass(frozen=True)
class LooseSand:
    """Calibrated default loose clean sand ((N1)60 ≈ 10; docs/liquefaction.md, "Parameters and calibration").

    Calibration target: an undrained cyclic simple-shear element at σ′_v0 = 100 kPa
    and CSR = 0.12 reaches r_u ≥ 0.95 in about 15 uniform cycles (Idriss &
    Boulanger 2008: CRR ≈ 0.12 for (N1)60 ≈ 10 at M 7.5, i.e. about 15 cycles).
    Measured with :func:`cyclic_simple_shear` (byrne law, σ′_v0 = 100 kPa, 100 steps
    per cycle; 15.93 with 200, 16.12 with 50):

    ===========  =====  =====  =====  =====  =====  =====
    CSR          0.08   0.10   0.12   0.14   0.16   0.20
    cycles       59.0   27.7   15.9   10.2   7.2    3.7
    ===========  =====  =====  =====  =====  =====  =====

    i.e. N ∝ CSR^−1/b with b ≈ 0.31 (Idriss & Boulanger: 0.34 for clean sand).
    Strain-controlled: γ_a = 0.05 %, 0.1 %, 0.2 %, 0.5 % liquefy in 42, 8.1, 2.6,
    0.9 cycles; 0.03 % not within 300. At CSR 0.12, σ′_v0 = 50 / 200 kPa take
    47.8 / 6.2 cycles (a stronger confining-stress effect than K_σ).

    How the values were chosen: Dr = 47 % is the relative density of (N1)60 = 10
    (Dr = √((N1)60/46), Idriss & Boulanger 2008), giving Byrne's C1 = 0.50, as his
    C1 = 8.7 (N1)60^−1.25 does; K2max = 30 is the loose end of Seed & Idriss;
    γ_ref = 0.1 % is the Hardin–Drnevich τ_max/G_max (see
    :func:`~twofluid.closures.shear_modulus.hyperbolic`). That leaves A, fitted to
    the target: A = 6e-4 makes the skeleton bulk modulus P_s/A = 167 MPa at
    100 kPa, i.e. Poisson's ratio 0.33 with G_max = 65.6 MPa. The thesis's
    A = 0.015 (bulk modulus 6.7 MPa) would need ε_v ≈ 5 % of Byrne densification
    to reach r_u = 0.95, which this law does not produce at CSR 0.12.
    The undrained response does not depend on the porosity n (only on
    (1 − n̄)/(1 − n)); n = 0.44 (e = 0.79) is a loose sand.

    Attributes
    ----------
    porosity : initial porosity n [-] (e = 0.79, loose)
    dr : relative density [%]; Byrne's C1 = 7600 Dr^−2.5
    A : compressibility of the granular pressure law [-]
    k2max : Seed–Idriss modulus number [-] (30 loose .. 70 dense)
    gamma_ref : reference strain of the hyperbolic G/G_max curve [-]
    p_ref : reference pressure of P_s(n, n̄) [Pa]
    """

    porosity: float = 0.44
    dr: float = 47.0
    A: float = 6e-4
    k2max: float = 30.0
    gamma_ref: float = 1e-3
    p_ref: float = 1.0


DEFAULT_SAND = LooseSand()


@dataclass
class ElementTestResult:
    """Histories [time step, element] and the cycles to liquefaction per element."""

    cycles: np.ndarray
    gamma: np.ndarray
    tau: np.ndarray
    p_s: np.ndarray
    n_bar: np.ndarray
    porosity: np.ndarray
    r_u: np.ndarray
    cycles_to_liquefaction: np.ndarray
    settings: dict = field(default_factory=dict)

    @property
    def liquefied(self) -> np.ndarray:
        return np.isfinite(self.cycles_to_liquefaction)


def _reference_porosity_law(law: str | Callable, law_params: dict | None, sand: LooseSand):
    if callable(law):
        func = law
        params = dict(law_params or {})
    else:
        func = registry.get("reference_porosity", law).func
        params = {"dr": sand.dr} if law == "byrne" else {}
        params.update(law_params or {})
    return lambda dg, g, nb, st: func(dg, g, nb, st, **params)


def cyclic_simple_shear(*, csr=None, gamma_amplitude=None, sigma_v0=100e3,
                        sand: LooseSand = DEFAULT_SAND, drained: bool = False,
                        law: str | Callable = "byrne", law_params: dict | None = None,
                        reduction: Callable | None = None, max_cycles: float = 50.0,
                        steps_per_cycle: int = 100, ru_liquefied: float = 0.95,
                        stop_at_liquefaction: bool = True) -> ElementTestResult:
    """Run undrained (or drained) cyclic simple shear on one or more elements.

    Parameters
    ----------
    csr : float or array_like, optional
        Cyclic stress ratio τ_cyc/σ′_v0 [-] (stress-controlled test).
    gamma_amplitude : float or array_like, optional
        Shear-strain amplitude γ_a [-] (strain-controlled test). Give exactly one
        of ``csr`` and ``gamma_amplitude``; arrays run several elements at once.
    sigma_v0 : float or array_like
        Initial vertical effective stress σ′_v0 = P_s at the start [Pa].
    sand : LooseSand
        Material (porosity, Dr, A, K2max, γ_ref, p_ref).
    drained : bool
        Drained (P_s held at σ′_v0) instead of undrained (n held constant).
    law : str or callable
        Reference-porosity law: a registered name ("byrne", "ann") or a function
        with the interface of :mod:`twofluid.closures.reference_porosity`.
    law_params : dict, optional
        Extra keyword arguments of the law (byrne gets ``dr=sand.dr`` by default).
    reduction : callable, optional
        G/G_max(γ); default hyperbolic with ``sand.gamma_ref``.
    max_cycles : float
        Length of the test [cycles].
    steps_per_cycle : int
        Time steps per loading cycle.
    ru_liquefied : float
        r_u at which the element counts as liquefied [-].
    stop_at_liquefaction : bool
        End the test once every element has liquefied.
    """
    if (csr is None) == (gamma_amplitude is None):
        raise ValueError("give exactly one of csr (stress control) "
                         "and gamma_amplitude (strain control)")
    stress_control = csr is not None
    amp, sig0 = (np.array(a, dtype=float) for a in np.broadcast_arrays(
        np.atleast_1d(np.asarray(csr if stress_control else gamma_amplitude, dtype=float)),
        np.asarray(sigma_v0, dtype=float)))
    if np.any(amp <= 0.0) or np.any(sig0 <= sand.p_ref):
        raise ValueError("amplitudes must be > 0 and sigma_v0 > p_ref")
    red = reduction or (lambda g: hyperbolic(g, sand.gamma_ref))
    step_law = _reference_porosity_law(law, law_params, sand)

    n = np.full(amp.shape, sand.porosity)
    n_bar = reference_porosity_for(n, sig0, sand.A, sand.p_ref)
    p_s = sig0.copy()
    gamma = np.zeros(amp.shape)
    state = ShearState.zeros(amp.shape)
    ln_sig = np.log(sig0 / sand.p_ref)
    liq_at = np.full(amp.shape, np.inf)
    total = int(round(max_cycles * steps_per_cycle))
    rows = [(0.0, gamma, np.zeros(amp.shape), p_s, n_bar, n)]
    gamma_cap = 0.1  # [-] strain recorded once the backbone has run away

    for k in range(1, total + 1):
        t = k / steps_per_cycle
        wave = np.sin(2.0 * np.pi * t)
        g_max = seed_idriss_gmax(p_s, sand.k2max)
        if stress_control:
            tau = amp * sig0 * wave
            if reduction is None:  # hyperbola: closed form γ = τ/(G_max − |τ|/γ_ref)
                slack = g_max - np.abs(tau) / sand.gamma_ref
                new_gamma = np.where(slack * gamma_cap > np.abs(tau),
                                     tau / np.where(slack > 0.0, slack, 1.0), np.inf)
            else:
                new_gamma = strain_from_stress(tau, g_max, red, gamma_max=gamma_cap)
            runaway = ~np.isfinite(new_gamma)
            new_gamma = np.where(runaway, np.sign(tau) * gamma_cap, new_gamma)
        else:
            new_gamma = amp * wave
            runaway = np.zeros(amp.shape, dtype=bool)
        dgamma = new_gamma - gamma
        n_bar, state = step_law(dgamma, new_gamma, n_bar, state)
        gamma = new_gamma
        if drained:
            n = 1.0 - (1.0 - n_bar) / (1.0 - sand.A * ln_sig)
        else:
            p_s = exponential(n, n_bar, sand.A, sand.p_ref)
        if not stress_control:
            tau = seed_idriss_gmax(p_s, sand.k2max) * red(gamma) * gamma
        r_u = 1.0 - p_s / sig0
        newly = np.isinf(liq_at) & ((r_u >= ru_liquefied) | runaway)
        liq_at = np.where(newly, t, liq_at)
        rows.append((t, gamma, tau, p_s, n_bar, n))
        if stop_at_liquefaction and np.all(np.isfinite(liq_at)):
            break

    cols = list(zip(*rows))
    hist = [np.array(c) if i == 0 else np.stack(c) for i, c in enumerate(cols)]
    settings = {"mode": "stress" if stress_control else "strain", "drained": drained,
                "law": law if isinstance(law, str) else getattr(law, "__name__", "custom"),
                "steps_per_cycle": steps_per_cycle, "ru_liquefied": ru_liquefied,
                "sand": asdict(sand)}
    return ElementTestResult(hist[0], hist[1], hist[2], hist[3], hist[4], hist[5],
                             1.0 - hist[3] / sig0, liq_at, settings)


#: Valid ranges of the ``twofluid element-test`` options: (low, high, low open, high open, unit).
#: The material ranges are those of the ``liquefaction_1d`` case keys ([deposit] porosity, [sand] …).
OPTION_RANGES = {
    "--csr": (0.0, 1.0, True, False, "-"),
    "--gamma": (0.0, 0.1, True, False, "-"),
    "--sigma-v0": (1e-3, 1e5, True, False, "kPa"),  # above p_ref = 1 Pa, up to 100 MPa
    "--dr": (1.0, 100.0, True, False, "%"),
    "--porosity": (0.2, 0.7, False, False, "-"),
    "--A": (0.0, 1.0, True, False, "-"),
    "--k2max": (0.0, 200.0, True, False, "-"),
    "--gamma-ref": (0.0, 1.0, True, False, "-"),
    "--max-cycles": (0.0, 1000.0, True, False, "cycles"),
    "--steps-per-cycle": (4, 1000, False, False, "-"),
}


def check_options(values: dict, source: str = "element-test") -> None:
    """Range-check element-test options {"--csr": 0.1, ...} (None = default, not checked).

    Raises :class:`~twofluid.casefile.schema.CaseError` naming the option and its valid range.

    >>> check_options({"--porosity": 0.44, "--csr": None})
    >>> check_options({"--porosity": 1.5})
    Traceback (most recent call last):
    ...
    twofluid.casefile.schema.CaseError: element-test: --porosity: 1.5 is outside the valid range [0.2, 0.7] [-]
    """
    from ..casefile.schema import CaseError

    for opt, value in values.items():
        if value is None:
            continue
        lo, hi, lo_open, hi_open, unit = OPTION_RANGES[opt]
        ok = (lo < value if lo_open else lo <= value) and (value < hi if hi_open else value <= hi)
        if not ok:  # also NaN
            rng = f"{'(' if lo_open else '['}{lo:g}, {hi:g}{')' if hi_open else ']'}"
            hint = (f"; the unit is per cent: did you mean {value * 100:g} (×100)?"
                    if unit == "%" and 0.0 < value <= 1.0 else "")
            raise CaseError(source, opt, f"{value:g} is outside the valid range {rng} [{unit}]{hint}")
    # the initial state must exist: n̄0 = 1 − (1 − n)(1 − A ln(σ′_v0/p_ref)) < 1 (> 0 holds, as
    # σ′_v0 > p_ref)
    sig = values.get("--sigma-v0")
    sig = 100e3 if sig is None else 1e3 * sig
    A = values.get("--A") if values.get("--A") is not None else DEFAULT_SAND.A
    if A * np.log(sig / DEFAULT_SAND.p_ref) >= 1.0:
        raise CaseError(source, "--A", f"{A:g} gives a reference porosity n̄ >= 1 at sigma'_v0 = "
                        f"{sig / 1e3:g} kPa; valid: A < 1/ln(sigma'_v0/p_ref) = "
                        f"{1.0 / np.log(sig / DEFAULT_SAND.p_ref):.4g}")


def run_element_test(*, csr: float | None = None, gamma_amplitude: float | None = None,
                     sigma_v0: float = 100e3, dr: float | None = None,
                     porosity: float | None = None, A: float | None = None,
                     k2max: float | None = None, gamma_ref: float | None = None,
                     drained: bool = False, law: str = "byrne", max_cycles: float = 50.0,
                     steps_per_cycle: int = 100, ru_liquefied: float = 0.95,
                     out_dir: str | Path | None = None) -> ElementTestResult:
    """Run one element test and, if ``out_dir`` is given, write its results there.

    Stress-controlled at ``csr`` [-] (default 0.12 when neither is given) or
    strain-controlled at ``gamma_amplitude`` [-]; ``sigma_v0`` [Pa]; material
    overrides of :data:`DEFAULT_SAND` (``dr`` [%], ``porosity`` [-], ``A`` [-],
    ``k2max`` [-], ``gamma_ref`` [-]); ``law`` "byrne" or "ann". Writes
    ``element_test.csv`` (histories, SI units), ``summary.json`` (cycles to
    liquefaction and every setting) and ``element_test.png``.
    """
    if out_dir is not None:  # the run commands' folder rules, checked before computing (io.folders)
        from ..io.folders import check_out_dir

        out_dir = check_out_dir(out_dir, "element test out_dir")
    if csr is None and gamma_amplitude is None:
        csr = 0.12
    overrides = {k: v for k, v in dict(dr=dr, porosity=porosity, A=A, k2max=k2max,
                                       gamma_ref=gamma_ref).items() if v is not None}
    sand = replace(DEFAULT_SAND, **overrides)
    result = cyclic_simple_shear(csr=csr, gamma_amplitude=gamma_amplitude, sigma_v0=sigma_v0,
                                 sand=sand, drained=drained, law=law, max_cycles=max_cycles,
                                 steps_per_cycle=steps_per_cycle, ru_liquefied=ru_liquefied)
    result.settings.update(csr=csr, gamma_amplitude=gamma_amplitude, sigma_v0_Pa=sigma_v0,
                           max_cycles=max_cycles)
    if out_dir is not None:
        from ..io.folders import OutputFolder
        from ..plots.element_test import plot_element_test  # matplotlib only when asked

        with OutputFolder(Path(out_dir)) as folder:
            _write(result, folder.path, plot_element_test)
    return result


def _write(result, out: Path, plot_element_test) -> None:
    """``element_test.csv``, ``summary.json`` and ``element_test.png`` into the claimed folder ``out``."""
    table = np.column_stack([result.cycles, result.gamma[:, 0], result.tau[:, 0],
                             result.p_s[:, 0], result.n_bar[:, 0], result.porosity[:, 0],
                             result.r_u[:, 0]])
    from ..io.folders import write_atomic
    from ..io.results import write_json

    buf = io.StringIO()  # written whole, never through a symbolic link (io.folders)
    np.savetxt(buf, table, delimiter=",", comments="", fmt="%.9g",
               header="cycles,gamma,tau_Pa,p_s_Pa,n_bar,porosity,r_u")
    write_atomic(out / "element_test.csv", buf.getvalue())
    n_liq = float(result.cycles_to_liquefaction[0])
    summary = {"cycles_to_liquefaction": n_liq if np.isfinite(n_liq) else None,
               "liquefied": bool(np.isfinite(n_liq)),
               "final_r_u": float(result.r_u[-1, 0]), "settings": result.settings}
    write_json(out / "summary.json", summary)
    plot_element_test(result, out / "element_test.png")  # on its own canvas: nothing to close
