"""vtkTet10Mesher / hoembed.tet10_mesh on generated shapes and the real meshes."""

import hoembed
import numpy as np
import pytest
import pyvista as pv
from mesh_checks import (
    boundary_mid_nodes,
    cells,
    distances_to_surface,
    expect_error,
    min_det_sampled,
    straight_scaled_jacobian,
    straight_volumes,
    surface_volume,
    tet10_volumes,
    vtk_cell_validator_states,
)

REAL = ["bunny_watertight", "armadillo", "fertility", "rocker-arm", "scorpion_low_resolution"]


def torus():
    return (
        pv.ParametricTorus(ringradius=1.0, crosssectionradius=0.35, u_res=160, v_res=80, w_res=2)
        .clean()
        .triangulate()
    )


def bumpy_blob():
    s = pv.Sphere(radius=1.0, theta_resolution=180, phi_resolution=180)
    p = s.points
    r = np.linalg.norm(p, axis=1, keepdims=True)
    u = p / r
    bump = 1 + 0.12 * np.sin(5 * u[:, :1]) * np.cos(4 * u[:, 1:2]) + 0.05 * np.sin(9 * u[:, 2:3])
    s.points = u * bump
    return s


SHAPES = {
    "sphere": lambda: pv.Sphere(radius=1.0, theta_resolution=160, phi_resolution=160),
    "torus": torus,
    "bumpy": bumpy_blob,
}


def check_mesh(surface, mesh, on_surface_fraction):
    """The properties the issue asks for; returns the figures for the log."""
    diag = surface.length
    assert mesh.n_cells > 0
    assert np.all(mesh.celltypes == pv.CellType.QUADRATIC_TETRA)
    assert np.all(np.isfinite(mesh.points))
    # Valid: the filter's own (Bernstein-bound) quality, VTK's validator, and sampled det J.
    assert mesh.cell_data["MinScaledJacobian"].min() > 0
    assert np.all(vtk_cell_validator_states(mesh) == 0)
    assert min_det_sampled(mesh, n=60).min() > 0
    # Boundary mid-edge nodes on the fine surface.
    mids = boundary_mid_nodes(mesh)
    d = distances_to_surface(surface, mesh.points[mids])
    frac = float(np.mean(d <= 1e-6 * diag))
    assert frac >= on_surface_fraction, f"only {frac:.3f} of boundary mid-edge nodes on the surface"
    # Every node off the surface is counted as relaxed (a relaxed node may still happen to
    # lie within the tolerance of the surface).
    relaxed = int(mesh.field_data["RelaxedNodeCount"][0])
    off = int(np.sum(d > 1e-6 * diag))
    assert off <= relaxed <= off + max(3, 0.01 * len(mids)), (relaxed, off)
    # Curving brings the volume closer to the surface's.
    v_fine = surface_volume(surface)
    v_curved = tet10_volumes(mesh).sum()
    v_straight = straight_volumes(mesh).sum()
    assert abs(v_curved - v_fine) < abs(v_straight - v_fine)
    return dict(
        cells=mesh.n_cells,
        on_surface=frac,
        vol_err_curved=(v_curved - v_fine) / v_fine,
        vol_err_straight=(v_straight - v_fine) / v_fine,
    )


@pytest.mark.parametrize(
    "shape,n",
    [("sphere", 1000), ("bumpy", 1000), ("torus", 1000), ("bumpy", 3000), ("torus", 3000)],
)
def test_generated_shapes(shape, n):
    surface = SHAPES[shape]()
    # the curving's reach: without the quality target (which blends nodes back off the
    # surface for quality, test_quality_target)
    mesh = hoembed.tet10_mesh(surface, n_elements=n, quality_target=0.0)
    figures = check_mesh(surface, mesh, on_surface_fraction=0.95)
    assert 0.5 * n < mesh.n_cells < 2.0 * n
    print(shape, figures)


def mesh_with_warnings(surface, n, **properties):
    alg = hoembed.vtkTet10Mesher()
    alg.SetInputData(surface)
    alg.SetTargetNumberOfElements(n)
    for name, value in properties.items():
        getattr(alg, "Set" + name)(value)
    warnings = []
    return pv.wrap(hoembed._errors.run_filter(alg, warnings)), warnings


def check_quality_floor(mesh, warnings, floor=0.05):
    """Every cell at the floor or, if its straight shape (vtkMeshQuality) is worse, as good
    as that; the field data's count and distribution agree with the cells; a warning
    exactly when some cell is below the floor."""
    q = np.asarray(mesh.cell_data["MinScaledJacobian"])
    straight = straight_scaled_jacobian(mesh)
    assert np.all(q >= np.minimum(floor, 0.999 * straight) - 1e-9), (q.min(), straight[q.argmin()])
    poor = int(mesh.field_data["PoorElementCount"][0])
    assert poor == int(np.sum(q < floor))
    quantiles = np.asarray(mesh.field_data["MinScaledJacobianQuantiles"]).ravel()
    assert quantiles[0] == q.min()
    assert quantiles[2] == np.sort(q)[(len(q) - 1) // 2]
    assert np.sum(q < quantiles[1]) <= 0.01 * len(q) + 1
    assert (poor > 0) == any("MinimumQuality" in w for w in warnings), (poor, warnings)
    return q


@pytest.mark.parametrize("shape", ["bumpy", "torus"])
def test_quality_floor(shape):
    """MinimumQuality (default 0.05): curving stops at the floor; with no floor the same
    input has elements far below it (so the floor is what keeps them)."""
    surface = SHAPES[shape]()
    mesh, warnings = mesh_with_warnings(surface, 1000)
    q = check_quality_floor(mesh, warnings)
    assert 0.7 * 1000 < mesh.n_cells < 1.3 * 1000
    loose, loose_warnings = mesh_with_warnings(
        surface, 1000, MinimumQuality=0.0, CurvedQualityTarget=0.0
    )
    q0 = np.asarray(loose.cell_data["MinScaledJacobian"])
    assert int(loose.field_data["PoorElementCount"][0]) == 0  # no floor: nothing is poor
    assert np.sum(q0 < 0.05) > np.sum(q < 0.05)
    print(
        shape,
        "min/1%/median",
        np.percentile(q, [0, 1, 50]),
        "without floor",
        np.percentile(q0, [0, 1, 50]),
    )


def test_small_mesh_quality():
    """Issue 27, 300 elements: the corners of the straight mesh are optimised before
    curving (hoembed::OptimiseLinearCorners). On this torus (a tube a third of the ring
    radius thick: most tets at 300 have four boundary corners) the median cell was 0.51
    (tet4) and 0.42 (tet10), the worst tet4 0.051, before that step; every boundary corner
    still lies on the surface (distance by VTK's implicit distance, not the mesher's)."""
    from vtkmodules.vtkFiltersCore import vtkImplicitPolyDataDistance

    surface = torus()
    distance = vtkImplicitPolyDataDistance()
    distance.SetInput(surface)
    for order, bound in ((1, 0.55), (2, 0.44)):
        mesh, warnings = mesh_with_warnings(surface, 300, ElementOrder=order)
        q = check_quality_floor(mesh, warnings)
        assert 0.7 * 300 < mesh.n_cells < 1.3 * 300
        assert np.median(q) >= bound, (order, np.median(q))
        if order == 1:
            assert q.min() >= 0.1, q.min()
            outer = mesh.extract_surface()
            d = np.array([abs(distance.EvaluateFunction(p)) for p in outer.points])
            on = np.mean(d <= 1e-6 * surface.length)
            print("boundary corners on the surface", on)
            assert on >= 0.9, on
        print(order, mesh.n_cells, "min/median", q.min(), np.median(q))


def test_linear_order_same_corners():
    surface = SHAPES["sphere"]()
    quad = hoembed.tet10_mesh(surface, n_elements=500)
    lin = hoembed.tet10_mesh(surface, n_elements=500, order=1)
    assert np.all(lin.celltypes == pv.CellType.TETRA)
    assert lin.n_cells == quad.n_cells
    np.testing.assert_array_equal(cells(lin), cells(quad)[:, :4])
    np.testing.assert_allclose(lin.points, quad.points[: lin.n_points])


def test_straight_option_keeps_midpoints():
    surface = SHAPES["sphere"]()
    mesh = hoembed.tet10_mesh(surface, n_elements=400, curve_boundary=False)
    conn = cells(mesh)
    P = mesh.points
    for e, (a, b) in enumerate([(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]):
        np.testing.assert_allclose(
            P[conn[:, 4 + e]], 0.5 * (P[conn[:, a]] + P[conn[:, b]]), atol=1e-12
        )


def test_edge_length_control():
    surface = SHAPES["sphere"]()
    coarse = hoembed.tet10_mesh(surface, edge_length=0.5)
    fine = hoembed.tet10_mesh(surface, edge_length=0.25)
    assert fine.n_cells > 4 * coarse.n_cells


def test_quads_are_triangulated():
    cube = pv.Cube().triangulate().subdivide(3)  # closed, from quads
    mesh = hoembed.tet10_mesh(pv.Cube(), n_elements=200)
    assert mesh.n_cells > 0 and cube.n_cells > 0


def test_progress_events():
    seen = []
    hoembed.tet10_mesh(SHAPES["sphere"](), n_elements=300, progress=seen.append)
    assert len(seen) >= 5 and seen[-1] == pytest.approx(1.0)
    assert all(b >= a for a, b in zip(seen, seen[1:]))


# ---- bad input -----------------------------------------------------------------------


def test_empty():
    expect_error(pv.PolyData(), "empty")


def test_nan():
    s = pv.Sphere()
    s.points[3] = [np.nan, 0, 0]
    expect_error(s, "non-finite")


def test_inf():
    s = pv.Sphere()
    s.points[5] = [0, np.inf, 0]
    expect_error(s, "non-finite")


# Open, non-manifold and self-intersecting surfaces are meshed through the envelope now:
# test_mesher_any_surface.py covers them.


def test_lines_only():
    expect_error(pv.Line(), "no polygons")


def test_error_leaves_no_output():
    alg = hoembed.vtkTet10Mesher()
    alg.SetInputData(pv.PolyData())
    with pytest.raises(hoembed.HOEmbedError):
        hoembed._errors.run_filter(alg)
    assert alg.GetOutput().GetNumberOfCells() == 0


# ---- real meshes ---------------------------------------------------------------------


@pytest.mark.parametrize("name", REAL)
@pytest.mark.parametrize("n", [1000, 3000])
def test_real_meshes(data_dir, name, n):
    surface = pv.read(data_dir / f"{name}.obj")
    mesh, warnings = mesh_with_warnings(surface, n, CurvedQualityTarget=0.0)
    # Without the quality target (test_quality_target). The issue asks for 95%: with PreserveBoundary on (the default) and the quality floor
    # every real mesh reaches 95.5-99.1% (Benchmarks/RESULTS.md, "Mesher").
    figures = check_mesh(surface, mesh, on_surface_fraction=0.95)
    q = check_quality_floor(mesh, warnings)
    assert 0.7 * n < mesh.n_cells < 1.3 * n
    print(name, n, figures, "quality min/1%/median", np.percentile(q, [0, 1, 50]))


@pytest.mark.parametrize("n", [1000, 3000])
def test_preserve_boundary(data_dir, n):
    # Fertility is the hardest real mesh for boundary coverage (85% at 3000 elements with
    # PreserveBoundary off); with it on (the default, set explicitly here) the coarse
    # facets stay whole and 96.1% (1000) / 98.5% (3000) of the boundary mid-edge nodes
    # reach the surface (98.9-99.5% before the quality floor MinimumQuality, which pulls
    # nodes back rather than leave elements below 0.05).
    surface = pv.read(data_dir / "fertility.obj")
    alg = hoembed.vtkTet10Mesher()
    alg.SetInputData(surface)
    alg.SetTargetNumberOfElements(n)
    alg.PreserveBoundaryOn()
    alg.SetCurvedQualityTarget(0.0)  # the curving's reach (test_quality_target)
    assert "PreserveBoundary: On" in str(alg)
    mesh = pv.wrap(hoembed._errors.run_filter(alg))
    assert 0.7 * n < mesh.n_cells < 1.3 * n
    figures = check_mesh(surface, mesh, on_surface_fraction=0.95)
    print(n, figures)


@pytest.mark.parametrize("name,n", [("rocker-arm", 4000), ("dragon", 1000)])
def test_tet10_keeps_the_floor_where_tet4_does(data_dir, name, n):
    """The default tet10 mesh has every cell at MinimumQuality wherever the tet4 mesh of the
    same input does: curving moves corners (the free-node fit, the crossing repair), and
    those moves must not take a straight shape below the floor, which the later steps
    measure cells against and fall back to (these two inputs had tet10 cells at 0.039 and
    0.011). Checked with VTK's own scaled Jacobian of the corners and its cell validator."""
    # read as the benchmark reads it (bench_mesher_real.py)
    surface = pv.read(data_dir / f"{name}.obj").extract_surface().triangulate()
    linear, _ = mesh_with_warnings(surface, n, ElementOrder=1)
    assert np.asarray(linear.cell_data["MinScaledJacobian"]).min() >= 0.05
    assert straight_scaled_jacobian(linear).min() >= 0.05 - 1e-9
    mesh, warnings = mesh_with_warnings(surface, n)
    q = check_quality_floor(mesh, warnings)
    straight = straight_scaled_jacobian(mesh)
    assert q.min() >= 0.05, (q.min(), int(np.sum(q < 0.05)))
    assert straight.min() >= 0.05 - 1e-9, straight.min()
    assert int(mesh.field_data["PoorElementCount"][0]) == 0
    assert int(mesh.field_data["BoundaryCrossingsLeft"][0]) == 0
    assert np.all(vtk_cell_validator_states(mesh) == 0)
    print(name, n, "tet10 min/median", q.min(), np.median(q), "straight min", straight.min())


def test_self_intersecting_real_mesh(data_dir):
    """dragon.obj has 28 self-intersecting faces: meshed robustly (the coarse surface is
    checked before TetGen) or refused with a clear message, never a crash."""
    surface = pv.read(data_dir / "dragon.obj")
    try:
        mesh = hoembed.tet10_mesh(surface, n_elements=1000)
    except hoembed.HOEmbedError as err:
        assert "self-intersection" in str(err)
    else:
        assert mesh.cell_data["MinScaledJacobian"].min() > 0
        assert np.all(vtk_cell_validator_states(mesh) == 0)


def test_quality_target():
    """CurvedQualityTarget (tet10_mesh's quality_target): curving never takes a cell below
    min(target, its straight quality), judged by VTK's own tet scaled Jacobian of the
    corners; without it (0) the same input has cells far below; a higher target gives a
    better lower quartile (the cells it acts on; the median, 0.62 here, is set by cells
    above every target and moved 0.002 either way between targets once the straight
    corners were optimised) and fewer boundary nodes on the surface."""
    surface = SHAPES["bumpy"]()
    meshes = {
        t: hoembed.tet10_mesh(surface, n_elements=1000, quality_target=t) for t in (0.0, 0.2, 0.3)
    }
    default = hoembed.tet10_mesh(surface, n_elements=1000)
    # 0.2 is the default: the same mesh (to round-off: test_mesher_invariance)
    assert np.array_equal(default.cells, meshes[0.2].cells)
    np.testing.assert_allclose(
        default.points, meshes[0.2].points, rtol=0, atol=1e-12 * surface.length
    )
    quartiles, on_surface = {}, {}
    for t, mesh in meshes.items():
        q = np.asarray(mesh.cell_data["MinScaledJacobian"])
        straight = straight_scaled_jacobian(mesh)
        floor = max(0.05, t)
        assert np.all(q >= np.minimum(floor, 0.999 * straight) - 1e-9), t
        quartiles[t] = np.percentile(q, 25)
        d = distances_to_surface(surface, mesh.points[boundary_mid_nodes(mesh)])
        on_surface[t] = np.mean(d <= 1e-6 * surface.length)
    assert np.sum(meshes[0.0].cell_data["MinScaledJacobian"] < 0.2) > np.sum(
        meshes[0.3].cell_data["MinScaledJacobian"] < 0.2
    )
    assert quartiles[0.3] >= quartiles[0.2] >= quartiles[0.0]
    assert on_surface[0.0] >= on_surface[0.2] >= on_surface[0.3]
    assert on_surface[0.0] >= 0.95 and on_surface[0.2] >= 0.9
    with pytest.raises(hoembed.HOEmbedError, match="quality_target"):
        hoembed.tet10_mesh(surface, quality_target=1.5)
    print(quartiles, on_surface)
