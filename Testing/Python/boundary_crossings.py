"""Independent check that the curved boundary of a tet10 mesh does not cross itself:
every boundary tri6 face is subdivided with VTK's own vtkQuadraticTriangle shape
functions, and VTK's vtkCollisionDetectionFilter (OBB trees) finds the touching pairs of
sub-triangles; pairs of faces that share a corner node are legitimate contacts."""

import numpy as np
import pyvista as pv
from vtkmodules.vtkCommonDataModel import vtkQuadraticTriangle
from vtkmodules.vtkCommonMath import vtkMatrix4x4
from vtkmodules.vtkFiltersModeling import vtkCollisionDetectionFilter

# tri6 nodes of the four faces of a VTK quadratic tetra (corners, then mids 01, 12, 20)
FACES6 = [(0, 1, 3, 4, 8, 7), (1, 2, 3, 5, 9, 8), (2, 0, 3, 6, 7, 9), (0, 2, 1, 6, 5, 4)]


def boundary_faces6(grid):
    """(n, 6) node ids of the faces seen by one cell."""
    conn = grid.cells.reshape(grid.n_cells, -1)[:, 1:]
    f6 = conn[:, FACES6].reshape(-1, 6)
    key = np.sort(f6[:, :3], axis=1)
    _, inv, count = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    return f6[count[inv.ravel()] == 1]


def _subdivision(level):
    """Parametric points and sub-triangles of a uniform split into 4**level pieces."""
    n = 2**level
    idx, pts = {}, []
    for j in range(n + 1):
        for i in range(n + 1 - j):
            idx[i, j] = len(pts)
            pts.append((i / n, j / n, 0.0))
    tris = []
    for j in range(n):
        for i in range(n - j):
            tris.append((idx[i, j], idx[i + 1, j], idx[i, j + 1]))
            if i + j < n - 1:
                tris.append((idx[i + 1, j], idx[i + 1, j + 1], idx[i, j + 1]))
    return np.array(pts), np.array(tris)


def crossing_face_pairs(grid, level=3):
    """Pairs of boundary faces (not sharing a corner) whose curved shapes intersect."""
    faces = boundary_faces6(grid)
    pc, sub = _subdivision(level)
    w = np.empty((len(pc), 6))
    for k, p in enumerate(pc):
        vtkQuadraticTriangle.InterpolationFunctions(list(p), w[k])
    X = np.einsum("pk,fkd->fpd", w, grid.points[faces])  # (faces, points, 3)
    npts = len(pc)
    points = X.reshape(-1, 3)
    tris = (np.arange(len(faces))[:, None, None] * npts + sub[None]).reshape(-1, 3)
    parent = np.repeat(np.arange(len(faces)), len(sub))
    surf = pv.PolyData(points, np.hstack([np.full((len(tris), 1), 3), tris]).ravel())
    col = vtkCollisionDetectionFilter()
    col.SetInputData(0, surf)
    col.SetInputData(1, surf.copy())
    col.SetMatrix(0, vtkMatrix4x4())
    col.SetMatrix(1, vtkMatrix4x4())
    col.SetCollisionModeToAllContacts()
    col.SetBoxTolerance(0.0)
    col.SetCellTolerance(0.0)
    col.Update()
    a = np.array(
        [col.GetContactCells(0).GetValue(i) for i in range(col.GetNumberOfContacts())], int
    )
    b = np.array(
        [col.GetContactCells(1).GetValue(i) for i in range(col.GetNumberOfContacts())], int
    )
    fa, fb = parent[a], parent[b]
    out = set()
    for x, y in zip(fa, fb):
        if x == y or np.intersect1d(faces[x, :3], faces[y, :3]).size:
            continue
        out.add((min(x, y), max(x, y)))
    return sorted(out)
