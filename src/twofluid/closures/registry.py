"""Registry of closures: ``(kind, name) -> Closure``.

A closure is a pure, vectorised function (arrays in, arrays out). Each is
registered under a *kind* (``"drag"``, ``"viscosity"``, ``"solids_pressure"``,
``"shear_modulus"``, ``"modulus_reduction"``, ``"reference_porosity"``, ``"granular_rheology"``,
``"permeability"``) and a
*name* chosen by case files (``[closures.drag] law = "wen_yu"``).

The registry records, per entry, the parameters the law accepts (with
defaults), the porosity and particle Reynolds number ranges where it is valid
(for a drag law also those of its Stokes limit, ``stokes = true``) and a one-line
summary taken from the docstring, so the CLI can list them, tests can exercise
every entry and a case used outside a law's range gets a warning
(:mod:`twofluid.casefile.validity`).

>>> from twofluid.closures import registry
>>> "wen_yu" in registry.names("drag")
True
>>> registry.get("drag", "wen_yu").summary.startswith("Wen")
True
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable

__all__ = ["Closure", "register", "get", "names", "kinds", "entries"]


@dataclass(frozen=True)
class Closure:
    """One registered constitutive law."""

    kind: str
    name: str
    func: Callable[..., Any]
    params: dict[str, float] = field(default_factory=dict)
    porosity_range: tuple[float, float] = (0.0, 1.0)
    reference: str = ""
    reynolds_range: tuple[float, float] = (0.0, math.inf)  # particle Re = ρ_f n |U_f − U_s| d/μ_f
    stokes_reynolds_range: tuple[float, float] | None = None  # the same for the Stokes limit (drag)

    def valid_reynolds(self, stokes: bool = False) -> tuple[float, float]:
        """The particle Reynolds number range [-] of the law (of its Stokes limit if ``stokes``).

        >>> from twofluid.closures import registry
        >>> registry.get("drag", "wen_yu").valid_reynolds(stokes=True)
        (0.0, 1.0)
        """
        if stokes and self.stokes_reynolds_range is not None:
            return self.stokes_reynolds_range
        return self.reynolds_range

    @property
    def summary(self) -> str:
        doc = (self.func.__doc__ or "").strip()
        return doc.splitlines()[0] if doc else ""


_REGISTRY: dict[tuple[str, str], Closure] = {}


def register(kind: str, name: str, *, params: dict[str, float] | None = None,
             porosity_range: tuple[float, float] = (0.0, 1.0), reference: str = "",
             reynolds_range: tuple[float, float] = (0.0, math.inf),
             stokes_reynolds_range: tuple[float, float] | None = None):
    """Decorator adding ``func`` to the registry under ``(kind, name)`` with its validity ranges."""

    def deco(func):
        key = (kind, name)
        if key in _REGISTRY:
            raise ValueError(f"closure {kind}/{name} registered twice")
        _REGISTRY[key] = Closure(kind, name, func, dict(params or {}), porosity_range, reference,
                                 tuple(map(float, reynolds_range)),
                                 None if stokes_reynolds_range is None else tuple(map(float, stokes_reynolds_range)))
        return func

    return deco


def get(kind: str, name: str) -> Closure:
    """Return the closure ``kind/name``; ``KeyError`` names the valid choices."""
    try:
        return _REGISTRY[(kind, name)]
    except KeyError:
        raise KeyError(f"no {kind} closure named {name!r}; choose one of "
                       f"{', '.join(names(kind))}") from None


def names(kind: str) -> list[str]:
    """Names registered under ``kind``, sorted."""
    return sorted(n for k, n in _REGISTRY if k == kind)


def kinds() -> list[str]:
    return sorted({k for k, _ in _REGISTRY})


def entries() -> list[Closure]:
    return [_REGISTRY[k] for k in sorted(_REGISTRY)]
