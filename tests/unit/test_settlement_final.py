"""A liquefaction run says whether its settlement is final, and gives the predicted final one beside it
(summary.json, layers.csv, elements.csv, an ensemble's members.csv and ensemble.json)."""
import csv

import pytest

from twofluid.casefile.loader import load_case
from twofluid.casefile.schema_liquefaction import DEFAULT_END_CAP_S
from twofluid.ensemble.engine import run_member
from twofluid.ensemble.results import figure_stats, settlement_notes, with_settlement_companions
from twofluid.runners.liquefaction import run_liquefaction


def _case(end=None):
    case = load_case("liquefaction-layered-site")
    case["output"]["plots"] = False
    if end is None:
        del case["time"]["end"]  # the schema's default: on to dissipation, capped
        case["output"]["times"] = [10.0]
    else:
        case["time"]["end"] = end
        case["output"]["times"] = [t for t in case["output"]["times"] if t <= end]
    return case


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    out = tmp_path_factory.mktemp("final")
    return {key: (run_liquefaction(_case(end), out_dir=out / key), out / key)
            for key, end in (("short", 100.0), ("default", None))}


def test_a_run_stopped_early_says_partial_beside_the_predicted_final(runs):
    res, out = runs["short"]
    s = res.summary
    assert s["settlement_final"] is False and s["end_cap_s"] == 100.0
    assert 0.0 < s["settlement_end_m"] < s["predicted_final_settlement_m"]
    assert s["settlement_fraction_reached"] == pytest.approx(s["settlement_end_m"] / s["predicted_final_settlement_m"])
    assert s["settlement_state"].startswith("partial:") and "100 s cap" in s["settlement_state"]
    layers = list(csv.DictReader(open(out / "layers.csv")))
    assert all(r["settlement_final"] == "no" for r in layers)
    total = sum(float(r["predicted_final_settlement_m"]) for r in layers)
    assert total == pytest.approx(s["predicted_final_settlement_m"], rel=1e-6)
    el = list(csv.DictReader(open(out / "elements.csv")))
    assert sum(float(r["settlement_contribution_final_m"]) for r in el) == pytest.approx(total, rel=1e-6)


def test_the_default_end_runs_to_dissipation_under_a_named_cap(runs):
    res, out = runs["default"]
    s = res.summary
    assert s["end_cap_s"] == DEFAULT_END_CAP_S and s["end_time_s"] == DEFAULT_END_CAP_S
    assert s["dissipation"]["dissipated"] and s["stopped_at_s"] < DEFAULT_END_CAP_S
    assert s["settlement_final"] is True and s["settlement_state"].startswith("final:")
    assert s["settlement_fraction_reached"] > 0.98
    # the partial run's prediction is the settlement the full run reaches
    assert runs["short"][0].summary["predicted_final_settlement_m"] == pytest.approx(s["settlement_end_m"], rel=0.03)


def test_ensemble_summary_counts_final_members_and_gives_the_predicted_final(tmp_path):
    collect = with_settlement_companions(["settlement_end_m"])
    rows = []
    for i, end in enumerate((100.0, 200.0)):
        res = run_member(_case(end), collect)
        rows.append({"member": i, "status": res["status"], **res["figures"]})
    st = figure_stats(rows, collect)["settlement_end_m"]
    assert st["members_final"] == 0 and st["final"].startswith("0 of 2 members final")
    assert st["predicted_final"]["count"] == 2 and st["predicted_final"]["min"] > st["max"]
    note = settlement_notes(rows, ["settlement_end_m"])  # the sensitivity study's table notes
    assert len(note) == 1 and note[0].startswith("settlement_end_m is partial in 2 of 2 runs")
