"""benchmarks/bench_versions.py: the works' case files, the commands, and the CPU it counts."""
import sys
import tomllib
from importlib import resources

import pytest
from repo_scripts import load_script

from twofluid.casefile.loader import case_text, load_case


@pytest.fixture(scope="module")
def bench():
    return load_script("benchmarks/bench_versions.py")


def test_case_files_are_valid_cases_with_the_works_edits(bench, tmp_path):
    files = bench.case_files(case_text, tmp_path, list(bench.WORKS))
    assert set(files) == set(bench.WORKS) - {"ensemble"}
    for work, path in files.items():
        case = load_case(str(path))  # validated by this version's schema
        text = tomllib.loads(path.read_text())
        for (section, key), value in bench.WORKS[work][2].items():
            assert text[section][key] == value
            assert case[section][key] == value
    chichi = tomllib.loads(files["chichi"].read_text())
    assert chichi["ground_motion"]["file"].startswith("RSN1180_CHICHI")
    # the Chi-Chi run is the member of the bundled five-motions ensemble with that record
    ens = tomllib.loads((resources.files("twofluid") / "data" / "ensembles" / "layered-site-five-motions.toml")
                        .read_text())
    i = ens["zip"]["ground_motion.file"].index(chichi["ground_motion"]["file"])
    member = {("ground_motion", key.split(".")[1]): values[i] for key, values in ens["zip"].items()}
    member |= {tuple(key.split(".")): value for key, value in ens["set"].items()}
    assert member == bench.WORKS["chichi"][2]


def test_commands_are_the_console_script_without_plots(bench, tmp_path):
    env = tmp_path / "venv"
    cmd = bench.command(env, "bed", tmp_path / "bed.toml", tmp_path / "out")
    assert cmd[0] == str(env / "bin" / "twofluid") and cmd[1] == "run" and "--no-plots" in cmd
    assert "--no-plots" not in bench.command(env, "bed", tmp_path / "bed.toml", tmp_path / "out", plots=True)
    ens = bench.command(env, "ensemble", None, tmp_path / "out")
    assert ens[1:3] == ["ensemble", "elcentro-pga-sweep"] and ens[-2:] == ["--workers", "2"]


def test_timed_counts_the_childrens_cpu(bench):
    # a child that spins 0.3 s of CPU in a grandchild: both are counted
    code = ("import subprocess, sys; subprocess.run([sys.executable, '-c', "
            "'import time\\nt = time.process_time()\\nwhile time.process_time() - t < 0.3: pass'], check=True)")
    cpu, wall, _ = bench.timed([sys.executable, "-c", code])
    assert cpu >= 0.3 and wall >= 0.3
    with pytest.raises(SystemExit):
        bench.timed([sys.executable, "-c", "raise SystemExit(3)"])


def test_runs_import_their_environments_own_package(bench, monkeypatch):
    # a developer's PYTHONPATH (a source tree) must not reach the timed runs
    monkeypatch.setenv("PYTHONPATH", "/nowhere/src")
    bench.timed([sys.executable, "-c", "import os, sys; sys.exit('PYTHONPATH' in os.environ)"])
    assert "PYTHONPATH" not in bench.installed_env(TWOFLUID_CACHE_DIR="x")
    assert bench.installed_env(TWOFLUID_CACHE_DIR="x")["TWOFLUID_CACHE_DIR"] == "x"
