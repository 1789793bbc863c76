"""The simplified table's Dr [%] is the one the procedure used; where a layer's n160cs or qc1ncs sets it
instead of the relative_density entered, `twofluid simplified` says so beneath the table."""
import subprocess
import sys
from pathlib import Path

from twofluid.casefile.loader import case_text


def test_a_dr_from_n160cs_is_explained_beneath_the_table(tmp_path):
    text = case_text("liquefaction-layered-site").replace("relative_density = 47.0", "relative_density = 45.0\nn160cs = 12.0", 1)
    (tmp_path / "dr.toml").write_text(text, encoding="utf-8")
    exe = Path(sys.executable).with_name("twofluid")
    r = subprocess.run([str(exe), "simplified", str(tmp_path / "dr.toml")], capture_output=True, text=True, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    rows = [line.split() for line in r.stdout.splitlines() if line.strip().startswith("2.12")]
    assert rows and rows[0][4] == "51"  # 100 sqrt(12/46) = 51.1 %
    assert "Dr of layer 'loose sand': 51 % from n160cs = 12" in r.stdout and "45 % entered" in r.stdout
    plain = subprocess.run([str(exe), "simplified", "liquefaction-layered-site"], capture_output=True, text=True,
                           cwd=tmp_path)
    assert plain.returncode == 0 and "Dr of layer" not in plain.stdout
