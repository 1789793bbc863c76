"""A layered soil column in total stress: twofluid's shear column against PySeismoSoil (issue 21).

Same column, same curves, same motion, same base on both sides:

- **Column** (``LAYERS``): 20 m in four layers, V_s 150–300 m/s, on an elastic half-space
  (V_r = 760 m/s, ρ_r = 2200 kg/m³). Small-strain damping 1 %.
- **Curves**: MKZ backbones G/G_max = 1/(1 + β (|γ|/γ_ref)^s), s = 0.92, β = 1, γ_ref
  0.035–0.09 % (growing with depth). PySeismoSoil runs them with Masing unload–reload
  (its NLHH kernel, Shi & Asimaki 2017, Iwan springs fitted to the curves; its damping
  parameter set is the same HH set, so its damping curve is the curve's Masing damping: no
  damping reduction). twofluid runs its hysteretic law (:mod:`twofluid.closures.hysteretic`,
  sub-steps :func:`twofluid.models.hysteretic_kernel.substeps`) in total stress: every element
  has a fixed G_max = ρ V_s² and a fixed strength, no pore pressure (``ns = 0``), no
  residual-strength floor and no dilation (γ_d0 = 10); per layer a GQ/H backbone fitted to the
  MKZ curve (:func:`layer_fits`) and Masing's rule, MRDF (1, 0, 1). PySeismoSoil's stand-in
  has no strength below 10 % strain (the MKZ stress keeps rising as γ^0.08), so the GQ/H
  strength τ_max is only a fitting device: the MKZ stress at 3 % (``STRENGTH_STRAIN``), which
  fits G/G_max over 1e-6–1e-2 to 0.003–0.011 (at 10 %: 0.013–0.019, and 8–13 % too much
  stress at 1 % strain).
- **Motion**: El Centro 1940 180° (bundled), scaled to the PGA, as the *outcrop*
  motion of the half-space: twofluid's compliant base (dashpot c = ρ_r V_r, input = outcrop
  acceleration); PySeismoSoil ``boundary="elastic"`` (it halves the outcrop motion into
  the incident wave itself).
- **Small-strain damping**: PySeismoSoil: the profile's 1 % as a frequency-independent Q
  (Liu & Archuleta 2006); twofluid: Rayleigh 1 % at f0 and 5 f0 (f0 = 1/(4 Σ h/V_s)), which is
  0.75 % at its minimum (√5 f0 = 6.3 Hz), 2.4 % at 1 Hz and 1.9 % at 30 Hz.
- **Time integration** (twofluid): 10 sub-steps per record sample (Δt = 1 ms), the record
  linear between samples; Newmark average acceleration (δ = 0) and, to show its effect, the
  liquefaction column's default δ = 0.05 (γ_N = 1/2 + δ, β_N = (γ_N + 1/2)²/4).

PySeismoSoil 0.7.0 (numpy ≥ 2.4 required by its wheel; its kernel is a bundled
Fortran executable): ``Nonlinear_Simulation`` accepts ``MKZ_Param_Multi_Layer`` but its
kernel reads nine HH parameters per material, so MKZ parameters end in
``forrtl: severe (24): end-of-file during read ... HH_G.dat`` and an empty-array error.
The workaround here: HH parameters that *are* the MKZ curve — transition strain
γ_t = 1 and a = 10 put the HH weight w(γ) above 1 − 2e-14 for γ ≤ 10 %, so the FKZ part
never acts (checked against PySeismoSoil's own MKZ curves, ``check_hh_equals_mkz``).

Compared quantities:

- Sa: 5 %-damped pseudo-spectral acceleration of the surface acceleration at 40
  periods log-spaced over 0.05–2 s, both records through
  :func:`twofluid.geotech.spectra.response_spectrum`; difference = max over the periods
  of |Sa_twofluid/Sa_pyseismosoil − 1|. Criteria: 20 % at 0.05 g, 25 % at 0.3 g.
- Peak strain: max |γ| over the record per sublayer. PySeismoSoil splits each layer into
  sublayers of at most V_s/225 m and reports one strain per sublayer; twofluid's mesh is
  those sublayers, each split into two elements, and its sublayer value is the larger of
  its two elements' peaks. (In the linear range, 0.001 g, PySeismoSoil's values equal
  twofluid's *lower* element of each sublayer to 1.3 % in the top three layers, while the
  upper elements' are 2–67 % smaller, most near the surface: the kernel reports its lower
  internal element.) Difference = max over the sublayers of |γ_twofluid/γ_PySeismoSoil − 1|.
  Criterion: 30 % at 0.3 g.
- 0.001 g (no criterion in the issue) checks the setup: in the linear range the two
  codes differ only by their small-strain damping (Q against Rayleigh) and their
  discretisations.
- ``--law-check``: the twofluid element law driven by PySeismoSoil's strain history of a
  sublayer, against PySeismoSoil's stress there, and beside it Masing's rules with reversal
  memory (:func:`masing_with_memory`) on the same path: tells the constitutive bookkeeping
  apart from the dynamics.

The twofluid side's model is built by :func:`twofluid_column` only.

    pip install -e '.[bench]'                             # PySeismoSoil, openseespy
    python benchmarks/bench_pyseismosoil.py --law-check   # 0.001, 0.05 and 0.3 g, both codes, δ = 0 and 0.05
    python benchmarks/bench_pyseismosoil.py --only pyseismosoil --out /tmp/pss   # one side, CSVs
"""
from __future__ import annotations

import argparse
import dataclasses
import functools
import resource
import tempfile
import time
from pathlib import Path

import numpy as np

from twofluid.closures import hysteretic as law
from twofluid.closures.backbone_fit import fit_gqh
from twofluid.closures.backbones import mkz_masing_damping
from twofluid.geotech.spectra import response_spectrum
from twofluid.io.ground_motion import G_STANDARD, bundled_record, load, scale_to_pga
from twofluid.models import hysteretic_kernel, hysteretic_sand
from twofluid.models.shear_column import rayleigh_coefficients

# thickness [m], V_s [m/s], density [kg/m³], MKZ γ_ref [-] (s and β below), top down
LAYERS = np.array([
    [3.0, 150.0, 1800.0, 3.5e-4],
    [5.0, 200.0, 1900.0, 5.5e-4],
    [6.0, 250.0, 1950.0, 7.5e-4],
    [6.0, 300.0, 2000.0, 9.0e-4],
])
MKZ_S, MKZ_BETA = 0.92, 1.0
ROCK_VS, ROCK_RHO = 760.0, 2200.0
XI_SMALL = 0.01
RECORD = "RSN6_IMPVALL.I_I-ELC180-hor1.AT2"
PERIODS = np.logspace(np.log10(0.05), np.log10(2.0), 40)
STRENGTH_STRAIN = 0.03  # the GQ/H strength τ_max is the MKZ stress at this strain [-]
MASING = (1.0, 0.0, 1.0)  # MRDF (p1, p2, p3) of Masing's rule
NO_DILATION = 10.0  # γ_d0 [-]: the dilation stiffening starts beyond 1000 % strain, i.e. never
NEWTON_TOL, NEWTON_MAX_ITER = 1e-10, 40  # the liquefaction column's (ShearColumn's defaults)
CRITERIA = {0.05: {"sa": 0.20}, 0.3: {"sa": 0.25, "strain": 0.30}}


def cpu_seconds() -> float:
    """CPU seconds of this process and its finished children (PySeismoSoil's kernel is one)."""
    c = resource.getrusage(resource.RUSAGE_CHILDREN)
    return time.process_time() + c.ru_utime + c.ru_stime


def mkz_reduction(gamma_ref: float, s: float = MKZ_S, beta: float = MKZ_BETA):
    """G/G_max(γ) of the MKZ backbone (Matasovic & Vucetic 1993) [-]."""
    return lambda g: 1.0 / (1.0 + beta * (np.abs(g) / gamma_ref) ** s)


def fundamental_frequency() -> float:
    """f0 = 1/(4 Σ h/V_s) of the soil column [Hz] (quarter-wavelength estimate)."""
    return 1.0 / (4.0 * float(np.sum(LAYERS[:, 0] / LAYERS[:, 1])))


def motion(pga_g: float):
    """El Centro 180° scaled to ``pga_g`` [g]: (time [s], acceleration [m/s²])."""
    m = scale_to_pga(load(bundled_record(RECORD)), pga_g)
    return m.time, m.acceleration


# ------------------------------------------------------------------ twofluid
def sublayers() -> np.ndarray:
    """Number of sublayers per layer: PySeismoSoil's rule, thickness ≤ V_s/225 m (15 points
    per wavelength at 15 Hz); both codes report peak strains per sublayer."""
    return np.ceil(LAYERS[:, 0] / (LAYERS[:, 1] / 225.0) - 1e-9).astype(int)


def mkz_stress(gamma, g_max: float, gamma_ref: float):
    """MKZ backbone stress τ = G_max γ G/G_max(γ) [Pa] at strains γ [-]."""
    g = np.asarray(gamma, dtype=float)
    return g_max * g * mkz_reduction(gamma_ref)(g)


@functools.lru_cache(maxsize=16)
def layer_fits(strength_strain: float = STRENGTH_STRAIN) -> tuple:
    """GQ/H fits of the layers' MKZ curves (:func:`twofluid.closures.backbone_fit.fit_gqh`), top down.

    Target: the MKZ G/G_max at 41 strains over 1e-6–1e-2 and its Masing damping (no floor: the
    small-strain damping is the Rayleigh term); strength τ_max = the MKZ stress at
    ``strength_strain``, reached by the GQ/H between 3 and 10 % (module docstring: PySeismoSoil's
    curves have no strength of their own, so τ_max only shapes the fit). Unloading–reloading is
    Masing's, MRDF (1, 0, 1), as in PySeismoSoil. The curves do not depend on the stress, so one
    fit serves every sublayer of a layer."""
    g = np.logspace(-6.0, -2.0, 41)
    fits = []
    for _, vs, rho, gref in LAYERS:
        g_max = rho * vs * vs
        fit = fit_gqh(g, mkz_reduction(gref)(g), mkz_masing_damping(g, gref, MKZ_BETA, MKZ_S),
                      tau_max=float(mkz_stress(strength_strain, g_max, gref)), g_max=g_max, d_min=0.0)
        fits.append(dataclasses.replace(fit, mrdf=MASING))
    return tuple(fits)


def fit_quality(strength_strain: float = STRENGTH_STRAIN) -> list:
    """Per layer: (max |ΔG/G_max| over 1e-6–1e-2, max |ΔD_Masing| there, τ_GQH/τ_MKZ at 0.1, 1
    and 10 % strain) of the fits against the MKZ curves [-]."""
    g = np.logspace(-6.0, -2.0, 401)
    out = []
    for fit, (_, _, _, gref) in zip(layer_fits(strength_strain), LAYERS):
        dg = np.max(np.abs(fit.modulus_reduction(g) - mkz_reduction(gref)(g)))
        dd = np.max(np.abs(fit.masing_damping(g) - mkz_masing_damping(g, gref, MKZ_BETA, MKZ_S)))
        ratio = [float(fit.backbone(x) / mkz_stress(x, fit.g_max, gref)) for x in (1e-3, 1e-2, 1e-1)]
        out.append((float(dg), float(dd), ratio))
    return out


def twofluid_column(per_sublayer: int = 2, strength_strain: float = STRENGTH_STRAIN) -> dict:
    """The twofluid shear model of the column for :func:`twofluid.models.hysteretic_kernel.substeps`,
    elements counted from the base up (node 0 the base): element thicknesses ``h`` [m], densities
    ``rho`` [kg/m³], the hysteretic law's parameter array ``par`` (every element total-stress:
    fixed G_max = ρ V_s² and fixed strength τ_max, no pore pressure, no residual-strength floor),
    Rayleigh ``a0`` [1/s] and ``a1`` [s], the base dashpot ``impedance`` ρ_r V_r [Pa·s/m] and
    ``sub``, the sublayer of each element counted from the surface. The one function to change
    for another shear model. Each sublayer is split into ``per_sublayer`` elements."""
    n_sub = sublayers()
    first_sub = np.concatenate([[0], np.cumsum(n_sub)])
    fits = layer_fits(strength_strain)
    top = np.concatenate([[0.0], np.cumsum(LAYERS[:, 0])])
    h, rho, g_max, tau_max, theta, sigma, sub = [], [], [], [], [], [], []
    for i in reversed(range(len(LAYERS))):
        thick, vs, r, _ = LAYERS[i]
        n = n_sub[i] * per_sublayer
        h += [thick / n] * n
        rho += [r] * n
        g_max += [r * vs * vs] * n
        tau_max += [fits[i].tau_max] * n
        theta += [fits[i].theta] * n
        # total vertical stress at the element centres (only to write τ_max as σ_v tan φ)
        depth = top[i + 1] - thick * (np.arange(n) + 0.5) / n
        above = float(np.sum(LAYERS[:i, 0] * LAYERS[:i, 2]))
        sigma += list(G_STANDARD * (above + r * (depth - top[i])))
        sub += list(first_sub[i] + (n - 1 - np.arange(n)) // per_sublayer)
    sigma, tau_max = np.array(sigma), np.array(tau_max)
    par = hysteretic_sand.parameters(sigma_v0=sigma, friction_angle=np.degrees(np.arctan(tau_max / sigma)),
                                     theta=np.array(theta), mrdf=MASING, g_max_fixed=np.array(g_max),
                                     liquefiable=False, gamma_d0=NO_DILATION)
    par[:, law.P_SR] = 0.0  # total stress: no residual-strength floor
    f0 = fundamental_frequency()
    a0, a1 = rayleigh_coefficients(XI_SMALL, f0, 5.0 * f0)
    return {"h": np.ascontiguousarray(h), "rho": np.ascontiguousarray(rho), "par": par, "a0": a0,
            "a1": a1, "impedance": ROCK_RHO * ROCK_VS, "sub": np.array(sub), "fits": fits}


def run_twofluid(pga_g: float, substeps: int = 10, per_sublayer: int = 2, delta: float = 0.0,
                 strength_strain: float = STRENGTH_STRAIN) -> dict:
    """Surface absolute acceleration at the record's samples and peak |γ| per sublayer, with Newmark
    γ_N = 1/2 + ``delta``, β_N = (γ_N + 1/2)²/4 (``delta`` = 0: average acceleration). The record is
    interpolated linearly to the sub-step times; a record interval whose Newton iterations fail is
    redone in halved sub-steps (four times at most)."""
    t, a = motion(pga_g)
    col = twofluid_column(per_sublayer, strength_strain)
    h, rho, par = col["h"], col["rho"], col["par"]
    ne = h.size
    nm_gamma = 0.5 + delta
    nm_beta = (nm_gamma + 0.5) ** 2 / 4.0
    u, v = np.zeros(ne + 1), np.zeros(ne + 1)
    acc = np.full(ne + 1, -float(a[0]))  # at rest: absolute acceleration 0, equilibrium at a[0]
    st = law.new_state(ne, par)
    empty = np.zeros(0)
    eta = np.zeros(ne)
    tau = np.empty(ne)
    surface = np.empty_like(a)
    surface[0] = a[0] + acc[-1]  # absolute acceleration of the surface at rest: 0
    # histories at the record's samples, base-up (the stress with its viscous part)
    strain, stress = np.zeros((t.size, ne)), np.zeros((t.size, ne))
    hysteretic_kernel.compiled()  # build or load it before the clock starts
    halved = 0
    start, cpu = time.perf_counter(), cpu_seconds()
    for i in range(1, t.size):
        for attempt in range(5):
            m = substeps * 2 ** attempt
            dt = float(t[i] - t[i - 1]) / m
            a_in = a[i - 1] + (a[i] - a[i - 1]) * np.arange(1, m + 1) / m
            uu, vv, aa, ss = u.copy(), v.copy(), acc.copy(), st.copy()
            out = np.empty(m)
            code = hysteretic_kernel.substeps(
                uu, vv, aa, ss, par, empty, empty, empty, empty, empty, rho, eta, h, 0, col["a0"],
                col["a1"], col["impedance"], 0, NEWTON_TOL, NEWTON_MAX_ITER, float(t[i - 1]), dt, a_in,
                float(t[-1]), out, tau, nm_beta, nm_gamma)
            if code != 1:
                break
            halved += 1
        if code != 0:
            raise RuntimeError(f"twofluid: sub-steps failed at t = {t[i]:.3f} s (code {code})")
        u, v, acc, st = uu, vv, aa, ss
        surface[i] = out[-1]
        strain[i] = np.diff(u) / h
        stress[i] = tau
    seconds, cpu = time.perf_counter() - start, cpu_seconds() - cpu
    peak = st[:, law.S_GM]
    peak_sub = np.zeros(col["sub"].max() + 1)
    np.maximum.at(peak_sub, col["sub"], peak)
    edges = np.concatenate([[0.0], np.cumsum(np.repeat(LAYERS[:, 0] / sublayers(), sublayers()))])
    return {"t": t, "input": a, "surface": surface, "depth": 0.5 * (edges[1:] + edges[:-1]),
            "peak_strain": peak_sub, "element_peak_strain": peak[::-1], "seconds": seconds,
            "cpu": cpu, "halved": halved, "delta": delta, "strain_history": strain[:, ::-1],
            "stress_history": stress[:, ::-1]}


# -------------------------------------------------------------- PySeismoSoil
def _pss_parameters():
    """HH parameters equal to the MKZ curves (module docstring), one set per material
    (the four layers and the half-space, which the kernel does not shear)."""
    from PySeismoSoil.class_parameters import HH_Param, HH_Param_Multi_Layer

    sets = [(gref, r * vs * vs) for _, vs, r, gref in LAYERS] + [(1.0, ROCK_RHO * ROCK_VS ** 2)]
    return HH_Param_Multi_Layer([
        HH_Param({"gamma_t": 1.0, "a": 10.0, "gamma_ref": gref, "beta": MKZ_BETA, "s": MKZ_S,
                  "Gmax": gmax, "mu": 1.0, "Tmax": gmax * gref, "d": 1.0})
        for gref, gmax in sets])


def check_hh_equals_mkz() -> float:
    """Largest |ΔG/G_max| and |Δξ| [-] between the HH stand-ins and PySeismoSoil's MKZ curves
    over 1e-4–6 % strain."""
    from PySeismoSoil.class_parameters import MKZ_Param

    strain_pct = np.geomspace(1e-4, 6.0, 60)
    worst = 0.0
    for hh, (_, vs, r, gref) in zip(_pss_parameters(), LAYERS):
        mkz = MKZ_Param({"gamma_ref": gref, "s": MKZ_S, "beta": MKZ_BETA, "Gmax": r * vs * vs})
        worst = max(worst, float(np.max(np.abs(hh.get_GGmax(strain_pct) - mkz.get_GGmax(strain_pct)))),
                    float(np.max(np.abs(hh.get_damping(strain_pct) - mkz.get_damping(strain_pct)))) / 100)
    return worst


def run_pyseismosoil(pga_g: float) -> dict:
    """PySeismoSoil's non-linear (NLHH) run: surface acceleration and peak |γ| per sublayer."""
    from PySeismoSoil.class_ground_motion import Ground_Motion
    from PySeismoSoil.class_simulation import Nonlinear_Simulation
    from PySeismoSoil.class_Vs_profile import Vs_Profile

    n = len(LAYERS)
    prof = np.column_stack([LAYERS[:, 0], LAYERS[:, 1], np.full(n, XI_SMALL), LAYERS[:, 2],
                            np.arange(1, n + 1)])
    prof = np.vstack([prof, [0.0, ROCK_VS, XI_SMALL, ROCK_RHO, n + 1]])
    t, a = motion(pga_g)
    params = _pss_parameters()
    sim = Nonlinear_Simulation(Vs_Profile(prof, damping_unit="1", density_unit="kg/m^3"),
                               Ground_Motion(np.column_stack([t, a]), unit="m/s/s"),
                               G_param=params, xi_param=params, boundary="elastic")
    with tempfile.TemporaryDirectory(prefix="pyseismosoil-") as tmp:  # it writes its files there
        start, cpu = time.perf_counter(), cpu_seconds()
        res = sim.run(sim_dir=str(Path(tmp) / "run"), verbose=False, remove_sim_dir=True)
        seconds, cpu = time.perf_counter() - start, cpu_seconds() - cpu
    surf = res.accel_on_surface.accel
    if not np.allclose(surf[:, 0], t):
        raise RuntimeError("PySeismoSoil's surface record is not sampled as its input")
    return {"t": t, "input": a, "surface": surf[:, 1], "depth": res.max_strain_stress[:, 0],
            "peak_strain": res.max_strain_stress[:, 1], "seconds": seconds, "cpu": cpu,
            "strain_history": res.time_history_strain, "stress_history": res.time_history_stress}


def masing_with_memory(strains, backbone) -> np.ndarray:
    """Stresses [Pa] of Masing's rules *with* reversal memory (extended Masing, as an Iwan model
    of parallel springs behaves) along a strain path [-], for an odd ``backbone(γ)`` [Pa]: from the
    last open reversal point (γ_r, τ_r) the branch is τ_r + 2 backbone((γ − γ_r)/2); when the
    strain passes the open reversal point before it, the inner loop is closed (both points are
    dropped) and the older branch is followed; past the mirror of the first one, the backbone.
    An independent reference for :func:`law_on_pyseismosoil_strain`."""
    stack, d_old, g_old, tau = [], 0.0, 0.0, 0.0
    out = np.zeros(len(strains))
    for i, g in enumerate(strains):
        d = float(np.sign(g - g_old))
        if d != 0.0:
            if d_old != 0.0 and d != d_old:
                stack.append((g_old, tau))
            d_old = d
            while True:
                if len(stack) >= 2 and d * (g - stack[-2][0]) >= 0.0:
                    del stack[-2:]
                elif len(stack) == 1 and d * g >= abs(stack[0][0]):
                    stack.clear()
                else:
                    break
            tau = backbone(g) if not stack else stack[-1][1] + 2.0 * backbone(0.5 * (g - stack[-1][0]))
            g_old = g
        out[i] = tau
    return out


def law_on_pyseismosoil_strain(ps: dict, sublayer: int, substeps: int = 10,
                               strength_strain: float = STRENGTH_STRAIN) -> dict:
    """The twofluid element law (plain Python, :mod:`twofluid.closures.hysteretic`) driven by
    PySeismoSoil's strain history of ``sublayer`` (linear between the record's samples, ``substeps``
    per interval), against PySeismoSoil's stress there: separates the constitutive bookkeeping from
    the dynamics. The sign is flipped (the codes' shear senses are opposite); PySeismoSoil's
    stress is the skeleton's alone (in the linear range it is G_max γ to 0.3 %). Beside it, the
    same path through :func:`masing_with_memory` on the MKZ curve and on the fitted GQ/H
    backbone. Returns rms and largest |Δτ| [Pa] of each against PySeismoSoil, and PySeismoSoil's
    largest |τ| [Pa]."""
    col = twofluid_column(1, strength_strain)
    e = int(np.flatnonzero(col["sub"] == sublayer)[0])
    par = np.ascontiguousarray(col["par"][e:e + 1])
    st = law.new_state(1, par)
    s, g_max = law.strength_modulus(0.0, par, 0)
    gr = s / g_max
    gh = -np.asarray(ps["strain_history"][:, sublayer], dtype=float)
    ref = -np.asarray(ps["stress_history"][:, sublayer], dtype=float)
    frac = np.arange(1, substeps + 1) / substeps
    path = np.concatenate([[gh[0]], (gh[:-1, None] + (gh[1:] - gh[:-1])[:, None] * frac).ravel()])
    at_samples = np.arange(gh.size) * substeps
    tau = np.zeros(path.size)
    for i in range(1, path.size):
        d = law.direction(path[i], st, 0)
        tau[i] = law.skeleton_stress(path[i], d, st, par, 0, s, gr)
        law.commit(path[i], d, tau[i], st, par, 0, s, 0.0, gr)
    layer = int(np.searchsorted(np.cumsum(sublayers()), sublayer, side="right"))
    fit, gref = col["fits"][layer], LAYERS[layer, 3]
    mkz = masing_with_memory(path, lambda g: float(mkz_stress(g, fit.g_max, gref)))
    gqh = masing_with_memory(path, lambda g: float(fit.backbone(g)))
    stats = lambda x: (float(np.sqrt(np.mean((x[at_samples] - ref) ** 2))),
                       float(np.max(np.abs(x[at_samples] - ref))))
    return {"law": stats(tau), "memory_mkz": stats(mkz), "memory_gqh": stats(gqh),
            "tau_max_pss": float(np.max(np.abs(ref))), "final": (float(tau[-1]), float(ref[-1]))}


# ---------------------------------------------------------------- comparison
def spectrum(run: dict) -> np.ndarray:
    """5 % Sa of the surface record at ``PERIODS`` [g]."""
    dt = float(run["t"][1] - run["t"][0])
    return response_spectrum(run["surface"], dt, PERIODS, 0.05)[0] / G_STANDARD


def compare(tf: dict, ps: dict) -> dict:
    sa_tf, sa_ps = spectrum(tf), spectrum(ps)
    if not np.allclose(tf["depth"], ps["depth"], atol=0.01):
        raise RuntimeError("the two codes' sublayers differ")
    strain_tf = tf["peak_strain"]
    return {"sa_tf": sa_tf, "sa_ps": sa_ps, "sa_diff": float(np.max(np.abs(sa_tf / sa_ps - 1.0))),
            "strain_tf": strain_tf,
            "strain_diff": float(np.max(np.abs(strain_tf / ps["peak_strain"] - 1.0)))}


def write_csv(out: Path, pga: float, name: str, run: dict) -> None:
    sa = spectrum(run)
    if "delta" in run:
        name = f"{name}_delta{run['delta']:g}"
    np.savetxt(out / f"sa_{name}_{pga:g}g.csv", np.column_stack([PERIODS, sa]), delimiter=",",
               header="period_s,sa_g", comments="", fmt="%.6g")
    np.savetxt(out / f"peak_strain_{name}_{pga:g}g.csv", np.column_stack([run["depth"], run["peak_strain"]]),
               delimiter=",", header="depth_m,peak_shear_strain", comments="", fmt="%.6g")


def report_side(name: str, pga: float, run: dict) -> None:
    sa = spectrum(run)
    print(f"\n{name}, {pga:g} g: {run['seconds']:.1f} s wall, {run['cpu']:.1f} s CPU; surface PGA "
          f"{np.max(np.abs(run['surface'])) / G_STANDARD:.4g} g")
    print("  Sa [g] at " + ", ".join(f"{T:.2f}" for T in PERIODS[::6]) + " s: "
          + ", ".join(f"{x:.3f}" for x in sa[::6]))
    print("  peak strain [%] by depth: " + ", ".join(
        f"{d:.1f} m {100 * g:.3f}" for d, g in zip(run["depth"][::3], run["peak_strain"][::3])))


def report_pair(pga: float, tf: dict, ps: dict) -> dict:
    c = compare(tf, ps)
    crit = CRITERIA.get(pga, {})
    print(f"\n=== {pga:g} g, Newmark δ = {tf['delta']:g}: twofluid {tf['seconds']:.1f} s wall, "
          f"{tf['cpu']:.1f} s CPU ({tf['halved']} intervals halved); "
          f"PySeismoSoil {ps['seconds']:.1f} s wall, {ps['cpu']:.1f} s CPU ===")
    print(f"surface PGA [g]: twofluid {np.max(np.abs(tf['surface'])) / G_STANDARD:.4g}, "
          f"PySeismoSoil {np.max(np.abs(ps['surface'])) / G_STANDARD:.4g}")
    print("period [s] | Sa twofluid [g] | Sa PySeismoSoil [g] | ratio")
    for T, a_tf, a_ps in list(zip(PERIODS, c["sa_tf"], c["sa_ps"]))[::3]:
        print(f"{T:10.3f} | {a_tf:15.3f} | {a_ps:19.3f} | {a_tf / a_ps:5.2f}")
    verdict = lambda x, key: "" if key not in crit else (" (criterion %d %%: %s)" % (
        round(100 * crit[key]), "pass" if x <= crit[key] else "FAIL"))
    print(f"Sa, max |ratio − 1| over 0.05–2 s: {100 * c['sa_diff']:.0f} %{verdict(c['sa_diff'], 'sa')}")
    print("depth [m] | peak γ twofluid [%] | peak γ PySeismoSoil [%] | ratio")
    for d, g_tf, g_ps in zip(ps["depth"], c["strain_tf"], ps["peak_strain"]):
        print(f"{d:9.2f} | {100 * g_tf:19.4f} | {100 * g_ps:23.4f} | {g_tf / g_ps:5.2f}")
    print(f"peak strain, max relative difference: {100 * c['strain_diff']:.0f} %"
          f"{verdict(c['strain_diff'], 'strain')}")
    return c


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--pga", type=float, nargs="+", default=[0.001, 0.05, 0.3], help="input PGAs [g]")
    p.add_argument("--only", choices=("twofluid", "pyseismosoil"), help="run one side")
    p.add_argument("--substeps", type=int, default=10, help="twofluid shear steps per record sample")
    p.add_argument("--per-sublayer", type=int, default=2, help="twofluid elements per sublayer")
    p.add_argument("--delta", type=float, nargs="+", default=[0.0, 0.05],
                   help="twofluid Newmark numerical damping δ (γ_N = 1/2 + δ), one run each")
    p.add_argument("--strength-strain", type=float, default=STRENGTH_STRAIN,
                   help="GQ/H strength = the MKZ stress at this strain [-]")
    p.add_argument("--law-check", action="store_true",
                   help="also drive the twofluid element law by PySeismoSoil's strain histories")
    p.add_argument("--out", type=Path, help="write Sa and peak-strain CSVs into this existing folder")
    args = p.parse_args(argv)
    if args.out is not None and not args.out.is_dir():
        p.error(f"--out {args.out}: not an existing folder")
    if not all(0.0 <= d <= 0.5 for d in args.delta):
        p.error(f"--delta {args.delta}: each must be in [0, 0.5]")
    if not 1e-3 <= args.strength_strain <= 1.0:
        p.error(f"--strength-strain {args.strength_strain}: must be in [1e-3, 1]")
    print(f"column: {len(LAYERS)} layers, {LAYERS[:, 0].sum():g} m, f0 = {fundamental_frequency():.2f} Hz; "
          f"half-space V_r = {ROCK_VS:g} m/s; record {RECORD}")
    if args.only != "pyseismosoil":
        start = time.process_time()
        quality = fit_quality(args.strength_strain)
        print(f"twofluid: GQ/H fitted to the MKZ curves, τ_max = MKZ stress at "
              f"{100 * args.strength_strain:g} % "
              f"({time.process_time() - start:.1f} s CPU), Masing unload-reload:")
        for (_, vs, _, gref), fit, (dg, dd, ratio) in zip(LAYERS, layer_fits(args.strength_strain), quality):
            print(f"  V_s {vs:g} m/s, γ_ref {100 * gref:.3f} %: τ_max {fit.tau_max / 1e3:.1f} kPa, "
                  f"θ = ({', '.join(f'{x:.4g}' for x in fit.theta)}); max |ΔG/G_max| {dg:.4f}, "
                  f"max |ΔD_Masing| {dd:.4f} over 1e-6–1e-2; τ_GQH/τ_MKZ at 0.1/1/10 %: "
                  + "/".join(f"{r:.3f}" for r in ratio))
    if args.only != "twofluid":
        import PySeismoSoil  # noqa: F401  (fails here, not mid-run, when the extra is missing)
        from importlib.metadata import version
        print(f"PySeismoSoil {version('PySeismoSoil')}, numpy {np.__version__}; "
              f"HH stand-in vs MKZ curves: max difference {check_hh_equals_mkz():.1e}")
    for pga in args.pga:
        tfs = [run_twofluid(pga, args.substeps, args.per_sublayer, d, args.strength_strain)
               for d in args.delta] if args.only != "pyseismosoil" else []
        ps = run_pyseismosoil(pga) if args.only != "twofluid" else None
        for name, run in [("twofluid", tf) for tf in tfs] + [("pyseismosoil", ps)]:
            if run is not None and args.out is not None:
                write_csv(args.out, pga, name, run)
        if ps is None:
            for tf in tfs:
                report_side(f"twofluid (δ = {tf['delta']:g})", pga, tf)
            continue
        if not tfs:
            report_side("PySeismoSoil", pga, ps)
        for tf in tfs:
            report_pair(pga, tf, ps)
        if args.law_check:
            worst = int(np.argmax(ps["peak_strain"]))
            for sl in sorted({1, worst, len(ps["peak_strain"]) - 2}):
                r = law_on_pyseismosoil_strain(ps, sl, args.substeps, args.strength_strain)
                print(f"PySeismoSoil's strain history at {ps['depth'][sl]:.2f} m (its max |τ| "
                      f"{r['tau_max_pss']:.0f} Pa), |Δτ| rms/max against its stress [Pa]: twofluid law "
                      f"{r['law'][0]:.0f}/{r['law'][1]:.0f} (final τ {r['final'][0]:.0f} against "
                      f"{r['final'][1]:.0f}); Masing with memory, MKZ {r['memory_mkz'][0]:.0f}/"
                      f"{r['memory_mkz'][1]:.0f}, GQ/H {r['memory_gqh'][0]:.0f}/{r['memory_gqh'][1]:.0f}")


if __name__ == "__main__":
    main()
