"""The damage-equivalent CSR (CSR_eq15 = CRR·D^b) per element at the first liquefaction anywhere, at
the first liquefaction below the element and at the end of shaking, and the residual strains."""
import csv
from types import SimpleNamespace

import numpy as np
import pytest

from twofluid.closures import hysteretic as law
from twofluid.runners.liquefaction_damage import DamageRecord, csr_eq15


def test_csr_eq15_is_crr_at_unit_damage_and_follows_the_slope():
    assert float(csr_eq15(1.0, 0.13, 0.2)) == pytest.approx(0.13, rel=1e-15)
    # the damage of N uniform cycles at CSR = CRR (15/N)^b is N/15: CSR_eq15 gives that CSR back
    n, crr, b = 5.0, 0.13, 0.19
    assert float(csr_eq15(n / 15.0, crr, b)) == pytest.approx(crr * (n / 15.0) ** b, rel=1e-15)
    assert float(csr_eq15(0.0, 0.13, 0.2)) == 0.0


def _column(ns, shaking_end=10.0):
    par = np.zeros((ns + 1, law.NPARAM))
    par[:ns, law.P_CRR], par[:ns, law.P_B], par[:ns, law.P_LIQ] = 0.12, 0.2, 1.0
    y = np.arange(ns + 2, dtype=float)
    return SimpleNamespace(hysteretic=par, n_sat=ns, shaking_end=shaking_end, wave=SimpleNamespace(h=np.ones(ns + 1)),
                           u_static=np.zeros(ns + 2), y_all=y, ground_surface=y[-1])


def _state(t, damage, gamma=None):
    st = np.zeros((len(damage) + 1, law.NSTATE))
    st[:len(damage), law.S_D] = damage
    return SimpleNamespace(t=t, shear=st, wave=SimpleNamespace(gamma=np.zeros(len(damage) + 1) if gamma is None
                                                              else np.asarray(gamma, float)))


def test_snapshots_at_the_first_liquefaction_anywhere_below_and_at_the_end_of_shaking():
    rec = DamageRecord(_column(4))
    rec.record(_state(1.0, [0.2, 0.3, 0.1, 0.1]), np.zeros(4, bool))
    rec.record(_state(2.0, [0.5, 1.0, 0.2, 0.1]), np.array([False, True, False, False]))  # element 1 liquefies
    rec.record(_state(3.0, [1.0, 1.0, 0.4, 0.3]), np.array([True, True, False, False]))  # then element 0
    rec.record(_state(11.0, [1.0, 1.0, 0.9, 0.9]), np.array([True, True, False, False]))  # after the shaking
    cols = [rec.columns(e) for e in range(5)]
    eq = lambda d: float(csr_eq15(d, 0.12, 0.2))  # noqa: E731
    assert [c[2] for c in cols[:4]] == pytest.approx([eq(0.5), eq(1.0), eq(0.2), eq(0.1)])
    # above element 1 at t = 2; element 1 itself when element 0 liquefies at t = 3; element 0: nothing below
    assert cols[0][3] is None and cols[1][3] == pytest.approx(eq(1.0))
    assert cols[2][3] == pytest.approx(eq(0.2)) and cols[3][3] == pytest.approx(eq(0.1))
    assert [c[4] for c in cols[:4]] == pytest.approx([eq(1.0), eq(1.0), eq(0.4), eq(0.3)])  # t <= 10 s
    assert cols[4][:5] == [None] * 5  # the crust


def test_the_layered_site_shows_why_sand_with_fs_below_one_stays_below_liquefaction(tmp_path):
    """Where an element of the bundled layered site has FS < 1 but r_u stays below 0.95, its CSR_eq15
    after the first liquefaction below it is under its CRR; the liquefied elements reached it."""
    from twofluid.runners.liquefaction import run_liquefaction

    r = run_liquefaction("liquefaction-layered-site", tmp_path / "o")
    assert r.status == "completed"
    rows = list(csv.DictReader(open(tmp_path / "o" / "elements.csv")))
    shielded = [x for x in rows if x["CSR_eq15_first_liquefaction_below"] and float(x["FS_simplified_run"] or 9) < 1.0
                and float(x["peak_r_u"]) < 0.95]
    assert shielded, "the loose sand above the liquefied band stays below r_u 0.95"
    for x in shielded:
        assert float(x["CSR_eq15_first_liquefaction_below"]) < float(x["CRR_model"])
    for x in rows:
        if x["time_first_liquefied_s"] and x["CSR_eq15_end_of_shaking"]:
            assert float(x["CSR_eq15_end_of_shaking"]) >= 0.9 * float(x["CRR_model"])
    rs = r.summary["residual_strain"]
    assert rs["mean_residual_strain_liquefied"] == pytest.approx(
        rs["surface_displacement_m"] / r.summary["liquefied_thickness_m"], rel=1e-12)
    peak = max(float(x["peak_shear_strain"]) for x in rows)
    assert rs["largest_peak_strain"] == pytest.approx(peak, rel=1e-6)
    resid = [float(x["residual_shear_strain"]) for x in rows]
    assert abs(rs["largest_residual_strain"]) == pytest.approx(max(map(abs, resid)), rel=1e-6)
