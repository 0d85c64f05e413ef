"""vtkTet10Mesher on every surface of ../shared/data/meshes and ../shared/data/meshes-real
(issue 27), plus generated cases (a thin-ribbed beam, a cube with a cavity), at every
count of --counts (default 300 1000 4000 10000) and order of --orders (default tet10, tet4),
one thread (--threads). Runs go count by count (1000 tet10 first), so a sweep cut short
still covers every input at the first counts.

Per run, each in its own process with a time limit (a run past it is recorded as such):
time, cells / target, the minimum / 1st percentile / median of the cell array
MinScaledJacobian, the mesher's crossing counts (found / left), the boundary mid-edge
nodes on the surface and pulled back (CurvedNodeCount, RelaxedNodeCount), and two checks by code
the mesher does not use: det J of every cell at the 35 points of the quartic lattice with
VTK's vtkQuadraticTetra derivatives (cells with det J <= 0 anywhere), and crossing pairs
of the curved boundary (Testing/Python/boundary_crossings.py: VTK's collision filter on
the subdivided tri6 faces).

    .venv/bin/python Benchmarks/bench_mesher_real.py [--counts 1000 ...] [--orders 2 1]
        [--timeout 240] [--threads 1] [--only NAME ...] [--out bench_mesher_real.json]
        [--set NAME=VALUE ...]   (settings other than the defaults, e.g. EnvelopeTolerance=0.01)
        [--data DIR ...]   (other folders of surfaces in place of ../shared/data's, e.g.
                            held-out files; the generated cases then only with --only)
    Low-poly generated cases (gen:cube, gen:long_box, gen:capped_cylinder,
    gen:icosahedron) run only when --only names them.

JSON: Benchmarks/results/<--out> (written after every run). A run past the time limit is
recorded as such, with the mesher's figures when only the checks ran out of time. Skips
cleanly without the data folders.
"""

import argparse
import json
import os
import pathlib
import subprocess
import sys
import time

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent
DATA = [ROOT.parent / "shared" / "data" / "meshes", ROOT.parent / "shared" / "data" / "meshes-real"]
SUFFIXES = {".obj", ".stl", ".ply", ".glb", ".gltf", ".vtp", ".vtk", ".off"}
GENERATED = ["gen:ribbed_beam", "gen:cube_with_cavity"]
# Low-poly surfaces of 12-192 triangles (test_low_poly_counts_follow_the_target's), whose
# boundaries are refined to the element size: run with --only, e.g. --only gen:cube.
LOW_POLY = {
    "gen:cube": lambda pv: pv.Cube().triangulate().clean(),
    "gen:long_box": lambda pv: pv.Box(bounds=(0, 4, 0, 1, 0, 1), level=3).triangulate().clean(),
    "gen:capped_cylinder": lambda pv: (
        pv.Cylinder(resolution=24, capping=True).triangulate().clean()
    ),
    "gen:icosahedron": lambda pv: pv.Icosahedron().triangulate().clean(),
}


def data_folders():
    """The input folders: --data's (passed to each run through the environment) or DATA."""
    given = os.environ.get("HOEMBED_BENCH_DATA")
    return [pathlib.Path(d) for d in given.split(os.pathsep)] if given else DATA


def one_run(name, count, order, threads):
    """Runs in the child: mesh, measure, print JSON lines (PARTIAL before the checks)."""
    import numpy as np
    import pyvista as pv

    sys.path.insert(0, str(ROOT / "Testing" / "Python"))
    from hoembed.hoembedFiltersMeshing import vtkTet10Mesher
    from vtkmodules.vtkCommonCore import vtkSMPTools
    from vtkmodules.vtkCommonDataModel import vtkQuadraticTetra

    vtkSMPTools.Initialize(threads)
    if name == "gen:ribbed_beam":
        from test_mesher_thin import ribbed_beam

        surface = ribbed_beam()
    elif name in LOW_POLY:
        surface = LOW_POLY[name](pv)
    elif name == "gen:cube_with_cavity":
        from test_mesher_any_surface import cube_with_cavity

        surface = cube_with_cavity()
    else:
        path = next(d / name for d in data_folders() if (d / name).exists())
        if path.suffix.lower() == ".off":  # not a VTK reader's: the CLI's own
            from hoembed import _readers

            points, tris = _readers.read_off(str(path))
            surface = pv.PolyData(points, np.hstack([np.full((len(tris), 1), 3), tris]).ravel())
        else:
            surface = pv.read(path)
        if isinstance(surface, pv.MultiBlock):
            surface = surface.combine()
        surface = surface.extract_surface().triangulate()
    alg = vtkTet10Mesher()
    alg.SetInputData(surface)
    alg.SetTargetNumberOfElements(count)
    alg.SetElementOrder(order)
    # --set: the parent passes its NAME=VALUE pairs to each run through the environment
    for kv in filter(None, os.environ.get("HOEMBED_BENCH_SET", "").split(",")):
        key, value = kv.split("=")
        getattr(alg, "Set" + key)(float(value))
    t0 = time.perf_counter()
    alg.Update()
    seconds = time.perf_counter() - t0
    grid = pv.wrap(alg.GetOutput())
    rec = dict(
        input=name,
        triangles=surface.n_cells,
        target=count,
        order=order,
        threads=threads,
        seconds=round(seconds, 2),
        cells=grid.n_cells,
    )
    if os.environ.get("HOEMBED_BENCH_SET"):
        rec["set"] = os.environ["HOEMBED_BENCH_SET"]
    if grid.n_cells == 0:
        rec["error"] = "no output"
        return rec
    fd = grid.field_data
    q = np.sort(np.asarray(grid.cell_data["MinScaledJacobian"]))
    rec.update(
        ratio=round(grid.n_cells / count, 3),
        msj_min=float(q[0]),
        msj_p1=float(q[int(0.01 * (len(q) - 1) + 0.5)]),
        msj_median=float(q[(len(q) - 1) // 2]),
        below_floor=int((q < 0.05).sum()),
        crossings_found=int(fd["BoundaryCrossingsFound"][0]),
        crossings_left=int(fd["BoundaryCrossingsLeft"][0]),
        wrapped=bool(fd["EnvelopeOffset"][0] > 0),
        curved_nodes=int(fd["CurvedNodeCount"][0]),
        relaxed_nodes=int(fd["RelaxedNodeCount"][0]),
    )
    print("PARTIAL " + json.dumps(rec), flush=True)
    # det J on the quartic lattice with VTK's own tet10 derivatives
    npc = 10 if order == 2 else 4
    conn = grid.cells.reshape(grid.n_cells, -1)[:, 1:]
    X = grid.points[conn]
    lattice = [
        (i / 4, j / 4, k / 4)
        for i in range(5)
        for j in range(5)
        for k in range(5)
        if i + j + k <= 4
    ]
    worst = np.full(grid.n_cells, np.inf)
    for p in lattice:
        if npc == 10:
            d = np.zeros(30)
            vtkQuadraticTetra.InterpolationDerivs(list(p), d)
            D = d.reshape(3, 10)
        else:
            D = np.array([[-1, 1, 0, 0], [-1, 0, 1, 0], [-1, 0, 0, 1]], float)
        J = np.einsum("nai,ja->nij", X, D)
        worst = np.minimum(worst, np.linalg.det(J))
    rec["vtk_detj_nonpositive"] = int((worst <= 0).sum())
    if order == 2:
        from boundary_crossings import crossing_face_pairs

        rec["vtk_crossing_pairs"] = len(crossing_face_pairs(grid))
    return rec


def print_table(results):
    """Per input: the tet10 run at 1000 in full, then per count and order the spread."""

    def q(r):
        return f"{r['msj_min']:.3f} / {r['msj_p1']:.3f} / {r['msj_median']:.2f}"

    print(
        "| input | s | cells (÷ target) | MSJ min / 1% / median | < 0.05 | crossings found / "
        "left / VTK | det J ≤ 0 (VTK) | path |"
    )
    print("| --- | --- | --- | --- | --- | --- | --- | --- |")
    for r in results:
        if r["target"] != 1000 or r["order"] != 2:
            continue
        if "msj_min" not in r:
            print(f"| {r['input']} | – | {r.get('error', '')[:60]} | | | | | |")
            continue
        print(
            f"| {r['input']} | {r['seconds']} | {r['cells']} ({r['ratio']:.2f}) | {q(r)} | "
            f"{r['below_floor']} | {r['crossings_found']} / {r['crossings_left']} / "
            f"{r.get('vtk_crossing_pairs', '–')} | {r['vtk_detj_nonpositive']} | "
            f"{'envelope' if r['wrapped'] else 'coarsened'} |"
        )
    print()
    print(
        "| count, order | runs done / meshed | s max | cells ÷ target | median MSJ: "
        "min / median over inputs | inputs < 0.2 | with cells < 0.05 | crossings left "
        "/ VTK | det J ≤ 0 |"
    )
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- |")

    def unchecked(rs):
        n = sum("vtk_detj_nonpositive" not in r for r in rs)
        return f" ({n} unchecked: time limit)" if n else ""

    keys = sorted({(r["target"], r["order"]) for r in results}, key=lambda k: (k[0], -k[1]))
    for count, order in keys:
        rs = [r for r in results if r["target"] == count and r["order"] == order]
        ok = [r for r in rs if "msj_min" in r]
        if not ok:
            continue
        med = sorted(r["msj_median"] for r in ok)
        ratio = [r["ratio"] for r in ok]
        print(
            f"| {count}, tet{10 if order == 2 else 4} | {len(rs)} / {len(ok)} | "
            f"{max(r['seconds'] for r in ok):.1f} | {min(ratio):.2f}–{max(ratio):.2f} | "
            f"{med[0]:.2f} / {med[(len(med) - 1) // 2]:.2f} | "
            f"{sum(m < 0.2 for m in med)} | {sum(r['below_floor'] > 0 for r in ok)} | "
            f"{sum(r['crossings_left'] for r in ok)} / "
            f"{sum(r.get('vtk_crossing_pairs', 0) for r in ok)} | "
            f"{sum(r.get('vtk_detj_nonpositive', 0) for r in ok)}"
            f"{unchecked(ok)} |"
        )
    return 0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--counts", type=int, nargs="+", default=[1000, 300, 4000, 10000])
    ap.add_argument("--orders", type=int, nargs="+", default=[2, 1])
    ap.add_argument("--timeout", type=float, default=240)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--only", nargs="*")
    ap.add_argument("--out", default="bench_mesher_real.json")
    ap.add_argument("--child", nargs=4)
    ap.add_argument(
        "--set",
        nargs="*",
        default=[],
        metavar="NAME=VALUE",
        help="vtkTet10Mesher settings other than the defaults, e.g. CurvedQualityTarget=0.3",
    )
    ap.add_argument(
        "--data",
        nargs="*",
        default=[],
        metavar="DIR",
        help="folders of surfaces to run in place of ../shared/data's",
    )
    ap.add_argument(
        "--table",
        action="store_true",
        help="print the Markdown tables of RESULTS.md from the JSON of --out",
    )
    args = ap.parse_args()
    if args.table:
        return print_table(json.loads((HERE / "results" / args.out).read_text()))
    if args.child:
        name, count, order, threads = args.child
        print("RESULT " + json.dumps(one_run(name, int(count), int(order), int(threads))))
        return 0
    if args.data:
        os.environ["HOEMBED_BENCH_DATA"] = os.pathsep.join(
            str(pathlib.Path(d).resolve()) for d in args.data
        )
    folders = data_folders()
    if not all(d.is_dir() for d in folders):
        print(f"bench_mesher_real: {', '.join(map(str, folders))} not found, skipped")
        return 0
    names = sorted(p.name for d in folders for p in d.iterdir() if p.suffix.lower() in SUFFIXES)
    names += GENERATED if not args.data or args.only else []
    names += list(LOW_POLY) if args.only else []
    if args.only:
        names = [n for n in names if n in args.only]
    if args.set:
        os.environ["HOEMBED_BENCH_SET"] = ",".join(args.set)
    runs = [(n, c, o) for c in args.counts for o in args.orders for n in names]
    out_dir = HERE / "results"
    out_dir.mkdir(exist_ok=True)
    results = []
    for name, count, order in runs:
        t0 = time.perf_counter()
        cmd = [sys.executable, __file__, "--child", name, str(count), str(order), str(args.threads)]
        try:
            p = subprocess.run(cmd, capture_output=True, text=True, timeout=args.timeout)
            stdout, stderr = p.stdout, p.stderr
            timed_out = False
        except subprocess.TimeoutExpired as e:
            stdout = e.stdout.decode() if isinstance(e.stdout, bytes) else (e.stdout or "")
            stderr = e.stderr.decode() if isinstance(e.stderr, bytes) else (e.stderr or "")
            timed_out = True
        lines = [ln for ln in stdout.splitlines() if ln.startswith(("RESULT ", "PARTIAL "))]
        if lines:
            rec = json.loads(lines[-1].split(" ", 1)[1])
            if timed_out:
                rec["error"] = f"checks past the time limit {args.timeout} s"
        elif timed_out:
            rec = dict(input=name, target=count, order=order, error=f"timeout {args.timeout} s")
        else:
            err = [ln for ln in stderr.splitlines() if "ERR" in ln or "Error" in ln]
            rec = dict(
                input=name,
                target=count,
                order=order,
                error=(err[-1] if err else stderr[-300:]).strip()[-300:],
            )
        rec["warnings"] = [
            ln.split("WARN|", 1)[1].strip()[:300] for ln in stderr.splitlines() if "WARN|" in ln
        ]
        rec["wall"] = round(time.perf_counter() - t0, 1)
        results.append(rec)
        print(json.dumps({k: v for k, v in rec.items() if k != "warnings"}), flush=True)
        (out_dir / args.out).write_text(json.dumps(results, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
