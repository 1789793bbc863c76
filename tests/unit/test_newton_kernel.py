"""The compiled steps' Newton test (timestepping/newton_kernel.py), run plainly, makes the Python
NewtonTest's decisions and keeps its samples, over steps of one run with iterates that converge
quadratically, linearly, or flip the side of V − W."""
from types import SimpleNamespace as NS

import numpy as np
import pytest

from twofluid.timestepping import newton, newton_kernel as nk

FLOOR = 1e-3


class Model:
    newton_iterates = True

    def velocity_scale(self, s):
        return max(float(np.abs(s.V).max()), float(np.abs(s.W).max()), FLOOR)


def _change(new, prev):
    scale = Model().velocity_scale(new)
    dn = float(np.abs(new.n - prev.n).max())
    dv = max(float(np.abs(new.V - prev.V).max()), float(np.abs(new.W - prev.W).max())) / scale
    return dn, dv


@pytest.mark.parametrize("seed", range(4))
def test_the_kernel_helpers_make_newton_tests_decisions(seed, monkeypatch):
    monkeypatch.setattr(newton, "_kernels", lambda: None)  # the Python test's own branches
    rng = np.random.default_rng(seed)
    model, tol, ne = Model(), 1e-6, 4
    idx, c, meta = np.zeros(64, np.int64), np.zeros(64), np.zeros(2, np.int64)
    last, decisions, predicted = None, 0, 0
    old = NS(t=0.0, n=rng.uniform(0.4, 0.6, ne), V=rng.normal(0, 0.01, ne + 1), W=rng.normal(0, 0.01, ne + 1))
    for step in range(40):
        if step % 13 == 12:  # a new run now and then
            last = None
            newton._RUNS.pop(model, None)
        test = newton.NewtonTest(model, old, tol)
        has_last = last is not None
        lV, lW, ln, lt = (last.V, last.W, last.n, last.t) if has_last else (old.V, old.W, old.n, 0.0)
        steps, count, C, fresh, e_prev, step_C, have_C = nk.start(has_last, lt, old.t, lV, lW, ln, old.V, old.W,
                                                                  old.n, idx, c, meta)
        assert (count, fresh) == (len(test.run.samples), test.fresh)
        if count:
            assert C == test.C
        target = NS(n=old.n + rng.normal(0, 1e-3, ne), V=old.V + rng.normal(0, 1e-3, ne + 1),
                    W=old.W + rng.normal(0, 1e-3, ne + 1))
        rate = rng.choice([0.0, 0.3, 0.9])  # 0: quadratic, else a linear part
        gap, before, prev = 10.0 ** rng.uniform(-4, -1), None, NS(n=old.n, V=old.V, W=old.W)
        for it in range(1, 9):
            gap = gap * gap * rng.uniform(0.5, 50) + rate * gap
            flip = rng.random() < 0.05
            new = NS(t=old.t + 1.0, n=target.n + gap * rng.normal(size=ne),
                     V=target.V + gap * rng.normal(size=ne + 1) * (-30 if flip else 1),
                     W=target.W + gap * rng.normal(size=ne + 1))
            dn, dv = _change(new, prev)
            r, plain, e_prev, step_C, have_C = nk.quadratic(dn, dv, tol, True, e_prev, step_C, have_C, C, count)
            b = before if before is not None else prev
            done = r > 0 or (r < 0 and nk.predicted(new.V, new.W, new.n, prev.V, prev.W, prev.n, b.V, b.W, b.n,
                                                    FLOOR, tol, it, fresh))
            assert done == test.converged(it, new, prev, max(dn, dv))
            assert plain == (dn < tol and dv < tol)
            decisions += 1
            predicted += done and not plain
            before, prev = prev, new
            if done:
                break
        if not done:
            continue
        test.close(new)
        nk.close(step_C, have_C, steps, count, idx, c, meta)
        assert meta[1] == test.run.steps
        assert [(int(i), float(x)) for i, x in zip(idx[:meta[0]], c[:meta[0]])] == list(test.run.samples)
        last = old = NS(t=new.t, n=new.n.copy(), V=new.V.copy(), W=new.W.copy())
        test.run.last = old
    assert decisions > 40 and predicted > 0  # the prediction was taken, not only the plain test
