"""Frame time of the live loop (hoembed.live.LiveSession), stage by stage.

Per frame, what the `hoembed live` window does between two renders: one stepper step
with moving prescribed nodes (a scripted drag of the tail's tip on a circle, the nodes'
targets changed every frame), then the transfer of the fine surface (normal-offset,
recomputed normals) with area-weighted point normals for shading. The FE mesh is meshed
from the built-in thorny tail (~3000 tet10); the fine surface is the same tail sampled
to ~1M vertices and embedded in that mesh.

Stages: `step` (vtkCorotationalFEMStepper.Step(1): the solver's rotations, assembly and
CG solve, reported by the filter, and the rest: loads in, output arrays out),
`transfer` (vtkDeformationTransferFilter.Update with point normals) and, from a second
pass of the same frames without point normals, `normals` (the difference). On 1 and 2
threads (vtkSMPTools), wall and process CPU time (all threads) per frame; median and
minimum over the frames (the machine is shared: the load average is recorded). Under an
X display (Xvfb: Mesa's software renderer, not what a GPU does) a third pass times the
window's whole frame (LiveApp.tick: step + transfer + render).

Grab and release (--grab-repeats, default 3 per mode): from rest, a grab of the tip, a
drag of --drag-frames frames, a release and 30 free frames, on 2 threads, alternately
with the stepper's BackgroundFactorization off (the synchronous refactorisation at the
grab and at the release: the peer) and on; per kind of frame (grab, drag, release, free)
the median and maximum wall time and the CG iterations, and after how many frames the
grab's own factor was taken.

    .venv/bin/python Benchmarks/bench_live.py [--frames 60] [--vertices 1000000]
        [--grab-repeats 3] [--drag-frames 60] [--passes 1,2]

Writes Benchmarks/results/bench_live.json; the last line printed is one JSON object
(frame_ms: median step + transfer + normals per frame on 2 threads, rendering excluded).
"""
import argparse
import json
import os
import pathlib
import time

import numpy as np
import pyvista as pv
from vtkmodules.vtkCommonCore import vtkSMPTools

import hoembed
from hoembed.live import LiveApp, LiveSession, default_clamp

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
            stages = session.step()
        else:
            app.tick()
            stages = dict(app.stages)
        t1, c1 = time.perf_counter(), time.process_time()
        t = st.timings
        rows.append(dict(
            wall=t1 - t0, cpu=c1 - c0, step=stages["step"], transfer=stages["transfer"],
            rotation=t["rotation"], assembly=t["assembly"], solve=t["solve"],
            factorization=t["factorization"], factorizations=t["factorizations"],
            iterations=t["iterations"]))
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
        rows.append(dict(kind=kind, wall=time.perf_counter() - t0,
                         iterations=t["iterations"], factorizations=t["factorizations"],
                         background=t["background_factorizations"]))
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
        out[f"{kind}_frame_ms"] = {"median": float(np.median(w)), "max": float(np.max(w)),
                                   "all": w}
        out[f"{kind}_iterations"] = [r["iterations"] for r in rows if r["kind"] == kind]
    for kind in ("drag", "free"):
        w = [1e3 * r["wall"] for r in rows if r["kind"] == kind]
        out[f"{kind}_frame_ms"] = {"median": float(np.median(w)), "max": float(np.max(w))}
        out[f"{kind}_iterations_mean"] = float(np.mean([r["iterations"] for r in rows
                                                        if r["kind"] == kind]))
    out["worst_frame_ms"] = float(max(1e3 * r["wall"] for r in rows))
    out["synchronous_factorizations"] = int(sum(r["factorizations"] for r in rows))
    out["background_factorizations"] = int(sum(r["background"] for r in rows))
    taken = []
    for run in runs:  # frames from the grab until the grab's own factor was taken
        k = next((i for i, r in enumerate(run) if r["background"] or r["factorizations"]),
                 None)
        taken.append(k)
    out["grab_factor_taken_after_frames"] = taken
    return out


def summarise(rows, skip):
    grab = rows[0]  # the frame of the grab: factorises for the new constraint set
    rows = rows[skip:]
    col = {k: [r[k] for r in rows] for k in rows[0]}
    out = {k: stats(col[k]) for k in ("wall", "cpu", "step", "transfer", "rotation",
                                      "assembly", "solve")}
    out["step_other"] = stats(np.array(col["step"]) - np.array(col["rotation"])
                              - np.array(col["assembly"]) - np.array(col["solve"]))
    out["iterations_mean"] = float(np.mean(col["iterations"]))
    out["factorizations"] = int(np.sum(col["factorizations"]))
    out["frames"] = len(rows)
    out["grab_frame_ms"] = 1e3 * grab["wall"]
    out["grab_factorization_ms"] = 1e3 * grab["factorization"]
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--frames", type=int, default=60)
    ap.add_argument("--vertices", type=int, default=1_000_000)
    ap.add_argument("--elements", type=int, default=3000)
    ap.add_argument("--grab-repeats", type=int, default=3,
                    help="grab/release runs per mode (synchronous, background); 0: none")
    ap.add_argument("--drag-frames", type=int, default=60)
    ap.add_argument("--passes", default="1,2",
                    help="thread counts of the frame-time passes ('' for none)")
    args = ap.parse_args()
    load_start = os.getloadavg()
    t0 = time.perf_counter()
    coarse = hoembed.thorny_tail()
    fe = hoembed.tet10_mesh(coarse, n_elements=args.elements)
    sectors = 512
    rings = max(8, int(round(args.vertices / sectors)))
    fine = hoembed.thorny_tail(rings=rings, sectors=sectors)
    embedded = hoembed.embed(fine, fe)
    setup = time.perf_counter() - t0
    session = LiveSession(fe, embedded, fixed=default_clamp(fe, builtin=True))
    threads0 = vtkSMPTools.GetEstimatedNumberOfThreads()
    result = {"vertices": int(fine.n_points), "triangles": int(fine.n_cells),
              "elements": int(fe.n_cells), "fe_nodes": int(fe.n_points),
              "frames": args.frames, "setup_s": setup, "load_average_start": load_start,
              "passes": {}}
    skip = min(5, args.frames // 4)
    for threads in [int(t) for t in args.passes.split(",") if t]:
        vtkSMPTools.Initialize(threads)
        rows, grabbed = run_pass(session, args.frames)
        result["passes"][f"{threads} thread{'s' if threads > 1 else ''}"] = summarise(rows, skip)
        session.point_normals = False
        rows, _ = run_pass(session, args.frames)
        session.point_normals = True
        result["passes"][f"{threads} thread{'s' if threads > 1 else ''}, no point normals"] = (
            summarise(rows, skip))
        result["grabbed_nodes"] = grabbed
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
    if "2 threads" in result["passes"] and "1 thread" in result["passes"]:
        two = result["passes"]["2 threads"]
        result["frame_ms"] = two["wall"]["median_ms"]
        result["frame_cpu_ms"] = two["cpu"]["median_ms"]
        result["frame_ms_1_thread"] = result["passes"]["1 thread"]["wall"]["median_ms"]
        result["normals_ms"] = (
            two["transfer"]["median_ms"]
            - result["passes"]["2 threads, no point normals"]["transfer"]["median_ms"])
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "bench_live.json").write_text(json.dumps(result, indent=1))
    for name, p in result["passes"].items():
        print(f"{name:<45} frame {p['wall']['median_ms']:6.1f} ms (cpu {p['cpu']['median_ms']:6.1f})"
              f"  step {p['step']['median_ms']:5.1f} [rot {p['rotation']['median_ms']:.1f} "
              f"asm {p['assembly']['median_ms']:.1f} solve {p['solve']['median_ms']:.1f} "
              f"other {p['step_other']['median_ms']:.1f}; {p['iterations_mean']:.1f} it]"
              f"  transfer {p['transfer']['median_ms']:5.1f}"
              + (f"  render {p['render']['median_ms']:.1f}" if "render" in p else "")
              + f"  grab frame {p['grab_frame_ms']:.0f}")
    for mode, g in result.get("grab_release", {}).items():
        if mode == "drag_frames":
            continue
        print(f"grab/release, {mode:<12} grab frame {g['grab_frame_ms']['median']:6.1f} ms "
              f"(max {g['grab_frame_ms']['max']:.1f}), release frame "
              f"{g['release_frame_ms']['median']:6.1f} ms (max {g['release_frame_ms']['max']:.1f}), "
              f"drag {g['drag_frame_ms']['median']:.1f} ms ({g['drag_iterations_mean']:.1f} it), "
              f"free {g['free_frame_ms']['median']:.1f} ms ({g['free_iterations_mean']:.1f} it), "
              f"worst frame {g['worst_frame_ms']:.1f} ms, factor taken after "
              f"{g['grab_factor_taken_after_frames']} frames")
    print(json.dumps(result))


if __name__ == "__main__":
    main()
