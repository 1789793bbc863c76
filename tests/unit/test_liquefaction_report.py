"""The liquefaction report tables: a NaN is refused, never written; inf (cannot liquefy) is an empty cell."""
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
    assert path.read_text().splitlines() == ["depth_m,FS", "1,", "2,"]


def test_tables_of_numbers_are_written_as_the_general_writer_writes_them(tmp_path):
    import numpy as np

    from twofluid.runners.liquefaction_report import _write_numbers

    rng = np.random.default_rng(4)
    cols = [rng.standard_normal(50) * 10.0 ** rng.integers(-12, 12, 50) for _ in range(3)]
    cols[1][7] = math.inf
    _write_numbers(tmp_path / "a.csv", ["t", "a", "b"], cols)
    _write_csv(tmp_path / "b.csv", ["t", "a", "b"], [list(map(float, r)) for r in zip(*cols)])
    assert (tmp_path / "a.csv").read_bytes() == (tmp_path / "b.csv").read_bytes()
    cols[2][3] = math.nan
    with pytest.raises(NonFiniteOutput, match=r"spectra\.csv, column b, row 4"):
        _write_numbers(tmp_path / "spectra.csv", ["t", "a", "b"], cols)
