"""Command line: parses arguments and calls the library. Nothing else lives here."""
from __future__ import annotations

import argparse
import sys

__all__ = ["main"]


def _cmd_run(args) -> int:
    from .simulation import run_case

    res = run_case(args.case, args.out, progress=not args.quiet and sys.stderr.isatty())
    s = res.summary
    print(f"{s['case']}: {s['status']} at t = {s['stopped_at_s']:.6g} s after {s['steps']} steps "
          f"in {s['wall_time_s']:.1f} s; results in {res.out_dir}")
    if s["status"] != "completed":
        print(f"  {s['reason']}; everything written so far is in {res.out_dir}", file=sys.stderr)
        return 130 if s["status"] == "interrupted" else 1
    for key in ("t1_s", "bed_height_initial_m", "bed_height_final_m"):
        if s.get(key) is not None:
            print(f"  {key} = {s[key]:.6g}")
    print(f"  solids volume balance error = {s['solids_volume_balance_error']:.3g}")
    return 0


def _cmd_cases(args) -> int:
    from .casefile.loader import bundled_cases

    cases = bundled_cases()
    width = max(map(len, cases)) if cases else 0
    for name, desc in cases.items():
        print(f"{name:<{width}}  {desc}")
    return 0


def _cmd_show(args) -> int:
    from .casefile.loader import case_text

    sys.stdout.write(case_text(args.case))
    return 0


def parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="twofluid", description="Finite element model of saturated "
                                "granular material and liquid moving together (Pringle 2001).")
    from . import __version__

    p.add_argument("--version", action="version", version=f"twofluid {__version__}")
    sub = p.add_subparsers(dest="command", required=True)
    r = sub.add_parser("run", help="run a bundled case or a case file")
    r.add_argument("case", help="bundled case name (see `twofluid cases`) or path to a TOML file")
    r.add_argument("--out", help="output folder (default: twofluid-out/<case name>)")
    r.add_argument("--quiet", action="store_true", help="no progress bar")
    r.set_defaults(func=_cmd_run)
    c = sub.add_parser("cases", help="list the bundled cases")
    c.set_defaults(func=_cmd_cases)
    s = sub.add_parser("show", help="print a case's TOML (copy it to edit)")
    s.add_argument("case")
    s.set_defaults(func=_cmd_show)
    return p


def main(argv=None) -> int:
    from .casefile.schema import CaseError

    args = parser().parse_args(argv)
    try:
        return args.func(args)
    except CaseError as exc:
        print(f"twofluid: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("twofluid: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
