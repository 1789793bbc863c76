"""Exact displacements of a one-way rigid sliding block under single pulses (Newmark 1965).

The block slides (relative velocity v ≥ 0) while the driving acceleration a(t) exceeds the
yield acceleration a_y > 0 or while v > 0, with v̇ = a(t) − a_y, and is at rest otherwise. Its
final displacement d = ∫ v dt has closed forms for

- a **rectangular pulse** a = A for 0 ≤ t < T, then 0 (A > a_y): the block accelerates at A − a_y
  to v = (A − a_y) T, then decelerates at a_y and stops after v/a_y, so

      d = (A − a_y) T²/2 + (A − a_y)² T²/(2 a_y) = A (A − a_y) T²/(2 a_y)      (Newmark 1965);

- a **half-sine pulse** a = A sin(ωt) for 0 ≤ t ≤ π/ω, then 0 (A > a_y): sliding starts at
  t₁ = asin(a_y/A)/ω, and

      v(t) = (A/ω)(cos ωt₁ − cos ωt) − a_y (t − t₁),
      d(t) = (A/ω) cos ωt₁ (t − t₁) − (A/ω²)(sin ωt − sin ωt₁) − a_y (t − t₁)²/2

  while the pulse lasts; if v(π/ω) > 0 the block then stops after v(π/ω)/a_y and
  d = d(π/ω) + v(π/ω)²/(2 a_y); otherwise it stops at the root t₂ of v in (π/ω − t₁, π/ω] (v
  decreases there, a < a_y), found by bisection to round-off, and d = d(t₂).

These are the references for :func:`twofluid.geotech.lateral_spread.newmark_sliding`.
"""
from __future__ import annotations

import math

__all__ = ["rectangular_pulse_displacement", "half_sine_pulse_displacement"]


def rectangular_pulse_displacement(a_pulse: float, duration_s: float, a_yield: float) -> float:
    """Final displacement d = A (A − a_y) T²/(2 a_y) [m] of a block under a rectangular pulse.

    A [m/s²] pulse height, T [s] its duration, a_y [m/s²] > 0; d = 0 when A ≤ a_y.

    >>> rectangular_pulse_displacement(2.0, 1.0, 1.0)      # 2 * 1 * 1 / 2
    1.0
    """
    if a_yield <= 0.0:
        raise ValueError("a_yield must be > 0 m/s^2")
    if a_pulse <= a_yield:
        return 0.0
    return a_pulse * (a_pulse - a_yield) * duration_s ** 2 / (2.0 * a_yield)


def half_sine_pulse_displacement(a_pulse: float, omega: float, a_yield: float) -> float:
    """Final displacement [m] of a block under a = A sin(ωt), 0 ≤ t ≤ π/ω (module docstring).

    A [m/s²], ω [rad/s] > 0, a_y [m/s²] > 0; 0 when A ≤ a_y.

    Hand value, A = 2, ω = π, a_y = 1: ωt₁ = π/6, v(1) = (2/π)(cos 30° + 1) − 5/6 = 0.354615,
    d(1) = (2/π)(√3/2)(5/6) − (2/π²)(0 − 1/2) − (5/6)²/2 = 0.459441 + 0.101321 − 0.347222
    = 0.213540, d = 0.213540 + 0.354615²/2 = 0.276416:

    >>> round(half_sine_pulse_displacement(2.0, math.pi, 1.0), 6)
    0.276416
    """
    if a_yield <= 0.0 or omega <= 0.0:
        raise ValueError("a_yield and omega must be > 0")
    if a_pulse <= a_yield:
        return 0.0
    t1 = math.asin(a_yield / a_pulse) / omega
    c1 = math.cos(omega * t1)
    s1 = math.sin(omega * t1)

    def vel(t):
        return a_pulse / omega * (c1 - math.cos(omega * t)) - a_yield * (t - t1)

    def disp(t):
        return (a_pulse / omega * c1 * (t - t1) - a_pulse / omega ** 2 * (math.sin(omega * t) - s1)
                - 0.5 * a_yield * (t - t1) ** 2)

    t_end = math.pi / omega
    v_end = vel(t_end)
    if v_end > 0.0:
        return disp(t_end) + v_end * v_end / (2.0 * a_yield)
    lo, hi = t_end - t1, t_end          # v > 0 at lo (its maximum), v <= 0 at hi
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if vel(mid) > 0.0:
            lo = mid
        else:
            hi = mid
        if hi - lo <= 1e-16 * t_end:
            break
    return disp(0.5 * (lo + hi))
