"""The Python API validates exactly as the CLI does, keeps results in memory, and is discoverable."""
from __future__ import annotations

import copy

import numpy as np
import pytest

import twofluid
from twofluid.casefile.loader import load_case
from twofluid.casefile.schema import CaseError
from twofluid.cli import main


def _short(name="settling-illite"):
    case = load_case(name)
    case["time"]["end"] = case["time"]["step"]
    case["output"].update(times=[], probes=[])
    return case


def _cli_error(case: dict, tmp_path, capsys) -> str:
    """The CLI's one line for ``case`` written as a TOML file (resolved-case writer)."""
    import tomli_w

    doc = {}
    for where, table in case.items():
        if where.startswith("_"):
            continue
        node = doc
        *parents, last = where.split(".")
        for p in parents:
            node = node.setdefault(p, {})
        node[last] = table
    path = tmp_path / "c.toml"
    path.write_text(tomli_w.dumps(doc))
    assert main(["run", str(path), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err
    return err.removeprefix("twofluid: error: ").replace(str(path), "<src>")


@pytest.mark.parametrize("edit, key", [
    (lambda c: c["materials"].__setitem__("particle_diameter", -1e-4), "[materials] particle_diameter"),
    (lambda c: c["materials"].__setitem__("particle_diametr", 1e-4), "[materials] particle_diametr"),
    (lambda c: c["mesh"].__setitem__("elements", "16"), "[mesh] elements"),
    (lambda c: c["mesh"].__setitem__("length", float("nan")), "[mesh] length"),
    (lambda c: c["output"].__setitem__("times", [1.0, float("inf")]), "[output] times"),
    (lambda c: c["materials"].__setitem__("particle_density", 1e308), "[materials] particle_density"),
])
def test_an_edited_dict_is_refused_with_the_clis_message(edit, key, tmp_path, capsys):
    case = _short()
    edit(case)
    with pytest.raises(CaseError) as api:
        twofluid.run_case(case, tmp_path / "api")
    assert key in str(api.value)
    assert str(api.value).split(": ", 1)[1] == _cli_error(case, tmp_path, capsys).split(": ", 1)[1]
    assert not (tmp_path / "api").exists()  # validated before the folder is made


def test_missing_sections_wrong_types_and_non_paths_are_case_errors():
    case = _short()
    del case["materials"]
    with pytest.raises(CaseError, match=r"\[materials\] liquid_density: missing"):
        twofluid.run_case(case)
    with pytest.raises(CaseError, match=r"<api>: case: must be a resolved case"):
        twofluid.run_case(42)
    with pytest.raises(CaseError, match=r"mesh: keys must sit inside a \[section\]"):
        twofluid.run_case({"case": {"name": "x"}, "mesh": 3})
    with pytest.raises(CaseError, match=r"out_dir|output folder"):
        twofluid.run_case(_short(), out_dir=3.5)


def test_out_dir_none_keeps_everything_in_memory(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    res = twofluid.run_case(_short())
    assert res.status == "completed" and res.out_dir is None
    assert list(tmp_path.iterdir()) == []  # no twofluid-out/, no file at all
    prof = res.tables["profiles.csv"]
    assert set(prof) >= {"time_s", "porosity", "P_Pa"}
    n = load_case("settling-illite")["mesh"]["elements"]
    assert prof["porosity"].size == 2 * n  # t = 0 and the end
    assert np.all(np.isfinite(prof["porosity"]))


def test_edit_a_case_workflow_changes_the_result():
    """README: load_case, change a value, run_case (in memory)."""
    a = _short()
    b = copy.deepcopy(a)
    b["materials"]["particle_diameter"] *= 2.0
    ra, rb = twofluid.run_case(a), twofluid.run_case(b)
    va, vb = ra.tables["profiles.csv"]["Us_m_s"], rb.tables["profiles.csv"]["Us_m_s"]
    assert np.nanmax(np.abs(vb)) > 1.5 * np.nanmax(np.abs(va))  # Stokes settling ∝ d²


def test_dir_lists_the_public_names():
    names = dir(twofluid)
    for n in ("run_case", "load_case", "CaseError", "RunResult", "build", "integrate", "bundled_cases"):
        assert n in names


def test_a_copied_case_runs_under_its_own_name(tmp_path, capsys, monkeypatch):
    assert main(["show", "settling-illite"]) == 0
    (tmp_path / "my.toml").write_text(capsys.readouterr().out)
    case = load_case(tmp_path / "my.toml")
    assert case["case"]["name"] == "my"
    monkeypatch.chdir(tmp_path)
    from twofluid.io.folders import default_out_dir

    assert default_out_dir(case).as_posix() == "twofluid-out/my"


def test_a_name_cannot_escape_the_output_folder():
    case = _short()
    case["case"]["name"] = "../../escaped"
    with pytest.raises(CaseError, match=r"\[case\] name"):
        twofluid.run_case(case)
    from twofluid.io.folders import default_out_dir

    case["case"]["name"] = "a b:c"
    assert default_out_dir(case).parent.as_posix() == "twofluid-out"


def test_the_resolved_2d_case_holds_only_what_acts(tmp_path):
    from twofluid.io.results import write_resolved_case

    case = load_case("viscometer")
    write_resolved_case(tmp_path / "r.toml", case)
    text = (tmp_path / "r.toml").read_text()
    assert "[boundary.left]" not in text and 'kind = "none"' not in text and "file = " not in text
    again = load_case(tmp_path / "r.toml")
    assert again["boundary"]["cut"] == case["boundary"]["cut"] and again["mesh"] == case["mesh"]
    one_d = load_case("settling-illite")
    write_resolved_case(tmp_path / "s.toml", one_d)
    assert "area_top" not in (tmp_path / "s.toml").read_text()


def test_the_cli_validates_a_case_once_and_runs_it_in_its_default_folder(tmp_path, monkeypatch):
    """`twofluid run CASE` loads and checks the case once (run_case does it), and without --out
    the results go to twofluid-out/<[case] name> of the working folder."""
    import tomli_w

    from twofluid.casefile import loader, schema

    c = load_case("settling-illite")
    c["time"]["end"], c["output"]["times"], c["output"]["plots"] = c["time"]["step"], [], False
    case = tmp_path / "short.toml"
    case.write_text(tomli_w.dumps({k: v for k, v in c.items() if not k.startswith("_")}))
    calls = []
    real = schema.validate

    def counted(*a, **k):
        calls.append(1)
        return real(*a, **k)

    monkeypatch.setattr(loader, "validate", counted)  # a case file's check
    monkeypatch.setattr(schema, "validate", counted)  # a dict's (schema.revalidate)
    monkeypatch.chdir(tmp_path)
    assert main(["run", str(case), "--quiet"]) == 0
    assert len(calls) == 1
    assert (tmp_path / "twofluid-out" / c["case"]["name"] / "summary.json").is_file()


@pytest.mark.parametrize("preset, expected", [(None, "1"), ("3", "3")])
def test_the_cli_runs_with_one_blas_thread_unless_the_user_set_one(preset, expected):
    """The command line sets OPENBLAS/OMP/MKL_NUM_THREADS to 1 before NumPy is imported, unless
    the user set them (a BLAS pool costs a 1D run CPU and buys it nothing)."""
    import os
    import subprocess
    import sys

    env = {k: v for k, v in os.environ.items() if k not in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS",
                                                             "MKL_NUM_THREADS")}
    if preset is not None:
        env["OPENBLAS_NUM_THREADS"] = preset
    code = ("import os, sys; from twofluid.cli import main; main(['cases']); "
            "print(os.environ['OPENBLAS_NUM_THREADS'], os.environ['OMP_NUM_THREADS'])")
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    assert out.stdout.split()[-2:] == [expected, "1"]
