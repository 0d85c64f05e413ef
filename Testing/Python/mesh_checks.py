"""Independent checks of a tet10/tet4 mesh against its fine surface (VTK + numpy only)."""

import hoembed
import numpy as np
import pytest
import pyvista as pv
from vtkmodules.vtkCommonCore import reference
from vtkmodules.vtkCommonDataModel import vtkCellLocator, vtkGenericCell
from vtkmodules.vtkFiltersCore import vtkMassProperties, vtkTriangleFilter
from vtkmodules.vtkFiltersGeneral import vtkCellValidator

EDGES = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]
FACES = [(0, 1, 3), (1, 2, 3), (2, 0, 3), (0, 2, 1)]


def cells(grid):
    """Connectivity as an (n_cells, nodes_per_cell) array."""
    c = grid.cells.reshape(grid.n_cells, -1)
    return c[:, 1:]


def boundary_mid_nodes(grid):
    """Mid-edge nodes on boundary faces (faces seen by one cell), from the connectivity."""
    conn = cells(grid)
    faces = {}
    for cid, c in enumerate(conn):
        for f in FACES:
            key = tuple(sorted(c[list(f)]))
            faces[key] = faces.get(key, 0) + 1
    bface = {k for k, v in faces.items() if v == 1}
    mids = set()
    for c in conn:
        for e, (a, b) in enumerate(EDGES):
            for f in bface:
                if c[a] in f and c[b] in f:
                    mids.add(int(c[4 + e]))
                    break
    return np.array(sorted(mids))


def distances_to_surface(surface, points):
    """Unsigned distance of each point to the triangle surface (vtkCellLocator)."""
    loc = vtkCellLocator()
    loc.SetDataSet(surface)
    loc.BuildLocator()
    cell = vtkGenericCell()
    out = np.empty(len(points))
    cp = [0.0, 0.0, 0.0]
    cid, sub, d2 = reference(0), reference(0), reference(0.0)
    for i, p in enumerate(points):
        loc.FindClosestPoint(list(p), cp, cell, cid, sub, d2)
        out[i] = np.sqrt(float(d2))
    return out


def surface_volume(surface):
    tri = vtkTriangleFilter()
    tri.SetInputData(surface)
    mp = vtkMassProperties()
    mp.SetInputConnection(tri.GetOutputPort())
    mp.Update()
    return mp.GetVolume()


def tet10_volumes(grid):
    """Volume of each tet10 by quadrature of det J (a cubic, integrated exactly by the
    64-point conical-product Gauss rule)."""
    conn = cells(grid)
    X = grid.points[conn]  # (n, 10, 3)
    pts, w = _quadrature_degree5()  # noqa: N806
    vol = np.zeros(len(conn))
    for p, wi in zip(pts, w):
        dN = _tet10_derivs(p)  # (3, 10)
        J = np.einsum("nai,ja->nij", X, dN)
        vol += wi * np.linalg.det(J)
    return vol


def straight_volumes(grid):
    X = grid.points[cells(grid)[:, :4]]
    return np.linalg.det(X[:, 1:] - X[:, :1]) / 6.0


def _tet10_derivs(p):
    r, s, t = p
    L0 = 1 - r - s - t
    a0 = 1 - 4 * L0
    dr = [a0, 4 * r - 1, 0, 0, 4 * (L0 - r), 4 * s, -4 * s, -4 * t, 4 * t, 0]
    ds = [a0, 0, 4 * s - 1, 0, -4 * r, 4 * r, 4 * (L0 - s), -4 * t, 0, 4 * t]
    dt = [a0, 0, 0, 4 * t - 1, -4 * r, 0, -4 * s, 4 * (L0 - t), 4 * r, 4 * s]
    return np.array([dr, ds, dt])


def _quadrature_degree5():
    """Conical-product (Duffy) Gauss rule with 4 points per direction on the unit tet:
    exact for polynomials of degree 7, so for the cubic det J."""
    g, gw = np.polynomial.legendre.leggauss(4)
    x = (g + 1) / 2
    wx = gw / 2
    pts, w = [], []
    for i in range(4):
        for j in range(4):
            for k in range(4):
                a, b, c = x[i], x[j], x[k]
                r = a
                s = b * (1 - a)
                t = c * (1 - a) * (1 - b)
                pts.append((r, s, t))
                w.append(wx[i] * wx[j] * wx[k] * (1 - a) ** 2 * (1 - b))
    return np.array(pts), np.array(w)


def vtk_cell_validator_states(grid):
    """vtkCellValidator state per cell (0 = valid)."""
    v = vtkCellValidator()
    v.SetInputData(grid)
    v.Update()
    out = pv.wrap(v.GetOutput())
    return np.asarray(out.cell_data["ValidityState"])


def straight_scaled_jacobian(grid):
    """vtkMeshQuality's scaled Jacobian of every cell's straight tet (its 4 corners)."""
    from vtkmodules.vtkFiltersVerdict import vtkMeshQuality

    straight = pv.UnstructuredGrid({pv.CellType.TETRA: cells(grid)[:, :4]}, grid.points)
    mq = vtkMeshQuality()
    mq.SetInputData(straight)
    mq.SetTetQualityMeasureToScaledJacobian()
    mq.Update()
    return np.asarray(pv.wrap(mq.GetOutput()).cell_data["Quality"])


def min_det_sampled(grid, n=200, seed=0):
    """Minimum det J over random points of every tet10 (a sample, not a bound)."""
    rng = np.random.default_rng(seed)
    p = rng.random((4 * n, 3))
    p = p[p.sum(1) <= 1][:n]
    p = np.vstack([p, [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]])
    conn = cells(grid)
    X = grid.points[conn]
    out = np.full(len(conn), np.inf)
    for q in p:
        J = np.einsum("nai,ja->nij", X, _tet10_derivs(q))
        out = np.minimum(out, np.linalg.det(J))
    return out


def expect_error(surface, *words):
    """tet10_mesh(surface) raises HOEmbedError naming the function and every one of
    `words`; returns the message."""
    with pytest.raises(hoembed.HOEmbedError) as info:
        hoembed.tet10_mesh(surface, n_elements=200)
    msg = str(info.value)
    assert msg.startswith("tet10_mesh: "), msg
    for w in words:
        assert w in msg, msg
    return msg
