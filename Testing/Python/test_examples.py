"""The Python examples run and write what they say (the VTK-pipeline one and the pyvista one)."""

import pathlib
import subprocess
import sys

import pyvista as pv

EXAMPLES = pathlib.Path(__file__).resolve().parents[2] / "Examples" / "Python"


def test_vtk_pipeline_example(tmp_path):
    out = subprocess.run(
        [sys.executable, str(EXAMPLES / "vtk_pipeline.py"), str(tmp_path)],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert out.returncode == 0, out.stderr
    reader = pv.get_reader(str(tmp_path / "surface.pvd"))
    assert len(reader.time_values) == 9
    reader.set_active_time_value(reader.time_values[-1])
    last = reader.read()[0]
    first = pv.read(str(sorted((tmp_path / "surface").glob("*.vtp"))[0]))
    assert last.n_points == first.n_points and last.n_points > 1000
    assert abs(last.points - first.points).max() > 0  # it moved


def test_pyvista_pipeline_example(tmp_path):
    out = subprocess.run(
        [
            sys.executable,
            str(EXAMPLES / "pyvista_pipeline.py"),
            "--elements",
            "300",
            "--steps",
            "3",
            "--out",
            str(tmp_path),
        ],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert out.returncode == 0, out.stderr
    assert (tmp_path / "surface.pvd").is_file() and (tmp_path / "fe_mesh.pvd").is_file()
    assert "tet10 elements" in out.stdout
