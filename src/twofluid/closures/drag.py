"""Interphase drag coefficient β [N·s/m⁴] (docs/model.md, "Drag").

Every law has the signature ``law(n, slip, d, rho_f, mu_f, *, stokes=False,
per_solids=False, **params)``:

- ``n`` porosity [-], ``slip`` = |U_f − U_s| [m/s] (arrays, broadcast together);
- ``d`` = ψ d_p the drag diameter [m]; ``rho_f`` [kg/m³]; ``mu_f`` [Pa·s];
- ``stokes=True`` drops the inertial part (β independent of slip);
- ``per_solids=True`` returns β/(1 − n), which stays finite in clear liquid
  (n = 1), where β itself vanishes (docs/model.md, "Numerical hygiene").

The drag force on the liquid per unit mixture volume is −β (U_f − U_s).
"""
from __future__ import annotations

import math

import numpy as np

from .registry import register

__all__ = ["ergun", "wen_yu", "gidaspow", "richardson_zaki", "ergun_richardson_zaki", "schiller_naumann_cd",
           "dallavalle_cd", "archimedes_number", "khan_richardson_exponent", "hydraulic_conductivity",
           "steady_fluidization_velocity", "wen_yu_minimum_fluidization_velocity"]

G = 9.81


def schiller_naumann_cd(re):
    """Schiller–Naumann (Rowe) drag coefficient of a sphere [-].

    C_D = 24/Re (1 + 0.15 Re^0.687) for Re < 1000, 0.44 above.
    Returns C_D·Re (finite at Re = 0, where it tends to 24).

    >>> float(schiller_naumann_cd(0.0))
    24.0
    >>> round(float(schiller_naumann_cd(2000.0)) / 2000.0, 2)
    0.44

    Reference: Schiller & Naumann (1933); Rowe (1961).
    """
    re = np.asarray(re, dtype=float)
    return np.where(re < 1000.0, 24.0 * (1.0 + 0.15 * re ** 0.687), 0.44 * re)


# The Stokes limits (stokes = true) drop the inertial drag: below Re = 1 it is under 15 % of the
# viscous drag in Schiller–Naumann's C_D and under 3 % in Ergun's law. With inertia, Wen–Yu's
# C_D = 0.44 holds up to the drag crisis of a sphere, Re ≈ 2e5.
_STOKES_RE = (0.0, 1.0)


@register("drag", "ergun", porosity_range=(0.0, 0.8), stokes_reynolds_range=_STOKES_RE,
          reference="Ergun (1952), in Gidaspow (1994) form; inertial term without the thesis's 1/n")
def ergun(n, slip, d, rho_f, mu_f, *, stokes=False, per_solids=False):
    """Ergun (dense) drag: β = 150 (1−n)² μ_f/(n d²) + 1.75 (1−n) ρ_f |U_f−U_s|/d.

    Units: β [N·s/m⁴]. Valid for packed and dense beds (n ≲ 0.6–0.8). The Stokes
    limit keeps only the first (viscous) term, which is Kozeny–Carman with 150.

    >>> b = ergun(0.4, 0.01, 1e-3, 1000.0, 1e-3)
    >>> round(float(b), 1)   # 150*0.36*1e-3/(0.4e-6) + 1.75*0.6*1000*0.01/1e-3
    145500.0

    Reference: Ergun, Chem. Eng. Prog. 48 (1952) 89; Gidaspow, Multiphase Flow
    and Fluidization (1994), eq. 5.72.
    """
    n = np.asarray(n, dtype=float)
    k = 150.0 * (1.0 - n) * mu_f / (n * d * d)
    if not stokes:
        k = k + 1.75 * rho_f * np.abs(slip) / d
    return k if per_solids else (1.0 - n) * k


@register("drag", "wen_yu", porosity_range=(0.2, 1.0), reynolds_range=(0.0, 2e5),
          stokes_reynolds_range=_STOKES_RE, reference="Wen & Yu (1966); Schiller & Naumann (1933) C_D")
def wen_yu(n, slip, d, rho_f, mu_f, *, stokes=False, per_solids=False):
    """Wen–Yu (dilute) drag: β = (3/4) C_D ρ_f n (1−n) |U_f−U_s| n^−2.65 / d.

    C_D from Schiller–Naumann at Re = ρ_f n |U_f−U_s| d / μ_f; the Stokes limit
    (C_D = 24/Re) is β = 18 μ_f (1−n) n^−2.65 / d², which makes a uniform bed
    fluidize at the Richardson–Zaki velocity U = U_t n^4.65. Units: β [N·s/m⁴].

    >>> b = wen_yu(0.7, 0.0, 1e-3, 1000.0, 1e-3, stokes=True)
    >>> round(float(b), 3)   # 18*1e-3*0.3*0.7**-2.65/1e-6
    13895.813

    Reference: Wen & Yu, Chem. Eng. Prog. Symp. Ser. 62 (1966) 100;
    Gidaspow (1994), eq. 5.73.
    """
    n = np.asarray(n, dtype=float)
    if stokes:
        cd_re = 24.0
    else:
        cd_re = schiller_naumann_cd(rho_f * n * np.abs(slip) * d / mu_f)
    # (3/4) C_D ρ_f n |s| / d  with C_D = (C_D Re)/Re and Re = ρ_f n |s| d/μ_f
    k = 0.75 * cd_re * mu_f / (d * d) * n ** -2.65
    return k if per_solids else (1.0 - n) * k


@register("drag", "gidaspow", params={"n_switch": 0.6, "blend_width": 0.0},
          porosity_range=(0.0, 1.0), reynolds_range=(0.0, 2e5), stokes_reynolds_range=_STOKES_RE,
          reference="Gidaspow (1994)")
def gidaspow(n, slip, d, rho_f, mu_f, *, stokes=False, per_solids=False,
             n_switch=0.6, blend_width=0.0):
    """Gidaspow's switched drag: Ergun below ``n_switch``, Wen–Yu above.

    With ``blend_width`` = w > 0 the two laws are blended across
    [n_switch − w, n_switch + w] by the C¹ smoothstep φ = 3x² − 2x³,
    x = (n − n_switch + w)/(2w) clipped to [0, 1]: β = (1−φ) β_Ergun + φ β_WenYu,
    each law exact outside the band. w = 0 (default) is the sharp switch of the
    thesis, at which β jumps by about 40 %: a porosity sitting at the switch can
    then make the Picard iterations cycle, which the blend avoids.
    Units: β [N·s/m⁴].

    >>> import numpy as np
    >>> b = gidaspow(np.array([0.5, 0.7]), 0.0, 1e-3, 1000.0, 1e-3, stokes=True)
    >>> bool(b[0] == ergun(0.5, 0.0, 1e-3, 1000.0, 1e-3, stokes=True))
    True

    Reference: Gidaspow, Multiphase Flow and Fluidization (1994), ch. 5.
    """
    n = np.asarray(n, dtype=float)
    args = (n, slip, d, rho_f, mu_f)
    ke = ergun(*args, stokes=stokes, per_solids=True)
    kw = wen_yu(*args, stokes=stokes, per_solids=True)
    if blend_width > 0.0:
        x = np.clip((n - n_switch + blend_width) / (2.0 * blend_width), 0.0, 1.0)
        phi = x * x * (3.0 - 2.0 * x)
    else:
        phi = (n >= n_switch).astype(float)
    k = (1.0 - phi) * ke + phi * kw
    return k if per_solids else (1.0 - n) * k


def dallavalle_cd(re):
    """Dallavalle's (1948) sphere drag coefficient as C_D·Re [-]: C_D = (0.63 + 4.8/√Re)².

    The single-particle drag of Syamlal & O'Brien's law and of Di Felice (1994); C_D·Re tends
    to 4.8² = 23.04 at Re = 0 (Stokes' 24 within 4 %) and C_D to 0.397 at large Re.

    >>> float(dallavalle_cd(0.0))
    23.04
    >>> round(float(dallavalle_cd(100.0)) / 100.0, 4)   # (0.63 + 0.48)²
    1.2321
    """
    re = np.asarray(re, dtype=float)
    r = 0.63 * np.sqrt(re) + 4.8
    return r * r


def archimedes_number(d, rho_s, rho_f, mu_f, g=G):
    """Archimedes (Galileo) number Ar = ρ_f (ρ_s − ρ_f) g d³/μ_f² [-] (d [m], densities [kg/m³], μ_f [Pa·s]).

    >>> round(float(archimedes_number(1e-3, 2600.0, 1000.0, 1e-3)), 1)
    15696.0
    """
    return rho_f * (rho_s - rho_f) * g * np.asarray(d, dtype=float) ** 3 / (mu_f * mu_f)


def khan_richardson_exponent(ar):
    """Richardson–Zaki exponent k [-] of Khan & Richardson (1989), without the wall term (d/D → 0).

    (4.8 − k)/(k − 2.4) = 0.043 Ar^0.57, i.e. k = (4.8 + 2.4 b)/(1 + b), b = 0.043 Ar^0.57:
    4.8 at Ar → 0 (Stokes), 2.4 at Ar → ∞ (Newton). Fitted for 1e-2 ≲ Re_t ≲ 1e4.

    >>> float(khan_richardson_exponent(0.0))
    4.8
    >>> round(float(khan_richardson_exponent(15696.0)), 3)   # 1 mm sand in water
    2.607

    Reference: Khan, A. R., Richardson, J. F., Chem. Eng. Commun. 78 (1989) 111–130.
    """
    b = 0.043 * np.asarray(ar, dtype=float) ** 0.57
    return (4.8 + 2.4 * b) / (1.0 + b)


# The Richardson–Zaki law holds for uniform suspensions and fluidized beds from about minimum
# fluidization (n ≈ 0.4) to a single particle, and Khan & Richardson's exponent for
# 1e-2 ≲ Re_t ≲ 1e4 (their data); Dallavalle's C_D is a fit to the standard curve below Re ≈ 1e4.
_RZ_RE = (0.0, 1e4)


@register("drag", "richardson_zaki", params={"exponent": 4.8}, porosity_range=(0.4, 1.0),
          reynolds_range=_RZ_RE, stokes_reynolds_range=_STOKES_RE,
          reference="Syamlal & O'Brien (1987) form calibrated to Richardson & Zaki (1954), "
                    "Khan & Richardson (1989) exponent; Dallavalle (1948) C_D")
def richardson_zaki(n, slip, d, rho_f, mu_f, *, stokes=False, per_solids=False, exponent=4.8):
    """Richardson–Zaki drag: β = (3/4) C_D(Re_s/V_r) ρ_f n (1−n) |U_f−U_s| / (V_r² d), V_r = n^(k−1).

    The form of Syamlal & O'Brien (1987) with its terminal-velocity ratio V_r set to the
    Richardson–Zaki value n^(k−1), k = ``exponent``: a particle in a suspension of porosity n
    feels the drag of an isolated one at the slip |s|/V_r, times n. C_D is Dallavalle's
    (:func:`dallavalle_cd`) at Re_s/V_r, Re_s = ρ_f |U_f−U_s| d/μ_f. Written out,

        β = (3/4) (C_D Re)(Re_s/V_r) μ_f (1 − n) n^(2−k) / d²        [N·s/m⁴],

    so a uniform bed at rest is held by exactly the Richardson–Zaki velocity U = U_t n^k, U_t the
    terminal velocity of a single particle with Dallavalle's C_D (docs/model.md, "Drag"). The
    case file sets k by Khan & Richardson (:func:`khan_richardson_exponent`, from the Archimedes
    number) unless ``[closures.drag] exponent`` is given. Holds for n ≥ 0.4 (a bed from
    minimum fluidization up) and Re up to 1e4; ``stokes=True`` keeps C_D Re = 23.04.

    >>> b = richardson_zaki(0.5, 0.0, 1e-3, 1000.0, 1e-3, stokes=True, exponent=4.8)
    >>> round(float(b), 3)   # 0.75*23.04*1e-3*0.5*0.5**-2.8/1e-6
    60172.455

    References: Syamlal, M., O'Brien, T. J., AIChE Symp. Ser. 85 (1989) 22–31 (the form);
    Richardson, J. F., Zaki, W. N., Trans. Inst. Chem. Eng. 32 (1954) 35–53; Khan & Richardson
    (1989); Dallavalle, J. M., Micromeritics (1948).
    """
    n = np.asarray(n, dtype=float)
    vr = n ** (exponent - 1.0)
    if stokes:
        cd_re = 23.04
    else:
        cd_re = dallavalle_cd(rho_f * np.abs(slip) * d / (mu_f * vr))
    k = 0.75 * cd_re * mu_f / (d * d) * n / vr
    return k if per_solids else (1.0 - n) * k


@register("drag", "ergun_richardson_zaki", params={"exponent": 4.8, "n_packed": 0.45, "n_fluidized": 0.49},
          porosity_range=(0.0, 1.0), reynolds_range=_RZ_RE, stokes_reynolds_range=_STOKES_RE,
          reference="Ergun (1952) up to n_packed, Richardson–Zaki (richardson_zaki) from n_fluidized, "
                    "C¹ blend between")
def ergun_richardson_zaki(n, slip, d, rho_f, mu_f, *, stokes=False, per_solids=False, exponent=4.8,
                          n_packed=0.45, n_fluidized=0.49):
    """Ergun in packed beds, Richardson–Zaki in fluidized ones: the default of liquid–solid beds.

    β = (1 − φ) β_Ergun + φ β_RZ with the C¹ smoothstep φ = 3x² − 2x³,
    x = (n − n_packed)/(n_fluidized − n_packed) clipped to [0, 1]: Ergun (:func:`ergun`, the packed
    bed's pressure drop) up to ``n_packed`` = 0.45, :func:`richardson_zaki` (the bed's
    expansion) from ``n_fluidized`` = 0.49. Between them Ergun's drag is 1.05–1.8 times the
    Richardson–Zaki law's (Re_t 0.1–1000), and the blend takes the bed from one to the other;
    the velocity that holds a uniform bed still grows with n through it. Units: β [N·s/m⁴].
    Why this default: docs/model.md, "Drag".

    >>> import numpy as np
    >>> args = (1e-3, 1000.0, 1e-3)
    >>> b = ergun_richardson_zaki(np.array([0.4, 0.6]), 0.01, *args, exponent=2.6)
    >>> bool(b[0] == ergun(0.4, 0.01, *args)), bool(b[1] == richardson_zaki(0.6, 0.01, *args, exponent=2.6))
    (True, True)

    References: Ergun (1952); Richardson & Zaki (1954); Khan & Richardson (1989).
    """
    n = np.asarray(n, dtype=float)
    args = (n, slip, d, rho_f, mu_f)
    ke = ergun(*args, stokes=stokes, per_solids=True)
    kr = richardson_zaki(*args, stokes=stokes, per_solids=True, exponent=exponent)
    x = np.clip((n - n_packed) / (n_fluidized - n_packed), 0.0, 1.0)
    phi = x * x * (3.0 - 2.0 * x)
    k = (1.0 - phi) * ke + phi * kr
    return k if per_solids else (1.0 - n) * k


def wen_yu_minimum_fluidization_velocity(d, rho_s, rho_f, mu_f, g=G) -> float:
    """Minimum fluidization velocity U_mf [m/s] of Wen & Yu (1966): Re_mf = √(33.7² + 0.0408 Ar) − 33.7.

    Re_mf = ρ_f U_mf d/μ_f; their correlation of 284 data points, ±34 % (one standard deviation).

    >>> round(wen_yu_minimum_fluidization_velocity(1e-3, 2600.0, 1000.0, 1e-3) * 1e3, 3)   # mm/s
    8.444

    Reference: Wen, C. Y., Yu, Y. H., AIChE J. 12 (1966) 610–612.
    """
    ar = float(archimedes_number(d, rho_s, rho_f, mu_f, g))
    re = math.sqrt(33.7 ** 2 + 0.0408 * ar) - 33.7
    return re * mu_f / (rho_f * d)


def hydraulic_conductivity(beta, n, rho_f, g=G):
    """Equivalent hydraulic conductivity k = ρ_f g n² / β [m/s] (Kozeny–Carman with the Stokes Ergun law).

    >>> round(float(hydraulic_conductivity(1e6, 0.4, 1000.0)), 5)
    0.00157
    """
    return rho_f * g * np.asarray(n, float) ** 2 / beta


def _velocity_root(residual, what: str) -> float:
    """The root in (0, 1000] m/s of a residual negative at 0 and growing with u (brentq)."""
    from ..scipy_kernels import brentq  # scipy.optimize's, without importing scipy.optimize

    hi = 1e-3
    while residual(hi) < 0.0:
        hi *= 2.0
        if hi > 1e3:
            raise ValueError(f"no {what} below 1000 m/s")
    return brentq(residual, 0.0, hi, xtol=1e-14, rtol=1e-13)


def steady_fluidization_velocity(law, n, d, rho_s, rho_f, mu_f, g=G, **params):
    """Superficial liquid velocity U [m/s] that holds a uniform bed at porosity n.

    With the solids at rest the liquid equation gives ∇P = ρ_f g − β s/n
    (s = U/n the slip) and the solid equation then balances
    β(n, s) s / n = (1 − n)(ρ_s − ρ_f) g: the drag carries the buoyant weight of
    the solids through the liquid pressure gradient. Solved with scipy's brentq.
    ``law`` is a drag function of this module.

    >>> u = steady_fluidization_velocity(wen_yu, 0.7, 1e-4, 2600., 1000., 1e-3, stokes=True)
    >>> ut = 1600*9.81*1e-8/18e-3
    >>> round(u / (ut * 0.7**4.65), 9)
    1.0
    """
    weight = n * (1.0 - n) * (rho_s - rho_f) * g

    def residual(u):
        s = u / n
        return float(law(n, s, d, rho_f, mu_f, **params)) * s - weight

    return _velocity_root(residual, "fluidization velocity")


def terminal_velocity(law, d, rho_s, rho_f, mu_f, g=G, **params):
    """Settling velocity U_t [m/s] of a single particle in unbounded liquid.

    Solves β/(1 − n)·U = (ρ_s − ρ_f) g at n = 1 (the drag per unit solids volume
    carries the buoyant weight) with scipy's brentq. ``law`` is a drag function of
    this module. In the Stokes limit this is Stokes' law Δρ g d²/(18 μ_f).

    >>> ut = terminal_velocity(wen_yu, 1e-4, 2600., 1000., 1e-3, stokes=True)
    >>> round(ut / (1600*9.81*1e-8/18e-3), 9)
    1.0
    """
    def residual(u):
        return float(law(1.0, u, d, rho_f, mu_f, per_solids=True, **params)) * u - (rho_s - rho_f) * g

    return _velocity_root(residual, "terminal velocity")


def slip_limit(law, factor, d, rho_s, rho_f, mu_f, g=G, **params) -> float:
    """``factor`` × the terminal velocity of ``law`` [m/s]: the ``slip_max`` of :func:`saturated_slip`.

    Infinite (no saturation) when ``factor`` is 0, when the particles do not
    sink, or when the law has no dilute limit (Ergun alone).

    >>> slip_limit(ergun, 3.0, 1e-3, 2600., 1000., 1e-3, stokes=True)
    inf
    >>> round(slip_limit(wen_yu, 3.0, 1e-4, 2600., 1000., 1e-3, stokes=True) / (1600*9.81*1e-8/18e-3), 9)
    3.0
    """
    if factor <= 0.0 or rho_s <= rho_f:
        return np.inf
    try:
        return factor * terminal_velocity(law, d, rho_s, rho_f, mu_f, g, **params)
    except ValueError:
        return np.inf


def saturated_slip(slip_abs, slip_max, p=4):
    """|slip| passed to a drag law, saturating smoothly at ``slip_max`` [m/s].

    s_eff = s / (1 + (s/s_max)^p)^(1/p): equal to s to within (s/s_max)^p / p for
    s ≪ s_max, increasing, and tending to s_max as s → ∞. It keeps the
    Reynolds-number dependence of β finite where 1 − n → 0 makes the slip
    (V − W)/(2(1 − n)) of a nearly empty element unbounded (docs/model.md,
    "Numerical hygiene"); the
    project's models use s_max = 3 U_t (three terminal velocities).

    >>> round(float(saturated_slip(0.01, 1.0)), 9)
    0.01
    >>> round(float(saturated_slip(1e9, 1.0)), 12)
    1.0
    """
    s = np.asarray(slip_abs, float)
    if not math.isfinite(slip_max):
        return s
    r = s / slip_max
    return np.where(r > 1e6, slip_max, s / (1.0 + r**p) ** (1.0 / p))
