"""Timing half of Benchmarks/bench_mpi.py, run by it under
`mpirun -np N scripts/pvbatch --mpi --symmetric` (every process runs this script).

Times, between barriers, the embedding of each process's pieces of the surface in the
whole mesh (mesh preparation included) and the transfer of FRAMES frames, each
re-executed alone after a first untimed run (the mesher, which gathers the pieces, and
the stepper's steps are not timed: stepper_s is an estimate, the first run of a frame
less the re-run). Every process also writes its own wall time to its end of each timed
part, its CPU time and its resident memory at the start (ParaView and the plugin loaded),
after the first embedding, at the end and at its peak (OUT.json.rankR), which rank 0 adds
to OUT.json as per_process.

    pv_bench_pieces.py SURFACE.pvtp OUT.json FRAMES ELEMENTS [MESH_SURFACE.vtp]

With MESH_SURFACE the mesher meshes that (coarser) surface of the same shape instead of
gathering the fine one: reading, meshing and a first embedding of a 2M-vertex surface took 411 s in
a 1-process run (the embedding is ~2 s of it), none of which the timed part includes.
"""

import json
import os
import resource
import sys
import time

from paraview.simple import (
    HOEmbedCorotationalFEMStepper,
    HOEmbedDeformationTransfer,
    HOEmbedEmbeddingCoordinates,
    HOEmbedTet10Mesher,
    OpenDataFile,
)
from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline as SDDP
from vtkmodules.vtkParallelCore import vtkMultiProcessController

surface_file, out_file, frames, elements = (
    sys.argv[1],
    sys.argv[2],
    int(sys.argv[3]),
    int(sys.argv[4]),
)
mesh_surface_file = sys.argv[5] if len(sys.argv) > 5 else None
ctrl = vtkMultiProcessController.GetGlobalController()
rank, size = ctrl.GetLocalProcessId(), ctrl.GetNumberOfProcesses()


def rss_mb():
    """This process's resident memory now (MiB)."""
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * resource.getpagesize() / 2**20


def cpu():
    """This process's CPU time (user + sys, all its threads), seconds."""
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


# Per process: wall time to its own end of each timed part (before the barrier: the
# difference to the barrier's time is waiting for the other process) and its CPU time.
mine = {
    "embedding_local_s": 0.0,
    "embedding_cpu_s": 0.0,
    "transfer_local_s": 0.0,
    "transfer_cpu_s": 0.0,
    "frame_update_local_s": 0.0,
    "frame_update_cpu_s": 0.0,
}


class Perf:
    """`perf record` under bench_mpi.py --perf: enabled over the parts named in
    HOEMBED_PERF_PARTS only (embedding, transfer: the timed re-runs; frame: the proxy's
    update of each frame, the stepper's step and the transfer)."""

    def __init__(self):
        base = os.environ.get("HOEMBED_PERF_CTL")
        self.parts = os.environ.get("HOEMBED_PERF_PARTS", "embedding,transfer").split(",")
        self.ctl = open(base + ".ctl", "w") if base else None
        self.ack = open(base + ".ack", "r") if base else None

    def set(self, on, part):
        if self.ctl and part in self.parts:
            self.ctl.write("enable\n" if on else "disable\n")
            self.ctl.flush()
            self.ack.readline()


perf = Perf()
surface = OpenDataFile(surface_file)
mesh_surface = OpenDataFile(mesh_surface_file) if mesh_surface_file else surface
mesher = HOEmbedTet10Mesher(Input=mesh_surface, TargetNumberOfElements=elements)
embedded = HOEmbedEmbeddingCoordinates(Surface=surface, Mesh=mesher)
stepper = HOEmbedCorotationalFEMStepper(
    Input=mesher,
    TimeStep=0.02,
    NumberOfTimeSteps=frames,
    YoungModulus=3e4,
    PoissonRatio=0.45,
    UseClampPlane=1,
    ClampPlaneOrigin=[-0.6, 0, 0],
    ClampPlaneNormal=[1, 0, 0],
)
transfer = HOEmbedDeformationTransfer(Surface=embedded, Mesh=stepper)

# The mesh is prepared anew in every timed embedding (as for a new surface).
embedded.ReuseMeshPreparation = 0
t0 = time.perf_counter()
mine["rss_start_mb"] = rss_mb()  # ParaView, Python and the plugin loaded
embedded.UpdatePipeline()  # read, gather + mesh, and a first embedding (untimed)
mine["rss_after_embedding_mb"] = rss_mb()
ctrl.Barrier()
t1 = time.perf_counter()
# Timed: the embedding alone, re-executed on the same inputs. (A proxy's UpdatePipeline
# asks the mesher for this process's piece while the embedding asks it for the whole:
# re-executing through the embedding keeps the mesher's request, so it is not re-run. The
# proxy skips an update when no property changed: the VTK object is updated directly.)
# The re-runs ask for the proxy's own request, ghost levels included: on more than one
# process ParaView asks for 1 ghost level (0 on one process), and a re-run asking for 0
# would leave data that the next proxy update (asking for 1) computes again, which the
# first frame's stepper_s then counted as a whole embedding.
emb_obj = embedded.GetClientSideObject()
ghosts = emb_obj.GetOutputInformation(0).Get(SDDP.UPDATE_NUMBER_OF_GHOST_LEVELS())
emb_obj.Modified()
perf.set(True, "embedding")
c0 = cpu()
emb_obj.UpdatePiece(rank, size, ghosts)
perf.set(False, "embedding")
mine["embedding_local_s"] = time.perf_counter() - t1
mine["embedding_cpu_s"] = cpu() - c0
ctrl.Barrier()
t2 = time.perf_counter()
times = [0.02 * k for k in range(1, frames + 1)]
stepper_s, transfer_s = 0.0, 0.0
for t in times:
    a = time.perf_counter()
    perf.set(True, "frame")
    c0 = cpu()
    transfer.UpdatePipeline(t)  # the stepper's step (replicated) and the transfer
    perf.set(False, "frame")
    mine["frame_update_local_s"] += time.perf_counter() - a
    mine["frame_update_cpu_s"] += cpu() - c0
    ctrl.Barrier()
    b = time.perf_counter()
    tr_obj = transfer.GetClientSideObject()
    tr_obj.Modified()
    perf.set(True, "transfer")
    c0 = cpu()
    tr_obj.UpdatePiece(rank, size, ghosts)  # timed: the transfer alone, same frame (time kept)
    perf.set(False, "transfer")
    mine["transfer_local_s"] += time.perf_counter() - b
    mine["transfer_cpu_s"] += cpu() - c0
    ctrl.Barrier()
    c = time.perf_counter()
    stepper_s += (b - a) - (c - b)
    transfer_s += c - b
local_points = emb_obj.GetOutputDataObject(0).GetNumberOfPoints()
assert tr_obj.GetOutputDataObject(0).GetNumberOfPoints() == local_points
mine["surface_points"] = local_points
mine["ghost_levels_requested"] = ghosts
mine["rss_end_mb"] = rss_mb()  # + the stepper and the transferred surface
mine["max_rss_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
with open(f"{out_file}.rank{rank}", "w") as f:
    json.dump(mine, f)
ctrl.Barrier()
if rank == 0:
    with open(out_file, "w") as f:
        json.dump(
            {
                "processes": size,
                "read_mesh_first_embedding_s": t1 - t0,
                "embedding_s": t2 - t1,
                "transfer_s": transfer_s,
                "transfer_frames": frames,
                "stepper_s": stepper_s,
                "embedding_plus_transfer_s": (t2 - t1) + transfer_s,
                "surface_points_rank0": local_points,
                "per_process": [json.load(open(f"{out_file}.rank{r}")) for r in range(size)],
            },
            f,
        )
