"""Timing half of Benchmarks/bench_mpi.py, run by it under
`mpirun -np N scripts/pvbatch --mpi --symmetric` (every process runs this script).

Times, between barriers, the embedding of each process's pieces of the surface in the
whole mesh (mesh preparation included) and the transfer of FRAMES frames, each
re-executed alone after a first untimed run (the mesher, which gathers the pieces, and
the stepper's steps are not timed: stepper_s is an estimate, the first run of a frame
less the re-run). Rank 0 writes JSON.

    pv_bench_pieces.py SURFACE.pvtp OUT.json FRAMES ELEMENTS [MESH_SURFACE.vtp]

With MESH_SURFACE the mesher meshes that (coarser) surface of the same shape instead of
gathering the fine one: reading, meshing and a first embedding of a 2M-vertex surface took 411 s in
a 1-process run (the embedding is ~2 s of it), none of which the timed part includes.
"""
import json
import sys
import time

from paraview.simple import (HOEmbedCorotationalFEMStepper, HOEmbedDeformationTransfer,
                             HOEmbedEmbeddingCoordinates, HOEmbedTet10Mesher, OpenDataFile)
from vtkmodules.vtkParallelCore import vtkMultiProcessController

surface_file, out_file, frames, elements = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
mesh_surface_file = sys.argv[5] if len(sys.argv) > 5 else None
ctrl = vtkMultiProcessController.GetGlobalController()
rank, size = ctrl.GetLocalProcessId(), ctrl.GetNumberOfProcesses()

surface = OpenDataFile(surface_file)
mesh_surface = OpenDataFile(mesh_surface_file) if mesh_surface_file else surface
mesher = HOEmbedTet10Mesher(Input=mesh_surface, TargetNumberOfElements=elements)
embedded = HOEmbedEmbeddingCoordinates(Surface=surface, Mesh=mesher)
stepper = HOEmbedCorotationalFEMStepper(Input=mesher, TimeStep=0.02, NumberOfTimeSteps=frames,
                                        YoungModulus=3e4, PoissonRatio=0.45, UseClampPlane=1,
                                        ClampPlaneOrigin=[-0.6, 0, 0], ClampPlaneNormal=[1, 0, 0])
transfer = HOEmbedDeformationTransfer(Surface=embedded, Mesh=stepper)

# The mesh is prepared anew in every timed embedding (as for a new surface).
embedded.ReuseMeshPreparation = 0
t0 = time.perf_counter()
embedded.UpdatePipeline()          # read, gather + mesh, and a first embedding (untimed)
ctrl.Barrier()
t1 = time.perf_counter()
# Timed: the embedding alone, re-executed on the same inputs. (A proxy's UpdatePipeline
# asks the mesher for this process's piece while the embedding asks it for the whole:
# re-executing through the embedding keeps the mesher's request, so it is not re-run. The
# proxy skips an update when no property changed: the VTK object is updated directly.)
emb_obj = embedded.GetClientSideObject()
emb_obj.Modified()
emb_obj.UpdatePiece(rank, size, 0)
ctrl.Barrier()
t2 = time.perf_counter()
times = [0.02 * k for k in range(1, frames + 1)]
stepper_s, transfer_s = 0.0, 0.0
for t in times:
    a = time.perf_counter()
    transfer.UpdatePipeline(t)         # the stepper's step (replicated) and the transfer
    ctrl.Barrier()
    b = time.perf_counter()
    tr_obj = transfer.GetClientSideObject()
    tr_obj.Modified()
    tr_obj.UpdatePiece(rank, size, 0)  # timed: the transfer alone, same frame (time kept)
    ctrl.Barrier()
    c = time.perf_counter()
    stepper_s += (b - a) - (c - b)
    transfer_s += c - b
local_points = emb_obj.GetOutputDataObject(0).GetNumberOfPoints()
assert tr_obj.GetOutputDataObject(0).GetNumberOfPoints() == local_points
if rank == 0:
    with open(out_file, "w") as f:
        json.dump({"processes": size, "read_mesh_first_embedding_s": t1 - t0, "embedding_s": t2 - t1,
                   "transfer_s": transfer_s, "transfer_frames": frames, "stepper_s": stepper_s,
                   "embedding_plus_transfer_s": (t2 - t1) + transfer_s,
                   "surface_points_rank0": local_points}, f)
