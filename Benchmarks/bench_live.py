"""Frame time of the live loop (hoembed.live.LiveSession), stage by stage.

Per frame, what the `hoembed live` window does between two renders: one stepper step
with moving prescribed nodes (a scripted drag of the tail's tip on a circle, the nodes'
targets changed every frame), then the transfer of the fine surface (normal-offset,
recomputed normals) with point normals for shading (the session's point_normals). The
FE mesh is meshed from the built-in thorny tail (--elements, the mesher's target: its
count lands within +-30% of it, and the default 2500 gives ~2900 tet10, the issue's ~3000);
the fine surface is the same tail sampled to ~1M vertices and embedded in that mesh.

Stages: `step` (vtkCorotationalFEMStepper.Step(1): the solver's rotations, assembly and
CG solve, reported by the filter, and the rest: loads in, output arrays out),
`transfer` (the session's transfer: the transfer driver with point normals) and, from a
pass of the same frames without point normals, `normals` (the difference). The point
normals are timed both ways the session offers (point_normals, the transfer filter's
PointNormalsMode): `transform` (the session's default: the rest
normals carried by cof(F) in the transfer's own pass; frame_ms) and `recompute`
(area-weighted normals of the deformed triangles). On 1 and 2 threads (vtkSMPTools),
wall and process CPU time (all threads) per frame; median and minimum over the frames
(the machine is shared: the load average is recorded). Under an X display (Xvfb: Mesa's
software renderer, not what a GPU does) a further pass times the window's whole frame
(LiveApp.tick: step + transfer + render).

Bytes per frame: what each stage must read and write at the least (the plan and the
output arrays of the transfer, the polygon and incidence arrays of the recomputed
normals; for the step, the solver's own count (stepper.traffic: the element matrices
read and the step matrix written by the assembly, the matrix per CG product, the factor
per preconditioner application) times the mean products and applications per step),
against the stream bandwidth of
this machine measured in the same run (a numpy copy of 256 MB: read + write).

Overlap (LiveSession(overlap=True), off in `hoembed live`): the step of the next frame on
a second thread while this frame is transferred; on 2 threads, --overlap-rounds rounds of
an overlapped pass and a sequential pass, alternated (frame_ms_overlap: the overlapped
median; overlap_speedup: the sequential peer's median over it).

Grab and release (--grab-repeats, default 3 per mode): from rest, a grab of the tip, a
drag of --drag-frames frames, a release and 30 free frames, on 2 threads, alternately
with the stepper's BackgroundFactorization off (the synchronous refactorisation at the
grab and at the release: the peer) and on (as `hoembed live` runs); per kind of frame
(grab, drag, release, free) the median and maximum wall time and the CG iterations, and
after how many frames the grab's own factor was taken.

    .venv/bin/python Benchmarks/bench_live.py [--frames 60] [--vertices 1000000]
        [--grab-repeats 3] [--drag-frames 60] [--overlap-rounds 2] [--passes 1,2]
        [--point-normals transform] [--float-points] [--save DIR]

In a venv with the wheel (what a pip user runs; `backend` "pip" in the JSON), whose loops
take their thread count from HOEMBED_NUM_THREADS at start-up:

    HOEMBED_NUM_THREADS=2 python Benchmarks/bench_live.py --passes 2 ...

After the 2-thread passes, the last frame of the drag is transferred with both kinds of
point normals and the angle between them reported (normals_angle_deg: median, 99th and
99.9th percentiles, max; the inverted elements and the normals recomputed for them).

Writes Benchmarks/results/bench_live.json; the last line printed is one JSON object
(frame_ms: median step + transfer + normals per frame on 2 threads with the
--point-normals mode, rendering excluded; step_ms, solve_ms, assembly_ms, transfer_ms,
normals_ms: the stage medians; frame_ms_recompute_normals / normals_ms_recompute: the
other mode; grab_release_worst_ms: the worst frame of the grab/release runs with the
background factorisation, as `hoembed live` runs; bytes_per_frame and
stream_ms_per_frame against stream_bandwidth_GBps).
"""

import argparse
import json
import os
import pathlib
import time

import hoembed
import numpy as np
import pyvista as pv
from hoembed.live import LiveApp, LiveSession, default_clamp
from vtkmodules.vtkCommonCore import vtkSMPTools

RESULTS = pathlib.Path(__file__).resolve().parent / "results"


def stats(values):
    v = 1e3 * np.asarray(values)
    return {"median_ms": float(np.median(v)), "min_ms": float(v.min())}


def drag_path(session, frames):
    """The scripted drag: grab the FE node region at the tail's tip and move it on a
    circle of radius 1 (a tenth of the tail) once per 120 frames."""
    pos = session.positions()
    tip = pos[np.argmax(pos[:, 0])]
    ids = session.grab(tip)
    ang = 2 * np.pi * np.arange(1, frames + 1) / 120.0
    path = tip + np.c_[0 * ang, np.sin(ang), 1.0 - np.cos(ang)]
    return ids, path


def run_pass(session, frames, app=None):
    """Frames of the drag from the rest state; per-frame stage times."""
    session.reset()
    ids, path = drag_path(session, frames)
    st = session.stepper
    rows = []
    for p in path:
        session.drag(p)
        c0, t0 = time.process_time(), time.perf_counter()
        if app is None:
            stages = session.step()  # with overlap: the step ran beside the transfer
        else:
            app.tick()
            stages = dict(app.stages)
        t1, c1 = time.perf_counter(), time.process_time()
        t = st.timings
        rows.append(
            dict(
                wall=t1 - t0,
                cpu=c1 - c0,
                step=stages["step"],
                transfer=stages["transfer"],
                rotation=t["rotation"],
                assembly=t["assembly"],
                solve=t["solve"],
                factorization=t["factorization"],
                factorizations=t["factorizations"],
                iterations=t["iterations"],
            )
        )
    session.release()
    return rows, len(ids)


def grab_release(session, mode, drag_frames, free_frames):
    """One grab, a drag of drag_frames frames, a release and free_frames frames, with the
    stepper's BackgroundFactorization on or off (mode "background" / "synchronous"): wall
    time, CG iterations and factorisations (synchronous, background) of every frame."""
    st = session.stepper
    st.set_background_factorization(mode == "background")
    session.reset()
    for _ in range(5):  # swinging freely under the clamp (the rest factor is in use)
        session.step()
    pos = session.positions()
    tip = pos[np.argmax(pos[:, 0])]
    session.grab(tip)
    ang = 2 * np.pi * np.arange(1, drag_frames + 1) / 120.0
    rows = []

    def frame(kind):
        t0 = time.perf_counter()
        session.step()
        t = st.timings
        rows.append(
            dict(
                kind=kind,
                wall=time.perf_counter() - t0,
                iterations=t["iterations"],
                factorizations=t["factorizations"],
                background=t["background_factorizations"],
            )
        )

    for k, a in enumerate(ang):
        session.drag(tip + np.array([0.0, np.sin(a), 1.0 - np.cos(a)]))
        frame("grab" if k == 0 else "drag")
    session.release()
    for k in range(free_frames):
        frame("release" if k == 0 else "free")
    return rows


def grab_release_summary(runs):
    """Per kind of frame (grab, drag, release, free) over the runs: median and maximum
    wall time; the transition: frames until the background factor was taken."""
    out = {}
    rows = [r for run in runs for r in run]
    for kind in ("grab", "release"):
        w = [1e3 * r["wall"] for r in rows if r["kind"] == kind]
        out[f"{kind}_frame_ms"] = {"median": float(np.median(w)), "max": float(np.max(w)), "all": w}
        out[f"{kind}_iterations"] = [r["iterations"] for r in rows if r["kind"] == kind]
    for kind in ("drag", "free"):
        w = [1e3 * r["wall"] for r in rows if r["kind"] == kind]
        out[f"{kind}_frame_ms"] = {"median": float(np.median(w)), "max": float(np.max(w))}
        out[f"{kind}_iterations_mean"] = float(
            np.mean([r["iterations"] for r in rows if r["kind"] == kind])
        )
    out["worst_frame_ms"] = float(max(1e3 * r["wall"] for r in rows))
    out["synchronous_factorizations"] = int(sum(r["factorizations"] for r in rows))
    out["background_factorizations"] = int(sum(r["background"] for r in rows))
    taken = []
    for run in runs:  # frames from the grab until the grab's own factor was taken
        k = next((i for i, r in enumerate(run) if r["background"] or r["factorizations"]), None)
        taken.append(k)
    out["grab_factor_taken_after_frames"] = taken
    return out


def summarise(rows, skip):
    grab = rows[0]  # the frame of the grab: factorises for the new constraint set
    rows = rows[skip:]
    col = {k: [r[k] for r in rows] for k in rows[0]}
    out = {
        k: stats(col[k])
        for k in ("wall", "cpu", "step", "transfer", "rotation", "assembly", "solve")
    }
    out["step_other"] = stats(
        np.array(col["step"])
        - np.array(col["rotation"])
        - np.array(col["assembly"])
        - np.array(col["solve"])
    )
    out["iterations_mean"] = float(np.mean(col["iterations"]))
    out["factorizations"] = int(np.sum(col["factorizations"]))
    out["frames"] = len(rows)
    out["grab_frame_ms"] = 1e3 * grab["wall"]
    out["grab_factorization_ms"] = 1e3 * grab["factorization"]
    return out


def stream_bandwidth(repeats=7):
    """Bytes per second of a numpy copy of 256 MB (read + write counted), best of
    `repeats` (one thread: numpy copies serially)."""
    a = np.ones(32 * 1024 * 1024)
    b = np.empty_like(a)
    best = np.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        np.copyto(b, a)
        best = min(best, time.perf_counter() - t0)
    return 2 * a.nbytes / best


def frame_bytes(fine, point_bytes):
    """Least bytes moved per frame by the transfer and the two kinds of point normals
    (every array read or written once; gathers from cache-resident tables not counted)."""
    nv, nt = int(fine.n_points), int(fine.n_cells)
    plan = 48  # TransferEntry: pc 24, d 8, cell 4, face 4
    return {
        "transfer": nv * (plan + 3 * point_bytes),
        # covectors read (3 floats) and normals written (3 floats), in the same pass
        "normals_transform": nv * (12 + 12),
        # polygon pass: offsets 8 + 3 ids x 8 read and 3 doubles written per triangle, the
        # points gathered (each once at best); vertex pass: offsets 8, ids 4 per incident
        # triangle (3 per triangle in all) and the triangle normals read back (each once
        # at best), 12 bytes written per vertex
        "normals_recompute": nt * (8 + 24 + 24)
        + nv * 3 * point_bytes
        + nv * (8 + 12)
        + nt * (3 * 4 + 24),
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--frames", type=int, default=60)
    ap.add_argument("--vertices", type=int, default=1_000_000)
    ap.add_argument("--elements", type=int, default=2500)
    ap.add_argument(
        "--grab-repeats",
        type=int,
        default=3,
        help="grab/release runs per mode (synchronous, background); 0: none",
    )
    ap.add_argument("--drag-frames", type=int, default=60)
    ap.add_argument(
        "--overlap-rounds",
        type=int,
        default=2,
        help="2 threads: rounds of (overlap, sequential) passes, alternated",
    )
    ap.add_argument(
        "--solver-tolerance",
        type=float,
        default=None,
        help="the session's solver_tolerance (default: the stepper's SolverTolerance)",
    )
    ap.add_argument(
        "--passes", default="1,2", help="thread counts of the frame-time passes ('' for none)"
    )
    ap.add_argument(
        "--point-normals",
        choices=("transform", "recompute"),
        default="transform",
        help="the session's point_normals of the frame_ms passes (its default; "
        "the other is timed beside it on 2 threads)",
    )
    ap.add_argument(
        "--float-points",
        action="store_true",
        help="single precision surface points (the session's transfer writes "
        "the embedded surface's point type)",
    )
    ap.add_argument(
        "--save",
        metavar="DIR",
        help="also write the FE mesh and the embedded surface (DIR/fe.vtu, "
        "DIR/embedded.vtp: the inputs of build/bin/hoembedTransferBench)",
    )
    args = ap.parse_args()
    passes = [int(t) for t in args.passes.split(",") if t]
    if hoembed.BACKEND == "pip" and any(t != hoembed.number_of_threads() for t in passes + [2]):
        # the wheel's loops take their thread count from HOEMBED_NUM_THREADS at start-up;
        # vtkSMPTools (the user's pip VTK) does not reach them
        ap.error(
            f"the wheel runs {hoembed.number_of_threads()} threads: run with "
            "HOEMBED_NUM_THREADS=2 and --passes 2"
        )
    bandwidth = stream_bandwidth()
    load_start = os.getloadavg()
    t0 = time.perf_counter()
    coarse = hoembed.thorny_tail()
    fe = hoembed.tet10_mesh(coarse, n_elements=args.elements)
    sectors = 512
    rings = max(8, int(round(args.vertices / sectors)))
    fine = hoembed.thorny_tail(rings=rings, sectors=sectors)
    embedded = hoembed.embed(fine, fe)
    setup = time.perf_counter() - t0
    if args.save:
        os.makedirs(args.save, exist_ok=True)
        fe.save(os.path.join(args.save, "fe.vtu"))
        embedded.save(os.path.join(args.save, "embedded.vtp"))
    if args.float_points:
        # the plan keeps the surface's point type for its output (the rest normals of
        # transform mode are then those of the rounded points, as the filter's)
        embedded.points = np.asarray(embedded.points, dtype=np.float32)
    session = LiveSession(
        fe,
        embedded,
        fixed=default_clamp(fe, builtin=True),
        point_normals=args.point_normals,
        solver_tolerance=args.solver_tolerance,
    )
    modes = ("recompute", "transform")
    point_bytes = session.transfer.points.dtype.itemsize
    threads0 = vtkSMPTools.GetEstimatedNumberOfThreads()
    result = {
        "vertices": int(fine.n_points),
        "triangles": int(fine.n_cells),
        "elements": int(fe.n_cells),
        "fe_nodes": int(fe.n_points),
        "frames": args.frames,
        "backend": hoembed.BACKEND,  # "vtk" (the VTK build) or "pip" (the wheel)
        "setup_s": setup,
        "load_average_start": load_start,
        "point_normals": args.point_normals,
        "solver_tolerance": args.solver_tolerance,  # None: the stepper's default
        "output_point_bytes": point_bytes,
        "stream_bandwidth_GBps": bandwidth / 1e9,
        "passes": {},
    }
    skip = min(5, args.frames // 4)
    for threads in passes:
        vtkSMPTools.Initialize(threads)
        rows, grabbed = run_pass(session, args.frames)
        result["passes"][f"{threads} thread{'s' if threads > 1 else ''}"] = summarise(rows, skip)
        session.point_normals = False
        rows, _ = run_pass(session, args.frames)
        session.point_normals = args.point_normals
        result["passes"][f"{threads} thread{'s' if threads > 1 else ''}, no point normals"] = (
            summarise(rows, skip)
        )
        result["grabbed_nodes"] = grabbed
        if threads == 2:  # LiveSession(overlap=True) against the sequential loop, alternated
            # with the sequential one: rounds of (sequential, overlap) passes
            seq, ovl = [], []
            for _ in range(args.overlap_rounds):
                session.overlap = True
                ovl += run_pass(session, args.frames)[0][skip:]
                session.overlap = False
                seq += run_pass(session, args.frames)[0][skip:]
            if ovl:
                result["passes"]["2 threads, overlap"] = summarise(ovl, 0)
                result["passes"]["2 threads, sequential beside overlap"] = summarise(seq, 0)
            # the other point normals mode, beside it
            other = next(m for m in modes if m != args.point_normals)
            session.point_normals = other
            rows, _ = run_pass(session, args.frames)
            session.point_normals = args.point_normals
            result["passes"][f"2 threads, {other} point normals"] = summarise(rows, skip)
    if "2 threads" in result["passes"]:
        # the two point normals on the last frame of the drag (same positions)
        run_pass(session, args.frames)
        # the same frame again with each mode (refresh: the transfer alone, no step)
        normals, folded = {}, 0
        for m in modes:
            session.point_normals = m
            session.refresh()
            normals[m] = np.array(session.surface.point_data["Normals"], float)
            folded = max(folded, session.folded_normals)
        session.point_normals = args.point_normals
        cos = np.clip(np.einsum("ij,ij->i", normals["recompute"], normals["transform"]), -1, 1)
        ang = np.degrees(np.arccos(cos))
        result["normals_angle_deg"] = {
            "median": float(np.median(ang)),
            "p99": float(np.percentile(ang, 99)),
            "p999": float(np.percentile(ang, 99.9)),
            "max": float(ang.max()),
            "inverted_elements": int(session.transfer.driver.number_of_inverted_cells),
            "folded_normals": int(folded),
        }
        session.release()
    if args.grab_repeats > 0:
        # the grab/release stall: synchronous refactorisation against the background
        # factorisation, alternated in the same run (2 threads)
        vtkSMPTools.Initialize(2)
        runs = {"synchronous": [], "background": []}
        for _ in range(args.grab_repeats):
            for mode in runs:
                runs[mode].append(grab_release(session, mode, args.drag_frames, 30))
        session.stepper.set_background_factorization(True)
        result["grab_release"] = {m: grab_release_summary(r) for m, r in runs.items()}
        result["grab_release"]["drag_frames"] = args.drag_frames
    if os.environ.get("DISPLAY"):
        vtkSMPTools.Initialize(2)
        pl = pv.Plotter(window_size=(1024, 768))
        app = LiveApp(session, plotter=pl)
        pl.show(interactive_update=True, auto_close=False)
        rows, _ = run_pass(session, args.frames, app=app)
        s = summarise(rows, skip)
        s["render"] = stats(np.array([r["wall"] - r["step"] - r["transfer"] for r in rows[skip:]]))
        result["passes"]["2 threads, rendered (Xvfb, Mesa software)"] = s
        pl.close()
    vtkSMPTools.Initialize(threads0)
    result["load_average_end"] = os.getloadavg()
    passes = result["passes"]
    if "2 threads" in passes:
        two = passes["2 threads"]
        bare = passes["2 threads, no point normals"]
        result["frame_ms"] = two["wall"]["median_ms"]
        if "2 threads, overlap" in passes:
            # LiveSession(overlap=True): the next frame's step beside this one's transfer
            ovl = passes["2 threads, overlap"]["wall"]["median_ms"]
            peer = passes["2 threads, sequential beside overlap"]["wall"]["median_ms"]
            result["frame_ms_overlap"] = ovl
            result["overlap_speedup"] = peer / ovl
        result["frame_cpu_ms"] = two["cpu"]["median_ms"]
        if "1 thread" in passes:
            result["frame_ms_1_thread"] = passes["1 thread"]["wall"]["median_ms"]
        result["step_ms"] = two["step"]["median_ms"]
        result["iterations_mean"] = two["iterations_mean"]
        result["solve_ms"] = two["solve"]["median_ms"]
        result["assembly_ms"] = two["assembly"]["median_ms"]
        result["transfer_ms"] = bare["transfer"]["median_ms"]
        result["normals_ms"] = two["transfer"]["median_ms"] - bare["transfer"]["median_ms"]
        other = next(m for m in modes if m != args.point_normals)
        o = passes[f"2 threads, {other} point normals"]
        result[f"frame_ms_{other}_normals"] = o["wall"]["median_ms"]
        result[f"normals_ms_{other}"] = o["transfer"]["median_ms"] - bare["transfer"]["median_ms"]
        moved = frame_bytes(fine, point_bytes)
        # the step: the solver's least bytes per product, preconditioner application and
        # assembly (stepper.traffic), times the CG's counts per step (the projection's
        # products, then one product and one application per iteration)
        tr = session.stepper.traffic
        it = two["iterations_mean"]
        moved["step"] = int(
            (tr["guess_products"] + it) * tr["product_bytes"]
            + it * tr["preconditioner_bytes"]
            + tr["assembly_bytes"]
        )
        result["bytes_per_frame"] = moved
        result["stream_ms_per_frame"] = {k: 1e3 * v / bandwidth for k, v in moved.items()}
    if "grab_release" in result:
        result["grab_release_worst_ms"] = result["grab_release"]["background"]["worst_frame_ms"]
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "bench_live.json").write_text(json.dumps(result, indent=1))
    for name, p in result["passes"].items():
        print(
            f"{name:<45} frame {p['wall']['median_ms']:6.1f} ms (cpu {p['cpu']['median_ms']:6.1f})"
            f"  step {p['step']['median_ms']:5.1f} [rot {p['rotation']['median_ms']:.1f} "
            f"asm {p['assembly']['median_ms']:.1f} solve {p['solve']['median_ms']:.1f} "
            f"other {p['step_other']['median_ms']:.1f}; {p['iterations_mean']:.1f} it]"
            f"  transfer {p['transfer']['median_ms']:5.1f}"
            + (f"  render {p['render']['median_ms']:.1f}" if "render" in p else "")
            + f"  grab frame {p['grab_frame_ms']:.0f}"
        )
    for mode, g in result.get("grab_release", {}).items():
        if mode == "drag_frames":
            continue
        print(
            f"grab/release, {mode:<12} grab frame {g['grab_frame_ms']['median']:6.1f} ms "
            f"(max {g['grab_frame_ms']['max']:.1f}), release frame "
            f"{g['release_frame_ms']['median']:6.1f} ms (max {g['release_frame_ms']['max']:.1f}), "
            f"drag {g['drag_frame_ms']['median']:.1f} ms ({g['drag_iterations_mean']:.1f} it), "
            f"free {g['free_frame_ms']['median']:.1f} ms ({g['free_iterations_mean']:.1f} it), "
            f"worst frame {g['worst_frame_ms']:.1f} ms, factor taken after "
            f"{g['grab_factor_taken_after_frames']} frames"
        )
    if "bytes_per_frame" in result:
        for k, v in result["bytes_per_frame"].items():
            print(
                f"bytes per frame, {k:<18} {v / 1e6:7.1f} MB = "
                f"{result['stream_ms_per_frame'][k]:.2f} ms at the stream bandwidth "
                f"{bandwidth / 1e9:.1f} GB/s (numpy copy, read + write)"
            )
    # the last line: the figures of the issue, in one object (bench_live.json has all)
    keys = (
        "frame_ms",
        "frame_ms_overlap",
        "overlap_speedup",
        "vertices",
        "elements",
        "point_normals",
        "step_ms",
        "solve_ms",
        "assembly_ms",
        "iterations_mean",
        "solver_tolerance",
        "transfer_ms",
        "normals_ms",
        "frame_ms_recompute_normals",
        "normals_ms_recompute",
        "frame_ms_transform_normals",
        "normals_ms_transform",
        "frame_ms_1_thread",
        "grab_release_worst_ms",
        "normals_angle_deg",
        "bytes_per_frame",
        "stream_bandwidth_GBps",
        "stream_ms_per_frame",
        "load_average_start",
        "load_average_end",
    )
    print(json.dumps({k: result[k] for k in keys if k in result}))


if __name__ == "__main__":
    main()
