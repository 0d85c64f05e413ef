"""hoembed.embed / vtkEmbeddingCoordinatesFilter against VTK's own tools.

References nobody here wrote: vtkCellLocator::FindClosestPoint on tet4 meshes (exact for
linear cells), vtkQuadraticTetra / vtkTetra interpolation (EvaluateLocation) for the
reconstruction, VTK's XML writer and reader for the save/load round trip.
"""

import hoembed
import numpy as np
import pytest
import pyvista as pv
from conftest import box_tet_mesh
from mesh_checks import distances_to_surface
from voxel_tet_mesh import linear_copy, voxel_tet_mesh
from vtkmodules.vtkCommonCore import reference

ARRAYS = [
    "EmbeddingCellId",
    "EmbeddingParametricCoords",
    "EmbeddingDistance",
    "EmbeddingResidual",
    "EmbeddingFace",
    "EmbeddingIterations",
    "EmbeddingElementsVisited",
]


def _curve(p):
    x, y, z = p[:, 0], p[:, 1], p[:, 2]
    return np.c_[
        x + 0.05 * np.sin(np.pi * y),
        y + 0.12 * np.sin(0.5 * np.pi * x),
        z + 0.08 * np.cos(np.pi * x) * y,
    ]


@pytest.fixture(scope="module")
def meshes():
    m10 = box_tet_mesh((4, 2, 2), (2.0, 1.0, 1.0), 2, _curve)
    m4 = box_tet_mesh((4, 2, 2), (2.0, 1.0, 1.0), 1, _curve)
    return m10, m4


@pytest.fixture(scope="module")
def surface():
    """An ellipsoid through the curved beam, a sphere inside it, a sphere far away and
    three points in no triangle."""
    a = pv.Sphere(radius=1.0, theta_resolution=40, phi_resolution=30)
    a = a.scale([1.15, 0.52, 0.5], inplace=False).translate([1.0, 0.55, 0.5], inplace=False)
    b = pv.Sphere(radius=0.3, center=(1.0, 0.5, 0.5), theta_resolution=12, phi_resolution=10)
    c = pv.Sphere(radius=2.0, center=(40.0, -25.0, 10.0), theta_resolution=10, phi_resolution=8)
    s = (a + b + c).clean(tolerance=0.0)
    lone = np.array([[0.5, 0.5, 0.5], [-0.8, 0.3, 0.2], [5.0, 5.0, 5.0]])
    pts = np.vstack([s.points, lone])
    out = pv.PolyData(pts, faces=s.faces, deep=True)
    return out


def vtk_distance(grid, points):
    """Exact distance of points to a linear tet mesh: 0 inside a cell (barycentric
    coordinates over every cell, numpy), else the distance to the boundary triangles by
    VTK's vtkCellLocator (exact for triangles). Returns (distance, distance to boundary).
    (vtkSelectEnclosedPoints and vtkCellLocator on the tets are not exact near the
    boundary: both use tolerances.)"""
    boundary = grid.extract_surface().triangulate()
    to_boundary = distances_to_surface(boundary, points)
    inside = inside_linear_tets(grid, points)
    return np.where(inside, 0.0, to_boundary), to_boundary


def check_distances(mine, grid, points):
    """Embedding distances against vtk_distance, within 1e-8 of the diagonal."""
    ref, _ = vtk_distance(grid, points)
    mine = np.asarray(mine)
    assert np.abs(mine - ref).max() <= 1e-8 * grid.length


def inside_linear_tets(grid4, points, chunk=256):
    """Exact containment in a linear tet mesh by barycentric coordinates over every cell
    (numpy brute force): True where some cell has all coordinates >= -1e-12."""
    cells = grid4.cells.reshape(-1, 5)[:, 1:]
    X = np.asarray(grid4.points, dtype=float)[cells]
    Ainv = np.linalg.inv(np.transpose(X[:, 1:] - X[:, :1], (0, 2, 1)))
    pts = np.asarray(points, dtype=float)
    out = np.zeros(len(pts), dtype=bool)
    for b in range(0, len(pts), chunk):
        p = pts[b : b + chunk]
        lam = np.einsum("nij,mnj->mni", Ainv, p[:, None, :] - X[None, :, 0, :])
        low = np.minimum(1.0 - lam.sum(axis=2), lam.min(axis=2))
        out[b : b + chunk] = (low >= -1e-12).any(axis=1)
    return out


def reconstruct(grid, out):
    """p from VTK's own cell interpolation at (cell, pcoords)."""
    cid = out["EmbeddingCellId"]
    pc = out["EmbeddingParametricCoords"]
    p = np.empty((out.n_points, 3))
    sub = reference(0)
    for i in range(out.n_points):
        cell = grid.GetCell(int(cid[i]))
        x = [0.0, 0.0, 0.0]
        w = [0.0] * cell.GetNumberOfPoints()
        cell.EvaluateLocation(sub, pc[i], x, w)
        p[i] = x
    return p


def test_arrays_and_field_data(meshes, surface):
    out = hoembed.embed(surface, meshes[0])
    assert isinstance(out, pv.PolyData)
    assert out.n_points == surface.n_points
    for name in ARRAYS:
        assert name in out.point_data, name
        assert np.all(np.isfinite(out[name]))
    assert out.point_data["EmbeddingParametricCoords"].shape == (out.n_points, 3)
    assert out.field_data["EmbeddingMethod"][0] == "normal-offset"
    assert len(out.field_data["EmbeddingMeshFingerprint"][0]) == 16
    face, d = out["EmbeddingFace"], out["EmbeddingDistance"]
    assert np.array_equal(face < 0, d == 0)
    assert (d > 0).any() and (d == 0).any()


def test_tet4_distances_match_vtk_cell_locator(meshes, surface):
    grid = meshes[1]
    out = hoembed.embed(surface, grid)
    check_distances(out["EmbeddingClosestDistance"], grid, surface.points)
    diag = grid.length
    # the far sphere maps with large distances, the inner sphere lies inside
    assert out["EmbeddingClosestDistance"].max() > 10 * diag


@pytest.mark.parametrize("which", [0, 1])
def test_normal_offset_reconstruction(meshes, surface, which):
    grid = meshes[which]
    out = hoembed.embed(surface, grid)
    diag = grid.length
    assert out["EmbeddingResidual"].max() <= 1e-10 * diag
    p = reconstruct(grid, out)
    d = out["EmbeddingDistance"]
    # where d = 0 the point itself is reproduced by VTK's interpolation
    inside = d == 0
    assert np.abs(p[inside] - surface.points[inside]).max() <= 1e-10 * diag
    # elsewhere v - p has length d (the smooth normal is a unit vector)
    gap = np.linalg.norm(surface.points[~inside] - p[~inside], axis=1)
    assert np.abs(gap - d[~inside]).max() <= 1e-10 * diag
    pc = out["EmbeddingParametricCoords"]
    assert pc.min() >= -1e-12 and pc.sum(axis=1).max() <= 1 + 1e-12


@pytest.mark.parametrize("which", [0, 1])
def test_barycentric(meshes, surface, which):
    grid = meshes[which]
    out = hoembed.embed(surface, grid, method="barycentric")
    assert out.field_data["EmbeddingMethod"][0] == "barycentric"
    assert np.all(out["EmbeddingDistance"] == 0) and np.all(out["EmbeddingFace"] == -1)
    p = reconstruct(grid, out)
    near = out["EmbeddingClosestDistance"] < 0.3 * grid.length
    if which == 1:
        near[:] = True  # tet4: extrapolation is exact everywhere
    err = np.linalg.norm(p - surface.points, axis=1)[near]
    assert err.max() <= 1e-10 * grid.length


def test_matches_between_runs_and_threads(meshes, surface):
    from vtkmodules.vtkCommonCore import vtkSMPTools

    vtkSMPTools.Initialize(1)
    a = hoembed.embed(surface, meshes[0], n_partitions=1)
    vtkSMPTools.Initialize(2)
    b = hoembed.embed(surface, meshes[0], n_partitions=7)
    diag = meshes[0].length
    assert (
        np.abs(a["EmbeddingClosestDistance"] - b["EmbeddingClosestDistance"]).max() <= 1e-12 * diag
    )


def test_filter_reused_across_inputs(meshes, surface):
    """One filter updated on different meshes, surfaces and methods, and after an error
    (it keeps its working memory between Updates), gives exactly the results of a fresh
    filter each time."""
    from hoembed import vtkEmbeddingCoordinatesFilter
    from hoembed._errors import run_filter

    m10, m4 = meshes
    small = pv.Sphere(radius=0.4, center=(1.0, 0.5, 0.5), theta_resolution=9, phi_resolution=7)
    nan_mesh = m10.copy()
    nan_mesh.points[3] = [np.nan, 0, 0]
    # the same mesh 100 times larger: the same counts, other per-cell data
    big, big_surface = m10.scale(100.0, inplace=False), surface.scale(100.0, inplace=False)
    runs = [
        (big_surface, big, 0),
        (surface, m10, 0),
        (small, m4, 0),
        (surface, nan_mesh, 0),
        (surface, m4, 1),
        (small, m10, 0),
        (surface, m10, 1),
    ]
    alg = vtkEmbeddingCoordinatesFilter()
    compared = 0
    for surf, mesh, method in runs:
        alg.SetInputData(0, surf)
        alg.SetMeshData(mesh)
        alg.SetMethod(method)
        name = "barycentric" if method else "normal-offset"
        if mesh is nan_mesh:
            with pytest.raises(hoembed.HOEmbedError, match="non-finite"):
                run_filter(alg)
            continue
        got = pv.wrap(run_filter(alg)).copy()
        want = hoembed.embed(surf, mesh, method=name)
        for array in ARRAYS:
            assert np.array_equal(got[array], want[array]), (array, name)
        compared += 1
    assert compared == len(runs) - 1


def test_save_load_identical(meshes, surface, tmp_path):
    out = hoembed.embed(surface, meshes[0])
    f = tmp_path / "embedded.vtp"
    out.save(f)
    back = pv.read(f)
    for name in ARRAYS:
        assert np.array_equal(out[name], back[name]), name
        assert out[name].dtype == back[name].dtype, name
    for name in ("EmbeddingMethod", "EmbeddingMeshFingerprint"):
        assert back.field_data[name][0] == out.field_data[name][0]


def test_progress_reported(meshes, surface):
    seen = []
    hoembed.embed(surface, meshes[0], progress=seen.append)
    assert seen and seen[-1] == pytest.approx(1.0)


def test_errors(meshes, surface):
    m10 = meshes[0]
    with pytest.raises(hoembed.HOEmbedError, match="surface .*empty"):
        hoembed.embed(pv.PolyData(), m10)
    with pytest.raises(hoembed.HOEmbedError, match="FE mesh .*empty"):
        hoembed.embed(surface, pv.UnstructuredGrid())
    bad = surface.copy()
    bad.points[5] = np.nan
    with pytest.raises(hoembed.HOEmbedError, match="non-finite"):
        hoembed.embed(bad, m10)
    badm = m10.copy()
    badm.points[3] = [np.inf, 0, 0]
    with pytest.raises(hoembed.HOEmbedError, match="non-finite"):
        hoembed.embed(surface, badm)
    with pytest.raises(hoembed.HOEmbedError, match="VTK_TETRA"):
        hoembed.embed(surface, pv.ImageData(dimensions=(3, 3, 3)).cast_to_unstructured_grid())
    # inverted element: swap two corners (and the mid nodes that follow them)
    cells = m10.cells.reshape(-1, 11).copy()
    c = cells[0, 1:]
    c[[1, 2]] = c[[2, 1]]
    c[[4, 6]] = c[[6, 4]]
    c[[8, 9]] = c[[9, 8]]
    cells[0, 1:] = c
    inv = pv.UnstructuredGrid(cells.ravel(), m10.celltypes, m10.points, deep=True)
    with pytest.raises(hoembed.HOEmbedError, match="inverted or degenerate"):
        hoembed.embed(surface, inv)
    with pytest.raises(ValueError):
        hoembed.embed(surface, m10, method="nearest")


@pytest.mark.parametrize("name", ["bunny_watertight", "rocker-arm"])
def test_real_mesh(data_dir, name):
    """A real surface on hoembed.tet10_mesh meshes of ~1000 elements: tet4 distances
    against VTK on 3000 sampled vertices, tet10 and tet4 residuals on all vertices, the
    tet10 reconstruction with VTK's vtkQuadraticTetra on the sample."""
    s = pv.read(data_dir / f"{name}.obj")
    g10 = hoembed.tet10_mesh(s, n_elements=1000)
    g4 = hoembed.tet10_mesh(s, n_elements=1000, order=1)
    rng = np.random.default_rng(0)
    sample = np.sort(rng.choice(s.n_points, min(3000, s.n_points), replace=False))
    out4 = hoembed.embed(s, g4)
    check_distances(out4["EmbeddingClosestDistance"][sample], g4, s.points[sample])
    assert out4["EmbeddingResidual"].max() <= 1e-10 * g4.length
    out10 = hoembed.embed(s, g10)
    assert out10["EmbeddingResidual"].max() <= 1e-10 * g10.length
    sub = out10.extract_points(sample, adjacent_cells=False, include_cells=False)
    p = reconstruct(g10, sub)
    d = np.asarray(sub["EmbeddingDistance"])
    gap = np.linalg.norm(np.asarray(sub.points) - p, axis=1)
    # a fallback point (no normal offset with a foot within 8x the closest distance) has
    # d = 0 and its closest point as p
    fb = np.asarray(sub["EmbeddingFallback"]) != 0
    assert np.abs(gap - d)[~fb].max() <= 1e-10 * g10.length
    assert (
        np.abs(gap - np.asarray(sub["EmbeddingClosestDistance"]))[fb].max(initial=0.0)
        <= 1e-8 * g10.length
    )


def test_voxel_mesh_bunny(data_dir):
    """The same on a voxel tet mesh (staircase boundary: large distances, many vertices
    closest to edges and corners)."""
    s = pv.read(data_dir / "bunny_watertight.obj")
    g10 = voxel_tet_mesh(s, 1000)
    g4 = linear_copy(g10)
    rng = np.random.default_rng(0)
    sample = np.sort(rng.choice(s.n_points, 3000, replace=False))
    out4 = hoembed.embed(s, g4)
    check_distances(out4["EmbeddingClosestDistance"][sample], g4, s.points[sample])
    out10 = hoembed.embed(s, g10)
    assert out10["EmbeddingResidual"].max() <= 1e-10 * g10.length
    assert np.all(np.isfinite(out10["EmbeddingParametricCoords"]))


def _vtk_reconstruction(mesh, embedded):
    """x(cell, pcoords) of every embedded point by VTK's own cell interpolation
    (vtkCell.EvaluateLocation), and its distance to the point."""
    cell = None
    out = np.empty(embedded.n_points)
    ids = embedded.point_data["EmbeddingCellId"]
    pcs = embedded.point_data["EmbeddingParametricCoords"]
    for i in range(embedded.n_points):
        cell = mesh.GetCell(int(ids[i]))
        x, w, sub = [0.0] * 3, [0.0] * cell.GetNumberOfPoints(), reference(0)
        cell.EvaluateLocation(sub, list(pcs[i]), x, w)
        out[i] = np.linalg.norm(np.asarray(x) - embedded.points[i])
    return out


def test_inexact_embedding_is_reported():
    """The barycentric method extrapolates the closest cell's map for points outside the
    mesh: exact for tet4 (affine), not for curved tet10 cells far out. Points whose
    reconstruction (by VTK's interpolation, not ours) misses them by more than 1e-6 of the
    mesh's diagonal are counted in a warning; exact embeddings warn nothing."""
    import warnings

    tail = hoembed.thorny_tail(rings=60, sectors=24)
    tet10 = hoembed.tet10_mesh(tail, n_elements=150)
    tet4 = hoembed.tet10_mesh(tail, n_elements=150, order=1)
    shifted = tail.copy()
    shifted.points = shifted.points + np.array([0.3 * tet10.length, 0.0, 0.0])
    for mesh, method, surface, expect in (
        (tet10, "barycentric", shifted, True),
        (tet10, "normal-offset", shifted, False),
        (tet4, "barycentric", shifted, False),
    ):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            emb = hoembed.embed(surface, mesh, method=method)
        msgs = [str(w.message) for w in caught if "not reproduced" in str(w.message)]
        if method == "normal-offset":
            assert not msgs, msgs
            continue
        miss = _vtk_reconstruction(mesh, emb)
        n = int(np.sum(miss > 1e-6 * mesh.length))
        if expect:
            assert n > 0 and len(msgs) == 1, (n, msgs)
            assert msgs[0].startswith(f"embed: {n} surface point(s)"), msgs[0]
            assert "barycentric method extrapolates" in msgs[0]
        else:
            assert n == 0 and not msgs, (n, msgs)
