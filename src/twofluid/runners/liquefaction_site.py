"""A layered site as the column's arrays: mesh, per-element soil, crust, and what to report per layer.

The ``[[layers]]`` of a ``liquefaction_1d`` case run from the ground surface down; the column's
elements run from the base up. The saturated layers (below the water table) make the vertical
two-component model's mesh; the crust layers above it are added on top for the shear wave only
(their weight reaches the vertical model as a surcharge at the water table).

Hydraulic conductivity: a layer given ``hydraulic_conductivity`` k gets the equivalent diameter d
at which the case's drag law gives k = ρ_f g n²/β at zero slip. For Ergun (and Gidaspow below its
switch) β(0) = 150 μ_f (1 − n)²/(n d²), Kozeny–Carman with 150:
d = √(150 μ_f (1 − n)² k / (ρ_f g n³)). Every bundled law has β(0) ∝ 1/d², so
d = d₁ √(β(d₁)/β_k) is exact for any trial d₁; it is iterated twice to be safe for any law.
"""
from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..casefile import schema_liquefaction as sl
from ..casefile.builder import closures
from ..closures import drag as drag_laws
from ..closures import hysteretic as law
from ..closures.shear_modulus import seed_idriss_gmax, tabulated_curve
from ..mesh.line import LineMesh
from ..models.liquefaction_1d import Crust, Sand
from ..models.shear_column import piecewise_reduction
from ..models.two_fluid_1d import Closures, Materials

__all__ = ["Site", "site_arrays", "equivalent_diameter", "sand_for", "crust_for"]


@dataclass
class Site:
    """Arrays of a layered site (saturated elements bottom first, then the crust bottom first)."""

    mesh: LineMesh  # saturated layers, y up from the base [m]
    mat: Materials  # d_p per saturated element
    clo: Closures  # A, p_ref per saturated element
    porosity: np.ndarray  # initial n per saturated element
    layer_of: np.ndarray  # index into case["layers"] per saturated element
    crust_layer_of: np.ndarray  # per crust element (bottom first)
    crust_h: np.ndarray  # crust element sizes [m] (bottom first)
    crust_weight: float  # Σ γ t of the crust [Pa]
    depth_top: np.ndarray  # per layer: depth of its top below the ground surface [m]
    depth_bottom: np.ndarray


def _mesh_of(layers, index) -> tuple[np.ndarray, np.ndarray]:
    """Vertex heights above the base and layer index per element, of the layers ``index``
    (top-down indices), elements bottom first."""
    y, owner = [0.0], []
    for i in reversed(index):
        la = layers[i]
        ne = sl.layer_elements(la)
        y.extend(y[-1] + np.linspace(0.0, la["thickness"], ne + 1)[1:])
        owner += [i] * ne
    return np.array(y), np.array(owner, dtype=int)


def equivalent_diameter(law, params: dict, n: float, k: float, rho_f: float, mu_f: float, g: float) -> float:
    """Diameter d [m] at which ``law`` gives hydraulic conductivity ``k`` [m/s] at porosity n.

    >>> from twofluid.closures.drag import ergun
    >>> d = equivalent_diameter(ergun, {}, 0.4, 1e-3, 1000.0, 1e-3, 9.81)
    >>> round(d * 1e6, 3)  # √(150 μ (1 − n)² k / (ρ g n³)) [µm]
    293.273
    """
    beta_k = rho_f * g * n * n / k
    d = 1e-3
    for _ in range(3):
        d = d * np.sqrt(float(law(n, 0.0, d, rho_f, mu_f, **params)) / beta_k)
    return float(d)


def site_arrays(case: dict) -> Site:
    """Mesh, materials and closures (per-element arrays) of the saturated layers, and the crust."""
    layers, ma = case["layers"], case["materials"]
    sat = sl.saturated(case)
    wet = [i for i, s in enumerate(sat) if s]
    dry = [i for i, s in enumerate(sat) if not s]
    y, owner = _mesh_of(layers, wet)
    yc, crust_owner = _mesh_of(layers, dry)
    # on a slope the column stands normal to the ground surface: gravity along it is g cos α
    mesh = LineMesh(y, np.ones_like(y), float(np.arctan(case["site"].get("slope", 0.0) / 100.0)))
    n_layer = {i: sl.layer_porosity(layers[i]) for i in wet}
    n = np.array([n_layer[i] for i in owner])
    # closures of the case with the first saturated layer's numbers, then per-element arrays
    first = layers[wet[0]]
    scalar = Materials(rho_f=ma["liquid_density"], mu_f=ma["liquid_viscosity"], rho_s=ma["particle_density"],
                       d_p=first["particle_diameter"] or 1e-3, sphericity=ma["sphericity"], g=ma["gravity"])
    view = dict(case, _skeleton={"compressibility": first["compressibility"], "p_ref": first["p_ref"]})
    clo = closures(view, scalar, pressure_section="_skeleton")
    d_p = {}
    for i in wet:
        la = layers[i]
        if la["particle_diameter"] > 0.0:
            d_p[i] = la["particle_diameter"]
        else:
            d = equivalent_diameter(clo.drag, clo.drag_params, n_layer[i], la["hydraulic_conductivity"],
                                    scalar.rho_f, scalar.mu_f, scalar.g)
            d_p[i] = d / scalar.sphericity
    mat = replace(scalar, d_p=np.array([d_p[i] for i in owner]))
    # the drag law's slip saturation (3 terminal velocities) of the finest layer: one scalar
    factor = case["closures"]["drag"]["slip_saturation"]
    slip_max = min(drag_laws.slip_limit(clo.drag, factor, scalar.sphericity * d_p[i], scalar.rho_s,
                                        scalar.rho_f, scalar.mu_f, scalar.g, **clo.drag_params) for i in wet)
    clo = replace(clo, A=np.array([layers[i]["compressibility"] for i in owner]),
                  p_ref=np.array([layers[i]["p_ref"] for i in owner]), slip_max=slip_max)
    tops = np.cumsum([0.0] + [la["thickness"] for la in layers])
    return Site(mesh, mat, clo, n, owner, crust_owner, np.diff(yc),
                float(sum(layers[i]["unit_weight"] * layers[i]["thickness"] for i in dry)),
                tops[:-1], tops[1:])


def _reduction(case, source, owner, gamma_ref_default=None):
    """Per-element G/G_max of the elements of ``owner`` (layer per element): None if every layer is
    hyperbolic (the ``gamma_ref`` array serves), else one piecewise curve."""
    tables = {i: sl.load_reduction_table(case, source, i) for i in set(owner.tolist())}
    if all(t is None for t in tables.values()):
        return None
    if len(tables) == 1:  # one curve for every element: any array of strains
        return tabulated_curve(*next(iter(tables.values())))
    from ..closures.shear_modulus import hyperbolic

    parts = []
    for i, table in tables.items():
        idx = np.flatnonzero(owner == i)
        ref = case["layers"][i]["gamma_ref"]
        parts.append((idx, tabulated_curve(*table) if table is not None else (lambda g, r=ref: hyperbolic(g, r))))
    return piecewise_reduction(parts, owner.size)


def sand_for(case: dict, source: str, site: Site, sigma_v0: np.ndarray) -> Sand:
    """The per-element :class:`Sand` of the saturated layers (σ′_v0 [Pa] sets K2max from V_s)."""
    layers, owner = case["layers"], site.layer_of

    def per(key):
        return np.array([layers[i][key] for i in owner], dtype=float)

    k2max = per("k2max")
    vs = per("shear_wave_velocity")
    if np.any(vs > 0.0):  # G_max = ρ V_s² at rest, then ∝ √P_s: K2max from σ′_v0
        mat = site.mat
        rho = site.porosity * mat.rho_f + (1.0 - site.porosity) * mat.rho_s
        k2 = rho * vs * vs / seed_idriss_gmax(sigma_v0, 1.0)
        k2max = np.where(vs > 0.0, k2, k2max)
    groups, laws = [], {}
    for i in sorted(set(owner.tolist())):
        la = layers[i]
        weights = sl.load_ann_weights(case, source, i)
        key = (la["reference_porosity_law"], id(weights) if weights is not None else None)
        laws.setdefault(key, ([], {"weights": weights} if weights is not None else {}))[0].append(i)
    if len(laws) > 1:
        groups = tuple((np.isin(owner, idx), law, params) for (law, _), (idx, params) in laws.items())
    (law, _), (_, params) = next(iter(laws.items()))
    return Sand(k2max=k2max, gamma_ref=per("gamma_ref"), dr=per("relative_density"), law=law,
                law_params=params, reduction=_reduction(case, source, owner),
                gamma_law_max=per("gamma_law_max"), viscosity=per("viscosity"),
                viscosity_exponent=np.array([layers[i]["viscosity_exponent"]
                                             if layers[i]["viscosity_law"] == "power_law" else 1.0
                                             for i in owner]),
                viscosity_reference_rate=per("viscosity_reference_rate"),
                liquefiable=np.array([layers[i]["liquefiable"] for i in owner], dtype=bool),
                law_groups=groups)


def crust_for(case: dict, source: str, site: Site) -> Crust | None:
    """The crust elements' thickness, density, G_max and G/G_max (None without a crust).

    σ′_v at a crust element's centre is the surcharge plus the crust weight above it, so
    G_max = 218.8 K2max √(σ′_v/1 kPa) kPa, or ρ V_s² with ρ = γ/g.
    """
    owner = site.crust_layer_of
    if owner.size == 0:
        return None
    layers, g = case["layers"], case["materials"]["gravity"]
    h = site.crust_h
    gam = np.array([layers[i]["unit_weight"] for i in owner])
    load = gam * h
    above = np.cumsum(load[::-1])[::-1] - load  # elements are bottom first
    sig = case["site"]["surcharge"] + above + 0.5 * load
    slope = case["site"].get("slope", 0.0)
    if slope > 0.0:  # the normal stress on a slope-parallel plane: the weight's component cos α
        sig = sig * float(np.cos(np.arctan(slope / 100.0)))
    vs = np.array([layers[i]["shear_wave_velocity"] for i in owner])
    k2 = np.array([layers[i]["k2max"] for i in owner])
    rho = gam / g
    g_max = np.where(vs > 0.0, rho * vs * vs, seed_idriss_gmax(sig, 1.0) * k2)
    return Crust(h, rho, g_max, gamma_ref=np.array([layers[i]["gamma_ref"] for i in owner]),
                 reduction=_reduction(case, source, owner), sigma_v=sig)


def hysteretic_parameters(case: dict, site: Site, sigma_v0: np.ndarray, crust: Crust | None,
                          k2max: np.ndarray) -> np.ndarray | None:
    """The hysteretic law's parameters of every shear-column element (saturated first, then the
    crust; :func:`twofluid.models.hysteretic_sand.parameters`), or None for the thesis model.

    A saturated element's soil comes from its layer's n160cs, else qc1ncs, else relative_density;
    σ′_v0 is its geostatic effective stress. A crust element keeps its G_max and σ′_v fixed. A layer
    without ``gqh_theta`` (``mrdf``) gets the GQ/H backbone (MRDF factor) fitted to Menq's curves at
    the σ′_v of its middle element, with that element's strength and G_max."""
    if case["shear_wave"]["model"] != "hysteretic":
        return None
    from ..models.hysteretic_sand import menq_fit, parameters

    layers = case["layers"]

    def per(owner, key):
        return np.array([layers[i][key] for i in owner], dtype=float)

    def positive(x):
        return np.where(x > 0.0, x, np.nan)

    def rows(owner, sig, k2, liquefiable, g_fix):
        par = parameters(sigma_v0=sig, n160cs=positive(per(owner, "n160cs")),
                         qc1ncs=positive(per(owner, "qc1ncs")), dr=per(owner, "relative_density"),
                         k2max=k2, friction_angle=positive(per(owner, "friction_angle")),
                         csr_n_slope=positive(per(owner, "csr_n_slope")),
                         liquefiable=liquefiable, g_max_fixed=g_fix)
        for i in sorted(set(owner.tolist())):
            idx = np.flatnonzero(owner == i)
            mid = idx[idx.size // 2]
            la = layers[i]
            theta, mrdf = la["gqh_theta"], la["mrdf"]
            if not theta or not mrdf:
                g_max = par[mid, law.P_GMAXFIX] if par[mid, law.P_GMAXFIX] > 0.0 else \
                    float(seed_idriss_gmax(sig[mid], par[mid, law.P_K2]))
                th_fit, p_fit, _ = menq_fit(sig[mid], par[mid, law.P_TANPHI], g_max)
                theta = theta or th_fit
                mrdf = mrdf or p_fit
            par[idx, law.P_TH1:law.P_TH5 + 1] = theta
            par[idx, law.P_P1:law.P_P3 + 1] = mrdf
        return par

    owner = site.layer_of
    par = rows(owner, sigma_v0, k2max, np.array([layers[i]["liquefiable"] for i in owner], dtype=float), 0.0)
    if crust is None:
        return par
    c_owner = site.crust_layer_of
    top = rows(c_owner, np.maximum(crust.sigma_v, 1.0), per(c_owner, "k2max"), 0.0, crust.g_max)
    return np.concatenate([par, top])
