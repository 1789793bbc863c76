"""Reference porosity n̄ under cyclic shear: the liquefaction trigger (docs/model.md).

Every law has the interface ``n_bar_new, state_new = law(dgamma, gamma, n_bar, state, **params)``
with ``dgamma`` the shear-strain increment of the step, ``gamma`` the strain at its
end, ``n_bar`` the reference porosity before it and ``state`` a
:class:`ShearState` (arrays over elements). Laws are pure: the state is returned,
never modified, and every operation is vectorised over elements.

>>> import numpy as np
>>> state = ShearState.zeros(2)
>>> nb, state = byrne(np.array([1e-3, 0.0]), np.array([1e-3, 0.0]), np.array([0.5, 0.5]), state)
>>> bool(nb[0] < 0.5), float(nb[1])
(True, 0.5)
"""
from __future__ import annotations

import json
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from .registry import register

__all__ = ["ShearState", "byrne", "byrne_constants", "ann", "AnnWeights", "AnnWeightsError",
           "load_weights", "weights_from_dict", "DEFAULT_WEIGHTS"]

#: Shipped weights, trained on the byrne law by scripts/train_ann.py.
DEFAULT_WEIGHTS = "default_weights.json"

DR_DEFAULT = 47.0  # [%] relative density of the default loose sand (models.element_test)


@dataclass(frozen=True)
class ShearState:
    """Shear-history state per element (all arrays of one shape).

    Attributes
    ----------
    eps_v : volumetric strain the skeleton has tried to make so far [-]
    gamma_a : peak |γ| since the last strain reversal [-]
    gamma : shear strain at the end of the last step [-]
    direction : sign (−1, 0, +1) of the last non-zero strain increment
    path : accumulated shear strain Σ|Δγ| [-]
    """

    eps_v: np.ndarray
    gamma_a: np.ndarray
    gamma: np.ndarray
    direction: np.ndarray
    path: np.ndarray

    @classmethod
    def zeros(cls, shape: int | tuple[int, ...], gamma: ArrayLike = 0.0) -> "ShearState":
        """A virgin state (no shear history) at strain ``gamma``."""
        z = np.zeros(shape)
        g = np.broadcast_to(np.asarray(gamma, dtype=float), z.shape).copy()
        return cls(z.copy(), np.abs(g), g, z.copy(), z.copy())


def _kinematics(dgamma, gamma, state):
    """Peak |γ| since the last reversal, new direction, new path length."""
    dgamma = np.asarray(dgamma, dtype=float)
    gamma = np.asarray(gamma, dtype=float)
    sgn = np.sign(dgamma)
    reversal = (sgn != 0) & (state.direction != 0) & (sgn != state.direction)
    # at a reversal the peak restarts from the strain where the path turned
    peak = np.where(reversal, np.abs(gamma - dgamma), state.gamma_a)
    peak = np.maximum(peak, np.abs(gamma))
    direction = np.where(sgn != 0, sgn, state.direction)
    return np.abs(dgamma), gamma, peak, direction, state.path + np.abs(dgamma)


def byrne_constants(dr: float) -> tuple[float, float]:
    """Byrne's C1 = 7600 Dr^−2.5 (Dr in %) and C2 = 0.4/C1.

    >>> [round(c, 4) for c in byrne_constants(40.0)]
    [0.751, 0.5326]
    """
    if not 0.0 < dr <= 100.0:
        raise ValueError(f"byrne: relative density Dr must be in (0, 100] %, got {dr}")
    c1 = 7600.0 * dr ** -2.5
    return c1, 0.4 / c1


@register("reference_porosity", "byrne", params={"dr": DR_DEFAULT}, porosity_range=(0.0, 0.5),
          reference="Byrne (1991); Martin, Finn & Seed (1975)")
def byrne(dgamma: ArrayLike, gamma: ArrayLike, n_bar: ArrayLike, state: ShearState,
          dr: float = DR_DEFAULT, c1: float | None = None,
          c2: float | None = None) -> tuple[np.ndarray, ShearState]:
    """Byrne (1991) shear densification: n̄ falls as the skeleton is cycled.

    Per full cycle of amplitude γ_a the volumetric strain grows by
    Δε_v = C1 γ_a exp(−C2 ε_v/γ_a), C1 = 7600 Dr^−2.5 (Dr in %), C2 = 0.4/C1.
    Spread over the strain path (a cycle travels Σ|dγ| = 4 γ_a):

        dε_v = (C1/4) exp(−C2 ε_v/γ_a) |dγ|,   dn̄ = −(1 − n̄) dε_v,

    γ_a the peak |γ| since the last reversal. Both are integrated exactly over
    the step with γ_a held at its end-of-step value:
    ε_v ← ε_v + (γ_a/C2) ln[1 + (C1 C2/4)(|Δγ|/γ_a) exp(−C2 ε_v/γ_a)] and
    1 − n̄ ← (1 − n̄) exp(Δε_v). n̄ never increases.

    Parameters
    ----------
    dgamma, gamma : array_like
        Shear-strain increment of the step and strain at its end [-].
    n_bar : array_like
        Reference porosity before the step [-].
    state : ShearState
        Shear history before the step.
    dr : float
        Relative density [%] giving C1, C2 (ignored where ``c1`` is given).
    c1, c2 : float, optional
        Explicit constants [-]; ``c2`` defaults to 0.4/``c1``.

    Returns
    -------
    n_bar_new : ndarray
    state_new : ShearState

    >>> s = ShearState.zeros(1)
    >>> nb, s = byrne([1e-4], [1e-4], [0.5], s, dr=40.0)
    >>> round(float(s.eps_v[0]) * 1e6, 3)  # (γ_a/C2) ln(1 + 0.1) for a first step of γ_a
    17.895
    >>> round(float((0.5 - nb[0]) * 1e6), 3)  # (1 − n̄) expm1(Δε_v)
    8.948

    Reference: Byrne, P. M. (1991), A cyclic shear-volume coupling and pore
    pressure model for sand, Proc. 2nd Int. Conf. Recent Adv. Geotech. Earthq.
    Eng. Soil Dyn., St. Louis, paper 1.24, 47–55.
    """
    if c1 is None:
        c1, c2_default = byrne_constants(dr)
    else:
        c2_default = 0.4 / c1
    c2 = c2_default if c2 is None else c2
    step, gamma, peak, direction, path = _kinematics(dgamma, gamma, state)
    active = (peak > 0.0) & (step > 0.0)
    safe = np.where(active, peak, 1.0)
    growth = 0.25 * c1 * c2 * (step / safe) * np.exp(-c2 * state.eps_v / safe)
    deps = np.where(active, safe / c2 * np.log1p(growth), 0.0)
    n_bar = np.asarray(n_bar, dtype=float)
    n_bar_new = n_bar - (1.0 - n_bar) * np.expm1(deps)
    return n_bar_new, ShearState(state.eps_v + deps, peak, gamma, direction, path)


@register("reference_porosity", "ann", params={}, porosity_range=(0.0, 0.5),
          reference="Pringle (2001) sec. 3.3.3 and app. 3.1; weights: scripts/train_ann.py")
def ann(dgamma: ArrayLike, gamma: ArrayLike, n_bar: ArrayLike, state: ShearState,
        weights: AnnWeights | str | None = None) -> tuple[np.ndarray, ShearState]:
    """Artificial neural network (3-3-1, logistic) for the new reference porosity.

    Inputs x = (log10 Σ|Δγ|, |Δγ|, n̄), each min–max normalised to [0, 1] with the
    ranges of the weights file (held at the range ends outside it); hidden layer
    V = σ(x̄ W_h + b_h), output Ȳ = σ(V·w_o + b_o), σ(v) = 1/(1 + e^−v).
    Ȳ is de-normalised to n̄_new over [Y_min, Y_max]: fixed bounds (thesis) or,
    for the shipped weights, Y_min = n̄ − r_max|Δγ|, Y_max = n̄ so that n̄ cannot
    rise and an unsheared element keeps its n̄ (see :class:`AnnWeights`).

    ``weights``: an :class:`AnnWeights`, a path to a JSON file, or None for the
    shipped ``data/ann/default_weights.json`` (trained on :func:`byrne`). A path is
    read and validated once, then reused while the file is unchanged (the law is
    called at every shear sub-step); callers in a loop may also pass the parsed
    :class:`AnnWeights` (:func:`load_weights`).

    >>> s = ShearState.zeros(1)
    >>> nb, s = ann([1e-4], [1e-4], [0.5], s)
    >>> bool(nb[0] < 0.5), float(ann([0.0], [1e-4], [0.5], s)[0][0])
    (True, 0.5)

    Reference: Pringle (2001), McMaster University, sec. 3.3.3 and appendix 3.1.
    """
    w = weights if isinstance(weights, AnnWeights) else _cached_weights(weights)
    step, gamma, peak, direction, path = _kinematics(dgamma, gamma, state)
    n_bar = np.asarray(n_bar, dtype=float)
    n_bar_new = w.predict(path, step, n_bar)
    return n_bar_new, ShearState(state.eps_v, peak, gamma, direction, path)


class AnnWeightsError(ValueError):
    """A weights file that cannot be used; the message names the file and the key."""


def _sigmoid(v):
    return 0.5 * (1.0 + np.tanh(0.5 * v))  # = 1/(1 + e^−v), without overflow


@dataclass(frozen=True)
class AnnWeights:
    """Weights, normalisation ranges and provenance of the 3-3-1 network.

    JSON layout (all keys required except ``provenance``)::

        {"format": "twofluid-ann-1",
         "inputs": ["log10_accumulated_shear_strain", "shear_strain_increment", "n_bar"],
         "input_min": [3 numbers], "input_max": [3 numbers],
         "hidden_weights": [[3 numbers] x 3 inputs],   # W_h[i][j], input i -> node j
         "hidden_bias": [3 numbers],
         "output_weights": [3 numbers], "output_bias": number,
         "output": {"mode": "absolute", "min": number, "max": number}
                or {"mode": "strain_scaled", "rate_max": number},
         "provenance": {...}}

    ``absolute`` is the thesis's de-normalisation n̄_new = Ȳ (Y_max − Y_min) + Y_min.
    ``strain_scaled`` uses Y_max = n̄ and Y_min = n̄ − rate_max |Δγ|, i.e.
    n̄_new = n̄ − (1 − Ȳ) rate_max |Δγ|: a fixed n̄ range cannot resolve the
    per-step changes (≈1e-6) a time-stepping model asks for, and this form keeps
    n̄ from rising and leaves unsheared elements alone.
    """

    input_min: np.ndarray
    input_max: np.ndarray
    hidden_weights: np.ndarray
    hidden_bias: np.ndarray
    output_weights: np.ndarray
    output_bias: float
    output: dict
    provenance: dict = field(default_factory=dict)
    source: str = ""

    def predict(self, path, step, n_bar) -> np.ndarray:
        """n̄_new from accumulated strain Σ|Δγ|, increment |Δγ| and n̄ (arrays)."""
        floor = 10.0 ** self.input_min[0]
        x = np.stack([np.log10(np.maximum(path, floor)), step, n_bar], axis=-1)
        xbar = np.clip((x - self.input_min) / (self.input_max - self.input_min), 0.0, 1.0)
        hidden = _sigmoid(xbar @ self.hidden_weights + self.hidden_bias)
        ybar = _sigmoid(hidden @ self.output_weights + self.output_bias)
        if self.output["mode"] == "absolute":
            return ybar * (self.output["max"] - self.output["min"]) + self.output["min"]
        return n_bar - (1.0 - ybar) * self.output["rate_max"] * step

    def to_json(self) -> dict:
        """The JSON-ready dictionary :func:`load_weights` reads."""
        return {"format": "twofluid-ann-1",
                "inputs": ["log10_accumulated_shear_strain", "shear_strain_increment", "n_bar"],
                "input_min": self.input_min.tolist(), "input_max": self.input_max.tolist(),
                "hidden_weights": self.hidden_weights.tolist(),
                "hidden_bias": self.hidden_bias.tolist(),
                "output_weights": self.output_weights.tolist(),
                "output_bias": float(self.output_bias), "output": dict(self.output),
                "provenance": dict(self.provenance)}


def _array(data: dict, key: str, shape: tuple[int, ...], where: str) -> np.ndarray:
    if key not in data:
        raise AnnWeightsError(f"{where}: missing key {key!r}")
    try:
        arr = np.asarray(data[key], dtype=float)
    except (TypeError, ValueError):
        raise AnnWeightsError(f"{where}: {key!r} must be numbers, got {data[key]!r}") from None
    if arr.shape != shape:
        raise AnnWeightsError(f"{where}: {key!r} must have shape {shape}, got {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise AnnWeightsError(f"{where}: {key!r} holds non-finite values")
    return arr


def weights_from_dict(data: dict, where: str = "<dict>") -> AnnWeights:
    """Validate a weights dictionary (the JSON layout of :class:`AnnWeights`)."""
    if not isinstance(data, dict):
        raise AnnWeightsError(f"{where}: top level must be a JSON object")
    lo = _array(data, "input_min", (3,), where)
    hi = _array(data, "input_max", (3,), where)
    if np.any(hi <= lo):
        raise AnnWeightsError(f"{where}: input_max must exceed input_min for every input")
    out = data.get("output")
    if not isinstance(out, dict) or out.get("mode") not in ("absolute", "strain_scaled"):
        raise AnnWeightsError(f"{where}: 'output' must be an object with mode "
                              "'absolute' or 'strain_scaled'")
    needed = ("min", "max") if out["mode"] == "absolute" else ("rate_max",)
    for key in needed:
        if not isinstance(out.get(key), (int, float)):
            raise AnnWeightsError(f"{where}: output.{key} must be a number")
    if out["mode"] == "absolute" and not out["max"] > out["min"]:
        raise AnnWeightsError(f"{where}: output.max must exceed output.min")
    if out["mode"] == "strain_scaled" and not out["rate_max"] > 0:
        raise AnnWeightsError(f"{where}: output.rate_max must be > 0")
    return AnnWeights(lo, hi, _array(data, "hidden_weights", (3, 3), where),
                      _array(data, "hidden_bias", (3,), where),
                      _array(data, "output_weights", (3,), where),
                      float(_array(data, "output_bias", (), where)), dict(out),
                      dict(data.get("provenance", {})), where)


def load_weights(path: str | Path | None = None) -> AnnWeights:
    """Read and validate a weights JSON file (None: the shipped default)."""
    if path is None:
        return _default_weights()
    path = Path(path)
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except json.JSONDecodeError as err:
        raise AnnWeightsError(f"{path}: not valid JSON (line {err.lineno}: {err.msg})") from None
    except UnicodeDecodeError:
        raise AnnWeightsError(f"{path}: not UTF-8 text (a weights file is JSON)") from None
    except FileNotFoundError:
        raise AnnWeightsError(f"{path}: no such file") from None
    except OSError as err:
        raise AnnWeightsError(f"{path}: cannot be read ({err.strerror or err})") from None
    return weights_from_dict(data, str(path))


def _cached_weights(path: str | Path | None) -> AnnWeights:
    """:func:`load_weights`, parsed once per file version (path, mtime, size)."""
    if path is None:
        return _default_weights()
    p = Path(path)
    try:
        st = p.stat()
    except OSError:
        return load_weights(p)  # raises the AnnWeightsError naming the file
    return _weights_version(str(p.resolve()), st.st_mtime_ns, st.st_size)


@lru_cache(maxsize=8)
def _weights_version(path: str, mtime_ns: int, size: int) -> AnnWeights:
    return load_weights(path)


@lru_cache(maxsize=1)
def _default_weights() -> AnnWeights:
    from importlib import resources  # (here: ~10 ms of imports that a run without the ANN closure does not pay)

    entry = resources.files("twofluid") / "data" / "ann" / DEFAULT_WEIGHTS
    return load_weights(Path(str(entry)))
