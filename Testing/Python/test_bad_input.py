"""Bad input for every pyvista-level function, the series writer and the CLI.

Each case runs in its own Python process: a crash (a signal) or a hang fails that case
instead of taking the test run down. A case passes when the bad input gets a clear error
(HOEmbedError naming the function/filter and the problem, or the CLI's exit code 2 with a
message naming the file or option) and leaves nothing half-written.
"""

import json
import os
import pathlib
import signal
import subprocess
import sys

import numpy as np
import pytest

HERE = pathlib.Path(__file__).resolve().parent


def _isolated(case, *args, env=None, timeout=600):
    """Run ``case(*args)`` (a function of this module) in a fresh interpreter."""
    code = (
        "import sys; sys.path.insert(0, sys.argv[1]); import test_bad_input as t; "
        "getattr(t, sys.argv[2])(*sys.argv[3:])"
    )
    r = subprocess.run(
        [sys.executable, "-c", code, str(HERE), case, *map(str, args)],
        capture_output=True,
        encoding="utf-8",
        errors="replace",
        timeout=timeout,
        env=env,
    )
    if r.returncode < 0:
        pytest.fail(f"{case} died with {signal.Signals(-r.returncode).name}:\n{r.stderr[-4000:]}")
    assert r.returncode == 0, f"{case} failed:\n{r.stderr[-4000:]}"
    return r


def _expect(needles, func, *args, **kwargs):
    """``func`` must raise HOEmbedError whose message holds every needle."""
    import hoembed

    try:
        func(*args, **kwargs)
    except hoembed.HOEmbedError as err:
        for n in [needles] if isinstance(needles, str) else needles:
            assert n in str(err), f"{n!r} not in {str(err)!r}"
        return str(err)
    raise AssertionError(f"no HOEmbedError from {getattr(func, '__name__', func)}")


def _sphere(res=20):
    import pyvista as pv

    return pv.Sphere(theta_resolution=res, phi_resolution=res)


def _mesh():
    import hoembed

    return hoembed.tet10_mesh(_sphere(), n_elements=60)


# ---- mesher ------------------------------------------------------------------------------


def case_mesher_point_ids(kind):
    import hoembed
    import pyvista as pv

    s = _sphere()
    faces = s.faces.reshape(-1, 4).copy()
    if kind == "too_large":
        faces[5, 2] = s.n_points
        _expect(
            ["tet10_mesh", "names point id", str(s.n_points)],
            hoembed.tet10_mesh,
            pv.PolyData(s.points, faces.ravel()),
        )
    elif kind == "negative":
        faces[5, 2] = -3
        _expect(["names point id -3"], hoembed.tet10_mesh, pv.PolyData(s.points, faces.ravel()))
    else:  # a triangle strip with an id out of range
        strip = pv.PolyData(s.points, strips=np.array([4, 0, 1, 2, s.n_points + 7]))
        _expect(["triangle strip 0", "names point id"], hoembed.tet10_mesh, strip)


def case_mesher_arguments():
    import hoembed
    import pyvista as pv
    from hoembed._errors import HOEmbedArgumentError

    s = _sphere()
    for kwargs, needle in [
        (dict(n_elements=0), "n_elements"),
        (dict(n_elements=-5), "n_elements"),
        (dict(n_elements=2.5), "n_elements"),
        (dict(n_elements=True), "n_elements"),
        (dict(order=0), "order"),
        (dict(order=3), "order"),
        (dict(radius_edge_ratio=float("nan")), "radius_edge_ratio"),
        (dict(radius_edge_ratio=1.0), "radius_edge_ratio"),
        (dict(min_dihedral_angle=float("nan")), "min_dihedral_angle"),
        (dict(min_dihedral_angle=45.0), "min_dihedral_angle"),
        (dict(edge_length=float("nan")), "edge_length"),
        (dict(edge_length=-1.0), "edge_length"),
        (dict(progress=3), "progress"),
    ]:
        msg = _expect(["tet10_mesh", needle], hoembed.tet10_mesh, s, **kwargs)
        try:
            hoembed.tet10_mesh(s, **kwargs)
        except HOEmbedArgumentError as err:
            assert isinstance(err, ValueError)
        else:
            raise AssertionError(msg)
    _expect(
        ["surface", "vtkPolyData", "UnstructuredGrid"],
        hoembed.tet10_mesh,
        pv.ImageData(dimensions=(2, 2, 2)).cast_to_unstructured_grid(),
    )


def case_mesher_vtk_nan_properties():
    import hoembed
    from hoembed._errors import run_filter

    for setter, name in (
        ("SetRadiusEdgeRatio", "RadiusEdgeRatio"),
        ("SetMinDihedralAngle", "MinDihedralAngle"),
        ("SetTargetEdgeLength", "TargetEdgeLength"),
        ("SetCurvedQualityRatio", "CurvedQualityRatio"),
    ):
        alg = hoembed.vtkTet10Mesher()
        alg.SetInputData(_sphere())
        getattr(alg, setter)(float("nan"))
        _expect([name, "nan"], run_filter, alg)


def case_mesher_size_limit():
    import hoembed
    from hoembed._errors import run_filter

    s = _sphere()
    # 1e7 elements (the setter's maximum): refused before any work, with the estimate.
    alg = hoembed.vtkTet10Mesher()
    alg.SetInputData(s)
    alg.SetTargetNumberOfElements(10_000_000)
    _expect(["about 10000000 elements", "GB", "MaximumNumberOfElements = 1000000"], run_filter, alg)
    # An edge length of 1e-4 of the size: about 1e11 elements.
    diag = s.length
    _expect(["MaximumNumberOfElements"], hoembed.tet10_mesh, s, edge_length=1e-4 * diag)
    # The limit is a property: below a small mesh it refuses, raised it meshes.
    alg = hoembed.vtkTet10Mesher()
    alg.SetInputData(s)
    alg.SetTargetNumberOfElements(200)
    alg.SetMaximumNumberOfElements(100)
    _expect(["about 200 elements", "MaximumNumberOfElements = 100"], run_filter, alg)
    alg.SetMaximumNumberOfElements(1000)
    assert run_filter(alg).GetNumberOfCells() > 0


def case_mesher_abort():
    """AbortExecute set from a progress observer stops the mesher inside TetGen."""
    import hoembed
    import pyvista as pv
    from hoembed._errors import run_filter

    alg = hoembed.vtkTet10Mesher()
    alg.SetInputData(pv.Sphere(theta_resolution=120, phi_resolution=120))
    alg.SetTargetNumberOfElements(200_000)
    seen = []

    def observe(obj, event):
        seen.append(obj.GetProgress())
        if obj.GetProgress() > 0.1:
            obj.SetAbortExecute(1)

    alg.AddObserver("ProgressEvent", observe)
    _expect(["aborted"], run_filter, alg)
    assert alg.GetOutput().GetNumberOfCells() == 0


# ---- embedding and transfer --------------------------------------------------------------


def case_embed_arguments():
    import hoembed

    s, m = _sphere(), _mesh()
    _expect(["embed", "method"], hoembed.embed, s, m, method="nearest")
    _expect(["embed", "n_partitions"], hoembed.embed, s, m, n_partitions=-1)
    _expect(["embed", "n_partitions"], hoembed.embed, s, m, n_partitions=float("nan"))
    _expect(["embed", "fe_mesh", "vtkUnstructuredGrid"], hoembed.embed, s, s)
    _expect(["embed", "surface", "vtkPolyData"], hoembed.embed, m, m)
    _expect(["embed", "progress"], hoembed.embed, s, m, progress="yes")


def case_transfer_arguments():
    import hoembed

    s, m = _sphere(), _mesh()
    e = hoembed.embed(s, m)
    _expect(["transfer", "normals"], hoembed.transfer, e, m, normals="bend")
    _expect(["transfer", "deformed_mesh"], hoembed.transfer, e, e)
    _expect(["transfer", "embedded_surface"], hoembed.transfer, m, m)


# ---- stepper ----------------------------------------------------------------------------


def case_simulate_arguments():
    import hoembed
    from hoembed._errors import HOEmbedArgumentError

    m = _mesh()
    fixed = {"plane": ((0, 0, 0), (0, 0, 1))}
    n = m.n_points
    nan = float("nan")
    cases = [
        (dict(dt=nan), "TimeStep"),
        (dict(dt=0.0), "TimeStep"),
        (dict(young=-5.0), "YoungModulus"),
        (dict(young=nan), "YoungModulus"),
        (dict(poisson=0.5), "PoissonRatio"),
        (dict(poisson=nan), "PoissonRatio"),
        (dict(density=float("inf")), "Density"),
        (dict(gravity=(0, nan, 0)), "Gravity"),
        (dict(gravity=(0, 1)), "Gravity"),
        (dict(steps=-1), "NumberOfTimeSteps"),
        (dict(every=0), "every"),
        (dict(rayleigh_mass=-1.0), "RayleighMass"),
        (dict(solver_tolerance=0.0), "SolverTolerance"),
        (dict(fixed=np.ones(n + 1)), "fixed mask"),
        (dict(fixed={"box": (1, 0, 0, 1, 0, 1)}), "fixed['box']"),
        (dict(fixed={"plane": ((0, 0, 0), (0, 0, 0))}), "normal is zero"),
        (dict(fixed={"sphere": 1}), "fixed dict"),
        (dict(external_force=np.full((n, 3), nan)), "external_force"),
        (dict(initial_velocity=np.zeros((n, 2))), "initial_velocity"),
    ]
    for kwargs, needle in cases:
        kw = dict(steps=1, fixed=fixed)
        kw.update(kwargs)
        _expect(["simulate", needle], hoembed.simulate, m, **kw)
        try:
            hoembed.simulate(m, **kw)
        except HOEmbedArgumentError:
            pass
    _expect(["simulate", "fe_mesh"], hoembed.simulate, _sphere(), steps=1)


# ---- series -----------------------------------------------------------------------------


def _frames(k):
    import pyvista as pv

    out = []
    for i in range(k):
        f = pv.Sphere(radius=1.0 + i)
        f.field_data["TimeValue"] = np.array([float(i)])
        out.append(f)
    return out


def _snapshot(folder):
    folder = pathlib.Path(folder)
    return {
        str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()
    }


def case_series_failure_keeps_old(folder):
    import hoembed
    import pyvista as pv

    hoembed.write_series(_frames(3), folder, "s")
    before = _snapshot(folder)
    bad = _frames(2) + [pv.ImageData(dimensions=(2, 2, 2))]  # fails at frame 2
    _expect(["unsupported data type"], hoembed.write_series, bad, folder, "s")
    assert _snapshot(folder) == before, "a failed write changed the old series"
    bad = [_frames(1)[0], pv.ImageData(dimensions=(2, 2, 2))]  # fails at frame 1
    _expect(["unsupported data type"], hoembed.write_series, bad, folder, "s")
    assert _snapshot(folder) == before, "a failed write changed the old series"
    r = pv.get_reader(os.path.join(folder, "s.pvd"))
    assert len(r.time_values) == 3


def case_series_shorter_rerun(folder):
    import hoembed
    import pyvista as pv

    hoembed.write_series(_frames(4), folder, "s")
    hoembed.write_series(_frames(2), folder, "s")
    assert sorted(os.listdir(os.path.join(folder, "s"))) == ["s_000000.vtp", "s_000001.vtp"]
    assert sorted(os.listdir(folder)) == ["s", "s.pvd"]
    assert len(pv.get_reader(os.path.join(folder, "s.pvd")).time_values) == 2


def case_series_writer_destroyed(folder):
    import gc

    import hoembed

    w = hoembed.vtkTimeSeriesWriter()
    w.SetFileName(os.path.join(folder, "s.pvd"))
    assert w.BeginSeries() == 1
    assert w.AddFrame(_frames(1)[0], 0.0) == 1
    del w
    gc.collect()
    assert os.listdir(folder) == [], os.listdir(folder)


def case_series_bad_paths(folder):
    import hoembed

    folder = pathlib.Path(folder)
    (folder / "d.pvd").mkdir()
    _expect(["d.pvd", "is a folder"], hoembed.write_series, _frames(1), folder, "d")
    assert sorted(os.listdir(folder)) == ["d.pvd"]  # no d.pvd.part, no staging folder
    (folder / "afile").write_text("x")
    _expect(
        ["write_series", "cannot create the output folder"],
        hoembed.write_series,
        _frames(1),
        folder / "afile" / "sub",
        "s",
    )
    (folder / "mine").mkdir()
    (folder / "mine" / "notes.txt").write_text("keep me")
    _expect(["notes.txt", "not a step file"], hoembed.write_series, _frames(1), folder, "mine")
    assert (folder / "mine" / "notes.txt").read_text() == "keep me"
    _expect(["series name"], hoembed.write_series, _frames(1), folder, "../up")


def case_series_nan_time(folder):
    import hoembed

    _expect(
        ["time is nan"], hoembed.write_series, _frames(2), folder, "s", times=[0.0, float("nan")]
    )
    assert os.listdir(folder) == []


# ---- pytest entry points: one subprocess per case ----------------------------------------


@pytest.mark.parametrize("kind", ["too_large", "negative", "strip"])
def test_mesher_point_ids(kind):
    _isolated("case_mesher_point_ids", kind)


@pytest.mark.parametrize(
    "case",
    [
        "case_mesher_arguments",
        "case_mesher_vtk_nan_properties",
        "case_mesher_size_limit",
        "case_mesher_abort",
        "case_embed_arguments",
        "case_transfer_arguments",
        "case_simulate_arguments",
    ],
)
def test_filter_arguments(case):
    _isolated(case)


@pytest.mark.parametrize(
    "case",
    [
        "case_series_failure_keeps_old",
        "case_series_shorter_rerun",
        "case_series_writer_destroyed",
        "case_series_bad_paths",
        "case_series_nan_time",
    ],
)
def test_series(case, tmp_path):
    _isolated(case, tmp_path)


# ---- CLI --------------------------------------------------------------------------------


def run_cli(*args, env=None):
    r = subprocess.run(
        [sys.executable, "-m", "hoembed", *map(str, args)],
        capture_output=True,
        encoding="utf-8",
        errors="replace",
        timeout=600,
        env=env,
    )
    if r.returncode < 0:
        pytest.fail(
            f"hoembed {' '.join(map(str, args))} died with "
            f"{signal.Signals(-r.returncode).name}:\n{r.stderr[-4000:]}"
        )
    return r


@pytest.fixture(scope="module")
def good_files(tmp_path_factory):
    import pyvista as pv

    d = tmp_path_factory.mktemp("files")
    s = pv.Sphere()
    s.save(d / "ok.ply")
    s.save(d / "ok_ascii.ply", binary=False)
    s.save(d / "ok.vtk")
    s.save(d / "ok.stl")
    s.save(d / "ok.vtp")
    return d


def _damaged(good_files, tmp_path, kind):
    src = {
        "trunc_ply": "ok.ply",
        "trunc_vtk": "ok.vtk",
        "trunc_stl": "ok.stl",
        "ascii_ply_ids": "ok_ascii.ply",
        "ascii_ply_short": "ok_ascii.ply",
        "ascii_ply_text": "ok_ascii.ply",
        "ply_header": "ok.ply",
        "empty": "ok.vtp",
        "vtk_header": "ok.vtk",
    }[kind]
    data = (good_files / src).read_bytes()
    out = tmp_path / (kind + pathlib.Path(src).suffix)
    if kind.startswith("trunc"):
        data = data[: len(data) // 2]
    elif kind == "ascii_ply_ids":
        lines = data.decode().splitlines()
        i = next(k for k, ln in enumerate(lines) if ln.startswith("3 "))
        lines[i] = "3 0 99999999 2"
        data = ("\n".join(lines) + "\n").encode()
    elif kind == "ascii_ply_short":
        data = data[: int(len(data) * 0.7)]
    elif kind == "ascii_ply_text":
        lines = data.decode().splitlines()
        i = next(k for k, ln in enumerate(lines) if ln.startswith("end_header"))
        lines[i + 3] = "not numbers at all"
        data = ("\n".join(lines) + "\n").encode()
    elif kind == "ply_header":
        data = data.replace(b"format binary_little_endian", b"format binary_middle_endian")
    elif kind == "empty":
        data = b""
    elif kind == "vtk_header":
        data = b"garbage\n" + data
    out.write_bytes(data)
    return out


@pytest.mark.parametrize(
    "kind, needle",
    [
        ("trunc_ply", "truncated"),
        ("trunc_vtk", "corrupt or truncated"),
        ("trunc_stl", "truncated"),
        ("ascii_ply_ids", "names a vertex outside"),
        ("ascii_ply_short", "truncated"),
        ("ascii_ply_text", "not numbers"),
        ("ply_header", "unknown PLY format"),
        ("empty", "is empty"),
        ("vtk_header", "not a legacy VTK file"),
    ],
)
def test_cli_bad_files(good_files, tmp_path, kind, needle):
    bad = _damaged(good_files, tmp_path, kind)
    out = tmp_path / "out"
    r = run_cli("run", bad, "--steps", "1", "--output", out)
    assert r.returncode == 2, r.stderr
    assert needle in r.stderr and bad.name in r.stderr, r.stderr
    assert not out.exists()


def test_cli_other_bad_inputs(good_files, tmp_path):
    out = tmp_path / "out"
    unknown = tmp_path / "s.xyz"
    unknown.write_text("1 2 3\n")
    for args, needle in [
        ((unknown,), "unsupported file type '.xyz'"),
        ((tmp_path,), "is not a file"),
        ((good_files / "ok.vtp", "--dt", "nan"), "--dt"),
        ((good_files / "ok.vtp", "--poisson", "0.5"), "--poisson"),
        ((good_files / "ok.vtp", "--young", "-5"), "--young"),
        ((good_files / "ok.vtp", "--gravity", "0", "inf", "0"), "--gravity"),
        ((good_files / "ok.vtp", "--clamp-sphere", "0", "0", "0", "-1"), "--clamp-sphere"),
        ((good_files / "ok.vtp", "--clamp-fraction", "0"), "--clamp-fraction"),
    ]:
        r = run_cli("run", *args, "--steps", "1", "--output", out)
        assert r.returncode == 2 and needle in r.stderr, (args, r.stderr)
        assert "Traceback" not in r.stderr
        assert not out.exists(), args
    afile = tmp_path / "afile"
    afile.write_text("x")
    r = run_cli("run", good_files / "ok.vtp", "--output", afile / "sub")
    assert r.returncode == 2 and "not a folder" in r.stderr, r.stderr


def test_cli_clamp_region_without_tet4_nodes(good_files, tmp_path):
    """A clamp sphere around one tet10 mid-edge node holds no tet4 node: refused before
    anything is written (it used to exit 2 after writing the tet10 series)."""
    import hoembed
    import pyvista as pv

    surface = pv.read(good_files / "ok.vtp")
    mesh = hoembed.tet10_mesh(surface, n_elements=100)
    mesh4 = hoembed.tet10_mesh(surface, n_elements=400, order=1)
    mid = mesh.cells.reshape(-1, 11)[0, 5]  # a mid-edge node of cell 0
    x = mesh.points[mid]
    assert np.linalg.norm(mesh4.points - x, axis=1).min() > 1e-6
    out = tmp_path / "out"
    r = run_cli(
        "run",
        good_files / "ok.vtp",
        "--elements",
        "100",
        "--steps",
        "1",
        "--clamp-sphere",
        *x,
        "1e-9",
        "--output",
        out,
    )
    assert r.returncode == 2 and "clamped region holds no FE node" in r.stderr, r.stderr
    assert not out.exists()


def test_cli_without_display(good_files, tmp_path):
    """No display: the picture is skipped with a one-line notice, the run completes."""
    env = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
    out = tmp_path / "out"
    r = run_cli(
        "run", good_files / "ok.vtp", "--elements", "60", "--steps", "1", "--output", out, env=env
    )
    assert r.returncode == 0, r.stderr
    assert "picture skipped" in r.stderr and "--no-picture" in r.stderr
    summary = json.loads((out / "summary.json").read_text())
    assert "picture" not in summary["files"] and summary["picture_skipped"]
    assert not (out / "comparison.png").exists()
