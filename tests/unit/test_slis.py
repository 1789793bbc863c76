"""Tests of the Slis et al. (1959) table loader and its Kynch t1 (verification/slis.py).

Tolerances: table values exact (parsed independently with the csv module);
terminal velocity force balance to 1e-9 relative; Kynch t1 reproduced from the
closed-form expressions to 1e-12 relative.
"""

import csv
from importlib import resources

import numpy as np
import pytest

from twofluid.verification import kynch, slis


def _independent_rows():
    text = resources.files("twofluid").joinpath("data", "validation", slis.CSV_NAME).read_text()
    return list(csv.DictReader(line for line in text.splitlines() if not line.startswith("#")))


def test_table_has_twelve_typed_rows_matching_the_file():
    rows, ref = slis.load_slis_table(), _independent_rows()
    assert len(rows) == 12 == len(ref)
    for row, r in zip(rows, ref):
        assert isinstance(row, slis.SlisRow) and row.material == r["material"]
        assert row.d == pytest.approx(float(r["d_mm"]) / 1000, rel=1e-15)
        assert (row.rho_s, row.n0, row.n1) == (float(r["rho_s_kg_m3"]), float(r["n0"]), float(r["n1"]))
        assert (row.t1_exp, row.t1_thesis) == (float(r["t1_exp_s"]), float(r["t1_thesis_fea_s"]))
    assert sum(r.n1 > r.n0 for r in rows) == 6  # six expansions, six contractions


def test_provenance_note_ships_with_the_data():
    note = resources.files("twofluid").joinpath("data", "validation", "PROVENANCE.md").read_text()
    assert "Slis" in note and "table 5.2" in note


@pytest.mark.parametrize("bad,line,what", [
    ("I,3,1140,0.54,0.76,15", 3, "expected 7 fields"),
    ("I,3,1140,0.54,zero,15,13.8", 3, "non-numeric"),
    ("I,3,1140,1.54,0.76,15,13.8", 3, "porosity"),
])
def test_malformed_row_names_file_and_line(bad, line, what):
    lines = ["# comment", ",".join(slis.HEADER), bad]
    with pytest.raises(ValueError, match=rf"table\.csv, line {line}: {what}"):
        slis.parse_slis_csv(lines, source="table.csv")


def test_wrong_header_is_reported():
    with pytest.raises(ValueError, match="table.csv, line 1: expected header"):
        slis.parse_slis_csv(["material,d,rho"], source="table.csv")


@pytest.mark.parametrize("d", [3e-3, 4e-3, 5e-3, 5e-2])
def test_schiller_naumann_terminal_velocity_balances_weight(d):
    rho_s, rho_f, mu = 1140.0, slis.RHO_WATER, slis.MU_WATER
    U = slis.schiller_naumann_terminal_velocity(d, rho_s, rho_f, mu)
    Re = rho_f * U * d / mu
    cd = 24 / Re * (1 + 0.15 * Re**0.687) if Re < 1000 else 0.44
    drag = cd * 0.5 * rho_f * U**2 * np.pi * d**2 / 4
    weight = (rho_s - rho_f) * 9.81 * np.pi * d**3 / 6
    assert drag == pytest.approx(weight, rel=1e-9)


def test_terminal_velocity_tends_to_stokes_for_small_particles():
    u = slis.schiller_naumann_terminal_velocity(2e-6, 2650.0, 1000.0, 1e-3)
    assert u == pytest.approx(float(kynch.stokes_terminal_velocity(2e-6, 2650.0, 1000.0, 1e-3)), rel=1e-4)


def test_exponent_correlations_limits_and_monotone():
    assert float(slis.rowe_exponent(1e-8)) == pytest.approx(4.7, abs=1e-5)
    assert float(slis.khan_richardson_exponent(1e20)) == pytest.approx(2.4, abs=1e-3)
    # Rowe (1987): (4.7 - k)/(k - 2.35) = 0.175 Re^0.75
    k = float(slis.rowe_exponent(263.0))
    assert (4.7 - k) / (k - 2.35) == pytest.approx(0.175 * 263.0**0.75, rel=1e-12)


def test_kynch_t1_table_reproduces_closed_forms_and_scales_with_H0():
    table = slis.kynch_t1_table()
    assert len(table) == 12
    for r in table:
        w, H0 = r.row, slis.H0_THESIS
        H1 = H0 * (1 - w.n0) / (1 - w.n1)
        if w.n1 > w.n0:
            expected = H1 / (r.k * r.U_t * (1 - w.n1) * w.n1 ** (r.k - 1))
        else:
            expected = (H0 - H1) / (r.U_t * (w.n0**r.k - w.n1**r.k))
        assert r.t1_kynch == pytest.approx(expected, rel=1e-12)
        assert 2.3 < r.k < 2.8 and 200 < r.Re_t < 1000  # intermediate regime for 3-5 mm nylon
    doubled = slis.kynch_t1_table(H0=2 * slis.H0_THESIS)
    assert all(b.t1_kynch == pytest.approx(2 * a.t1_kynch, rel=1e-12) for a, b in zip(table, doubled))


def test_unknown_exponent_name_raises():
    with pytest.raises(ValueError, match="unknown exponent"):
        slis.kynch_t1_table(exponent="nope")


# --- the bed-height diagnostic of the table (slis_check.height_exponent, inventory_fits) ---------------

def _kynch_rows():
    """The twelve rows with Kynch's t1 of the bundled case's own law (no model runs)."""
    from twofluid.verification.slis_check import kynch_t1_same_law, slis_case

    out = []
    for r in slis.load_slis_table():
        case = slis_case(r)
        out.append({"n0": r.n0, "H0": case["initial"]["bed_height"], "t1_exp": r.t1_exp,
                    "t1_kynch": kynch_t1_same_law(case)})
    return out


@pytest.mark.parametrize("p_true", [0.0, 1.0, 2.5])
def test_height_exponent_recovers_a_power_law_and_its_noise(p_true):
    from twofluid.verification.slis_check import height_exponent

    n0 = np.linspace(0.5, 0.8, 7)
    rows = [{"n0": n, "t1_exp": 3.0 * (1 - n) ** -p_true, "t1_kynch": 1.5} for n in n0]
    p, se = height_exponent(rows)
    assert p == pytest.approx(p_true, abs=1e-10) and se < 1e-10
    wobble = np.array([1.1, 0.9, 1.1, 0.9, 1.1, 0.9, 1.1])  # ±10 % scatter: a non-zero standard error
    rows = [dict(r, t1_exp=r["t1_exp"] * w) for r, w in zip(rows, wobble)]
    p, se = height_exponent(rows)
    assert se > 0.05 and abs(p - p_true) < 3 * se


def test_height_exponent_leaves_out_unfinished_rows():
    from twofluid.verification.slis_check import height_exponent

    rows = [{"n0": n, "t1_exp": 1 / (1 - n), "t1_twofluid": 1.0} for n in (0.5, 0.6, 0.7)]
    rows.append({"n0": 0.75, "t1_exp": 99.0, "t1_twofluid": float("nan")})
    assert height_exponent(rows, "t1_twofluid")[0] == pytest.approx(1.0, abs=1e-12)


def test_inventory_fits_are_leave_one_out():
    from twofluid.verification.slis_check import inventory_fits

    # one amount of particles except row 0, whose t1 is doubled: the fit left without row 0 misses it by
    # exactly 1/2 − 1, and the other rows only through row 0's weight in their geometric means
    n0 = [0.5, 0.6, 0.7, 0.8]
    rows = [{"n0": n, "H0": 0.3, "t1_exp": 0.2 / (1 - n), "t1_kynch": 1.0} for n in n0]
    rows[0]["t1_exp"] *= 2.0
    f = inventory_fits(rows)
    assert f["charge"]["errors"][0] == pytest.approx(-0.5, rel=1e-12)
    assert f["charge"]["errors"][1] == pytest.approx(2.0 ** (1 / 3) - 1, rel=1e-12)
    assert f["Hs_fit"] == pytest.approx(0.3 * 0.2 * 2.0 ** 0.25, rel=1e-12)


def test_shipped_table_scales_with_the_amount_of_particles_not_a_fixed_height():
    """The measured t1 of Slis et al. against Kynch's with the case's law (docs/verification.md): the ratio
    grows as (1 − n0)^−p with p ≈ 1.1 ± 0.2; p = 0 (the thesis's one bed height) lies > 3 standard errors off."""
    from twofluid.verification.slis_check import height_exponent, inventory_fits

    rows = _kynch_rows()
    p, se = height_exponent(rows)
    assert abs(p - 1.0) < 2 * se and p > 3 * se
    f = inventory_fits(rows)
    assert f["charge"]["mean_abs"] < 0.6 * f["height"]["mean_abs"]


def test_inventory_table_reruns_rows_from_the_left_out_amount_of_particles():
    """Rows 4, 11 and 12: each runs from H_s/(1 − n0) on an element face, H_s fitted on the other two."""
    from twofluid.verification.slis_check import inventory_table, slis_markdown

    rows = [dict(r, row=i + 1) for i, r in enumerate(_kynch_rows()) if i in (3, 10, 11)]
    out = inventory_table(rows, workers=1)
    amount = [r["H0"] * r["t1_exp"] / r["t1_kynch"] * (1 - r["n0"]) for r in rows]
    for i, (r, o) in enumerate(zip(rows, out)):
        others = [a for j, a in enumerate(amount) if j != i]
        h = np.sqrt(others[0] * others[1]) / (1 - r["n0"])
        assert o["row"] == r["row"] and abs(o["H0"] - h) <= 0.005 + 1e-12  # nearest 1 cm face
        assert o["H0"] * 100 == pytest.approx(round(o["H0"] * 100), abs=1e-9)
        assert np.isfinite(o["t1_twofluid"]) and o["t1_kynch"] == pytest.approx(
            r["t1_kynch"] * o["H0"] / r["H0"], rel=1e-9)  # Kynch's t1 ∝ H0
    table = [dict(r, t1_twofluid=1.0, err_twofluid=0.0, t1_reach=1.0, err_kynch=0.0, t1_thesis=1.0,
                  err_thesis=0.0, material="x", d_mm=1.0, n1=0.5, note="") for r in rows]
    assert "twofluid rerun with that amount of particles" in slis_markdown(table, out)
    assert "twofluid rerun" not in slis_markdown(table)
