"""The pip wheel's write_series (hoembed::SeriesFiles + the pip VTK's XML writers) against
the VTK build's (vtkTimeSeriesWriter over the same class).

HOEMBED_PIP_REFERENCE/series holds what the VTK build wrote (series_reference.py): the
wheel writes the same frames (read from the same reference files) and its .pvd must be
the same text, every frame file the same name, and every frame's points, cells and
arrays bit for bit the same as read back with pyvista (the XML headers may differ
between VTK versions; the data may not). Then what the VTK build's own tests check:
pyvista.read opens it, a failure midway leaves an older series intact, a re-run replaces
it whole, and bad calls fail with the VTK build's sentences.
"""

import json
import os
import pathlib

import hoembed
import numpy as np
import pytest
import pyvista
import series_reference as sr
from vtkmodules.util.numpy_support import vtk_to_numpy

REF = os.environ.get("HOEMBED_PIP_REFERENCE", "")
SERIES = os.path.join(REF, "series")
if not REF or not os.path.exists(os.path.join(SERIES, "errors.json")):
    pytest.skip(
        "HOEMBED_PIP_REFERENCE (generate_reference.py output with series) not given",
        allow_module_level=True,
    )
CASES = json.load(open(os.path.join(REF, "cases.json")))


def bitwise(a, b):
    a, b = np.asarray(a), np.asarray(b)
    return (
        a.shape == b.shape
        and a.dtype == b.dtype
        and np.array_equal(a.view(np.uint8), b.view(np.uint8))
    )


def snapshot(folder):
    folder = pathlib.Path(folder)
    return {
        str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()
    }


def same_dataset(got, ref):
    assert type(got) is type(ref)
    assert bitwise(got.points, ref.points)
    cells = (
        (lambda d: d.GetCells())
        if isinstance(ref, pyvista.UnstructuredGrid)
        else (lambda d: d.GetPolys())
    )
    for part in ("GetOffsetsArray", "GetConnectivityArray"):
        assert bitwise(
            vtk_to_numpy(getattr(cells(got), part)()), vtk_to_numpy(getattr(cells(ref), part)())
        ), part
    if isinstance(ref, pyvista.UnstructuredGrid):
        assert bitwise(got.celltypes, ref.celltypes)
    for attr in ("point_data", "cell_data", "field_data"):
        g, r = getattr(got, attr), getattr(ref, attr)
        assert sorted(g.keys()) == sorted(r.keys()), attr
        for name in r.keys():
            assert bitwise(g[name], r[name]), f"{attr} {name}"


def writer_settings(path):
    head = open(path, "rb").read(4000).decode("latin-1")
    tag = head[head.index("<VTKFile") :].split(">", 1)[0]
    compressor = [w for w in tag.split() if w.startswith("compressor=")]
    return (
        compressor[0] if compressor else None,
        'format="appended"' in head,
        'format="ascii"' in head or 'format="binary"' in head,
    )


def same_series(got_folder, ref_folder, name):
    ref_pvd = os.path.join(ref_folder, f"{name}.pvd")
    got_pvd = os.path.join(got_folder, f"{name}.pvd")
    assert open(got_pvd).read() == open(ref_pvd).read()
    ref_files = sorted(os.listdir(os.path.join(ref_folder, name)))
    assert sorted(os.listdir(os.path.join(got_folder, name))) == ref_files
    assert sorted(os.listdir(got_folder)) == [name, f"{name}.pvd"]  # no staging, no .part
    for f in ref_files:
        # the writers' settings (vtkTimeSeriesWriter's: appended data, zlib)
        assert (
            writer_settings(os.path.join(got_folder, name, f))
            == writer_settings(os.path.join(ref_folder, name, f))
            == ('compressor="vtkZLibDataCompressor"', True, False)
        )
        same_dataset(
            pyvista.read(os.path.join(got_folder, name, f)),
            pyvista.read(os.path.join(ref_folder, name, f)),
        )
    # and as a collection: pyvista.read opens it, with the reference's times
    got, ref = pyvista.get_reader(got_pvd), pyvista.get_reader(ref_pvd)
    assert got.time_values == ref.time_values
    assert pyvista.read(got_pvd).n_blocks == 1
    return len(ref_files)


@pytest.mark.parametrize("case", sorted(CASES))
@pytest.mark.parametrize("series", [sr.STEPPER_SERIES, sr.SURFACE_SERIES], ids=lambda s: s[0])
def test_frames_series_equal_vtk_build(case, series, tmp_path):
    name, _, times = series
    frames = [pyvista.read(os.path.join(REF, case, f)) for f in sr.frame_files(CASES[case], series)]
    assert len(frames) >= 2
    path = hoembed.write_series(
        frames, tmp_path, name, times=times[: len(frames)] if times else None
    )
    assert path == os.path.join(str(tmp_path), f"{name}.pvd")
    assert same_series(tmp_path, os.path.join(SERIES, case), name) == len(frames)


def test_algorithm_series_equal_vtk_build(tmp_path):
    # a temporal pip-VTK algorithm, updated at each advertised time (UPDATE_TIME_STEP)
    alg = sr.timed_sphere_class()()
    hoembed.write_series(alg, tmp_path, "sphere")
    assert same_series(tmp_path, os.path.join(SERIES, "algorithm"), "sphere") == 3
    r = pyvista.get_reader(os.path.join(tmp_path, "sphere.pvd"))
    r.set_active_time_value(1.5)
    np.testing.assert_allclose(np.linalg.norm(r.read()[0].points, axis=1), 2.5, rtol=1e-6)


def test_algorithm_series_explicit_times(tmp_path):
    alg = sr.timed_sphere_class()()
    hoembed.write_series(alg, tmp_path, "sphere", times=[0.25, 2.0])
    r = pyvista.get_reader(os.path.join(tmp_path, "sphere.pvd"))
    assert r.time_values == [0.25, 2.0]
    r.set_active_time_value(2.0)
    np.testing.assert_allclose(np.linalg.norm(r.read()[0].points, axis=1), 3.0, rtol=1e-6)


def test_failing_algorithm_leaves_nothing(tmp_path):
    hoembed.write_series([pyvista.Sphere()], tmp_path, "s")
    before = snapshot(tmp_path)
    with pytest.raises(hoembed.HOEmbedError, match=r"The input failed at time 1.5 \(step 2\)"):
        hoembed.write_series(sr.failing_sphere(), tmp_path, "s")
    assert snapshot(tmp_path) == before


@pytest.mark.parametrize("fail_at", [1, 2])
def test_bad_frame_midway_keeps_old_series(tmp_path, fail_at):
    frames = [pyvista.Sphere(radius=1.0 + i) for i in range(3)]
    hoembed.write_series(frames, tmp_path, "s")
    before = snapshot(tmp_path)
    bad = frames[:fail_at] + [pyvista.ImageData(dimensions=(2, 2, 2))]
    with pytest.raises(
        hoembed.HOEmbedError, match=f"Frame {fail_at}: unsupported data type vtkImageData"
    ):
        hoembed.write_series(bad, tmp_path, "s")
    assert snapshot(tmp_path) == before
    assert len(pyvista.get_reader(os.path.join(tmp_path, "s.pvd")).time_values) == 3


def test_shorter_rerun_replaces_whole_series(tmp_path):
    hoembed.write_series([pyvista.Sphere(radius=1.0 + i) for i in range(4)], tmp_path, "s")
    hoembed.write_series([pyvista.Cube(), pyvista.Cube()], tmp_path, "s", times=[1.0, 2.0])
    assert sorted(os.listdir(tmp_path / "s")) == ["s_000000.vtp", "s_000001.vtp"]
    assert sorted(os.listdir(tmp_path)) == ["s", "s.pvd"]
    assert pyvista.get_reader(os.path.join(tmp_path, "s.pvd")).time_values == [1.0, 2.0]


def test_failure_in_the_users_vtk_leaves_nothing(tmp_path):
    # an exception raised while frames are being written (here: a frame pyvista cannot
    # wrap) abandons the staged series too
    hoembed.write_series([pyvista.Sphere()], tmp_path, "s")
    before = snapshot(tmp_path)
    with pytest.raises(Exception):
        hoembed.write_series([pyvista.Sphere(), object()], tmp_path, "s")
    assert snapshot(tmp_path) == before


ERRORS = json.load(open(os.path.join(SERIES, "errors.json")))


@pytest.mark.parametrize("key", sorted(ERRORS))
def test_errors_are_the_vtk_builds(key, tmp_path):
    with pytest.raises(hoembed.HOEmbedError) as info:
        sr.bad_calls(pyvista, hoembed.write_series, str(tmp_path))[key]()
    ref = ERRORS[key]
    got = str(info.value)
    # the VTK build's absolute paths were under its own folder: compare relative to it
    ref_folder = os.path.join(SERIES, "bad", key)
    assert sr.sentence(got).replace(str(tmp_path), "<folder>") == sr.sentence(ref).replace(
        ref_folder, "<folder>"
    )
    # nothing written besides what the case itself set up
    assert not [p for p in os.listdir(tmp_path) if p.endswith(".part") or "staging" in p]
    if key == "foreign_file":
        assert (tmp_path / "mine" / "notes.txt").read_text() == "keep me"


def test_docstring_and_signature_are_the_vtk_builds():
    import inspect

    from hoembed._checks import WRITE_SERIES_DOC

    assert hoembed.write_series.__doc__ == WRITE_SERIES_DOC
    assert (
        str(inspect.signature(hoembed.write_series))
        == "(frames_or_algorithm, folder, name='series', times=None)"
    )
