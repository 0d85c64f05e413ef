"""hoembed.embed / hoembed.transfer and the VTK filters on hexahedral meshes:
VTK_LAGRANGE_HEXAHEDRON of order 1-3, VTK_TRIQUADRATIC_HEXAHEDRON and
VTK_QUADRATIC_HEXAHEDRON, built from VTK's own node positions (GetParametricCoords of
VTK's cells), checked with VTK's own cells (EvaluateLocation) and a sampled boundary:
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

KINDS = {  # name: (VTK type, node count)
    "lagrange-1": (72, 8),
    "lagrange-2": (72, 27),
    "lagrange-3": (72, 64),
    "hex27": (29, 27),
    "hex20": (25, 20),
}


def vtk_cell(kind):
    vtk_type, npc = KINDS[kind]
    if vtk_type == 72:
        cell = dm.vtkLagrangeHexahedron()
        cell.SetUniformOrderFromNumPoints(npc)
    elif vtk_type == 29:
        cell = dm.vtkTriQuadraticHexahedron()
    else:
        cell = dm.vtkQuadraticHexahedron()
    cell.GetPointIds().SetNumberOfIds(npc)
    cell.GetPoints().SetNumberOfPoints(npc)
    cell.Initialize()
    return cell


def hex_box(kind, n=2, amplitude=0.1):
    """n^3 unit cubes as cells of `kind`, nodes at VTK's parametric positions shared
    through their lattice position, then curved."""
    vtk_type, npc = KINDS[kind]
    cell = vtk_cell(kind)
    pc = np.array([cell.GetParametricCoords()[i] for i in range(3 * npc)]).reshape(-1, 3)
    scale = 6  # a lattice holding every order's node positions (1/1, 1/2, 1/3)
    keys, conn = {}, []
    for cube in np.ndindex(n, n, n):
        ids = []
        for p in pc:
            key = tuple(np.rint(scale * (np.array(cube) + p)).astype(int))
            ids.append(keys.setdefault(key, len(keys)))
        conn.append(ids)
    points = np.zeros((len(keys), 3))
    for key, i in keys.items():
        points[i] = np.array(key, float) / scale
    x, y, z = points.T.copy()
    points[:, 0] += amplitude * np.sin(1.3 * y + 0.5 * z)
    points[:, 1] += amplitude * np.sin(1.1 * z + 0.7 * x)
    points[:, 2] += amplitude * np.sin(0.9 * x + 0.6 * y)
    conn = np.array(conn)
    cells = np.column_stack([np.full(len(conn), npc), conn]).ravel()
    return pv.UnstructuredGrid(cells, np.full(len(conn), vtk_type, np.uint8), points)


def vtk_location(kind, mesh, cell_id, pcoords):
    cell = vtk_cell(kind)
    ids = mesh.cells.reshape(mesh.n_cells, -1)[cell_id, 1:]
    for k, i in enumerate(ids):
        cell.GetPointIds().SetId(k, k)
        cell.GetPoints().SetPoint(k, mesh.points[i])
    x = [0.0, 0.0, 0.0]
    w = [0.0] * len(ids)
    cell.EvaluateLocation(vtkCommonCore.reference(0), list(pcoords), x, w)
    return np.array(x)


def boundary_samples(kind, mesh, n=2, per_face=8):
    """Points of the curved boundary (the box's faces), by VTK's cell."""
    out = []
    grid = np.linspace(0, 1, per_face + 1)
    for c, cube in enumerate(np.ndindex(n, n, n)):
        for axis in range(3):
            for side in (0, n - 1):
                if cube[axis] != side:
                    continue
                for u in grid:
                    for v in grid:
                        pc = np.zeros(3)
                        pc[axis] = 1.0 if side == n - 1 else 0.0
                        pc[(axis + 1) % 3], pc[(axis + 2) % 3] = u, v
                        out.append(vtk_location(kind, mesh, c, pc))
    return np.array(out)


@pytest.fixture(scope="module", params=list(KINDS))
def case(request):
    mesh = hex_box(request.param)
    surface = pv.Sphere(radius=1.35, center=(1.0, 1.0, 1.0), theta_resolution=10, phi_resolution=8)
    surface.points = surface.points.astype(np.float64)  # the transfer writes the input's type
    return request.param, mesh, surface


def test_routes_agree_and_points_rebuilt(case):
    kind, mesh, surface = case
    check_routes_agree_and_points_rebuilt(
        mesh, surface, lambda c, pc: vtk_location(kind, mesh, c, pc), boundary_samples(kind, mesh)
    )


def test_rigid_transfer(case):
    _, mesh, surface = case
    check_rigid_transfer(mesh, surface)


def test_mixed_mesh_refused(case):
    kind, mesh, surface = case
    types = np.array(mesh.celltypes)
    types[1] = 29 if types[0] != 29 else 72
    mixed = pv.UnstructuredGrid(mesh.cells, types, mesh.points)
    with pytest.raises(hoembed.HOEmbedError, match="embed.*mixes cell types"):
        hoembed.embed(surface, mixed)
    with pytest.raises(
        hoembed.HOEmbedError, match="vtkEmbeddingCoordinatesFilter.*mixes cell types"
    ):
        filter_embed(surface, mixed)


def test_non_uniform_degrees_refused():
    """HigherOrderDegrees (1, 3, 7) on a 64-node cell: as many nodes as order 3, refused by
    every route rather than read as order 3."""
    mesh = hex_box("lagrange-3")
    surface = pv.Sphere(radius=1.35, center=(1.0, 1.0, 1.0), theta_resolution=6, phi_resolution=5)
    degrees = np.full((mesh.n_cells, 3), 3.0)
    degrees[2] = (1, 3, 7)
    mesh.cell_data["HigherOrderDegrees"] = degrees
    mesh.GetCellData().SetHigherOrderDegrees(mesh.GetCellData().GetArray("HigherOrderDegrees"))
    with pytest.raises(hoembed.HOEmbedError, match=r"embed.*cell 2.*orders \(1, 3, 7\)"):
        hoembed.embed(surface, mesh)
    with pytest.raises(hoembed.HOEmbedError, match=r"vtkEmbeddingCoordinatesFilter.*cell 2"):
        filter_embed(surface, mesh)
    degrees[2] = 3
    mesh.cell_data["HigherOrderDegrees"] = degrees
    mesh.GetCellData().SetHigherOrderDegrees(mesh.GetCellData().GetArray("HigherOrderDegrees"))
    assert hoembed.embed(surface, mesh).n_points == surface.n_points
