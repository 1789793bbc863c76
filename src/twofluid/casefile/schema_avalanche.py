"""Case-file sections of model ``immersed_avalanche``: a saturated granular layer on a submerged incline.

The layer (:class:`twofluid.models.avalanche_1d.AvalancheLayer`, docs/avalanche.md) is
``[layer] thickness`` thick at each initial solid fraction of ``[layer] solid_fractions`` (one
run per value: an ensemble over φ0), inclined at ``slope_deg`` under still liquid on an
impermeable, no-slip base. ``[closures.granular_rheology]`` is the Boyer–Pailha friction with
dilatancy, ``[closures.permeability]`` Carman–Kozeny; ``[time]`` sets the end and the BDF
tolerances; ``[output]`` the profile times, the plots and the comparison with the data of
Pailha, Nicolas & Pouliquen (2008).
"""
from __future__ import annotations

from .schema import FLOATS, REQUIRED, SCHEMA, CaseError, K, register_model

__all__ = ["SECTIONS_AVALANCHE", "check_avalanche"]

_LAYER = [
    K("thickness", float, REQUIRED, "m", "layer thickness normal to the plane at the start (the same for "
      "every φ0)", lo=0.0, hi=1.0, lo_open=True),
    K("elements", int, 40, "-", "elements across the layer", lo=2, hi=2000),
    K("grading", float, 1.0, "-", "thickness of the top element over the base element's at the start "
      "(geometric progression; 1: uniform, above 1: refined at the base)", lo=1.0, hi=1000.0),
    K("slope_deg", float, REQUIRED, "deg", "inclination θ of the plane, applied in one step at t = 0",
      lo=0.0, hi=60.0, hi_open=True),
    K("solid_fractions", FLOATS, REQUIRED, "-", "initial solid fractions φ0, uniform in the layer; one run "
      "each", lo=0.3, hi=0.7),
    K("skeleton_modulus", float, 4e7, "Pa", "M of the skeleton law P_s = M (φ − φ̄): the tangent modulus of "
      "a Hertzian glass-bead packing at 10–40 Pa; it must keep the consolidation time η_f h²/(k M) far "
      "below the flow's times", lo=1e3, hi=1e12),
    K("top", str, "drained", "-", "surface: drained (p = 0, under still liquid) or closed (no flow through "
      "it: an undrained layer)", choices=("drained", "closed")),
]

_RHEOLOGY = [
    K("law", str, "boyer_pailha", "-", "granular rheology: μ(I_v) of Boyer, Guazzelli & Pouliquen (2011) "
      "plus tan ψ = K (φ − φ_eq(I_v)) of Pailha & Pouliquen (2009), local (boyer_pailha) or made nonlocal by "
      "the granular fluidity of Kamrin & Koval (2012) (boyer_pailha_nonlocal)",
      choices=("boyer_pailha", "boyer_pailha_nonlocal")),
    K("mu_s", float, 0.425, "-", "μ_s, friction at I_v → 0", lo=0.0, hi=2.0, lo_open=True),
    K("mu_2", float, 0.765, "-", "μ_2, friction at large I_v (> mu_s)", lo=0.0, hi=3.0, lo_open=True),
    K("i_0", float, 0.004, "-", "I_0 of μ(I_v)", lo=0.0, hi=1.0, lo_open=True),
    K("phi_c", float, 0.585, "-", "φ_c, critical solid fraction at I_v → 0", lo=0.3, hi=0.74),
    K("k_dil", float, 4.09, "-", "K, dilatancy constant", lo=0.0, hi=1000.0),
    K("amplitude", float, 0.48, "-", "A of the nonlocal law, cooperativity length ξ = A d/√abs(μ − μ_y) (Henann & "
      "Kamrin 2013, glass beads)", lo=0.0, hi=10.0, lo_open=True, used_when=("law", ("boyer_pailha_nonlocal",))),
]

_PERMEABILITY = [
    K("law", str, "carman_kozeny", "-", "k = d² (1 − φ)³/(C φ²)", choices=("carman_kozeny",)),
    K("constant", float, 180.0, "-", "C of Carman–Kozeny", lo=1.0, hi=1e4),
]

_TIME = [
    K("end", float, REQUIRED, "s", "end time of every run", lo=0.0, lo_open=True, hi=1e7),
    K("rtol", float, 1e-7, "-", "relative tolerance of the BDF steps", lo=1e-12, hi=1e-3),
    K("step", float, 2.0, "s", "largest BDF step (the steps adapt below it to rtol)", lo=0.0, lo_open=True),
]

_OUTPUT = [
    K("times", FLOATS, [], "s", "times at which the φ, u, p profiles are written (0 and the end always are)",
      lo=0.0),
    K("samples", int, 400, "-", "history samples per run (uniform to the end, 0.1 s apart in the first 10 s)",
      lo=10, hi=100000),
    K("compare", bool, False, "-", "compare with Pailha, Nicolas & Pouliquen (2008) (every φ0 must be one "
      "of theirs: 0.562, 0.568, 0.571, 0.578, 0.584, 0.588, 0.592)"),
    K("plots", bool, True, "-", "write PNG plots"),
]

SECTIONS_AVALANCHE = {"layer": _LAYER, "closures.granular_rheology": _RHEOLOGY,
                      "closures.permeability": _PERMEABILITY, "time": _TIME, "output": _OUTPUT}


def check_avalanche(case: dict, source: str) -> None:
    """Consistency across keys: μ_2 > μ_s; the data exist for every φ0 when comparing."""
    rh = case["closures"]["granular_rheology"]
    if rh["mu_2"] <= rh["mu_s"]:
        raise CaseError(source, "[closures.granular_rheology] mu_2", f"must exceed mu_s = {rh['mu_s']:g}")
    fr = case["layer"]["solid_fractions"]
    if not fr:
        raise CaseError(source, "[layer] solid_fractions", "give at least one solid fraction in [0.3, 0.7]")
    if case["output"]["compare"]:
        from ..verification.pailha2008 import PHI0

        bad = [f for f in fr if not any(abs(f - p) < 1e-9 for p in PHI0)]
        if bad:
            raise CaseError(source, "[layer] solid_fractions", f"{bad[0]:g} has no data to compare with; "
                            "with [output] compare = true use " + ", ".join(f"{p:g}" for p in PHI0))


register_model("immersed_avalanche", SECTIONS_AVALANCHE, check_avalanche,
               ignored={"materials": {"sphericity": "the permeability uses the bead diameter"}})
