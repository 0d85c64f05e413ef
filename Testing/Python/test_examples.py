"""The Python examples run and write what they say (the VTK-pipeline one and the pyvista one)."""

import json
import pathlib
import subprocess
import sys

import pytest
import pyvista as pv

EXAMPLES = pathlib.Path(__file__).resolve().parents[2] / "Examples" / "Python"


def test_vtk_pipeline_example(tmp_path):
    out = subprocess.run(
        [sys.executable, str(EXAMPLES / "vtk_pipeline.py"), str(tmp_path)],
        capture_output=True,
        encoding="utf-8",
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
        encoding="utf-8",
        timeout=600,
    )
    assert out.returncode == 0, out.stderr
    assert (tmp_path / "surface.pvd").is_file() and (tmp_path / "fe_mesh.pvd").is_file()
    assert "tet10 elements" in out.stdout


def test_lagrange_fe_result_example(tmp_path):
    """gmsh's curved P2 mesh, scikit-fem's solution on it, written as VTK Lagrange
    tetrahedra: the embedding is exact, the transfer at rest is the identity, and inside the
    mesh VTK's own vtkLagrangeTetra at HOEmbed's coordinates gives the rest and the
    transferred points."""
    pytest.importorskip("gmsh", reason="the gmsh wheel is not installed (scripts/setup.sh)")
    pytest.importorskip("skfem", reason="scikit-fem is not installed (scripts/setup.sh)")
    out = subprocess.run(
        [sys.executable, str(EXAMPLES / "lagrange_fe_result.py"), "--out", str(tmp_path)],
        capture_output=True,
        encoding="utf-8",
        timeout=900,
    )
    assert out.returncode == 0, out.stderr
    summary = json.loads(out.stdout.strip().splitlines()[-1])
    assert summary["cells"] > 300 and summary["surface_vertices"] > 10000
    assert summary["residual"] <= 1e-10
    assert summary["rest_move"] <= 1e-10
    # part of the fine CAD surface lies inside the P2 boundary that approximates it
    assert summary["inside"] > summary["surface_vertices"] / 20
    assert summary["inside_rest_vs_vtk"] <= 1e-12
    assert summary["inside_deformed_vs_vtk"] <= 1e-12
    assert (tmp_path / "lagrange_fe_result.png").stat().st_size > 10000
