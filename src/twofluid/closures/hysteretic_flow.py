"""The hysteretic law's flow rule: no dilation on the side of a static shear above the residual
strength, so a sand with FS_post < 1 flows once liquefied (module docstring of
:mod:`twofluid.closures.hysteretic`, "Flow liquefaction"). Numba-compilable, runs un-jitted.
"""
from __future__ import annotations

from .hysteretic_layout import (C_SR, C_TAUS, NCONST)

__all__ = ['flows']


def flows(ex, c):
    """Whether an element with the constants ``c`` (:func:`twofluid.closures.hysteretic_backbone._constants`)
    has no dilation at ``ex`` = γ − γ_c: on the side of its static shear τ_s where |τ_s| exceeds
    the residual strength S_r (FS_post = S_r/|τ_s| < 1), flow liquefaction (module docstring).

    >>> c = [0.0] * NCONST; c[C_TAUS] = 5e3; c[C_SR] = 4e3
    >>> flows(0.01, c), flows(-0.01, c)
    (True, False)
    """
    ts = c[C_TAUS]
    return ts * ex > 0.0 and abs(ts) > c[C_SR]
