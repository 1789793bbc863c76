"""What the tests of the compiled and NumPy paths of the 1D models share (test_reduced_kernel,
test_full_kernel): a bundled case built with another model or element, and a model advanced on
one of its paths."""
from twofluid.casefile.builder import build
from twofluid.casefile.loader import load_case
from twofluid.timestepping.backward_euler import integrate


def model_of(name: str, model: str, element: str | None = None, drag: str | None = None):
    """The bundled case ``name`` built with ``[case] model`` and, if given, ``[mesh] element`` and
    ``[closures.drag] law`` (the other drag keys as the case has them)."""
    case = load_case(name)
    case["case"]["model"] = model
    if element:
        case["mesh"]["element"] = element
    if drag:
        case["closures"]["drag"]["law"] = drag
    return build(case)


def advance(b, t_end: float, compiled):
    """The state of the built case ``b`` after ``t_end`` [s] with ``b.model.compiled`` set to ``compiled``."""
    b.model.compiled = compiled
    s = b.state
    for step in integrate(b.model, s, t_end, b.dt, settings=b.settings):
        s = step.state
    return s


def band_to_dense(ab, kl: int, ku: int):
    """The matrix of LAPACK band storage with ``kl`` sub- and ``ku`` superdiagonals (entry (i, j)
    at ab[kl + ku + i − j, j]; the first kl rows are the LU's fill-in)."""
    import numpy as np

    N = ab.shape[1]
    A = np.zeros((N, N))
    for j in range(N):
        for i in range(max(0, j - ku), min(N, j + kl + 1)):
            A[i, j] = ab[kl + ku + i - j, j]
    return A


def assert_same_state(ref, fast, rel: float = 1e-8) -> None:
    """``fast`` is ``ref`` to ``rel``: V and W relative to the velocity scale (V is round-off where a
    wall stops it), n and P relative to their largest entries; at the same time."""
    import numpy as np
    import pytest

    assert fast.t == pytest.approx(ref.t, rel=1e-14)
    vscale = max(np.abs(ref.V).max(), np.abs(ref.W).max())
    for f in ("V", "W", "n", "P"):
        a, c = getattr(ref, f), getattr(fast, f)
        assert np.abs(a - c).max() <= rel * (vscale if f in "VW" else np.abs(a).max()), f
