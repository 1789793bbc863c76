"""The band LU written out for the full 1D model's half-widths (fem/banded.py ``_gbsv55``, kl = ku = 5).

It must perform the general band LU's (``_gbsv``, LAPACK's dgbtf2/dgbtrs order) operations on every
entry in the same order: the same factors, pivots, solution and ``info`` bit for bit, as plain Python
and compiled, on random matrices (row interchanges in most columns), matrices with zero entries in
the band (the updates a zero multiplier skips), a zero column and a NaN pivot, and on a system of
the full model itself.
"""
from __future__ import annotations

import numpy as np
import pytest

from twofluid.fem import banded

LDAB = 16  # 2 kl + ku + 1


def _systems(N: int, seed: int):
    rng = np.random.default_rng(seed)
    for trial in range(8):
        ab = np.asfortranarray(rng.standard_normal((LDAB, N)))  # (the fill-in rows: overwritten by both)
        if trial in (1, 2):
            ab[rng.random(ab.shape) < 0.4] = 0.0
        if trial == 3:
            ab[:, N // 2] = 0.0  # a zero column: info = N // 2 + 1 (or earlier)
        if trial == 4:
            ab[10, 0] = np.nan  # a NaN pivot
        yield ab, rng.standard_normal(N)


def _same(lu55, lu, N, seed):
    for ab, b in _systems(N, seed):
        a1, x1, a2, x2 = ab.copy(order="F"), b.copy(), ab.copy(order="F"), b.copy()
        with np.errstate(all="ignore"):
            info1, info2 = lu55(a1, x1), lu(a2, x2, 5, 5)
        assert info1 == info2
        if info1 == 0:
            assert np.array_equal(a1, a2) and np.array_equal(x1, x2)


@pytest.mark.parametrize("N", [1, 2, 5, 6, 7, 11, 12, 40])
def test_the_written_out_lu_is_the_general_one_in_plain_python(N):
    _same(banded._gbsv55, banded._gbsv, N, N)


@pytest.mark.parametrize("N", [1, 3, 6, 7, 12, 13, 402])
def test_the_written_out_lu_is_the_general_one_compiled(N):
    numba = pytest.importorskip("numba")
    from twofluid.compiled import _compiled_helpers

    with _compiled_helpers((banded._u,)):
        lu55, lu = numba.njit(banded._gbsv55), numba.njit(banded._gbsv)
        _same(lu55, lu, N, 100 + N)
