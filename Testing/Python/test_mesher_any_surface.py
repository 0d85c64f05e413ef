"""vtkTet10Mesher on surfaces that are not clean closed manifolds (meshed through their
alpha-wrapped envelope): each input class on a small generated case, judged by VTK's own
tools (vtkCellValidator, the subdivided curved boundary with vtkSelectEnclosedPoints and
implicit distances), plus the inputs that still cannot be meshed."""

import hoembed
import numpy as np
import pytest
import pyvista as pv
from mesh_checks import expect_error, vtk_cell_validator_states


def open_sphere():
    s = pv.Sphere(theta_resolution=30, phi_resolution=30).triangulate()
    keep = np.where(s.cell_centers().points[:, 2] < 0.35)[0]
    return s.extract_cells(keep).extract_surface()


def sheet():
    p = pv.Plane(i_resolution=24, j_resolution=24).triangulate()
    p.points[:, 2] = 0.1 * np.sin(3 * p.points[:, 0])
    return p


def overlapping():
    return pv.Sphere().merge(pv.Sphere(center=(0.3, 0, 0)))


def nested():
    return pv.Sphere(radius=1.0).merge(pv.Sphere(radius=0.4))


def far_apart_with_tiny():
    # a tiny component (smaller than the envelope tolerance) must be absorbed, not dropped
    return (
        pv.Sphere()
        .merge(pv.Sphere(radius=0.004, center=(1.5, 0, 0)))
        .merge(pv.Sphere(radius=0.3, center=(3, 0, 0)))
    )


def fin():
    return (
        pv.Cube()
        .triangulate()
        .merge(
            pv.Plane(center=(0.75, 0, 0), direction=(0, 0, 1), i_size=0.5, j_size=0.6).triangulate()
        )
    )


def duplicated():
    s = pv.Sphere()
    return s.merge(s, merge_points=False)


def flipped():
    s = pv.Sphere().triangulate()
    f = s.faces.reshape(-1, 4).copy()
    f[::3, 1:] = f[::3, 1:][:, ::-1]
    return pv.PolyData(s.points, f.ravel())


def degenerate_and_duplicate_triangles():
    s = pv.Sphere().triangulate()
    f = s.faces.reshape(-1, 4)
    extra = np.array([[3, f[0, 1], f[0, 1], f[0, 2]], f[5], f[6]])
    return pv.PolyData(s.points, np.vstack([f, extra]).ravel())


def random_deletions():
    s = pv.Sphere(theta_resolution=30, phi_resolution=30).triangulate()
    rng = np.random.default_rng(1)
    return s.remove_cells(rng.choice(s.n_cells, 40, replace=False))


CASES = dict(
    open_sphere=open_sphere,
    sheet=sheet,
    overlapping=overlapping,
    nested=nested,
    far_apart_with_tiny=far_apart_with_tiny,
    fin=fin,
    duplicated=duplicated,
    flipped=flipped,
    degenerate=degenerate_and_duplicate_triangles,
    random_deletions=random_deletions,
)


def used_points(surface):
    return surface.points[np.unique(surface.faces.reshape(-1, 4)[:, 1:])]


@pytest.mark.parametrize("name", list(CASES))
def test_input_class(name):
    surface = CASES[name]()
    mesh = hoembed.tet10_mesh(surface, n_elements=400)
    assert mesh.n_cells > 50
    assert mesh.cell_data["MinScaledJacobian"].min() > 0
    assert np.all(
        vtk_cell_validator_states(mesh) & 0b100111 == 0
    )  # points, edges, faces, orientation
    # far_apart_with_tiny is three clean closed parts: the coarsening path is tried first,
    # the tiny part vanishes in the decimation, and the envelope takes over
    assert mesh.field_data["EnvelopeOffset"][0] > 0, "not meshed through the envelope"
    assert mesh.field_data["EnvelopeNodeCount"][0] >= 0
    # every input vertex is inside the curved mesh, or next to its boundary (the curved
    # boundary follows the surface between its nodes to within the element's sagitta)
    boundary = mesh.extract_surface(nonlinear_subdivision=3)
    pts = pv.PolyData(used_points(surface))
    inside = pts.select_enclosed_points(boundary, check_surface=False)["SelectedPoints"]
    dist = np.abs(pts.compute_implicit_distance(boundary)["implicit_distance"])
    worst = dist[inside == 0].max(initial=0.0) / surface.length
    # (the quality target, CurvedQualityTarget, leaves the boundary a little looser:
    # 0.031 on `overlapping`)
    assert worst < 0.035, worst
    print(
        name,
        mesh.n_cells,
        mesh.cell_data["MinScaledJacobian"].min(),
        worst,
        {k: mesh.field_data[k][0] for k in mesh.field_data.keys()},
    )


def test_envelope_tolerance_is_used():
    alg = hoembed.vtkTet10Mesher()
    alg.SetInputData(sheet())
    alg.SetTargetNumberOfElements(400)
    alg.SetEnvelopeTolerance(0.04)
    assert "EnvelopeTolerance: 0.04" in str(alg)
    mesh = pv.wrap(hoembed._errors.run_filter(alg))
    diag = sheet().length
    assert mesh.field_data["EnvelopeOffset"][0] == pytest.approx(0.04 * diag)
    assert mesh.cell_data["MinScaledJacobian"].min() > 0


def test_clean_closed_input_keeps_coarsening_path():
    mesh = hoembed.tet10_mesh(pv.Sphere(), n_elements=400)
    assert mesh.field_data["EnvelopeOffset"][0] == 0.0
    assert mesh.field_data["EnvelopeNodeCount"][0] == 0


def test_progress_through_wrap():
    seen = []
    hoembed.tet10_mesh(open_sphere(), n_elements=300, progress=seen.append)
    assert seen[-1] == 1.0
    assert len(seen) >= 6 and all(b >= a for a, b in zip(seen, seen[1:]))


def test_points_only():
    expect_error(
        pv.PolyData(np.random.default_rng(0).random((50, 3))), "no polygons", "reconstruct"
    )


def test_lines_only():
    expect_error(pv.Line(), "no polygons")


def test_zero_area_triangles_only():
    pts = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [3, 0, 0.0]])
    faces = np.array([3, 0, 1, 2, 3, 1, 2, 3])
    expect_error(pv.PolyData(pts, faces), "cannot be enclosed", "area")


def test_open_real_mesh(data_dir):
    surface = pv.read(data_dir / "stanford-bunny.obj")
    mesh = hoembed.tet10_mesh(surface, n_elements=1000)
    assert mesh.cell_data["MinScaledJacobian"].min() > 0
    assert np.all(vtk_cell_validator_states(mesh) & 0b100111 == 0)
    curved = mesh.field_data["CurvedNodeCount"][0]
    total = (
        curved + mesh.field_data["RelaxedNodeCount"][0] + mesh.field_data["EnvelopeNodeCount"][0]
    )
    print("stanford-bunny", mesh.n_cells, curved / total)
    assert curved / total > 0.5


# ---- a curved boundary that does not cross itself --------------------------------------


def _crossings(mesh):
    from boundary_crossings import crossing_face_pairs

    return crossing_face_pairs(mesh)


def test_crossing_check_can_fail():
    """The independent check (VTK's collision filter on the subdivided curved boundary)
    sees a crossing made on purpose: a boundary mid-edge node pushed through the far side."""
    mesh = hoembed.tet10_mesh(pv.Sphere(), n_elements=300)
    assert _crossings(mesh) == []
    from boundary_crossings import boundary_faces6

    f = boundary_faces6(mesh)[0]
    bent = mesh.copy()
    bent.points[f[3]] = -1.5 * bent.points[f[3]]  # through the sphere and out the other side
    assert len(_crossings(bent)) > 0


@pytest.mark.parametrize("name", ["thorny", "open_sphere", "sheet", "fin"])
def test_no_boundary_crossings(name):
    surface = hoembed.thorny_tail() if name == "thorny" else CASES[name]()
    mesh = hoembed.tet10_mesh(surface, n_elements=1000 if name == "thorny" else 400)
    assert mesh.field_data["BoundaryCrossingsLeft"][0] == 0
    assert _crossings(mesh) == []
    print(name, "crossing pairs repaired:", mesh.field_data["BoundaryCrossingsFound"][0])


@pytest.mark.parametrize("name", ["bunny_watertight", "fertility", "scorpion_low_resolution"])
def test_no_boundary_crossings_real(data_dir, name):
    mesh = hoembed.tet10_mesh(pv.read(data_dir / f"{name}.obj"), n_elements=1000)
    assert mesh.field_data["BoundaryCrossingsLeft"][0] == 0
    assert _crossings(mesh) == []


# ---- the crossing repair never leaves an element invalid ---------------------------------
# Restoring the corners of straight faces that still crossed used to straighten the
# mid-edge nodes of the cells around each restored corner without the safety net: cells
# sharing those edges (and the restored corner's cells, whose other curved edges followed
# the old geometry) ended invalid, and the mesher failed with "N elements are not valid
# after meshing (internal error)". Both cases below failed so at 06c59cb/b13c4f8.


def _check_valid(mesh):
    """Every element valid, judged by VTK (shape-function derivatives, vtkCellValidator)
    and the crossing count that the filter reports matches the independent check."""
    from test_fuzz_surfaces import _jacobian_dets, _vtk_invalid_cells

    assert mesh.n_cells > 0 and np.all(mesh.celltypes == 24)
    assert np.all(_jacobian_dets(mesh) > 0)
    assert _vtk_invalid_cells(mesh) == 0
    left = int(mesh.field_data["BoundaryCrossingsLeft"][0])
    assert (left == 0) == (_crossings(mesh) == [])


def test_crossing_repair_keeps_elements_valid_tiny_overlap():
    """Generated: two overlapping boxes at a diagonal of 5e-6 (fuzz seed 1248)."""
    from test_fuzz_surfaces import damaged_surface

    surface, kinds = damaged_surface(1248)
    assert sorted(kinds) == ["overlap", "tiny"] and surface.length < 1e-5
    mesh = hoembed.tet10_mesh(surface, n_elements=150)
    _check_valid(mesh)


def test_crossing_repair_keeps_elements_valid_fertility(data_dir):
    """fertility.obj at 300 elements (a clean closed surface, coarsening path)."""
    mesh = hoembed.tet10_mesh(pv.read(data_dir / "fertility.obj"), n_elements=300)
    _check_valid(mesh)


# ---- what a user means by closed is closed ---------------------------------------------


def test_rounded_shared_vertices_are_merged():
    """An STL-like sphere: every triangle has its own three vertices, rounded differently
    (1e-8 of the diagonal): merged, it is a clean closed surface (coarsening path)."""
    s = pv.Sphere(theta_resolution=24, phi_resolution=24).triangulate()
    tri = s.faces.reshape(-1, 4)[:, 1:]
    rng = np.random.default_rng(2)
    pts = s.points[tri.ravel()] + rng.uniform(-1e-8, 1e-8, (tri.size, 3)) * s.length
    faces = np.hstack([np.full((len(tri), 1), 3), np.arange(tri.size).reshape(-1, 3)])
    soup = pv.PolyData(pts, faces.ravel())
    mesh = hoembed.tet10_mesh(soup, n_elements=300)
    assert mesh.field_data["EnvelopeOffset"][0] == 0.0, "not merged into a closed surface"
    alg = hoembed.vtkTet10Mesher()
    alg.SetMergeTolerance(0.0)
    alg.SetInputData(soup)
    alg.SetTargetNumberOfElements(300)
    unmerged = pv.wrap(hoembed._errors.run_filter(alg))
    assert unmerged.field_data["EnvelopeOffset"][0] > 0  # open everywhere without the merge


def test_non_planar_quads_and_strips():
    cube = pv.Cube().clean()
    cube.points[0] += [0.02, -0.03, 0.05]  # three quads around it are no longer planar
    assert np.all(cube.faces.reshape(-1, 5)[:, 0] == 4)
    mesh = hoembed.tet10_mesh(cube, n_elements=200)
    assert mesh.field_data["EnvelopeOffset"][0] == 0.0  # every quad gave two triangles
    strips = pv.Sphere().strip()
    assert strips.GetNumberOfStrips() > 0 and strips.GetNumberOfPolys() == 0
    mesh = hoembed.tet10_mesh(strips, n_elements=300)
    assert mesh.field_data["EnvelopeOffset"][0] == 0.0
    assert mesh.cell_data["MinScaledJacobian"].min() > 0


def test_size_estimate_of_an_open_sheet():
    """The size check before any work estimates an open sheet by its envelope (area times
    half the element size), whatever its position: a flat sheet through the origin has a
    signed volume of 0, which used to let any request through."""
    plane = pv.Plane(
        center=(0, 0, 0), i_size=1.0, j_size=1.0, i_resolution=20, j_resolution=20
    ).triangulate()
    for shift in (0.0, 50.0):
        sheet = plane.translate((shift, shift, shift), inplace=False)
        alg = hoembed.vtkTet10Mesher()
        alg.SetInputData(sheet)
        alg.SetTargetEdgeLength(0.05)
        # envelope volume about 1 * 0.025; a regular tet of edge 0.05 has 1.47e-5: ~1700
        alg.SetMaximumNumberOfElements(1000)
        with pytest.raises(hoembed.HOEmbedError, match="MaximumNumberOfElements"):
            hoembed._errors.run_filter(alg)


def cube_with_cavity(outer=1.0, inner=0.5):
    """A clean closed solid with a closed inner shell (a cube inside a cube, the inner one's
    triangles facing into the cavity): two components, 0.875 of volume."""
    a = pv.Cube(x_length=outer, y_length=outer, z_length=outer).triangulate()
    b = pv.Cube(x_length=inner, y_length=inner, z_length=inner).triangulate()
    a, b = a.subdivide(2, "linear").clean(), b.subdivide(2, "linear").clean()
    f = b.faces.reshape(-1, 4).copy()
    f[:, 1:] = f[:, 1:][:, ::-1]
    return a.merge(pv.PolyData(b.points, f.ravel()))


@pytest.mark.parametrize("n", [300, 1000])
def test_cavity_stays_empty(n):
    """TetGen fills the inside of a closed inner shell unless it is named a hole: the run
    used to fail its volume check, fall back to the envelope and fill the cavity."""
    surface = cube_with_cavity()
    assert surface.n_open_edges == 0 and surface.is_manifold
    assert surface.volume == pytest.approx(0.875)
    mesh = hoembed.tet10_mesh(surface, n_elements=n)
    assert mesh.field_data["EnvelopeOffset"][0] == 0.0  # the coarsening path, no fallback
    volume = mesh.compute_cell_sizes(length=False, area=False)["Volume"].sum()
    assert volume == pytest.approx(0.875, rel=0.02)
    probes = pv.PolyData(np.array([[0.0, 0, 0], [0.1, -0.15, 0.2], [0.4, 0.4, 0.4]]))
    inside = probes.select_enclosed_points(
        mesh.extract_surface(nonlinear_subdivision=2), check_surface=False
    )["SelectedPoints"]
    assert list(inside) == [0, 0, 1]  # the cavity is empty, the material is not


def test_poor_elements_warning_names_a_count(data_dir):
    """Elements whose straight shape is below the floor are named in a warning with the
    figures and the count that would lift them (issue 27), each by its output cell id;
    meshing at that count does. At the default floor (0.05) the inputs of ../shared/data
    leave none (curving keeps the floor where the straight mesh has it), so the floor is
    raised to 0.3: fertility at 300 keeps one straight shape below it."""
    import re
    import warnings

    path = data_dir / "fertility.obj"
    if not path.exists():
        pytest.skip(f"{path} not available")
    surface = pv.read(path)
    floor = 0.3
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        mesh = hoembed.tet10_mesh(surface, n_elements=300, minimum_quality=floor)
    poor = int(mesh.field_data["PoorElementCount"][0])
    assert poor > 0
    text = [
        str(w.message)
        for w in caught
        if "elements have a minimum scaled Jacobian" in str(w.message)
    ]
    assert len(text) == 1 and f"{poor} of {mesh.n_cells} elements" in text[0], text
    assert f"below MinimumQuality = {floor}" in text[0], text[0]
    m = re.search(
        r"about (\d+) elements \(TargetNumberOfElements; TargetEdgeLength "
        r"([0-9.e+-]+), now ([0-9.e+-]+)\)",
        text[0],
    )
    assert m, text[0]
    # every poor cell named by its output id with its quality, worst first
    named = re.search(r"Output cells \(id: quality\) (.*)$", text[0])
    assert named, text[0]
    pairs = [p.split(": ") for p in named.group(1).split(", ")]
    ids = [int(i) for i, _ in pairs]
    q = np.asarray(mesh.cell_data["MinScaledJacobian"])
    assert sorted(ids) == sorted(np.nonzero(q < floor)[0].tolist())
    assert all(abs(float(v) - q[i]) <= 1e-5 * q[i] for i, (_, v) in zip(ids, pairs))
    assert [float(v) for _, v in pairs] == sorted(float(v) for _, v in pairs)
    count, size, now = int(m.group(1)), float(m.group(2)), float(m.group(3))
    assert mesh.n_cells < count <= 100 * mesh.n_cells and size < now
    finer = hoembed.tet10_mesh(surface, n_elements=count, minimum_quality=floor)
    assert int(finer.field_data["PoorElementCount"][0]) < poor


def test_minimum_quality_default_and_range():
    """tet10_mesh's minimum_quality is the driver's MinimumQuality: its default, and its
    range refused with the driver's sentence."""
    import inspect

    from hoembed._errors import HOEmbedArgumentError
    from hoembed._hoembed import DEFAULTS

    default = inspect.signature(hoembed.tet10_mesh).parameters["minimum_quality"].default
    assert default == DEFAULTS["mesher"]["MinimumQuality"] == 0.05
    with pytest.raises(HOEmbedArgumentError, match="MinimumQuality must be in"):
        hoembed.tet10_mesh(pv.Sphere(), minimum_quality=1.5)


@pytest.mark.parametrize("n", [300, 1000, 4000])
def test_low_poly_input_reaches_the_count(n):
    """A cube of 12 triangles: TetGen adds no point on the boundary (PreserveBoundary), so
    its long edges are bisected to the element size; it gave 6 elements at any count."""
    mesh = hoembed.tet10_mesh(pv.Cube().triangulate(), n_elements=n)
    assert 0.7 * n <= mesh.n_cells <= 1.3 * n
    assert mesh.field_data["EnvelopeOffset"][0] == 0.0
    assert mesh.cell_data["MinScaledJacobian"].min() >= 0.05


def test_low_poly_counts_follow_the_target():
    """Four low-poly surfaces (cube, long box, capped cylinder, icosahedron: 12-192
    triangles) at six counts from 300 to 10000: the count lands within 30% of the target in
    all but at most one of the 24 runs. Splitting every triangle in four moved the
    boundary's resolution in steps of four: 4 of these 24 runs were off (up to 2.19x)."""
    surfaces = [
        pv.Cube().triangulate().clean(),
        pv.Box(bounds=(0, 4, 0, 1, 0, 1), level=3).triangulate().clean(),
        pv.Cylinder(resolution=24, capping=True).triangulate().clean(),
        pv.Icosahedron().triangulate().clean(),
    ]
    ratios = []
    for surface in surfaces:
        for n in (300, 1000, 2000, 4000, 7000, 10000):
            mesh = hoembed.tet10_mesh(surface, n_elements=n, order=1)
            assert mesh.cell_data["MinScaledJacobian"].min() >= 0.05
            ratios.append(round(mesh.n_cells / n, 2))
    off = [r for r in ratios if not 1 / 1.3 <= r <= 1.3]
    assert len(off) <= 1, ratios


def test_count_off_target_is_warned():
    """Where the count control finds no element size within 30% of the target, a warning
    says so with the count and the target; where it does, none. Off when written: a plate
    of 10 x 10 x 0.2 at 20 elements (1.70x: it is thinner than the element size) and a
    capped cylinder of 92 triangles at 50 (0.54x); within: the cylinder at 4000 and a long
    box of 192 triangles at 10000 (1.83x and 0.57x when low-poly boundaries were split in
    four). The test needs one of its cases to be off target, so it names new ones if the
    count control learns to hit these."""
    import re
    import warnings

    cylinder = pv.Cylinder(resolution=24, capping=True).triangulate().clean()
    cases = [
        (pv.Box(bounds=(0, 10, 0, 10, 0, 0.2)).triangulate().clean(), 20),
        (cylinder, 50),
        (cylinder, 4000),
        (pv.Box(bounds=(0, 4, 0, 1, 0, 1), level=3).triangulate().clean(), 10000),
    ]
    warned = 0
    for surface, n in cases:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            mesh = hoembed.tet10_mesh(surface, n_elements=n, order=1)
        text = [str(w.message) for w in caught if "elements for a target of" in str(w.message)]
        off = not (n / 1.3 <= mesh.n_cells <= 1.3 * n)
        assert len(text) == int(off), (n, mesh.n_cells, text)
        if off:
            warned += 1
            m = re.search(r"the mesh has (\d+) elements for a target of (\d+)", text[0])
            assert m and int(m.group(1)) == mesh.n_cells and int(m.group(2)) == n, text[0]
    assert warned >= 1
