"""Compiled forms of the closure laws the 1D models' compiled iterates call, element by element.

The closures are pure vectorised NumPy functions in the registry (:mod:`.registry`), and they
stay the reference. On arrays of a few hundred entries each of them costs 15–30 µs, nearly all
of it NumPy's per-operation overhead, and a compiled 1D iterate calls three of them: about a
third of a compiled step (docs/benchmarks.md). So each law those iterates use has a compiled
form here as well: the same formula for one element, in the same order of operations, looped
over the entries in one call. Tests check every form against its registry function over the
laws' ranges (``tests/unit/test_closure_kernels.py``); the two differ by the last bits of
``exp`` and ``pow`` (libm against NumPy's), a few ulp. Wen–Yu's two powers per point are the
exception: libm's scalar ``pow`` (~15 ns) would make the compiled law no faster than NumPy's
SIMD one on a fluidized bed's 600 points, so its loop is split around the two powers, which
NumPy computes (:meth:`CompiledLaws.beta_per_solids`).

Covered: the drag laws ``ergun``, ``wen_yu``, ``gidaspow``, ``richardson_zaki`` and
``ergun_richardson_zaki`` (with its default transition 0.45–0.49; with the |slip| saturation of
:func:`.drag.saturated_slip`), the exponential P_s with the Foscolo–Gibilaro term, and the
solid-phase viscosity from ``mooney_pringle``. :func:`for_closures` returns None for a run that
uses any other law (or per-element values where these take one value): its model then calls the
registry functions, as it does on the NumPy path. A new law in the registry needs nothing
here; a compiled form only makes it faster.

>>> from twofluid.models.data_1d import Closures, Materials
>>> laws = for_closures(Closures(), Materials(1000.0, 1e-3, 2600.0, 1e-3))
>>> laws is None or laws.drag_law == "gidaspow"
True
"""
from __future__ import annotations

import math

import numpy as np

from . import drag as drag_laws
from . import solids_pressure as ps_laws
from .viscosity import K1, K2, _blend_coefficients

__all__ = ["for_closures", "CompiledLaws"]

ERGUN, WEN_YU, GIDASPOW, RICHARDSON_ZAKI, ERGUN_RZ = 0, 1, 2, 3, 4
_DRAG_IDS = {drag_laws.ergun: ERGUN, drag_laws.wen_yu: WEN_YU, drag_laws.gidaspow: GIDASPOW,
             drag_laws.richardson_zaki: RICHARDSON_ZAKI, drag_laws.ergun_richardson_zaki: ERGUN_RZ}
_DRAG_PARAMS = {ERGUN: {"stokes"}, WEN_YU: {"stokes"}, GIDASPOW: {"stokes", "n_switch", "blend_width"},
                RICHARDSON_ZAKI: {"stokes", "exponent"}, ERGUN_RZ: {"stokes", "exponent"}}
# ergun_richardson_zaki's transition, as the registry function's defaults (a case cannot change them)
_RZ_PACKED, _RZ_FLUIDIZED = 0.45, 0.49
_MAX_EXPONENT = 700.0  # as solids_pressure._MAX_EXPONENT


def _ergun(n, s, d, rho_f, mu_f, stokes):
    """:func:`.drag.ergun` per solids (β/(1 − n)) at one point."""
    k = 150.0 * (1.0 - n) * mu_f / (n * d * d)
    if not stokes:
        k = k + 1.75 * rho_f * abs(s) / d
    return k


def _wen_yu(n, s, d, rho_f, mu_f, stokes):
    """:func:`.drag.wen_yu` per solids at one point (Schiller–Naumann C_D Re)."""
    if stokes:
        cd_re = 24.0
    else:
        re = rho_f * n * abs(s) * d / mu_f
        cd_re = 24.0 * (1.0 + 0.15 * re ** 0.687) if re < 1000.0 else 0.44 * re
    return 0.75 * cd_re * mu_f / (d * d) * n ** -2.65


def _drag(law, n, s, d, rho_f, mu_f, stokes, n_switch, blend_width):
    """β/(1 − n) of drag law ``law`` (ERGUN, WEN_YU, GIDASPOW, RICHARDSON_ZAKI, ERGUN_RZ) at one point.

    ``n_switch`` carries the law's one parameter: Gidaspow's switch, or the Richardson–Zaki
    exponent k of the two Richardson–Zaki laws."""
    if law == ERGUN:
        return _ergun(n, s, d, rho_f, mu_f, stokes)
    if law == WEN_YU:
        return _wen_yu(n, s, d, rho_f, mu_f, stokes)
    if law == RICHARDSON_ZAKI or law == ERGUN_RZ:
        # :func:`.drag.richardson_zaki` per solids (exponent k = n_switch, Dallavalle's C_D Re), written
        # here rather than as a helper so the models' kernel groups need no new helper
        phi = 1.0
        if law == ERGUN_RZ:
            x = (n - _RZ_PACKED) / (_RZ_FLUIDIZED - _RZ_PACKED)
            x = 0.0 if x < 0.0 else (1.0 if x > 1.0 else x)  # np.clip (NaN stays NaN)
            phi = x * x * (3.0 - 2.0 * x)
            if phi == 0.0 and n > 0.0 and abs(s) < math.inf:
                return _ergun(n, s, d, rho_f, mu_f, stokes)
        vr = n ** (n_switch - 1.0)
        if stokes:
            cd_re = 23.04
        else:
            r = 0.63 * math.sqrt(rho_f * abs(s) * d / (mu_f * vr)) + 4.8
            cd_re = r * r
        kr = 0.75 * cd_re * mu_f / (d * d) * n / vr
        if phi == 1.0 and (law == RICHARDSON_ZAKI or (n > 0.0 and abs(s) < math.inf)):
            return kr
        return (1.0 - phi) * _ergun(n, s, d, rho_f, mu_f, stokes) + phi * kr
    if blend_width > 0.0:
        x = (n - n_switch + blend_width) / (2.0 * blend_width)
        x = 0.0 if x < 0.0 else (1.0 if x > 1.0 else x)  # np.clip (NaN stays NaN)
        phi = x * x * (3.0 - 2.0 * x)
    else:
        phi = 1.0 if n >= n_switch else 0.0
    # outside the blend one law alone: (1 − φ) β_E + φ β_W is that law's value exactly where the
    # other is finite (n > 0 and a finite slip), and the other law's pow calls are saved
    one = n > 0.0 and abs(s) < math.inf
    if phi == 0.0 and one:
        return _ergun(n, s, d, rho_f, mu_f, stokes)
    if phi == 1.0 and one:
        return _wen_yu(n, s, d, rho_f, mu_f, stokes)
    ke = _ergun(n, s, d, rho_f, mu_f, stokes)
    kw = _wen_yu(n, s, d, rho_f, mu_f, stokes)
    return (1.0 - phi) * ke + phi * kw


def _beta_per_solids(law, stokes, n_switch, blend_width, slip_max, n, slip, d, rho_f, mu_f, out):
    """``out[i]`` = β/(1 − n)(n[i], saturated |slip[i]|) with ``d[i % d.size]`` (d per element
    or one value): :meth:`Closures.beta_per_solids <twofluid.models.data_1d.Closures.beta_per_solids>`."""
    m = d.size
    j = 0  # i % m, counted (an integer division per point cost a quarter of these loops)
    for i in range(n.size):
        out[i] = _drag(law, n[i], _saturated(slip[i], slip_max), d[j], rho_f, mu_f, stokes, n_switch,
                       blend_width)
        j = _next(j, m)


def _next(j, m):
    """(j + 1) % m for 0 ≤ j < m, without the integer division."""
    j += 1
    return 0 if j == m else j


def _saturated(s, slip_max):
    """:func:`.drag.saturated_slip` with p = 4 at one point: s/(1 + r⁴)^¼, r = s/s_max (s itself
    where r⁴ is below half an ulp of 1, as there)."""
    if slip_max < math.inf:
        r = s / slip_max
        if r > 1e6:
            return slip_max
        r4 = (r * r) * (r * r)
        if not r4 < 1e-16:
            return s / math.sqrt(math.sqrt(1.0 + r4))
    return s


def _wen_yu_reynolds(slip_max, n, slip, d, rho_f, mu_f, re):
    """``re[i]`` = ρ_f n |s| d/μ_f at the saturated slip (the Reynolds number of :func:`_wen_yu`)."""
    m = d.size
    j = 0  # i % m
    for i in range(n.size):
        re[i] = rho_f * n[i] * abs(_saturated(slip[i], slip_max)) * d[j] / mu_f
        j = _next(j, m)


def _wen_yu_given(stokes, n, re, re_pow, n_pow, d, mu_f, out):
    """:func:`_wen_yu` per solids with its two powers given: ``re_pow`` = Re^0.687 (unused if
    ``stokes``) and ``n_pow`` = n^−2.65."""
    m = d.size
    j = 0  # i % m
    for i in range(n.size):
        if stokes:
            cd_re = 24.0
        else:
            cd_re = 24.0 * (1.0 + 0.15 * re_pow[i]) if re[i] < 1000.0 else 0.44 * re[i]
        di = d[j]
        out[i] = 0.75 * cd_re * mu_f / (di * di) * n_pow[i]
        j = _next(j, m)


def _solids_pressure(n, n_bar, A, p_ref, modulus, fluidized, ps, dps):
    """P_s and ∂P_s/∂n: :func:`.solids_pressure.exponential` with ``A[i % A.size]`` and
    ``p_ref[i % p_ref.size]``, plus the Foscolo–Gibilaro term of modulus ``modulus[i % modulus.size]``
    if ``fluidized``."""
    ma, mp, mm = A.size, p_ref.size, modulus.size
    ja = jp = jm = 0  # i % ma, i % mp, i % mm
    for i in range(n.size):
        one_m = 1.0 - n[i]
        a = A[ja]
        if one_m > 0.0:
            s_bar = 1.0 - n_bar[i]
            x = (1.0 - s_bar / one_m) / a
            p = p_ref[jp] * math.exp(x if not x > _MAX_EXPONENT else _MAX_EXPONENT)
            dp = -p * s_bar / (a * one_m * one_m)
        else:
            p = 0.0
            dp = 0.0
        if fluidized:
            mod = modulus[jm]
            p = p + 0.5 * mod * one_m * one_m
            dp = dp + -mod * one_m
        ps[i] = p
        dps[i] = dp
        ja, jp, jm = _next(ja, ma), _next(jp, mp), _next(jm, mm)


def _mooney(n, mu_f, k1, k2, eps_blend, n_c, b, c):
    """:func:`.viscosity.mooney_pringle` at one point, with the blend's cubic coefficients ``b``, ``c``."""
    e = 1.0 - n
    top = 1.0 - n_c
    eps = e if not e < 0.0 else 0.0  # np.maximum / np.minimum: NaN propagates
    eps = eps if not eps > top else top
    if eps < eps_blend:
        return mu_f * (1.0 + eps * (2.5 + eps * (b + c * eps)))
    return mu_f * math.exp(math.exp(eps / (k1 + k2 * eps)))


def _viscosity(n, mu_f, k1, k2, eps_blend, n_c, b, c, solid, out):
    """``out`` = μ_s (``solid``: :func:`.viscosity.solid_viscosity`) or the mixture's μ_m
    (:func:`.viscosity.mooney_pringle`) [Pa·s] at porosities ``n``."""
    for i in range(n.size):
        mu_m = _mooney(n[i], mu_f, k1, k2, eps_blend, n_c, b, c)
        if solid:
            e = 1.0 - n[i]
            out[i] = (mu_m - n[i] * mu_f) / e if e > 1e-6 else 3.5 * mu_f
        else:
            out[i] = mu_m


# C-contiguous arrays (the ahead-of-time module checks each on each call, a ValueError otherwise:
# check_layouts, twofluid.compiled._unbox_checked): the argument types the models' compiled steps call
# these loops with, so that a build compiles each once (twofluid.compiled._stub)
C1 = "f8[::1]"
SIGNATURES = {
    "beta_per_solids": f"void(i8,b1,f8,f8,f8,{C1},{C1},{C1},f8,f8,{C1})",
    "solids_pressure": f"void({C1},{C1},{C1},{C1},{C1},b1,{C1},{C1})",
    "viscosity": f"void({C1},f8,f8,f8,f8,f8,f8,f8,b1,{C1})",
    "wen_yu_reynolds": f"void(f8,{C1},{C1},{C1},f8,f8,{C1})",
    "wen_yu_given": f"void(b1,{C1},{C1},{C1},{C1},{C1},f8,{C1})",
}
_KERNELS = None
_TRIED = False


def _compiled():
    """{name: compiled kernel} (:func:`twofluid.compiled.group`), or None without numba."""
    global _KERNELS, _TRIED
    if not _TRIED:
        _TRIED = True
        from ..compiled import group

        funcs = {"beta_per_solids": _beta_per_solids, "solids_pressure": _solids_pressure,
                 "viscosity": _viscosity, "wen_yu_reynolds": _wen_yu_reynolds,
                 "wen_yu_given": _wen_yu_given}
        _KERNELS = group("closures_1d", {k: (f, SIGNATURES[k]) for k, f in funcs.items()},
                         helpers=(_ergun, _wen_yu, _drag, _saturated, _mooney, _next, *funcs.values()),
                         check_layouts=True)
    return _KERNELS


def _vector(x) -> np.ndarray | None:
    """``x`` as a 1D float array (a scalar as one entry), or None if it is not numeric."""
    try:
        a = np.asarray(x, dtype=float)
    except (TypeError, ValueError):
        return None
    return np.ascontiguousarray(a.reshape(-1))


class CompiledLaws:
    """A run's drag, P_s and μ_s laws compiled, with the registry calls' results (:func:`for_closures`)."""

    def __init__(self, kernels: dict, law: int, drag_law: str, drag_args: tuple, slip_max: float,
                 d: np.ndarray, rho_f: float, mu_f: float, A: np.ndarray, p_ref: np.ndarray,
                 modulus: np.ndarray | None, viscosity_args: tuple):
        self._k = kernels
        self.drag_law = drag_law
        self._drag = (law, *drag_args, slip_max)
        self._d, self._rho_f, self._mu_f = d, rho_f, mu_f
        self._ps = (A, p_ref, modulus if modulus is not None else np.zeros(1), modulus is not None)
        self._visc = viscosity_args

    def beta_per_solids(self, n: np.ndarray, slip: np.ndarray, out: np.ndarray | None = None) -> np.ndarray:
        """β/(1 − n) [N·s/m⁴] at porosities ``n`` and |slip| ``slip`` [m/s] (1D float arrays of one
        size, or a whole number of copies of the elements, each with its element's diameter); into
        ``out`` if given (a C-contiguous float array of that size)."""
        if out is None:
            out = np.empty(n.size)
        law, stokes, slip_max = self._drag[0], self._drag[1], self._drag[-1]
        if law == WEN_YU:  # its two powers by NumPy's SIMD routines (wen_yu_powers)
            re = np.empty(n.size)
            self._k["wen_yu_reynolds"](slip_max, n, slip, self._d, self._rho_f, self._mu_f, re)
            n_pow, re_pow = self.wen_yu_powers(n, re)
            self._k["wen_yu_given"](stokes, n, re, re_pow, n_pow, self._d, self._mu_f, out)
            return out
        self._k["beta_per_solids"](*self._drag, n, slip, self._d, self._rho_f, self._mu_f, out)
        return out

    def wen_yu_powers(self, n: np.ndarray, re: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Wen–Yu's (n^−2.65, Re^0.687) at porosities ``n`` and Reynolds numbers ``re`` by NumPy's array
        power, 2.4x faster than libm's scalar ``pow`` in a compiled loop (with Stokes drag Re's is
        not used: n's stands in)."""
        n_pow = n ** -2.65
        return n_pow, (n_pow if self._drag[1] else re ** 0.687)

    def kernel_args(self) -> tuple:
        """The laws as a compiled caller passes them to this module's loops: (drag law id, [stokes,
        n_switch, blend_width, slip_max, ρ_f], d, A, p_ref, modulus, fluidized, [k1, k2, eps_blend,
        n_c, b, c]) (``twofluid.models.reduced_kernel._whole_iterate``)."""
        law, stokes, n_switch, blend_width, slip_max = self._drag
        A, p_ref, modulus, fluidized = self._ps
        return (law, np.array([float(stokes), n_switch, blend_width, slip_max, self._rho_f]), self._d, A, p_ref,
                modulus, fluidized, np.array(self._visc, dtype=float))

    def solids_pressure(self, n: np.ndarray, n_bar: np.ndarray, out: tuple | None = None) -> tuple[np.ndarray, np.ndarray]:
        """(P_s, ∂P_s/∂n) [Pa] at porosities ``n`` of the elements with reference porosities ``n_bar``;
        into the two arrays ``out`` if given."""
        ps, dps = (np.empty(n.size), np.empty(n.size)) if out is None else out
        self._k["solids_pressure"](n, n_bar, *self._ps, ps, dps)
        return ps, dps

    def solid_viscosity(self, n: np.ndarray, out: np.ndarray | None = None) -> np.ndarray:
        """μ_s [Pa·s] at porosities ``n``; into ``out`` if given."""
        if out is None:
            out = np.empty(n.size)
        self._k["viscosity"](n, self._mu_f, *self._visc, True, out)
        return out

    def mixture_viscosity(self, n: np.ndarray) -> np.ndarray:
        """μ_m [Pa·s] (:func:`~twofluid.closures.viscosity.mooney_pringle`) at porosities ``n``."""
        out = np.empty(n.size)
        self._k["viscosity"](n, self._mu_f, *self._visc, False, out)
        return out


def for_closures(clo, mat) -> CompiledLaws | None:
    """The compiled laws of a run's :class:`~twofluid.models.data_1d.Closures` and
    :class:`~twofluid.models.data_1d.Materials`, or None: without numba, for a law with no
    compiled form here, or for per-element liquid properties or drag and viscosity parameters
    (the registry calls take those; the particle diameter, A and p_ref may be per element)."""
    law = _DRAG_IDS.get(clo.drag)
    if law is None or not set(clo.drag_params) <= _DRAG_PARAMS[law]:
        return None
    if clo.fluidized_pressure not in (None, ps_laws.foscolo_gibilaro) or set(clo.fluidized_params) - {"coefficient"}:
        return None
    if set(clo.viscosity_params) - {"k1", "k2", "eps_blend", "n_c"}:
        return None
    scalars = [clo.drag_params.get("n_switch", 0.6), clo.drag_params.get("exponent", 4.8), clo.drag_params.get("blend_width", 0.0), clo.slip_max,
               mat.rho_f, mat.mu_f, mat.rho_s, mat.g, *clo.viscosity_params.values(),
               *clo.fluidized_params.values()]
    if any(np.ndim(v) != 0 for v in scalars) or np.ndim(clo.drag_params.get("stokes", False)) != 0:
        return None
    d, A, p_ref = _vector(mat.d), _vector(clo.A), _vector(clo.p_ref)
    if d is None or A is None or p_ref is None:
        return None
    kernels = _compiled()
    if kernels is None:
        return None
    modulus = None
    if clo.fluidized_pressure is not None:  # foscolo_gibilaro's c g d (ρ_s − ρ_f), per element if d is
        c = clo.fluidized_params.get("coefficient", 3.2)
        modulus = np.ascontiguousarray(c * mat.g * d * (mat.rho_s - mat.rho_f), dtype=float)
    vp = clo.viscosity_params
    k1, k2 = float(vp.get("k1", K1)), float(vp.get("k2", K2))
    eps_b, n_c = float(vp.get("eps_blend", 0.2)), float(vp.get("n_c", 0.5))
    b, c = _blend_coefficients(eps_b, k1, k2)
    second = clo.drag_params.get("exponent", 4.8) if law in (RICHARDSON_ZAKI, ERGUN_RZ) \
        else clo.drag_params.get("n_switch", 0.6)  # the parameter slot of _drag
    drag_args = (bool(clo.drag_params.get("stokes", False)), float(second),
                 float(clo.drag_params.get("blend_width", 0.0)))
    return CompiledLaws(kernels, law, clo.drag.__name__, drag_args, float(clo.slip_max), d, float(mat.rho_f),
                        float(mat.mu_f), A, p_ref, modulus, (k1, k2, eps_b, n_c, float(b), float(c)))
