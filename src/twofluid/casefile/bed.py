"""The initial bed of a 1D case as a process engineer gives it.

``[initial]`` sets the bed by its porosity (or ``state = "fluidized"``: the porosity at
which the inlet velocity at t = 0 holds a uniform bed, from the case's own drag law)
and by its height, its solids mass or its settled height at a packing porosity. A bed
given by its solids inventory has its surface placed exactly: the element it cuts holds
the solids of the part below it, so the inventory is the one asked for. A bed given by its
height fills whole elements (those whose centres lie below it), with a one-line warning
when that moves the surface: a cut element starts as a dilute layer out of balance on top
of the bed, which shifts t1 by about 9 % on the Slis bed at 90 elements.
"""
from __future__ import annotations

import warnings

import numpy as np
from ..scipy_kernels import brentq  # scipy.optimize's, without importing scipy.optimize (0.35 s)

from .schema import CaseError, CaseWarning

__all__ = ["volume_below", "height_of_volume", "bed_porosity", "fluidized_porosity", "initial_bed"]


def volume_below(mesh, h: float) -> float:
    """Column volume [m³] between the bottom and the height ``h`` [m] above it (area linear per element).

    >>> from twofluid.mesh.line import uniform_line
    >>> round(volume_below(uniform_line(2.0, 2, area=(1.0, 3.0)), 1.5), 12)  # 1.5 + (2 + 2.5)/2 · 0.5
    2.625
    """
    y = mesh.y - mesh.y[0]
    x = np.clip(h - y[:-1], 0.0, mesh.lengths)  # length of each element below h
    slope = mesh.area_slope
    return float((mesh.area[:-1] * x + 0.5 * slope * x * x).sum())


def height_of_volume(mesh, volume: float) -> float:
    """Height [m] above the bottom below which the column holds ``volume`` [m³] (its length if more)."""
    total = float(mesh.volumes.sum())
    length = float(mesh.y[-1] - mesh.y[0])
    if volume >= total:
        return length
    return float(brentq(lambda h: volume_below(mesh, h) - volume, 0.0, length, xtol=1e-15, rtol=1e-14))


def bed_porosity(mesh, n: float, h: float) -> np.ndarray:
    """Element porosities of a uniform bed at ``n`` up to ``h`` [m] with clear liquid above.

    The element cut by the surface holds the solids of its part below ``h``:
    1 − n_e = (1 − n) × (its volume below h)/(its volume).

    >>> from twofluid.mesh.line import uniform_line
    >>> [round(float(x), 12) for x in bed_porosity(uniform_line(1.0, 4), 0.6, 0.6)]
    [0.6, 0.6, 0.84, 1.0]
    """
    y = mesh.y - mesh.y[0]
    x = np.clip(h - y[:-1], 0.0, mesh.lengths)
    below = mesh.area[:-1] * x + 0.5 * mesh.area_slope * x * x
    frac = below / mesh.volumes
    frac = np.where(np.abs(frac - 1.0) < 1e-12, 1.0, np.where(frac < 1e-12, 0.0, frac))  # faces stay faces
    return 1.0 - (1.0 - n) * frac


def fluidized_porosity(clo, mat, u: float, source: str = "<case>") -> float:
    """Porosity [-] at which the superficial velocity ``u`` [m/s] holds a uniform bed (the case's drag law).

    Inverts :func:`~twofluid.closures.drag.steady_fluidization_velocity`, which grows with n
    from 0 to the terminal velocity U_t.
    """
    key = "[initial] state = 'fluidized'"

    def U(n):
        return clo.fluidization_velocity(n, mat)

    if not u > 0.0:
        raise CaseError(source, key, f"needs an upward inlet velocity at t = 0 (got {u:g} m/s)")
    lo, hi = 1e-3, 1.0 - 1e-9
    try:
        u_lo, u_hi = U(lo), U(hi)
    except ValueError as exc:
        raise CaseError(source, key, f"no fluidization velocity for these particles ({exc})") from None
    if not u_lo < u < u_hi:
        raise CaseError(source, key, f"the inlet velocity at t = 0 ({u:.4g} m/s) is outside the fluidized "
                        f"range {u_lo:.3g}–{u_hi:.4g} m/s of the drag law (up to the terminal velocity)")
    return float(brentq(lambda n: U(n) - u, lo, hi, xtol=1e-14, rtol=1e-13))


def initial_bed(mesh, case: dict, clo, mat, u0: float) -> tuple[float, float, np.ndarray]:
    """(bed porosity, bed height [m], element porosities) of the case's ``[initial]`` section.

    ``u0`` [m/s]: the inlet velocity into the column at t = 0 (for ``state = "fluidized"``).
    """
    init, src = case["initial"], case.get("_source", "<case>")
    n = fluidized_porosity(clo, mat, u0, src) if init["state"] == "fluidized" else init["porosity"]
    length = float(mesh.y[-1] - mesh.y[0])
    if init["solids_mass"] > 0.0 or init["settled_height"] > 0.0:
        if init["solids_mass"] > 0.0:
            vs, key = init["solids_mass"] / mat.rho_s, "solids_mass"
        else:
            vs = (1.0 - init["settled_porosity"]) * volume_below(mesh, init["settled_height"])
            key = "settled_height"
        if vs > (1.0 - n) * float(mesh.volumes.sum()) * (1.0 + 1e-12):
            raise CaseError(src, f"[initial] {key}", f"the solids ({vs:.4g} m³) do not fit in the column at "
                            f"porosity {n:.4g} (room for {(1.0 - n) * mesh.volumes.sum():.4g} m³)")
        h = height_of_volume(mesh, vs / (1.0 - n))
        return n, h, bed_porosity(mesh, n, h)
    if init["bed_height"] <= 0:
        return n, length, np.full(mesh.n_elements, n)
    # a height fills the elements whose centres lie below it (the surface on an element face:
    # a cut element would start as a dilute layer out of balance on the bed), and says so
    h = init["bed_height"]
    inside = mesh.centres - mesh.y[0] < h
    used = float(mesh.y[int(inside.sum())] - mesh.y[0])
    if abs(used - h) > 1e-9 * max(h, 1e-3):
        warnings.warn(CaseWarning(
            f"{src}: [initial] bed_height: {h:g} m is not on an element face; the bed fills the elements "
            f"whose centres lie below it, up to {used:g} m (solids_mass or settled_height place the "
            "surface exactly)"), stacklevel=3)
    return n, used, np.where(inside, n, 1.0)
