"""Solve the block system of a line (1D) model as a band matrix with LAPACK's ``dgbsv``.

On a line every unknown couples only to unknowns of its own and the neighbouring
elements, so once the unknowns are numbered along the line (velocity nodes, then
the pressure and porosity of the element above them, …) the matrix is a band of
a few diagonals either side of the main one. The band LU with partial pivoting
costs O(N kl (kl + ku)) and needs no sparse-matrix construction, no slicing of
the prescribed rows and columns and no symbolic factorisation; the element
triplets are summed straight into LAPACK's band storage (``np.bincount``).

Prescribed values become identity rows (scaled to the matrix's diagonal): their
columns stay in the other rows, which is the same elimination as moving them to
the right-hand side. The system is solved for the increment from the iterate it
was assembled about (right-hand side = minus the residual), so the round-off of
the solve is relative to the increment, not to the unknowns: on a slowly settling
column (velocities ~1e-6 m/s beside pressures ~1e3 Pa, condition number ~1e11)
solving for the unknowns themselves left a change of ~2e-7 of the velocity scale
between iterates, above the Picard tolerance, while the increment form gives ~1e-12.

:func:`band_lu` is LAPACK's band LU (dgbtf2/dgbtrs) as a kernel (:mod:`twofluid.compiled`): the
same operations without f2py's and the per-column BLAS calls' overhead (``BandSolver.solve``
takes it with ``compiled=True``; the models choose, see ``TwoFluid1D.compiled``).
"""
from __future__ import annotations

import numpy as np
from ..scipy_kernels import dgbsv  # scipy.linalg.lapack's, without importing scipy.linalg

__all__ = ["BandSolver", "band_lu", "band_lu_22", "block_solve_22"]


def _u(i):
    """An array index as an unsigned integer: numba then leaves out the test for a negative index
    (counted from the end) that it adds to every access with a signed one, which took 40 % of the
    band LU's instructions (the LU's indices are never negative). The same index in NumPy."""
    return np.uint64(i)


def _gbsv(ab, b, kl, ku):
    """LAPACK ``dgbsv`` in place: band LU with partial pivoting of ``ab`` (2 kl + ku + 1, n; A[i, j]
    at ab[kl + ku + i − j, j], the first kl rows for the fill-in) and the solve of ``b``; returns
    LAPACK's ``info`` (0, or j + 1 for a zero pivot in column j).

    The order of operations of LAPACK's unblocked dgbtf2 and dgbtrs (pivot = first largest
    entry, the column scaled by the reciprocal pivot, rank-one updates, column back substitution),
    so the results agree with ``dgbsv``'s to round-off (an optimised BLAS may fuse multiply-adds).
    The f2py call of ``dgbsv`` costs ~20 µs on 401 unknowns, mostly its per-column BLAS calls.
    Every index is passed through :func:`_u`: 18 % less time than plain indexing.
    """
    n = b.size
    kv = kl + ku
    ipiv = np.empty(n, dtype=np.int64)
    for j in range(n):  # the fill-in rows start at zero
        for i in range(kl):
            ab[_u(i), _u(j)] = 0.0
    ju = 0
    for j in range(n):
        km = min(kl, n - 1 - j)
        p = 0
        amax = abs(ab[_u(kv), _u(j)])
        for i in range(1, km + 1):
            a = abs(ab[_u(kv + i), _u(j)])
            if a > amax:
                amax = a
                p = i
        ipiv[_u(j)] = j + p
        piv = ab[_u(kv + p), _u(j)]
        if piv == 0.0 or piv != piv:
            return j + 1
        ju = max(ju, min(j + ku + p, n - 1))
        if p != 0:  # swap rows j and j + p in columns j..ju
            for c in range(j, ju + 1):
                t = ab[_u(kv + p + j - c), _u(c)]
                ab[_u(kv + p + j - c), _u(c)] = ab[_u(kv + j - c), _u(c)]
                ab[_u(kv + j - c), _u(c)] = t
        if km > 0:
            rp = 1.0 / piv
            for i in range(1, km + 1):
                ab[_u(kv + i), _u(j)] *= rp
            for c in range(j + 1, ju + 1):
                t = ab[_u(kv + j - c), _u(c)]
                if t != 0.0:
                    for i in range(1, km + 1):
                        ab[_u(kv + j + i - c), _u(c)] -= ab[_u(kv + i), _u(j)] * t
    for j in range(n - 1):  # L y = P b
        lm = min(kl, n - 1 - j)
        q = ipiv[_u(j)]
        if q != j:
            t = b[_u(q)]
            b[_u(q)] = b[_u(j)]
            b[_u(j)] = t
        t = b[_u(j)]
        if t != 0.0:
            for i in range(1, lm + 1):
                b[_u(j + i)] -= ab[_u(kv + i), _u(j)] * t
    for j in range(n - 1, -1, -1):  # U x = y (U has kl + ku superdiagonals)
        if b[_u(j)] != 0.0:
            b[_u(j)] /= ab[_u(kv), _u(j)]
            t = b[_u(j)]
            for i in range(max(0, j - kv), j):
                b[_u(i)] -= t * ab[_u(kv + i - j), _u(j)]
    return 0


def _gbsv22(ab, b):
    """:func:`_gbsv` for kl = ku = 2 (the reduced 1D model's band), its inner loops written out: the
    same operations in the same order (the same results, bit for bit), a third less time.

    ``ab`` (7, n) Fortran order, A[i, j] at ab[4 + i − j, j]; returns LAPACK's ``info``."""
    n = b.size
    ipiv = np.empty(n, dtype=np.int64)
    for j in range(n):
        ab[_u(0), _u(j)] = 0.0
        ab[_u(1), _u(j)] = 0.0
    ju = 0
    for j in range(n):
        km = n - 1 - j
        if km > 2:
            km = 2
        p = 0
        amax = abs(ab[_u(4), _u(j)])
        if km >= 1:
            a = abs(ab[_u(5), _u(j)])
            if a > amax:
                amax = a
                p = 1
            if km >= 2:
                a = abs(ab[_u(6), _u(j)])
                if a > amax:
                    amax = a
                    p = 2
        ipiv[_u(j)] = j + p
        piv = ab[_u(4 + p), _u(j)]
        if piv == 0.0 or piv != piv:
            return j + 1
        t = j + 2 + p
        if t > n - 1:
            t = n - 1
        if t > ju:
            ju = t
        if p != 0:
            for c in range(j, ju + 1):
                r1 = 4 + p + j - c
                r0 = 4 + j - c
                x = ab[_u(r1), _u(c)]
                ab[_u(r1), _u(c)] = ab[_u(r0), _u(c)]
                ab[_u(r0), _u(c)] = x
        if km > 0:
            rp = 1.0 / piv
            l1 = ab[_u(5), _u(j)] * rp
            ab[_u(5), _u(j)] = l1
            l2 = 0.0
            if km == 2:
                l2 = ab[_u(6), _u(j)] * rp
                ab[_u(6), _u(j)] = l2
            for c in range(j + 1, ju + 1):
                t = ab[_u(4 + j - c), _u(c)]
                if t != 0.0:
                    ab[_u(5 + j - c), _u(c)] -= l1 * t
                    if km == 2:
                        ab[_u(6 + j - c), _u(c)] -= l2 * t
    for j in range(n - 1):
        q = ipiv[_u(j)]
        if q != j:
            t = b[_u(q)]
            b[_u(q)] = b[_u(j)]
            b[_u(j)] = t
        t = b[_u(j)]
        if t != 0.0:
            b[_u(j + 1)] -= ab[_u(5), _u(j)] * t
            if j + 2 < n:
                b[_u(j + 2)] -= ab[_u(6), _u(j)] * t
    for j in range(n - 1, -1, -1):
        if b[_u(j)] != 0.0:
            b[_u(j)] /= ab[_u(4), _u(j)]
            t = b[_u(j)]
            i0 = j - 4
            if i0 < 0:
                i0 = 0
            for i in range(i0, j):
                b[_u(i)] -= t * ab[_u(4 + i - j), _u(j)]
    return 0


def _gbsv55(ab, b):
    """:func:`_gbsv` for kl = ku = 5 (the full 1D model's band, ``models/full_kernel``), its inner loops
    written out: the same operations on each entry in the same order (the same results, bit for bit),
    the five multipliers of a column held while its rank-one update sweeps the columns to its right.

    ``ab`` (16, n) in Fortran order (A[i, j] at ab[10 + i − j, j]: read as one flat array, column j
    at 16 j); returns LAPACK's ``info``."""
    n = b.size
    a = ab.T.reshape(ab.size)  # (a view: the columns one after another)
    ipiv = np.empty(n, dtype=np.int64)
    for j in range(n):  # the fill-in rows start at zero
        o = 16 * j
        a[_u(o)] = 0.0
        a[_u(o + 1)] = 0.0
        a[_u(o + 2)] = 0.0
        a[_u(o + 3)] = 0.0
        a[_u(o + 4)] = 0.0
    ju = 0
    for j in range(n):
        d = 16 * j + 10  # the diagonal of column j
        km = n - 1 - j
        if km > 5:
            km = 5
        p = 0
        amax = abs(a[_u(d)])
        for i in range(1, km + 1):
            x = abs(a[_u(d + i)])
            if x > amax:
                amax = x
                p = i
        ipiv[_u(j)] = j + p
        piv = a[_u(d + p)]
        if piv == 0.0 or piv != piv:
            return j + 1
        t = j + 5 + p
        if t > n - 1:
            t = n - 1
        if t > ju:
            ju = t
        if km == 5:
            # rows j and j + p swapped in column j, its multipliers, then each column c of j + 1..ju
            # swapped and updated in turn (entry (r, c) at 15 c + 10 + r): each entry's operations
            # those of the swap of all the columns first and the updates after, in the same order
            if p != 0:
                a[_u(d + p)] = a[_u(d)]
                a[_u(d)] = piv
            rp = 1.0 / piv
            l1 = a[_u(d + 1)] * rp
            l2 = a[_u(d + 2)] * rp
            l3 = a[_u(d + 3)] * rp
            l4 = a[_u(d + 4)] * rp
            l5 = a[_u(d + 5)] * rp
            a[_u(d + 1)] = l1
            a[_u(d + 2)] = l2
            a[_u(d + 3)] = l3
            a[_u(d + 4)] = l4
            a[_u(d + 5)] = l5
            for c in range(j + 1, ju + 1):
                r0 = 15 * c + 10 + j  # row j of column c
                t = a[_u(r0)]
                if p != 0:
                    x = a[_u(r0 + p)]
                    a[_u(r0 + p)] = t
                    a[_u(r0)] = x
                    t = x
                if t != 0.0:
                    a[_u(r0 + 1)] -= l1 * t
                    a[_u(r0 + 2)] -= l2 * t
                    a[_u(r0 + 3)] -= l3 * t
                    a[_u(r0 + 4)] -= l4 * t
                    a[_u(r0 + 5)] -= l5 * t
            continue
        if p != 0:  # swap rows j and j + p in columns j..ju
            for c in range(j, ju + 1):
                r0 = 15 * c + 10 + j
                x = a[_u(r0 + p)]
                a[_u(r0 + p)] = a[_u(r0)]
                a[_u(r0)] = x
        if km > 0:
            rp = 1.0 / piv
            for i in range(1, km + 1):
                a[_u(d + i)] *= rp
            for c in range(j + 1, ju + 1):
                r0 = 15 * c + 10 + j
                t = a[_u(r0)]
                if t != 0.0:
                    for i in range(1, km + 1):
                        a[_u(r0 + i)] -= a[_u(d + i)] * t
    for j in range(n - 1):  # L y = P b
        q = ipiv[_u(j)]
        if q != j:
            t = b[_u(q)]
            b[_u(q)] = b[_u(j)]
            b[_u(j)] = t
        t = b[_u(j)]
        if t != 0.0:
            d = 16 * j + 10
            if j + 5 < n:
                b[_u(j + 1)] -= a[_u(d + 1)] * t
                b[_u(j + 2)] -= a[_u(d + 2)] * t
                b[_u(j + 3)] -= a[_u(d + 3)] * t
                b[_u(j + 4)] -= a[_u(d + 4)] * t
                b[_u(j + 5)] -= a[_u(d + 5)] * t
            else:
                for i in range(1, n - j):
                    b[_u(j + i)] -= a[_u(d + i)] * t
    for j in range(n - 1, -1, -1):  # U x = y (U has kl + ku superdiagonals)
        if b[_u(j)] != 0.0:
            o = 16 * j + 10 - j  # entry (i, j) at o + i
            b[_u(j)] /= a[_u(o + j)]
            t = b[_u(j)]
            i0 = j - 10
            if i0 < 0:
                i0 = 0
            for i in range(i0, j):
                b[_u(i)] -= t * a[_u(o + i)]
    return 0


_LU = _LU22 = _BT22 = None
_TRIED = False


_BT_TOL = 1e-12  # largest row-wise backward error of :func:`_bt22`'s solution before it falls back


def _bt22(ab, b):
    """:func:`_gbsv22`'s system (kl = ku = 2, ``ab`` (7, n) in LAPACK's band storage, n odd) solved
    as block tridiagonal: the unknowns in pairs (2v, 2v + 1), the last one alone, by block LU
    without interchanges between blocks, each 2 × 2 pivot block inverted whole (Golub & Van Loan
    2013, sec. 4.5.3). About a quarter of the band LU's instructions; the result differs from it
    by round-off. Not backward stable for every matrix, so the solution is checked: where a
    pivot block is singular, or the row-wise backward error max_i |b − A x|_i / (|A||x| + |b|)_i
    (Oettli–Prager) exceeds ``_BT_TOL`` (≈ 4500 ε: far above the residual's own round-off of a
    few ε, far below what moves a Newton increment at the condition numbers of these systems,
    ~1e4), the system is solved by :func:`_gbsv22` (partial pivoting) instead, as it is for even n.
    ``b`` ← x; ``ab`` is overwritten only by that fallback. Returns 0, or LAPACK's ``info`` of the fallback."""
    n = b.size
    if n % 2 == 0:  # not pairs and a last one: the band LU's
        return _gbsv22(ab, b)
    m = n // 2
    G = np.empty((m, 4))  # S_v⁻¹ U_v of block v, row by row
    x = np.empty(n)  # z_v = S_v⁻¹ (b_v − L_v z_{v−1}), then the solution
    g00 = g01 = g10 = g11 = z0 = z1 = 0.0
    ok = True
    for v in range(m):
        i = 2 * v
        d00, d01, d10, d11 = ab[4, i], ab[3, i + 1], ab[5, i], ab[4, i + 1]  # A[i:i+2, i:i+2]
        r0, r1 = b[i], b[i + 1]
        if v > 0:  # L_v = [[A[i, i−2], A[i, i−1]], [0, A[i+1, i−1]]]
            l00, l01, l11 = ab[6, i - 2], ab[5, i - 1], ab[6, i - 1]
            d00 -= l00 * g00 + l01 * g10
            d01 -= l00 * g01 + l01 * g11
            d10 -= l11 * g10
            d11 -= l11 * g11
            r0 -= l00 * z0 + l01 * z1
            r1 -= l11 * z1
        det = d00 * d11 - d01 * d10
        if not (det != 0.0 and det - det == 0.0):
            ok = False
            break
        inv = 1.0 / det
        u00, u10 = ab[2, i + 2], ab[3, i + 2]  # U_v = [[A[i, i+2], 0], [A[i+1, i+2], A[i+1, i+3]]]
        u11 = ab[2, i + 3] if i + 3 < n else 0.0
        g00 = inv * (d11 * u00 - d01 * u10)
        g01 = -inv * (d01 * u11)
        g10 = inv * (d00 * u10 - d10 * u00)
        g11 = inv * (d00 * u11)
        z0 = inv * (d11 * r0 - d01 * r1)
        z1 = inv * (d00 * r1 - d10 * r0)
        G[v, 0], G[v, 1], G[v, 2], G[v, 3] = g00, g01, g10, g11
        x[i], x[i + 1] = z0, z1
    if ok:
        k = n - 1  # the last unknown: its 1 × 1 block
        s = ab[4, k]
        r = b[k]
        if m > 0:
            s -= ab[6, k - 2] * g00 + ab[5, k - 1] * g10
            r -= ab[6, k - 2] * z0 + ab[5, k - 1] * z1
        if not (s != 0.0 and s - s == 0.0):
            ok = False
        else:
            x[k] = r / s
            for v in range(m - 1, -1, -1):  # x_v = z_v − G_v x_{v+1}
                i = 2 * v
                x2 = x[i + 2]
                x3 = x[i + 3] if i + 3 < n else 0.0
                x[i] -= G[v, 0] * x2 + G[v, 1] * x3
                x[i + 1] -= G[v, 2] * x2 + G[v, 3] * x3
            worst = 0.0  # the row-wise backward error, max |r_i| − tol (|A||x| + |b|)_i
            for i in range(n):
                if 2 <= i < n - 2:  # (the five entries written out)
                    a0, a1, a2 = ab[6, i - 2] * x[i - 2], ab[5, i - 1] * x[i - 1], ab[4, i] * x[i]
                    a3, a4 = ab[3, i + 1] * x[i + 1], ab[2, i + 2] * x[i + 2]
                    r = b[i] - a0 - a1 - a2 - a3 - a4
                    den = abs(b[i]) + abs(a0) + abs(a1) + abs(a2) + abs(a3) + abs(a4)
                else:
                    r = b[i]
                    den = abs(b[i])
                    for j in range(max(i - 2, 0), min(i + 2, n - 1) + 1):
                        a = ab[4 + i - j, j] * x[j]
                        r -= a
                        den += abs(a)
                e = abs(r) - _BT_TOL * den
                if not e <= worst:  # (NaN too)
                    worst = e
            ok = worst <= 0.0
    if not ok:
        return _gbsv22(ab, b)
    for i in range(n):
        b[i] = x[i]
    return 0


def band_lu():
    """:func:`_gbsv` compiled (``lu(ab, b, kl, ku) -> info``, in place; :mod:`twofluid.compiled`).

    >>> lu = band_lu()
    >>> ab = np.array([[0.0, 0.0, 0.0], [0.0, 1.0, 1.0], [2.0, 2.0, 2.0], [1.0, 1.0, 0.0]], order="F")
    >>> b = np.array([3.0, 4.0, 3.0])  # [[2, 1, 0], [1, 2, 1], [0, 1, 2]] x = b, kl = ku = 1
    >>> lu is None or (lu(ab, b, 1, 1) == 0 and b.round(12).tolist() == [1.0, 1.0, 1.0])
    True
    """
    global _LU, _TRIED
    if not _TRIED:
        _TRIED = True
        from ..compiled import group

        lu = group("band_lu", {"band_lu": (_gbsv, "i8(f8[::1,:], f8[::1], i8, i8)")}, helpers=(_u,))
        _LU = None if lu is None else lu["band_lu"]
    return _LU


def _gbsv22_entry(ab, b):
    """:func:`_gbsv22` as exported: a call of the helper, compiled once per process for these argument
    types whether the export or the reduced model's whole iterate asks for it first."""
    return _gbsv22(ab, b)


def _bt22_entry(ab, b):
    """:func:`_bt22` as exported (as :func:`_gbsv22_entry`)."""
    return _bt22(ab, b)


def _band_22():
    """The reduced model's band solvers (kl = ku = 2), a group of their own (the full model's band LU
    needs neither): (:func:`_gbsv22`, :func:`_bt22`) compiled, or (None, None)."""
    global _LU22, _BT22
    if _LU22 is None:
        from ..compiled import group

        lu = group("band_22", {"band_lu_22": (_gbsv22_entry, "i8(f8[::1,:], f8[::1])"),
                               "block_solve_22": (_bt22_entry, "i8(f8[::1,:], f8[::1])")},
                   helpers=(_u, _gbsv22, _bt22))
        _LU22, _BT22 = (False, False) if lu is None else (lu["band_lu_22"], lu["block_solve_22"])
    return _LU22 or None, _BT22 or None


def band_lu_22():
    """:func:`_gbsv22` compiled (``lu(ab, b) -> info``, ``ab`` (7, n) in Fortran order, in place), or None."""
    return _band_22()[0]


def block_solve_22():
    """:func:`_bt22` compiled (``solve(ab, b) -> info``, ``ab`` (7, n) in Fortran order, n odd), or None."""
    return _band_22()[1]


class BandSolver:
    """Band LU solves of :class:`~twofluid.fem.assembly.BlockSystem` systems of one size.

    Parameters
    ----------
    position : (N,) array
        A coordinate along the line of every global unknown (e.g. in element
        lengths); the band numbering sorts by it, ties kept in global order.

    >>> from twofluid.fem.assembly import BlockSystem
    >>> S = BlockSystem({"u": 3})
    >>> S.add("u", "u", np.array([[0, 1], [1, 2]]), np.array([[0, 1], [1, 2]]),
    ...       np.array([[[2.0, -1.0], [-1.0, 2.0]]] * 2))
    >>> S.add_rhs("u", np.array([1]), np.array([1.0]))
    >>> x = BandSolver(np.arange(3.0)).solve(S, np.zeros(3), np.array([0, 2]), np.zeros(2))
    >>> x.round(12).tolist()  # u_0 = u_2 = 0, 4 u_1 = 1
    [0.0, 0.25, 0.0]
    """

    def __init__(self, position: np.ndarray):
        self.perm = np.argsort(np.asarray(position, dtype=float), kind="stable")  # band row -> global
        self.size = self.perm.size
        self.pos = np.empty(self.size, dtype=np.intp)
        self.pos[self.perm] = np.arange(self.size)  # global -> band row
        self._fixed_of = None
        self._entries_of = (None, None)
        self._index_of = None

    def _row_mask(self, idx: np.ndarray) -> np.ndarray:
        """1.0 on free rows, 0.0 on prescribed ones (cached for the last index set)."""
        cached = self._fixed_of
        if cached is None or not np.array_equal(cached[0], idx):
            keep = np.ones(self.size)
            keep[idx] = 0.0
            self._fixed_of = cached = (idx.copy(), keep)
        return cached[1]

    def _band_index(self, rows: np.ndarray, cols: np.ndarray) -> tuple[int, int, np.ndarray]:
        """(kl, ku, flat band-storage index of every triplet), kept while the triplets' positions repeat."""
        last = self._index_of
        if last is not None and np.array_equal(last[0], rows) and np.array_equal(last[1], cols):
            return last[2]
        pr, pc = self.pos[rows], self.pos[cols]
        dist = pr - pc
        kl, ku = max(int(dist.max()), 0), max(int(-dist.min()), 0)
        out = (kl, ku, pc * (2 * kl + ku + 1) + (kl + ku + dist))
        self._index_of = (rows, cols, out)
        return out

    def _row_entries(self, pi: np.ndarray, kl: int, ku: int, ldab: int) -> np.ndarray:
        """Flat band-storage indices of all entries of band rows ``pi`` (cached for the last rows and band)."""
        key, flat = self._entries_of
        if key is None or key[1:] != (kl, ku) or not np.array_equal(key[0], pi):
            d = np.arange(-ku, kl + 1)  # i − j
            j = pi[:, None] - d[None, :]
            ok = (j >= 0) & (j < self.size)
            flat = (j * ldab + (kl + ku) + d[None, :])[ok]
            self._entries_of = ((pi.copy(), kl, ku), flat)
        return flat

    def solve(self, S, a_k: np.ndarray, idx: np.ndarray, val: np.ndarray, compiled: bool = True) -> np.ndarray:
        """The solution a of S with a[idx] = val, from the increment about ``a_k``.

        NaN everywhere if the matrix has non-finite entries or is singular (the
        stepper then rejects the iterate and shrinks the step). ``compiled``: the band LU
        by :func:`band_lu` where numba is installed (LAPACK's algorithm; ``dgbsv``'s
        per-column BLAS calls cost ~0.3 ms on the full model's 800 unknowns), else ``dgbsv``.
        """
        rows, cols, vals = S.triplets()
        N = self.size
        keep = self._row_mask(idx)
        # minus the residual at a_k of the free rows; prescribed rows: the increment to val
        res = keep * (S.rhs - np.bincount(rows, vals * a_k[cols], minlength=N))
        kl, ku, flat = self._band_index(rows, cols)
        ldab = 2 * kl + ku + 1
        diag = kl + ku
        ab = np.bincount(flat, vals, minlength=ldab * N)
        pi = self.pos[idx]
        dflat = pi * ldab + diag
        scale = np.abs(ab[dflat]) + 1.0  # keep the identity rows on the matrix's scale
        ab[self._row_entries(pi, kl, ku, ldab)] = 0.0
        ab[dflat] = scale
        b = res[self.perm]
        b[pi] = scale * (val - a_k[idx])
        ab = ab.reshape(N, ldab).T  # LAPACK band storage (Fortran order): A[i, j] at ab[diag + i - j, j]
        if not (np.isfinite(ab).all() and np.isfinite(b).all()):
            return np.full(N, np.nan)
        lu = band_lu() if compiled else None
        if lu is not None:
            info, x = lu(ab, b, kl, ku), b
        else:
            _, _, x, info = dgbsv(kl, ku, ab, b, overwrite_ab=1, overwrite_b=1)
        if info != 0:
            return np.full(N, np.nan)
        out = a_k.copy()
        out[self.perm] += x
        out[idx] = val
        return out
