"""The HOEmbed pipeline on a surface with ghost cells, as ParaView's D3 makes them
(it redistributes the surface and adds one layer of ghost triangles and their ghost
points around each process's piece, marked in vtkGhostType; ExtractSurface makes it a
vtkPolyData again), in pvbatch (serial, or `mpirun -np N scripts/pvbatch
--mpi`). Every output is fetched as the client would (servermanager.Fetch) and written
by the process running the script: mesh.vtu (the mesher's), embedded.vtp, and
surface_first.vtp / surface_last.vtp (the transfer's first and last step), the meshes
(mesh.vtu, mesh_ghosted.vtu, mesh_unghosted.vtu), plus fetch.json (counts).

    scripts/pvbatch [--mpi] Plugin/Testing/pv_ghosts.py SURFACE OUT_DIR [--mesh-ghosts]

--mesh-ghosts puts a GhostCellsGenerator on the FE mesh (between the mesher and the
embedding and stepper): a distributed mesh, which every HOEmbed filter refuses. (ParaView 5.11's GhostCellsGenerator makes no ghosts on a surface
of triangles, as a vtkPolyData or a vtkUnstructuredGrid: seen here; it does on 3D cells.)
"""

import argparse
import json
import os

from paraview import servermanager, simple
from paraview.vtk.vtkIOXML import vtkXMLPolyDataWriter, vtkXMLUnstructuredGridWriter

p = argparse.ArgumentParser()
p.add_argument("surface")
p.add_argument("out")
p.add_argument("--elements", type=int, default=300)
p.add_argument("--steps", type=int, default=3)
p.add_argument("--mesh-ghosts", action="store_true")
args = p.parse_args()
os.makedirs(args.out, exist_ok=True)

surface = simple.OpenDataFile(args.surface)
# MinimumNumberOfGhostLevels: the ghost layer is made whatever the downstream filters ask
# for (the mesher asks for none).
ghosted = simple.ExtractSurface(Input=simple.D3(Input=surface, MinimumNumberOfGhostLevels=1))
# The mesh from the surface as read (a serial reader: the same triangle order as in one
# process; the mesher's result follows the order of the triangles), so that the
# embedding and the transfer of the ghosted surface can be compared with one process's.
mesher = simple.HOEmbedTet10Mesher(Input=surface, TargetNumberOfElements=args.elements)
# The mesher on the ghosted surface and on the same surface without its ghost cells
# (ParaView's RemoveGhostInformation): the same gathered surface, the same mesh.
mesher_ghosted = simple.HOEmbedTet10Mesher(Input=ghosted, TargetNumberOfElements=args.elements)
mesher_unghosted = simple.HOEmbedTet10Mesher(
    Input=simple.RemoveGhostInformation(Input=ghosted), TargetNumberOfElements=args.elements
)
mesh = mesher
if args.mesh_ghosts:
    mesh = simple.GhostCellsGenerator(Input=mesher, BuildIfRequired=0, MinimumNumberOfGhosts=1)
embedded = simple.HOEmbedEmbeddingCoordinates(Surface=ghosted, Mesh=mesh, NumberOfPartitions=1)
stepper = simple.HOEmbedCorotationalFEMStepper(
    Input=mesh,
    TimeStep=0.02,
    NumberOfTimeSteps=args.steps,
    YoungModulus=3e4,
    PoissonRatio=0.45,
    UseClampPlane=1,
    ClampPlaneOrigin=[-0.6, 0.0, 0.0],
    ClampPlaneNormal=[1.0, 0.0, 0.0],
)
transfer = simple.HOEmbedDeformationTransfer(Surface=embedded, Mesh=stepper, ComputePointNormals=1)
times = list(transfer.TimestepValues) or [0.0]

result = {
    "processes": servermanager.vtkProcessModule.GetProcessModule().GetNumberOfLocalPartitions()
}


def fetch(name, proxy, t=None):
    if t is not None:
        proxy.UpdatePipeline(t)
    data = servermanager.Fetch(proxy)
    result[name] = {"points": data.GetNumberOfPoints(), "cells": data.GetNumberOfCells()}
    w = vtkXMLPolyDataWriter() if data.IsA("vtkPolyData") else vtkXMLUnstructuredGridWriter()
    w.SetFileName(os.path.join(args.out, name + (".vtp" if data.IsA("vtkPolyData") else ".vtu")))
    w.SetInputData(data)
    w.SetDataModeToBinary()
    assert w.Write() == 1
    print("fetched", name, result[name], flush=True)


fetch("ghosted", ghosted)
fetch("embedded", embedded)
fetch("surface_last", transfer, times[-1])
fetch("surface_first", transfer, times[0])
if not args.mesh_ghosts:
    fetch("mesh", mesher)
    fetch("mesh_ghosted", mesher_ghosted)
    fetch("mesh_unghosted", mesher_unghosted)
with open(os.path.join(args.out, "fetch.json"), "w") as f:
    json.dump(result, f)
print("done", flush=True)
