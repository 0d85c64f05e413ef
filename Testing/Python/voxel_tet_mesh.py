"""A stand-in FE mesh for a closed surface while no real mesher is at hand: the cubes of a
regular grid whose centres lie inside the surface (VTK's vtkSelectEnclosedPoints), each
split into 6 conforming (Kuhn) tets; for tet10, boundary mid-edge nodes moved part of the
way to the surface (VTK's vtkCellLocator) so that the boundary is curved.

Used by the embedding tests and Benchmarks/bench_embedding.py. Not a quality mesher: the
boundary is a voxel staircase, so surface vertices lie up to about one cube away from it.
"""

import itertools

import numpy as np
import pyvista as pv
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import reference
from vtkmodules.vtkCommonDataModel import vtkCellLocator
from vtkmodules.vtkFiltersModeling import vtkSelectEnclosedPoints


def _inside(surface, points):
    sel = vtkSelectEnclosedPoints()
    sel.SetSurfaceData(surface)
    probe = pv.PolyData(np.array(points, dtype=float), deep=True)  # kept alive until Update
    sel.SetInputData(probe)
    sel.SetTolerance(1e-9)
    sel.Update()
    return vtk_to_numpy(sel.GetOutput().GetPointData().GetArray("SelectedPoints")).astype(bool)


def _valid(grid):
    """True when hoembed accepts every element (det J > 0 everywhere, Bernstein bound)."""
    import hoembed

    try:
        hoembed.embed(pv.PolyData(np.array(grid.points[:1], dtype=float), deep=True), grid)
        return True
    except hoembed.HOEmbedError:
        return False


def voxel_tet_mesh(surface, n_elements=1000, order=2, curve_fraction=0.5):
    """About ``n_elements`` tets (6 per cube) inside the closed ``surface``.

    Returns a pyvista.UnstructuredGrid of VTK_QUADRATIC_TETRA (order 2) or VTK_TETRA. The
    boundary mid-edge nodes move ``curve_fraction`` of the way to the surface (at most a
    quarter cube); the fraction is halved until every element is valid."""
    fraction = curve_fraction
    while True:
        grid = _voxel_tet_mesh(surface, n_elements, order, fraction)
        if order != 2 or fraction < 0.01 or _valid(grid):
            return grid
        fraction *= 0.5


def _voxel_tet_mesh(surface, n_elements, order, curve_fraction):
    surface = pv.wrap(surface).triangulate()
    lo = np.array(surface.bounds[0::2])
    hi = np.array(surface.bounds[1::2])
    h = (6.0 * abs(surface.volume) / n_elements) ** (1.0 / 3.0)
    for _ in range(6):  # adjust h so that the cube count is near the target
        n = np.maximum(np.ceil((hi - lo) / h).astype(int), 1)
        origin = lo - 0.5 * (n * h - (hi - lo))
        idx = np.stack(np.meshgrid(*[np.arange(k) for k in n], indexing="ij"), -1).reshape(-1, 3)
        keep = _inside(surface, origin + (idx + 0.5) * h)
        count = 6 * keep.sum()
        if count > 0 and abs(count - n_elements) < 0.15 * n_elements:
            break
        h *= (count / n_elements) ** (1.0 / 3.0) if count > 0 else 0.7
    cubes = idx[keep]
    nx, ny, nz = n + 1

    def gid(c):
        return (c[..., 2] * ny + c[..., 1]) * nx + c[..., 0]

    tets = []
    for perm in itertools.permutations(range(3)):
        steps = [np.zeros(3, int)]
        for a in perm:
            s = steps[-1].copy()
            s[a] = 1
            steps.append(s)
        corner = np.array(steps, dtype=float)
        det = np.linalg.det(corner[1:] - corner[0])
        t = np.stack([gid(cubes + s) for s in steps], axis=1)
        if det < 0:
            t[:, [1, 2]] = t[:, [2, 1]]
        tets.append(t)
    tets = np.concatenate(tets)
    used, inverse = np.unique(tets, return_inverse=True)
    tets = inverse.reshape(tets.shape)
    lattice = np.stack([used % nx, (used // nx) % ny, used // (nx * ny)], axis=1)
    points = origin + lattice * h
    if order == 2:
        edges = np.array([(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)])
        pairs = np.sort(tets[:, edges], axis=2).reshape(-1, 2)
        uniq, einv = np.unique(pairs, axis=0, return_inverse=True)
        mids = 0.5 * (points[uniq[:, 0]] + points[uniq[:, 1]])
        mid_ids = len(points) + einv.reshape(-1, 6)
        # boundary faces -> boundary mid nodes
        faces = np.array([(0, 1, 3), (1, 2, 3), (2, 0, 3), (0, 2, 1)])
        fk = np.sort(tets[:, faces], axis=2).reshape(-1, 3)
        fu, fcount = np.unique(fk, axis=0, return_counts=True)
        bnodes = set(map(tuple, fu[fcount == 1].tolist()))
        bedge = set()
        for a, b, c in bnodes:
            bedge.update({(min(a, b), max(a, b)), (min(b, c), max(b, c)), (min(a, c), max(a, c))})
        on_boundary = np.array([tuple(e) in bedge for e in uniq.tolist()])
        if curve_fraction > 0 and on_boundary.any():
            loc = vtkCellLocator()
            loc.SetDataSet(surface)
            loc.BuildLocator()
            cp = [0.0, 0.0, 0.0]
            cid, sub, d2 = reference(0), reference(0), reference(0.0)
            for i in np.where(on_boundary)[0]:
                loc.FindClosestPoint(mids[i], cp, cid, sub, d2)
                move = np.asarray(cp) - mids[i]
                ln = np.linalg.norm(move)
                if ln > 0:
                    mids[i] += curve_fraction * move * min(1.0, 0.25 * h / ln)
        points = np.vstack([points, mids])
        conn = np.hstack([tets, mid_ids])
        ctype = pv.CellType.QUADRATIC_TETRA
    else:
        conn = tets
        ctype = pv.CellType.TETRA
    cells = np.hstack([np.full((len(conn), 1), conn.shape[1]), conn]).ravel()
    return pv.UnstructuredGrid(
        cells.astype(np.int64), np.full(len(conn), ctype, dtype=np.uint8), points, deep=True
    )


def linear_copy(grid10):
    """The tet4 mesh on the corner nodes of a tet10 grid (same corner numbering)."""
    conn = grid10.cells.reshape(-1, 11)[:, 1:5]
    used, inv = np.unique(conn, return_inverse=True)
    cells = np.hstack([np.full((len(conn), 1), 4), inv.reshape(-1, 4)]).ravel()
    return pv.UnstructuredGrid(
        cells.astype(np.int64),
        np.full(len(conn), pv.CellType.TETRA, dtype=np.uint8),
        grid10.points[used],
        deep=True,
    )
