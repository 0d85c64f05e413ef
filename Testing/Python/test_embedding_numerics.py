"""vtkEmbeddingCoordinatesFilter / vtkDeformationTransferFilter: scale invariance and the
fallback for vertices without a normal offset (issue 19).

References: the embedding at scale 1 (scaling by a power of two is exact in floating
point, so a filter whose every test is relative to the mesh size must give the same bits),
VTK's own vtkQuadraticTetra interpolation for the closest point, and affine maps of the
FE mesh, under which the fallback's p' + F (v - p) is exactly the same affine map of v.
"""

import hoembed
import numpy as np
import pytest
import pyvista as pv
from conftest import box_tet_mesh
from hoembed._errors import run_filter
from hoembed.hoembedFiltersEmbedding import vtkEmbeddingCoordinatesFilter
from vtkmodules.vtkCommonCore import reference

EXACT = ["EmbeddingCellId", "EmbeddingParametricCoords", "EmbeddingFace", "EmbeddingFallback"]
LENGTHS = ["EmbeddingDistance", "EmbeddingResidual", "EmbeddingClosestDistance"]


def _curve(p):
    x, y, z = p[:, 0], p[:, 1], p[:, 2]
    return np.c_[
        x + 0.05 * np.sin(np.pi * y),
        y + 0.12 * np.sin(0.5 * np.pi * x),
        z + 0.08 * np.cos(np.pi * x) * y,
    ]


def reconstruct(grid, out):
    """p from VTK's own cell interpolation at (cell, pcoords)."""
    p = np.empty((out.n_points, 3))
    sub = reference(0)
    for i, (c, pc) in enumerate(zip(out["EmbeddingCellId"], out["EmbeddingParametricCoords"])):
        cell = grid.GetCell(int(c))
        x = [0.0, 0.0, 0.0]
        cell.EvaluateLocation(sub, pc, x, [0.0] * cell.GetNumberOfPoints())
        p[i] = x
    return p


@pytest.fixture(scope="module")
def beam():
    """The curved tet10 beam of test_embedding.py."""
    return box_tet_mesh((4, 2, 2), (2.0, 1.0, 1.0), 2, _curve)


@pytest.fixture(scope="module")
def surface():
    """An ellipsoid through the curved beam (inside and outside points), a sphere inside
    it and one a few diagonals away, in double precision."""
    a = pv.Sphere(radius=1.0, theta_resolution=30, phi_resolution=24)
    a = a.scale([1.15, 0.52, 0.5], inplace=False).translate([1.0, 0.55, 0.5], inplace=False)
    b = pv.Sphere(radius=0.3, center=(1.0, 0.5, 0.5), theta_resolution=12, phi_resolution=10)
    c = pv.Sphere(radius=2.0, center=(8.0, -5.0, 3.0), theta_resolution=10, phi_resolution=8)
    s = (a + b + c).clean(tolerance=0.0)
    return pv.PolyData(np.asarray(s.points, dtype=float), faces=s.faces, deep=True)


def embed(surface, mesh, warnings=None, method=vtkEmbeddingCoordinatesFilter.NORMAL_OFFSET):
    alg = vtkEmbeddingCoordinatesFilter()
    alg.SetInputData(0, surface)
    alg.SetMeshData(mesh)
    alg.SetMethod(method)
    out = pv.wrap(run_filter(alg, warnings)).copy()
    return out, alg.GetNumberOfFallbackPoints()


def scaled(data, s):
    out = data.copy()
    out.points = np.asarray(data.points, dtype=float) * s
    return out


@pytest.mark.parametrize("k", [-30, -20, -10, 10, 20, 30])
@pytest.mark.parametrize("variant", ["tet10", "tet4", "tet10-barycentric"])
def test_power_of_two_scales_give_the_same_bits(beam, surface, k, variant):
    """2^-30 ~ 1e-9 ... 2^30 ~ 1e9: every relative result identical to scale 1 (before
    the fix, from 2^-15 down, 2134 of bunny_lowres's 3485 vertices changed and had
    residuals up to 1.3% of the diagonal)."""
    s = 2.0**k
    method = vtkEmbeddingCoordinatesFilter.NORMAL_OFFSET
    if variant == "tet4":
        beam = box_tet_mesh((4, 2, 2), (2.0, 1.0, 1.0), 1, _curve)
    elif variant == "tet10-barycentric":
        method = vtkEmbeddingCoordinatesFilter.BARYCENTRIC
    ref, _ = embed(surface, beam, method=method)
    out, _ = embed(scaled(surface, s), scaled(beam, s), method=method)
    for name in EXACT:
        assert np.array_equal(out[name], ref[name]), name
    for name in LENGTHS:
        assert np.array_equal(out[name] / s, ref[name]), name
    # the transfer of a deformation, scaled with it
    moved = beam.copy()
    moved.points = beam.points + 0.1 * np.sin(beam.points)[:, [1, 2, 0]]
    t1 = hoembed.transfer(ref, moved)
    ts = hoembed.transfer(out, scaled(moved, s))
    assert np.array_equal(ts.points / s, t1.points)


@pytest.mark.parametrize("s", [1e-9, 3e-7, 1e-5, 1e5, 1e9])
def test_decimal_scales_match_scale_one(beam, surface, s):
    """Scales that round the coordinates: the same relative results as at scale 1 to
    round-off. Tolerances: residuals below 1e-10 of the diagonal, the filter's own bound
    at scale 1; distances and closest points within 1e-9 of the diagonal, the
    certification tolerance (1e-10) with room for the rounding of the input, which moves
    a closest point by far less but may move an iterate's stop."""
    diag = beam.length
    ref, _ = embed(surface, beam)
    S, M = scaled(surface, s), scaled(beam, s)
    out, nfall = embed(S, M)
    assert nfall == 0
    assert out["EmbeddingResidual"].max() <= 1e-10 * diag * s
    for name in LENGTHS[:1] + LENGTHS[2:]:
        assert np.abs(out[name] / s - ref[name]).max() <= 1e-9 * diag, name
    assert np.array_equal(out["EmbeddingFace"] < 0, ref["EmbeddingFace"] < 0)
    # the closest point p itself (cells may differ where p lies on a shared face)
    p1 = reconstruct(beam, ref)
    ps = reconstruct(M, out)
    assert np.abs(ps / s - p1).max() <= 1e-9 * diag


@pytest.fixture(scope="module", params=[2, 1], ids=["tet10", "tet4"])
def far(request):
    """A sphere a million diagonals around the beam (tet10 or tet4): for many of its
    vertices no d rebuilds v to the 1e-12 tolerance (the round-off of d n alone exceeds
    it)."""
    beam = box_tet_mesh((4, 2, 2), (2.0, 1.0, 1.0), request.param, _curve)
    radius = 1e6 * beam.length
    s = pv.Sphere(radius=radius, center=(1.0, 0.5, 0.5), theta_resolution=20, phi_resolution=12)
    s = pv.PolyData(np.asarray(s.points, dtype=float), faces=s.faces, deep=True)
    warnings = []
    out, count = embed(s, beam, warnings)
    return s, out, count, warnings, beam


def test_fallback_flagged_and_exact(far):
    s, out, count, warnings, beam = far
    flag = np.asarray(out["EmbeddingFallback"])
    assert out["EmbeddingFallback"].dtype == np.uint8
    # flagged, counted, warned about
    assert 0 < count == flag.sum() < s.n_points
    assert out.field_data["NumberOfFallbackPoints"][0] == count
    assert any(f"{count} surface point(s)" in w and "no normal offset" in w for w in warnings)
    fb = flag == 1
    # no normal offset for them, the closest point instead (VTK's interpolation)
    assert np.all(out["EmbeddingDistance"][fb] == 0) and np.all(out["EmbeddingFace"][fb] == -1)
    p = reconstruct(beam, out)
    gap = np.linalg.norm(s.points - p, axis=1)
    closest = out["EmbeddingClosestDistance"]
    assert np.abs(gap[fb] - closest[fb]).max() <= 1e-14 * closest[fb].max()
    # the offset is only there for them; the rest are rebuilt as before
    q = np.asarray(out["EmbeddingFallbackOffset"])
    assert np.all(q[~fb] == 0) and np.all(np.abs(q[fb]).sum(axis=1) > 0)
    # v = p + J q at rest to round-off of |v - p| (before the fix: residuals up to 2.9e5
    # diagonals, nothing flagged)
    assert out["EmbeddingResidual"][fb].max() <= 1e-14 * closest[fb].max()
    assert out["EmbeddingResidual"].max() <= 1e-14 * closest.max()


def test_no_fallback_on_ordinary_inputs(beam, surface):
    out, count = embed(surface, beam)
    assert count == 0 and out.field_data["NumberOfFallbackPoints"][0] == 0
    assert np.all(out["EmbeddingFallback"] == 0)
    assert "EmbeddingFallbackOffset" not in out.point_data


@pytest.mark.parametrize("normals", ["recompute", "rotate", "deform"])
def test_fallback_transfer_follows_affine_maps(far, normals):
    """Under an affine map of the FE mesh the cell maps move by that map, F equals its
    matrix, and p' + F (v - p) is the same map of v: at rest (identity), a rigid motion and
    a shear."""
    s, out, _, _, beam = far
    fb = out["EmbeddingFallback"] == 1
    v = np.asarray(s.points)
    scale = np.linalg.norm(v, axis=1)[fb].max()
    th = 0.7
    rot = np.array([[np.cos(th), -np.sin(th), 0], [np.sin(th), np.cos(th), 0], [0, 0, 1]])
    shear = np.array([[1.0, 0.3, 0.0], [0.0, 1.1, 0.2], [0.1, 0.0, 0.9]])
    for A, b in [
        (np.eye(3), np.zeros(3)),
        (rot, np.array([3.0, -2.0, 1.0])),
        (shear, np.array([0.5, 0.0, -1.0])),
    ]:
        moved = beam.copy()
        moved.points = beam.points @ A.T + b
        moved["Displacement"] = moved.points - beam.points
        moved["NodalRotation"] = np.tile(
            rot.ravel() if A is rot else np.eye(3).ravel(), (beam.n_points, 1)
        )
        t = hoembed.transfer(out, moved, normals=normals)
        err = np.linalg.norm(t.points[fb] - (v[fb] @ A.T + b), axis=1)
        assert err.max() <= 1e-14 * scale
    # single-precision output: the same, rounded once
    single = out.copy()
    single.points = np.asarray(out.points, dtype=np.float32)
    t = hoembed.transfer(single, beam, normals=normals)
    assert t.points.dtype == np.float32
    err = np.linalg.norm(t.points[fb].astype(float) - v[fb], axis=1)
    assert err.max() <= 1e-7 * scale


def test_transfer_rejects_bad_fallback_offsets(far):
    _, out, _, _, beam = far
    bad = out.copy()
    q = np.array(bad["EmbeddingFallbackOffset"])
    q[np.flatnonzero(bad["EmbeddingFallback"])[0]] = np.nan
    bad["EmbeddingFallbackOffset"] = q
    with pytest.raises(hoembed.HOEmbedError, match="EmbeddingFallbackOffset"):
        hoembed.transfer(bad, beam)
    bad = out.copy()
    bad["EmbeddingFallbackOffset"] = np.zeros(bad.n_points)
    with pytest.raises(hoembed.HOEmbedError, match="EmbeddingFallbackOffset"):
        hoembed.transfer(bad, beam)
