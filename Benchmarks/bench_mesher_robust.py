"""vtkTet10Mesher on surfaces that are not clean closed manifolds (issue 18), made from
../shared/data/meshes and generated shapes: holes cut in closed meshes, a face-like open
sheet, overlapping / nested components, a non-manifold fin, a duplicated shell, a
self-intersecting union of two closed meshes, stanford-bunny.obj (open), dragon.obj
(self-intersecting), random triangle deletions.

For each input: completes or not (the error), time (and per 100k input triangles), element
count against the target, every element valid (the filter's Bernstein bound
MinScaledJacobian > 0 and VTK's vtkCellValidator), the curved boundary free of crossings
(VTK's vtkCollisionDetectionFilter on the boundary subdivided with vtkQuadraticTriangle,
Testing/Python/boundary_crossings.py), the embedding exact on every vertex (the C++ tool
of bench_embedding_exact.py against its certified brute force), and a transfer onto a
rigidly moved mesh finite.

    .venv/bin/python Benchmarks/bench_mesher_robust.py [--elements 1000] [--cases a b ...]
                                                      [--no-exact]

JSON: Benchmarks/results/bench_mesher_robust.json. Skips cleanly without the data folder.
"""

import argparse
import json
import os
import pathlib
import sys
import tempfile
import time

import numpy as np
import pyvista as pv

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "Testing" / "Python"))
sys.path.insert(0, str(HERE))
import hoembed  # noqa: E402
from boundary_crossings import crossing_face_pairs  # noqa: E402
from mesh_checks import vtk_cell_validator_states  # noqa: E402

DATA = HERE.parent.parent / "shared" / "data" / "meshes"


def load(name):
    return pv.read(DATA / f"{name}.obj").triangulate().clean(tolerance=0.0)


def holes(name, centers, radius):
    s = load(name)
    c = s.cell_centers().points
    keep = np.ones(s.n_cells, bool)
    for k in centers:
        keep &= np.linalg.norm(c - s.points[k], axis=1) > radius * s.length
    return s.extract_cells(np.where(keep)[0]).extract_surface()


def face_sheet():
    # the front of the bunny: an open sheet with one boundary loop
    s = load("bunny_lowres")
    c = s.cell_centers().points
    mid = s.center
    return s.extract_cells(np.where(c[:, 2] > mid[2])[0]).extract_surface()


def overlapping():
    a = load("bunny_lowres")
    b = a.copy()
    b.points += np.array([0.3, 0.1, 0.0]) * a.length
    return a.merge(b, merge_points=False)


def nested():
    a = load("fertility")
    b = a.copy()
    b.points = (b.points - a.center) * 0.3 + a.center
    return a.merge(b, merge_points=False)


def fin():
    a = load("fandisk")
    plane = pv.Plane(
        center=a.center,
        direction=(1, 1, 0),
        i_size=0.8 * a.length,
        j_size=0.3 * a.length,
        i_resolution=20,
        j_resolution=8,
    ).triangulate()
    return a.merge(plane, merge_points=False)


def duplicated():
    a = load("rocker-arm")
    return a.merge(a.copy(), merge_points=False)


def union():
    a = load("bunny_lowres")
    b = load("armadillo_lowres")
    b.points = (
        (b.points - b.center) * (0.6 * a.length / b.length)
        + a.center
        + np.array([0.25, 0, 0]) * a.length
    )
    return a.merge(b, merge_points=False)


def random_deletions():
    s = load("armadillo_lowres")
    rng = np.random.default_rng(0)
    return s.remove_cells(rng.choice(s.n_cells, s.n_cells // 100, replace=False))


def generated_open_sphere():
    s = pv.Sphere(theta_resolution=80, phi_resolution=80).triangulate()
    return s.extract_cells(np.where(s.cell_centers().points[:, 2] < 0.3)[0]).extract_surface()


CASES = {
    "holes_bunny_watertight": lambda: holes("bunny_watertight", [0, 5000, 20000], 0.04),
    "face_sheet_bunny": face_sheet,
    "overlapping_bunnies": overlapping,
    "nested_fertility": nested,
    "fin_fandisk": fin,
    "duplicated_rocker_arm": duplicated,
    "union_bunny_armadillo": union,
    "stanford_bunny_open": lambda: load("stanford-bunny"),
    "dragon_self_intersecting": lambda: load("dragon"),
    "random_deletions_armadillo": random_deletions,
    "generated_open_sphere": generated_open_sphere,
}


def exactness(surface, mesh, tmp):
    from bench_embedding_exact import TOOL, run_tool

    if not TOOL.is_file():
        return dict(skipped=f"{TOOL} missing")
    sfile, gfile = tmp / "s.vtp", tmp / "g.vtu"
    surface.save(sfile)
    mesh.save(gfile)
    r = run_tool(sfile, gfile, "normal-offset", os.cpu_count() or 1)
    keys = [
        "surface_vertices",
        "vertices_checked",
        "count_dist_err_above_1e-8",
        "count_residual_above_1e-10",
        "max_dist_err_rel",
        "max_residual_rel",
        "vertices_inside_undecided",
    ]
    return {k: r[k] for k in keys if k in r}


def transfer_finite(surface, mesh):
    embedded = hoembed.embed(surface, mesh)
    moved = mesh.copy()
    c, s = np.cos(0.3), np.sin(0.3)
    moved.points = moved.points @ np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]]).T + 1.0
    out = hoembed.transfer(embedded, moved)
    return bool(np.all(np.isfinite(out.points)))


def measure(name, make, n, tmp, exact):
    surface = make()
    row = dict(case=name, triangles=int(surface.n_cells), target=n)
    warnings = []
    alg = hoembed.vtkTet10Mesher()
    alg.SetInputData(surface)
    alg.SetTargetNumberOfElements(n)
    t0 = time.perf_counter()
    try:
        out = hoembed._errors.run_filter(alg, warnings)
    except hoembed.HOEmbedError as err:
        row.update(completed=False, error=str(err))
        return row
    seconds = time.perf_counter() - t0
    mesh = pv.wrap(out)
    q = mesh.cell_data["MinScaledJacobian"]
    states = vtk_cell_validator_states(mesh)
    fd = {k: np.asarray(mesh.field_data[k][0]).tolist() for k in mesh.field_data.keys()}
    row.update(
        completed=True,
        seconds=round(seconds, 3),
        seconds_per_100k_triangles=round(seconds * 1e5 / max(1, surface.n_cells), 3),
        cells=mesh.n_cells,
        count_ratio=round(mesh.n_cells / n, 3),
        min_scaled_jacobian=float(q.min()),
        msj_quantiles={p: float(np.quantile(q, p / 100)) for p in (1, 5, 50)},
        cells_below_0_05=int((q < 0.05).sum()),
        bernstein_valid=bool(q.min() > 0),
        vtk_validator_invalid=int(np.count_nonzero(states & 0b100111)),
        vtk_boundary_crossings=len(crossing_face_pairs(mesh)),
        field_data=fd,
        warnings=warnings,
    )
    if exact:
        row["exactness"] = exactness(surface, mesh, tmp)
    row["transfer_finite"] = transfer_finite(surface, mesh)
    return row


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--elements", type=int, default=1000)
    ap.add_argument("--cases", nargs="+", default=list(CASES))
    ap.add_argument("--no-exact", action="store_true")
    ap.add_argument("--out", default=str(HERE / "results" / "bench_mesher_robust.json"))
    args = ap.parse_args()
    if not DATA.is_dir():
        print(json.dumps({"skipped": f"no data folder {DATA}"}))
        return 0
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for name in args.cases:
            row = measure(name, CASES[name], args.elements, pathlib.Path(tmp), not args.no_exact)
            rows.append(row)
            print(json.dumps(row), flush=True)
    ok = [
        r
        for r in rows
        if r.get("completed")
        and r["bernstein_valid"]
        and r["vtk_validator_invalid"] == 0
        and r["vtk_boundary_crossings"] == 0
        and r["transfer_finite"]
        and r.get("exactness", {}).get("count_dist_err_above_1e-8", 0) == 0
    ]
    summary = dict(
        cases=len(rows),
        all_checks_passed=len(ok),
        worst_seconds_per_100k_triangles=max(
            (r["seconds_per_100k_triangles"] for r in rows if r.get("completed")), default=None
        ),
    )
    out = pathlib.Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(
        json.dumps(dict(benchmark="mesher_robust", summary=summary, rows=rows), indent=1)
    )
    print(json.dumps(summary))
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
