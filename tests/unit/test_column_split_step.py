"""The liquefaction column's split step after its shear sub-steps in one compiled call
(models.column_step_kernel.vertical_step with its arguments from ``check`` on, through
models.column_split and LiquefactionColumn._split_step).

The call makes the vertical step (the same as ReducedVerticalColumn.fast_step) and then what the
column's Python did after it: the solids outflow, dn/dt for the next shear step's interpolation, the
next shear step's mixture density and viscosity and σ′_v of the new state. The run must be the same, bit for bit, as the
one without the call (the vertical step alone compiled, the rest in NumPy), also where the call
hands steps back; its plain Python (``TWOFLUID_DISABLE_JIT=1``) and its compiled form agree to
round-off; a non-finite shear result is refused before anything is written.
"""
from __future__ import annotations

import copy
import inspect

import numpy as np
import pytest

from twofluid.casefile.loader import load_case
from twofluid.models import column_step_kernel as csk
from twofluid.models.liquefaction_1d import LiquefactionColumn
from twofluid.runners.liquefaction import _Recorder, build_column  # (_Recorder: what a run keeps)

_SPLIT_ARGS = LiquefactionColumn._split_args
_ARG = {name: i for i, name in enumerate(inspect.signature(csk.vertical_step).parameters)}  # argument positions


def _column(duration: float = 1.0, free_vibration: float = 1.0):
    c = load_case("liquefaction-layered-site")  # the hysteretic law, a crust, two sands
    c["output"]["plots"], c["ground_motion"]["duration"] = False, duration
    c["shear_wave"]["free_vibration"] = free_vibration
    return build_column(c)


def _run(monkeypatch, fused: bool, fail_every: int = 0, t_end: float = 5.0):
    """Every step of a short run (shaking, free vibration, the floor's step, reconsolidation with
    growing steps): the step's numbers and the wave properties its shear sub-steps used; and how
    many split steps were made and handed back."""
    b = _column()
    col = b.column
    counts = {"made": 0, "back": 0}
    calls = [0]

    def split_args(self):
        fixed = _SPLIT_ARGS(self)
        if not fused or fixed is None:
            return None
        ker = fixed[0]

        def counted(*a):
            calls[0] += 1
            code = csk.NOT_CONVERGED if fail_every and calls[0] % fail_every == 0 else ker(*a)
            counts["made" if code == csk.OK else "back"] += 1
            return code
        return (counted, *fixed[1:])

    monkeypatch.setattr(LiquefactionColumn, "_split_args", split_args)
    rows = []
    for step in col.run(b.state, t_end, b.dt, b.dt_after):
        s = step.state
        v, w = s.vertical, s.wave
        rows.append(((v.t, step.iterations, step.substeps, step.solids_inflow, step.surface),
                     (v.V, v.W, v.n, v.P, v.n_bar, w.u, w.v, w.a, w.gamma, w.tau, s.shear, col._ndot.copy(),
                      col.wave.rho.copy(), col.wave.eta.copy(), col.granular_pressure(s))))
    assert col.shear_end < t_end  # (the run went past the floor's step)
    return rows, counts


def _same(ref, got):
    assert len(got) == len(ref) > 100
    for (r0, r1), (g0, g1) in zip(ref, got):
        assert r0 == g0
        for a, b in zip(r1, g1):
            np.testing.assert_array_equal(a, b)


def test_the_split_step_makes_the_same_run_bit_for_bit(monkeypatch):
    if csk.compiled() is None:
        pytest.skip("no compiled kernels here")
    ref, off = _run(monkeypatch, fused=False)
    got, on = _run(monkeypatch, fused=True)
    assert off["made"] == 0
    assert on["made"] > 0.9 * len(got)
    _same(ref, got)


def test_a_split_step_the_call_cannot_make_goes_back_to_the_python_path(monkeypatch):
    """Told it did not converge on every seventh call, the column takes the stepper and its own
    NumPy for those steps (and the wave properties of the step after), and makes the same run."""
    if csk.compiled() is None:
        pytest.skip("no compiled kernels here")
    ref, _ = _run(monkeypatch, fused=False)
    got, counts = _run(monkeypatch, fused=True, fail_every=7)
    assert counts["back"] >= len(got) // 7 > 10
    _same(ref, got)


def test_plain_and_compiled_split_steps_agree(monkeypatch):
    """Each compiled call of a short run repeated by the plain Python function on copies of its
    arguments: the same code and outputs to 1e-12 (relative to each output's largest entry)."""
    ker = csk.compiled()
    if ker is None or ker is csk.vertical_step:
        pytest.skip("no compiled kernel here (or the JIT is disabled: the plain function is the kernel)")
    checked = [0]

    def split_args(self):
        fixed = _SPLIT_ARGS(self)

        def both(*args):
            mine = copy.deepcopy(args)
            code = ker(*args)
            assert csk.vertical_step(*mine) == code
            if code == csk.OK:  # the outflow, dn/dt, ρ, η, σ′_v; the vertical step's [V, W, n] and P
                for name in ("out_s", "ndot", "wrho", "weta", "ps", "a_out", "P_out"):
                    a, b = args[_ARG[name]], mine[_ARG[name]]
                    scale = max(float(np.abs(a).max()), 1e-300)
                    assert np.all(np.abs(a - b) <= 1e-12 * scale)
                checked[0] += 1
            return code
        return (both, *fixed[1:])

    monkeypatch.setattr(LiquefactionColumn, "_split_args", split_args)
    b = _column(duration=0.3, free_vibration=0.2)
    for _ in b.column.run(b.state, 0.8, b.dt, b.dt_after):
        pass
    assert checked[0] > 20


@pytest.mark.parametrize("where", ["n_bar", "u"])
def test_a_non_finite_shear_result_is_refused_before_anything_is_written(where, monkeypatch):
    """With the check on, a NaN in the new n̄ or in the displacements returns NOT_FINITE_SHEAR and
    leaves every output as it was (the column then says which step failed, as without the call)."""
    b = _column(duration=0.2)
    col = b.column
    captured = {}

    def split_args(self):
        fixed = _SPLIT_ARGS(self)
        if fixed is None:
            pytest.skip("no compiled kernels here")

        def keep(*args):
            captured.setdefault("args", copy.deepcopy(args))
            return fixed[0](*args)
        return (keep, *fixed[1:])

    monkeypatch.setattr(LiquefactionColumn, "_split_args", split_args)
    next(iter(col.run(b.state, 0.2, b.dt, b.dt_after)))
    args = list(captured["args"])
    assert args[_ARG["check"]] is True  # (level ground, no flow rule: the check is the call's)
    i = _ARG["onb" if where == "n_bar" else "u"]
    args[i] = args[i].copy()
    args[i][args[i].size // 2] = np.nan
    before = copy.deepcopy(args)
    assert csk.vertical_step(*args) == csk.NOT_FINITE_SHEAR
    for a, b0 in zip(args, before):
        if isinstance(a, np.ndarray):
            np.testing.assert_array_equal(a, b0)


def _outputs(monkeypatch, tmp_path, fused: bool, name: str) -> dict:
    """Every output file of a short run of the layered site (``summary.json`` without its wall times)."""
    import json

    from twofluid.runners.liquefaction import run_liquefaction

    if not fused:
        monkeypatch.setattr(LiquefactionColumn, "_split_args", lambda self: None)
    recorders = []
    init = _Recorder.__init__

    def kept(self, *a):
        init(self, *a)
        recorders.append(self)

    monkeypatch.setattr(_Recorder, "__init__", kept)
    c = load_case("liquefaction-layered-site")
    c["output"]["plots"], c["ground_motion"]["duration"] = False, 1.0
    c["shear_wave"]["free_vibration"], c["time"]["end"] = 1.0, 6.0
    c["output"]["times"] = [1.0, 3.0]
    res = run_liquefaction(c, tmp_path / name)
    monkeypatch.undo()
    files = {}
    for f in sorted((tmp_path / name).iterdir()):
        if f.name == "summary.json":
            files[f.name] = {k: v for k, v in json.loads(f.read_text()).items() if "wall" not in k}
        elif not f.name.startswith("."):
            files[f.name] = f.read_bytes()
    r = recorders[0]  # and what the run kept in memory, exactly (the files' numbers have 10 digits)
    files["record"] = [np.array(getattr(r, k), dtype=float) for k in (
        "t", "ru", "sig", "settle", "pbase", "ru_top", "flux_top", "field", "peak", "t_peak", "first", "ever",
        "peak_strain", "max_contribution", "ps", "last_contribution")]
    return files, res


def test_a_runs_outputs_are_the_same_with_and_without_the_split_step(monkeypatch, tmp_path):
    """Every output file of a run (and what it keeps in memory for the summary and figures: r_u, its
    peaks and first times, σ′_v, the settlement, the strains' peaks) is the same, byte for byte, as
    the run's without the compiled split step."""
    if csk.compiled() is None:
        pytest.skip("no compiled kernels here")
    made = [0]
    real = LiquefactionColumn._split_step

    def counted(self, *a):
        out = real(self, *a)
        made[0] += out is not None
        return out

    ref, res_ref = _outputs(monkeypatch, tmp_path, False, "ref")
    monkeypatch.setattr(LiquefactionColumn, "_split_step", counted)
    got, res = _outputs(monkeypatch, tmp_path, True, "got")
    assert made[0] > 100  # (every step but the floor's and those the stepper halves)
    assert res.status == res_ref.status == "completed"
    assert set(got) == set(ref) and "probes.csv" in got
    for k in ref:
        if k == "record":
            for a, b in zip(ref[k], got[k]):
                np.testing.assert_array_equal(a, b)
        else:
            assert got[k] == ref[k], k
