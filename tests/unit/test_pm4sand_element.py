"""The frozen OpenSees PM4Sand element tests (benchmarks/pm4sand_element_results.json).

The numbers were produced by benchmarks/pm4sand_element.py with a pinned openseespy; these tests
read them without OpenSees: the file's structure, its parameters against the script's (the manual's
G_o relation, Idriss & Boulanger's CRR), and the consistency of the calibration. Where openseespy
of the pinned version is importable, one short case (level ground at CSR = CRR to 3 %) is rerun and
must give the frozen N_3%.
"""
from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from repo_scripts import load_script

BENCH = Path(__file__).resolve().parents[2] / "benchmarks"
RESULTS = BENCH / "pm4sand_element_results.json"


def _script():
    return load_script("benchmarks/pm4sand_element.py")


@pytest.fixture(scope="module")
def frozen():
    return json.loads(RESULTS.read_text())


@pytest.fixture(scope="module")
def script():
    return _script()


def test_frozen_file_states_version_protocol_and_every_parameter(frozen, script):
    assert frozen["openseespy"] == script.OPENSEESPY_VERSION
    assert len(frozen["script_sha256_16"]) == 16 and int(frozen["script_sha256_16"], 16) >= 0
    assert frozen["sigma_v0_kPa"] == pytest.approx(101.3) and frozen["K0_target"] == 0.5
    assert frozen["secondary"] == pytest.approx(script.SECONDARY)
    for dr in script.DRS:
        p = frozen["primary"][str(dr)]
        assert p["n160"] == pytest.approx(46.0 * (dr / 100.0) ** 2, rel=1e-12)
        assert p["G_o"] == pytest.approx(167.0 * math.sqrt(p["n160"] + 2.5), rel=1e-12)
        assert p["crr15_ib"] == pytest.approx(script.crr15(dr), rel=1e-12)
        assert 0.02 < p["h_po"] < 10.0 and p["h_po"] == frozen["h_po"][str(dr)]


def test_frozen_cases_are_the_protocol_cases(frozen, script):
    cases = frozen["cases"]
    assert len(cases) == len(script.CASES)
    for row, (dr, alpha, csr) in zip(cases, script.CASES):
        assert row["dr_percent"] == dr and row["alpha"] == alpha
        want = script.crr15(dr) if csr == "crr" else csr
        assert row["csr"] == pytest.approx(want, rel=1e-12)
        assert row["stress_reversal"] == (alpha - row["csr"] < 0.0)
        pm = row["pm4sand"]
        assert pm["K0"] == pytest.approx(0.5, abs=1e-3)
        n = len(pm["gamma_end"])
        assert n >= 20 and len(pm["ru_max"]) == n and len(pm["gamma_peak"]) == n
        # the end-of-cycle strain is within the cycle's peak single-amplitude strain
        assert all(abs(g) <= p + 1e-12 for g, p in zip(pm["gamma_end"], pm["gamma_peak"]))
        if pm["n3"] is not None:
            k = int(pm["n3"])                   # cycle k+1 reaches 3 %
            assert pm["gamma_peak"][k] >= 0.03 and max(pm["gamma_peak"][:k], default=0.0) < 0.03
        else:
            assert max(pm["gamma_peak"]) < 0.03


def test_calibration_reaches_3_percent_at_15_cycles_at_the_crr(frozen, script):
    """h_po was set so that CSR = CRR15 reaches 3 % in 15 cycles; N_3% jumps by half cycles (the 3 %
    strain comes in one half cycle), so the boundary value sits within half a cycle of 15."""
    for row in frozen["cases"]:
        if row["alpha"] == 0.0:
            assert abs(row["pm4sand"]["n3"] - 15.0) <= 0.5
    for dr in script.DRS:
        c = frozen["crr_curve"][str(dr)]
        assert c["5"]["csr"] > c["15"]["csr"] > c["30"]["csr"]
        assert c["15"]["csr"] == pytest.approx(script.crr15(dr), rel=0.03)


def test_one_short_case_reproduces_the_frozen_number(frozen, script):
    try:
        ops = script.load_ops()
        version = script.openseespy_version()
    except Exception:                           # noqa: BLE001 - any import failure: no OpenSees here
        pytest.skip("openseespy is not importable")
    if version != frozen["openseespy"]:
        pytest.skip(f"openseespy {version} is not the pinned {frozen['openseespy']}")
    row = next(r for r in frozen["cases"] if r["dr_percent"] == 35 and r["alpha"] == 0.0)
    r = script.run(35, frozen["h_po"]["35"], 0.0, row["csr"], n_cycles=20.0, ops=ops)
    assert r["n3"] == pytest.approx(row["pm4sand"]["n3"], abs=0.01)
    k = min(10, len(r["gamma_end"]))
    assert r["gamma_end"][:k] == pytest.approx(row["pm4sand"]["gamma_end"][:k], rel=1e-6, abs=1e-9)


def test_frozen_columns_hold_the_reported_quantities():
    """benchmarks/pm4sand_column_results.json: each run has the surface displacement history, the
    residual and peak strain profiles, peak r_u, the liquefied range, surface Sa and the settlement;
    the history ends at the reported final displacement, and the profile spans the column."""
    res = json.loads((BENCH / "pm4sand_column_results.json").read_text())["runs"]
    assert set(res) >= {"sloping-site +1", "sloping-site -1", "liquefaction-layered-site +1"}
    for run in res.values():
        h = run["surface_displacement_history"]
        assert len(h["t_s"]) == len(h["u_m"]) > 100
        assert h["u_m"][-1] == pytest.approx(run["surface_displacement_end_m"], abs=1e-5)
        prof = run["profile"]
        assert prof[0]["depth_m"] < prof[-1]["depth_m"]
        assert all({"gamma_residual", "gamma_peak", "ru_max", "sigma_v0_kPa"} <= set(p) for p in prof)
        liq = [p["depth_m"] for p in prof if p["ru_max"] is not None and p["ru_max"] >= 0.95]
        if liq:
            lo, hi = run["liquefied_range_m"]
            assert lo < min(liq) and max(liq) < hi
        assert set(run["surface_sa_g"]) >= {"0.2", "0.5", "1"} and run["settlement_m"] > -0.01
    for key in ("sloping-site +1", "sloping-site -1"):
        assert res[key]["slope"] == pytest.approx(0.03)


def test_frozen_small_bias_cases_are_the_drift_grid_and_their_drifts_follow(frozen, script):
    """The small-bias cases (drift a cycle after N_3% against alpha): every Dr x CSR factor x alpha of
    the script's grid, each with its per-cycle strains; the drifts stored are the ones the script's
    own definition gives from them, and on level ground the cycles' mean strain does not drift
    (the end-of-cycle strain moves only as the loops widen)."""
    sb = frozen["small_bias"]
    assert sb["openseespy"] == script.OPENSEESPY_VERSION
    grid = {(dr, f, a) for dr in script.DRS for f in script.DRIFT_CSR_FACTORS for a in script.DRIFT_ALPHAS}
    assert {(c["dr_percent"], c["csr_over_crr15"], c["alpha"]) for c in sb["cases"]} == grid
    for c in sb["cases"]:
        pm = c["pm4sand"]
        assert c["csr"] == pytest.approx(c["csr_over_crr15"] * script.crr15(c["dr_percent"]), rel=1e-12)
        n = len(pm["gamma_end"])
        assert len(pm["gamma_max"]) == len(pm["gamma_min"]) == n >= 5
        assert all(lo <= g <= hi for g, hi, lo in zip(pm["gamma_end"], pm["gamma_max"], pm["gamma_min"]))
        assert pm["drift_per_cycle"] == script.drift_per_cycle(pm["gamma_end"], pm["n3"])
        mean = [0.5 * (a + b) for a, b in zip(pm["gamma_max"], pm["gamma_min"])]
        assert pm["mean_drift_per_cycle"] == script.drift_per_cycle(mean, pm["n3"])
        if c["alpha"] == 0.0 and pm["mean_drift_per_cycle"] is not None:
            assert abs(pm["mean_drift_per_cycle"]) < 1e-3
        elif pm["mean_drift_per_cycle"] is not None:
            assert pm["mean_drift_per_cycle"] > 0.0          # downslope


def test_drift_per_cycle_reads_between_cycle_ends(script):
    ends = [0.0, 0.01, 0.03, 0.06, 0.10, 0.15, 0.21]
    assert script.drift_per_cycle(ends, 1.0) == pytest.approx((0.15 - 0.01) / 4)
    assert script.drift_per_cycle(ends, 1.5) == pytest.approx((0.18 - 0.02) / 4)
    assert script.drift_per_cycle(ends, 3.0) is None and script.drift_per_cycle(ends, None) is None


@pytest.mark.parametrize("dr,factor,alpha", [(35, 1.3, 0.02), (55, 1.3, 0.05)])
def test_twofluid_beside_the_small_bias_cases_is_the_current_law(frozen, script, dr, factor, alpha):
    """The twofluid element stored beside each small-bias case (the script's ``twofluid_case``) is
    the hysteretic law as it is: rerun, it gives the frozen end-of-cycle strains, so the comparison
    of drifts in docs/liquefaction.md ("Strain after triggering") describes the current law."""
    row = next(c for c in frozen["small_bias"]["cases"]
               if c["dr_percent"] == dr and c["csr_over_crr15"] == factor and c["alpha"] == alpha)
    tf = script.twofluid_case(dr, alpha, row["csr"], script.DRIFT_CYCLES)
    assert tf["n3"] == row["twofluid"]["n3"]
    assert tf["gamma_end"] == pytest.approx(row["twofluid"]["gamma_end"], rel=1e-6, abs=1e-9)
