"""Tests of the ParaView plugin (run by `make test-paraview`, under Xvfb, with .venv's
Python = the VTK 9.1 build): the pvbatch pipeline against the VTK 9.1 build stage by
stage, its screenshot, the GUI's filter list, and the pipeline on 2 and 3 MPI processes
against 1, bitwise. Skipped when the plugin is not built."""
import json
import os
import pathlib
import shutil
import subprocess

import numpy as np
import pytest
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkIdTypeArray
from vtkmodules.vtkCommonDataModel import vtkPolyData
from vtkmodules.vtkFiltersCore import vtkTriangleFilter
from vtkmodules.vtkFiltersSources import vtkSphereSource
from vtkmodules.vtkIOImage import vtkPNGReader
from vtkmodules.vtkIOXML import (vtkXMLPolyDataWriter, vtkXMLPPolyDataReader,
                                 vtkXMLPUnstructuredGridReader)

import hoembed

ROOT = pathlib.Path(__file__).resolve().parents[2]
PVBATCH = ROOT / "scripts" / "pvbatch"
PIPELINE = ROOT / "Plugin" / "Testing" / "pv_pipeline.py"
PLUGIN = ROOT / "build-paraview" / "build" / "lib" / "paraview-plugins" / "HOEmbed"
STEPS, DT, ELEMENTS = 5, 0.02, 300

pytestmark = pytest.mark.skipif(not PLUGIN.is_dir(), reason="ParaView plugin not built (make paraview)")


def run(cmd, timeout=600, **kw):
    r = subprocess.run([str(c) for c in cmd], capture_output=True, text=True, timeout=timeout, **kw)
    assert r.returncode == 0, f"{cmd} failed ({r.returncode}):\n{r.stdout[-3000:]}\n{r.stderr[-3000:]}"
    return r


def make_surface(pieces_dir, npieces=4):
    """A generated closed surface (an ellipsoid, ~6k triangles) with a GlobalPointId
    array, as one .vtp and as a .pvtp of `npieces` slabs along x (each with its points)."""
    sphere = vtkSphereSource()
    sphere.SetThetaResolution(72)
    sphere.SetPhiResolution(48)
    sphere.SetRadius(1.0)
    tri = vtkTriangleFilter()
    tri.SetInputConnection(sphere.GetOutputPort())
    tri.Update()
    pts = vtk_to_numpy(tri.GetOutput().GetPoints().GetData()).astype(np.float64)
    pts = pts * np.array([1.0, 0.45, 0.3]) + 0.05 * np.sin(3 * pts[:, [1, 2, 0]])
    polys = vtk_to_numpy(tri.GetOutput().GetPolys().GetData()).reshape(-1, 4)[:, 1:]
    os.makedirs(pieces_dir, exist_ok=True)

    def write(path, p, t, gid):
        pd = vtkPolyData()
        from vtkmodules.vtkCommonCore import vtkPoints
        from vtkmodules.vtkCommonDataModel import vtkCellArray
        vp = vtkPoints()
        vp.SetData(numpy_to_vtk(np.ascontiguousarray(p), deep=True))
        pd.SetPoints(vp)
        ca = vtkCellArray()
        conn = np.hstack([np.full((len(t), 1), 3), t]).astype(np.int64).ravel()
        ca.SetCells(len(t), numpy_to_vtk(conn, deep=True, array_type=vtkIdTypeArray().GetDataType()))
        pd.SetPolys(ca)
        a = numpy_to_vtk(gid.astype(np.int64), deep=True)
        a.SetName("GlobalPointId")
        pd.GetPointData().AddArray(a)
        w = vtkXMLPolyDataWriter()
        w.SetFileName(str(path))
        w.SetInputData(pd)
        w.SetDataModeToBinary()
        assert w.Write() == 1

    whole = pathlib.Path(pieces_dir) / "surface.vtp"
    write(whole, pts, polys, np.arange(len(pts)))
    cx = pts[polys].mean(axis=1)[:, 0]
    edges = np.quantile(cx, np.linspace(0, 1, npieces + 1))
    slab = np.clip(np.searchsorted(edges, cx, side="right") - 1, 0, npieces - 1)
    lines = ['<?xml version="1.0"?>',
             '<VTKFile type="PPolyData" version="0.1" byte_order="LittleEndian" header_type="UInt64">',
             '  <PPolyData GhostLevel="0">',
             '    <PPointData><PDataArray type="Int64" Name="GlobalPointId"/></PPointData>',
             '    <PPoints><PDataArray type="Float64" NumberOfComponents="3"/></PPoints>']
    for k in range(npieces):
        t = polys[slab == k]
        used, inv = np.unique(t.ravel(), return_inverse=True)
        write(pathlib.Path(pieces_dir) / f"surface_{k}.vtp", pts[used], inv.reshape(-1, 3), used)
        lines.append(f'    <Piece Source="surface_{k}.vtp"/>')
    lines += ['  </PPolyData>', '</VTKFile>']
    pvtp = pathlib.Path(pieces_dir) / "surface.pvtp"
    pvtp.write_text("\n".join(lines) + "\n")
    return whole, pvtp


def read_pvtp(path):
    r = vtkXMLPPolyDataReader()
    r.SetFileName(str(path))
    r.Update()
    out = vtkPolyData()
    out.DeepCopy(r.GetOutput())
    return out


def read_pvtu(path):
    r = vtkXMLPUnstructuredGridReader()
    r.SetFileName(str(path))
    r.Update()
    return r.GetOutput()


def arr(ds, name):
    return vtk_to_numpy(ds.GetPointData().GetArray(name))


def points(ds):
    return vtk_to_numpy(ds.GetPoints().GetData()).astype(np.float64)


@pytest.fixture(scope="module")
def inputs(tmp_path_factory):
    d = tmp_path_factory.mktemp("pv_inputs")
    return make_surface(d)


@pytest.fixture(scope="module")
def serial_run(inputs, tmp_path_factory):
    out = tmp_path_factory.mktemp("pv_serial")
    shot = out / "shot.png"
    run([PVBATCH, PIPELINE, inputs[0], out, "--screenshot", shot,
         "--elements", ELEMENTS, "--steps", STEPS, "--dt", DT])
    return out


def test_pipeline_matches_vtk91_build(inputs, serial_run):
    """Every stage of the pvbatch pipeline against the VTK 9.1 build given the same input
    (the previous stage's ParaView output): equal to round-off."""
    from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
    r = vtkXMLPolyDataReader()
    r.SetFileName(str(inputs[0]))
    r.Update()
    surface = r.GetOutput()
    diag = np.linalg.norm(np.ptp(points(surface), axis=0))
    tol = 1e-9 * diag

    # Mesher: same element count and nodes (TetGen and the curving run on the same input).
    pv_rest = read_pvtu(serial_run / "rest_mesh.pvtu")
    mesher = hoembed.vtkTet10Mesher()
    mesher.SetInputData(surface)
    mesher.SetTargetNumberOfElements(ELEMENTS)
    mesher.Update()
    ref = mesher.GetOutput()
    assert pv_rest.GetNumberOfCells() == ref.GetNumberOfCells() > 50
    assert np.abs(points(pv_rest) - points(ref)).max() <= tol

    # Embedding of the same surface in ParaView's rest mesh.
    emb = hoembed.vtkEmbeddingCoordinatesFilter()
    emb.SetInputData(0, surface)
    emb.SetInputData(1, pv_rest)
    emb.Update()
    pv_emb = read_pvtp(serial_run / "embedded.pvtp")
    ids = arr(pv_emb, "GlobalPointId")
    assert np.array_equal(np.sort(ids), np.arange(surface.GetNumberOfPoints()))
    e = emb.GetOutput()
    assert np.array_equal(arr(pv_emb, "EmbeddingCellId"), arr(e, "EmbeddingCellId")[ids])
    assert np.abs(arr(pv_emb, "EmbeddingParametricCoords") - arr(e, "EmbeddingParametricCoords")[ids]).max() <= 1e-9
    assert np.abs(arr(pv_emb, "EmbeddingDistance") - arr(e, "EmbeddingDistance")[ids]).max() <= tol

    # Stepper on ParaView's rest mesh, and the transfer of ParaView's embedded surface with
    # ParaView's deformed mesh, at every time step the animation played.
    times = json.loads((serial_run / "times.json").read_text())["times"]
    assert len(times) == STEPS + 1 and times[-1] == pytest.approx(STEPS * DT)
    stepper = hoembed.vtkCorotationalFEMStepper()
    stepper.SetInputData(pv_rest)
    stepper.SetTimeStep(DT)
    stepper.SetNumberOfTimeSteps(STEPS)
    stepper.SetYoungModulus(3e4)
    stepper.SetPoissonRatio(0.45)
    stepper.UseClampPlaneOn()
    stepper.SetClampPlaneOrigin(-0.6, 0, 0)
    stepper.SetClampPlaneNormal(1, 0, 0)
    moved = 0.0
    for k, t in enumerate(times):
        stepper.UpdateTimeStep(t)
        pv_mesh = read_pvtu(serial_run / f"mesh_{k}.pvtu")
        u_ref = arr(stepper.GetOutput(), "Displacement")
        scale = max(np.abs(u_ref).max(), 1e-30)
        # Different VTK and compiler flags: the CG solve agrees to well within its tolerance.
        assert np.abs(arr(pv_mesh, "Displacement") - u_ref).max() <= 1e-6 * scale + 1e-12
        tr = hoembed.vtkDeformationTransferFilter()
        tr.SetInputData(0, pv_emb)
        tr.SetInputData(1, pv_mesh)
        tr.Update()
        pv_surf = read_pvtp(serial_run / f"surface_{k}.pvtp")
        assert np.abs(points(pv_surf) - points(tr.GetOutput())).max() <= tol
        moved = max(moved, np.abs(points(pv_surf) - points(pv_emb)).max())
    assert moved > 1e-3 * diag, "the simulation did not move the surface"


def test_screenshot_not_blank(serial_run):
    r = vtkPNGReader()
    r.SetFileName(str(serial_run / "shot.png"))
    r.Update()
    img = r.GetOutput()
    nx, ny, _ = img.GetDimensions()
    px = vtk_to_numpy(img.GetPointData().GetScalars()).reshape(ny, nx, -1)[..., :3].astype(int)
    background = px[0, 0]
    differs = np.any(np.abs(px - background) > 10, axis=-1)
    assert (nx, ny) == (640, 480)
    assert 0.05 < differs.mean() < 0.95, f"screenshot looks blank ({differs.mean():.3f} of pixels drawn)"
    assert len(np.unique(px[differs].reshape(-1, 3), axis=0)) > 20   # shaded and coloured


def test_gui_lists_the_filters(tmp_path):
    script = tmp_path / "list.py"
    out = tmp_path / "filters.json"
    script.write_text(
        "import json\n"
        "from paraview import servermanager as sm\n"
        "names = []\n"
        "pxm = sm.ProxyManager()\n"
        "defs = pxm.GetProxyDefinitionManager()\n"
        "it = defs.NewSingleGroupIterator('filters')\n"
        "it.GoToFirstItem()\n"
        "while not it.IsDoneWithTraversal():\n"
        "    if it.GetProxyName().startswith('HOEmbed'): names.append(it.GetProxyName())\n"
        "    it.GoToNextItem()\n"
        "from paraview import simple\n"
        "json.dump({'names': names, 'simple': [n for n in dir(simple) if n.startswith('HOEmbed')]}, open(%r, 'w'))\n"
        % str(out))
    env = dict(os.environ, PVTOOL="paraview")
    run([ROOT / "scripts" / "pvpython", f"--script={script}", "--exit"], env=env, timeout=300)
    got = json.loads(out.read_text())
    want = ["HOEmbedCorotationalFEMStepper", "HOEmbedDeformationTransfer",
            "HOEmbedEmbeddingCoordinates", "HOEmbedTet10Mesher"]
    assert sorted(got["names"]) == want
    assert sorted(got["simple"]) == want


@pytest.mark.skipif(shutil.which("mpirun") is None, reason="no mpirun")
def test_mpi_pieces_equal_serial_bitwise(inputs, tmp_path):
    """The surface in 4 pieces on 1, 2 and 3 (oversubscribed) processes: each embeds and
    transfers its pieces with the whole mesh; gathered by GlobalPointId, the embedding
    arrays and transferred points equal the 1-process run's bitwise."""
    results = {}
    for n in (1, 2, 3):
        out = tmp_path / f"np{n}"
        run(["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", n, PVBATCH, "--mpi",
             PIPELINE, inputs[1], out, "--elements", ELEMENTS, "--steps", 3, "--dt", DT],
            env=dict(os.environ, OMPI_MCA_rmaps_base_oversubscribe="1"))
        results[n] = out

    def gathered(out, name, arrays):
        pd = read_pvtp(out / name)
        gid = arr(pd, "GlobalPointId")
        u, first = np.unique(gid, return_index=True)
        vals = {a: (points(pd) if a == "Points" else arr(pd, a)) for a in arrays}
        for a, v in vals.items():   # a vertex on a piece seam is in both pieces: same values
            order = np.argsort(gid, kind="stable")
            g, vv = gid[order], v[order]
            same = g[1:] == g[:-1]
            assert np.array_equal(vv[1:][same], vv[:-1][same]), (name, a)
        return u, {a: v[first] for a, v in vals.items()}

    emb_arrays = ["EmbeddingCellId", "EmbeddingParametricCoords", "EmbeddingDistance",
                  "EmbeddingResidual", "EmbeddingFace"]
    ref_ids, ref = gathered(results[1], "embedded.pvtp", emb_arrays)
    for n in (2, 3):
        ids, got = gathered(results[n], "embedded.pvtp", emb_arrays)
        assert np.array_equal(ids, ref_ids)
        for a in emb_arrays:
            assert np.array_equal(got[a], ref[a]), f"{a} differs on {n} processes"
        for k in range(4):
            _, s1 = gathered(results[1], f"surface_{k}.pvtp", ["Points"])
            _, sn = gathered(results[n], f"surface_{k}.pvtp", ["Points"])
            assert np.array_equal(s1["Points"], sn["Points"]), f"step {k} differs on {n} processes"
