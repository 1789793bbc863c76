"""The bundled sloping site as a case dict for the slope tests, without plots, with edits given
as ``section__key=value``."""
from twofluid.casefile.loader import case_text, load_case

CASE = "sloping-site"


def sloping_case(**edits):
    c = load_case(CASE)
    c["output"]["plots"] = False
    for k, v in edits.items():
        sec, key = k.split("__")
        c[sec][key] = v
    return c


def assert_site_line_refused(site_line: str, key: str, tmp_path, capsys):
    """The bundled sloping site with its ``slope = 3.0`` line replaced by ``site_line``, run through the
    command: exit 2, one line on standard error naming ``key``, no output folder."""
    from twofluid.cli import main

    path = tmp_path / "case.toml"
    path.write_text(case_text(CASE).replace("slope = 3.0", site_line))
    assert main(["run", str(path), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and key in err, err
    assert not (tmp_path / "out").exists()
