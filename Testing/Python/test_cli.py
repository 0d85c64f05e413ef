"""The hoembed command line: a small end-to-end run and clear errors for bad input."""

import json
import subprocess
import sys

import pyvista as pv


def run_cli(*args, cwd=None):
    # The output is decoded as UTF-8 whatever the locale: VTK 9.1's legacy writers leave
    # the process in the C locale (pyvista's .vtk/.stl saves in another test of the same
    # session), and the progress bars are not ASCII.
    return subprocess.run(
        [sys.executable, "-m", "hoembed", *args],
        capture_output=True,
        encoding="utf-8",
        cwd=cwd,
        timeout=600,
    )


def test_help_explains_options():
    out = run_cli("run", "--help")
    assert out.returncode == 0
    for opt in (
        "--elements",
        "--young",
        "--poisson",
        "--clamp-axis",
        "--steps",
        "--output",
        "--normals",
    ):
        assert opt in out.stdout


def test_missing_file(tmp_path):
    out = run_cli("run", str(tmp_path / "nope.obj"), "--output", str(tmp_path / "o"))
    assert out.returncode == 2
    assert "no such file" in out.stderr


def test_unreadable_file(tmp_path):
    bad = tmp_path / "bad.obj"
    bad.write_text("this is not a mesh\n")
    out = run_cli("run", str(bad), "--output", str(tmp_path / "o"))
    assert out.returncode == 2
    assert "hoembed: error:" in out.stderr


def test_bad_option_values(tmp_path):
    s = tmp_path / "s.vtp"
    pv.Sphere().save(s)
    out = run_cli("run", str(s), "--steps", "0", "--output", str(tmp_path / "o"))
    assert out.returncode == 2 and "--steps must be positive" in out.stderr
    out = run_cli(
        "run",
        str(s),
        "--poisson",
        "0.5",
        "--steps",
        "2",
        "--no-tet4",
        "--output",
        str(tmp_path / "o"),
    )
    assert out.returncode == 2 and "--poisson" in out.stderr
    assert not (tmp_path / "o").exists()  # checked before anything is written


def test_surface_without_polygons_is_refused(tmp_path):
    # open surfaces are meshed now (through their envelope); lines enclose nothing
    s = tmp_path / "lines.vtp"
    pv.Line().save(s)
    out = run_cli("run", str(s), "--steps", "2", "--output", str(tmp_path / "o"))
    assert out.returncode == 2 and ("no polygons" in out.stderr or "no surface" in out.stderr)


def test_small_run_writes_series(tmp_path):
    s = tmp_path / "sphere.vtp"
    pv.Sphere(radius=1.0, theta_resolution=60, phi_resolution=60).save(s)
    outdir = tmp_path / "out"
    out = run_cli(
        "run",
        str(s),
        "--elements",
        "200",
        "--steps",
        "3",
        "--clamp-axis",
        "z",
        "--no-tet4",
        "--normals",
        "deform",
        "--output",
        str(outdir),
    )
    assert out.returncode == 0, out.stderr
    summary = json.loads((outdir / "summary.json").read_text())
    assert summary["frames"] == 4
    reader = pv.get_reader(str(outdir / "surface.pvd"))
    assert len(reader.time_values) == 4
    reader.set_active_time_value(reader.time_values[-1])
    last = reader.read()[0]
    assert last.n_points == pv.read(s).n_points
    fe = pv.get_reader(str(outdir / "fe_mesh.pvd"))
    assert len(fe.time_values) == 4


def test_run_material(tmp_path):
    # --material reaches the stepper (a hyperelastic law, same frames count); an unknown
    # name is refused with the driver's sentence
    s = tmp_path / "sphere.vtp"
    pv.Sphere(radius=1.0, theta_resolution=30, phi_resolution=30).save(s)
    outdir = tmp_path / "out"
    out = run_cli(
        "run",
        str(s),
        "--elements",
        "200",
        "--steps",
        "2",
        "--clamp-axis",
        "z",
        "--no-tet4",
        "--material",
        "neo-hookean",
        "--output",
        str(outdir),
    )
    assert out.returncode == 0, out.stderr
    assert json.loads((outdir / "summary.json").read_text())["frames"] == 3
    bad = run_cli(
        "run",
        str(s),
        "--elements",
        "200",
        "--steps",
        "2",
        "--clamp-axis",
        "z",
        "--no-tet4",
        "--material",
        "rubber",
        "--output",
        str(tmp_path / "bad"),
    )
    assert bad.returncode != 0
    assert (
        "Material 'rubber' is not one of corotated, stvk, neo-hookean, mooney-rivlin"
        in bad.stderr + bad.stdout
    )
