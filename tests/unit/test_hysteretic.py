"""The hysteretic shear law (closures/hysteretic.py) and its element test (models/hysteretic_kernel.py).

Criteria: undrained cyclic simple shear (σ′_v0 = 100 kPa, uniform cycles),
N to the first of r_u ≥ 0.98 or γ ≥ 3 %, against the CRR curve of Idriss & Boulanger with the slope b
of the magnitude scaling factor; K_σ; the threshold strain; the Seed–Booker growth of r_u; a cycle
during which r_u rises (stress within the strength envelope, dissipated energy ≥ 0); the
reconsolidation floor.
"""
import math

import numpy as np
import pytest

from twofluid.closures import hysteretic as law
from twofluid.models import hysteretic_kernel as hk
from twofluid.models import hysteretic_sand as hs
from twofluid.geotech.simplified import k_sigma


def _element(n160, amplitude, mode=0, sigma_v0=100e3, spc=100, max_cycles=120, jit=True):
    par = hs.parameters(sigma_v0=[sigma_v0], n160cs=n160)
    st = law.new_state(1, par)
    size = spc * max_cycles + 1
    g, tau, ru = np.zeros(size), np.zeros(size), np.zeros(size)
    n = hk.element_cycles(st, par, mode, amplitude, spc, max_cycles, 0.98, 0.03, g, tau, ru, jit=jit)
    return n, par, g, tau, ru, st


@pytest.mark.parametrize("n160", [5.0, 10.0, 15.0, 20.0, 25.0, 30.0])
def test_cycles_to_liquefaction_follow_the_crr_curve(n160):
    """CSR(N) = CRR (15/N)^b within ±15 % in CSR over N = 3–50 (5–50 where CSR ≥ 0.6).

    The CSR error of a measured N at an applied CSR is (N/N_target)^b − 1: the CSR that the
    correlation would need for the measured N, relative to the applied one."""
    par = hs.parameters(sigma_v0=[100e3], n160cs=n160)
    crr, b = par[0, law.P_CRR], par[0, law.P_B]
    for n_target in (3.0, 5.0, 15.0, 50.0):
        csr = crr * (15.0 / n_target) ** b
        if csr >= 0.6 and n_target < 5.0:
            continue
        n = _element(n160, csr)[0]
        assert n > 0, (n160, csr)
        assert abs((n / n_target) ** b - 1.0) <= 0.15, (n160, n_target, n)


def test_fifteen_cycles_at_crr_m75():
    """N = 15 at CSR = CRR_M7.5 (1 atm, no 0.9 factor): within one step of the cycle count's
    discretisation plus the first quarter cycle (0.3 cycles)."""
    par = hs.parameters(sigma_v0=[101325.0], n160cs=10.0)
    n = _element(10.0, par[0, law.P_CRR], sigma_v0=101325.0)[0]
    assert abs(n - 15.0) <= 0.5


@pytest.mark.parametrize("sigma", [200e3, 400e3])
def test_k_sigma_of_the_element_test(sigma):
    """CRR(σ′)/CRR(100 kPa) from element tests (CSR giving 15 cycles, by bisection) within ±10 %
    of Idriss & Boulanger's K_σ."""
    def crr15(sig):
        lo, hi = 0.02, 1.0
        for _ in range(30):
            mid = 0.5 * (lo + hi)
            n = _element(10.0, mid, sigma_v0=sig, max_cycles=60)[0]
            if n < 0 or n > 15.0:
                lo = mid
            else:
                hi = mid
        return 0.5 * (lo + hi)
    ratio = crr15(sigma) / crr15(100e3)
    target = float(k_sigma(sigma, 10.0) / k_sigma(100e3, 10.0))
    assert abs(ratio / target - 1.0) <= 0.10


def test_no_pore_pressure_below_the_threshold_strain():
    """r_u < 0.02 after 100 strain-controlled cycles at γ = 0.005 %."""
    ru = _element(10.0, 5e-5, mode=1, max_cycles=100)[4]
    assert ru.max() < 0.02


def test_growth_of_r_u_follows_seed_booker():
    """r_u at N/N_L = 0.25, 0.5, 0.75 within ±0.1 of Seed & Booker (α = 0.7)."""
    n, par, g, tau, ru, st = _element(10.0, 0.13)
    for f in (0.25, 0.5, 0.75):
        k = int(round(f * n * 100))
        assert abs(ru[k] - law.seed_booker(f, 0.7)) <= 0.1


def test_a_cycle_with_rising_r_u_stays_within_the_strength_and_dissipates():
    """Strain-controlled 0.2 % cycles: |τ| ≤ the envelope (the current strength, or the dilation
    stress at the element's strain), and the work per completed cycle is ≥ 0."""
    n, par, g, tau, ru, st = _element(10.0, 2e-3, mode=1, max_cycles=20)
    last = np.flatnonzero(g)[-1]
    sd = par[0, law.P_SIG0] * par[0, law.P_TANPHI]
    s = np.maximum(par[0, law.P_SIG0] * (1.0 - ru[:last + 1]) * par[0, law.P_TANPHI], par[0, law.P_SR])
    assert np.all(np.abs(tau[:last + 1]) <= np.maximum(s, sd) * (1 + 1e-9))
    assert ru[last] > ru[100]  # r_u rises over the cycles
    for c in range(int(last / 100)):
        k0, k1 = c * 100, (c + 1) * 100
        work = np.trapezoid(tau[k0:k1 + 1], g[k0:k1 + 1])
        assert work >= -1e-9 * sd * 2e-3


def test_stress_of_an_old_reversal_never_exceeds_the_new_strength():
    """Reversal stresses are kept as τ/τ_max: after the strength halves, a reloading branch from an
    old reversal stays within the new strength (strains inside the zone without dilation)."""
    par = hs.parameters(sigma_v0=[100e3], n160cs=10.0, liquefiable=False)
    st = law.new_state(1, par)
    s, gm = law.strength_modulus(100e3, par, 0)
    gr = s / gm
    for g in np.linspace(0.0, 3 * gr, 50)[1:]:
        law.commit(g, 1.0, law.skeleton_stress(g, 1.0, st, par, 0, s, gr), st, par, 0, s, 0.0, gr)
    s2, gm2 = law.strength_modulus(25e3, par, 0)
    gr2 = s2 / gm2
    assert 3 * gr < par[0, law.P_GD0]
    for g in np.linspace(3 * gr, -3 * gr, 80):
        assert abs(law.skeleton_stress(g, -1.0, st, par, 0, s2, gr2)) <= s2 * (1 + 1e-12)


@pytest.mark.parametrize("dr", [0.35, 0.55, 0.75])
@pytest.mark.parametrize("gamma_max", [0.005, 0.03, 0.1])
def test_reconsolidation_floor(dr, gamma_max):
    """ε_v floor = 1.5 exp(−2.5 Dr) min(0.08, γ_max) (Yoshimine et al. 2006) with γ_max the larger of
    the element's strain and I&B's γ_max(FS = D^−b, Dr); 0 where no pore pressure is generated."""
    from twofluid.geotech.settlement import max_shear_strain
    from twofluid.models.liquefaction_1d import ColumnState, LiquefactionColumn

    par = hs.parameters(sigma_v0=[50e3, 80e3, 80e3], dr=100 * dr, liquefiable=[True, True, False])
    st = law.new_state(3, par)
    st[:, law.S_GM] = gamma_max
    st[1, law.S_D] = 3.0  # liquefied: FS = 3^-b
    col = LiquefactionColumn.__new__(LiquefactionColumn)
    col.hysteretic, col.n_sat = par, 3
    eps = col.reconsolidation_floor(ColumnState(None, None, st))
    expect0 = 1.5 * math.exp(-2.5 * par[0, law.P_DR]) * min(0.08, gamma_max)
    g1 = max(gamma_max, float(max_shear_strain(3.0 ** -par[1, law.P_B], par[1, law.P_DR])))
    expect1 = 1.5 * math.exp(-2.5 * par[1, law.P_DR]) * min(0.08, g1)
    assert math.isclose(eps[0], expect0, rel_tol=1e-12)
    assert math.isclose(eps[1], expect1, rel_tol=1e-12) and eps[1] >= eps[0] * (1 - 1e-12)
    assert eps[2] == 0.0


def test_the_plain_python_and_the_compiled_kernel_agree():
    """The one source run un-jitted and compiled: the same cycles to liquefaction (to the step)."""
    a = _element(10.0, 0.14, max_cycles=20)
    b = _element(10.0, 0.14, max_cycles=20, jit=False)
    assert a[0] == b[0]
    np.testing.assert_allclose(a[2], b[2], rtol=1e-9, atol=1e-15)


def test_element_test_command_prints_the_csr_n_curve(tmp_path):
    """`twofluid element-test --model hysteretic --curve` prints and writes the curve; bad --n160cs
    is one line and exit 2."""
    import subprocess
    import sys

    out = tmp_path / "et"
    r = subprocess.run([sys.executable, "-m", "twofluid.cli", "element-test", "--model", "hysteretic",
                        "--n160cs", "15", "--curve", "--out", str(out)], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert "N correlation" in r.stdout and (out / "csr_n.csv").is_file() and (out / "csr_n.png").is_file()
    rows = np.genfromtxt(out / "csr_n.csv", delimiter=",", names=True)
    assert np.all(np.abs(rows["csr_error"]) <= 0.15)
    bad = subprocess.run([sys.executable, "-m", "twofluid.cli", "element-test", "--model", "hysteretic",
                          "--n160cs", "99"], capture_output=True, text=True)
    assert bad.returncode == 2 and len(bad.stderr.strip().splitlines()) == 1 and "--n160cs" in bad.stderr


# ---- the memory of open reversal points (extended Masing rules)
def _total_stress_element(mrdf):
    """A total-stress element (no pore pressure, no dilation in reach) at σ′_v = 100 kPa: state,
    parameters, τ_max [Pa] and γ_r [-]."""
    par = hs.parameters(sigma_v0=[100e3], n160cs=10.0, liquefiable=False, mrdf=mrdf, gamma_d0=10.0)
    st = law.new_state(1, par)
    s, gm = law.strength_modulus(100e3, par, 0)
    return st, par, s, s / gm


def _drive(path, st, par, s, gr):
    """The law (plain Python) along a strain path, committing every point: the stresses [Pa]."""
    tau = np.zeros(len(path))
    for i, g in enumerate(path):
        d = law.direction(g, st, 0)
        tau[i] = law.skeleton_stress(g, d, st, par, 0, s, gr)
        law.commit(g, d, tau[i], st, par, 0, s, 0.0, gr)
    return tau


def _legs(points, per_unit):
    """A piecewise-linear strain path through ``points`` [-], ``per_unit`` points per unit of strain."""
    out = [np.array([0.0])]
    for a, b in zip(points[:-1], points[1:]):
        k = max(2, int(round(abs(b - a) * per_unit)))
        out.append(np.linspace(a, b, k + 1)[1:])
    return np.concatenate(out)


def _masing_reference(path, backbone):
    """Masing's rules with the memory of every open reversal point, written independently of the
    law: from the last open point (γ_r, τ_r) the branch τ_r + 2 f((γ − γ_r)/2); a branch reaching
    the open point before it closes that loop (both points dropped) and continues the older
    branch; past the first point's mirror image, the backbone f."""
    pts, tau, g_old, d_old = [], 0.0, 0.0, 0.0
    out = np.zeros(len(path))
    for i, g in enumerate(path):
        d = np.sign(g - g_old)
        if d != 0.0:
            if d_old != 0.0 and d != d_old:
                pts.append((g_old, tau))
            d_old = d
            while True:
                if len(pts) >= 2 and d * (g - pts[-2][0]) >= 0.0:
                    pts = pts[:-2]
                elif len(pts) == 1 and d * g >= abs(pts[0][0]):
                    pts = []
                else:
                    break
            tau = backbone(g) if not pts else pts[-1][1] + 2.0 * backbone(0.5 * (g - pts[-1][0]))
            g_old = g
        out[i] = tau
    return out


def test_masing_memory_matches_an_independent_reference():
    """Masing's rule (MRDF (1, 0, 1)), constant strength: along an irregular strain path with nested
    loops (three sines, up to 3 γ_r) the law's stress equals the extended-Masing reference to
    1e-12 τ_max (round-off: the same backbone evaluated in the same order)."""
    st, par, s, gr = _total_stress_element((1.0, 0.0, 1.0))
    t = np.linspace(0.0, 20.0, 8001)
    path = gr * (2.0 * np.sin(1.3 * t) + 0.7 * np.sin(5.1 * t + 1.0) + 0.3 * np.sin(13.7 * t + 2.0)) \
        * np.minimum(t / 5.0, 1.0)
    tau = _drive(path, st, par, s, gr)
    th = par[0, law.P_TH1:law.P_TH5 + 1]
    ref = _masing_reference(path, lambda g: s * math.copysign(law.gqh_ratio(abs(g) / gr, *th), g))
    assert np.max(np.abs(tau - ref)) <= 1e-12 * s


@pytest.mark.parametrize("mrdf", [(1.0, 0.0, 1.0), (0.9, 0.6, 1.2)])
def test_a_closed_inner_loop_returns_onto_the_outer_branch(mrdf):
    """Backbone to 3 γ_r, unloading to −2 γ_r with an inner loop (−0.5 → 0.3 → −0.5 γ_r) on the
    way: past −0.5 γ_r the stress is the one of the same unloading without the inner loop, to
    1e-9 τ_max (Masing and MRDF: the return branch meets the reversal point exactly, being odd)."""
    per = 400.0
    plain = _legs([0.0, 3.0, -2.0], per)
    inner = _legs([0.0, 3.0, -0.5, 0.3, -2.0], per)
    st, par, s, gr = _total_stress_element(mrdf)
    t_plain = _drive(plain * gr, st, par, s, gr)
    st, par, s, gr = _total_stress_element(mrdf)
    t_inner = _drive(inner * gr, st, par, s, gr)
    tail = plain < -0.5
    k = np.flatnonzero(tail)[0]
    n_tail = int(tail.sum())
    np.testing.assert_allclose(inner[-n_tail:], plain[k:], atol=1e-12)
    assert np.max(np.abs(t_inner[-n_tail:] - t_plain[k:])) <= 1e-9 * s
    assert st[0, law.S_NSTK] == 1  # only the backbone reversal is open


@pytest.mark.parametrize("mrdf", [(1.0, 0.0, 1.0), (0.9, 0.6, 1.2)])
def test_small_inner_cycles_do_not_ratchet(mrdf):
    """N = 20 small symmetric cycles (±0.1 γ_r) at γ = 0.5 γ_r on the reloading branch from −2 γ_r,
    then on to 2 γ_r: the stress at each strain of the outer branch is the one without the cycles,
    to 1e-9 τ_max (a law that kept only the last reversal point ratchets here by a fraction of τ_max)."""
    per = 400.0
    base = [0.0, 2.0, -2.0]
    plain = _legs(base + [2.0], per)
    cycles = _legs(base + [0.5] + [0.4, 0.6] * 20 + [2.0], per)
    st, par, s, gr = _total_stress_element(mrdf)
    t_plain = _drive(plain * gr, st, par, s, gr)
    st, par, s, gr = _total_stress_element(mrdf)
    t_cyc = _drive(cycles * gr, st, par, s, gr)
    after = (plain > 0.6) & (np.arange(plain.size) > np.argmin(plain))  # the last leg past the cycles
    n_tail = int(after.sum())
    np.testing.assert_allclose(cycles[-n_tail:], plain[after], atol=1e-12)
    assert np.max(np.abs(t_cyc[-n_tail:] - t_plain[after])) <= 1e-9 * s
    # and every cycle's top (0.6 γ_r, reached loading) is on the outer branch: no cycle-by-cycle drift
    k = np.flatnonzero(np.isclose(plain, 0.6) & (np.arange(plain.size) > np.argmin(plain)))[0]
    top = np.flatnonzero(np.isclose(cycles, 0.6) & (np.arange(cycles.size) > np.argmin(cycles)))
    top = top[np.diff(cycles, prepend=0.0)[top] > 0.0]
    assert top.size == 20 and np.max(np.abs(t_cyc[top] - t_plain[k])) <= 1e-9 * s


def test_the_stress_is_continuous_where_loops_close_under_a_changing_strength():
    """Open inner loops recorded at one strength, then the strength and γ_r lowered by 30 % and 16 %
    (rising pore pressure) and MRDF: over a sub-step's iterates around the closure point the stress
    is a continuous function of the strain (adjacent iterates 1e-6 γ_r apart differ by at most
    1.01 G_max × 1e-6 γ_r), and committing past the closure point does not change the stress there."""
    st, par, s, gr = _total_stress_element((0.9, 0.6, 1.2))
    _drive(_legs([0.0, 3.0, -1.0, 0.5, -0.2], 400.0) * gr, st, par, s, gr)
    assert st[0, law.S_NSTK] == 3  # 3 γ_r, −1 γ_r and 0.5 γ_r open
    s2, gm2 = law.strength_modulus(70e3, par, 0)  # τ_max ∝ P_s, γ_r ∝ √P_s
    gr2 = s2 / gm2
    g_close = st[0, law.S_STK + 2 * 2]  # reloading from −0.2 γ_r closes the loop at 0.5 γ_r
    d = 1.0
    grid = np.arange(-0.2 * gr, g_close + 0.3 * gr, 1e-6 * gr)
    tau = np.array([law.skeleton_stress(g, d, st, par, 0, s2, gr2) for g in grid])
    assert np.max(np.abs(np.diff(tau))) <= 1.01 * gm2 * 1e-6 * gr
    for g in (g_close - 0.05 * gr, g_close + 1e-9 * gr, g_close + 0.05 * gr, g_close + 0.2 * gr):
        st2 = st.copy()
        te = law.skeleton_stress(g, d, st2, par, 0, s2, gr2)
        law.commit(g, d, te, st2, par, 0, s2, 0.0, gr2)
        assert abs(law.skeleton_stress(g, d, st2, par, 0, s2, gr2) - te) <= 1e-12 * s2


def test_the_stack_holds_at_most_nstack_points():
    """Ever smaller nested loops (more reversals than the stack holds): at most NSTACK points stay
    open, the stress stays within the strength, and every commit leaves the stress at the committed
    strain unchanged."""
    st, par, s, gr = _total_stress_element((1.0, 0.0, 1.0))
    pts = [0.0] + [(-1.0) ** k * 3.0 * 0.9 ** k for k in range(2 * law.NSTACK + 4)]  # nested loops
    for g in _legs(pts, 2000.0) * gr:
        d = law.direction(g, st, 0)
        te = law.skeleton_stress(g, d, st, par, 0, s, gr)
        law.commit(g, d, te, st, par, 0, s, 0.0, gr)
        assert st[0, law.S_NSTK] <= law.NSTACK
        assert abs(te) <= s * (1 + 1e-12)
        assert abs(law.skeleton_stress(g, d, st, par, 0, s, gr) - te) <= 1e-12 * s


def _counted(path, n160=10.0, sigma_v0=100e3, b=None):
    """Total damage after a stress path [(γ, τ [Pa]), ...] is committed point by point (the law's
    damage count only: the stresses are imposed, not computed); ``b`` a CSR–N slope of its own."""
    par = hs.parameters(sigma_v0=[sigma_v0], n160cs=n160, csr_n_slope=b)
    st = law.new_state(1, par)
    total = 0.0
    for g, tau in path:
        d = law.direction(g, st, 0)
        total = law.commit(g, d, tau, st, par, 0, 1e9, 0.0, 1e-3)  # γ_r only for the loop bookkeeping
    return total, par


def _half_cycle(par, tau_a, gamma_a):
    return law.half_cycle_damage(tau_a, gamma_a, par, 0)


def test_a_wiggle_within_a_half_cycle_costs_it_nothing():
    """Rainflow counting: a half cycle 0 → +τ with a small dip on the way counts the whole half
    cycle (amplitude τ/2, from its start) plus the small closed cycle, not two pieces; counted
    from the last reversal alone, the dip would remove almost all of its damage (a soil of its own
    slope b = 0.10: 1/b = 10)."""
    g1, t1 = 2e-3, 15e3
    plain, par = _counted([(g1 / 2, t1 / 2), (g1, t1)], b=0.1)
    dipped, _ = _counted([(g1 / 2, t1 / 2), (0.45 * g1, 0.45 * t1), (g1, t1)], b=0.1)
    whole = _half_cycle(par, t1 / 2, g1 / 2)
    inner = 2.0 * _half_cycle(par, 0.025 * t1, 0.025 * g1)
    assert plain == pytest.approx(whole, rel=1e-12)
    assert dipped == pytest.approx(whole + inner, rel=1e-12)
    split = _half_cycle(par, t1 / 4, g1 / 4) + _half_cycle(par, 0.275 * t1, 0.275 * g1)
    assert split < 0.01 * dipped  # what counting from the last reversal would have given


def test_closed_inner_cycles_count_as_full_cycles():
    """A large cycle ±τ with three inner cycles of ±τ/2 around +τ/2 on its way up: rainflow gives the
    outer half cycles (0 → −τ, −τ → +τ, +τ → −τ) plus three full inner cycles: six half cycles of
    amplitude τ/4."""
    t, g = 20e3, 3e-3
    path = [(-g, -t)]
    for _ in range(3):
        path += [(0.75 * g, 0.75 * t), (0.25 * g, 0.25 * t)]
    path += [(g, t), (-g, -t)]
    total, par = _counted(path)
    outer = _half_cycle(par, t / 2, g / 2) + 2.0 * _half_cycle(par, t, g)
    inner = 6.0 * _half_cycle(par, 0.25 * t, 0.25 * g)
    assert total == pytest.approx(outer + inner, rel=1e-12)


def test_cyclic_mobility_strain_grows_cycle_by_cycle_towards_gamma_lim():
    """Uniform stress cycles at CSR = CRR ((N1)60cs = 10, σ′_v0 = 100 kPa) carried on past r_u = 0.98:
    the single-amplitude strain at r_u = 0.98 is 3–4.5 % (Yoshimine et al. 2006: 3.5 % at FS = 1;
    the laboratory's 3 %: γ_dr = 10 % is chosen so), then grows in every cycle, by 0.5–2 % a cycle,
    and never passes γ_lim(Dr)."""
    par = hs.parameters(sigma_v0=[100e3], n160cs=10.0)
    st = law.new_state(1, par)
    spc, cycles = 200, 40
    g, tau, ru = (np.zeros(spc * cycles + 1) for _ in range(3))
    hk.element_cycles(st, par, 0, par[0, law.P_CRR], spc, cycles, 2.0, 0.6, g, tau, ru)
    k = int(np.argmax(ru >= 0.98))
    assert ru[k] >= 0.98
    amp = [np.abs(g[k + c * spc:k + (c + 1) * spc]).max() for c in range(20)]
    assert 0.03 <= amp[0] <= 0.045
    steps = np.diff(amp)
    assert np.all(steps > 0.0) and 0.005 <= np.mean(steps) <= 0.02
    assert np.abs(g).max() <= par[0, law.P_GLIM] * (1 + 1e-12)


def _liquefied_element(gd=0.01):
    par = hs.parameters(sigma_v0=[100e3], n160cs=10.0)
    st = law.new_state(1, par)
    st[0, law.S_LIQ] = 1.0
    st[0, law.S_GD] = gd
    s, gm = law.strength_modulus(par[0, law.P_SR] / par[0, law.P_TANPHI], par, 0)
    return st, par, s, s / gm


def _cross(steps):
    """γ_d after one crossing of a liquefied element's zone (−γ_d → +γ_d, then 1 % beyond) in ``steps``."""
    st, par, s, gr = _liquefied_element()
    path = list(np.linspace(-0.01, 0.01, steps + 1)) + [0.02]
    st[0, law.S_G] = path[0]
    for g in path[1:]:
        d = law.direction(g, st, 0)
        law.commit(g, d, law.skeleton_stress(g, d, st, par, 0, s, gr), st, par, 0, s, 0.0, gr)
    return st[0, law.S_GD] - 0.01, par[0, law.P_DGD]


def test_the_zone_widens_with_the_strain_travelled_in_it_not_with_the_steps():
    """Once liquefied, a crossing of the zone without dilation (γ_d = 1 %, from −γ_d to +γ_d and on
    beyond) widens it by about Δγ_d = γ_lim/100 (d(γ_d²) = Δγ_d |dγ| inside the zone: 0.5–1.5 Δγ_d),
    the same in 10 sub-steps as in 1000 (within 5 % of Δγ_d), and with no reversal counted."""
    w10, dgd = _cross(10)
    w1000, _ = _cross(1000)
    assert 0.5 * dgd <= w1000 <= 1.5 * dgd
    assert abs(w10 - w1000) <= 0.05 * dgd


def test_a_reversal_within_the_dilation_zone_keeps_its_stress():
    """Loading outwards into the dilation zone, a small unloading and reloading there: the stress
    right after each reversal is the committed one (the dilation gained since the branch's origin
    is added, not the whole τ_d again), and reloading returns to the dilation envelope."""
    st, par, s, gr = _liquefied_element(gd=0.005)
    path = list(np.linspace(0.0, 0.02, 200)) + list(np.linspace(0.02, 0.018, 20)) + list(np.linspace(0.018, 0.03, 120))
    taus = []
    for g in path[1:]:
        d = law.direction(g, st, 0)
        t_after = law.skeleton_stress(g, d, st, par, 0, s, gr)
        if d != st[0, law.S_DIR] and st[0, law.S_DIR] != 0.0:  # a reversal: continuous from the committed stress
            near = law.skeleton_stress(st[0, law.S_G] + d * 1e-12, d, st, par, 0, s, gr)
            assert abs(near - st[0, law.S_TAU]) <= 1e-6 * par[0, law.P_SIG0]
        law.commit(g, d, t_after, st, par, 0, s, 0.0, gr)
        taus.append(t_after)
    ex = 0.03 - st[0, law.S_GC]
    assert taus[-1] == pytest.approx(max(s, law._dilation(ex, st, par, 0)), rel=1e-9)
    assert np.all(np.abs(np.diff(taus)) <= 0.05 * par[0, law.P_SIG0])  # no jump anywhere on the path


def test_generation_is_counted_at_the_stress_it_leaves():
    """A strong half cycle in one sub-step (CSR 0.2 at (N1)60cs = 10 with a slope b = 0.10 of its own,
    damage ∝ CSR^10): counted at
    the stress of the strength before it, r_g would jump to r_cap; counted consistently
    (commit_generating) the strength factor q = (1 − r_new)/(1 − r_old) and the committed stress
    agree: the stress is the skeleton's at q P_s, and q is what its damage gives, to 1e-8."""
    par = hs.parameters(sigma_v0=[100e3], n160cs=10.0, csr_n_slope=0.1)
    ps = 100e3 * (1.0 - 0.5)
    st = law.new_state(1, par)
    st[0, law.S_RG] = 0.5
    st[0, law.S_D] = math.sin(0.5 * math.pi / 2) ** 1.4  # the damage of r_g = 0.5 (Seed–Booker, α = 0.7)
    g = 0.004
    explicit = st.copy()
    s0, gm0 = law.strength_modulus(ps, par, 0)
    law.commit(g, 1.0, law.skeleton_stress(g, 1.0, explicit, par, 0, s0, s0 / gm0), explicit, par, 0, s0, 0.0, s0 / gm0)
    r_explicit = law.generated_ratio(explicit, par, 0)
    before = st.copy()
    tau = law.commit_generating(g, 1.0, st, par, 0, ps, 0.0, np.empty(law.NSTATE), 0.0)
    r_new = law.generated_ratio(st, par, 0)
    q = (1.0 - r_new) / 0.5
    s1, gm1 = law.strength_modulus(ps * q, par, 0)
    assert tau == pytest.approx(law.skeleton_stress(g, 1.0, before, par, 0, s1, s1 / gm1), rel=1e-6)
    assert 0.5 < r_new < r_explicit
    assert r_explicit >= 0.99 and r_new < 0.95


def _monotonic(tau_static, ps, to, steps=400):
    """Stresses of a liquefied element ((N1)60cs = 10, γ_d = 1 %, σ′_v0 = 100 kPa) loaded
    monotonically from γ_c = 0 to ``to`` at effective stress ``ps``, with static shear ``tau_static``."""
    st, par, _, _ = _liquefied_element()
    par[0, law.P_TAUS] = tau_static
    s, gm = law.strength_modulus(ps, par, 0)
    taus = []
    for g in np.linspace(0.0, to, steps + 1)[1:]:
        d = law.direction(g, st, 0)
        t = law.skeleton_stress(g, d, st, par, 0, s, s / gm)
        law.commit(g, d, t, st, par, 0, s, 0.0, s / gm)
        taus.append(t)
    return np.array(taus), s, par


@pytest.mark.parametrize("sign", [1.0, -1.0])
@pytest.mark.parametrize("ps", [1e3, 20e3])
def test_flow_liquefaction_no_dilation_on_the_side_of_a_static_shear_above_s_r(sign, ps):
    """An element whose static shear exceeds its residual strength (|τ_s| = 1.5 S_r), liquefied and
    loaded on the side of its static shear to 20 % strain (beyond γ_d + γ_dr = 11 %): its skeleton
    stress never exceeds the strength max(P_s tan φ′, S_r) (at P_s = 1 kPa the floor S_r, at 20 kPa
    P_s tan φ′) and ends within 1 % of it (the column adds the rate part η γ̇ to it); with τ_s = 0.5
    S_r (FS_post = 2: cyclic mobility) the same path ends on the dilation envelope σ′_v0 tan φ′,
    many times the strength. Loaded the other way, against the static shear, its stresses are those
    of the element without static shear, to the last bit."""
    par0 = hs.parameters(sigma_v0=[100e3], n160cs=10.0)
    sr, tanphi = par0[0, law.P_SR], par0[0, law.P_TANPHI]
    flow, s, par = _monotonic(sign * 1.5 * sr, ps, sign * 0.2)
    assert s == pytest.approx(max(ps * tanphi, sr), rel=1e-12)
    assert np.all(np.abs(flow) <= s * (1.0 + 1e-12)) and abs(flow[-1]) >= 0.99 * s
    assert np.all(sign * flow > 0.0)
    mobile, _, _ = _monotonic(sign * 0.5 * sr, ps, sign * 0.2)
    assert abs(mobile[-1]) == pytest.approx(100e3 * tanphi, rel=1e-9) and abs(mobile[-1]) > 4.0 * s
    against, _, _ = _monotonic(sign * 1.5 * sr, ps, -sign * 0.2)
    level, _, _ = _monotonic(0.0, ps, -sign * 0.2)
    assert np.array_equal(against, level) and abs(level[-1]) == pytest.approx(100e3 * tanphi, rel=1e-9)
