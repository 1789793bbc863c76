"""The peer column side by side with OpenSees: surface PGA, Sa at 0.2/0.5/1.0 s, liquefied range,
settlement and peak strain (accuracy, not speed; `bench_peers.py` times the same two runs).

OpenSees: ``../shared/peers/opensees/column.py`` as shipped (PressureDependMultiYield02, u-p
elements, rigid base under the El Centro record as a within motion, k = 1e-4 m/s), run in this
process with one recorder added: the absolute acceleration of the surface node (the node's
relative acceleration plus the base record, ``-timeSeries``). twofluid: the same column as
``bench_peers.py`` builds it (the bundled ``liquefaction-elcentro`` deposit, 20 elements, 30 s of
shaking at 0.1 g, the hysteretic model), run to dissipation (max r_u < 0.01).

Both surface records are low-passed the same way (``geotech.filtering``: zero-phase 4th-order
Butterworth at 15 Hz) and their 5 %-damped spectra computed by ``geotech.spectra``. "Liquefied" is
r_u > 0.95 at an element's centre at any time.

    python benchmarks/compare_opensees.py [--pga 0.1] [--out DIR]

Needs openseespy (``pip install -e '.[bench]'``).
"""
from __future__ import annotations

import argparse
import importlib.util
import json
import shutil
import sys
import tempfile
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from bench_peers import MOTION, PEERS, column_case  # noqa: E402

G = 9.81


def _opensees(pga: float, work: Path) -> dict:
    spec = importlib.util.spec_from_file_location("peer_column", work / "column.py")
    peer = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(peer)
    ops = peer.ops
    original = ops.recorder
    acc_file = work / "out" / "_acc.out"

    def recorder(*args):  # the surface displacement recorder also gets an absolute acceleration one
        if "disp" in args and "-dof" in args:
            node = args[args.index("-node") + 1]
            original("Node", "-file", str(acc_file), "-time", "-timeSeries", 2, "-node", node, "-dof", 1, "accel")
        return original(*args)

    ops.recorder = recorder
    try:
        peer.main(["--perm", "1e-4", "--quiet", "--out", str(work / "out"), "--motion", str(MOTION),
                   "--pga", str(pga)])
    finally:
        ops.recorder = original
    acc = np.loadtxt(acc_file, ndmin=2)
    prof = np.genfromtxt(work / "out" / "profile.csv", delimiter=",", names=True)
    settle = np.loadtxt(work / "out" / "settlement.csv", delimiter=",", skiprows=1, ndmin=2)
    liq = prof["depth_m"][prof["ru_max"] > 0.95]
    t_liq = prof["t_first_ru_gt_095_s"] if "t_first_ru_gt_095_s" in prof.dtype.names else None
    return dict(t=acc[:, 0], a=acc[:, 1], liquefied=liq, settlement=float(settle[-1, 1]),
                first=None if t_liq is None else float(np.nanmin(t_liq)))


def _twofluid(pga: float, work: Path) -> dict:
    from twofluid.casefile.loader import load_case
    from twofluid.runners.common import run_case

    path = column_case(work / "column-20.toml", elements=20, shaking=30.0, end=180.0)
    case = load_case(str(path))
    case["ground_motion"]["pga_g"] = pga
    case["reconsolidation"]["dissipated_r_u"] = 0.01
    out = work / "tf"
    run_case(case, out_dir=out, plots=False)
    s = json.loads((out / "summary.json").read_text())
    m = np.loadtxt(out / "surface_motion.csv", delimiter=",", skiprows=1)
    rng = s["liquefied_depth_range_m"]
    return dict(t=m[:, 0], a=m[:, 1] / 9.80665 * G, range=rng, settlement=s["settlement_end_m"],
                first=s["first_liquefaction"]["time_s"] if s.get("first_liquefaction") else None,
                strain=max(la["peak_shear_strain"] for la in s["layers"]))


def _figures(t, a) -> dict:
    from twofluid.geotech.filtering import low_passed_peak, spectral_ordinates

    sa = spectral_ordinates(t, a, periods=(0.2, 0.5, 1.0))
    return dict(pga=float(np.max(np.abs(a)) / G), pga_lp=low_passed_peak(t, a) / G,
                sa=[sa[T] / G for T in (0.2, 0.5, 1.0)])


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--pga", type=float, default=0.1, help="input PGA [g] (default 0.1)")
    p.add_argument("--out", default=None, help="keep the two runs' files here")
    a = p.parse_args(argv)
    work = Path(a.out) if a.out else Path(tempfile.mkdtemp())
    work.mkdir(parents=True, exist_ok=True)
    shutil.copy(PEERS / "opensees" / "column.py", work / "column.py")
    o = _opensees(a.pga, work)
    f = _twofluid(a.pga, work)
    fo, ff = _figures(o["t"], o["a"]), _figures(f["t"], f["a"])
    liq_o = (f"{o['liquefied'].min() - 0.25:.2f}–{o['liquefied'].max() + 0.25:.2f} m"
             if o["liquefied"].size else "none")
    liq_f = f"{f['range'][0]:.2f}–{f['range'][1]:.2f} m" if f["range"] else "none"
    print(f"| at {a.pga:g} g | OpenSees PDMY02 | twofluid, hysteretic |")
    print("|---|---|---|")
    print(f"| surface PGA raw / low-passed [g] | {fo['pga']:.3f} / {fo['pga_lp']:.3f} | {ff['pga']:.3f} / {ff['pga_lp']:.3f} |")
    for T, so, sf in zip((0.2, 0.5, 1.0), fo["sa"], ff["sa"]):
        print(f"| Sa({T:g} s) [g] | {so:.3f} | {sf:.3f} |")
    print(f"| liquefied (r_u > 0.95) | {liq_o} | {liq_f} |")
    print(f"| first liquefaction | {o['first']:.2f} s | {f['first']:.2f} s |")
    print(f"| settlement | {100 * o['settlement']:.2f} cm | {100 * f['settlement']:.2f} cm |")
    print(f"| peak shear strain | — | {100 * f['strain']:.1f} % |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
