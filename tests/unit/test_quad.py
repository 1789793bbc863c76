"""Q1 element, quadrature, measure weight and the 2D weak-form terms."""

import numpy as np
import pytest
import scipy.sparse as sp

from twofluid.fem.quad import (Q1, FaceBasis, QuadBasis, SparsityPattern, element_dofs,
                               nodal_dofs)
from twofluid.fem.terms_2d import (body_force, checkerboard_penalty, divergence, mass,
                                   pressure_face_gradient, pressure_jump, viscous)
from twofluid.mesh.quad import QuadMesh, annular_sector, graded_points, rectangle


def distorted(axisymmetric=False, seed=0):
    """3 × 3 mesh on [1, 2] × [0, 1] with interior nodes moved randomly."""
    m = rectangle(1.0, 2.0, 0.0, 1.0, 3, 3, axisymmetric=axisymmetric)
    rng = np.random.default_rng(seed)
    inner = np.setdiff1d(np.arange(m.n_nodes), np.concatenate(
        [m.boundary_nodes(k) for k in ("left", "right", "bottom", "top")]))
    pts = m.points.copy()
    pts[inner] += rng.uniform(-0.08, 0.08, (inner.size, 2))
    return QuadMesh(pts, m.cells, m.boundaries, axisymmetric)


def test_partition_of_unity_and_gradients_sum_to_zero():
    el = Q1(3)
    xi = np.random.default_rng(1).uniform(-1, 1, (20, 2))
    assert np.allclose(el.shape(xi).sum(axis=1), 1.0, atol=1e-15)
    assert np.allclose(el.shape_grad(xi).sum(axis=1), 0.0, atol=1e-15)
    assert np.allclose(el.shape(el.nodes), np.eye(4))          # Kronecker property
    b = QuadBasis(distorted())
    assert np.allclose(b.dN.sum(axis=2), 0.0, atol=1e-12)


def test_bilinear_field_and_linear_gradient_reproduced():
    m = distorted()
    b = QuadBasis(m)
    f = lambda x: 1.0 + 2.0 * x[..., 0] - 3.0 * x[..., 1]  # noqa: E731
    assert np.allclose(b.interpolate(f(m.points)), f(b.x), atol=1e-13)
    grad = np.einsum("eqad,ea->eqd", b.dN, f(m.points)[m.cells])
    assert np.allclose(grad, [2.0, -3.0], atol=1e-12)


@pytest.mark.parametrize("a,bexp", [(0, 0), (2, 3), (3, 1)])
def test_gauss_2x2_integrates_cubics_exactly(a, bexp):
    b = QuadBasis(rectangle(0.0, 2.0, 1.0, 3.0, 3, 2))
    exact = (2.0 ** (a + 1) / (a + 1)) * ((3.0 ** (bexp + 1) - 1.0) / (bexp + 1))
    assert b.integrate(b.x[..., 0] ** a * b.x[..., 1] ** bexp) == pytest.approx(exact, rel=1e-13)


def test_axisymmetric_volume_of_annulus():
    r_i, r_o, h = 0.02, 0.05, 0.06
    b = QuadBasis(rectangle(r_i, r_o, 0.0, h, 3, 5, axisymmetric=True, grading=(2.0, 0.5)))
    assert b.integrate(np.ones_like(b.dx)) == pytest.approx(np.pi * (r_o**2 - r_i**2) * h, rel=1e-13)
    # ∫ r dV = 2π h (r_o³ − r_i³)/3: the 2πr weight really is in dx
    assert b.integrate(b.radius) == pytest.approx(2 * np.pi * h * (r_o**3 - r_i**3) / 3, rel=1e-13)


def test_mass_matrix_sums_to_volume():
    m = distorted(axisymmetric=True)
    b = QuadBasis(m)
    assert mass(b, 1600.0).sum() == pytest.approx(1600.0 * b.dx.sum(), rel=1e-13)


def test_viscous_rigid_motions_do_no_work():
    bp = QuadBasis(distorted())
    Kp = viscous(bp, 1.0, 3)
    x, y = bp.mesh.points.T
    for u in ([np.ones_like(x), 0 * x, 0 * x], [0 * x, np.ones_like(x), 0 * x],
              [-y, x, 0 * x], [0 * x, 0 * x, np.ones_like(x)]):
        v = np.concatenate(u)[nodal_dofs(bp.mesh.cells, bp.mesh.n_nodes, 3)]
        assert np.abs(np.einsum("eij,ej->ei", Kp, v)).max() < 1e-12
    ba = QuadBasis(distorted(axisymmetric=True))
    Ka = viscous(ba, 1.0, 3)
    r = ba.mesh.points[:, 0]
    # axial translation and rigid rotation u_θ = ω r are strain free; u_r = const is not (hoop)
    for u, free in (([0 * r, 1 + 0 * r, 0 * r], True), ([0 * r, 0 * r, 3 * r], True),
                    ([1 + 0 * r, 0 * r, 0 * r], False)):
        v = np.concatenate(u)[nodal_dofs(ba.mesh.cells, ba.mesh.n_nodes, 3)]
        work = np.einsum("ei,eij,ej->", v, Ka, v)
        assert (abs(work) < 1e-12) == free


def test_viscous_energy_of_simple_shear_and_swirl():
    # u_x = y on [0,1]²: τ_xy = μ, dissipation ∫ τ:∇u = μ |Ω|
    b = QuadBasis(rectangle(0, 1, 0, 1, 2, 2))
    v = np.concatenate([b.mesh.points[:, 1], 0 * b.mesh.points[:, 0]])
    v = v[nodal_dofs(b.mesh.cells, b.mesh.n_nodes, 2)]
    assert np.einsum("ei,eij,ej->", v, viscous(b, 2.5), v) == pytest.approx(2.5)
    # u_θ = r z in 1 < r < 2, 0 < z < 1: ∂u_θ/∂r − u_θ/r = 0, ∂u_θ/∂z = r,
    # dissipation μ ∫ r² 2πr dr dz = 7.5 π μ (the −u_θ/r term must cancel ∂u_θ/∂r)
    ba = QuadBasis(rectangle(1.0, 2.0, 0.0, 1.0, 2, 2, axisymmetric=True))
    r, z = ba.mesh.points.T
    v = np.concatenate([0 * z, 0 * z, r * z])[nodal_dofs(ba.mesh.cells, ba.mesh.n_nodes, 3)]
    assert np.einsum("ei,eij,ej->", v, viscous(ba, 1.0, 3), v) == pytest.approx(7.5 * np.pi)


@pytest.mark.parametrize("axi", [False, True])
def test_divergence_includes_hoop_term(axi):
    m = distorted(axisymmetric=axi)
    b = QuadBasis(m)
    x = m.points
    u = np.concatenate([x[:, 0], x[:, 1]])[nodal_dofs(m.cells, m.n_nodes, 2)]
    # u = (x, y): ∇·u = 2 planar; u = (r, z): ∇·u = 1 + 1 + 1 = 3 axisymmetric
    div = np.einsum("ea,ea->e", divergence(b), u)
    assert np.allclose(div, (3.0 if axi else 2.0) * b.dx.sum(axis=1), rtol=1e-12)


@pytest.mark.parametrize("axi", [False, True])
def test_face_gradient_equals_weak_divergence_on_interior_dofs(axi):
    """Σ_F ∫ [[p]] ν·δu = −∫ p ∇·δu for δu vanishing on the boundary (P0 p)."""
    m = distorted(axisymmetric=axi)
    n, ne = m.n_nodes, m.n_elements
    p = np.random.default_rng(3).normal(size=ne)
    D = sp.coo_matrix((divergence(QuadBasis(m)).ravel(),
                       (np.repeat(np.arange(ne), 8), nodal_dofs(m.cells, n, 2).ravel())),
                      shape=(ne, 2 * n)).toarray()
    G, nodes = pressure_face_gradient(FaceBasis(m))
    rows = nodal_dofs(nodes, n, 2)
    Gp = np.bincount(rows.ravel(), np.einsum("fij,fj->fi", G, p[FaceBasis(m).elements]).ravel(),
                     minlength=2 * n)
    bnd = np.unique(np.concatenate([m.boundary_nodes(k) for k in ("left", "right", "bottom", "top")]))
    interior = np.setdiff1d(np.arange(n), bnd)
    dofs = np.concatenate([interior, n + interior])
    assert np.allclose(Gp[dofs], -(D.T @ p)[dofs], atol=1e-12)


def test_body_force_total():
    b = QuadBasis(distorted(axisymmetric=True))
    F = body_force(b, [0.0, -1600 * 9.81], 2)
    assert F[:, 4:].sum() == pytest.approx(-1600 * 9.81 * b.dx.sum(), rel=1e-13)
    assert np.abs(F[:, :4]).max() == 0.0


def test_sparsity_pattern_matches_coo_sum_and_reuses_indices():
    m = distorted()
    b = QuadBasis(m)
    ud = nodal_dofs(m.cells, m.n_nodes, 2)
    pd = element_dofs(m.n_elements, 2 * m.n_nodes)
    size = 2 * m.n_nodes + m.n_elements
    pat = SparsityPattern([(ud, ud), (pd, ud)], (size, size))
    K, D = viscous(b, 1.0), divergence(b)[:, None, :]
    for scale in (1.0, 2.0):           # same pattern, new values
        A = pat.assemble([scale * K, D])
        rows = np.concatenate([np.repeat(ud, 8, axis=1).ravel(), np.repeat(pd, 8, axis=1).ravel()])
        cols = np.concatenate([np.tile(ud, (1, 8)).ravel(), np.tile(ud, (1, 1)).ravel()])
        ref = sp.coo_matrix((np.concatenate([(scale * K).ravel(), D.ravel()]), (rows, cols)),
                            shape=(size, size)).toarray()
        assert np.allclose(A.toarray(), ref, atol=1e-13)


def test_checkerboard_penalty_sees_only_the_checkerboard():
    m = rectangle(0.0, 1.0, 0.0, 1.0, 4, 4)
    C, el = checkerboard_penalty(QuadBasis(m), 0.25, 1.0)
    xc = m.points[m.cells].mean(axis=1)
    lin = 3.0 + 2.0 * xc[:, 0] - 5.0 * xc[:, 1]
    assert np.abs(np.einsum("pab,pb->pa", C, lin[el])).max() < 1e-13
    i, j = np.meshgrid(np.arange(4), np.arange(4))
    s = ((-1.0) ** (i + j)).ravel()
    energy = np.einsum("pa,pab,pb->", s[el], C, s[el])
    # on square elements it equals the local jump term on the checkerboard
    Cj = pressure_jump(FaceBasis(m), 0.25, 1.0, local=True)
    fe = FaceBasis(m).elements
    assert energy == pytest.approx(np.einsum("fa,fab,fb->", s[fe], Cj, s[fe]), rel=1e-12)
    assert energy > 0


def test_meshes():
    m = annular_sector(0.5, 1.0, np.pi / 3, 4, 6)
    assert np.allclose(np.hypot(*m.points[m.boundary_nodes("inner")].T), 0.5)
    assert np.allclose(np.arctan2(*m.points[m.boundary_nodes("end")].T[::-1]), np.pi / 3)
    assert np.all(QuadBasis(m).detJ > 0)
    g = graded_points(0.0, 1.0, 5, ratio=4.0)
    d = np.diff(g)
    assert d[-1] / d[0] == pytest.approx(4.0) and g[-1] == pytest.approx(1.0)
    r = rectangle(0.0, 1.0, 0.0, 1.0, 3, 2)
    assert r.patches is None and rectangle(0, 1, 0, 1, 4, 2).patches is not None
    edges, el = r.interior_edges()
    assert edges.shape[0] == 2 * 2 + 3 * 1
    with pytest.raises(ValueError):
        QuadBasis(QuadMesh(r.points, r.cells[:, ::-1]))          # clockwise cells
