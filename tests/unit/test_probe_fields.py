"""The probes' fields at their elements only are the element fields there (the same operations)."""
import numpy as np

from twofluid.casefile.builder import build
from twofluid.casefile.loader import load_case


def test_element_fields_at_some_elements_are_those_of_all_elements():
    b = build(load_case("fluidized-bed-step"))
    m, s = b.model, b.state
    rng = np.random.default_rng(3)
    s = s.copy(V=s.V + 1e-3 * rng.standard_normal(s.V.shape), W=s.W + 1e-3 * rng.standard_normal(s.W.shape),
               n=np.clip(s.n + 0.05 * rng.standard_normal(s.n.shape), 0.4, 1.0))  # clear liquid too (NaN U_s)
    at = np.array([0, 7, s.n.size - 1, 7])
    full, some = m.element_fields(s), m.element_fields(s, at)
    assert full.keys() == some.keys()
    for name, values in full.items():
        want = np.broadcast_to(values, s.n.shape)[at]
        np.testing.assert_allclose(some[name], want, rtol=4 * np.finfo(float).eps, atol=0, equal_nan=True,
                                   err_msg=name)
