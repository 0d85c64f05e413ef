"""The checks test_lagrange.py (tetrahedra) and test_lagrange_hex.py (hexahedra) share:
both routes give the same embedding, inside points sit where VTK's own cell puts their
coordinates, outside points are no farther than any sampled boundary point, and a rigid
motion of the mesh moves the surface rigidly."""

import hoembed
import numpy as np
from filter_routes import embed as filter_embed
from filter_routes import transfer as filter_transfer


def check_routes_agree_and_points_rebuilt(mesh, surface, location, samples):
    """location(cell, pcoords): VTK's cell at those coordinates; samples: points sampled
    on the mesh's boundary."""
    got = hoembed.embed(surface, mesh)
    via_filter = filter_embed(surface, mesh)
    for name in (
        "EmbeddingCellId",
        "EmbeddingParametricCoords",
        "EmbeddingDistance",
        "EmbeddingClosestDistance",
        "EmbeddingResidual",
        "EmbeddingFace",
    ):
        assert np.array_equal(got[name], via_filter[name]), name
    diag = mesh.length
    assert got["EmbeddingResidual"].max() <= 1e-10 * diag
    assert not got["EmbeddingFallback"].any()
    closest = got["EmbeddingClosestDistance"]
    inside = closest == 0
    assert 5 < inside.sum() < surface.n_points - 5
    for i in np.where(inside)[0]:
        x = location(got["EmbeddingCellId"][i], got["EmbeddingParametricCoords"][i])
        assert np.linalg.norm(x - surface.points[i]) <= 1e-10 * diag
    for i in np.where(~inside)[0]:
        sampled = np.linalg.norm(samples - surface.points[i], axis=1).min()
        assert closest[i] <= sampled + 1e-8 * diag


def check_rigid_transfer(mesh, surface):
    embedded = hoembed.embed(surface, mesh)
    a = 0.8
    R = np.array([[np.cos(a), -np.sin(a), 0], [np.sin(a), np.cos(a), 0], [0, 0, 1]])
    t = np.array([1.5, -2.0, 0.25])
    moved = mesh.copy()
    moved.points = mesh.points @ R.T + t
    want = surface.points @ R.T + t
    for route in (hoembed.transfer, filter_transfer):
        out = route(embedded, moved)
        err = np.abs(np.asarray(out.points, float) - want).max()
        assert err <= 1e-9 * mesh.length, (route, err)
