"""`twofluid element-test`: argument parsing only; the numbers come from models.element_test."""
from __future__ import annotations

import json

import pytest

from twofluid.cli import main
from twofluid.models.element_test import cyclic_simple_shear


def test_element_test_prints_cycles_and_writes_plot(tmp_path, capsys):
    assert main(["element-test", "--gamma", "2e-3", "--max-cycles", "20", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    expected = cyclic_simple_shear(gamma_amplitude=2e-3, max_cycles=20).cycles_to_liquefaction[0]
    assert f"after {expected:.2f} cycles" in out
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["cycles_to_liquefaction"] == pytest.approx(expected)
    assert (tmp_path / "element_test.png").stat().st_size > 10_000


def test_element_test_default_is_the_calibration_point(capsys):
    assert main(["element-test", "--max-cycles", "40"]) == 0
    assert "CSR = 0.12, sigma'_v0 = 100 kPa: liquefied (r_u >= 0.95) after 15.94 cycles" in capsys.readouterr().out


def test_drained_element_test_reports_no_liquefaction(capsys):
    assert main(["element-test", "--gamma", "2e-3", "--drained", "--max-cycles", "5"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("drained") and "not liquefied in 5 cycles (final r_u = 0.000)" in out


def test_element_test_rejects_both_loadings():
    with pytest.raises(SystemExit):
        main(["element-test", "--csr", "0.1", "--gamma", "1e-3"])
