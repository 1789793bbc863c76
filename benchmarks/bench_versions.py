"""Two installed versions of twofluid against each other: whole-process CPU of the same runs, alternated.

Each version is a plain ``pip install .`` in its own virtual environment (``--base`` and ``--new``:
the environments' folders), with its kernels built (``twofluid build-kernels`` of each is run first;
it only checks when they are). Every work is one command of that environment's console script, as a
user types it, its outputs in a temporary folder:

- ``bed``: ``twofluid run fluidized-bed-step --no-plots`` (the default case);
- ``layered``: the layered site (``liquefaction-layered-site``);
- ``sloping``: the sloping site (``sloping-site``, 3 %);
- ``chichi``: the layered site under the longest bundled record, Chi-Chi CHY002 (86.9 s of shaking),
  as the member of the bundled ensemble ``layered-site-five-motions`` (0.15 g outcrop, compliant base);
- ``flow``: the sloping site at 5 %, a flow slide whose shear wave runs on about a minute after the
  shaking (the flow phase);
- ``ensemble``: ``twofluid ensemble elcentro-pga-sweep --workers 2`` (20 members on a local Dask
  cluster; the workers' CPU counted as the process's children).

The case files are written once from the new version's bundled cases (``twofluid show``), with the
edits above, and both versions run the same file (what either says on standard error, a warning or a
key it ignores, ``--check`` prints). ``PYTHONPATH`` is removed from the runs' environment, so that each
runs its environment's own package, not a developer's source tree; the header names the two. The CPU of a run is the user + system
time of the process and its children (``resource.getrusage(RUSAGE_CHILDREN)`` around it, as
``bench_peers.py`` does). After one warm-up of each, every round runs each work on both versions, the
order of the two swapped from one round to the next; the ratio of a round is base CPU / new CPU, and
the table gives the medians and the ratio's median and min–max, with the vertical steps of each
version's run (``summary.json``: the same work takes the same steps unless the results changed).

``--readme`` times, in the new environment, what the README and the build's aims quote: ``twofluid
build-kernels`` in a fresh kernel cache (CPU and wall), the default case's first run in a fresh cache
minus a warm run (the build it does itself), and the default case with its plots and with
``--no-plots``. The build per kernel group is ``NEW/bin/python benchmarks/bench_build.py --families``.
About 7 minutes for the comparison and 4 for ``--readme`` on the 2-core VM at load 3–4.

    python benchmarks/bench_versions.py --base /work/basevenv --new /path/to/venv --rounds 5
    python benchmarks/bench_versions.py --base B --new N --only bed layered --rounds 7
    python benchmarks/bench_versions.py --new N --readme --rounds 3
"""
from __future__ import annotations

import argparse
import datetime
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_peers import _case_file  # noqa: E402  (the TOML edits, one source)

#: work -> (what it is, bundled case or None for the ensemble, {(section, key): value} edits)
WORKS = {
    "bed": ("the default bed case (fluidized-bed-step)", "fluidized-bed-step", {}),
    "layered": ("the layered site (liquefaction-layered-site)", "liquefaction-layered-site", {}),
    "sloping": ("the sloping site (sloping-site, 3 %)", "sloping-site", {}),
    "chichi": ("the layered site under Chi-Chi CHY002, 86.9 s (layered-site-five-motions' member)",
               "liquefaction-layered-site",
               {("ground_motion", "file"): "RSN1180_CHICHI_CHY002-N.AT2", ("ground_motion", "pga_g"): 0.15,
                ("ground_motion", "magnitude"): 7.62, ("ground_motion", "duration"): 86.9,
                ("shear_wave", "base"): "compliant"}),
    "flow": ("the sloping site at 5 %: flow after the shaking", "sloping-site", {("site", "slope"): 5.0}),
    "ensemble": ("an ensemble: elcentro-pga-sweep, 20 members, 2 workers", None, {}),
}


def console(env: Path) -> str:
    return str(env / "bin" / "twofluid")


def command(env: Path, work: str, case_file: Path | None, out: Path, plots: bool = False) -> list[str]:
    """The user's command of ``work`` in environment ``env``, results in ``out``."""
    if work == "ensemble":
        return [console(env), "ensemble", "elcentro-pga-sweep", "--out", str(out), "--quiet", "--workers", "2"]
    return [console(env), "run", str(case_file), "--out", str(out), "--quiet"] + ([] if plots else ["--no-plots"])


def shown(env: Path, name: str) -> str:
    """The TOML of bundled case ``name`` as ``twofluid show`` of environment ``env`` prints it."""
    return subprocess.run([console(env), "show", name], capture_output=True, text=True, check=True,
                          env=installed_env()).stdout


def case_files(show, folder: Path, works) -> dict[str, Path]:
    """{work: its case file in ``folder``}: the bundled case's TOML (``show(name)``) with the work's
    edits (``WORKS``); none for the ensemble."""
    return {w: _case_file(show(WORKS[w][1]), folder / f"{w}.toml", WORKS[w][2]) for w in works if WORKS[w][1]}


def installed_env(**extra: str) -> dict:
    """This process's environment without ``PYTHONPATH`` (which would put another source tree's twofluid
    before the environment's own: a developer's shell sets it) and with ``extra``."""
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME")}
    return {**env, **extra}


def package_of(env: Path) -> str:
    """The folder of the twofluid that environment ``env``'s interpreter imports, as the timed runs do."""
    return subprocess.run([str(env / "bin" / "python"), "-c", "import twofluid, os; "
                           "print(os.path.dirname(twofluid.__file__))"], capture_output=True, text=True,
                          check=True, env=installed_env()).stdout.strip()


def timed(cmd: list[str], env: dict | None = None) -> tuple[float, float, str]:
    """(CPU [s] of ``cmd`` and its children, wall [s], standard error) run in ``env`` (default:
    :func:`installed_env`); fails if the command does."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    w0 = time.perf_counter()
    r = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                       env=installed_env() if env is None else env)
    wall = time.perf_counter() - w0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if r.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)} failed ({r.returncode}):\n{r.stderr[-2000:]}")
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime), wall, r.stderr


def steps_of(out: Path) -> str:
    try:
        return str(json.loads((out / "summary.json").read_text()).get("steps", "-"))
    except (OSError, ValueError):
        return "-"


def header(started: datetime.datetime, load0: float) -> str:
    try:
        from twofluid.verification.suite import machine

        where = machine()
    except Exception:  # noqa: BLE001  (the line is a courtesy)
        import platform

        where = f"{platform.processor() or platform.machine()}, {os.cpu_count()} logical CPUs"
    return (f"{started:%Y-%m-%d %H:%M} UTC; {where}; load average (1 min) {load0:.2f} before, "
            f"{os.getloadavg()[0]:.2f} after")


def compare(base: Path, new: Path, works: list[str], rounds: int, check: bool) -> int:
    for env in (base, new):
        timed([console(env), "build-kernels"])
    load0 = os.getloadavg()[0]
    started = datetime.datetime.now(datetime.timezone.utc)
    cpu = {w: {"base": [], "new": []} for w in works}
    steps = {w: {} for w in works}
    with tempfile.TemporaryDirectory(prefix="twofluid-versions-") as td:
        tmp = Path(td)
        files = case_files(lambda name: shown(new, name), tmp, works)
        for w in works:  # the warm-up, which also reads the steps and what each version says
            for label, env in (("base", base), ("new", new)):
                out = tmp / f"warm-{w}-{label}"
                _, _, err = timed(command(env, w, files.get(w), out))
                steps[w][label] = steps_of(out)
                if check and err.strip():
                    print(f"{w}, {label}: {err.strip()}", file=sys.stderr)
        for r in range(rounds):
            for w in works:
                order = (("base", base), ("new", new)) if r % 2 == 0 else (("new", new), ("base", base))
                for label, env in order:
                    c, _, _ = timed(command(env, w, files.get(w), tmp / f"out-{w}-{label}-{r}"))
                    cpu[w][label].append(c)
                print(f"round {r + 1} {w}: base {cpu[w]['base'][-1]:.2f} s, new {cpu[w]['new'][-1]:.2f} s, "
                      f"load {os.getloadavg()[0]:.2f}", file=sys.stderr, flush=True)
    print(header(started, load0) + f"; base {package_of(base)}, new {package_of(new)}; {rounds} alternated "
          "rounds after a warm-up")
    print("\n| work | base CPU [s], median (min–max) | new CPU [s], median (min–max) "
          "| base / new, median (min–max) | vertical steps, base / new |\n|---|---|---|---|---|")
    for w in works:
        b, n = cpu[w]["base"], cpu[w]["new"]
        ratio = sorted(x / y for x, y in zip(b, n))
        print(f"| {WORKS[w][0]} | {statistics.median(b):.2f} ({min(b):.2f}–{max(b):.2f}) | "
              f"{statistics.median(n):.2f} ({min(n):.2f}–{max(n):.2f}) | **{statistics.median(ratio):.2f}** "
              f"({ratio[0]:.2f}–{ratio[-1]:.2f}) | {steps[w].get('base', '-')} / {steps[w].get('new', '-')} |")
    return 0


def readme(new: Path, rounds: int) -> int:
    """The README's figures and the build's, in environment ``new``: medians of ``rounds``."""
    load0 = os.getloadavg()[0]
    started = datetime.datetime.now(datetime.timezone.utc)
    rows = {k: [] for k in ("build-kernels CPU", "build-kernels wall", "first run (no plots) CPU",
                            "warm run (no plots) CPU", "first run's build CPU", "default case with plots CPU",
                            "default case --no-plots CPU")}
    with tempfile.TemporaryDirectory(prefix="twofluid-readme-") as td:
        tmp = Path(td)
        case = case_files(lambda name: shown(new, name), tmp, ["bed"])["bed"]
        timed([console(new), "build-kernels"])
        timed(command(new, "bed", case, tmp / "warm"))
        for r in range(rounds):
            cache = tmp / f"cache-a{r}"
            env = installed_env(TWOFLUID_CACHE_DIR=str(cache), NUMBA_CACHE_DIR=str(cache / "numba"))
            c, w, _ = timed([console(new), "build-kernels"], env)
            rows["build-kernels CPU"].append(c)
            rows["build-kernels wall"].append(w)
            cache = tmp / f"cache-b{r}"
            env = installed_env(TWOFLUID_CACHE_DIR=str(cache), NUMBA_CACHE_DIR=str(cache / "numba"))
            first, _, _ = timed(command(new, "bed", case, tmp / f"first{r}"), env)
            warm, _, _ = timed(command(new, "bed", case, tmp / f"again{r}"), env)
            rows["first run (no plots) CPU"].append(first)
            rows["warm run (no plots) CPU"].append(warm)
            rows["first run's build CPU"].append(first - warm)
            print(f"round {r + 1}: build-kernels {c:.1f} s CPU, {w:.1f} s wall; first run {first:.2f}, warm {warm:.2f}"
                  f" s; load {os.getloadavg()[0]:.2f}", file=sys.stderr, flush=True)
        for r in range(max(rounds, 5)):  # the installed cache, warm: with and without the plots, alternated
            rows["default case with plots CPU"].append(timed(command(new, "bed", case, tmp / f"p{r}", plots=True))[0])
            rows["default case --no-plots CPU"].append(timed(command(new, "bed", case, tmp / f"n{r}"))[0])
    print(header(started, load0) + f"; {package_of(new)}")
    print("\n| what | median [s] (min–max) | runs |\n|---|---|---|")
    for k, v in rows.items():
        print(f"| {k} | {statistics.median(v):.2f} ({min(v):.2f}–{max(v):.2f}) | {len(v)} |")
    return 0


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--base", type=Path, help="the earlier version's virtual environment (pip install .)")
    p.add_argument("--new", type=Path, required=True, help="the new version's virtual environment")
    p.add_argument("--rounds", type=int, default=5, help="alternated rounds (default 5)")
    p.add_argument("--only", nargs="+", choices=list(WORKS), help="these works only (default: all)")
    p.add_argument("--check", action="store_true", help="print what each version says on standard error "
                   "in the warm-up (a key it does not know, a warning)")
    p.add_argument("--readme", action="store_true", help="the README's and the build's figures in --new instead")
    a = p.parse_args(argv)
    if a.readme:
        return readme(a.new.resolve(), a.rounds)
    if a.base is None:
        p.error("--base is needed (or --readme)")
    return compare(a.base.resolve(), a.new.resolve(), a.only or list(WORKS), a.rounds, a.check)


if __name__ == "__main__":
    sys.exit(main())
