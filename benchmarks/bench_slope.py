"""A sloping liquefaction run against the same site on level ground (issue 22: at most 2×).

The bundled ``sloping-site`` (3 % slope) and the same case with ``[site] slope = 0``, each as a
whole process (``twofluid run --no-plots`` would print; here ``run_case`` in a child process),
alternated A B A B; CPU time = user + system of the child (``resource.getrusage``). Both runs
take the same vertical and shear steps until ``free_vibration`` after the shaking; the sloping
run's shear wave then runs on while it flows (``[shear_wave] flow_velocity``), and the
reconsolidation after it ends when the excess pore pressure has dissipated, which differs between
the two. ``--slope 5`` runs the site at 5 % instead, a flow slide (FS_post < 1) that flows for
about 40 s after the shaking: the costliest sloping run of this site.

    python benchmarks/bench_slope.py --rounds 5
    python benchmarks/bench_slope.py --rounds 5 --slope 5
"""
from __future__ import annotations

import argparse
import json
import resource
import statistics
import subprocess
import sys

CHILD = r"""
import json, sys
from twofluid.casefile.loader import load_case
from twofluid.runners.common import run_case
c = load_case("sloping-site")
c["output"]["plots"] = False
c["site"]["slope"] = float(sys.argv[1])
r = run_case(c)
print(json.dumps({"wall_loop_s": r.summary["wall_time_s"], "steps": r.summary["steps"],
                  "substeps": r.summary["shear_substeps"], "status": r.status}))
"""


def _one(slope: float) -> dict:
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    out = subprocess.run([sys.executable, "-c", CHILD, str(slope)], capture_output=True, text=True, check=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    row = json.loads(out.stdout.strip().splitlines()[-1])
    row["cpu_s"] = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return row


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--rounds", type=int, default=5)
    p.add_argument("--slope", type=float, default=3.0, help="the sloping run's slope [%%] (5: a flow slide, "
                   "FS_post < 1, that flows after the shaking)")
    args = p.parse_args(argv)
    sl = args.slope
    _one(sl)  # warm the kernels' cache
    rows = {sl: [], 0.0: []}
    for _ in range(args.rounds):
        for slope in (sl, 0.0):
            rows[slope].append(_one(slope))
    med = {s: {k: statistics.median(r[k] for r in rs) for k in ("cpu_s", "wall_loop_s", "steps", "substeps")}
           for s, rs in rows.items()}
    for s in (0.0, sl):
        m = med[s]
        print(f"slope {s:g} %: CPU {m['cpu_s']:.2f} s, time loop {m['wall_loop_s']:.2f} s, {m['steps']:.0f} "
              f"vertical steps, {m['substeps']:.0f} shear sub-steps")
    print(f"sloping / level: CPU {med[sl]['cpu_s'] / med[0.0]['cpu_s']:.2f}, time loop "
          f"{med[sl]['wall_loop_s'] / med[0.0]['wall_loop_s']:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
