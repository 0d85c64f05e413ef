"""The HOEmbed pipeline as a plain VTK pipeline (SetInputConnection chains), no pyvista.

    .venv/bin/python Examples/Python/vtk_pipeline.py [OUTPUT_FOLDER]

A sphere source feeds the mesher and the embedding filter; the stepper's time steps flow
through the transfer filter into the time-series writer, which requests every step.
"""

import sys

import hoembed
from vtkmodules.vtkFiltersSources import vtkSphereSource

out = sys.argv[1] if len(sys.argv) > 1 else "vtk_pipeline_output"

source = vtkSphereSource()
source.SetThetaResolution(120)
source.SetPhiResolution(120)

mesher = hoembed.vtkTet10Mesher()
mesher.SetInputConnection(source.GetOutputPort())
mesher.SetTargetNumberOfElements(300)

embed = hoembed.vtkEmbeddingCoordinatesFilter()
embed.SetInputConnection(0, source.GetOutputPort())
embed.SetInputConnection(1, mesher.GetOutputPort())

stepper = hoembed.vtkCorotationalFEMStepper()
stepper.SetInputConnection(mesher.GetOutputPort())
stepper.SetYoungModulus(2e4)
stepper.SetPoissonRatio(0.49)
stepper.SetGravity(9.81, 0.0, 0.0)
stepper.SetTimeStep(0.02)
stepper.SetNumberOfTimeSteps(8)
stepper.SetUseClampPlane(True)
stepper.SetClampPlaneOrigin(0.0, 0.0, -0.35)
stepper.SetClampPlaneNormal(0.0, 0.0, 1.0)

transfer = hoembed.vtkDeformationTransferFilter()
transfer.SetInputConnection(0, embed.GetOutputPort())
transfer.SetInputConnection(1, stepper.GetOutputPort())

writer = hoembed.vtkTimeSeriesWriter()
writer.SetInputConnection(transfer.GetOutputPort())
writer.SetFileName(f"{out}/surface.pvd")
if not writer.Write():
    sys.exit("writing the series failed")
print(f"{mesher.GetOutput().GetNumberOfCells()} tet10 elements; wrote {out}/surface.pvd")
