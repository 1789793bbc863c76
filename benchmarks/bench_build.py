"""The kernels' one-off build, group by group: the CPU of each group's build in a process of its
own and a fresh cache folder (``twofluid.compiled.GROUPS``), with numba's own compile events per
function (type inference and lowering of each export and of each helper it calls).

    python benchmarks/bench_build.py [GROUP ...] [--events] [--repeats] [--together]
    python benchmarks/bench_build.py --families [--repeats]

Prints, per group, the process's CPU [s] (user + system, children included: the C compiler and
linker), the CPU of importing numba, with ``--events`` the numba compile time of each
function (the helpers, which numba's JIT types; the exports are typed by ``numba.pycc`` and not
listed), and with ``--repeats`` every function compiled more than once in a process (another
argument type: layout, integer width, a literal) with its argument types. Each group gets an
empty cache folder, so nothing is shared between groups but numba's C helper objects that every
build of the first group compiles (the first group pays them).
``--together`` builds the groups named in one process and one cache folder instead, as a run's
first build or a worker of ``twofluid build-kernels`` does (helpers shared between groups then
compiled once), and prints each group's CPU in the order built (a helper counted with the first
group that calls it). ``--families`` builds each process's groups of ``twofluid build-kernels``
(``compiled.FAMILIES``) in their order there, one process and fresh cache folder per family: the
table per group of docs/benchmarks.md.
"""
from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time

CHILD = r'''
import json, os, sys, time, resource
def cpu():
    s, c = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return s.ru_utime + s.ru_stime + c.ru_utime + c.ru_stime
t0 = cpu()
import numba
from numba.core import event
t1 = cpu()
events = []
class Rec(event.Listener):
    def on_start(self, ev):
        ev.data["t0"] = time.process_time()
    def on_end(self, ev):
        d = ev.data
        f = getattr(d.get("dispatcher"), "py_func", None)
        name = f"{f.__module__}.{f.__qualname__}" if f is not None else str(d.get("dispatcher", ""))
        events.append((name[-80:], str(d.get("args", "")), time.process_time() - d.get("t0", time.process_time())))
rec = Rec()
event.register("numba:compile", rec)
from twofluid import compiled
pairs = list(zip(sys.argv[1::2], sys.argv[2::2]))
each = []
import contextlib
with getattr(compiled, "_young_gc_only", contextlib.nullcontext)():  # as build-kernels' processes
    for spec, name in pairs:
        t = cpu()
        compiled._build_group(spec)
        each.append((name, cpu() - t))
t2 = cpu()
outs = [compiled._LOADED.get(name) or {} for _spec, name in pairs]
aot = all(out and all(type(f).__name__ == "builtin_function_or_method" for f in out.values()) for out in outs)
print(json.dumps({"numba_import": t1 - t0, "build": t2 - t1, "aot": aot, "events": events, "each": each}))
'''


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("groups", nargs="*")
    p.add_argument("--events", action="store_true")
    p.add_argument("--together", action="store_true",
                   help="build the groups in one process and cache folder, as a run or a build-kernels worker does")
    p.add_argument("--repeats", action="store_true",
                   help="the functions numba compiled more than once in a process, with their argument types")
    p.add_argument("--families", action="store_true",
                   help="each of build-kernels' processes (compiled.FAMILIES), its groups in its order")
    args = p.parse_args(argv)
    from twofluid import compiled

    groups = [g for g in compiled.GROUPS if not args.groups or g[0] in args.groups]
    total = 0.0
    batches = [groups] if args.together else [[g] for g in groups]
    if args.families:
        specs = dict(compiled.GROUPS)
        batches = [[(n, specs[n]) for n in family] for family in compiled.FAMILIES]
    for batch in batches:
        name = "+".join(n for n, _ in batch)
        argv_groups = [a for n, spec in batch for a in (spec, n)]
        with tempfile.TemporaryDirectory(prefix="twofluid-bench-build-") as tmp:
            env = dict(os.environ, TWOFLUID_CACHE_DIR=tmp, TWOFLUID_BUILDING_KERNELS="1")
            before = resource.getrusage(resource.RUSAGE_CHILDREN)
            w0 = time.perf_counter()
            r = subprocess.run([sys.executable, "-c", CHILD, *argv_groups], env=env, capture_output=True, text=True)
            wall = time.perf_counter() - w0
            after = resource.getrusage(resource.RUSAGE_CHILDREN)
            cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
            if r.returncode != 0:
                print(f"{name}: failed\n{r.stderr[-2000:]}")
                continue
            d = json.loads(r.stdout.strip().splitlines()[-1])
            total += cpu
            print(f"{name:16s} process CPU {cpu:6.2f} s  wall {wall:6.2f} s  numba import {d['numba_import']:.2f} s"
                  f"  build {d['build']:.2f} s  {'ahead of time' if d['aot'] else 'JIT'}", flush=True)
            if len(batch) > 1:  # each group's CPU in the order built (the helpers it compiles first included)
                print("    " + ", ".join(f"{n} {t:.2f} s" for n, t in d["each"]))
            if args.events:
                for disp, sig, t in sorted(d["events"], key=lambda e: -e[2])[:25]:
                    print(f"    {t:6.2f} s  {disp} {sig[:60]}")
            if args.repeats:  # a function typed and compiled more than once in the process
                seen: dict = {}
                for disp, sig, t in d["events"]:
                    seen.setdefault(disp, []).append((sig, t))
                repeated = {k: v for k, v in seen.items() if len(v) > 1}
                print(f"    compiled more than once: {len(repeated)} of {len(seen)} functions")
                for disp, v in sorted(repeated.items(), key=lambda kv: -sum(t for _s, t in kv[1])):
                    print(f"    {sum(t for _s, t in v):6.2f} s  {disp}: {len(v)}x " + "; ".join(s[:120] for s, _t in v))
    print(f"all: {total:.2f} s of CPU; load {os.getloadavg()[0]:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
