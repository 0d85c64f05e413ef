"""hoembed.transfer: identity, rigid exactness, an affine deformation against the analytic
answer, rotated normals, point normals, bad input; real meshes when available.

Embedded surfaces are built by construction on straight box meshes: points on boundary
faces that do not touch a box edge (there the smooth normal field is the flat face normal
exactly), moved off along that normal, so v = p + d n holds by construction and the
affine image of the surface is known analytically."""

import hoembed
import numpy as np
import pytest
import pyvista as pv
import vtkmodules.vtkCommonCore as vcore
from conftest import box_tet_mesh

# VTK face order, tri6 corners first (hoembed::TetFaceNodes).
FACE_CORNERS = np.array([[0, 1, 3], [1, 2, 3], [2, 0, 3], [0, 2, 1]])
CORNER_PC = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)


def fingerprint(mesh):
    """hoembed::MeshFingerprint: FNV-1a 64 over little-endian int64 values."""
    h = 14695981039346656037
    mask = (1 << 64) - 1

    def add(v):
        nonlocal h
        for b in int(v).to_bytes(8, "little", signed=True):
            h ^= b
            h = (h * 1099511628211) & mask

    add(mesh.n_points)
    add(mesh.n_cells)
    conn = mesh.cells.reshape(mesh.n_cells, -1)[:, 1:]
    for t, ids in zip(mesh.celltypes, conn):
        add(t)
        for i in ids:
            add(i)
    return f"{h:016x}"


def cell_conn(mesh):
    return mesh.cells.reshape(mesh.n_cells, -1)[:, 1:]


def embedded_box_surface(mesh, size, rng, method="normal-offset", n_interior=30):
    """Points on boundary faces away from box edges, offset along the face normal."""
    conn = cell_conn(mesh)
    pts = mesh.points
    size = np.asarray(size, float)
    keys = {}
    for c in range(mesh.n_cells):
        for f in range(4):
            key = tuple(sorted(conn[c, FACE_CORNERS[f]]))
            keys.setdefault(key, []).append((c, f))
    cells, pcs, dists, faces, verts, tris = [], [], [], [], [], []
    for key, owners in keys.items():
        if len(owners) != 1:
            continue
        c, f = owners[0]
        corners = pts[conn[c, FACE_CORNERS[f]]]
        on_planes = np.isclose(corners, 0.0) | np.isclose(corners, size)
        axis = np.where(on_planes.all(axis=0))[0]
        if len(axis) != 1 or (on_planes.sum(axis=1) > 1).any():
            continue  # touches a box edge: the nodal normals there are averaged
        a = axis[0]
        normal = np.zeros(3)
        normal[a] = 1.0 if np.isclose(corners[0, a], size[a]) else -1.0
        base = len(verts)
        for uv in ((0.2, 0.2), (0.6, 0.2), (0.2, 0.6)):
            w = np.array([1 - uv[0] - uv[1], uv[0], uv[1]])
            pc = w @ CORNER_PC[FACE_CORNERS[f]]
            p = w @ corners
            d = rng.uniform(-0.1, 0.3) if method == "normal-offset" else 0.0
            cells.append(c)
            pcs.append(pc)
            dists.append(d)
            faces.append(f if d != 0.0 else -1)
            verts.append(p + d * normal)
        tris.append([3, base, base + 1, base + 2])
    for _ in range(n_interior):
        c = rng.integers(mesh.n_cells)
        lam = rng.uniform(0.05, 1.0, 4)
        lam /= lam.sum()
        corners = pts[conn[c, :4]]
        cells.append(c)
        pcs.append(lam[1:])
        dists.append(0.0)
        faces.append(-1)
        verts.append(lam @ corners)
    surf = pv.PolyData(np.array(verts), faces=np.hstack(tris), deep=True)
    surf.point_data["EmbeddingCellId"] = np.array(cells, dtype=np.int64)
    surf.point_data["EmbeddingParametricCoords"] = np.array(pcs)
    surf.point_data["EmbeddingDistance"] = np.array(dists)
    surf.point_data["EmbeddingResidual"] = np.zeros(len(verts))
    surf.point_data["EmbeddingFace"] = np.array(faces, dtype=np.int8)
    _set_field(surf, "EmbeddingMethod", method)
    _set_field(surf, "EmbeddingMeshFingerprint", fingerprint(mesh))
    return surf


def _set_field(ds, name, value):
    arr = vcore.vtkStringArray()
    arr.SetName(name)
    arr.InsertNextValue(value)
    ds.GetFieldData().AddArray(arr)


def moved(mesh, fn, displacement=False):
    """A copy of mesh with its points mapped by fn; with `displacement`, also the
    point data Displacement a stepper gives (new - old points)."""
    out = mesh.copy()
    out.points = fn(np.asarray(mesh.points))
    if displacement:
        out.point_data["Displacement"] = np.asarray(out.points) - np.asarray(mesh.points)
    return out


def random_rigid(rng):
    q = rng.normal(size=4)
    q /= np.linalg.norm(q)
    w, x, y, z = q
    R = np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )
    return R, rng.normal(scale=5.0, size=3)


SIZE = (4.0, 3.0, 3.0)


def rest_p_and_n(surf):
    """p and the box-face normal n of every vertex (n = 0 where d = 0), recovered from the
    construction: p lies on the box plane that v - d n hits exactly."""
    d = surf.point_data["EmbeddingDistance"]
    v = np.asarray(surf.points)
    n = np.zeros_like(v)
    for i in np.where(d != 0)[0]:
        for a in range(3):
            for s, plane in ((-1.0, 0.0), (1.0, SIZE[a])):
                if abs(v[i, a] - s * d[i] - plane) < 1e-12:
                    n[i, a] = s
    assert np.allclose(np.abs(n[d != 0]).sum(axis=1), 1.0)
    return v - d[:, None] * n, n


@pytest.fixture(params=[2, 1], ids=["tet10", "tet4"])
def setup(request):
    rng = np.random.default_rng(5)
    mesh = box_tet_mesh((4, 3, 3), SIZE, order=request.param)
    return mesh, rng


@pytest.mark.parametrize("method", ["normal-offset", "barycentric"])
def test_identity_and_rigid(setup, method):
    mesh, rng = setup
    surf = embedded_box_surface(mesh, SIZE, rng, method=method)
    diag = surf.length
    out = hoembed.transfer(surf, mesh)
    assert isinstance(out, pv.PolyData)
    assert out.n_points == surf.n_points and out.n_cells == surf.n_cells
    assert "EmbeddingCellId" not in out.point_data
    assert np.abs(out.points - surf.points).max() < 1e-10 * diag
    for _ in range(3):
        R, t = random_rigid(rng)
        out = hoembed.transfer(surf, moved(mesh, lambda x: x @ R.T + t))
        assert np.abs(out.points - (surf.points @ R.T + t)).max() < 1e-9 * diag


def test_affine_deformation_analytic(setup):
    """Affine map A x + b: p' = A p + b and flat faces keep flat normals cof(A) n, so
    v' = A p + b + d normalise(A^-T n) exactly; barycentric would give A v + b instead."""
    mesh, rng = setup
    surf = embedded_box_surface(mesh, SIZE, rng)
    A = np.array([[1.3, 0.2, -0.1], [0.1, 0.8, 0.3], [-0.2, 0.1, 1.1]])
    b = np.array([0.5, -1.0, 2.0])
    out = hoembed.transfer(surf, moved(mesh, lambda x: x @ A.T + b))
    d = surf.point_data["EmbeddingDistance"]
    v = np.asarray(surf.points)
    p, n_rest = rest_p_and_n(surf)
    offset = d != 0
    n_def = n_rest @ np.linalg.inv(A)  # rows: A^-T n
    n_def[offset] /= np.linalg.norm(n_def[offset], axis=1)[:, None]
    expect = p @ A.T + b + d[:, None] * n_def
    err = np.abs(out.points - expect).max() / surf.length
    assert err < 1e-12
    # The test can fail: barycentric extrapolation would be A v + b.
    assert np.abs(out.points - (v @ A.T + b)).max() > 1e-3


def test_rotate_normals(setup):
    mesh, rng = setup
    surf = embedded_box_surface(mesh, SIZE, rng)
    R, t = random_rigid(rng)
    m = moved(mesh, lambda x: x @ R.T + t, displacement=True)
    m.point_data["NodalRotation"] = np.tile(R.reshape(1, 9), (m.n_points, 1))
    warnings = []
    out = hoembed.transfer(surf, m, normals="rotate", warnings=warnings)
    assert not warnings
    assert np.abs(out.points - (surf.points @ R.T + t)).max() < 1e-9 * surf.length
    # Identity rotations with a shear: the rest normals are kept (recompute would tilt them).
    A = np.array([[1.0, 0.0, 0.5], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    m2 = moved(mesh, lambda x: x @ A.T, displacement=True)
    m2.point_data["NodalRotation"] = np.tile(np.eye(3).reshape(1, 9), (m2.n_points, 1))
    rot = hoembed.transfer(surf, m2, normals="rotate")
    rec = hoembed.transfer(surf, m2, normals="recompute")
    d = surf.point_data["EmbeddingDistance"]
    p, n_rest = rest_p_and_n(surf)
    assert np.abs(rot.points - (p @ A.T + d[:, None] * n_rest)).max() < 1e-12 * surf.length
    assert np.abs(rec.points - rot.points).max() > 1e-3
    # Without the arrays: a warning, then recomputed normals.
    warnings = []
    out = hoembed.transfer(
        surf, moved(mesh, lambda x: x @ R.T + t), normals="rotate", warnings=warnings
    )
    assert any("NodalRotation" in w for w in warnings)
    assert np.abs(out.points - (surf.points @ R.T + t)).max() < 1e-9 * surf.length


def test_deform_normals(setup):
    """normals="deform": rigid motions stay exact; under a shear of the surface layer the
    offsets lean with the material (unlike the recomputed surface normals); without
    Displacement a warning and the recomputed normals (exactness against normalise(A n) is
    checked in cxx.TestDeformationTransferFilter)."""
    mesh, rng = setup
    surf = embedded_box_surface(mesh, SIZE, rng)
    R, t = random_rigid(rng)
    m = moved(mesh, lambda x: x @ R.T + t, displacement=True)
    warnings = []
    out = hoembed.transfer(surf, m, normals="deform", warnings=warnings)
    assert not warnings
    assert np.abs(out.points - (surf.points @ R.T + t)).max() < 1e-9 * surf.length
    A = np.array([[1.0, 0.0, 0.5], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    m2 = moved(mesh, lambda x: x @ A.T, displacement=True)
    dfm = hoembed.transfer(surf, m2, normals="deform")
    rec = hoembed.transfer(surf, m2, normals="recompute")
    assert np.abs(dfm.points - rec.points).max() > 1e-3
    # Closer to the material map A v than the recomputed normals are.
    exact = np.asarray(surf.points) @ A.T
    assert (
        np.linalg.norm(dfm.points - exact, axis=1).mean()
        < np.linalg.norm(rec.points - exact, axis=1).mean()
    )
    warnings = []
    out = hoembed.transfer(
        surf, moved(mesh, lambda x: x @ A.T), normals="deform", warnings=warnings
    )
    assert any("Displacement" in w for w in warnings)
    assert np.abs(out.points - rec.points).max() < 1e-12 * surf.length


def test_point_normals(setup):
    mesh, rng = setup
    surf = embedded_box_surface(mesh, SIZE, rng)
    out = hoembed.transfer(surf, mesh, compute_point_normals=True)
    n = out.point_data["Normals"]
    used = np.zeros(out.n_points, bool)
    used[out.faces.reshape(-1, 4)[:, 1:].ravel()] = True
    assert np.allclose(np.linalg.norm(n[used], axis=1), 1.0, atol=1e-6)
    # Each triangle here is isolated: its vertex normals are its face normal.
    tri = out.faces.reshape(-1, 4)[:, 1:]
    P = np.asarray(out.points)
    fn = np.cross(P[tri[:, 1]] - P[tri[:, 0]], P[tri[:, 2]] - P[tri[:, 0]])
    fn /= np.linalg.norm(fn, axis=1)[:, None]
    assert np.abs(n[tri[:, 0]] - fn).max() < 1e-5


def test_bad_input(setup):
    mesh, rng = setup
    surf = embedded_box_surface(mesh, SIZE, rng)
    for name in ("EmbeddingCellId", "EmbeddingParametricCoords", "EmbeddingDistance"):
        s = surf.copy()
        s.point_data.remove(name)
        with pytest.raises(hoembed.HOEmbedError, match=name):
            hoembed.transfer(s, mesh)
    other = box_tet_mesh((4, 3, 2), SIZE, order=2)
    with pytest.raises(hoembed.HOEmbedError, match="not the mesh"):
        hoembed.transfer(surf, other)
    nan = mesh.copy()
    nan.points[3] = np.nan
    with pytest.raises(hoembed.HOEmbedError, match="non-finite"):
        hoembed.transfer(surf, nan)
    with pytest.raises(ValueError):
        hoembed.transfer(surf, mesh, normals="sideways")
    # Inverted elements: a warning, still mapped.
    flipped = moved(mesh, lambda x: x * np.array([1.0, 1.0, -1.0]))
    warnings = []
    out = hoembed.transfer(surf, flipped, warnings=warnings)
    assert any("inverted" in w for w in warnings)
    assert np.isfinite(out.points).all() and out.n_points == surf.n_points


def test_vtk_pipeline_class():
    alg = hoembed.vtkDeformationTransferFilter()
    assert alg.GetNormalMode() == 0 and not alg.GetComputePointNormals()
    alg.SetNormalModeToRotate()
    assert alg.GetNormalMode() == 1
    alg.SetNormalModeToDeform()
    assert alg.GetNormalMode() == alg.DEFORM_NORMALS == 2


def test_saved_embedding_round_trip(setup, tmp_path):
    """The embedded surface written to .vtp and read back (as users load it at start-up)
    transfers like the original; without EmbeddingFace (older files) too."""
    mesh, rng = setup
    surf = embedded_box_surface(mesh, SIZE, rng)
    path = tmp_path / "embedded.vtp"
    surf.save(path)
    back = pv.read(path)
    assert back.GetFieldData().GetAbstractArray("EmbeddingMethod") is not None
    R, t = random_rigid(rng)
    m = moved(mesh, lambda x: x @ R.T + t)
    ref = hoembed.transfer(surf, m)
    out = hoembed.transfer(back, m)
    assert np.abs(out.points - ref.points).max() < 1e-12 * surf.length
    back.point_data.remove("EmbeddingFace")
    out = hoembed.transfer(back, m)
    assert np.abs(out.points - ref.points).max() < 1e-12 * surf.length


def test_time_series_pipeline(setup):
    """A time-aware mesh source -> transfer: TIME_STEPS reach the output, the requested
    time reaches the source, the output carries DATA_TIME_STEP (so a writer downstream
    sees a surface time series)."""
    from vtkmodules.util.vtkAlgorithm import VTKPythonAlgorithmBase
    from vtkmodules.vtkCommonDataModel import vtkDataObject, vtkUnstructuredGrid
    from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline as SDDP

    mesh, rng = setup
    surf = embedded_box_surface(mesh, SIZE, rng)
    steps = [0.0, 0.5, 1.0]

    class Source(VTKPythonAlgorithmBase):
        def __init__(self):
            super().__init__(nInputPorts=0, nOutputPorts=1, outputType="vtkUnstructuredGrid")

        def RequestInformation(self, request, inInfo, outInfo):
            info = outInfo.GetInformationObject(0)
            info.Set(SDDP.TIME_STEPS(), steps, len(steps))
            info.Set(SDDP.TIME_RANGE(), [steps[0], steps[-1]], 2)
            return 1

        def RequestData(self, request, inInfo, outInfo):
            info = outInfo.GetInformationObject(0)
            t = info.Get(SDDP.UPDATE_TIME_STEP()) if info.Has(SDDP.UPDATE_TIME_STEP()) else 0.0
            m = moved(mesh, lambda x: x + np.array([t, 0.0, 0.0]))
            out = vtkUnstructuredGrid.GetData(outInfo)
            out.ShallowCopy(m)
            out.GetInformation().Set(vtkDataObject.DATA_TIME_STEP(), t)
            return 1

    src = Source()
    alg = hoembed.vtkDeformationTransferFilter()
    alg.SetInputData(0, surf)
    alg.SetMeshConnection(src.GetOutputPort())
    alg.UpdateInformation()
    info = alg.GetOutputInformation(0)
    assert [info.Get(SDDP.TIME_STEPS(), i) for i in range(info.Length(SDDP.TIME_STEPS()))] == steps
    for t in (0.5, 1.0):
        alg.UpdateTimeStep(t)
        out = alg.GetOutput()
        assert out.GetInformation().Get(vtkDataObject.DATA_TIME_STEP()) == t
        shift = pv.wrap(out).points - surf.points
        assert np.abs(shift - np.array([t, 0.0, 0.0])).max() < 1e-12


def test_passes_user_data_drops_embedding_arrays(setup):
    mesh, rng = setup
    surf = embedded_box_surface(mesh, SIZE, rng)
    surf.point_data["EmbeddingIterations"] = np.ones(surf.n_points, dtype=np.int32)
    surf.point_data["Color"] = np.arange(surf.n_points, dtype=float)
    surf.cell_data["Label"] = np.arange(surf.n_cells)
    out = hoembed.transfer(surf, mesh)
    assert not [k for k in out.point_data.keys() if k.startswith("Embedding")]
    assert np.array_equal(out.point_data["Color"], surf.point_data["Color"])
    assert np.array_equal(out.cell_data["Label"], surf.cell_data["Label"])


def _embedding_available():
    return hasattr(hoembed, "embed")


def _check_embedded_transfer(surface, mesh, method, rng):
    surface = surface.copy()
    surface.points = np.asarray(surface.points, dtype=float)  # double output (default: as input)
    emb = hoembed.embed(surface, mesh, method=method)
    diag = emb.length
    rest = hoembed.transfer(emb, mesh)
    # The embedding reports |v - rebuilt v| per vertex (computed as this filter rebuilds):
    # the transfer at rest must reproduce the surface up to exactly that.
    residual = np.asarray(emb.point_data["EmbeddingResidual"])
    identity = np.linalg.norm(rest.points - surface.points, axis=1)
    assert np.all(identity <= residual + 1e-10 * diag), np.max(identity - residual) / diag
    for _ in range(2):
        R, t = random_rigid(rng)
        out = hoembed.transfer(emb, moved(mesh, lambda x: x @ R.T + t))
        assert np.abs(out.points - (np.asarray(rest.points) @ R.T + t)).max() < 1e-9 * diag
    return identity.max() / diag, residual.max() / diag


@pytest.mark.skipif(not _embedding_available(), reason="vtkEmbeddingCoordinatesFilter not built")
@pytest.mark.parametrize("method", ["normal-offset", "barycentric"])
def test_end_to_end_with_embedding_filter(method):
    """hoembed.embed -> hoembed.transfer on a curved box mesh carrying a finer box surface
    around it: identity within the embedding's residual, rigid exactness."""
    rng = np.random.default_rng(8)

    def curve(p):
        q = p.copy()
        q[:, 0] += 0.05 * np.sin(2 * p[:, 1] + p[:, 2])
        q[:, 2] += 0.06 * np.cos(1.7 * p[:, 0] + p[:, 1])
        return q

    mesh = box_tet_mesh((4, 2, 2), (4.0, 1.0, 1.0), order=2, mapping=curve)
    surface = pv.Box(bounds=(-0.1, 4.1, -0.15, 1.15, -0.2, 1.2), level=12).triangulate()
    surface = surface.clean()
    surface.points = curve(np.asarray(surface.points))
    _check_embedded_transfer(surface, mesh, method, rng)


@pytest.mark.skipif(not _embedding_available(), reason="vtkEmbeddingCoordinatesFilter not built")
def test_end_to_end_real_mesh(data_dir):
    """A real surface, its vtkTet10Mesher mesh, its embedding: identity within the
    residual, rigid exactness (normal-offset and barycentric)."""
    rng = np.random.default_rng(9)
    surface = pv.read(data_dir / "bunny_lowres.obj")
    mesh = hoembed.tet10_mesh(surface, n_elements=300)
    for method in ("normal-offset", "barycentric"):
        _check_embedded_transfer(surface, mesh, method, rng)
