"""The simplified procedure over a layered profile (crust, loose sand, dense sand).

Profile (also the worked example of docs/simplified.md): water table at 2 m, crust
0–2 m (18 kN/m³, not liquefiable), loose sand 2–6 m (Dr 45 %, 19 kN/m³), dense sand
6–10 m (Dr 80 %, 20 kN/m³), γ_w = 9.81 kN/m³; rows of 2 m; a_max = 0.25 g, M_w = 6.95.

Hand row 2 (z = 2–4 m, mid 3 m): σ_v = 2·18 + 1·19 = 55 kPa, u = 9.81 kPa,
σ′_v = 45.19 kPa; FS = 0.65330 (every factor by hand in test_geotech_simplified.py).
FS = 0.6533 < F_α = 0.032 + 4.7·0.45 − 6·0.45² = 0.932, so γ_max = γ_lim =
1.859·0.65³ = 0.51053, capped at 0.08: ε_v = 1.5·exp(−1.125)·0.08 = 1.5·0.32465·0.08
= 0.038958, settlement 2 m × 0.038958 = 0.077917 m.
"""
import numpy as np
import pytest

from twofluid.casefile.schema import CaseError
from twofluid.geotech import simplified_procedure

Z_TOP = np.array([0.0, 2.0, 4.0, 6.0, 8.0])
Z_BOT = Z_TOP + 2.0
S_V = np.array([18.0, 55.0, 93.0, 132.0, 172.0]) * 1e3
U = np.array([0.0, 9.81, 29.43, 49.05, 68.67]) * 1e3
DR = np.array([45.0, 45.0, 45.0, 80.0, 80.0])  # per cent, as the API takes it
LIQ = np.array([False, True, True, True, True])


def run(**kw):
    args = dict(z_top_m=Z_TOP, z_bottom_m=Z_BOT, sigma_v_Pa=S_V, sigma_v_eff_Pa=S_V - U,
                relative_density=DR, liquefiable=LIQ, a_max_g=0.25, magnitude=6.95)
    args.update(kw)
    return simplified_procedure(**args)


def test_hand_row_and_totals():
    r = run()
    assert r.depth_mid_m.tolist() == [1.0, 3.0, 5.0, 7.0, 9.0]
    assert r.FS[1] == pytest.approx(0.65330, rel=1e-4)
    assert r.eps_v[1] == pytest.approx(0.038958, rel=1e-4)
    assert r.settlement_m[1] == pytest.approx(0.077917, rel=1e-4)
    # crust above the water table cannot liquefy; the dense sand has FS > 2: no strain
    assert np.isinf(r.FS[0]) and r.eps_v[0] == 0.0 and not r.can_liquefy[0]
    assert np.all(r.FS[3:] > 2.0) and np.all(r.eps_v[3:] == 0.0)
    assert r.total_settlement_m == pytest.approx(float(np.sum(r.eps_v * 2.0)), rel=1e-15)
    for name in ("r_d", "CSR", "CRR_75", "MSF", "K_sigma", "eps_v", "settlement_m"):
        assert np.all(np.isfinite(getattr(r, name))), name
    assert not np.any(np.isnan(r.FS))


def test_unsaturated_rows_cannot_liquefy():
    """A liquefiable row with σ′_v = σ_v (above the water table) gets FS = inf, ε_v = 0."""
    r = run(liquefiable=True, sigma_v_eff_Pa=S_V)
    assert np.all(np.isinf(r.FS)) and r.total_settlement_m == 0.0


def test_fs_falls_with_a_max_and_rises_with_density():
    fs = np.array([run(a_max_g=a).FS[1:] for a in (0.1, 0.2, 0.3, 0.4)])
    assert np.all(np.diff(fs, axis=0) < 0.0)
    fs_dr = np.array([run(relative_density=d).FS[1:] for d in (30.0, 50.0, 70.0, 90.0)])
    assert np.all(np.diff(fs_dr, axis=0) > 0.0)
    s = [run(a_max_g=a).total_settlement_m for a in (0.1, 0.2, 0.3, 0.4)]
    assert np.all(np.diff(s) >= 0.0) and s[-1] > s[0]


def test_zero_shaking_is_safe_not_nan():
    r = run(a_max_g=0.0)
    assert np.all(np.isinf(r.FS)) and r.total_settlement_m == 0.0


def test_msf_forms():
    """At M = 7.5 both MSF forms are 1 (to the 4 digits of their constants)."""
    a, b = run(magnitude=7.5), run(magnitude=7.5, msf_form="ib2008")
    np.testing.assert_allclose(a.FS[1:], b.FS[1:], rtol=1e-3)
    assert run(msf_form="ib2008").MSF[1] == pytest.approx(6.9 * np.exp(-6.95 / 4) - 0.058)


def test_table_and_rows():
    r = run()
    rows = r.to_rows()
    assert len(rows) == 5 and rows[1]["FS [-]"] == pytest.approx(0.65330, rel=1e-4)
    assert rows[1]["settlement [mm]"] == pytest.approx(77.917, rel=1e-4)
    assert rows[1]["sigma'_v [kPa]"] == pytest.approx(45.19)
    text = r.table()
    assert "z_mid [m]" in text and "total settlement 155.8 mm" in text
    assert "nan" not in text.lower()


@pytest.mark.parametrize("kw, key", [
    (dict(z_top_m=[]), "z_top_m"),
    (dict(z_top_m=Z_TOP - 1.0, z_bottom_m=Z_BOT - 1.0), "z_top_m"),
    (dict(z_bottom_m=Z_TOP), "z_bottom_m"),
    (dict(z_bottom_m=Z_BOT[:3]), "z_bottom_m"),
    (dict(sigma_v_Pa=-S_V), "sigma_v_Pa"),
    (dict(sigma_v_eff_Pa=np.where(LIQ, S_V - U, 0.0)), "sigma_v_eff_Pa"),
    (dict(sigma_v_eff_Pa=np.full(5, np.nan)), "sigma_v_eff_Pa"),
    (dict(sigma_v_Pa=S_V * 100, sigma_v_eff_Pa=(S_V - U) * 100), "sigma_v_eff_Pa"),
    (dict(relative_density=DR * 100), "relative_density"),
    (dict(relative_density=DR / 100), "relative_density"),
    (dict(liquefiable=[1, 1, 1, 1, 1]), "liquefiable"),
    (dict(a_max_g=-0.1), "a_max_g"),
    (dict(a_max_g="big"), "a_max_g"),
    (dict(magnitude=4.0), "magnitude"),
    (dict(msf_form="youd2001"), "msf_form"),
])
def test_bad_arguments_name_the_argument(kw, key):
    with pytest.raises(CaseError) as err:
        run(**kw)
    msg = str(err.value)
    assert f": {key}:" in msg and "\n" not in msg


def test_a_fraction_given_for_per_cent_is_refused_with_what_it_meant():
    with pytest.raises(CaseError, match=r"relative_density: 0.45 is <= 1: Dr is in per cent.*did you mean 45"):
        run(relative_density=DR / 100)


def test_docs_worked_example_is_current():
    """docs/simplified.md prints this profile's table; it must match the code to the
    digits it shows (half a unit in the last printed place)."""
    from pathlib import Path
    doc = (Path(__file__).resolve().parents[2] / "docs" / "simplified.md").read_text(encoding="utf-8")
    block = doc[doc.index("### Worked example"):doc.index("Total settlement")]
    rows = [line.strip("|").split("|") for line in block.splitlines()
            if line.startswith("| ") and line[2].isdigit()]
    assert len(rows) == 5
    r = run()
    cols = [r.depth_mid_m, r.sigma_v_Pa / 1e3, r.sigma_v_eff_Pa / 1e3, r.relative_density, r.N1_60cs,
            r.r_d, r.CSR, r.CRR_75, r.MSF, r.K_sigma, r.FS, 100 * r.eps_v, 1e3 * r.settlement_m]
    for i, row in enumerate(rows):
        for cell, col in zip(row, cols):
            cell = cell.strip()
            if cell == "inf":
                assert np.isinf(col[i])
                continue
            decimals = len(cell.split(".")[1]) if "." in cell else 0
            assert abs(float(cell) - col[i]) <= 0.5 * 10.0 ** -decimals + 1e-12, (i, cell, col[i])
    assert f"Total settlement {1e3 * r.total_settlement_m:.1f} mm" in doc


def test_a_layer_given_by_spt_or_cpt_takes_its_own_route():
    """(N1)60cs given: the same FS as the Dr that 46 Dr² maps to it; q_c1Ncs given: Boulanger &
    Idriss's CPT CRR, C_σ and MSF_max (not the SPT curve at the equivalent Dr)."""
    from twofluid.geotech import correlations as co

    args = ([3.0], [3.5], [60e3], [40e3])
    by_dr = simplified_procedure(*args, [47.0], True, 0.2, 7.5)
    by_n = simplified_procedure(*args, [80.0], True, 0.2, 7.5, n160cs=[46.0 * 0.47 ** 2])
    assert by_n.FS[0] == pytest.approx(by_dr.FS[0], rel=1e-12)
    q = 100.0
    by_q = simplified_procedure(*args, [80.0], True, 0.2, 7.5, qc1ncs=[q])
    assert by_q.CRR_75[0] == pytest.approx(float(co.crr_75_cpt(q)), rel=1e-12)
    assert by_q.K_sigma[0] == pytest.approx(float(co.k_sigma_cpt(40e3, q)), rel=1e-12)
    assert by_q.relative_density[0] == pytest.approx(float(co.dr_from_qc1ncs(q)), rel=1e-12)
