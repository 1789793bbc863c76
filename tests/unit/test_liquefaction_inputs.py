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
from twofluid.casefile.schema import CaseError, CaseWarning
from twofluid.cli import main
from twofluid.closures import reference_porosity as rp
from twofluid.runners.liquefaction import build_column, run_liquefaction
from twofluid.models import liquefaction_1d

RECORD = "time_s,acceleration_g\n" + "".join(f"{0.01 * i:.2f},{0.1 * np.sin(2 * np.pi * 2 * 0.01 * i):.6f}\n"
                                              for i in range(31))


def _case(layer=None, **sections) -> str:
    """A tiny one-layer site shaken by record.csv (next to the case file); ``layer`` and ``sections``
    add or replace keys (of the layer, of the sections)."""
    base = {
        "case": {"name": "tiny", "model": "liquefaction_1d"},
        "materials": {"liquid_density": 1000.0, "liquid_viscosity": 1e-3, "particle_density": 2650.0},
        "site": {},
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
    one = {"name": "sand", "thickness": 4.0, "elements": 4, "particle_diameter": 8e-5, "porosity": 0.44,
           **(layer or {})}
    lines.append("[[layers]]")
    lines += [f"{k} = {json.dumps(v)}" for k, v in one.items()]
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
    (dict(layer={"reference_porosity_law": "ann", "ann_weights": "missing.json"}), (),
     ["bad.toml", "[layers 1 'sand'] ann_weights", "missing.json", "no such file"]),
    (dict(layer={"reference_porosity_law": "ann", "ann_weights": "broken.json"}), [("broken.json", "{nope")],
     ["[layers 1 'sand'] ann_weights", "broken.json", "not valid JSON"]),
    (dict(layer={"reference_porosity_law": "ann", "ann_weights": "short.json"}),
     [("short.json", json.dumps({"input_min": [0, 0, 0]}))], ["[layers 1 'sand'] ann_weights", "missing key"]),
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
    (dict(layer={"compressibility": 0.5}), (), ["[layers 1 'sand'] compressibility", "valid: A <"]),
    # tabulated G/G_max (docs/model.md, "Shear modulus"): inline lists or a CSV file next to the case file
    (dict(layer={"modulus_reduction": "tabulated"}), (), ["[layers 1 'sand'] modulus_reduction", "needs a table"]),
    (dict(layer={"modulus_reduction": "tabulated", "reduction_strains": [1e-4, 1e-5],
                "reduction_ratios": [1.0, 0.5]}), (),
     ["bad.toml", "[layers 1 'sand'] reduction_strains", "strictly increase", "0.0001 (point 1) then 1e-05"]),
    (dict(layer={"modulus_reduction": "tabulated", "reduction_strains": [0.0, 1e-4],
                "reduction_ratios": [1.0, 0.5]}), (), ["[layers 1 'sand'] reduction_strains", "valid range (0, inf)"]),
    (dict(layer={"modulus_reduction": "tabulated", "reduction_strains": [1e-5, 1e-4],
                "reduction_ratios": [1.0, 1.5]}), (), ["[layers 1 'sand'] reduction_ratios", "1.5", "valid range (0, 1]"]),
    (dict(layer={"modulus_reduction": "tabulated", "reduction_strains": [1e-5, 1e-4, 1e-3],
                "reduction_ratios": [1.0, 0.5, 0.7]}), (), ["[layers 1 'sand'] reduction_ratios", "must not increase"]),
    (dict(layer={"modulus_reduction": "tabulated", "reduction_strains": [1e-5],
                "reduction_ratios": [1.0]}), (), ["[layers 1 'sand'] reduction_strains", "at least 2"]),
    (dict(layer={"modulus_reduction": "tabulated", "reduction_strains": [1e-5, 1e-4, 1e-3],
                "reduction_ratios": [1.0, 0.5]}), (), ["[layers 1 'sand'] reduction_ratios", "3 strain(s) but 2"]),
    (dict(layer={"modulus_reduction": "tabulated", "reduction_strains": [1e-5, 1e-4],
                "reduction_ratios": "0.5"}), (), ["[layers 1 'sand'] reduction_ratios", "list of numbers"]),
    (dict(layer={"modulus_reduction": "tabulated", "reduction_file": "missing.csv"}), (),
     ["[layers 1 'sand'] reduction_file", "missing.csv", "no such file"]),
    (dict(layer={"modulus_reduction": "tabulated", "reduction_file": "g.csv"}),
     [("g.csv", "strain,G_over_Gmax\n1e-5,1.0\n1e-4,abc\n")],
     ["[layers 1 'sand'] reduction_file", "g.csv line 3", "non-numeric"]),
    (dict(layer={"modulus_reduction": "tabulated", "reduction_file": "g.csv"}),
     [("g.csv", "1e-5,1.0,3\n1e-4,0.5\n")], ["[layers 1 'sand'] reduction_file", "g.csv line 1", "3 value(s)"]),
    (dict(layer={"modulus_reduction": "tabulated", "reduction_file": "g.csv"}),
     [("g.csv", "# Seed-Idriss\n1e-5,1.0\n1e-4,0.0\n")],
     ["[layers 1 'sand'] reduction_file", "g.csv: G/G_max = 0 at strain 0.0001", "(0, 1]"]),
    (dict(layer={"modulus_reduction": "tabulated", "reduction_file": "g.csv"}), [("g.csv", "strain,ratio\n")],
     ["[layers 1 'sand'] reduction_file", "has 0 point(s)", "at least 2"]),
    (dict(layer={"modulus_reduction": "tabulated", "reduction_file": "g.csv", "reduction_strains": [1e-5, 1e-4],
                "reduction_ratios": [1.0, 0.5]}), [("g.csv", "1e-5,1\n1e-4,0.5\n")],
     ["[layers 1 'sand'] reduction_file", "not both"]),
    # compliant base (docs/liquefaction.md, "Compliant base")
    (dict(shear_wave={"base": "elastic"}), (), ["[shear_wave] base", "'rigid', 'compliant'"]),
    (dict(shear_wave={"base": "compliant", "bedrock_shear_velocity": 0.0}), (),
     ["[shear_wave] bedrock_shear_velocity", "(0, 10000]", "m/s"]),
    (dict(shear_wave={"base": "compliant", "bedrock_density": 500.0}), (),
     ["[shear_wave] bedrock_density", "[1000, 5000]", "kg/m³"]),
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
    c["layers"][0]["porosity"] = 0.95
    with pytest.raises(CaseError, match=r"\[layers 1 'sand'\] porosity.*\[0, 0\.7\]"):
        run_liquefaction(c, tmp_path / "o2")
    assert not (tmp_path / "o2").exists()


def test_weights_path_is_relative_to_the_case_file_and_read_once(folder, monkeypatch):
    calls = []
    real = rp.load_weights
    monkeypatch.setattr(rp, "load_weights", lambda p=None: calls.append(p) or real(p))
    path = folder / "ann.toml"
    path.write_text(_case(layer={"reference_porosity_law": "ann", "ann_weights": "weights.json"},
                          shear_wave={"model": "thesis"}))
    # the current folder (work/) holds no weights.json: found next to the case file
    r = run_liquefaction(str(path), folder / "out")
    assert r.status == "completed"
    assert r.summary["shear_substeps"] >= 20  # the law ran at every sub-step ...
    # ... but the file was read once by the validation, once by the build and once by the build of
    # the total-stress companion run (the simplified procedure's a_max)
    assert len(calls) == 3
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
    # the reference shear path calls seed_idriss_gmax; the compiled kernel evaluates G_max itself
    monkeypatch.setattr(liquefaction_1d._shear_kernel, "available", lambda: False)
    path = folder / "ok.toml"
    path.write_text(_case(shear_wave={"model": "thesis"}))
    out = folder / "out"
    assert main(["run", str(path), "--out", str(out), "--quiet"]) == 1
    captured = capsys.readouterr()
    assert "Traceback" not in captured.err and "failed" in captured.out
    s = json.loads((out / "summary.json").read_text())
    assert s["status"] == "failed" and "non-finite G_max" in s["reason"]
    assert s["stopped_at_s"] == pytest.approx(0.06)
    rows = list(csv.DictReader(open(out / "probes.csv")))
    assert float(rows[-1]["time_s"]) == pytest.approx(0.06)


def _probes(out):
    return list(csv.DictReader(open(out / "probes.csv")))


def test_tabulated_reduction_from_a_csv_next_to_the_case_file(folder):
    """A table of the default hyperbola (γ_ref = 0.1 %, 20 points per decade) runs like the default
    (surface displacement within 1.2e-4 of its peak; asserted 1e-3); a stiffer table (γ_ref = 1 %)
    does not (127 %). The CSV is found next to the case file."""
    from twofluid.closures.shear_modulus import hyperbolic

    strains = np.logspace(-7, -1, 121)
    for name, ref in (("same.csv", 1e-3), ("stiff.csv", 1e-2)):
        rows = "".join(f"{g:.10g},{r:.10g}\n" for g, r in zip(strains, hyperbolic(strains, ref)))
        (folder / name).write_text("# shear strain [-], G/G_max\nstrain,G_over_Gmax\n" + rows)
    runs = {}
    for name, sand in (("hyp", {}), ("same", {"modulus_reduction": "tabulated", "reduction_file": "same.csv"}),
                       ("stiff", {"modulus_reduction": "tabulated", "reduction_file": "stiff.csv"})):
        path = folder / f"{name}.toml"
        path.write_text(_case(layer=sand, ground_motion={"pga_g": 0.5}, shear_wave={"model": "thesis"}))
        r = run_liquefaction(str(path), folder / name)
        assert r.status == "completed"
        assert r.summary["shaking"]["modulus_reduction"] == ("hyperbolic" if name == "hyp" else "tabulated")
        runs[name] = np.array([float(row["surface_displacement_m"]) for row in _probes(folder / name)])
    scale = np.max(np.abs(runs["hyp"]))
    assert scale > 0.0
    assert np.max(np.abs(runs["same"] - runs["hyp"])) < 1e-3 * scale
    assert np.max(np.abs(runs["stiff"] - runs["hyp"])) > 0.01 * scale


def test_inline_table_and_its_warnings(folder, capsys):
    """Inline lists work; gamma_ref is then ignored (warning), and a table whose log interpolation
    makes the stress fall between two points is run with a warning naming them."""
    path = folder / "inline.toml"
    path.write_text(_case(layer={"modulus_reduction": "tabulated", "gamma_ref": 2e-3,
                                "reduction_strains": [1e-6, 1e-4, 1e-3, 3e-3, 1e-2],
                                "reduction_ratios": [1.0, 0.9, 0.5, 0.3, 0.12]}))
    assert main(["run", str(path), "--out", str(folder / "o"), "--quiet"]) == 0
    err = capsys.readouterr().err
    assert "[layers 1 'sand'] gamma_ref: ignored" in err
    assert "[layers 1 'sand'] reduction_ratios" in err and "0.003–0.01" in err and "softening" in err
    with pytest.warns(CaseWarning) as caught:
        case = load_case(str(path))
    assert sorted("softening" in str(w.message) for w in caught) == [False, True]
    b = build_column(case)
    assert b.column.sand.reduction(np.array([1e-3, 1.0])).tolist() == [0.5, 0.12]


def test_compliant_base_case(folder):
    """[shear_wave] base = "compliant": the record is the outcrop motion, the base node moves, the
    summary gives c = ρ_r V_r and the impedance ratio of the bottom element. The stiffest bedrock
    the ranges allow (α = 0.0053) moves the surface 1.6 % of its peak away from the rigid base,
    a soft one (α = 0.44) 67 %: asserted < 5 % of the soft difference, and > 10 % (measured with the
    thesis model, whose column is elastic at these strains). (The precise checks against the exact
    solution are in test_liquefaction_base.py.)"""
    out = {}
    for name, sw in (("rigid", {}), ("soft", {"base": "compliant", "bedrock_density": 2000.0,
                                             "bedrock_shear_velocity": 300.0}),
                     ("stiff", {"base": "compliant", "bedrock_density": 5000.0,
                                "bedrock_shear_velocity": 10000.0})):
        path = folder / f"{name}.toml"
        path.write_text(_case(shear_wave={"model": "thesis", **sw}))
        r = run_liquefaction(str(path), folder / name)
        assert r.status == "completed"
        out[name] = (r, _probes(folder / name))
    base = out["soft"][0].summary["shaking"]["base"]
    assert base["kind"] == "compliant" and base["bedrock_impedance_Pa_s_m"] == pytest.approx(6e5)
    b = build_column(load_case(str(folder / "soft.toml")))
    rho0 = b.column.mixture_density(b.state.vertical.n)[0]
    vs0 = np.sqrt(liquefaction_1d.seed_idriss_gmax(b.column.sigma_v0[0], 30.0) / rho0)
    assert base["impedance_ratio_bottom_element"] == pytest.approx(rho0 * vs0 / 6e5, rel=1e-12)
    assert out["rigid"][0].summary["shaking"]["base"] == {"kind": "rigid", "record_is": "base motion"}
    rec = {k: np.array([float(row["base_acceleration_m_s2"]) for row in rows]) for k, (_, rows) in out.items()}
    top = {k: np.array([float(row["surface_displacement_m"]) for row in rows]) for k, (_, rows) in out.items()}
    assert np.max(np.abs(rec["soft"] - rec["rigid"])) > 0.1 * np.max(np.abs(rec["rigid"]))  # the base moves
    soft = np.max(np.abs(top["soft"] - top["rigid"]))
    assert soft > 0.1 * np.max(np.abs(top["rigid"]))
    assert np.max(np.abs(top["stiff"] - top["rigid"])) < 0.05 * soft


def test_units_given_with_an_at2_record_is_warned_as_without_effect(tmp_path):
    """An .AT2 record is in g by its format: `[ground_motion] units` only acts on a .csv record."""
    import warnings

    from twofluid.casefile.loader import case_text

    text = case_text("liquefaction-elcentro").replace("[ground_motion]\n", '[ground_motion]\nunits = "m/s2"\n', 1)
    path = tmp_path / "at2.toml"
    path.write_text(text, encoding="utf-8")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        load_case(str(path))
    msgs = [str(w.message) for w in caught if issubclass(w.category, CaseWarning)]
    assert any("[ground_motion] units: ignored" in m and "'.csv' file" in m for m in msgs), msgs


def test_a_site_too_deep_for_the_simplified_procedure_is_refused_at_load_time(tmp_path):
    """K_σ of the simplified procedure (run beside every case) holds to 20 atm: refused before anything runs."""
    from twofluid.casefile.loader import case_text

    text = case_text("liquefaction-gravel").replace("thickness = 10.0", "thickness = 300.0", 1)
    path = tmp_path / "deep.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(CaseError, match=r"\[layers 1 .*\] thickness: .*20 atm"):
        load_case(str(path))
    assert not (tmp_path / "twofluid-out").exists()
