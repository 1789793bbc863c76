"""The idealised set of gentle-slope lateral spreads: a protocol fixed before any run, its columns,
and the column against Youd, Hansen & Bartlett's (2002) median (docs/lateral-spreading.md,
"The idealised set").

The protocol (nothing here is tuned to a result):

- a crust to a 1.5 m water table at 18 kN/m³ (0.5 m elements);
- a layer of thickness T15 at (N1)60 = 8 with Idriss & Boulanger's (2008) fines correction,
  (N1)60cs = 8 + exp(1.63 + 9.7/(F15 + 0.01) − (15.7/(F15 + 0.01))²), Dr = √((N1)60cs/46),
  e = 0.79 − 0.41 (Dr − 0.361) (the bundled sloping site's loose and dense sands on one line),
  A = 4e-3, K2max = 30, 0.25 m elements;
- 5 m of dense sand at (N1)60cs 29 (Dr 79.4 %, A = 2e-3, K2max = 60, 0.5 m elements);
- a compliant base, V_s 760 m/s (2400 kg/m³);
- k from F15: 1e-4 m/s below 15 %, 1e-5 m/s above; D50_15 0.25 mm at F15 5 %, 0.1 mm at 30 %;
- the grid below: S 0.5–4 %, T15 1.5–10 m, M 6.4–7.7, R 1–30 km, F15 5 and 30 %, with two
  controls (small M, far: simplified FS > 1.3 expected) and two near-flow columns (FS_post
  1.1–1.3, checked on the built column before any run and printed);
- motion: the bundled records nearest and second nearest in (M, R) by
  d = √((ΔM/0.5)² + (log10(R/R_rec)/log10 2)²) (half a magnitude unit, a factor of 2 in distance)
  among those whose scale factor to the target is within 0.5–2, scaled to the median PGA of
  Boore, Stewart, Seyhan & Atkinson (2014) (pygmm, mechanism unspecified, region "california",
  R_JB = R_rup = R, V_s30 = 760 m/s); each whole record to its Arias t95, then the column's own
  flow criterion; both polarities;
- the column's displacement: the surface's downslope displacement at the end, the mean of the two
  polarities, then of the two records; the law as it is in the branch (no parameter touched).

Judged against Youd's median over the columns that are neither controls nor flow slides
(FS_post ≤ 1 reported apart): the geometric mean of column/Youd, the log10 standard deviation, the
fraction inside ×/÷ 2.5 and the count below ×0.2.

    python scripts/idealised_spreads.py --out runs/idealised            # every column, 4 runs each
    python scripts/idealised_spreads.py --columns 1,4 --records 1       # a subset: say which

Needs pygmm (the ``bench`` extra). Every run's summary goes to ``<out>/<column>-<record>-<p>.json``;
the table to ``<out>/table.md`` and ``<out>/runs.csv``.

    python scripts/idealised_spreads.py --columns 3,8,11 --records 1 --write-cases runs/cases

writes each picked run's resolved case file, ``<dir>/<column>-<record>-<p|m>.toml``, and runs
nothing: ``twofluid run FILE`` runs it, and ``benchmarks/pm4sand_column.py FILE`` runs the same
column, record, scale, duration and polarity in OpenSees PM4Sand.
"""
from __future__ import annotations

import argparse
import copy
import json
import math
import sys
import warnings
from pathlib import Path

import numpy as np

from twofluid.casefile.loader import load_case
from twofluid.io import ground_motion as gm

# the bundled input records: M_w, R_rup [km] (data/ground_motions/PROVENANCE.md)
RECORDS = {"RSN6_IMPVALL.I_I-ELC180-hor1.AT2": (6.95, 6.1), "RSN1120_KOBE_TAK000.AT2": (6.9, 1.5),
           "RSN779_LOMAP_LGP000.AT2": (6.93, 3.9), "RSN1180_CHICHI_CHY002-N.AT2": (7.62, 25.0),
           "RSN1762_HECTOR_ABY360.AT2": (7.13, 43.0)}
SCALE_RANGE = (0.5, 2.0)
CRUST_M, WATER_TABLE_M, DENSE_M = 1.5, 1.5, 5.0
N160 = 8.0
DENSE_N160CS = 29.0

# the grid: (name, S [%], T15 [m], M, R [km], F15 [%], role); fixed before any run
COLUMNS = [
    ("c01", 0.5, 3.0, 7.5, 10.0, 5.0, "spread"),
    ("c02", 0.5, 10.0, 7.2, 8.0, 5.0, "spread"),
    ("c03", 1.0, 1.5, 6.9, 5.0, 5.0, "spread"),
    ("c04", 1.0, 6.0, 7.5, 20.0, 30.0, "spread"),
    ("c05", 1.0, 10.0, 6.6, 2.0, 5.0, "spread"),
    ("c06", 2.0, 3.0, 6.6, 3.0, 5.0, "spread"),
    ("c07", 2.0, 10.0, 7.0, 15.0, 30.0, "spread"),
    ("c08", 3.0, 3.0, 7.0, 5.0, 30.0, "spread"),
    ("c09", 3.0, 6.0, 7.7, 25.0, 5.0, "spread"),
    ("c10", 4.0, 1.5, 6.9, 10.0, 30.0, "spread"),
    ("n11", 4.0, 6.0, 7.0, 8.0, 5.0, "near-flow"),
    ("n12", 4.0, 10.0, 7.2, 12.0, 5.0, "near-flow"),
    ("k13", 2.0, 3.0, 6.4, 30.0, 30.0, "control"),
    ("k14", 1.0, 6.0, 6.4, 30.0, 30.0, "control"),
]


def fines_corrected(n160: float, fines: float) -> float:
    """(N1)60cs = (N1)60 + Δ(N1)60 of Idriss & Boulanger (2008)."""
    f = fines + 0.01
    return n160 + math.exp(1.63 + 9.7 / f - (15.7 / f) ** 2)


def porosity(dr: float) -> float:
    e = 0.79 - 0.41 * (dr - 0.361)
    return e / (1.0 + e)


def bssa14_pga(m: float, r: float) -> float:
    import pygmm

    sc = pygmm.Scenario(mag=m, dist_jb=r, dist_rup=r, v_s30=760.0, mechanism="U", region="california")
    return float(pygmm.BooreStewartSeyhanAtkinson2014(sc).pga)


def arias_t95(name: str) -> float:
    rec = gm.load(gm.bundled_record(name))
    ia = np.cumsum(rec.acceleration ** 2)
    return math.ceil(10.0 * float(rec.time[np.searchsorted(ia / ia[-1], 0.95)])) / 10.0


def motions(m: float, r: float) -> list[tuple[str, float, float, float]]:
    """The two nearest records in (M, R) whose scale factor is within 0.5–2: (file, pga_g, factor, d)."""
    pga = bssa14_pga(m, r)
    out = []
    for name, (mr, rr) in RECORDS.items():
        own = gm.load(gm.bundled_record(name)).pga / gm.G_STANDARD
        d = math.hypot((m - mr) / 0.5, math.log10(r / rr) / math.log10(2.0))
        factor = pga / own
        if SCALE_RANGE[0] <= factor <= SCALE_RANGE[1]:
            out.append((name, pga, factor, d))
    return sorted(out, key=lambda x: x[3])[:2]


def column_case(s, t15, m, r, f15, record=None, pga=None, polarity=1) -> dict:
    c = load_case("sloping-site")
    c["output"]["plots"] = False
    c["site"]["slope"] = s
    c["site"]["water_table_depth"] = WATER_TABLE_M
    cs = fines_corrected(N160, f15)
    dr = math.sqrt(cs / 46.0)
    crust, loose, dense = (copy.deepcopy(x) for x in c["layers"])
    crust.update(thickness=CRUST_M, element_size=0.5, unit_weight=18000.0)
    loose.update(name="T15 layer", thickness=t15, element_size=0.25, n160cs=cs, relative_density=100.0 * dr,
                 porosity=porosity(dr), fines_content=f15, mean_grain_size=2.5e-4 if f15 < 15.0 else 1.0e-4,
                 hydraulic_conductivity=1e-4 if f15 < 15.0 else 1e-5)
    dd = math.sqrt(DENSE_N160CS / 46.0)
    dense.update(thickness=DENSE_M, n160cs=DENSE_N160CS, relative_density=100.0 * dd, porosity=porosity(dd),
                 hydraulic_conductivity=1e-4)
    c["layers"] = [crust, loose, dense]
    c["report"]["depths"] = [CRUST_M + 0.5 * t15]
    c["output"]["times"] = []
    g = c["ground_motion"]
    g.update(magnitude=m, distance_km=r, polarity=polarity)
    if record is not None:
        g.update(file=record, pga_g=round(pga, 4), duration=arias_t95(record))
    return c


def fs_post_min(c) -> float:
    """FS_post = S_r/τ_static, least over the T15 layer, of the built column (no run)."""
    from twofluid.closures import hysteretic as law
    from twofluid.runners.liquefaction import build_column

    b = build_column(c)
    col = b.column
    e = np.flatnonzero(b.site.layer_of == 1)
    tau = col.static_shear(col.n0)[e]
    return float((col.hysteretic[e, law.P_SR] / tau).min())


def simplified_fs_min(c) -> float:
    """The simplified procedure's least FS over the T15 layer at the input PGA (no run)."""
    from twofluid.runners.liquefaction import simplified_table

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = simplified_table(c)
    t15 = c["layers"][1]["thickness"]
    inside = (res.depth_mid_m > CRUST_M) & (res.depth_mid_m < CRUST_M + t15)
    return float(np.nanmin(np.where(np.isfinite(res.FS[inside]), res.FS[inside], np.inf)))


def run_name(name: str, record: str, polarity: int) -> str:
    """``<column>-<record's NGA label>-<p|m>``: the stem of a run's summary and of its case file."""
    return f"{name}-{record.split('_')[1]}-{'p' if polarity > 0 else 'm'}"


def _changes(doc: dict, ref: dict, new: dict) -> None:
    """Into ``doc`` (a case file's TOML document), every key whose value in ``new`` differs from ``ref``
    (both resolved, as ``effective`` gives them); tables and arrays of tables (layers) key by key."""
    for k, v in new.items():
        if isinstance(v, dict):
            sub = doc.get(k, {})
            _changes(sub, ref.get(k, {}), v)
            if sub:
                doc[k] = sub
        elif isinstance(v, list) and v and all(isinstance(x, dict) for x in v):
            old = ref.get(k, [])
            rows = doc.setdefault(k, [])
            for i, row in enumerate(v):
                if i == len(rows):
                    rows.append({})
                _changes(rows[i], old[i] if i < len(old) else {}, row)
        elif k not in ref or ref[k] != v:
            doc[k] = v


def case_document(c) -> dict:
    """The column's case as a case file: the bundled sloping site's own file with the keys the column
    changes, and without its ``[case] name`` (a written case runs under its file's name)."""
    import tomllib

    from twofluid.casefile.loader import case_text
    from twofluid.casefile.schema import effective
    from twofluid.runners.liquefaction import validated

    doc = tomllib.loads(case_text("sloping-site"))
    _changes(doc, effective(load_case("sloping-site")), effective(validated(c)))
    doc["case"].pop("name", None)
    g = c["ground_motion"]
    doc["case"]["description"] = (f"idealised gentle-slope column (scripts/idealised_spreads.py): S {c['site']['slope']:g} %, "
                                  f"T15 {c['layers'][1]['thickness']:g} m, F15 {c['layers'][1]['fines_content']:g} %, "
                                  f"M {g['magnitude']:g}, R {g['distance_km']:g} km; {g['file']} at {g['pga_g']:g} g "
                                  f"to t95 {g['duration']:g} s, polarity {g['polarity']:+d}")
    return doc


def write_case(c, path: Path) -> Path:
    """The column's case file (:func:`case_document`); ``twofluid run`` loads it to the same case."""
    import tomli_w

    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(tomli_w.dumps(case_document(c)))
    return path


def run_one(c, path: Path) -> dict:
    from twofluid.runners.common import run_case

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = run_case(c)
    s = r.summary
    sl = s["slope"]
    fs = [row["FS [-]"] for row in s["simplified_procedure"]["table_run"]
          if row["FS [-]"] is not None and CRUST_M < row["z_mid [m]"] < CRUST_M + c["layers"][1]["thickness"]]
    row = {"status": s["status"], "d_m": sl["surface_displacement_end_m"],
           "d_shaking_m": sl["surface_displacement_end_of_shaking_m"],
           "youd_m": sl["estimates"]["youd_2002"]["median_m"],
           "zhang_m": sl["estimates"]["zhang_2004_ib_gamma_max"]["displacement_m"],
           "newmark_m": sl["estimates"]["newmark"].get("displacement_m"),
           "newmark_flow": bool(sl["estimates"]["newmark"].get("flow_failure")),
           "fs_min": min(fs) if fs else None, "fs_post_min": min([la["FS_post_min"] for la in sl["layers"]] or [math.inf]),
           "liquefied_m": s["liquefied_thickness_m"], "flag": sl["beyond_measured_spreads"]["flag"],
           "wall_s": s["wall_time_s"]}
    path.write_text(json.dumps(row, indent=1))
    return row


def stats(ratios) -> dict:
    x = np.log10(np.asarray(ratios, dtype=float))
    return {"n": int(x.size), "geometric_mean": float(10.0 ** x.mean()) if x.size else None,
            "log10_sd": float(x.std(ddof=1)) if x.size > 1 else None,
            "inside_2.5": float(np.mean(np.abs(x) <= math.log10(2.5))) if x.size else None,
            "below_0.2": int(np.sum(x < math.log10(0.2)))}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=Path("runs/idealised"))
    ap.add_argument("--columns", default="", help="comma-separated 1-based column numbers (default: all)")
    ap.add_argument("--records", type=int, default=2, choices=(1, 2), help="records per column (nearest first)")
    ap.add_argument("--plan", action="store_true", help="print the columns, motions and FS_post; run nothing")
    ap.add_argument("--table-only", action="store_true", help="the table of the runs already in --out; run nothing")
    ap.add_argument("--write-cases", type=Path, default=None, metavar="DIR",
                    help="write each picked run's case file to DIR (<column>-<record>-<p|m>.toml); run nothing")
    a = ap.parse_args(argv)
    pick = [int(x) - 1 for x in a.columns.split(",") if x.strip()] or list(range(len(COLUMNS)))
    if not a.plan and a.write_cases is None:
        a.out.mkdir(parents=True, exist_ok=True)
    lines = ["| column | role | S [%] | T15 [m] | M | R [km] | F15 [%] | records (scale) | FS min | FS_post | "
             "liquefied [m] | column [m] (runs) | Youd [m] | column/Youd | Zhang I&B [m] | Newmark [m] |", "|" + "---|" * 16]
    ratios, rows_csv = [], []
    for i in pick:
        name, s, t15, m, r, f15, role = COLUMNS[i]
        mot = motions(m, r)[:a.records]
        fsp = fs_post_min(column_case(s, t15, m, r, f15))
        fs_in = simplified_fs_min(column_case(s, t15, m, r, f15, *mot[0][:2]))
        print(f"{name} {role}: S {s} T15 {t15} M {m} R {r} F15 {f15}; FS_post {fsp:.3f}; FS(input PGA) {fs_in:.2f}; "
              + "; ".join(f"{n.split('_')[1]} {p:.3f} g (x{f:.2f}, d {d:.2f})" for n, p, f, d in mot), flush=True)
        if a.write_cases is not None:
            for rec, pga, f, d in mot:
                for pol in (1, -1):
                    path = write_case(column_case(s, t15, m, r, f15, rec, pga, pol),
                                      a.write_cases / f"{run_name(name, rec, pol)}.toml")
                    print(f"  wrote {path}", flush=True)
        if a.plan or a.write_cases is not None:
            continue
        runs = []
        for rec, pga, f, d in mot:
            for pol in (1, -1):
                path = a.out / f"{run_name(name, rec, pol)}.json"
                if a.table_only and not path.exists():
                    continue
                row = json.loads(path.read_text()) if path.exists() else run_one(
                    column_case(s, t15, m, r, f15, rec, pga, pol), path)
                row.update(column=name, record=rec, polarity=pol)
                runs.append(row)
                rows_csv.append(row)
                print(f"  {rec.split('_')[1]} {pol:+d}: {row['d_m']:.4g} m ({row['status']}, {row['wall_s']:.0f} s)",
                      flush=True)
        if not runs:
            continue
        d_col = float(np.mean([x["d_m"] for x in runs]))
        youd = runs[0]["youd_m"]
        nm = [x["newmark_m"] for x in runs if x["newmark_m"] is not None]
        fs_min = min(x["fs_min"] for x in runs if x["fs_min"] is not None) if any(
            x["fs_min"] is not None for x in runs) else None
        flow = fsp <= 1.0
        ratio = d_col / youd if youd else None
        if role != "control" and not flow and ratio:
            ratios.append(ratio)
        liq = float(np.mean([x["liquefied_m"] for x in runs]))
        each = ", ".join(f"{x['d_m']:.3g}" for x in runs)
        nm_s = f"{np.mean(nm):.3g}" if nm else ("flow" if runs[0]["newmark_flow"] else "-")
        recs = ", ".join(f"{n.split('_')[1]} x{f:.2f}" for n, p, f, d in mot)
        lines.append(f"| {name} | {role}{' (flow slide)' if flow else ''} | {s:g} | {t15:g} | {m:g} | {r:g} | {f15:g} | "
                     f"{recs} | {fs_min if fs_min is None else f'{fs_min:.2f}'} | {fsp:.2f} | {liq:.3g} | {d_col:.3g} "
                     f"({each}) | "
                     f"{youd if youd is None else f'{youd:.3g}'} | {ratio if ratio is None else f'{ratio:.3g}'} | "
                     f"{runs[0]['zhang_m']:.3g} | {nm_s} |")
    if a.plan or a.write_cases is not None:
        return 0
    st = stats(ratios)
    lines += ["", "Against Youd's median (spreads and near-flow columns with FS_post > 1): " + json.dumps(st)]
    (a.out / "table.md").write_text("\n".join(lines) + "\n")
    (a.out / "runs.csv").write_text("\n".join([",".join(rows_csv[0])] + [",".join(str(v) for v in x.values())
                                                                        for x in rows_csv]) + "\n" if rows_csv else "")
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
