"""Bad inputs of a ``liquefaction_1d`` run: checked before anything is written (exit 2, one line
naming file and key), and a step that goes non-finite ends the run as "failed" with its results.

All cases here are tiny (4 elements, 0.2 s) or stop at validation: the file runs in a few seconds.
"""
from __future__ import annotations

import csv
import json
import subprocess
import sys

import numpy as np
import pytest

from twofluid.casefile.loader import load_case
from twofluid.casefile.schema import CaseError
from twofluid.cli import main
from twofluid.closures import reference_porosity as rp
from twofluid.liquefaction import build_column, run_liquefaction
from twofluid.models import liquefaction_1d

RECORD = "time_s,acceleration_g\n" + "".join(f"{0.01 * i:.2f},{0.1 * np.sin(2 * np.pi * 2 * 0.01 * i):.6f}\n"
                                              for i in range(31))


def _case(**sections) -> str:
    """A tiny column shaken by record.csv (next to the case file); ``sections`` add or replace keys."""
    base = {
        "case": {"name": "tiny", "model": "liquefaction_1d"},
        "materials": {"liquid_density": 1000.0, "liquid_viscosity": 1e-3, "particle_density": 2650.0,
                      "particle_diameter": 8e-5},
        "deposit": {"depth": 4.0, "elements": 4},
        "sand": {},
        "ground_motion": {"file": "record.csv", "pga_g": 0.1, "duration": 0.2},
        "shear_wave": {"step": 0.01, "free_vibration": 0.0},
        "time": {"end": 0.2, "step": 0.02},
        "reconsolidation": {"step": 0.02},
        "report": {"depths": [1.0, 3.0]},
        "output": {"plots": False},
    }
    for sec, keys in sections.items():
        base.setdefault(sec, {}).update(keys)
    lines = []
    for sec, keys in base.items():
        lines.append(f"[{sec}]")
        for k, v in keys.items():
            lines.append(f"{k} = {json.dumps(v)}")
    return "\n".join(lines) + "\n"


@pytest.fixture
def folder(tmp_path, monkeypatch):
    """Case folder with the record; the run starts from another folder (paths are case-relative)."""
    cases = tmp_path / "cases"
    cases.mkdir()
    (cases / "record.csv").write_text(RECORD)
    (cases / "weights.json").write_text(json.dumps(rp.load_weights().to_json()))
    work = tmp_path / "work"
    work.mkdir()
    monkeypatch.chdir(work)
    return cases


def _bad_run(folder, capsys, text, files=()):
    for name, content in files:
        (folder / name).write_text(content)
    path = folder / "bad.toml"
    path.write_text(text)
    out = folder / "out"
    code = main(["run", str(path), "--out", str(out), "--quiet"])
    err = capsys.readouterr().err.strip()
    assert code == 2, err
    assert len(err.splitlines()) == 1 and "Traceback" not in err
    assert not out.exists()  # checked before the output folder is made
    return err


BAD = [  # (case sections, extra files, words in the message)
    (dict(sand={"reference_porosity_law": "ann", "ann_weights": "missing.json"}), (),
     ["bad.toml", "[sand] ann_weights", "missing.json", "no such file"]),
    (dict(sand={"reference_porosity_law": "ann", "ann_weights": "broken.json"}), [("broken.json", "{nope")],
     ["[sand] ann_weights", "broken.json", "not valid JSON"]),
    (dict(sand={"reference_porosity_law": "ann", "ann_weights": "short.json"}),
     [("short.json", json.dumps({"input_min": [0, 0, 0]}))], ["[sand] ann_weights", "missing key"]),
    (dict(ground_motion={"file": "zero.csv"}), [("zero.csv", "0,0\n0.01,0\n0.02,0\n")],
     ["[ground_motion] file", "zero.csv", "all zero", "pga_g = 0"]),
    (dict(ground_motion={"file": "const.csv"}), [("const.csv", "0,0.1\n0.01,0.1\n0.02,0.1\n")],
     ["[ground_motion] file", "zero once the velocity baseline"]),
    (dict(ground_motion={"file": "text.csv"}), [("text.csv", "0,0\n0.01,abc\n")],
     ["[ground_motion] file", "text.csv", "line 2", "non-numeric"]),
    (dict(ground_motion={"file": "nowhere.csv"}), (), ["[ground_motion] file", "nowhere.csv"]),
    (dict(ground_motion={"duration": 0.005}), (), ["[ground_motion] duration", "at least 2 samples"]),
    (dict(materials={"particle_density": 900.0}), (),
     ["[materials] particle_density", "must exceed [materials] liquid_density = 1000"]),
    (dict(materials={"gravity": 0.0}), (), ["[materials] gravity", "(0, inf)"]),
    (dict(sand={"compressibility": 0.5}), (), ["[sand] compressibility", "valid: A <"]),
]


@pytest.mark.parametrize("sections, files, words", BAD)
def test_bad_input_stops_before_anything_is_written(folder, capsys, sections, files, words):
    err = _bad_run(folder, capsys, _case(**sections), files)
    for w in words:
        assert w in err, err


def test_bad_record_from_the_console_is_exit_2_without_traceback(folder):
    (folder / "zero.csv").write_text("0,0\n0.01,0\n")
    path = folder / "bad.toml"
    path.write_text(_case(ground_motion={"file": "zero.csv"}))
    p = subprocess.run([sys.executable, "-m", "twofluid.cli", "run", str(path), "--out", str(folder / "o")],
                       capture_output=True, text=True)
    assert p.returncode == 2
    assert "Traceback" not in p.stderr and "[ground_motion] file" in p.stderr
    assert not (folder / "o").exists()


def test_edited_case_dict_is_checked_again_before_writing(folder, tmp_path):
    """A resolved case edited after loading (as tests and scripts do) is validated by the runner."""
    path = folder / "ok.toml"
    path.write_text(_case())
    c = load_case(str(path))
    c["ground_motion"]["file"] = "no-such-record.csv"
    with pytest.raises(CaseError, match=r"ok\.toml: \[ground_motion\] file"):
        run_liquefaction(c, tmp_path / "o1")
    assert not (tmp_path / "o1").exists()
    c = load_case(str(path))
    c["deposit"]["porosity"] = 0.95
    with pytest.raises(CaseError, match=r"\[deposit\] porosity.*\[0\.2, 0\.7\]"):
        run_liquefaction(c, tmp_path / "o2")
    assert not (tmp_path / "o2").exists()


def test_weights_path_is_relative_to_the_case_file_and_read_once(folder, monkeypatch):
    calls = []
    real = rp.load_weights
    monkeypatch.setattr(rp, "load_weights", lambda p=None: calls.append(p) or real(p))
    path = folder / "ann.toml"
    path.write_text(_case(sand={"reference_porosity_law": "ann", "ann_weights": "weights.json"}))
    # the current folder (work/) holds no weights.json: found next to the case file
    r = run_liquefaction(str(path), folder / "out")
    assert r.status == "completed"
    assert r.summary["shear_substeps"] >= 20  # the law ran at every sub-step ...
    assert len(calls) == 2  # ... but the file was read once by the validation, once by the build
    assert all(str(p) == str(folder / "weights.json") for p in calls)
    w = build_column(load_case(str(path))).column.sand.law_params["weights"]
    assert isinstance(w, rp.AnnWeights)


def test_ann_law_reads_a_weights_path_once(tmp_path, monkeypatch):
    """The law itself, given a path, parses the file once per version (mtime, size)."""
    path = tmp_path / "w.json"
    path.write_text(json.dumps(rp.load_weights().to_json()))
    calls = []
    real = rp.load_weights
    monkeypatch.setattr(rp, "load_weights", lambda p=None: calls.append(p) or real(p))
    s = rp.ShearState.zeros(1)
    nb = np.array([0.45])
    for _ in range(5):
        nb, s = rp.ann([1e-4], [1e-4], nb, s, weights=str(path))
    assert len(calls) <= 1
    with pytest.raises(rp.AnnWeightsError, match="no such file"):
        rp.ann([1e-4], [1e-4], nb, s, weights=str(tmp_path / "gone.json"))


def test_non_finite_shear_step_is_a_failed_run_with_its_results(folder, monkeypatch, capsys):
    real = liquefaction_1d.seed_idriss_gmax
    calls = {"n": 0}

    def gmax(p_s, k2max):  # G_max goes non-finite after 6 shear sub-steps (3 vertical steps)
        calls["n"] += 1
        g = real(p_s, k2max)
        return g if calls["n"] <= 6 else np.full_like(g, np.nan)

    monkeypatch.setattr(liquefaction_1d, "seed_idriss_gmax", gmax)
    path = folder / "ok.toml"
    path.write_text(_case())
    out = folder / "out"
    assert main(["run", str(path), "--out", str(out), "--quiet"]) == 1
    captured = capsys.readouterr()
    assert "Traceback" not in captured.err and "failed" in captured.out
    s = json.loads((out / "summary.json").read_text())
    assert s["status"] == "failed" and "non-finite G_max" in s["reason"]
    assert s["stopped_at_s"] == pytest.approx(0.06)
    rows = list(csv.DictReader(open(out / "probes.csv")))
    assert float(rows[-1]["time_s"]) == pytest.approx(0.06)
