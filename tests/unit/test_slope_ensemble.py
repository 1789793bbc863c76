"""The bundled sloping example ensemble: the sloping site under the five input records, both
polarities (checked without running it: 10 members, each record with its M_w and t95)."""
from twofluid.ensemble.members import members
from twofluid.ensemble.spec import load_ensemble
from twofluid.io import ground_motion as gm


def test_the_sloping_five_motion_ensemble_expands_to_ten_members():
    spec = load_ensemble("sloping-site-five-motions")
    assert spec.base["case"]["name"] == "sloping-site"
    ms = members(spec)
    assert len(ms) == 10 and not [m.error for m in ms if m.error]
    assert len({m.hash for m in ms}) == 10
    seen = set()
    for m in ms:
        g = m.case["ground_motion"]
        assert g["pga_g"] == 0.25 and m.case["site"]["slope"] == 3.0
        assert m.case["shear_wave"]["base"] == "compliant" and m.case["shear_wave"]["flow_velocity"] > 0.0
        assert g["magnitude"] == gm.BUNDLED[g["file"]].magnitude
        seen.add((g["file"], g["polarity"]))
    inputs = [name for name, b in gm.BUNDLED.items() if b.input_motion]
    assert seen == {(name, p) for name in inputs for p in (1, -1)}
