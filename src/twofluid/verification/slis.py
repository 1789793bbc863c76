"""Slis, Willemse & Kramers (1959) fluidized-bed step changes, with Kynch's t1.

The shipped table (``twofluid/data/validation/slis1959_step_change.csv``, see the
PROVENANCE.md beside it) lists 12 step changes of nylon spheres (ρ_s = 1140 kg/m³)
in tap water: initial and final porosity, measured t1 and the thesis's FEA t1.

For each row :func:`kynch_t1_table` gives the kinematic-wave (Kynch) t1 from
:func:`twofluid.verification.kynch.step_change_t1`, with

* water at 20 °C: ρ_f = 998.2 kg/m³, μ_f = 1.002e-3 Pa·s (standard tables,
  e.g. CRC Handbook); "tap water" temperature is not reported;
* U_t from the Schiller–Naumann single-sphere drag (C_D = 0.44 above Re = 1000,
  as in the Wen & Yu (1966) drag law), solved for the force balance with ``scipy.optimize.brentq``;
* k from Rowe (1987), (4.7 − k)/(k − 2.35) = 0.175 Re_t^(3/4), Re_t = ρ_f U_t d/μ_f;
  Khan & Richardson (1989), (4.8 − k)/(k − 2.4) = 0.043 Ar^0.57, is offered for a
  sensitivity check (wall factor omitted: the column diameter is not known);
* initial bed height H0 = 0.275 m, the column height the thesis simulated (its
  text says the initial porosity filled the column). t1 is proportional to H0.

This is theory for the verification table only: Kynch neglects particle inertia
and granular pressure, and takes Richardson–Zaki as exact.

References
----------
Slis, P. L., Willemse, Th. W., Kramers, H. (1959). Appl. Sci. Res. A 8, 209–218.
Schiller, L., Naumann, A. (1933). Z. Ver. Dtsch. Ing. 77, 318–320.
Rowe, P. N. (1987). A convenient empirical equation for estimation of the
Richardson–Zaki exponent. Chem. Eng. Sci. 42, 2795–2796.
Khan, A. R., Richardson, J. F. (1989). Fluid–particle interactions and flow
characteristics of fluidized beds and settling suspensions of spherical
particles. Chem. Eng. Commun. 78, 111–130.
"""

from __future__ import annotations

from dataclasses import dataclass
from importlib import resources
from typing import Iterable

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import brentq

from twofluid.verification.kynch import stokes_terminal_velocity, step_change_t1

__all__ = [
    "SlisRow", "load_slis_table", "parse_slis_csv", "schiller_naumann_terminal_velocity",
    "rowe_exponent", "khan_richardson_exponent", "KynchRow", "kynch_t1_table",
]

CSV_NAME = "slis1959_step_change.csv"
HEADER = ("material", "d_mm", "rho_s_kg_m3", "n0", "n1", "t1_exp_s", "t1_thesis_fea_s")
RHO_WATER = 998.2  # [kg/m³] at 20 °C
MU_WATER = 1.002e-3  # [Pa·s] at 20 °C
H0_THESIS = 0.275  # [m] column height simulated in the thesis


@dataclass(frozen=True)
class SlisRow:
    """One step-change experiment; d [m], rho_s [kg/m³], n0, n1 [-], t1_* [s]."""

    material: str
    d: float
    rho_s: float
    n0: float
    n1: float
    t1_exp: float
    t1_thesis: float


def parse_slis_csv(lines: Iterable[str], source: str = CSV_NAME) -> list[SlisRow]:
    """Parse the table's text; '#' lines are comments.

    Raises ``ValueError`` naming ``source`` and the 1-based line for a bad header
    or row (wrong field count, non-numeric or non-physical value).

    >>> parse_slis_csv([",".join(HEADER), "I,3,1140,0.54,0.76,15,13.8"])[0].d
    0.003
    """
    rows: list[SlisRow] = []
    header_seen = False
    for lineno, raw in enumerate(lines, start=1):
        line = raw.strip()
        if not line or line.startswith("#"):
            continue
        fields = [f.strip() for f in line.split(",")]
        where = f"{source}, line {lineno}"
        if not header_seen:
            if tuple(fields) != HEADER:
                raise ValueError(f"{where}: expected header {','.join(HEADER)!r}, got {line!r}")
            header_seen = True
            continue
        if len(fields) != len(HEADER):
            raise ValueError(f"{where}: expected {len(HEADER)} fields, got {len(fields)}: {line!r}")
        try:
            d_mm, rho_s, n0, n1, t_exp, t_fea = (float(f) for f in fields[1:])
        except ValueError as exc:
            raise ValueError(f"{where}: non-numeric field in {line!r} ({exc})") from None
        if not (0.0 < n0 < 1.0 and 0.0 < n1 < 1.0) or min(d_mm, rho_s, t_exp, t_fea) <= 0.0:
            raise ValueError(f"{where}: porosity outside (0, 1) or non-positive value: {line!r}")
        rows.append(SlisRow(fields[0], d_mm * 1e-3, rho_s, n0, n1, t_exp, t_fea))
    if not header_seen:
        raise ValueError(f"{source}: no header line found")
    return rows


def load_slis_table() -> list[SlisRow]:
    """The 12 shipped rows of thesis table 5.2 as :class:`SlisRow`.

    >>> rows = load_slis_table()
    >>> len(rows), rows[0].material, rows[0].n0, rows[0].n1
    (12, 'I', 0.54, 0.76)
    """
    ref = resources.files("twofluid").joinpath("data", "validation", CSV_NAME)
    return parse_slis_csv(ref.read_text(encoding="utf-8").splitlines(), source=str(ref))


def schiller_naumann_terminal_velocity(d: float, rho_s: float, rho_f: float,
                                       mu_f: float, g: float = 9.81) -> float:
    """Terminal velocity U_t [m/s] of a sphere with Schiller–Naumann drag.

    Solves C_D(Re) ρ_f U² = (4/3) d (ρ_s − ρ_f) g, C_D = 24/Re (1 + 0.15 Re^0.687)
    (Re < 1000), 0.44 above. C_D ≥ 24/Re, so U_t lies below the Stokes value,
    which brackets the root. d [m], densities [kg/m³], mu_f [Pa·s].

    >>> u = schiller_naumann_terminal_velocity(1e-5, 2650.0, 1000.0, 1e-3)
    >>> bool(abs(u / float(stokes_terminal_velocity(1e-5, 2650.0, 1000.0, 1e-3)) - 1) < 2e-3)
    True
    """
    def residual(U: float) -> float:
        Re = rho_f * U * d / mu_f
        cd = 24.0 / Re * (1.0 + 0.15 * Re**0.687) if Re < 1000.0 else 0.44
        return cd * rho_f * U**2 - 4.0 / 3.0 * d * (rho_s - rho_f) * g

    u_stokes = float(stokes_terminal_velocity(d, rho_s, rho_f, mu_f, g))
    return float(brentq(residual, 1e-12 * u_stokes, u_stokes, xtol=1e-14, rtol=1e-12))


def rowe_exponent(Re_t: ArrayLike) -> NDArray[np.float64]:
    """Richardson–Zaki exponent k = (4.7 + 2.35 a)/(1 + a), a = 0.175 Re_t^0.75 (Rowe 1987).

    >>> float(rowe_exponent(0.0)), round(float(rowe_exponent(1e12)), 3)
    (4.7, 2.35)
    """
    a = 0.175 * np.asarray(Re_t, dtype=float) ** 0.75
    return (4.7 + 2.35 * a) / (1.0 + a)


def khan_richardson_exponent(Ar: ArrayLike) -> NDArray[np.float64]:
    """k = (4.8 + 2.4 b)/(1 + b), b = 0.043 Ar^0.57 (Khan & Richardson 1989, no wall term).

    Ar = ρ_f (ρ_s − ρ_f) g d³/μ_f² [-].

    >>> float(khan_richardson_exponent(0.0))
    4.8
    """
    b = 0.043 * np.asarray(Ar, dtype=float) ** 0.57
    return (4.8 + 2.4 * b) / (1.0 + b)


@dataclass(frozen=True)
class KynchRow:
    """A table row with U_t [m/s], k [-], Re_t [-] and the Kynch t1 [s]."""

    row: SlisRow
    U_t: float
    k: float
    Re_t: float
    t1_kynch: float


def kynch_t1_table(H0: float = H0_THESIS, rho_f: float = RHO_WATER, mu_f: float = MU_WATER,
                   exponent: str = "rowe", g: float = 9.81) -> list[KynchRow]:
    """Kynch t1 [s] for every shipped row (assumptions in the module docstring).

    ``exponent`` is ``"rowe"`` or ``"khan_richardson"``; H0 [m].

    >>> [round(r.k, 2) for r in kynch_t1_table()[:1]]
    [2.54]
    """
    out = []
    for row in load_slis_table():
        U_t = schiller_naumann_terminal_velocity(row.d, row.rho_s, rho_f, mu_f, g)
        Re_t = rho_f * U_t * row.d / mu_f
        if exponent == "rowe":
            k = float(rowe_exponent(Re_t))
        elif exponent == "khan_richardson":
            Ar = rho_f * (row.rho_s - rho_f) * g * row.d**3 / mu_f**2
            k = float(khan_richardson_exponent(Ar))
        else:
            raise ValueError(f"unknown exponent correlation {exponent!r}")
        t1 = float(step_change_t1(row.n0, row.n1, H0, U_t, k))
        out.append(KynchRow(row, U_t, k, Re_t, t1))
    return out
