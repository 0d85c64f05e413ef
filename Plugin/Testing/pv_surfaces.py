"""Generated test surfaces for the ParaView plugin's tests and MPI benchmark (VTK 9.1
side: run with .venv's Python)."""

import os
import pathlib

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkIdTypeArray, vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData
from vtkmodules.vtkFiltersCore import vtkTriangleFilter
from vtkmodules.vtkFiltersSources import vtkSphereSource
from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter


def make_surface(pieces_dir, npieces=4, theta=72, phi=48):
    """A generated closed surface (a bumpy ellipsoid; theta*(phi-2)+2 vertices, 3314 by
    default) with a GlobalPointId array, written as surface.vtp and as surface.pvtp of
    `npieces` slabs along x (each slab's triangles with their points)."""
    sphere = vtkSphereSource()
    sphere.SetThetaResolution(theta)
    sphere.SetPhiResolution(phi)
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
        vp = vtkPoints()
        vp.SetData(numpy_to_vtk(np.ascontiguousarray(p), deep=True))
        pd.SetPoints(vp)
        ca = vtkCellArray()
        conn = np.hstack([np.full((len(t), 1), 3), t]).astype(np.int64).ravel()
        ca.SetCells(
            len(t), numpy_to_vtk(conn, deep=True, array_type=vtkIdTypeArray().GetDataType())
        )
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
    lines = [
        '<?xml version="1.0"?>',
        '<VTKFile type="PPolyData" version="0.1" byte_order="LittleEndian" header_type="UInt64">',
        '  <PPolyData GhostLevel="0">',
        '    <PPointData><PDataArray type="Int64" Name="GlobalPointId"/></PPointData>',
        '    <PPoints><PDataArray type="Float64" NumberOfComponents="3"/></PPoints>',
    ]
    for k in range(npieces):
        t = polys[slab == k]
        used, inv = np.unique(t.ravel(), return_inverse=True)
        write(pathlib.Path(pieces_dir) / f"surface_{k}.vtp", pts[used], inv.reshape(-1, 3), used)
        lines.append(f'    <Piece Source="surface_{k}.vtp"/>')
    lines += ["  </PPolyData>", "</VTKFile>"]
    pvtp = pathlib.Path(pieces_dir) / "surface.pvtp"
    pvtp.write_text("\n".join(lines) + "\n")
    return whole, pvtp
