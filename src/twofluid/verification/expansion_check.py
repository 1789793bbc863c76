"""Bed expansion, packed bed and minimum fluidization of the drag laws against the correlations.

Expansion: for a terminal Reynolds number Re_t = ρ_f U_t d/μ_f of 0.1, 1, 10, 100 and 1000
(particles of 2600 kg/m³ in water at 20 °C, the diameter chosen for that Re_t with the
law's own single-particle drag), the porosity n at which the law's uniform bed is at rest
in a superficial velocity U (:func:`twofluid.closures.drag.steady_fluidization_velocity`)
is compared with Richardson & Zaki's, n_RZ = (U/U_t)^(1/k), k of Khan & Richardson (1989)
without the wall term (d/D → 0) and U_i = U_t, U_t the terminal velocity of one particle
with the same law. The compared quantity is the solids fraction, |(1 − n) − (1 − n_RZ)|/(1 − n_RZ),
and so the bed height (H ∝ 1/(1 − n)); its largest value over 19 porosities spread over
[n_lo, 0.85] must be at most 5 %. n_lo = ε_mf = 0.40 for `richardson_zaki`; for
`ergun_richardson_zaki` n_lo is the top of its transition, 0.49: below it the law is
Ergun's packed bed (next check), and the transition 0.45–0.49 is reported, not gated.

Packed bed: the pressure gradient of `ergun_richardson_zaki` at rest, β s/n (s = U/n), against
Ergun's (1952) 150 μ_f U (1 − n)²/(n³ d²) + 1.75 ρ_f U² (1 − n)/(n³ d), at n = 0.36, 0.40, 0.45 and
particle Reynolds numbers ρ_f U d/μ_f = 0.1, 10 and 1000: within 5 %.

Minimum fluidization: U_mf of `ergun_richardson_zaki` (the velocity at which its drag at
n_mf = 0.40 carries the bed's buoyant weight) against Wen & Yu's (1966) correlation
Re_mf = √(33.7² + 0.0408 Ar) − 33.7: within their ±30 % band, for the same five particles.
"""
from __future__ import annotations

import numpy as np

from ..closures import drag as D
from ..scipy_kernels import brentq

__all__ = ["expansion_table", "expansion_rows", "packed_rows", "minimum_fluidization_rows", "TOL"]

TOL = 0.05
RHO_F, MU_F, RHO_S, G = 998.2, 1.002e-3, 2600.0, 9.81
RE_T = (0.1, 1.0, 10.0, 100.0, 1000.0)
N_MF = 0.40
LAWS = {"richardson_zaki": N_MF, "ergun_richardson_zaki": 0.49}
SHOWN = ("wen_yu", "gidaspow", "richardson_zaki", "ergun_richardson_zaki")


def _params(name: str, d: float) -> dict:
    if name in ("richardson_zaki", "ergun_richardson_zaki"):
        return {"exponent": float(D.khan_richardson_exponent(D.archimedes_number(d, RHO_S, RHO_F, MU_F, G)))}
    if name == "gidaspow":
        return {"blend_width": 0.02}
    return {}


def _law(name: str):
    from ..closures.registry import get

    return get("drag", name).func


def diameter_for(re_t: float, name: str = "richardson_zaki") -> float:
    """Particle diameter [m] whose single-particle terminal Reynolds number with law ``name`` is ``re_t``."""
    law = _law(name)

    def res(logd):
        d = float(np.exp(logd))
        return RHO_F * D.terminal_velocity(law, d, RHO_S, RHO_F, MU_F, G, **_params(name, d)) * d / MU_F - re_t

    return float(np.exp(brentq(res, np.log(1e-7), np.log(0.1), xtol=1e-12, rtol=1e-12)))


def _equilibrium(name: str, d: float, u: float) -> float:
    """Porosity at which law ``name`` holds a uniform bed at rest in ``u`` [m/s]."""
    law, p = _law(name), _params(name, d)
    return float(brentq(lambda n: D.steady_fluidization_velocity(law, n, d, RHO_S, RHO_F, MU_F, G, **p) - u,
                        0.2, 1.0 - 1e-9, xtol=1e-13, rtol=1e-13))


def expansion_table(re_ts=RE_T, porosities=(0.45, 0.55, 0.65, 0.75, 0.85)) -> list[dict]:
    """Rows (Re_t, d, k, RZ porosity, each law's porosity) at the velocities U = U_t n_RZ^k
    (U_t of `richardson_zaki`'s particle; each law at the same U and particle)."""
    out = []
    for re_t in re_ts:
        d = diameter_for(re_t)
        k = _params("richardson_zaki", d)["exponent"]
        u_t = D.terminal_velocity(D.richardson_zaki, d, RHO_S, RHO_F, MU_F, G, exponent=k)
        for n_rz in porosities:
            u = u_t * n_rz ** k
            row = {"Re_t": re_t, "d_mm": 1e3 * d, "k": k, "U_mm_s": 1e3 * u, "n_rz": n_rz}
            for name in SHOWN:
                row[name] = _equilibrium(name, d, u)
            out.append(row)
    return out


def expansion_markdown(table: list[dict]) -> str:
    """The expansion table as markdown (porosities; solids-fraction error against RZ in brackets)."""
    head = "| Re_t | d [mm] | k (KR) | U [mm/s] | n RZ | " + " | ".join(f"n {s}" for s in SHOWN) + " |"
    lines = [head, "|" + "---|" * (5 + len(SHOWN))]
    for r in table:
        cells = [f"{r[s]:.4f} ({100 * ((1 - r[s]) - (1 - r['n_rz'])) / (1 - r['n_rz']):+.1f} %)" for s in SHOWN]
        lines.append(f"| {r['Re_t']:g} | {r['d_mm']:.4g} | {r['k']:.3f} | {r['U_mm_s']:.4g} | {r['n_rz']:.2f} | "
                     + " | ".join(cells) + " |")
    return "\n".join(lines)


def _row(check, quantity, ref, comp, tol=TOL, unit="-"):
    err = abs(comp - ref) / abs(ref)
    return {"check": check, "quantity": quantity, "unit": unit, "reference": ref, "computed": comp, "error": err,
            "tolerance": tol, "error_kind": "relative", "pass": bool(err <= tol)}


def expansion_rows(re_ts=RE_T, points: int = 19) -> list[dict]:
    """Largest solids-fraction error against Richardson–Zaki (module docstring), per law and Re_t."""
    rows = []
    for name, n_lo in LAWS.items():
        law = _law(name)
        for re_t in re_ts:
            d = diameter_for(re_t, name)
            p = _params(name, d)
            k = p["exponent"]
            u_t = D.terminal_velocity(law, d, RHO_S, RHO_F, MU_F, G, **p)
            worst, at = 0.0, n_lo
            for n in np.linspace(n_lo, 0.85, points):
                u = D.steady_fluidization_velocity(law, n, d, RHO_S, RHO_F, MU_F, G, **p)
                n_rz = (u / u_t) ** (1.0 / k)
                e = ((1.0 - n) - (1.0 - n_rz)) / (1.0 - n_rz)
                if abs(e) >= abs(worst):
                    worst, at = e, n
            rows.append({"check": f"bed expansion {name}, Re_t = {re_t:g}",
                         "quantity": f"largest solids-fraction error vs Richardson–Zaki, n in [{n_lo:g}, 0.85] "
                                     f"(at n = {at:.3f})", "unit": "-", "reference": 0.0, "computed": worst,
                         "error": abs(worst), "tolerance": TOL, "error_kind": "absolute",
                         "pass": bool(abs(worst) <= TOL)})
    return rows


def packed_rows(name: str = "ergun_richardson_zaki") -> list[dict]:
    """The law's packed-bed pressure gradient against Ergun's (module docstring)."""
    law, rows = _law(name), []
    d = 1e-3
    p = _params(name, d)
    for re in (0.1, 10.0, 1000.0):
        u = re * MU_F / (RHO_F * d)
        for n in (0.36, 0.40, 0.45):
            s = u / n
            grad = float(law(n, s, d, RHO_F, MU_F, **p)) * s / n
            ergun = 150.0 * MU_F * u * (1 - n) ** 2 / (n ** 3 * d * d) + 1.75 * RHO_F * u * u * (1 - n) / (n ** 3 * d)
            rows.append(_row(f"packed bed {name}", f"pressure gradient at n = {n:g}, Re = {re:g}", ergun, grad,
                             unit="Pa/m"))
    return rows


def minimum_fluidization_rows(name: str = "ergun_richardson_zaki", re_ts=RE_T) -> list[dict]:
    """The law's U_mf at n_mf = 0.40 against Wen & Yu (1966), ±30 % (module docstring)."""
    law, rows = _law(name), []
    for re_t in re_ts:
        d = diameter_for(re_t, name)
        u = D.steady_fluidization_velocity(law, N_MF, d, RHO_S, RHO_F, MU_F, G, **_params(name, d))
        wy = D.wen_yu_minimum_fluidization_velocity(d, RHO_S, RHO_F, MU_F, G)
        rows.append(_row(f"minimum fluidization {name}", f"U_mf against Wen & Yu, Re_t = {re_t:g}", wy, u,
                         tol=0.30, unit="m/s"))
    return rows
