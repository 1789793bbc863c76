"""Command line: parses arguments and calls the library. Nothing else lives here."""
import os
import sys

from .command_signals import Signals as _Signals, internal_error as _internal_error, note_early

note_early()  # first: a Ctrl-C from here on is noted, not raised in the middle of an import

__all__ = ["main"]

# BLAS thread pools cost a run CPU and buy it nothing: the 1D systems are band matrices of a few
# hundred rows, and the 2D ones go to SuperLU, whose dense blocks are small. OpenBLAS's pool
# alone costs ~0.05 s of CPU at NumPy's import (spinning threads), a fifth of a short 1D run. So
# unless the user chose otherwise, the command line runs with one BLAS thread, as Dask's
# nanny does for its workers. Set before NumPy is imported (the library itself imports it).
_ONE_THREAD = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")


def _cmd_run(args) -> int:
    from .io.folders import default_out_dir
    from .runners import run_case

    _Signals.pending()  # a signal during the imports, swallowed there: the run does not start
    res = run_case(args.case, default_out_dir if args.out is None else args.out,
                   progress=False if args.quiet else (True if sys.stderr.isatty() else "lines"),
                   plots=False if args.no_plots else None)
    s = res.summary
    clock = "pseudo-time t" if s.get("stepping") == "pseudo_transient" and not s.get("stepping_fallback") \
        else "t"  # Δt grows to 1e4 s there; after a fallback to the transient the time is physical
    print(f"{s['case']}: {s['status']} at {clock} = {s['stopped_at_s']:.6g} s after {s['steps']} steps "
          f"in {s['wall_time_s']:.1f} s; results in {res.out_dir}")
    if s["status"] != "completed":
        print(f"  {s['reason']}; everything written so far is in {res.out_dir}", file=sys.stderr)
        if s["status"] == "interrupted":
            return _Signals.status(str(s.get("reason", "")))
        return 1
    if str(s.get("reason", "")).startswith(("steady", "dissipated", "stopped at the end time")):
        print(f"  {s['reason']}")  # why a completed run ended: steady state, dissipation, or its end time
    for key in ("t1_s", "bed_height_initial_m", "bed_height_final_m", "liquefied_thickness_m",
                "peak_r_u_top_element", "settlement_end_of_shaking_m", "settlement_end_m"):
        if s.get(key) is not None:
            print(f"  {key} = {s[key]:.6g}")
    _print_bed(s.get("bed"))
    if "first_liquefaction" in s:
        first = s["first_liquefaction"]
        print(f"  first liquefaction (r_u > 0.95) at t = {first['time_s']:.3g} s, depth {first['depth_m']:.3g} m"
              if first else "  no liquefaction (r_u > 0.95 nowhere)")
    boil = s.get("surface")
    if boil is not None:
        print("  surface: liquefied while shaking" if boil["surface_liquefied_while_shaking"] else
              "  surface: not liquefied while shaking; " + (
                  f"sand boil at {boil['start_s']:.3g} s for {boil['duration_s']:.3g} s, seepage up to "
                  f"{boil['peak_seepage_velocity_m_s']:.3g} m/s" if boil["sand_boil"] else "no sand boil"))
    simp = s.get("simplified_procedure")
    if simp is not None:
        for which in ("input", "run"):
            zone = simp[f"liquefied_depth_range_{which}_m"]
            print(f"  simplified procedure, a_max = {simp[f'a_max_{which}_g']:.3g} g ({which}): FS < 1 at "
                  + ("no depth" if zone is None else f"{zone[0]:.3g}-{zone[1]:.3g} m")
                  + f", settlement {simp[f'settlement_{which}_m']:.3g} m")
    if s.get("slope") is not None:  # a sloping site: the lateral displacement and the estimates
        from .runners.liquefaction_slope import slope_lines

        print("\n".join(slope_lines(s["slope"])))
    balance = s.get("solids_volume_balance_error")
    print(f"  solids volume balance error = {balance:.3g}" if balance is not None
          else "  solids volume balance error: not computed")
    return 0


def _print_bed(bed) -> None:
    """The bed figures of a 1D run's summary (summary.json "bed"), if it has them."""
    if not bed:
        return
    print(f"  bed at t = 0: porosity {bed['initial_porosity']:.4g}, height {bed['initial_height_m']:.4g} m")
    if "U_mf_m_s" in bed:
        print(f"  U_mf = {bed['U_mf_m_s']:.4g} m/s (at n_mf = {bed['packed_porosity_n_mf']:.3g}; Wen & Yu "
              f"{bed['U_mf_wen_yu_m_s']:.4g} m/s), U_t = {bed['U_t_m_s']:.4g} m/s")
    exp = bed.get("expanded")
    if exp:
        for name, label in (("model", "model equilibrium"), ("richardson_zaki", "Richardson-Zaki")):
            e = exp[name]
            h = "carried away" if e["height_m"] is None else f"height {e['height_m']:.4g} m"
            print(f"  bed at {exp['inlet_velocity_m_s']:.4g} m/s, {label}: porosity {e['porosity']:.4g}, {h}")


def _cmd_fluidization_curve(args) -> int:
    from .casefile.loader import load_case
    from .fluidization_curve import fluidization_curve, write_curve

    from .casefile.schema import CaseError
    from .io.folders import OutputFolder, check_out_dir, safe_name

    if not 2 <= args.points <= 10000:
        raise CaseError("fluidization-curve", "--points", f"{args.points} is outside the valid range [2, 10000]")
    case = load_case(args.case)  # every error of the case before anything is written
    out = check_out_dir(args.out if args.out is not None else
                        f"twofluid-out/{safe_name(case['case']['name'])}-fluidization-curve", "fluidization-curve --out")
    curve = fluidization_curve(case, points=args.points, exponent=args.rz_exponent)
    with OutputFolder(out):  # the run commands' folder rules: lock, the earlier curve's files only, no links
        paths = write_curve(curve, out, plot=not args.no_plots)
    f = curve["figures"]
    print(f"{curve['case']}: fluidization curve ({f['method']}): U_mf = {f['U_mf_m_s']:.4g} m/s at n_mf = "
          f"{f['packed_porosity_n_mf']:.3g}, U_t = {f['U_t_m_s']:.4g} m/s, buoyant weight per area "
          f"{f['buoyant_weight_per_area_Pa']:.4g} Pa")
    print("  U [mm/s]  state      porosity  height [m]  dP [Pa]   RZ porosity")
    rows = curve["rows"]
    for r in rows[:: max(1, len(rows) // 12)]:
        print(f"  {1e3 * r['U_m_s']:8.4g}  {r['state']:<9}  {r['porosity']:.4f}    {r['bed_height_m']:.4f}     "
              f"{r['bed_pressure_drop_Pa']:<8.5g}  {r['porosity_richardson_zaki']:.4f}")
    print(f"written: {', '.join(str(p) for p in paths)}")
    return 0


def _cmd_simplified(args) -> int:
    from .runners.liquefaction import simplified_table

    print(simplified_table(args.case, args.a_max).table())
    from .casefile.loader import load_case
    from .runners.liquefaction_report import dr_notes

    for line in dr_notes(load_case(args.case)):  # a Dr taken from n160cs/qc1ncs, not the entered one
        print(line)
    return 0


def _cmd_cases(args) -> int:
    from .casefile.loader import bundled_cases, case_readme

    cases = bundled_cases()
    width = max(map(len, cases)) if cases else 0
    readmes = [name for name in cases if case_readme(name)]
    for name, desc in cases.items():
        print(f"{name:<{width}}  {'R' if name in readmes else ' '}  {desc}")
    print("\nR: has a README (`twofluid show --readme NAME`); `twofluid show NAME > my.toml` copies a case")
    return 0


def _cmd_show(args) -> int:
    from .casefile.loader import case_readme, case_text, copyable

    if args.readme:
        text = case_readme(args.case)
        if text is None:
            from .casefile.schema import CaseError

            raise CaseError(args.case, "README.md", "this case has no README")
        sys.stdout.write(text)
        return 0
    sys.stdout.write(copyable(case_text(args.case)))
    return 0


def _cmd_verify(args) -> int:
    from .verification.slis_check import slis_markdown
    from .verification.suite import format_table, validation_summary, verify

    if args.out is not None and not args.no_write:  # before computing
        from .io.folders import check_out_file

        check_out_file(args.out, "verify --out")
    print("twofluid verify: running the checks ...", file=sys.stderr)
    tables: dict = {}
    rows, _ = verify(out=None if args.no_write else args.out, quick=args.quick, slis=not args.no_slis,
                     only=args.only, log=lambda m: print(m, file=sys.stderr), tables=tables)
    print(format_table(rows))
    if tables.get("slis") is not None:
        print("\nValidation: Slis, Willemse & Kramers (1959), thesis table 5.2 (errors relative to the "
              "experiment)\n")
        print(slis_markdown(tables["slis"], tables.get("slis_inventory")))
        print("\n" + validation_summary(tables["slis"]))
    if args.out and not args.no_write:
        print(f"report written to {args.out}", file=sys.stderr)
    return 0 if all(r["pass"] for r in rows) else 1


def _cmd_sensitivity(args) -> int:
    from .sensitivity import parse_change, sensitivity_study

    from .casefile.schema import CaseError

    by = args.by or ["10%"]
    if len(by) not in (1, len(args.vary)):
        raise CaseError("command line", "--by", f"give one change for all parameters or one per --vary "
                        f"parameter ({len(args.vary)}), not {len(by)}")
    _check_workers(args)
    changes = [parse_change(v, b) for v, b in zip(args.vary, by * len(args.vary) if len(by) == 1 else by)]
    if args.csv is not None:  # before computing
        from .io.folders import check_out_file

        check_out_file(args.csv, "sensitivity --csv")
    if args.out is not None:
        from .io.folders import check_out_dir

        check_out_dir(args.out, "sensitivity --out", own=False)
    res = sensitivity_study(args.case, changes, figure=args.figure, csv_path=args.csv, workers=args.workers,
                            scheduler=args.scheduler, out_dir=args.out, progress=sys.stderr.isatty())
    print(res.markdown())
    if args.csv:
        print(f"table written to {args.csv}", file=sys.stderr)
    return 0


def _check_workers(args) -> None:
    from .casefile.schema import CaseError

    if args.workers is not None and not 1 <= args.workers <= 1024:
        raise CaseError("command line", "--workers", f"{args.workers} is outside the valid range [1, 1024]")
    if args.scheduler is not None and not args.scheduler.strip():
        raise CaseError("command line", "--scheduler", "is empty; give the address a running scheduler prints")


def _cmd_ensemble(args) -> int:
    from .ensemble import load_ensemble, run_ensemble
    from .ensemble.engine import ensemble_out_dir
    from .io.folders import check_out_dir

    _check_workers(args)
    spec = load_ensemble(args.file)  # every error of the file before a cluster starts
    out = check_out_dir(ensemble_out_dir(spec) if args.out is None else args.out, "ensemble --out")
    try:
        rows = run_ensemble(spec, out, workers=args.workers, scheduler=args.scheduler,
                            progress=False if args.quiet else (True if sys.stderr.isatty() else "lines"))
    except KeyboardInterrupt as exc:
        rc = _Signals.status(exc=exc)
        print(f"twofluid: {'terminated (SIGTERM)' if rc == 143 else 'interrupted (Ctrl-C)'}; the finished "
              f"members are in {out}/members.csv (run the same command again to run the rest)", file=sys.stderr)
        return rc
    done = sum(r["status"] == "completed" for r in rows)
    print(f"{spec.name}: {done} of {len(rows)} members completed; results in {out}")
    for r in rows:
        if r["status"] != "completed":
            print(f"  member {r['member']} {r['status']}: {r['reason']}", file=sys.stderr)
    return 0 if done == len(rows) else 1


def _cmd_element_test(args) -> int:
    if args.model == "hysteretic":
        return _element_test_hysteretic(args)
    from .models.element_test import check_options, run_element_test

    if args.alpha is not None:
        from .casefile.schema import CaseError

        raise CaseError("element-test", "--alpha", "a static shear bias needs --model hysteretic")
    if args.csr_n_slope is not None:
        from .casefile.schema import CaseError

        raise CaseError("element-test", "--csr-n-slope", "a CSR-N slope needs --model hysteretic")
    check_options({"--csr": args.csr, "--gamma": args.gamma, "--sigma-v0": args.sigma_v0, "--dr": args.dr,
                   "--porosity": args.porosity, "--A": args.A, "--k2max": args.k2max,
                   "--gamma-ref": args.gamma_ref, "--max-cycles": args.max_cycles,
                   "--steps-per-cycle": args.steps_per_cycle})
    if args.out is not None:  # before computing
        from .io.folders import check_out_dir

        check_out_dir(args.out, "element-test --out")
    res = run_element_test(csr=args.csr, gamma_amplitude=args.gamma, sigma_v0=args.sigma_v0 * 1e3,
                           dr=args.dr, porosity=args.porosity, A=args.A, k2max=args.k2max,
                           gamma_ref=args.gamma_ref, drained=args.drained, law=args.law or "byrne",
                           max_cycles=args.max_cycles, steps_per_cycle=args.steps_per_cycle,
                           out_dir=args.out)
    load = (f"CSR = {res.settings['csr']:g}" if res.settings["csr"] is not None
            else f"gamma_a = {res.settings['gamma_amplitude']:g}")
    n_liq = float(res.cycles_to_liquefaction[0])
    kind = "drained" if args.drained else "undrained"
    if n_liq != float("inf"):
        print(f"{kind} cyclic simple shear, {load}, sigma'_v0 = {args.sigma_v0:g} kPa: "
              f"liquefied (r_u >= 0.95) after {n_liq:.2f} cycles")
    else:
        print(f"{kind} cyclic simple shear, {load}, sigma'_v0 = {args.sigma_v0:g} kPa: not liquefied "
              f"in {args.max_cycles:g} cycles (final r_u = {float(res.r_u[-1, 0]):.3f})")
    if args.out:
        print(f"results and plot written to {args.out}")
    return 0


def _element_test_hysteretic(args) -> int:
    from .models.element_test import check_options
    from .models.element_test_hysteretic import csr_n_curve, element_test

    from .casefile.schema import CaseError

    thesis_only = [opt for opt, given in (("--drained", args.drained), ("--porosity", args.porosity is not None),
                                          ("--A", args.A is not None), ("--gamma-ref", args.gamma_ref is not None),
                                          ("--law", args.law is not None)) if given]
    if thesis_only:
        raise CaseError("element-test", ", ".join(thesis_only), "acts on --model thesis only (the hysteretic model "
                        "is undrained and calibrated by --n160cs, --qc1ncs or --dr)")
    if args.out is not None and not args.curve:
        raise CaseError("element-test", "--out", "the hysteretic model writes files only with --curve (csr_n.csv, "
                        "csr_n.png); without it the test is printed")
    check_options({"--csr": args.csr, "--gamma": args.gamma, "--sigma-v0": args.sigma_v0, "--dr": args.dr,
                   "--k2max": args.k2max, "--max-cycles": args.max_cycles,
                   "--steps-per-cycle": args.steps_per_cycle})
    for opt, value, hi in (("--n160cs", args.n160cs, 46.0), ("--qc1ncs", args.qc1ncs, 250.0)):
        if value is not None and not 0.0 < value <= hi:
            from .casefile.schema import CaseError

            raise CaseError("element-test", opt, f"{value:g} is outside the valid range (0, {hi:g}]")
    if args.alpha is not None and not 0.0 <= args.alpha <= 0.35:
        from .casefile.schema import CaseError

        raise CaseError("element-test", "--alpha", f"{args.alpha:g} is outside the valid range [0, 0.35] "
                        "(the range of Idriss & Boulanger's K_alpha)")
    if args.csr_n_slope is not None:
        from .casefile.schema import CaseError
        from .geotech.correlations import CSR_N_SLOPE_RANGE

        lo, hi = CSR_N_SLOPE_RANGE
        if not lo <= args.csr_n_slope <= hi:
            raise CaseError("element-test", "--csr-n-slope", f"{args.csr_n_slope:g} is outside the valid range "
                            f"[{lo:g}, {hi:g}]")
    if args.out is not None:
        from .io.folders import check_out_dir

        check_out_dir(args.out, "element-test --out")
    soil = dict(n160cs=args.n160cs, qc1ncs=args.qc1ncs, dr=args.dr,
                k2max=30.0 if args.k2max is None else args.k2max)
    if args.alpha:
        soil["alpha"] = args.alpha
    if args.csr_n_slope is not None:
        soil["csr_n_slope"] = args.csr_n_slope
    sig = args.sigma_v0 * 1e3
    if args.curve:
        rows = csr_n_curve(sigma_v0=sig, **soil)
        print(f"CSR-N curve, hysteretic model, sigma'_v0 = {args.sigma_v0:g} kPa "
              "(liquefied: r_u >= 0.98 or gamma >= 3 %)")
        print("      CSR   N model   N correlation   CSR error")
        for r in rows:
            print(f"  {r['csr']:7.4f}  {r['cycles_model']:8.2f}  {r['cycles_correlation']:14.1f}  "
                  f"{100 * r['csr_error']:+9.1f} %")
        if args.out is not None:
            from pathlib import Path

            from .io.folders import OutputFolder, write_atomic
            from .io.results import write_json
            from .plots.element_test import plot_csr_n

            out = Path(args.out)
            with OutputFolder(out):  # the run commands' folder rules (io.folders)
                write_atomic(out / "csr_n.csv", "csr,cycles_model,cycles_correlation,csr_error\n" + "".join(
                    f"{r['csr']:.6g},{r['cycles_model']:.6g},{r['cycles_correlation']:.6g},{r['csr_error']:.6g}\n"
                    for r in rows))
                write_json(out / "summary.json", {"csr_n": rows, "sigma_v0_Pa": sig, "soil": soil})
                plot_csr_n(rows, out / "csr_n.png")
            print(f"results and plot written to {args.out}")
        return 0
    csr = args.csr if args.gamma is None and args.csr is not None else (0.12 if args.gamma is None else None)
    r = element_test(csr=csr, gamma_amplitude=args.gamma, sigma_v0=sig, max_cycles=int(args.max_cycles),
                     steps_per_cycle=args.steps_per_cycle, **soil)
    load = f"CSR = {csr:g}" if csr is not None else f"gamma_a = {args.gamma:g}"
    if r.cycles == r.cycles:
        extra = f" (correlation: {r.correlation_cycles:.2f})" if csr is not None else ""
        print(f"undrained cyclic simple shear, hysteretic model, {load}, sigma'_v0 = {args.sigma_v0:g} kPa: "
              f"liquefied (r_u >= 0.98 or gamma >= 3 %) after {r.cycles:.2f} cycles{extra}")
    else:
        print(f"undrained cyclic simple shear, hysteretic model, {load}, sigma'_v0 = {args.sigma_v0:g} kPa: "
              f"not liquefied in {args.max_cycles:g} cycles (final r_u = {float(r.r_u[-1]):.3f})")
    if args.alpha:
        from .models.element_test_hysteretic import model_crr

        base = {k: v for k, v in soil.items() if k != "alpha"}
        r0 = model_crr(sigma_v0=sig, steps_per_cycle=args.steps_per_cycle, **base)
        r1 = model_crr(sigma_v0=sig, steps_per_cycle=args.steps_per_cycle, **soil)
        k_a = r.crr / element_test(csr=0.1, sigma_v0=sig, max_cycles=1, **base).crr
        print(f"static shear alpha = {args.alpha:g} (cycles ride on tau_s; strain counted from the static "
              f"strain): model CRR(15 cycles) {r1:.4f} / {r0:.4f} = {r1 / r0:.4f}, K_alpha of Idriss & "
              f"Boulanger (2008) {k_a:.4f} ({100.0 * (r1 / r0 / k_a - 1.0):+.1f} %)")
    return 0


def _cmd_build_kernels(args) -> int:
    import time

    from . import compiled

    t0 = time.perf_counter()
    failed = compiled.build_all(args.workers)
    folder = compiled.cache_dir()
    print(f"twofluid: kernels in {folder} ({time.perf_counter() - t0:.0f} s)")
    if failed:
        print("twofluid: warning: not built ahead of time (numba's JIT is used, ~0.7 s per run): "
              + ", ".join(failed), file=sys.stderr)
    return 0


def _cluster_options(p) -> None:
    p.add_argument("--workers", type=int, help="worker processes of the local cluster (default: the CPU count)")
    p.add_argument("--scheduler", help="address of a running Dask scheduler, e.g. tcp://head:8786 "
                   "(instead of a local cluster)")


def parser():
    """The command line's argparse parser (argparse imported here: main's signal handlers come first)."""
    import argparse

    p = argparse.ArgumentParser(prog="twofluid", description="Finite element model of saturated "
                                "granular material and liquid moving together (Pringle 2001).")
    from . import __version__

    p.add_argument("--version", action="version", version=f"twofluid {__version__}")
    sub = p.add_subparsers(dest="command", required=True)
    r = sub.add_parser("run", help="run a bundled case or a case file")
    r.add_argument("case", help="bundled case name (see `twofluid cases`) or path to a TOML file")
    r.add_argument("--out", help="output folder (default: twofluid-out/<case name>)")
    r.add_argument("--quiet", action="store_true", help="no progress bar (or, when stderr is not a terminal, "
                   "no progress lines)")
    r.add_argument("--no-plots", action="store_true", help="write no PNG plots (overrides [output] plots)")
    r.set_defaults(func=_cmd_run)
    sp = sub.add_parser("simplified", help="the simplified liquefaction procedure (Idriss & Boulanger) on a "
                        "liquefaction_1d case's profile, per element, without running the column")
    sp.add_argument("case", help="bundled case name or TOML file (model liquefaction_1d)")
    sp.add_argument("--a-max", type=float, help="peak ground-surface acceleration [g] of the CSR "
                    "(default: the case's [ground_motion] pga_g)")
    sp.set_defaults(func=_cmd_simplified)
    fc = sub.add_parser("fluidization-curve", help="steady bed pressure drop, porosity and height against the "
                        "superficial velocity of a 1D bed (uniform equilibria of its drag law; defluidization branch)")
    fc.add_argument("case", help="bundled case name or TOML file (a 1D column with a bottom inlet)")
    fc.add_argument("--out", help="folder for fluidization_curve.csv and .png "
                    "(default: twofluid-out/<case name>-fluidization-curve)")
    fc.add_argument("--points", type=int, default=60, help="velocities on the curve (default 60)")
    fc.add_argument("--rz-exponent", choices=("khan_richardson", "richardson_zaki_1954"), default="khan_richardson",
                    help="k of the Richardson-Zaki comparison: Khan & Richardson (1989, default) or Richardson & Zaki "
                    "(1954) with the wall term d/D (D: a round column of the case's cross-section)")
    fc.add_argument("--no-plots", action="store_true", help="write the CSV only")
    fc.set_defaults(func=_cmd_fluidization_curve)
    c = sub.add_parser("cases", help="list the bundled cases")
    c.set_defaults(func=_cmd_cases)
    s = sub.add_parser("show", help="print a case's TOML (copy it to edit: `twofluid show NAME > my.toml` "
                       "runs as \"my\"), or its README")
    s.add_argument("case")
    s.add_argument("--readme", action="store_true", help="print the case's README.md instead")
    s.set_defaults(func=_cmd_show)
    v = sub.add_parser("verify", help="run the verification checks and the Slis validation table")
    v.add_argument("--out", help="also write the full report (tables, definitions, tolerances) to this "
                   "file, e.g. docs/verification.md (default: print the tables only, write nothing)")
    v.add_argument("--no-write", action="store_true", help="write nothing even with --out")
    v.add_argument("--quick", action="store_true", help="cheaper settings and a subset (as in the tests)")
    v.add_argument("--no-slis", action="store_true", help="skip the twelve Slis et al. runs")
    v.add_argument("--only", nargs="+", help="run only the checks whose name contains one of these words")
    v.set_defaults(func=_cmd_verify)
    se = sub.add_parser("sensitivity", help="change parameters by a fraction and report figures "
                        "(any model; members run in parallel on Dask)")
    se.add_argument("case", help="bundled case name or TOML file")
    se.add_argument("--vary", nargs="+", required=True,
                    help="parameters as section.key, e.g. materials.particle_diameter (short: particle.diameter)")
    se.add_argument("--by", nargs="+", help="relative change per parameter (one for all), e.g. 10%% or 0.05; "
                    "write a negative change as --by=-5%%")
    se.add_argument("--figure", nargs="+", help="figures: t1 (step_change), porosity_error@T (T in s, or @end) "
                    "or dotted paths into summary.json (default from the model)")
    se.add_argument("--csv", help="also write the table as CSV")
    se.add_argument("--out", help="keep the members' table here (a rerun reuses completed members)")
    _cluster_options(se)
    se.set_defaults(func=_cmd_sensitivity)
    en = sub.add_parser("ensemble", help="run an ensemble file (grid, zipped lists, samples, ground-motion "
                        "suites, PGA sweeps) on Dask; see docs/ensembles.md")
    en.add_argument("file", help="ensemble TOML file (or a bundled example: elcentro-pga-sweep, "
                    "layered-site-five-motions, sloping-site-five-motions)")
    en.add_argument("--out", help="results folder (default: twofluid-out/<ensemble name>); a rerun into the "
                    "same folder skips completed members")
    en.add_argument("--quiet", action="store_true", help="no progress bar (or, when stderr is not a terminal, no "
                    "progress line every 30 s)")
    _cluster_options(en)
    en.set_defaults(func=_cmd_ensemble)
    et = sub.add_parser("element-test", help="undrained cyclic simple shear of one element: cycles to "
                        "liquefaction (defaults: the calibrated loose sand at CSR 0.12, 100 kPa)")
    load = et.add_mutually_exclusive_group()
    load.add_argument("--csr", type=float, help="cyclic stress ratio tau/sigma'_v0 (stress control; default 0.12)")
    load.add_argument("--gamma", type=float, help="shear-strain amplitude, e.g. 1e-3 (strain control)")
    et.add_argument("--sigma-v0", type=float, default=100.0, help="vertical effective stress [kPa] (default 100)")
    et.add_argument("--dr", type=float, help="relative density [%%] (default 47)")
    et.add_argument("--porosity", type=float, help="porosity [-] (default 0.44)")
    et.add_argument("--A", type=float, help="compressibility of P_s [-] (default 6e-4)")
    et.add_argument("--k2max", type=float, help="Seed-Idriss K2max [-] (default 30)")
    et.add_argument("--gamma-ref", type=float, help="reference strain of G/G_max [-] (default 1e-3)")
    et.add_argument("--law", choices=("byrne", "ann"), help="thesis: reference-porosity law (default byrne)")
    et.add_argument("--model", default="thesis", choices=("thesis", "hysteretic"),
                    help="shear law: thesis (backbone and densification law) or hysteretic (calibrated to "
                    "the CRR curve of (N1)60cs)")
    et.add_argument("--n160cs", type=float, help="hysteretic: (N1)60cs (default from --dr)")
    et.add_argument("--qc1ncs", type=float, help="hysteretic: q_c1Ncs, the CPT route")
    et.add_argument("--alpha", type=float, help="hysteretic: static shear stress ratio tau_s/sigma'_v0 "
                    "in [0, 0.35] the cycles ride on (a slope's); prints the model's CRR ratio beside K_alpha")
    et.add_argument("--csr-n-slope", type=float, help="hysteretic: slope b of CSR ~ N^-b from the soil's own "
                    "cyclic tests, in [0.05, 0.6] (default: the b the magnitude scaling factor implies)")
    et.add_argument("--curve", action="store_true", help="hysteretic: the CSR-N curve against the "
                    "correlation (printed; csr_n.csv and csr_n.png with --out)")
    et.add_argument("--drained", action="store_true", help="drained test (P_s held, n follows n-bar)")
    et.add_argument("--max-cycles", type=float, default=50.0, help="length of the test [cycles] "
                    "(default 50; the test stops earlier once liquefied)")
    et.add_argument("--steps-per-cycle", type=int, default=100, help="time steps per loading cycle "
                    "(default 100)")
    et.add_argument("--out", help="folder for element_test.csv, summary.json and element_test.png")
    et.set_defaults(func=_cmd_element_test)
    bk = sub.add_parser("build-kernels", help="compile the numerical kernels once for this installation "
                        "(otherwise the first runs do it; ~1 min of CPU)")
    bk.add_argument("--workers", type=int, help="build processes at a time (default: the CPU count)")
    bk.set_defaults(func=_cmd_build_kernels)
    return p


def _show_case_warning(message, category, filename, lineno, file=None, line=None):
    print(f"twofluid: warning: {message}", file=sys.stderr)


def one_blas_thread() -> None:
    """One BLAS thread unless the user chose otherwise (``_ONE_THREAD``); before NumPy is imported
    (in a process that has NumPy already it would not take effect)."""
    if "numpy" not in sys.modules:
        for var in _ONE_THREAD:
            os.environ.setdefault(var, "1")


def main(argv=None) -> int:
    """The command line. ``argv``: the arguments (called from Python: returns the exit status, the
    caller's signal handlers restored; a usage error raises argparse's ``SystemExit``); None:
    ``sys.argv``, the command itself, which ends the process with the status (skipping the
    interpreter's shutdown, where a signal would kill it). Exit status: 0 (also ``--help``,
    ``--version``), 1 (a run failed, a file could not be written, an internal error: one line naming
    it and the log its traceback went to), 2 (bad input, a usage error), 130 (SIGINT), 143 (SIGTERM)."""
    old = _Signals.install()
    rc = 130
    try:
        try:
            _Signals.pending()  # a signal noted before main began
            rc = _main(argv)
            _Signals.pending()  # a signal swallowed on the way still ends the command as interrupted
        except SystemExit as exc:  # argparse: --help and --version (0), a usage error (2, its message printed)
            if argv is not None:
                raise
            rc = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
        except KeyboardInterrupt as exc:
            if argv is None:
                _Signals.late()  # a second signal while saying so ends it at once, with the same status
            rc = _Signals.status(exc=exc)
            print("twofluid: terminated (SIGTERM)" if rc == 143 else "twofluid: interrupted", file=sys.stderr)
        return rc
    finally:
        if argv is None:  # the command: a signal from here to the exit ends it with the signal's status
            _Signals.late()
            _Signals.leave(rc)
        else:  # called from Python: its handlers back
            _Signals.restore(old)


def _main(argv=None) -> int:
    import warnings

    from .casefile.schema import CaseError, CaseWarning

    one_blas_thread()
    if argv is None:  # the command's own process: matplotlib imported lean when a figure is drawn
        from .plots import command_process

        command_process()
    args = parser().parse_args(argv)
    default_show = warnings.showwarning
    warnings.showwarning = lambda m, c, *a, **k: (_show_case_warning(m, c, *a, **k) if issubclass(c, CaseWarning)
                                                  else default_show(m, c, *a, **k))
    try:
        return args.func(args)
    except CaseError as exc:
        print(f"twofluid: error: {exc}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # the reader of the output has gone (`twofluid cases | head`): nothing to say
        try:
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        except (OSError, ValueError):
            pass
        return 141
    except OSError as exc:  # a file that could be checked but not written (disk full, removed meanwhile)
        where = f"{exc.filename}: " if getattr(exc, "filename", None) else ""
        print(f"twofluid: error: {where}{exc.strerror or exc}", file=sys.stderr)
        return 1
    except Exception as exc:  # noqa: BLE001 - a defect of twofluid: one line, the traceback in a log file
        return _internal_error(exc)
    finally:
        warnings.showwarning = default_show


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
