"""The pip package (the wheel, in a venv with a pip VTK and pyvista) against the VTK build.

HOEMBED_PIP_REFERENCE names a folder written by generate_reference.py with the VTK
build (Debian VTK 9.1): the same inputs go through the pip package here, and its
embedding arrays and transferred points must equal the VTK filters' bit for bit (both
bindings call the same drivers, compiled from the same sources with the same flags;
the loops write per-vertex results, so the thread count does not matter either). The
stepper's frames too, when its kernels are compiled with the VTK build's flags
(HOEMBED_SIMULATION_NATIVE=ON: `make test-pip` builds the wheel so; these meshes of a few
hundred cells stay below the solver's thresholds for parallel loops, so the thread count
is not exercised for the stepper here). scripts/test_pip.sh sets HOEMBED_PIP_NATIVE=1 for
that test build; the portable wheel's frames (no -march=native: no FMA contraction) must
agree to round-off instead (ROUND_OFF).
"""

import json
import os
import subprocess
import sys
import warnings

import hoembed
import numpy as np
import pytest
import pyvista
from generate_reference import resolve  # the same "@Name" arguments as the references

REF = os.environ.get("HOEMBED_PIP_REFERENCE", "")
if not REF or not os.path.exists(os.path.join(REF, "cases.json")):
    pytest.skip(
        "HOEMBED_PIP_REFERENCE (generate_reference.py output) not given", allow_module_level=True
    )
CASES = json.load(open(os.path.join(REF, "cases.json")))

EMBEDDING_ARRAYS = [
    "EmbeddingCellId",
    "EmbeddingParametricCoords",
    "EmbeddingDistance",
    "EmbeddingResidual",
    "EmbeddingFace",
    "EmbeddingIterations",
    "EmbeddingElementsVisited",
    "EmbeddingClosestDistance",
    "EmbeddingFallback",
]


def read(case, name):
    return pyvista.read(os.path.join(REF, case, name))


def bitwise(a, b):
    a, b = np.asarray(a), np.asarray(b)
    return (
        a.shape == b.shape
        and a.dtype == b.dtype
        and np.array_equal(a.view(np.uint8), b.view(np.uint8))
    )


# the stepper's kernels compiled as the VTK build's (HOEMBED_SIMULATION_NATIVE=ON)?
NATIVE = os.environ.get("HOEMBED_PIP_NATIVE") == "1"
# the portable wheel against the VTK build's -march=native frames: FMA contraction moves
# the last bits; relative to the run's largest magnitude of that array (the bounding-box
# diagonal for the points), since quantities near zero (the rest frame's stress) are all
# round-off. Seen on 9.4.2 and 9.7.2: points 1.9e-13, Displacement 1.2e-11, VonMisesStress
# 2.9e-11; integer arrays equal.
ROUND_OFF = 1e-9
# The dragged ("prescribed") run's CG: at its default stop (SolverTolerance 1e-4) the two
# builds' round-off could end it at neighbouring iterates, by an amount that changed with
# the bunny's mesh and the machine (the VTK build is -march=native): VonMisesStress 3.3e-6,
# later 1.3e-5 of its largest value (VTK 9.4.2). The reference runs it to 1e-10 instead
# (generate_reference.py): 1.2e-10 on the bunny, points 4.6e-13 of the diagonal.
CG_PATH = 1e-8


def same_frame_values(a, b, scale, tolerance=ROUND_OFF):
    """Bitwise for the test build, else equal integers and floats within `tolerance` of
    scale."""
    if NATIVE:
        return bitwise(a, b)
    a, b = np.asarray(a), np.asarray(b)
    if a.shape != b.shape or a.dtype != b.dtype:
        return False
    if not np.issubdtype(b.dtype, np.floating):
        return np.array_equal(a, b)
    return bool(np.all(np.abs(a - b) <= tolerance * scale))


def test_not_the_vtk_build():
    # the package under test is the wheel's, beside a pip VTK (no Debian VTK 9.1)
    import vtkmodules

    assert hoembed.BACKEND == "pip"
    assert sys.prefix != sys.base_prefix  # a venv ...
    assert not any("dist-packages" in p for p in sys.path)  # ... without system packages
    assert not vtkmodules.__file__.startswith("/usr/lib/python3/dist-packages")
    assert "site-packages" in hoembed.__file__


@pytest.mark.parametrize("case", sorted(CASES))
@pytest.mark.parametrize("method", ["normal-offset", "barycentric"])
def test_embedding_bitwise(case, method):
    surface, mesh = read(case, "surface.vtp"), read(case, "mesh.vtu")
    ref = read(case, f"embedded_{method}.vtp")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        got = hoembed.embed(surface, mesh, method=method)
    names = EMBEDDING_ARRAYS + (
        ["EmbeddingFallbackOffset"] if "EmbeddingFallbackOffset" in ref.point_data else []
    )
    for name in names:
        assert name in got.point_data, name
        assert bitwise(got.point_data[name], ref.point_data[name]), name
    assert sorted(got.point_data.keys()) == sorted(ref.point_data.keys())
    for name in ("EmbeddingMethod", "EmbeddingMeshFingerprint"):
        assert str(got.field_data[name][0]) == str(ref.field_data[name][0]), name
    assert int(got.field_data["NumberOfFallbackPoints"][0]) == int(
        ref.field_data["NumberOfFallbackPoints"][0]
    )
    assert bitwise(got.points, surface.points)
    assert bitwise(got.faces, surface.faces)
    # something real was embedded: all ids valid, residuals at round-off
    assert got.point_data["EmbeddingCellId"].min() >= 0
    assert got.point_data["EmbeddingCellId"].max() < mesh.n_cells


@pytest.mark.parametrize("case", sorted(CASES))
def test_transfer_bitwise(case):
    info = CASES[case]
    embedded_ref = read(case, "embedded_normal-offset.vtp")
    embedded_pip = hoembed.embed(read(case, "surface.vtp"), read(case, "mesh.vtu"))
    for k in range(info["frames"]):
        deformed = read(case, f"deformed_{k}.vtu")
        for mode in info["modes"]:
            ref = read(case, f"transferred_{mode}_{k}.vtp")
            normals = mode == "recompute"
            for emb in (embedded_ref, embedded_pip):
                got = hoembed.transfer(emb, deformed, normals=mode, compute_point_normals=normals)
                assert bitwise(got.points, ref.points), (mode, k)
                assert sorted(got.point_data.keys()) == sorted(ref.point_data.keys())
                if normals:
                    assert bitwise(got.point_data["Normals"], ref.point_data["Normals"])
            # not trivially equal: the surface moved
            assert not np.allclose(ref.points, embedded_ref.points)


def cpu_has_avx2():
    try:
        with open("/proc/cpuinfo") as f:
            return any(
                line.startswith("flags") and "avx2" in line.split()
                for line in f.read().splitlines()
            )
    except OSError:
        return False


@pytest.mark.skipif(not cpu_has_avx2(), reason="this CPU has no AVX2 (the plain kernel runs)")
def test_the_wheel_runs_the_avx2_transfer_kernel():
    # the wheel compiles the transfer kernel's AVX2 copy as the VTK build does (one source
    # list, Filters/Transfer/sources.cmake), and chooses it here; it gives the plain bits
    from hoembed import _hoembed

    case = sorted(CASES)[0]
    mesh = read(case, "mesh.vtu")
    emb = hoembed.embed(read(case, "surface.vtp"), mesh)
    deformed = read(case, "deformed_1.vtu")
    # the shading normals carried by the deformation go through the kernel too
    deformed.point_data["Displacement"] = deformed.points - mesh.points
    got = {}
    try:
        assert _hoembed.transfer_kernel_simd(-1)
        for simd in (1, 0):
            assert _hoembed.transfer_kernel_simd(simd) == bool(simd)
            out = hoembed.transfer(emb, deformed, compute_point_normals="transform")
            got[simd] = (np.array(out.points), np.array(out.point_data["Normals"]))
    finally:
        _hoembed.transfer_kernel_simd(-1)
    for a, b in zip(got[1], got[0]):
        assert bitwise(a, b)
    assert not np.allclose(got[1][0], emb.points)


def test_rigid_motion_is_rigid():
    # independent of the reference: frame 0 is a rigid motion (generate_reference.py)
    case = sorted(CASES)[0]
    surface, mesh = read(case, "surface.vtp"), read(case, "mesh.vtu")
    deformed = read(case, "deformed_0.vtu")
    got = hoembed.transfer(hoembed.embed(surface, mesh), deformed)
    X, x = np.asarray(surface.points, float), np.asarray(got.points, float)
    Y, y = np.asarray(mesh.points, float), np.asarray(deformed.points, float)
    # the mesh's rigid map, fitted on its nodes, applied to the surface
    A = np.c_[Y, np.ones(len(Y))]
    M = np.linalg.lstsq(A, y, rcond=None)[0]
    pred = np.c_[X, np.ones(len(X))] @ M
    diag = np.linalg.norm(np.ptp(X, axis=0))
    tol = 1e-5 if got.points.dtype == np.float32 else 1e-10
    assert np.abs(pred - x).max() < tol * diag


def test_thread_count_does_not_matter():
    case = sorted(CASES)[0]
    code = (
        "import hoembed, pyvista, numpy as np, sys, os\n"
        f"r = {os.path.join(REF, case)!r}\n"
        "e = hoembed.embed(pyvista.read(r + '/surface.vtp'), pyvista.read(r + '/mesh.vtu'))\n"
        "np.save(sys.argv[1], np.c_[e.point_data['EmbeddingParametricCoords'],"
        " e.point_data['EmbeddingDistance']])\n"
        "print(hoembed.number_of_threads())\n"
    )
    ref = read(case, "embedded_normal-offset.vtp")
    want = np.c_[ref.point_data["EmbeddingParametricCoords"], ref.point_data["EmbeddingDistance"]]
    for threads in ("1", "3"):
        out = os.path.join(REF, f"threads_{threads}.npy")
        env = dict(os.environ, HOEMBED_NUM_THREADS=threads)
        r = subprocess.run(
            [sys.executable, "-c", code, out], env=env, capture_output=True, text=True, check=True
        )
        assert r.stdout.strip() == threads
        assert bitwise(np.load(out), want)


def test_errors():
    case = sorted(CASES)[0]
    surface, mesh = read(case, "surface.vtp"), read(case, "mesh.vtu")
    with pytest.raises(hoembed.HOEmbedError, match="surface is empty"):
        hoembed.embed(pyvista.PolyData(), mesh)
    bad = surface.copy()
    bad.points[5] = np.nan
    with pytest.raises(hoembed.HOEmbedError, match="non-finite .* at point 5"):
        hoembed.embed(bad, mesh)
    inverted = mesh.copy()
    cells = inverted.cell_connectivity.reshape(mesh.n_cells, -1).copy()
    cells[0, [0, 1]] = cells[0, [1, 0]]
    inverted = pyvista.UnstructuredGrid({mesh.celltypes[0]: cells}, mesh.points)
    with pytest.raises(hoembed.HOEmbedError, match="inverted or degenerate element: cell 0"):
        hoembed.embed(surface, inverted)
    with pytest.raises(ValueError, match="method"):
        hoembed.embed(surface, mesh, method="nearest")
    emb = hoembed.embed(surface, mesh)
    other = read(sorted(CASES)[-1], "mesh.vtu")
    with pytest.raises(hoembed.HOEmbedError, match="not the mesh the surface was embedded in"):
        hoembed.transfer(emb, other)
    with pytest.raises(hoembed.HOEmbedError, match="no field data EmbeddingMethod"):
        hoembed.transfer(surface, mesh)
    nan_mesh = mesh.copy()
    nan_mesh.points[3] = np.inf
    with pytest.raises(hoembed.HOEmbedError, match="transfer:"):
        hoembed.transfer(emb, nan_mesh)


def test_the_wheel_has_every_function():
    # the six pyvista-level functions of the VTK build's package, none stubbed (the
    # mesher: test_pip_mesher.py, write_series: test_pip_series.py)
    for name in ("tet10_mesh", "embed", "transfer", "simulate", "write_series", "thorny_tail"):
        assert callable(getattr(hoembed, name)) and name in hoembed.__all__


STEPPER_RUNS = sorted((case, run) for case in CASES for run in CASES[case].get("stepper", {}))


@pytest.mark.parametrize("case,run", STEPPER_RUNS)
def test_stepper_frames_bitwise(case, run):
    info = CASES[case]["stepper"][run]
    mesh = read(case, "stepper_mesh.vtu")
    seen = []
    frames = hoembed.simulate(
        mesh, progress=lambda i, n: seen.append((i, n)), **resolve(info["kwargs"], mesh)
    )
    assert len(frames) == info["frames"]
    assert seen == [(i + 1, len(frames)) for i in range(len(frames))]
    refs = [read(case, f"stepper_{run}_{i}.vtu") for i in range(len(frames))]
    diag = np.linalg.norm(np.ptp(np.asarray(mesh.points, float), axis=0))
    attrs = ("point_data", "cell_data", "field_data")
    scale = {
        (attr, name): max(
            float(np.abs(np.asarray(getattr(r, attr)[name], float)).max()) for r in refs
        )
        for attr in attrs
        for name in getattr(refs[0], attr).keys()
    }
    tol = CG_PATH if run == "prescribed" else ROUND_OFF
    for i, (got, ref) in enumerate(zip(frames, refs)):
        assert same_frame_values(got.points, ref.points, diag, tol), i
        for attr in attrs:
            data, want = getattr(got, attr), getattr(ref, attr)
            assert sorted(data.keys()) == sorted(want.keys()), attr
            for name in want.keys():
                assert same_frame_values(data[name], want[name], scale[attr, name], tol), (i, name)
        assert bitwise(got.cells, ref.cells)
    # not trivially equal: the mesh moved (the first dynamic frame is the initial state),
    # and a meaningful run: it bent without blowing up
    last = frames[-1]
    assert 0 < np.abs(last.point_data["Displacement"]).max() < 0.5 * diag


def test_static_solve_is_balanced():
    # independent of the reference: the clamped nodes stay, the free end sags along
    # gravity, and the static frame has no velocity
    case = sorted(CASES)[0]
    info = CASES[case]["stepper"]["static"]
    mesh = read(case, "stepper_mesh.vtu")
    (frame,) = hoembed.simulate(mesh, **resolve(info["kwargs"], mesh))
    origin, axis = (np.asarray(v) for v in info["kwargs"]["fixed"]["plane"])
    clamped = (np.asarray(mesh.points, float) - origin) @ axis <= 0
    d = frame.point_data["Displacement"]
    assert np.all(d[clamped] == 0.0)
    assert d[~clamped][:, 2].mean() < 0
    assert np.all(frame.point_data["Velocity"] == 0.0)
    assert float(frame.field_data["TimeValue"][0]) == 0.0


def test_prescribed_nodes_reach_their_targets():
    # independent of the reference: without a speed limit the grabbed nodes sit at rest +
    # the 3-vector from the first step on; at the speed limit they move that far per step
    # and no farther; the static solve holds them on their targets
    case = sorted(CASES)[0]
    runs = CASES[case]["stepper"]
    mesh = read(case, "stepper_mesh.vtu")
    grab = np.asarray(mesh.point_data["Grab"]) != 0
    pull = np.asarray(mesh.point_data["Pull"], float)
    assert grab.any() and not grab.all()
    kwargs = resolve(runs["prescribed"]["kwargs"], mesh)
    target = np.asarray(kwargs["prescribed"][1], float)
    frames = hoembed.simulate(mesh, **kwargs)
    assert np.all(frames[0].point_data["Displacement"] == 0.0)
    for f in frames[1:]:
        assert np.allclose(f.point_data["Displacement"][grab], target, rtol=0, atol=1e-12)
    kwargs = resolve(runs["prescribed_speed"]["kwargs"], mesh)
    step = kwargs["prescribed_speed_limit"] * kwargs["dt"]
    frames = hoembed.simulate(mesh, **kwargs)
    moved = [np.linalg.norm(f.point_data["Displacement"][grab], axis=1).max() for f in frames]
    assert np.all(np.diff(moved) <= step * (1 + 1e-9)) and moved[-1] > 0.5 * step
    assert moved[-1] < np.linalg.norm(pull[grab], axis=1).max()  # the limit held them back
    (static,) = hoembed.simulate(mesh, **resolve(runs["prescribed_static"]["kwargs"], mesh))
    assert np.allclose(static.point_data["Displacement"][grab], pull[grab], rtol=0, atol=1e-12)


def test_simulate_signature_and_docstring_are_the_vtk_builds():
    with open(os.path.join(REF, "simulate_api.json")) as f:
        api = json.load(f)
    import inspect

    assert str(inspect.signature(hoembed.simulate)) == api["signature"]
    assert hoembed.simulate.__doc__ == api["doc"]
    assert "prescribed_speed_limit=0.0" in api["signature"]


def test_stepper_errors():
    case = sorted(CASES)[0]
    mesh = read(case, "stepper_mesh.vtu")
    with pytest.raises(ValueError, match="poisson"):
        hoembed.simulate(mesh, poisson=0.5)
    with pytest.raises(hoembed.HOEmbedError, match="external_force must have shape"):
        hoembed.simulate(mesh, external_force=np.zeros((3, 3)))
    with pytest.raises(hoembed.HOEmbedError, match="FixedArrayName 'Nope' is not a point-data"):
        hoembed.simulate(mesh, fixed="Nope")
    # prescribed motion's arguments (the checks shared with the VTK build, _checks.py)
    grab = np.asarray(mesh.point_data["Grab"])
    with pytest.raises(ValueError, match="prescribed mask must have %d entries" % mesh.n_points):
        hoembed.simulate(mesh, prescribed=(grab[:-1], (0, 0, 1)))
    with pytest.raises(hoembed.HOEmbedError, match="prescribed must be \\(mask, displacement\\)"):
        hoembed.simulate(mesh, prescribed=grab)
    with pytest.raises(ValueError, match="prescribed displacement"):
        hoembed.simulate(mesh, prescribed=(grab, (0, np.nan, 1)))
    with pytest.raises(
        ValueError, match="prescribed_speed_limit: PrescribedSpeedLimit must be >= 0"
    ):
        hoembed.simulate(mesh, prescribed=(grab, (0, 0, 1)), prescribed_speed_limit=-1)
    cells = mesh.cell_connectivity.reshape(mesh.n_cells, -1).copy()
    cells[0, [0, 1]] = cells[0, [1, 0]]
    inverted = pyvista.UnstructuredGrid({mesh.celltypes[0]: cells}, mesh.points)
    with pytest.raises(hoembed.HOEmbedError, match="simulate: Rest cell 0 is inverted"):
        hoembed.simulate(inverted, steps=1)
    # the driver's own errors (its sentence, after the binding's name)
    with pytest.raises(
        hoembed.HOEmbedError, match="simulate: StaticSolve failed: the static solve needs clamped"
    ):
        hoembed.simulate(mesh, static=True)
