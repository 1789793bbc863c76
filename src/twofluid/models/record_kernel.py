"""The liquefaction column's per-step record in one compiled call.

After every split step the run keeps, per saturated element, the peak excess pore-pressure ratio
r_u and when it was reached, the time r_u first passed the liquefaction threshold, the peak shear
strain, the largest settlement contribution h (n0 − n)/(1 − n), and per step the surface
settlement, the base's excess pressure, the top element's r_u and the seepage at the water table
(``runners.liquefaction._Recorder``). :func:`record_step` does all of it in one loop over the
elements, written once in numba-compatible Python (:mod:`twofluid.compiled`), with the NumPy
expressions' arithmetic in the same order, so that the compiled record, the plain-Python one
(``TWOFLUID_DISABLE_JIT=1``) and the former NumPy one are the same numbers, bit for bit:

- r_u = (P − P_hydrostatic)/σ′_v0 and the settlement contribution h (n0 − n)/(1 − n) element by
  element, as NumPy's element-wise operations;
- maxima as ``np.maximum`` (a NaN is kept);
- the settlement, the sum of the contributions, in NumPy's pairwise order (:func:`_pairwise_sum`,
  the order of ``np.add.reduce`` on a contiguous float64 array).

>>> import numpy as np
>>> a = np.linspace(0.1, 3.7, 37)
>>> bool(_np_sum(a) == np.sum(a))
True
"""
from __future__ import annotations

import numpy as np

__all__ = ["record_step", "compiled"]

#: NumPy's block of the pairwise sum (``PW_BLOCKSIZE`` in its loops): below it, eight running sums
_BLOCK = 128


def _block_sum(a, lo, n):
    """Σ a[lo:lo + n], n ≤ :data:`_BLOCK`, in NumPy's order: a plain sum below 8 terms, else eight
    running sums combined pairwise, then the remainder."""
    if n < 8:
        res = 0.0
        for i in range(lo, lo + n):
            res += a[i]
        return res
    r0 = a[lo]
    r1 = a[lo + 1]
    r2 = a[lo + 2]
    r3 = a[lo + 3]
    r4 = a[lo + 4]
    r5 = a[lo + 5]
    r6 = a[lo + 6]
    r7 = a[lo + 7]
    m = n - n % 8
    for i in range(lo + 8, lo + m, 8):
        r0 += a[i]
        r1 += a[i + 1]
        r2 += a[i + 2]
        r3 += a[i + 3]
        r4 += a[i + 4]
        r5 += a[i + 5]
        r6 += a[i + 6]
        r7 += a[i + 7]
    res = ((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))
    for i in range(lo + m, lo + n):
        res += a[i]
    return res


def _pairwise_sum(a, lo, n):
    """Σ a[lo:lo + n] in NumPy's pairwise order (its ``pairwise_sum`` for float64): blocks of at most
    :data:`_BLOCK` terms (:func:`_block_sum`); a longer run split in two at half its length rounded
    down to a multiple of 8, the halves' sums added. The recursion is walked with an explicit stack
    (an ahead-of-time module cannot hold a recursive function)."""
    if n <= _BLOCK:
        return _block_sum(a, lo, n)
    start = np.empty(64, np.int64)
    size = np.empty(64, np.int64)
    stage = np.zeros(64, np.int64)  # 0: split next; 1: left half pending; 2: right half pending
    left = np.zeros(64)
    right = np.zeros(64)
    sp = 0
    start[0] = lo
    size[0] = n
    result = 0.0
    while sp >= 0:
        m = size[sp]
        if m <= _BLOCK or stage[sp] == 2:
            v = _block_sum(a, start[sp], m) if m <= _BLOCK else left[sp] + right[sp]
            sp -= 1
            if sp < 0:
                result = v
            elif stage[sp] == 1:
                left[sp] = v
            else:
                right[sp] = v
        else:
            h = m // 2
            h -= h % 8
            stage[sp] += 1
            lo_child = start[sp] if stage[sp] == 1 else start[sp] + h
            sp += 1
            start[sp] = lo_child
            size[sp] = h if stage[sp - 1] == 1 else m - h
            stage[sp] = 0
    return result


def _np_sum(a):
    """``float(np.sum(a))`` of a contiguous 1-D float64 array, in NumPy's order (its pairwise sum over
    the whole array; ``tests/unit/test_record_kernel.py`` checks it against ``np.sum``)."""
    return _pairwise_sum(a, 0, a.size)


def record_step(t, P, p_hydro, sigma_v0, n, n0, lengths, gamma, ps, elem, sig0_elem, ru_liq, V_top, W_top,
                peak, t_peak, first, ever, liq, peak_strain, max_contribution, ru, contribution, ru_elem,
                sig_elem, scalars):
    """One step's record (module docstring), in place. Inputs: the time ``t`` [s], the pressure
    ``P`` [Pa], ``p_hydro`` [Pa], ``sigma_v0`` [Pa], the porosity ``n`` and its initial ``n0``, the
    element ``lengths`` [m] (all per saturated element), the shear strain ``gamma`` of every element
    of the shear column, σ′_v ``ps`` [Pa] per element, the report elements ``elem`` and their
    σ′_v0 ``sig0_elem``, the threshold ``ru_liq``, the top node's V, W [m/s]. Kept across steps:
    ``peak``, ``t_peak``, ``first`` (NaN until liquefied), ``ever``, ``peak_strain``,
    ``max_contribution``. Written: ``liq`` (r_u > ru_liq), ``ru``, ``contribution``, ``ru_elem``,
    ``sig_elem`` (σ′_v/σ′_v0 at ``elem``) and ``scalars`` = (settlement [m], base excess pressure
    [Pa], top r_u, seepage at the water table [m/s]) and, where it has a fifth entry, the lowest element
    with ``liq`` (−1: none; ``int(liq.argmax())`` where there is one)."""
    ne = ru.size
    low = -1
    for e in range(ne):
        r = (P[e] - p_hydro[e]) / sigma_v0[e]
        ru[e] = r
        if r > peak[e]:
            peak[e] = r
            t_peak[e] = t
        lq = r > ru_liq
        liq[e] = lq
        if lq:
            if low < 0:
                low = e
            ever[e] = True
            if first[e] != first[e]:
                first[e] = t
        c = lengths[e] * (n0[e] - n[e]) / (1.0 - n[e])
        contribution[e] = c
        m = max_contribution[e]
        if c > m or c != c:  # np.maximum: a NaN is kept
            max_contribution[e] = c
    for e in range(gamma.size):
        g = abs(gamma[e])
        if g > peak_strain[e] or g != g:
            peak_strain[e] = g
    for k in range(elem.size):
        ru_elem[k] = ru[elem[k]]
        sig_elem[k] = ps[elem[k]] / sig0_elem[k]
    nt = n[ne - 1]
    scalars[0] = _np_sum(contribution)
    scalars[1] = P[0] - p_hydro[0]
    scalars[2] = ru[ne - 1]
    scalars[3] = 0.5 * (V_top + W_top) - nt * 0.5 * (V_top - W_top) / (1.0 - nt)
    if scalars.size > 4:
        scalars[4] = low
    return scalars


_SIGNATURE = ("f8[::1](f8, f8[::1], f8[::1], f8[::1], f8[::1], f8[::1], f8[::1], f8[::1], f8[::1], i8[::1], "
              "f8[::1], f8, f8, f8, f8[::1], f8[::1], f8[::1], b1[::1], b1[::1], f8[::1], f8[::1], f8[::1], "
              "f8[::1], f8[::1], f8[::1], f8[::1])")


def compiled():
    """:func:`record_step` compiled (:mod:`twofluid.compiled`; the plain function where the JIT is
    disabled), or None where it cannot be (no numba and nothing built).

    >>> f = compiled()
    >>> f is None or callable(f)
    True
    """
    from ..compiled import group

    try:
        out = group("column_record", {"record_step": (record_step, _SIGNATURE)}, helpers=(_block_sum, _pairwise_sum, _np_sum))
    except ImportError:
        return None
    return None if out is None else out["record_step"]
