"""Train the thesis's 3-3-1 reference-porosity network on byrne element tests.

Writes ``src/twofluid/data/ann/default_weights.json`` (or ``--out``). NumPy/SciPy only.

Data: cyclic simple-shear element tests (:func:`twofluid.models.element_test.cyclic_simple_shear`)
of the default loose sand with the ``byrne`` law, 100 steps per cycle:
strain-controlled at several amplitudes and stress-controlled at several CSRs
(the latter stopped at liquefaction), at several porosities and confining
stresses. Every step gives one sample: inputs (log10 Σ|Δγ|, |Δγ|, n̄_old),
target n̄_new. The network's output is de-normalised in ``strain_scaled`` mode
(n̄_new = n̄ − (1 − Ȳ) r_max |Δγ|, see ``twofluid.closures.reference_porosity.AnnWeights``).
The weights are fitted by ``scipy.optimize.least_squares`` from several seeded
random starts; residuals are the normalised output errors weighted by |Δγ|
relative to the test's mean step, so that each test counts by its accumulated
n̄ change. Tests at other amplitudes/CSRs are held out and reported.

Usage: ``python scripts/train_ann.py [--out PATH] [--starts 3]`` (about 2 minutes)
"""
from __future__ import annotations

import argparse
import json
from dataclasses import asdict
from pathlib import Path

import numpy as np
import scipy
from scipy.optimize import least_squares

from twofluid.closures.reference_porosity import AnnWeights, byrne_constants
from twofluid.models.element_test import DEFAULT_SAND, LooseSand, cyclic_simple_shear

STEPS_PER_CYCLE = 100
TRAIN_STRAINS = [1e-4, 2e-4, 5e-4, 1e-3, 2e-3, 5e-3, 1e-2]
TRAIN_CSR = [0.08, 0.10, 0.14, 0.20]
HELD_OUT_STRAINS = [3e-4, 3e-3]
HELD_OUT_CSR = [0.12]
POROSITIES = [0.40, 0.44, 0.48]
STRESSES = [50e3, 100e3, 200e3]  # [Pa]
CYCLES = 30.0
SAMPLES_PER_TEST = 250


def element_samples(sand: LooseSand, strains, csrs):
    """Rows (path, |Δγ|, n̄_old, n̄_new, weight) from byrne element tests."""
    rows = []
    rng = np.random.default_rng(7)
    for n in POROSITIES:
        for sig in STRESSES:
            mat = LooseSand(**{**asdict(sand), "porosity": n})
            runs = [cyclic_simple_shear(gamma_amplitude=np.asarray(strains, float), sigma_v0=sig,
                                        sand=mat, max_cycles=CYCLES, stop_at_liquefaction=False,
                                        steps_per_cycle=STEPS_PER_CYCLE)]
            if csrs:
                runs.append(cyclic_simple_shear(csr=np.asarray(csrs, float), sigma_v0=sig, sand=mat,
                                                max_cycles=CYCLES, steps_per_cycle=STEPS_PER_CYCLE))
            for r, j in ((r, j) for r in runs for j in range(r.gamma.shape[1])):
                # stress control: keep the steps before liquefaction (no run-away strains)
                stop = r.cycles.size if r.settings["mode"] == "strain" or \
                    not np.isfinite(r.cycles_to_liquefaction[j]) else \
                    int(np.searchsorted(r.cycles, r.cycles_to_liquefaction[j]))
                g = r.gamma[:stop, j]
                nb = r.n_bar[:stop, j]
                step = np.abs(np.diff(g))
                path = np.cumsum(step)
                keep = step > 0
                weight = step / step[keep].mean()
                sample = np.column_stack([path, step, nb[:-1], nb[1:], weight])[keep]
                # every test keeps at most SAMPLES_PER_TEST steps (random, seeded)
                pick = rng.choice(len(sample), min(len(sample), SAMPLES_PER_TEST), replace=False)
                rows.append(sample[np.sort(pick)])
    return np.concatenate(rows)


def unpack(theta):
    return theta[:9].reshape(3, 3), theta[9:12], theta[12:15], theta[15]


def make_weights(theta, lo, hi, rate_max, provenance=None) -> AnnWeights:
    wh, bh, wo, bo = unpack(theta)
    return AnnWeights(lo, hi, wh, bh, wo, float(bo), {"mode": "strain_scaled",
                      "rate_max": float(rate_max)}, provenance or {})


def fit(data, lo, hi, rate_max, starts: int, seed: int = 20010601):
    """Least-squares fit from ``starts`` seeded random initial guesses."""
    path, step, nb_old, nb_new, weight = data.T

    def residual(theta):
        pred = make_weights(theta, lo, hi, rate_max).predict(path, step, nb_old)
        return (pred - nb_new) / (rate_max * step) * weight

    rng = np.random.default_rng(seed)
    best = None
    for _ in range(starts):
        sol = least_squares(residual, rng.normal(0.0, 1.0, 16), method="trf", x_scale=1.0,
                            max_nfev=3000)
        if best is None or sol.cost < best.cost:
            best = sol
    return best.x


def rms_normalised(weights: AnnWeights, data) -> float:
    path, step, nb_old, nb_new, _ = data.T
    pred = weights.predict(path, step, nb_old)
    return float(np.sqrt(np.mean(((pred - nb_new) / (weights.output["rate_max"] * step)) ** 2)))


def relative_change_error(weights: AnnWeights, sand: LooseSand) -> dict:
    """Held-out element tests: relative error of the total n̄ change, ann vs byrne."""
    out = {}
    for g in HELD_OUT_STRAINS:
        kw = dict(gamma_amplitude=g, sand=sand, max_cycles=CYCLES, stop_at_liquefaction=False)
        b = cyclic_simple_shear(**kw)
        a = cyclic_simple_shear(**kw, law="ann", law_params={"weights": weights})
        db = b.n_bar[0, 0] - b.n_bar[-1, 0]
        out[f"strain_{g:g}"] = float(abs((a.n_bar[0, 0] - a.n_bar[-1, 0]) - db) / db)
    return out


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    root = Path(__file__).resolve().parents[1]
    parser.add_argument("--out", type=Path,
                        default=root / "src/twofluid/data/ann/default_weights.json")
    parser.add_argument("--starts", type=int, default=3)
    args = parser.parse_args(argv)

    sand = DEFAULT_SAND
    train = element_samples(sand, TRAIN_STRAINS, TRAIN_CSR)
    held = element_samples(sand, HELD_OUT_STRAINS, HELD_OUT_CSR)
    x = np.column_stack([np.log10(train[:, 0]), train[:, 1], train[:, 2]])
    lo, hi = x.min(axis=0), x.max(axis=0)
    rate_max = 1.25 * np.max((train[:, 2] - train[:, 3]) / train[:, 1])
    theta = fit(train, lo, hi, rate_max, args.starts)
    weights = make_weights(theta, lo, hi, rate_max)
    c1, c2 = byrne_constants(sand.dr)
    provenance = {
        "generated_by": "scripts/train_ann.py (twofluid repository)",
        "training_law": "byrne",
        "byrne": {"dr_percent": sand.dr, "C1": c1, "C2": c2},
        "sand": asdict(sand),
        "element_tests": {"steps_per_cycle": STEPS_PER_CYCLE, "cycles": CYCLES,
                          "strain_amplitudes": TRAIN_STRAINS, "csr": TRAIN_CSR,
                          "porosities": POROSITIES, "sigma_v0_Pa": STRESSES},
        "held_out": {"strain_amplitudes": HELD_OUT_STRAINS, "csr": HELD_OUT_CSR},
        "samples": {"per_test_at_most": SAMPLES_PER_TEST, "training": int(train.shape[0]),
                    "held_out": int(held.shape[0])},
        "fit": "scipy.optimize.least_squares (trf), residual = output error / (rate_max |dgamma|) "
               "weighted by |dgamma| / mean |dgamma| of its test; best of seeded random starts",
        "random_starts": args.starts,
        "rms_error_normalised": {"training": rms_normalised(weights, train),
                                 "held_out": rms_normalised(weights, held)},
        "held_out_relative_error_of_total_n_bar_change": relative_change_error(weights, sand),
        "valid_for": "the default loose sand and time steps near 1/100 of a 1 Hz-like cycle; "
                     "retrain for other sands or loading resolutions",
        "versions": {"numpy": np.__version__, "scipy": scipy.__version__},
    }
    weights = make_weights(theta, lo, hi, rate_max, provenance)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(weights.to_json(), indent=2) + "\n")
    print(json.dumps(provenance["rms_error_normalised"]),
          json.dumps(provenance["held_out_relative_error_of_total_n_bar_change"]))
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
