"""Ensemble files: validation (one line naming the file and key, exit 2), member generation,
sampling (same seed, same samples; the distributions' moments), hashing, lognormal fragility MLE.
No cluster here: these run in the test process."""
from __future__ import annotations

import numpy as np
import pytest
from scipy import stats

from twofluid.casefile.schema import CaseError
from twofluid.cli import main
from twofluid.ensemble import load_ensemble
from twofluid.ensemble.fragility import fit_lognormal_fragility
from twofluid.ensemble.members import members, samples

GRID = """
[ensemble]
name = "small-grid"
base = "settling-illite"
collect = ["porosity_range"]
[set]
"time.end" = 1.0
"output.times" = [1.0]
[grid]
"materials.particle_diameter" = [5e-5, 6e-5, 7e-5]
"closures.solids_pressure.compressibility" = [0.1, 0.2]
"""


def write(tmp_path, text, name="ens.toml"):
    p = tmp_path / name
    p.write_text(text)
    return p


def test_grid_zip_and_samples_multiply(tmp_path):
    text = GRID + """
[zip]
"materials.liquid_density" = [870.0, 880.0]
"materials.liquid_viscosity" = [0.5e-3, 0.6e-3]
[sample]
seed = 4
count = 3
"initial.porosity" = { distribution = "uniform", low = 0.94, high = 0.96 }
"""
    ms = members(load_ensemble(write(tmp_path, text)))
    assert len(ms) == 3 * 2 * 2 * 3
    assert all(m.error == "" and len(m.hash) == 64 for m in ms)
    assert len({m.hash for m in ms}) == len(ms)  # every member a different case
    zipped = {(m.params["materials.liquid_density"], m.params["materials.liquid_viscosity"]) for m in ms}
    assert zipped == {(870.0, 0.5e-3), (880.0, 0.6e-3)}
    m = ms[-1]
    for key, value in m.params.items():  # a dotted key is a path into the nested case
        node = m.case
        for part in key.split("."):
            node = node[part]
        assert node == value
    assert m.case["time"]["end"] == 1.0 and m.case["output"]["plots"] is False


def test_same_seed_same_samples_and_the_moments_follow_the_distributions():
    n = 20000
    spec = {"seed": 11, "count": n, "distributions": {
        "a": {"distribution": "normal", "mean": 47.0, "std": 5.0},
        "b": {"distribution": "lognormal", "median": 1e-4, "log_std": 0.3},
        "c": {"distribution": "truncnorm", "mean": 0.44, "std": 0.02, "low": 0.42, "high": 0.45},
        "d": {"distribution": "uniform", "low": 1.0, "high": 3.0}}}
    s1, s2 = samples(spec), samples(spec)
    other = samples({**spec, "seed": 12})
    for k in s1:
        assert np.array_equal(s1[k], s2[k])
        assert not np.array_equal(s1[k], other[k])
    # sample means within 5 standard errors of the exact means (a false failure has p < 1e-6)
    exact = {"a": stats.norm(47.0, 5.0), "b": stats.lognorm(s=0.3, scale=1e-4),
             "c": stats.truncnorm(-1.0, 0.5, loc=0.44, scale=0.02), "d": stats.uniform(1.0, 2.0)}
    for k, dist in exact.items():
        assert abs(s1[k].mean() - dist.mean()) < 5 * dist.std() / np.sqrt(n), k
    assert s1["c"].min() >= 0.42 and s1["c"].max() <= 0.45
    assert abs(np.median(np.log(s1["b"])) - np.log(1e-4)) < 5 * 0.3 * 1.26 / np.sqrt(n)


def test_a_bad_combination_is_a_failed_member_with_its_reason(tmp_path):
    text = GRID.replace("[0.1, 0.2]", "[0.1, -1.0]")
    ms = members(load_ensemble(write(tmp_path, text)))
    bad = [m for m in ms if m.error]
    assert len(bad) == 3 and all(m.case is None and m.hash == "" for m in bad)
    assert "[closures.solids_pressure] compressibility" in bad[0].error and "(0, inf)" in bad[0].error


def test_the_bundled_example_is_valid():
    spec = load_ensemble("elcentro-pga-sweep")
    ms = members(spec)
    assert len(ms) == 5 * 4 and not any(m.error for m in ms)
    assert spec.fragility["intensity"] == "ground_motion.pga_g"


@pytest.mark.parametrize("change, words", [
    (("[grid]", "[grid]\n\"materials.nonsense\" = [1.0]\n"), ["ens.toml", "[grid] materials.nonsense",
                                                              "no key 'nonsense'"]),
    (("[grid]", "[grid]\n\"nosection.key\" = [1.0]\n"), ["[grid] nosection.key", "no section [nosection]"]),
    (("[0.1, 0.2]", "0.1"), ["[grid] closures.solids_pressure.compressibility", "non-empty list"]),
    (("collect = [\"porosity_range\"]", "collect = []"), ["[ensemble] collect", "non-empty list"]),
    (("base = \"settling-illite\"", "base = \"nope\""), ["nope", "bundled"]),
    (("[set]", "[bogus]\nx = 1\n[set]"), ["[bogus]", "unknown section"]),
    (("name = \"small-grid\"", "name = \"small-grid\"\nkeep = true"), ["[ensemble] keep", "unknown key"]),
    (("[set]", "[zip]\n\"materials.liquid_density\" = [1.0, 2.0]\n\"materials.sphericity\" = [1.0]\n[set]"),
     ["[zip]", "one length"]),
    (("[set]", "[sample]\nseed = -1\ncount = 2\n\"initial.porosity\" = { distribution = \"uniform\", "
               "low = 0.9, high = 0.95 }\n[set]"), ["[sample] seed", "integer >= 0"]),
    (("[set]", "[sample]\nseed = 1\ncount = 2\n\"initial.porosity\" = { distribution = \"uniform\", "
               "low = 0.95, high = 0.9 }\n[set]"), ["[sample] initial.porosity", "low < high"]),
    (("[set]", "[sample]\nseed = 1\ncount = 2\n\"initial.porosity\" = { distribution = \"beta\" }\n[set]"),
     ["[sample] initial.porosity", "uniform, normal, lognormal, truncnorm"]),
    (("[set]", "[sample]\nseed = 1\ncount = 2\n\"initial.porosity\" = { distribution = \"normal\", mean = 0.9 }"
               "\n[set]"), ["[sample] initial.porosity", "mean, std"]),
    (("[set]", "[ground_motions]\nfiles = \"nowhere/*.AT2\"\n[set]"),
     ["[ground_motions] ground_motion.file", "no section [ground_motion]"]),
    (("\"time.end\" = 1.0", "\"time.end\" = -1.0"), ["[set]", "[time] end"]),
    (("[grid]", "[fragility]\nfigure = \"porosity_range\"\nthreshold = 0.9\nintensity = \"time.end\"\n[grid]"),
     ["[fragility] intensity", "varied key"]),
    (("[grid]\n\"materials.particle_diameter\" = [5e-5, 6e-5, 7e-5]\n"
      "\"closures.solids_pressure.compressibility\" = [0.1, 0.2]", ""), ["[grid]", "nothing varies"]),
    (("[set]", "[set]\n\"materials.particle_diameter\" = 5e-5"), ["materials.particle_diameter", "more than one"]),
    (("[ensemble]", "[ensemble"), ["TOML syntax"]),
])
def test_bad_ensemble_files_are_exit_2_and_one_line(tmp_path, capsys, change, words):
    old, new = change
    assert old in GRID
    path = write(tmp_path, GRID.replace(old, new, 1))
    assert main(["ensemble", str(path), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and err.startswith("twofluid: error: ") and "Traceback" not in err, err
    for w in words:
        assert w in err, err
    assert not (tmp_path / "out").exists()  # nothing ran, nothing was written
    with pytest.raises(CaseError):
        load_ensemble(path)


def test_record_files_that_match_nothing_are_exit_2(tmp_path, capsys):
    path = write(tmp_path, GRID.replace("settling-illite", "liquefaction-elcentro").replace(
        "[grid]", "[ground_motions]\nfiles = \"nowhere/*.AT2\"\npga_g = [0.1]\n[grid]").replace(
        "[grid]\n\"materials.particle_diameter\" = [5e-5, 6e-5, 7e-5]\n"
        "\"closures.solids_pressure.compressibility\" = [0.1, 0.2]", ""))
    assert main(["ensemble", str(path)]) == 2
    err = capsys.readouterr().err
    assert "[ground_motions] files" in err and "'nowhere/*.AT2' matches no record" in err


def test_a_missing_ensemble_file_is_exit_2(tmp_path, capsys):
    assert main(["ensemble", str(tmp_path / "none.toml")]) == 2
    assert "none.toml: file" in capsys.readouterr().err


def test_fragility_mle_recovers_the_curve_it_was_drawn_from():
    """Outcomes drawn from Φ(ln(x/0.12)/0.45) at 8 levels × 400: the MLE is within 5 of its
    standard errors (≈ θβ/√(n f(z)) ~ 0.004 for θ; ~0.03 for β) of the truth."""
    rng = np.random.default_rng(5)
    x = np.repeat(np.geomspace(0.03, 0.5, 8), 400)
    y = rng.random(x.size) < stats.norm.cdf(np.log(x / 0.12) / 0.45)
    fit = fit_lognormal_fragility(x, y)
    assert fit["theta"] == pytest.approx(0.12, abs=5 * 0.004)
    assert fit["beta"] == pytest.approx(0.45, abs=5 * 0.03)
    assert fit_lognormal_fragility(x, np.zeros_like(y))["theta"] is None
