"""Ensembles on Dask: throughput of 1 vs 2 workers, scheduler overhead, the driver's memory.

Three measurements, each printed as a Markdown table (``--write FILE`` replaces the section
"## Ensembles on Dask" of FILE, or appends it):

1. ``throughput``: a 20-member liquefaction ensemble (liquefaction-elcentro, 8 s simulated:
   the first 6 s of El Centro and 2 s after, PGA 0.05 .. 0.24 g) on a LocalCluster of 1 and
   of 2 worker processes; members per minute and the ratio.
2. overhead (from the same runs): the ensemble's wall time × workers minus the members' own
   wall time (measured inside each member), per member and as a share of a member.
3. ``memory``: a 3000-member ensemble of short 1D runs (settling-illite, 0.1 s simulated,
   a grid of particle diameters) on 2 workers, with the driver's resident set size sampled
   every 0.25 s against the members finished (the LocalCluster's scheduler runs in the
   driver's process, so its memory is counted too).

    python benchmarks/bench_ensemble.py                    # all three
    python benchmarks/bench_ensemble.py --only memory --write docs/benchmarks.md
"""
from __future__ import annotations

import argparse
import os
import platform
import tempfile
import threading
import time
from pathlib import Path

import numpy as np
import psutil

import twofluid
from twofluid.ensemble import parse_ensemble

SECTION = "## Ensembles on Dask"


def liquefaction_spec(members: int = 20):
    pgas = [round(float(p), 4) for p in np.linspace(0.05, 0.24, members)]
    return parse_ensemble({
        "ensemble": {"name": "bench-liquefaction", "base": "liquefaction-elcentro",
                     "collect": ["settlement_end_m", "liquefied_thickness_m"]},
        "set": {"time.end": 8.0, "output.times": [6.0], "shear_wave.free_vibration": 2.0},
        "grid": {"ground_motion.pga_g": pgas}}, "<bench>")


def short_1d_spec(members: int = 3000):
    return parse_ensemble({
        "ensemble": {"name": "bench-1d", "base": "settling-illite", "collect": ["porosity_range"]},
        "set": {"time.end": 0.1, "output.times": [0.1], "output.probe_interval": 0.0},
        "grid": {"materials.particle_diameter": [float(d) for d in np.linspace(5e-5, 8e-5, members)]}},
        "<bench>")


def throughput() -> tuple[list[str], dict]:
    spec = liquefaction_spec()
    rows_out, res = [], {}
    for workers in (1, 2):
        load0 = os.getloadavg()[0]
        with tempfile.TemporaryDirectory() as out:
            t0 = time.perf_counter()
            rows = twofluid.run_ensemble(spec, out, workers=workers, plots=False)
            wall = time.perf_counter() - t0  # includes starting and closing the cluster
        ok = [r for r in rows if r["status"] == "completed"]
        inside = sum(r["wall_time_s"] for r in ok)
        res[workers] = {"wall": wall, "rate": 60 * len(ok) / wall, "member": inside / len(ok),
                        "cpu": sum(r["cpu_time_s"] for r in ok) / len(ok),
                        "overhead": (wall * workers - inside) / len(ok), "load": (load0, os.getloadavg()[0]),
                        "done": len(ok)}
    ratio = res[2]["rate"] / res[1]["rate"]
    rows_out += ["| workers | members completed | ensemble wall [s] | members per minute | mean member wall [s] "
                 "| mean member CPU [s] | overhead per member [s] | overhead / member | load avg before, after |",
                 "|---|---|---|---|---|---|---|---|---|"]
    for w, r in res.items():
        rows_out.append(f"| {w} | {r['done']} | {r['wall']:.1f} | {r['rate']:.1f} | {r['member']:.2f} | {r['cpu']:.2f} | "
                        f"{r['overhead']:.2f} | {100 * r['overhead'] / r['member']:.1f} % | "
                        f"{r['load'][0]:.2f}, {r['load'][1]:.2f} |")
    rows_out.append("")
    rows_out.append(f"Throughput ratio, 2 workers / 1 worker: **{ratio:.2f}×**.")
    return rows_out, res


def memory() -> tuple[list[str], dict]:
    spec = short_1d_spec()
    load0 = os.getloadavg()[0]
    proc = psutil.Process()
    samples, stop = [], threading.Event()
    with tempfile.TemporaryDirectory() as out:
        table = Path(out) / "members.csv"

        def sample():
            while not stop.is_set():
                try:
                    done = max(sum(1 for _ in open(table)) - 1, 0) if table.is_file() else 0
                except OSError:
                    done = 0
                samples.append((time.perf_counter(), done, proc.memory_info().rss / 2**20))
                stop.wait(0.25)

        th = threading.Thread(target=sample, daemon=True)
        t0 = time.perf_counter()
        th.start()
        rows = twofluid.run_ensemble(spec, out, workers=2, plots=False)
        stop.set()
        th.join()
        wall = time.perf_counter() - t0
    s = np.array(samples)
    done = s[:, 1]
    marks = []
    for frac in (0.01, 1 / 6, 1 / 3, 0.5, 2 / 3, 5 / 6, 1.0):
        i = int(np.argmax(done >= frac * len(rows))) if (done >= frac * len(rows)).any() else len(s) - 1
        marks.append((frac, int(done[i]), s[i, 2]))
    rss = [m[2] for m in marks]
    ok = [r for r in rows if r["status"] == "completed"]
    inside = sum(r["wall_time_s"] for r in ok)
    overhead = (wall * 2 - inside) / len(ok)
    lines = ["| members finished | driver RSS [MiB] |", "|---|---|"]
    lines += [f"| {n} ({100 * f:.0f} %) | {r:.1f} |" for f, n, r in marks]
    lines += ["", f"{len(rows)} members ({len(ok)} completed) in {wall:.0f} s on 2 workers (load average "
              f"{load0:.2f} before, {os.getloadavg()[0]:.2f} after); mean member wall {inside / len(ok) * 1e3:.0f} ms, "
              f"CPU {sum(r['cpu_time_s'] for r in ok) / len(ok) * 1e3:.0f} ms; time outside the members "
              f"(scheduling, transfer, the cluster's start and close) {overhead * 1e3:.0f} ms per member and worker. "
              f"Driver RSS from {rss[0]:.1f} MiB at 1 % to {rss[-1]:.1f} MiB at 100 % "
              f"(peak {s[:, 2].max():.1f} MiB); growth per member: "
              + ", ".join(f"{(b[2] - a[2]) / max(b[1] - a[1], 1) * 1024:.1f} KiB over members {a[1]}-{b[1]}"
                          for a, b in ((marks[1], marks[3]), (marks[3], marks[6]))) + "."]
    return lines, {"wall": wall, "marks": marks}


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--only", choices=("throughput", "memory"))
    p.add_argument("--write", help="Markdown file whose section '## Ensembles on Dask' is replaced (or appended)")
    args = p.parse_args(argv)
    text = [SECTION, "", f"Generated by `python benchmarks/bench_ensemble.py` on {time.strftime('%Y-%m-%d %H:%M')}. "
            f"Machine: {platform.processor() or platform.machine()}, {os.cpu_count()} logical CPUs, shared with "
            "other work (the load averages say how much).", ""]
    if args.only in (None, "throughput"):
        lines, _ = throughput()
        text += ["### Throughput and scheduler overhead: 20 liquefaction members (8 s simulated each)", "", *lines, ""]
    if args.only in (None, "memory"):
        lines, _ = memory()
        text += ["### Driver memory: 3000 short 1D members", "", *lines, ""]
    out = "\n".join(text)
    print(out)
    if args.write:
        path = Path(args.write)
        old = path.read_text(encoding="utf-8") if path.is_file() else ""
        if SECTION in old:
            head, _, rest = old.partition(SECTION)
            tail = rest[rest.find("\n## "):] if "\n## " in rest else ""
            old = head.rstrip() + "\n\n" + out + tail
        else:
            old = old.rstrip() + "\n\n" + out
        path.write_text(old, encoding="utf-8")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
