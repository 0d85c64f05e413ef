"""Timing half of Benchmarks/bench_mpi.py, run by it under
`mpirun -np N scripts/pvbatch --mpi --symmetric` (every process runs this script).

Times, between barriers, the embedding of each process's pieces of the surface in the
whole mesh and the transfer of FRAMES frames (the mesher, which gathers the pieces, and
the stepper's steps are run before and not timed). Rank 0 writes JSON.

    pv_bench_pieces.py SURFACE.pvtp OUT.json FRAMES ELEMENTS
"""
import json
import sys
import time

from paraview.simple import (HOEmbedCorotationalFEMStepper, HOEmbedDeformationTransfer,
                             HOEmbedEmbeddingCoordinates, HOEmbedTet10Mesher, OpenDataFile)
from vtkmodules.vtkParallelCore import vtkMultiProcessController

surface_file, out_file, frames, elements = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
ctrl = vtkMultiProcessController.GetGlobalController()
rank, size = ctrl.GetLocalProcessId(), ctrl.GetNumberOfProcesses()

surface = OpenDataFile(surface_file)
mesher = HOEmbedTet10Mesher(Input=surface, TargetNumberOfElements=elements)
embedded = HOEmbedEmbeddingCoordinates(Surface=surface, Mesh=mesher)
stepper = HOEmbedCorotationalFEMStepper(Input=mesher, TimeStep=0.02, NumberOfTimeSteps=frames,
                                        YoungModulus=3e4, PoissonRatio=0.45, UseClampPlane=1,
                                        ClampPlaneOrigin=[-0.6, 0, 0], ClampPlaneNormal=[1, 0, 0])
transfer = HOEmbedDeformationTransfer(Surface=embedded, Mesh=stepper)

t0 = time.perf_counter()
surface.UpdatePipeline()
mesher.UpdatePipeline()
ctrl.Barrier()
t1 = time.perf_counter()
embedded.UpdatePipeline()
ctrl.Barrier()
t2 = time.perf_counter()
times = [0.02 * k for k in range(1, frames + 1)]
stepper_s, transfer_s = 0.0, 0.0
for t in times:
    a = time.perf_counter()
    stepper.UpdatePipeline(t)
    ctrl.Barrier()
    b = time.perf_counter()
    transfer.UpdatePipeline(t)
    ctrl.Barrier()
    c = time.perf_counter()
    stepper_s += b - a
    transfer_s += c - b
local_points = embedded.GetDataInformation().GetNumberOfPoints()
if rank == 0:
    with open(out_file, "w") as f:
        json.dump({"processes": size, "read_and_mesh_s": t1 - t0, "embedding_s": t2 - t1,
                   "transfer_s": transfer_s, "transfer_frames": frames, "stepper_s": stepper_s,
                   "embedding_plus_transfer_s": (t2 - t1) + transfer_s,
                   "surface_points_all_pieces": local_points}, f)
