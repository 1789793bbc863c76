"""What the hysteretic law's damage count tells an engineer about each element, and the strains the
run leaves: the damage-equivalent uniform CSR and the residual shear strain.

An element of the hysteretic law (:mod:`twofluid.closures.hysteretic`) counts damage
D = Σ 1/(2 N_L) over its half cycles, N_L = 15 (CRR/CSR)^(1/b), and liquefies at D = 1. The uniform
cyclic stress ratio that would have caused the same damage in 15 cycles is

    CSR_eq15 = CRR · D^b,

with the element's CRR (CRR_M7.5 K_σ, times K_α on a slope) and b, the slope of its CSR–N curve.
CSR_eq15 ≥ CRR means the element has taken the damage of liquefaction; below CRR, its loading fell
short by that ratio. :class:`DamageRecord` keeps it at three moments: the first liquefaction
anywhere in the column, the first liquefaction of an element below this one (the sand above a
liquefied band is shielded from then on), and the end of the shaking.

The residual shear strain is the element's γ at the end of the run less its static strain (on
level ground the static strain is 0).
"""
from __future__ import annotations

import numpy as np

from ..closures import hysteretic as law

__all__ = ["DamageRecord", "csr_eq15", "DAMAGE_COLUMNS"]

#: elements.csv columns written from a :class:`DamageRecord` (empty cells for the thesis model and the crust)
DAMAGE_COLUMNS = ["CRR_model", "b_model", "CSR_eq15_first_liquefaction", "CSR_eq15_first_liquefaction_below",
                  "CSR_eq15_end_of_shaking", "residual_shear_strain"]


def csr_eq15(damage, crr, b):
    """CSR_eq15 = CRR · D^b [-]: the uniform CSR that gives damage D [-] in 15 cycles.

    >>> round(float(csr_eq15(1.0, 0.12, 0.19)), 6), round(float(csr_eq15(0.5, 0.12, 0.2)), 6)
    (0.12, 0.104466)
    """
    d = np.maximum(np.asarray(damage, dtype=float), 0.0)
    return np.asarray(crr, dtype=float) * d ** np.asarray(b, dtype=float)


class DamageRecord:
    """Damage snapshots of the saturated elements (bottom first) of a column with the hysteretic law.

    Call :meth:`record` with each state the run yields and the mask of the elements liquefied in it.
    """

    def __init__(self, col):
        par = col.hysteretic
        self.active = par is not None
        ns = col.n_sat
        self.ns, self.shaking_end = ns, col.shaking_end
        self.crr = par[:ns, law.P_CRR].copy() if self.active else np.full(ns, np.nan)
        self.b = par[:ns, law.P_B].copy() if self.active else np.full(ns, np.nan)
        self.liquefiable = par[:ns, law.P_LIQ] > 0.0 if self.active else np.zeros(ns, dtype=bool)
        h = col.wave.h
        u0 = getattr(col, "u_static", None)
        self.gamma_static = np.zeros(h.size) if u0 is None else np.diff(np.asarray(u0, dtype=float)) / h
        self.d_first_any = np.full(ns, np.nan)
        self.d_first_below = np.full(ns, np.nan)
        self._end_shear = None  # the law's state at the last step of the shaking (its damage: d_end)
        self.lowest = ns  # lowest element index that has liquefied so far
        self._gamma = np.zeros(h.size)  # γ of the last state recorded (its own array: read when asked)

    @property
    def gamma_end(self) -> np.ndarray:
        """γ of every element of the shear column in the last state recorded (zeros before one) [-], a copy."""
        return np.array(self._gamma, dtype=float)

    def record(self, s, liquefied, low: int | None = None) -> None:
        """Snapshots of this state ``s`` (a ColumnState) with ``liquefied`` (bool per saturated element);
        ``low``: the lowest liquefied element, −1 where none is (found in ``liquefied`` where not given)."""
        self._gamma = s.wave.gamma  # (each step's strains are a new array, not written after the step)
        if not self.active:
            return
        st = s.shear
        if s.t <= self.shaking_end + 1e-9:
            self._end_shear = st  # (each step's law state is a new array; the damage columns stay as they are)
        if low is None:
            low = int(liquefied.argmax())  # the lowest liquefied element (0 where none is)
            if not liquefied[low]:
                return
        elif low < 0:
            return
        first = self.d_first_any[0] != self.d_first_any[0]  # (NaN: not yet taken)
        if not first and low >= self.lowest:
            return
        d = self._damage(st)
        if first:
            self.d_first_any[:] = d
        if low < self.lowest:  # every element above a newly liquefied one, not yet taken
            take = np.zeros(self.ns, dtype=bool)
            take[low + 1:self.lowest + 1] = True  # (the previous lowest had none below it)
            self.d_first_below[take] = d[take]
            self.lowest = low

    def _damage(self, st) -> np.ndarray:
        """D of the saturated elements in the law state ``st`` [-]."""
        return st[:self.ns, law.S_D] + st[:self.ns, law.S_DPART]

    @property
    def d_end(self) -> np.ndarray:
        """D of the saturated elements at the last step of the shaking (NaN before it) [-]."""
        return np.full(self.ns, np.nan) if self._end_shear is None else self._damage(self._end_shear)

    def columns(self, e: int) -> list:
        """The :data:`DAMAGE_COLUMNS` of element ``e`` (whole column's index: saturated bottom first, then
        the crust); None where it does not apply."""
        resid = float(self._gamma[e] - self.gamma_static[e])
        if e >= self.ns or not self.active or not self.liquefiable[e]:
            return [None] * 5 + [resid]
        c, b = float(self.crr[e]), float(self.b[e])

        def eq(d):
            return None if not np.isfinite(d) else float(csr_eq15(d, c, b))
        return [c, b, eq(self.d_first_any[e]), eq(self.d_first_below[e]), eq(self.d_end[e]), resid]

    def summary(self, col, last, liquefied_thickness_m: float, peak_strain) -> dict:
        """The liquefied layer's mean residual strain (surface displacement over the liquefied
        thickness) and the largest residual and peak (``peak_strain``, |γ| per element) element strains."""
        resid = self.gamma_end - self.gamma_static
        e = int(np.argmax(np.abs(resid)))
        disp = float(col.surface_displacement(last))
        return {"surface_displacement_m": disp,
                "mean_residual_strain_liquefied": (disp / liquefied_thickness_m if liquefied_thickness_m > 0.0
                                                   else None),
                "largest_residual_strain": float(resid[e]),
                "largest_residual_strain_depth_m": self._depth(col, e),
                "largest_peak_strain": float(np.max(peak_strain)),
                "largest_peak_strain_depth_m": self._depth(col, int(np.argmax(peak_strain))),
                "definition": "residual: the shear strain at the end of the run less the static strain; mean over "
                              "the liquefied thickness: surface displacement / liquefied_thickness_m; peak: the "
                              "largest |gamma| of any element (static strain included)"}

    @staticmethod
    def _depth(col, e: int) -> float:
        return float(col.ground_surface - 0.5 * (col.y_all[e] + col.y_all[e + 1]))
