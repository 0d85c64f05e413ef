"""Speed of two HOEmbed builds, measured in the same run: embedding and transfer.

    .venv/bin/python Benchmarks/compare_speed.py --a /work/main/.venv/bin/python \
        --b .venv/bin/python --rounds 4

A reduced, alternating form of bench_embedding / bench_transfer for comparing builds
(e.g. before and after a refactoring): each round runs one worker process per build,
A then B then B then A (so drifts in the machine's load cancel), on the same inputs. A
worker meshes the surface (~1000 tet10), then times the normal-offset embedding (a new
filter each time: mesh preparation included), the barycentric one, and one transfer
frame in each normal mode with point normals (after a few stepper steps, so rotate and
deform have their arrays). Each figure is the minimum over its repeats, of the wall time
and of the process CPU time (cpu_*: all threads; less sensitive to other load on a
shared machine); the ratio B/A is the median over rounds of the per-round ratio (< 1: B
faster). JSON on stdout and in
Benchmarks/results/compare_speed.json.
"""

import argparse
import json
import os
import pathlib
import statistics
import subprocess
import sys
import time

HERE = pathlib.Path(__file__).resolve().parent
DEFAULT_DATA = HERE.parent.parent / "shared" / "data" / "meshes"


def worker(surface_name, elements, repeats, subdivide):
    import hoembed
    import pyvista

    path = DEFAULT_DATA / surface_name
    surface = (
        (pyvista.read(str(path)) if path.exists() else hoembed.thorny_tail()).triangulate().clean()
    )
    fe = hoembed.tet10_mesh(surface, n_elements=elements)
    if subdivide:  # a finer surface in the same mesh (each level: 4x the triangles)
        surface = surface.subdivide(subdivide, subfilter="linear")
    lo, hi = fe.bounds[4], fe.bounds[5]
    box = (
        fe.bounds[0] - 1,
        fe.bounds[1] + 1,
        fe.bounds[2] - 1,
        fe.bounds[3] + 1,
        lo - 1,
        lo + 0.2 * (hi - lo),
    )
    frame = hoembed.simulate(fe, steps=3, dt=0.02, young=3e4, fixed={"box": box})[-1]
    out = {"vertices": surface.n_points, "cells": fe.n_cells}

    def best(name, fn, n):
        wall, cpu = [], []
        for _ in range(n):
            t0, c0 = time.perf_counter(), time.process_time()
            fn()
            wall.append(time.perf_counter() - t0)
            cpu.append(time.process_time() - c0)
        out[name] = min(wall)
        out["cpu_" + name] = min(cpu)

    best("embed_normal_offset", lambda: hoembed.embed(surface, fe), repeats)
    best("embed_barycentric", lambda: hoembed.embed(surface, fe, method="barycentric"), repeats)
    embedded = hoembed.embed(surface, fe)
    for mode, value in (("recompute", 0), ("rotate", 1), ("deform", 2)):
        f = hoembed.vtkDeformationTransferFilter()
        f.SetInputData(0, embedded)
        f.SetInputData(1, frame)
        f.SetNormalMode(value)
        f.ComputePointNormalsOn()
        f.Update()  # plan and topology built once, as in an animation

        def one():
            frame.GetPoints().Modified()
            frame.Modified()
            f.Update()

        best(f"transfer_{mode}", one, 10 * repeats)
    return out


def main(argv=None):
    p = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    p.add_argument("--a", help="interpreter of build A (the reference)")
    p.add_argument("--b", help="interpreter of build B")
    p.add_argument("--rounds", type=int, default=4)
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--surface", default="bunny_watertight.obj")
    p.add_argument("--elements", type=int, default=1000)
    p.add_argument(
        "--subdivide", type=int, default=0, help="linear subdivision levels of the surface"
    )
    p.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    args = p.parse_args(argv)
    if args.worker:
        print(json.dumps(worker(args.surface, args.elements, args.repeats, args.subdivide)))
        return 0
    runs = {"a": [], "b": []}
    for r in range(args.rounds):
        for which in ("a", "b") if r % 2 == 0 else ("b", "a"):
            exe = args.a if which == "a" else args.b
            res = subprocess.run(
                [
                    exe,
                    os.path.abspath(__file__),
                    "--worker",
                    "--surface",
                    args.surface,
                    "--elements",
                    str(args.elements),
                    "--repeats",
                    str(args.repeats),
                    "--subdivide",
                    str(args.subdivide),
                ],
                capture_output=True,
                text=True,
                check=True,
            )
            runs[which].append(json.loads(res.stdout.strip().splitlines()[-1]))
            print(which, runs[which][-1], file=sys.stderr)
    keys = [k for k in runs["a"][0] if k.startswith(("embed", "transfer", "cpu_"))]
    summary = {
        "a": args.a,
        "b": args.b,
        "surface": args.surface,
        "subdivide": args.subdivide,
        "rounds": args.rounds,
        "vertices": runs["a"][0]["vertices"],
        "cells": runs["a"][0]["cells"],
        "ratio_b_over_a": {},
        "a_min_s": {},
        "b_min_s": {},
    }
    for k in keys:
        ratios = [rb[k] / ra[k] for ra, rb in zip(runs["a"], runs["b"])]
        summary["ratio_b_over_a"][k] = round(statistics.median(ratios), 4)
        summary["a_min_s"][k] = min(r[k] for r in runs["a"])
        summary["b_min_s"][k] = min(r[k] for r in runs["b"])
    (HERE / "results").mkdir(exist_ok=True)
    (HERE / "results" / "compare_speed.json").write_text(json.dumps(summary, indent=1))
    print(json.dumps(summary, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
