"""`twofluid verify` prints one table and writes the report."""
from twofluid.cli import main


def test_verify_subset_writes_report(tmp_path, capsys):
    out = tmp_path / "verification.md"
    code = main(["verify", "--quick", "--no-slis", "--only", "terzaghi", "hydrostatic", "--out", str(out)])
    text = capsys.readouterr().out
    assert code == 0
    assert text.startswith("| check | quantity | unit | reference | computed | error | tolerance | pass |")
    assert "Terzaghi" in text and "hydrostatic" in text and "**NO**" not in text
    report = out.read_text()
    assert "## Definitions and tolerances" in report and "2D annulus" in report


def test_verify_overwrites_an_existing_report(tmp_path, capsys):
    """An existing report file is replaced (its folder is what is checked, not the file as a folder)."""
    out = tmp_path / "verification.md"
    out.write_text("old report\n")
    code = main(["verify", "--quick", "--no-slis", "--only", "hydrostatic", "--out", str(out)])
    capsys.readouterr()
    assert code == 0
    assert "## Definitions and tolerances" in out.read_text()
