"""hoembed.embed / hoembed.transfer and the VTK filters on VTK_LAGRANGE_TETRAHEDRON meshes
of order 3 and 4 (orders 1-2 are tet4/tet10 node for node), built from VTK's own node
positions (vtkLagrangeTetra.GetParametricCoords), checked with VTK's own cell
(EvaluateLocation) and a sampled boundary:
- the two routes (package function, VTK filter) give the same arrays;
- inside points are located exactly (VTK's interpolation at the stored coordinates);
- outside points: the closest distance is no more than any sampled boundary point's, and
  p + d n rebuilds the point (EmbeddingResidual <= 1e-10 of the diagonal);
- a rigid motion of the mesh moves the surface rigidly (1e-9 of the diagonal);
- a mixed mesh is refused with a sentence naming the function or filter."""

import hoembed
import numpy as np
import pytest
import pyvista as pv
import vtkmodules.vtkCommonCore as vtkCommonCore
import vtkmodules.vtkCommonDataModel as dm
from filter_routes import embed as filter_embed
from lagrange_checks import check_rigid_transfer, check_routes_agree_and_points_rebuilt

LAGRANGE_TETRA = 71


def lagrange_box(order, n=2, amplitude=0.1):
    """Kuhn tets of an n^3 box of unit cubes, with order-p nodes at VTK's parametric
    positions, shared through their lattice position, then curved."""
    cell = dm.vtkLagrangeTetra()
    npc = (order + 1) * (order + 2) * (order + 3) // 6
    cell.GetPointIds().SetNumberOfIds(npc)
    cell.GetPoints().SetNumberOfPoints(npc)
    cell.Initialize()
    pc = np.array([cell.GetParametricCoords()[i] for i in range(3 * npc)]).reshape(-1, 3)
    bary = np.column_stack([1 - pc.sum(axis=1), pc])
    keys, conn = {}, []
    for cube in np.ndindex(n, n, n):
        for perm in ((0, 1, 2), (0, 2, 1), (1, 0, 2), (1, 2, 0), (2, 0, 1), (2, 1, 0)):
            c = np.array(cube)
            corners = [c.copy()]
            for axis in perm:
                c = c.copy()
                c[axis] += 1
                corners.append(c)
            corners = np.array(corners)
            e = corners[1:] - corners[0]
            if np.linalg.det(e) < 0:
                corners[[1, 2]] = corners[[2, 1]]
            ids = []
            for b in bary:
                key = tuple(np.rint(order * (b @ corners)).astype(int))
                ids.append(keys.setdefault(key, len(keys)))
            conn.append(ids)
    points = np.zeros((len(keys), 3))
    for key, i in keys.items():
        points[i] = np.array(key, float) / order
    x, y, z = points.T.copy()
    points[:, 0] += amplitude * np.sin(1.3 * y + 0.5 * z)
    points[:, 1] += amplitude * np.sin(1.1 * z + 0.7 * x)
    points[:, 2] += amplitude * np.sin(0.9 * x + 0.6 * y)
    conn = np.array(conn)
    cells = np.column_stack([np.full(len(conn), npc), conn]).ravel()
    types = np.full(len(conn), LAGRANGE_TETRA, np.uint8)
    return pv.UnstructuredGrid(cells, types, points)


def vtk_location(mesh, cell_id, pcoords):
    cell = dm.vtkLagrangeTetra()
    ids = mesh.cells.reshape(mesh.n_cells, -1)[cell_id, 1:]
    cell.GetPointIds().SetNumberOfIds(len(ids))
    cell.GetPoints().SetNumberOfPoints(len(ids))
    for k, i in enumerate(ids):
        cell.GetPointIds().SetId(k, k)
        cell.GetPoints().SetPoint(k, mesh.points[i])
    cell.Initialize()
    x = [0.0, 0.0, 0.0]
    w = [0.0] * len(ids)
    cell.EvaluateLocation(vtkCommonCore.reference(0), list(pcoords), x, w)
    return np.array(x)


def boundary_samples(mesh, per_face=6):
    """Points of the curved boundary, by VTK's cell at parametric points of its faces."""
    conn = mesh.cells.reshape(mesh.n_cells, -1)[:, 1:5]
    faces = [[0, 1, 3], [1, 2, 3], [2, 0, 3], [0, 2, 1]]
    corner_pc = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    count = {}
    for c in range(mesh.n_cells):
        for f in faces:
            count.setdefault(tuple(sorted(conn[c, f])), []).append((c, f))
    out = []
    for owners in count.values():
        if len(owners) != 1:
            continue
        c, f = owners[0]
        for i in range(per_face + 1):
            for j in range(per_face + 1 - i):
                u, v = i / per_face, j / per_face
                pc = (1 - u - v) * corner_pc[f[0]] + u * corner_pc[f[1]] + v * corner_pc[f[2]]
                out.append(vtk_location(mesh, c, pc))
    return np.array(out)


@pytest.fixture(scope="module", params=[3, 4])
def case(request):
    mesh = lagrange_box(request.param)
    surface = pv.Sphere(radius=1.35, center=(1.0, 1.0, 1.0), theta_resolution=10, phi_resolution=8)
    surface.points = surface.points.astype(np.float64)  # the transfer writes the input's type
    return request.param, mesh, surface


def test_routes_agree_and_points_rebuilt(case):
    order, mesh, surface = case
    check_routes_agree_and_points_rebuilt(
        mesh, surface, lambda c, pc: vtk_location(mesh, c, pc), boundary_samples(mesh)
    )


def test_rigid_transfer(case):
    _, mesh, surface = case
    check_rigid_transfer(mesh, surface)


def test_mixed_mesh_refused(case):
    order, mesh, surface = case
    mixed = mesh.copy()
    types = np.array(mixed.celltypes)
    types[1] = 24
    mixed = pv.UnstructuredGrid(mixed.cells, types, mixed.points)
    with pytest.raises(hoembed.HOEmbedError, match="embed.*mixes cell types"):
        hoembed.embed(surface, mixed)
    with pytest.raises(
        hoembed.HOEmbedError, match="vtkEmbeddingCoordinatesFilter.*mixes cell types"
    ):
        filter_embed(surface, mixed)


def test_order_two_is_tet10():
    """VTK_LAGRANGE_TETRAHEDRON of order 2 is VTK_QUADRATIC_TETRA node for node: the same
    embedding, array for array (only the mesh fingerprint names the cell type)."""
    lagrange = lagrange_box(2)
    tet10 = pv.UnstructuredGrid(
        lagrange.cells, np.full(lagrange.n_cells, 24, np.uint8), lagrange.points
    )
    surface = pv.Sphere(radius=1.35, center=(1.0, 1.0, 1.0), theta_resolution=10, phi_resolution=8)
    a, b = hoembed.embed(surface, lagrange), hoembed.embed(surface, tet10)
    for name in (
        "EmbeddingCellId",
        "EmbeddingParametricCoords",
        "EmbeddingDistance",
        "EmbeddingClosestDistance",
        "EmbeddingResidual",
    ):
        assert np.array_equal(a[name], b[name]), name
