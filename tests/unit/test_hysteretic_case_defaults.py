"""What a liquefaction case with the hysteretic model gets when a key is left out or does not apply:
the viscous floor's default, a warning for gamma_ref (which the GQ/H backbone ignores) and for a
damping ratio above the floor, and the simplified procedure's statement of the blow count its
table takes."""
import tomllib
import warnings

import numpy as np
import pytest
import tomli_w

from twofluid.casefile.loader import case_text, load_case
from twofluid.casefile.schema import CaseWarning
from twofluid.runners.liquefaction_report import simplified_method


def _load(tmp_path, edit):
    case = tomllib.loads(case_text("liquefaction-layered-site"))
    edit(case)
    path = tmp_path / "c.toml"
    path.write_text(tomli_w.dumps(case))
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        resolved = load_case(str(path))
    return resolved, [str(x.message) for x in w if issubclass(x.category, CaseWarning)]


def test_the_hysteretic_model_defaults_to_a_one_per_cent_viscous_floor(tmp_path):
    resolved, lines = _load(tmp_path, lambda c: c["shear_wave"].pop("damping_ratio"))
    assert resolved["shear_wave"]["damping_ratio"] == 0.01
    assert not any("[shear_wave] damping_ratio" in x for x in lines)


def test_the_thesis_model_keeps_its_default(tmp_path):
    case = tomllib.loads(case_text("liquefaction-elcentro"))
    case["shear_wave"].pop("damping_ratio")
    path = tmp_path / "c.toml"
    path.write_text(tomli_w.dumps(case))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert load_case(str(path))["shear_wave"]["damping_ratio"] == 0.05


@pytest.mark.parametrize("ratio, warns", [(0.02, False), (0.05, True)])
def test_a_damping_ratio_above_the_floor_warns_in_one_line(tmp_path, ratio, warns):
    resolved, lines = _load(tmp_path, lambda c: c["shear_wave"].update(damping_ratio=ratio))
    assert resolved["shear_wave"]["damping_ratio"] == ratio
    hits = [x for x in lines if "[shear_wave] damping_ratio" in x]
    assert len(hits) == int(warns)
    if warns:
        assert "\n" not in hits[0] and "0.05" in hits[0] and "[shear_wave]" in hits[0]


def test_gamma_ref_on_a_layer_warns_that_the_hysteretic_model_ignores_it(tmp_path):
    _, lines = _load(tmp_path, lambda c: c["layers"][1].update(gamma_ref=5e-4))
    hits = [x for x in lines if "gamma_ref:" in x]
    assert len(hits) == 1 and "\n" not in hits[0] and "[layers 2 'loose sand'] gamma_ref: ignored" in hits[0]
    _, lines = _load(tmp_path, lambda c: None)
    assert not any("gamma_ref:" in x for x in lines)


def test_the_simplified_method_names_the_blow_count_it_takes():
    dr = {"n160cs": 0.0, "qc1ncs": 0.0, "csr_n_slope": 0.0}
    assert "46 Dr^2" in simplified_method({"layers": [dr]})
    text = simplified_method({"layers": [{**dr, "n160cs": 10.0}]})
    assert "46 Dr^2" not in text and "n160cs" in text
    text = simplified_method({"layers": [{**dr, "n160cs": 10.0}, dr]})
    assert "n160cs, else (N1)60cs = 46 Dr^2" in text
    assert "qc1ncs" in simplified_method({"layers": [{**dr, "qc1ncs": 90.0}]})
    assert "csr_n_slope" in simplified_method({"layers": [{**dr, "csr_n_slope": 0.3}]})


def test_a_layer_s_n160cs_enters_the_run_s_simplified_table():
    """The run's table takes the layer's n160cs (docs/liquefaction.md says so), not 46 Dr²."""
    from twofluid.runners.liquefaction import build_column
    from twofluid.runners.liquefaction_report import simplified_rows

    case = load_case("liquefaction-layered-site")
    case["layers"][1]["n160cs"] = 7.0
    b = build_column(case)
    rows = simplified_rows(b.column, b.site, case, 0.2)
    loose = np.asarray(b.site.layer_of) == 1
    assert np.all(rows.N1_60cs[:b.column.n_sat][loose] == 7.0)
