"""What the tests of the compiled and NumPy paths of the 1D models share (test_reduced_kernel,
test_full_kernel): a bundled case built with another model or element, and a model advanced on
one of its paths."""
from twofluid.casefile.builder import build
from twofluid.casefile.loader import load_case
from twofluid.timestepping.backward_euler import integrate


def model_of(name: str, model: str, element: str | None = None):
    """The bundled case ``name`` built with ``[case] model`` and, if given, ``[mesh] element``."""
    case = load_case(name)
    case["case"]["model"] = model
    if element:
        case["mesh"]["element"] = element
    return build(case)


def advance(b, t_end: float, compiled):
    """The state of the built case ``b`` after ``t_end`` [s] with ``b.model.compiled`` set to ``compiled``."""
    b.model.compiled = compiled
    s = b.state
    for step in integrate(b.model, s, t_end, b.dt, settings=b.settings):
        s = step.state
    return s
