"""The command's exit statuses, through the installed executable (a subprocess), not main(argv) alone:
0 for help and --version, 2 for a usage error (argparse's message) or bad input (one line), 1 for an
internal error (one line naming it and the log its traceback went to), 130 for Ctrl-C."""
import os
import shutil
import subprocess
import sys

import pytest

from twofluid.cli import parser

EXE = [shutil.which("twofluid")] if shutil.which("twofluid") else [sys.executable, "-m", "twofluid.cli"]
COMMANDS = sorted(next(a for a in parser()._actions if a.dest == "command").choices)


def _run(*args, cwd=None, timeout=120, exe=None):
    return subprocess.run([*(exe or EXE), *args], capture_output=True, text=True, cwd=cwd, timeout=timeout)


def test_every_command_is_tested():
    assert {"run", "ensemble", "element-test", "fluidization-curve", "verify", "build-kernels"} <= set(COMMANDS)


@pytest.mark.parametrize("command", [None, *COMMANDS])
def test_help_exits_0(command):
    p = _run(*([command] if command else []), "--help")
    assert p.returncode == 0, p.stderr
    assert "usage: twofluid" in p.stdout and p.stderr == ""


def test_version_exits_0():
    p = _run("--version")
    assert p.returncode == 0 and p.stdout.startswith("twofluid "), (p.returncode, p.stderr)


@pytest.mark.parametrize("args", [[], ["no-such-command"], ["run"], ["run", "x", "--no-such-option"],
                                  ["element-test", "--csr", "0.1", "--gamma", "1e-3"],
                                  ["fluidization-curve", "fluidized-bed-step", "--points", "many"]])
def test_a_usage_error_exits_2_with_argparses_message(args):
    p = _run(*args)
    assert p.returncode == 2, (p.returncode, p.stderr)
    errors = [ln for ln in p.stderr.splitlines() if "error:" in ln]
    assert len(errors) == 1 and errors[0].startswith("twofluid") and "Traceback" not in p.stderr


@pytest.mark.parametrize("args, says", [
    (["run", "no-such-case"], "no-such-case"),
    (["fluidization-curve", "fluidized-bed-step", "--points", "1"], "--points"),
    (["fluidization-curve", "fluidized-bed-step", "--out", ""], "--out: is empty"),
    (["element-test", "--model", "hysteretic", "--drained"], "--drained"),
    (["ensemble", "elcentro-pga-sweep", "--scheduler", " "], "--scheduler"),
])
def test_bad_input_exits_2_with_one_line(args, says, tmp_path):
    p = _run(*args, cwd=tmp_path)
    assert p.returncode == 2, (p.returncode, p.stderr)
    assert p.stderr.count("\n") == 1 and says in p.stderr and "Traceback" not in p.stderr
    assert not any(tmp_path.iterdir())  # nothing written


def test_an_internal_error_exits_1_naming_it_and_its_log(tmp_path):
    """A defect of the program (here: an exception planted in a command) is one line with the
    exception and the file its traceback went to; not a traceback, not status 130."""
    code = ("import sys; sys.argv = ['twofluid', 'cases']\n"
            "import twofluid.cli as c\n"
            "def boom(args):\n    raise ZeroDivisionError('planted for the test')\n"
            "c._cmd_cases = boom\n"
            "c.main()\n")
    env = {**os.environ, "TMPDIR": str(tmp_path)}
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=120)
    assert p.returncode == 1, (p.returncode, p.stderr)
    lines = p.stderr.splitlines()
    assert len(lines) == 1 and "internal error: ZeroDivisionError: planted for the test" in lines[0], p.stderr
    log = lines[0].rsplit("traceback in ", 1)[1]
    text = open(log, encoding="utf-8").read()
    assert "Traceback (most recent call last)" in text and "planted for the test" in text


def test_an_internal_error_of_a_run_logs_into_the_run_folder(tmp_path):
    from twofluid.io.folders import ERROR_LOG, MANIFEST, OutputFolder, write_error_log

    with OutputFolder(tmp_path / "run"):
        pass
    path = write_error_log("Traceback (most recent call last):\nX\n")
    assert path == tmp_path / "run" / ERROR_LOG
    assert ERROR_LOG in (tmp_path / "run" / MANIFEST).read_text()  # recorded: the next run removes it
    with OutputFolder(tmp_path / "run"):
        assert not path.exists()


def test_ctrl_c_before_main_starts_is_one_line_and_130():
    """A SIGINT that arrives while the command's module is imported, before main() runs, ends it as an
    interruption: status 130 and one line, no traceback from the import."""
    code = ("import sys; sys.argv = ['twofluid', 'cases']\n"
            "import os, signal\nimport twofluid.cli as c\n"
            "os.kill(os.getpid(), signal.SIGINT)\n"
            "c.main()\n")
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert p.returncode == 130 and p.stderr == "twofluid: interrupted\n", (p.returncode, p.stderr)


def test_sigterm_before_main_starts_is_143():
    code = ("import sys; sys.argv = ['twofluid', 'cases']\n"
            "import os, signal\nimport twofluid.cli as c\n"
            "os.kill(os.getpid(), signal.SIGTERM)\n"
            "c.main()\n")
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert p.returncode == 143 and "terminated (SIGTERM)" in p.stderr, (p.returncode, p.stderr)


def _short_case(tmp_path):
    text = _run("show", "settling-illite").stdout
    import re

    text = re.sub(r"(?m)^end\s*=.*$", "end = 0.4", text)
    text = re.sub(r"(?m)^times\s*=.*$", "times = []", text)
    (tmp_path / "short.toml").write_text(text)
    return "short.toml"


@pytest.mark.parametrize("args", [
    ["cases"], ["show", "settling-illite"], ["show", "--readme", "liquefaction-layered-site"],
    ["simplified", "liquefaction-layered-site"],
    ["element-test", "--gamma", "2e-3", "--max-cycles", "1", "--steps-per-cycle", "20", "--out", "et"],
    ["fluidization-curve", "fluidized-bed-step", "--no-plots", "--points", "10", "--out", "fc"],
    ["run", "SHORT", "--no-plots", "--out", "r"],
    ["verify", "--quick", "--only", "hydrostatic"],
])
def test_a_command_that_works_exits_0_through_the_executable(tmp_path, args):
    args = [_short_case(tmp_path) if a == "SHORT" else a for a in args]
    p = _run(*args, cwd=tmp_path, timeout=600)
    assert p.returncode == 0, (p.returncode, p.stderr[-2000:])
    assert "Traceback" not in p.stderr
