"""A layer's own CSR–N slope b (``csr_n_slope``) instead of the one the magnitude scaling factor
implies: the element follows the curve of that b, the simplified procedure takes the MSF_max that
b implies, and the column's elements carry it.

Compared quantities: the element test's cycles to liquefaction against N = 15 (CRR/CSR)^(1/b)
(±15 % in CSR, as for the derived b); the MSF of the simplified table at M = 5.25, where B&I
(2014)'s relation reaches MSF_max to 3e-4, against the MSF_max that B&I's b(MSF_max) curve gives
for that b.
"""
import math

import numpy as np
import pytest

from twofluid.casefile.loader import load_case
from twofluid.closures import hysteretic as law
from twofluid.geotech import correlations as co
from twofluid.geotech.profile import simplified_procedure
from twofluid.models.element_test_hysteretic import csr_n_curve, element_test


def test_the_element_follows_the_given_slope():
    assert element_test(csr=0.1, n160cs=10.0, max_cycles=1).b == pytest.approx(0.193, abs=0.001)  # derived
    assert element_test(csr=0.1, n160cs=10.0, max_cycles=1, csr_n_slope=0.34).b == 0.34
    for r in csr_n_curve(n160cs=10.0, csr_n_slope=0.34, n_targets=(3.0, 15.0, 50.0)):
        assert abs(r["csr_error"]) <= 0.15, r


def test_the_crr_at_15_cycles_is_kept():
    a = element_test(csr=0.1, n160cs=10.0, max_cycles=1)
    b = element_test(csr=0.1, n160cs=10.0, max_cycles=1, csr_n_slope=0.34)
    assert a.crr == b.crr


def test_the_simplified_procedure_takes_the_msf_max_the_slope_implies():
    z = np.array([2.0, 3.0])
    r = simplified_procedure(z, z + 1.0, [50e3, 70e3], [40e3, 50e3], 47.0, True, 0.2, 5.25,
                             n160cs=10.0, csr_n_slope=[0.333, 0.0])
    assert r.MSF[0] == pytest.approx(1.768, abs=1e-3)  # B&I's curve: (1.768, 0.333), (1.891, 0.353)
    assert r.MSF[1] == pytest.approx(float(co.msf_max_spt(10.0)), abs=1e-3)
    assert co.csr_slope_b(co.msf_max_from_slope(0.2)) == pytest.approx(0.2, rel=1e-12)


def test_bad_slope_in_the_api_is_one_line():
    with pytest.raises(ValueError, match=r"csr_n_slope = 0.9 is outside the valid range \[0.05, 0.6\]"):
        element_test(csr=0.1, n160cs=10.0, csr_n_slope=0.9)
    from twofluid.casefile.schema import CaseError
    with pytest.raises(CaseError, match="csr_n_slope"):
        simplified_procedure([2.0], [3.0], [50e3], [40e3], 47.0, True, 0.2, 7.0, csr_n_slope=0.01)


def test_element_test_command_refuses_a_slope_out_of_range(capsys):
    from twofluid.cli import main

    assert main(["element-test", "--model", "hysteretic", "--csr", "0.15", "--csr-n-slope", "0.9"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "--csr-n-slope" in err and "[0.05, 0.6]" in err


def test_the_column_carries_the_layer_slope_and_its_simplified_msf():
    from twofluid.runners.liquefaction import build_column
    from twofluid.runners.liquefaction_report import simplified_rows

    case = load_case("liquefaction-layered-site")
    case["layers"][1]["csr_n_slope"] = 0.34
    b = build_column(case)
    par, ns = b.column.hysteretic, b.column.n_sat
    loose = par[:ns, law.P_SIG0] < 90e3  # the loose sand (2-8 m) below the crust
    assert np.all(par[:ns][loose, law.P_B] == 0.34)
    assert np.all(par[:ns][~loose, law.P_B] > 0.34)  # the dense sand keeps its derived b
    rows = simplified_rows(b.column, b.site, case, 0.2)
    m = case["ground_motion"]["magnitude"]
    expect = 1.0 + (float(co.msf_max_from_slope(0.34)) - 1.0) * (8.64 * math.exp(-m / 4.0) - 1.325)
    liq = rows.can_liquefy & (rows.z_bottom_m <= 8.0)
    assert np.allclose(rows.MSF[liq], expect, rtol=1e-12)


def test_a_slope_on_the_crust_is_a_warning(tmp_path):
    """A crust generates no pore pressure: its csr_n_slope has no effect, and the case says so."""
    import tomllib

    import tomli_w

    from twofluid.casefile.loader import case_text
    from twofluid.casefile.schema import CaseWarning

    case = tomllib.loads(case_text("liquefaction-layered-site"))
    case["layers"][0]["csr_n_slope"] = 0.3
    path = tmp_path / "c.toml"
    path.write_text(tomli_w.dumps(case))
    with pytest.warns(CaseWarning, match=r"\[layers 1 'crust'\] csr_n_slope: ignored above the water table"):
        load_case(str(path))
