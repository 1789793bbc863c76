"""Reading quadrilateral meshes with named boundary groups through meshio."""

import meshio
import numpy as np
import pytest

from twofluid.fem.quad import QuadBasis
from twofluid.mesh.gmsh_io import MeshError, read_quad_mesh

# two unit squares side by side, an unused geometry point (node 7), the second quad
# written clockwise; physical curves "inlet" (x = 0) and "wall" (y = 0)
MSH22 = """$MeshFormat
2.2 0 8
$EndMeshFormat
$PhysicalNames
3
1 1 "inlet"
1 2 "wall"
2 3 "fluid"
$EndPhysicalNames
$Nodes
7
1 0 0 0
2 1 0 0
3 2 0 0
4 0 1 0
5 1 1 0
6 2 1 0
7 5 5 0
$EndNodes
$Elements
5
1 1 2 1 1 1 4
2 1 2 2 2 1 2
3 1 2 2 2 2 3
4 3 2 3 1 1 2 5 4
5 3 2 3 1 2 5 6 3
$EndElements
"""

MSH41 = """$MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
3
1 1 "inlet"
1 2 "wall"
2 3 "fluid"
$EndPhysicalNames
$Entities
0 2 1 0
1 0 0 0 0 1 0 1 1 0
2 0 0 0 2 0 0 1 2 0
1 0 0 0 2 1 0 1 3 0
$EndEntities
$Nodes
1 6 1 6
2 1 0 6
1
2
3
4
5
6
0 0 0
1 0 0
2 0 0
0 1 0
1 1 0
2 1 0
$EndNodes
$Elements
3 5 1 5
1 1 1 1
1 1 4
1 2 1 2
2 1 2
3 2 3
2 1 3 2
4 1 2 5 4
5 2 3 6 5
$EndElements
"""


def check(mesh):
    assert mesh.n_nodes == 6 and mesh.n_elements == 2
    assert np.all(QuadBasis(mesh).detJ > 0)                  # clockwise cell reordered
    inlet = mesh.points[mesh.boundary_nodes("inlet")]
    assert np.allclose(inlet[:, 0], 0.0) and len(inlet) == 2
    assert mesh.boundary_edges("wall").shape == (2, 2)
    assert np.allclose(mesh.points[mesh.boundary_nodes("wall"), 1], 0.0)


@pytest.mark.parametrize("text", [MSH22, MSH41], ids=["msh2.2", "msh4.1"])
def test_reads_gmsh_physical_groups(tmp_path, text):
    f = tmp_path / "two.msh"
    f.write_text(text)
    m = read_quad_mesh(f, require=["inlet", "wall"])
    check(m)
    assert set(m.boundaries) == {"inlet", "wall"}


def test_axisymmetric_flag(tmp_path):
    f = tmp_path / "two.msh"
    f.write_text(MSH41)
    m = read_quad_mesh(f, axisymmetric=True)
    assert m.axisymmetric
    assert QuadBasis(m).dx.sum() == pytest.approx(np.pi * 2.0**2 * 1.0)


def test_reads_cell_sets():
    pts = np.array([[0, 0], [1, 0], [2, 0], [0, 1], [1, 1], [2, 1]], float)
    mesh = meshio.Mesh(pts, [("quad", [[0, 1, 4, 3], [1, 2, 5, 4]]),
                             ("line", [[0, 3], [0, 1], [1, 2]])],
                       cell_sets={"inlet": [[], [0]], "wall": [[], [1, 2]]})
    check(read_quad_mesh(mesh))


def test_missing_group_names_file(tmp_path):
    f = tmp_path / "two.msh"
    f.write_text(MSH22)
    with pytest.raises(MeshError, match=r"two\.msh.*outlet"):
        read_quad_mesh(f, require=["inlet", "outlet"])


def test_unsupported_cells_name_file(tmp_path):
    f = tmp_path / "tri.msh"
    meshio.Mesh(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0.0]]),
                [("triangle", [[0, 1, 2]])]).write(f, file_format="gmsh22")
    with pytest.raises(MeshError, match=r"tri\.msh.*triangle"):
        read_quad_mesh(f)
    with pytest.raises(MeshError, match="nothing.msh"):
        read_quad_mesh(tmp_path / "nothing.msh")
    assert issubclass(MeshError, ValueError)
