"""Fetch (what ParaView's client-server delivery does to bring a parallel server's data
to the client) and display of every HOEmbed output, in pvbatch (serial or
`mpirun -np N scripts/pvbatch --mpi`). Writes, from the process running the script,
a JSON file with the number of points and cells each Fetch returned.

    scripts/pvbatch [--mpi] Plugin/Testing/pv_fetch.py SURFACE OUT_JSON [--display] [--native]

--native builds a pipeline of the same shape from ParaView's own filters (Delaunay3D for
the mesher, ResampleWithDataset for the embedding and the transfer, Transform for the
stepper), for a pvbatch run without the HOEmbed plugin: it tells the plugin's problems
from ParaView's.
"""

import argparse
import json

from paraview import servermanager, simple
from paraview.simple import GetActiveViewOrCreate, Hide, OpenDataFile, Render, Show

p = argparse.ArgumentParser()
p.add_argument("surface")
p.add_argument("out")
p.add_argument("--elements", type=int, default=300)
p.add_argument("--steps", type=int, default=3)
p.add_argument("--only", nargs="*", default=None)
p.add_argument("--display", action="store_true", help="also Show and Render each output")
p.add_argument("--native", action="store_true", help="ParaView's own filters, same shape")
p.add_argument(
    "--warmup",
    action="store_true",
    help="with --display: render the empty view once before anything is shown",
)
args = p.parse_args()

surface = OpenDataFile(args.surface)
if args.native:
    mesher = simple.Delaunay3D(Input=surface)
    embedded = simple.ResampleWithDataset(SourceDataArrays=mesher, DestinationMesh=surface)
    stepper = simple.Transform(Input=mesher)
    stepper.Transform.Translate = [0.0, 0.0, 0.01]
    transfer = simple.ResampleWithDataset(SourceDataArrays=stepper, DestinationMesh=embedded)
    times = [None, None]
else:
    mesher = simple.HOEmbedTet10Mesher(Input=surface, TargetNumberOfElements=args.elements)
    embedded = simple.HOEmbedEmbeddingCoordinates(
        Surface=surface, Mesh=mesher, NumberOfPartitions=1
    )
    stepper = simple.HOEmbedCorotationalFEMStepper(
        Input=mesher,
        TimeStep=0.02,
        NumberOfTimeSteps=args.steps,
        YoungModulus=3e4,
        PoissonRatio=0.45,
        UseClampPlane=1,
        ClampPlaneOrigin=[-0.6, 0.0, 0.0],
        ClampPlaneNormal=[1.0, 0.0, 0.0],
    )
    transfer = simple.HOEmbedDeformationTransfer(Surface=embedded, Mesh=stepper)
    times = list(transfer.TimestepValues)

if args.display and args.warmup:
    print("warming up", flush=True)
    warm = GetActiveViewOrCreate("RenderView")
    warm.ViewSize = [320, 240]
    Render(warm)

result = {
    "processes": servermanager.vtkProcessModule.GetProcessModule().GetNumberOfLocalPartitions()
}


def fetch(name, proxy, t=None):
    if args.only is not None and name not in args.only:
        return
    # As the client does: Fetch a proxy not updated before (only the time is chosen).
    # It hung so on 2 processes when the embedding failed on an empty piece of the
    # surface: that process skipped the gather.
    if t is not None:
        proxy.UpdatePipeline(t)
    print("fetching", name, flush=True)
    data = servermanager.Fetch(proxy)
    result[name] = {"points": data.GetNumberOfPoints(), "cells": data.GetNumberOfCells()}
    print("fetched", name, result[name], flush=True)


fetch("mesher", mesher)
fetch("embedding", embedded)
fetch("stepper", stepper, times[-1])
fetch("transfer", transfer, times[-1])
fetch("stepper_first", stepper, times[0])
fetch("transfer_first", transfer, times[0])

if args.display:
    view = GetActiveViewOrCreate("RenderView")
    view.ViewSize = [320, 240]
    for name, proxy in (
        ("mesher", mesher),
        ("embedding", embedded),
        ("stepper", stepper),
        ("transfer", transfer),
    ):
        print("showing", name, flush=True)
        display = Show(proxy, view)
        Render(view)
        Hide(proxy, view)
        result["shown_" + name] = True

with open(args.out, "w") as f:
    json.dump(result, f)
print("done", flush=True)
