"""hoembed.write_series / vtkTimeSeriesWriter: .vtu/.vtp per step plus a .pvd."""

import os
import xml.etree.ElementTree as ET

import hoembed
import numpy as np
import pytest
import pyvista as pv
from conftest import box_tet_mesh


def test_frames_roundtrip_with_pyvista(tmp_path):
    mesh = box_tet_mesh((4, 1, 1), (4.0, 1.0, 1.0), 2)
    frames = hoembed.simulate(
        mesh, steps=6, dt=0.05, young=1e6, fixed={"plane": ((0, 0, 0), (1, 0, 0))}, every=2
    )
    path = hoembed.write_series(frames, tmp_path, "beam")
    assert path == os.path.join(str(tmp_path), "beam.pvd")
    files = sorted(os.listdir(tmp_path / "beam"))
    assert files == [f"beam_{i:06d}.vtu" for i in range(4)]
    root = ET.parse(path).getroot()
    assert root.get("type") == "Collection"
    times = [float(d.get("timestep")) for d in root.iter("DataSet")]
    assert times == pytest.approx([0.0, 0.1, 0.2, 0.3])
    reader = pv.get_reader(path)
    assert reader.time_values == pytest.approx([0.0, 0.1, 0.2, 0.3])
    reader.set_active_time_value(reader.time_values[-1])
    block = reader.read()
    grid = block[0]
    np.testing.assert_allclose(grid.points, frames[-1].points)
    np.testing.assert_allclose(
        grid.point_data["Displacement"], frames[-1].point_data["Displacement"]
    )
    assert grid.celltypes[0] == pv.CellType.QUADRATIC_TETRA
    assert pv.read(path).n_blocks == 1  # pyvista.read opens the collection
    assert not [f for f in os.listdir(tmp_path) if f.endswith(".part")]


def test_algorithm_series_synchronised(tmp_path):
    mesh = box_tet_mesh((3, 1, 1), (3.0, 1.0, 1.0), 2)
    st = hoembed.vtkCorotationalFEMStepper()
    st.SetInputData(mesh)
    st.SetUseClampPlane(True)
    st.SetYoungModulus(1e6)
    st.SetTimeStep(0.02)
    st.SetNumberOfTimeSteps(5)
    path = hoembed.write_series(st, tmp_path, "fe")
    reader = pv.get_reader(path)
    assert reader.time_values == pytest.approx([0.0, 0.02, 0.04, 0.06, 0.08, 0.1])
    ref = hoembed.simulate(
        mesh, steps=5, dt=0.02, young=1e6, fixed={"plane": ((0, 0, 0), (1, 0, 0))}
    )
    for k, t in enumerate(reader.time_values):
        reader.set_active_time_value(t)
        np.testing.assert_allclose(
            reader.read()[0].point_data["Displacement"],
            ref[k].point_data["Displacement"],
            atol=1e-12,
        )


def test_polydata_frames_and_explicit_times(tmp_path):
    frames = [pv.Sphere(radius=1.0 + 0.1 * k) for k in range(3)]
    path = hoembed.write_series(frames, tmp_path / "sub", "surf", times=[0.0, 0.5, 1.0])
    assert sorted(os.listdir(tmp_path / "sub" / "surf")) == [
        "surf_000000.vtp",
        "surf_000001.vtp",
        "surf_000002.vtp",
    ]
    reader = pv.get_reader(path)
    assert reader.time_values == pytest.approx([0.0, 0.5, 1.0])
    reader.set_active_time_value(reader.time_values[-1])
    assert reader.read()[0].n_points == frames[2].n_points
    np.testing.assert_allclose(reader.read()[0].points, frames[2].points, rtol=1e-6)


def test_unsupported_frame_leaves_no_series(tmp_path):
    frames = [pv.Sphere(), pv.ImageData(dimensions=(2, 2, 2))]
    with pytest.raises(hoembed.HOEmbedError, match="unsupported data type"):
        hoembed.write_series(frames, tmp_path, "bad")
    assert not (tmp_path / "bad.pvd").exists()
    assert not (tmp_path / "bad").exists()  # the frame written before is removed
    assert os.listdir(tmp_path) == []  # nor any staging folder


def test_failing_input_leaves_no_series(tmp_path):
    mesh = box_tet_mesh((2, 1, 1), (2.0, 1.0, 1.0), 2)
    st = hoembed.vtkCorotationalFEMStepper()
    st.SetInputData(mesh)
    st.SetPoissonRatio(0.6)
    with pytest.raises(hoembed.HOEmbedError):
        hoembed.write_series(st, tmp_path, "fail")
    assert not (tmp_path / "fail.pvd").exists()
