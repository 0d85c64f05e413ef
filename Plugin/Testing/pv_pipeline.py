"""The HOEmbed pipeline in ParaView: mesher -> embedding -> stepper -> transfer.

Run with scripts/pvbatch (serial, or `mpirun -np N scripts/pvbatch`); the HOEmbed plugin
is loaded through PV_PLUGIN_PATH. Plays the stepper's time steps through the animation
scene and writes, for every step k, `surface_<k>.pvtp` (the transferred surface) and
`mesh_<k>.pvtu` (the deformed FE mesh), plus `embedded.pvtp` and `rest_mesh.pvtu`, in
parallel pieces (one per process). Optionally a screenshot of the last frame.

    scripts/pvbatch Plugin/Testing/pv_pipeline.py SURFACE OUT_DIR [--screenshot PNG]
"""

import argparse
import json
import os

from paraview import servermanager
from paraview.simple import (
    ColorBy,
    CreateWriter,
    GetActiveViewOrCreate,
    GetAnimationScene,
    HOEmbedCorotationalFEMStepper,
    HOEmbedDeformationTransfer,
    HOEmbedEmbeddingCoordinates,
    HOEmbedTet10Mesher,
    OpenDataFile,
    Render,
    ResetCamera,
    SaveScreenshot,
    Show,
)

p = argparse.ArgumentParser()
p.add_argument("surface")
p.add_argument("out")
p.add_argument("--screenshot")
p.add_argument("--elements", type=int, default=300)
p.add_argument("--steps", type=int, default=5)
p.add_argument("--dt", type=float, default=0.02)
p.add_argument("--partitions", type=int, default=0)
args = p.parse_args()
os.makedirs(args.out, exist_ok=True)

surface = OpenDataFile(args.surface)
mesher = HOEmbedTet10Mesher(Input=surface, TargetNumberOfElements=args.elements)
embedded = HOEmbedEmbeddingCoordinates(
    Surface=surface, Mesh=mesher, NumberOfPartitions=args.partitions
)
stepper = HOEmbedCorotationalFEMStepper(Input=mesher)
stepper.TimeStep = args.dt
stepper.NumberOfTimeSteps = args.steps
stepper.YoungModulus = 3e4
stepper.PoissonRatio = 0.45
stepper.UseClampPlane = 1
stepper.ClampPlaneOrigin = [-0.6, 0.0, 0.0]
stepper.ClampPlaneNormal = [1.0, 0.0, 0.0]
transfer = HOEmbedDeformationTransfer(Surface=embedded, Mesh=stepper)

# The transfer is time-aware: it reports its mesh input's times to the animation.
times = list(transfer.TimestepValues)
assert len(times) == args.steps + 1, times
scene = GetAnimationScene()
scene.UpdateAnimationUsingDataTimeSteps()

CreateWriter(os.path.join(args.out, "embedded.pvtp"), embedded).UpdatePipeline()
CreateWriter(os.path.join(args.out, "rest_mesh.pvtu"), mesher).UpdatePipeline()
for k, t in enumerate(times):
    scene.AnimationTime = t  # the animation plays the simulation
    CreateWriter(os.path.join(args.out, "surface_%d.pvtp" % k), transfer).UpdatePipeline(t)
    CreateWriter(os.path.join(args.out, "mesh_%d.pvtu" % k), stepper).UpdatePipeline(t)

if args.screenshot:
    view = GetActiveViewOrCreate("RenderView")
    view.ViewSize = [640, 480]
    view.OrientationAxesVisibility = 0
    display = Show(transfer, view)
    ColorBy(display, ("POINTS", "EmbeddingDistance"))
    ResetCamera(view)
    Render(view)
    SaveScreenshot(args.screenshot, view, ImageResolution=[640, 480])

with open(os.path.join(args.out, "times.json"), "w") as f:
    json.dump(
        {
            "times": times,
            "processes": servermanager.vtkProcessModule.GetProcessModule().GetNumberOfLocalPartitions(),
        },
        f,
    )
