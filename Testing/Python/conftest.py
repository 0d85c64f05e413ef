"""Shared pytest fixtures: the real-mesh folder and small generated meshes."""

import itertools
import os
import pathlib

import numpy as np
import pytest
import pyvista as pv

_DEFAULT_DATA = pathlib.Path(__file__).resolve().parents[2].parent / "shared" / "data" / "meshes"


@pytest.fixture(scope="session")
def data_dir():
    """../shared/data/meshes (or $HOEMBED_DATA_DIR); the test is skipped when absent."""
    path = pathlib.Path(os.environ.get("HOEMBED_DATA_DIR") or _DEFAULT_DATA)
    if not path.is_dir():
        pytest.skip(f"real meshes not available ({path})")
    return path


def box_tet_mesh(n=(4, 2, 2), size=(4.0, 1.0, 1.0), order=2, mapping=None):
    """A box of n[0]*n[1]*n[2] cubes, 6 conforming (Kuhn) tets each, as a pyvista grid of
    VTK_TETRA (order 1) or VTK_QUADRATIC_TETRA (order 2). ``mapping(points) -> points``
    moves all nodes afterwards (e.g. to curve the mesh)."""
    nx, ny, nz = n
    g = np.stack(
        np.meshgrid(*[np.linspace(0, s, k + 1) for s, k in zip(size, n)], indexing="ij"), axis=-1
    )
    pts = [tuple(p) for p in g.transpose(2, 1, 0, 3).reshape(-1, 3)]

    def gid(i, j, k):
        return (k * (ny + 1) + j) * (nx + 1) + i

    tets = []
    for k, j, i in itertools.product(range(nz), range(ny), range(nx)):
        for perm in itertools.permutations(range(3)):
            c = [0, 0, 0]
            t = [gid(i, j, k)]
            for a in perm:
                c[a] = 1
                t.append(gid(i + c[0], j + c[1], k + c[2]))
            p = np.array([pts[v] for v in t])
            if np.linalg.det(p[1:] - p[0]) < 0:
                t[1], t[2] = t[2], t[1]
            tets.append(t)
    cells = []
    mids = {}
    edges = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]
    for t in tets:
        ids = list(t)
        if order == 2:
            for a, b in edges:
                key = (min(t[a], t[b]), max(t[a], t[b]))
                if key not in mids:
                    mids[key] = len(pts)
                    pts.append(tuple(0.5 * (np.array(pts[t[a]]) + np.array(pts[t[b]]))))
                ids.append(mids[key])
        cells.append([len(ids)] + ids)
    points = np.array(pts, dtype=float)
    if mapping is not None:
        points = np.asarray(mapping(points), dtype=float)
    ctype = pv.CellType.QUADRATIC_TETRA if order == 2 else pv.CellType.TETRA
    return pv.UnstructuredGrid(
        np.hstack(cells).astype(np.int64),
        np.full(len(cells), ctype, dtype=np.uint8),
        points,
        deep=True,
    )


@pytest.fixture
def box_mesh():
    """The box_tet_mesh generator (call it with the sizes you need)."""
    return box_tet_mesh
