"""The liquefaction report tables: a NaN is refused, never written; inf keeps its meaning."""
import math

import pytest

from twofluid.io.results import NonFiniteOutput
from twofluid.runners.liquefaction_report import _write_csv


def test_a_nan_in_a_report_table_is_refused_naming_file_column_and_row(tmp_path):
    path = tmp_path / "layers.csv"
    with pytest.raises(NonFiniteOutput, match=r"layers\.csv, column peak_r_u, row 2"):
        _write_csv(path, ["layer", "peak_r_u"], [["crust", 0.1], ["loose", math.nan]])
    assert not path.exists()


def test_inf_and_none_are_written_as_documented(tmp_path):
    path = tmp_path / "elements.csv"
    _write_csv(path, ["depth_m", "FS"], [[1.0, math.inf], [2.0, None]])
    assert path.read_text().splitlines() == ["depth_m,FS", "1,inf", "2,"]
