"""Benchmark of vtkEmbeddingCoordinatesFilter (paper section 6.2, Fig. 7) and of VTK's own
tools on the same points and meshes.

Measures, on the real surfaces of ../shared/data/meshes:
- speed: surface vertices per second of the filter's Update on 1 and 2 threads
  (vtkSMPTools.Initialize(n)), normal-offset on tet10 and barycentric on tet4: the best
  of repeated full Updates of one filter (it keeps its working memory), and the first
  Update of a fresh filter (`..._first_update`: fresh memory, one run);
- the 2-thread speed-up of normal-offset on tet10 (`speedup_2thr_tet10_wall`): best wall
  times of 1- and 2-thread Updates timed alternately (time_speedup);
- the fixed set-up cost (mesh preparation and element validation: the filter on a
  one-triangle surface) apart from the per-vertex cost; every timed Update prepares the
  mesh (it is marked modified), but for `..._mesh_prepared_once`, where the filter keeps
  the prepared mesh between Updates (ReuseMeshPreparation, as when embedding several
  surfaces in one FE mesh);
- scaling like Fig. 7: time against surface size (linear subdivision, x4 per level, 4
  sizes, up to > 1M vertices) on ~1000 and ~3000 element meshes, with the time ratio per
  4x vertices with and without the set-up, and the mean Newton iterations and elements
  visited per vertex at each size (finer surfaces give the flood closer starting points);
- VTK: vtkProbeFilter with a vtkStaticCellLocator on the tet4 mesh (barycentric, inside
  points only) and vtkCellLocator::FindClosestPoint on the tet10 grid (a Python loop over
  a sample; its per-call Python overhead is included), with time ratios and the distance
  error of VTK's closest points on curved cells against the exact ones;
- exactness on tet4 meshes for all vertices against VTK (boundary-triangle distances and
  vtkSelectEnclosedPoints), and the reconstruction residual on tet10.

FE meshes: hoembed.tet10_mesh (vtkTet10Mesher) at ~1000 and ~3000 elements, and the tet4
mesh on the same corner nodes; voxel tet meshes (Testing/Python/voxel_tet_mesh.py) when the mesher
fails on a surface. Results go to
Benchmarks/results/bench_embedding.json (+ .png when matplotlib is there). Skips cleanly
when the data folder is absent. The machine is shared: compare ratios, not absolute times.
"""

import json
import pathlib
import sys
import time

import numpy as np
import pyvista as pv
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import reference, vtkSMPTools
from vtkmodules.vtkCommonDataModel import vtkCellLocator, vtkStaticCellLocator
from vtkmodules.vtkFiltersCore import vtkProbeFilter
from vtkmodules.vtkFiltersModeling import vtkLinearSubdivisionFilter, vtkSelectEnclosedPoints

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "Testing" / "Python"))
import hoembed  # noqa: E402
from mesh_checks import distances_to_surface  # noqa: E402
from test_embedding import inside_linear_tets  # noqa: E402
from voxel_tet_mesh import linear_copy, voxel_tet_mesh  # noqa: E402

DATA = ROOT.parent / "shared" / "data" / "meshes"
SURFACES = [
    "bunny_watertight",
    "armadillo",
    "dragon",
    "fertility",
    "rocker-arm",
    "scorpion_low_resolution",
]
REPEATS = 3
# Short runs are repeated for about BUDGET_S seconds in all (at most MAX_RUNS runs) and the
# best is kept: bursts of load on this shared machine slow single runs by up to 1.5x, so a
# minimum over few runs of a 5-25 ms Update is mostly noise (best of 20 against best of
# 200 Updates, the same code: fertility ~1000 elements 2 threads 1.48x against 1.68-1.79x).
BUDGET_S = 2.0
MAX_RUNS = 150


def runs_for(best):
    """How many runs in all, given the best time of the first."""
    return max(REPEATS, min(MAX_RUNS, int(BUDGET_S / max(best, 1e-6))))


def make_filter(surface, grid, method):
    """An embedding filter on `surface` and the FE mesh `grid`."""
    f = hoembed.vtkEmbeddingCoordinatesFilter()
    f.SetInputData(0, surface)
    f.SetMeshData(grid)
    f.SetMethod(method)
    return f


def time_filter(surface, grid, method, threads, repeats=None, first=None, prepare=True):
    """Best time of the filter's Update over REPEATS runs (more for short runs: about
    BUDGET_S seconds of runs in all, at most MAX_RUNS): process CPU time for 1 thread
    (less sensitive to the other jobs on this shared machine), wall time for more threads
    (the 2-thread speed-up: time_speedup). Every run is a full Update of one filter, which keeps its
    working memory between Updates; with `prepare` (default) the mesh is marked modified
    before each run, so that every run prepares it (ReuseMeshPreparation would otherwise
    keep it: that is the `prepare=False` figure). The time of the first Update (fresh
    memory: page faults) is appended to the list `first` when one is given."""
    vtkSMPTools.Initialize(threads)
    f = make_filter(surface, grid, method)
    clock = time.process_time if threads == 1 else time.perf_counter
    best = np.inf
    runs, n = 0, repeats or REPEATS
    while runs < n:
        f.Modified()
        if prepare:
            grid.Modified()
        t = clock()
        f.Update()
        best = min(best, clock() - t)
        if first is not None and runs == 0:
            first.append(clock() - t)
        runs += 1
        if repeats is None and runs == 1:
            n = runs_for(best)
    out = pv.wrap(f.GetOutput()).copy()
    return best, out


def time_speedup(surface, grid, method=0):
    """Best wall times of the filter's Update on 1 and on 2 threads, runs alternating
    (1, 2, 1, 2, ...; one filter per thread count, each keeping its working memory) for
    about 2 BUDGET_S seconds: both bests then come from the same stretch of time. (Timed
    one block after the other, the bursts of load on this shared machine fall on one count
    more than the other: fertility gave 1.45-1.86 in blocks, 1.69-1.75 alternating in
    the same quiet stretch.) Returns (best 1-thread wall time, best 2-thread wall time)."""
    filters = {th: make_filter(surface, grid, method) for th in (1, 2)}
    best = {1: np.inf, 2: np.inf}
    pairs, n = 0, REPEATS
    while pairs < n:
        for th in (1, 2):
            vtkSMPTools.Initialize(th)
            f = filters[th]
            f.Modified()
            grid.Modified()  # every run prepares the mesh
            t = time.perf_counter()
            f.Update()
            best[th] = min(best[th], time.perf_counter() - t)
        pairs += 1
        if pairs == 1:
            n = runs_for(0.5 * (best[1] + best[2]))
    return best[1], best[2]


def time_setup(grid, method=0):
    """Best process time of the filter on a one-triangle surface at the mesh centre: the
    fixed cost (mesh preparation, element validation, output) of one Update."""
    c = np.asarray(grid.center, dtype=float)
    h = 1e-3 * grid.length
    tri = pv.PolyData(np.array([c, c + [h, 0, 0], c + [0, h, 0]]), faces=[3, 0, 1, 2])
    t, _ = time_filter(tri, grid, method, 1, repeats=7)
    return t


def fe_meshes(surface, n_el):
    """(tet10, tet4, how) meshes of about n_el elements."""
    try:
        g10 = hoembed.tet10_mesh(surface, n_elements=n_el)
        return g10, linear_copy(g10), "vtkTet10Mesher"
    except hoembed.HOEmbedError:
        g10 = voxel_tet_mesh(surface, n_el)
        return g10, linear_copy(g10), "voxel"


def time_probe(surface, grid4):
    """Best process time of vtkProbeFilter (static cell locator), repeated like our filter
    (time_filter: the same run budget)."""
    vtkSMPTools.Initialize(1)
    best = np.inf
    runs, n = 0, REPEATS
    while runs < n:
        p = vtkProbeFilter()
        probe = pv.PolyData(np.array(surface.points, dtype=float), deep=True)
        p.SetInputData(probe)
        p.SetSourceData(grid4)
        p.SetCellLocatorPrototype(vtkStaticCellLocator())
        t = time.process_time()
        p.Update()
        best = min(best, time.process_time() - t)
        runs += 1
        if runs == 1:
            n = runs_for(best)
    mask = vtk_to_numpy(p.GetOutput().GetPointData().GetArray("vtkValidPointMask"))
    return best, float(mask.mean())


def vtk_closest_tet10(grid10, points):
    loc = vtkCellLocator()
    loc.SetDataSet(grid10)
    t = time.perf_counter()
    loc.BuildLocator()
    cp = [0.0, 0.0, 0.0]
    cid, sub, d2 = reference(0), reference(0), reference(0.0)
    dist = np.empty(len(points))
    for i, p in enumerate(points):
        loc.FindClosestPoint(p, cp, cid, sub, d2)
        dist[i] = np.sqrt(float(d2))
    return time.perf_counter() - t, dist


def exact_tet4(grid4, points):
    """0 inside a cell (exact barycentric test over all cells, numpy), else the distance to
    the boundary triangles (VTK's locator, exact for triangles)."""
    boundary = grid4.extract_surface().triangulate()
    to_b = distances_to_surface(boundary, points)
    inside = inside_linear_tets(grid4, points)
    # VTK's own inside test, for the record: it disagrees near the boundary
    sel = vtkSelectEnclosedPoints()
    sel.SetSurfaceData(boundary)
    probe = pv.PolyData(np.array(points, dtype=float), deep=True)  # kept alive until Update
    sel.SetInputData(probe)
    sel.Update()
    vtk_inside = vtk_to_numpy(sel.GetOutput().GetPointData().GetArray("SelectedPoints")) > 0
    return np.where(inside, 0.0, to_b), int((vtk_inside != inside).sum())


def main():
    if not DATA.is_dir():
        print(json.dumps({"skipped": f"no data folder {DATA}"}))
        return 0
    results = {
        "machine_note": "2 shared cores; ratios matter, absolute times are noisy; "
        "1-thread times are process CPU times, 2-thread times wall times",
        "fe_meshes": "hoembed.tet10_mesh (voxel meshes where it fails)",
        "surfaces": {},
        "scaling": {},
        "scaling_exponent": {},
    }
    rng = np.random.default_rng(1)
    for name in SURFACES:
        path = DATA / f"{name}.obj"
        if not path.exists():
            continue
        s = pv.read(path).triangulate().clean(tolerance=0.0)
        entry = {"vertices": int(s.n_points)}
        for n_el in (1000, 3000):
            g10, g4, how = fe_meshes(s, n_el)
            diag = g10.length
            key = f"fe{n_el}"
            r = {"cells": int(g10.n_cells), "cells_tet4": int(g4.n_cells), "mesher": how}
            for th in (1, 2):
                first = []
                t10, out10 = time_filter(s, g10, 0, th, first=first)
                t4, out4 = time_filter(s, g4, 1, th)
                r[f"normal_offset_tet10_vps_{th}thr"] = s.n_points / t10
                r[f"barycentric_tet4_vps_{th}thr"] = s.n_points / t4
                # the first Update of a fresh filter (one run: noisy)
                r[f"normal_offset_tet10_vps_{th}thr_first_update"] = s.n_points / first[0]
            # the mesh prepared once and kept (ReuseMeshPreparation): another surface, or
            # the same one changed, embedded in the same FE mesh
            t_once, _ = time_filter(s, g10, 0, 1, prepare=False)
            r["normal_offset_tet10_vps_1thr_mesh_prepared_once"] = s.n_points / t_once
            r["setup_seconds_tet10"] = time_setup(g10)
            r["normal_offset_tet10_vps_1thr_excluding_setup"] = s.n_points / max(
                s.n_points / r["normal_offset_tet10_vps_1thr"] - r["setup_seconds_tet10"], 1e-9
            )
            w1, w2 = time_speedup(s, g10)
            r["normal_offset_tet10_vps_1thr_wall"] = s.n_points / w1
            r["normal_offset_tet10_vps_2thr_alternating"] = s.n_points / w2
            r["speedup_2thr_tet10_wall"] = w1 / w2
            r["inside_fraction"] = float(np.mean(out10["EmbeddingDistance"] == 0))
            r["max_residual_over_diag"] = float(out10["EmbeddingResidual"].max() / diag)
            r["max_distance_over_diag"] = float(out10["EmbeddingClosestDistance"].max() / diag)
            r["mean_iterations"] = float(out10["EmbeddingIterations"].mean())
            r["mean_elements_visited"] = float(out10["EmbeddingElementsVisited"].mean())
            if n_el == 1000:
                # exactness of tet4 distances against VTK, every vertex
                ref, vtk_inside_disagrees = exact_tet4(g4, s.points)
                _, o4 = time_filter(s, g4, 0, 1)
                mine = np.asarray(o4["EmbeddingClosestDistance"])
                err = np.abs(mine - ref)
                r["tet4_exact_fraction"] = float(np.mean(err <= 1e-8 * diag))
                r["tet4_max_error_over_diag"] = float(err.max() / diag)
                r["vtk_select_enclosed_points_wrong_vertices"] = vtk_inside_disagrees
                # VTK's probe (tet4, barycentric, inside points only)
                tp, valid = time_probe(s, g4)
                r["vtk_probe_tet4_vps"] = s.n_points / tp
                r["vtk_probe_valid_fraction"] = valid
                r["ratio_ours_tet4_barycentric_vs_probe"] = (
                    r["barycentric_tet4_vps_1thr"] / r["vtk_probe_tet4_vps"]
                )
                r["ratio_ours_tet10_vs_probe_tet4"] = (
                    r["normal_offset_tet10_vps_1thr"] / r["vtk_probe_tet4_vps"]
                )
                # vtkCellLocator::FindClosestPoint on the curved tet10 grid, sample
                sample = rng.choice(s.n_points, min(3000, s.n_points), replace=False)
                tc, dv = vtk_closest_tet10(g10, s.points[sample])
                exact = np.asarray(out10["EmbeddingClosestDistance"])[sample]
                e = dv - exact
                r["vtk_celllocator_tet10_vps"] = len(sample) / tc
                r["ratio_ours_tet10_vs_celllocator"] = (
                    r["normal_offset_tet10_vps_1thr"] / r["vtk_celllocator_tet10_vps"]
                )
                r["vtk_tet10_distance_error_max_over_diag"] = float(np.abs(e).max() / diag)
                r["vtk_tet10_distance_error_mean_over_diag"] = float(np.abs(e).mean() / diag)
                r["vtk_tet10_fraction_off_by_1e-8_diag"] = float(np.mean(np.abs(e) > 1e-8 * diag))
                r["vtk_tet10_min_signed_error_over_diag"] = float(e.min() / diag)
            entry[key] = r
        entry["time_ratio_fe3000_vs_fe1000"] = (
            entry["fe1000"]["normal_offset_tet10_vps_1thr"]
            / entry["fe3000"]["normal_offset_tet10_vps_1thr"]
        )
        results["surfaces"][name] = entry
        print(name, json.dumps(entry, indent=1), flush=True)

    # Fig. 7: time against surface size, two FE sizes, 4 sizes (x4 vertices per level by
    # linear subdivision) up to > 1M vertices
    for name in ("bunny_watertight", "dragon"):
        path = DATA / f"{name}.obj"
        if not path.exists():
            continue
        base = pv.read(path).triangulate().clean(tolerance=0.0)
        meshes = {n: fe_meshes(base, n)[0] for n in (1000, 3000)}
        setup = {n: time_setup(g) for n, g in meshes.items()}
        rows = []
        surf = base
        for level in range(4):
            if level > 0:
                sub = vtkLinearSubdivisionFilter()
                sub.SetInputData(surf)
                sub.SetNumberOfSubdivisions(1)
                sub.Update()
                surf = pv.wrap(sub.GetOutput()).clean(tolerance=0.0)
            row = {"vertices": int(surf.n_points)}
            # best of many for the short runs, of 5 / 3 for the long ones
            repeats = None if surf.n_points < 200_000 else (5 if surf.n_points < 1_000_000 else 3)
            for n, g in meshes.items():
                t, out = time_filter(surf, g, 0, 1, repeats=repeats)
                row[f"seconds_fe{n}"] = t
                row[f"setup_seconds_fe{n}"] = setup[n]
                row[f"per_vertex_seconds_fe{n}"] = t - setup[n]
                row[f"vps_fe{n}"] = surf.n_points / t
                row[f"cells_fe{n}"] = int(g.n_cells)
                row[f"mean_iterations_fe{n}"] = float(np.mean(out["EmbeddingIterations"]))
                row[f"mean_elements_visited_fe{n}"] = float(
                    np.mean(out["EmbeddingElementsVisited"])
                )
                row[f"inside_fraction_fe{n}"] = float(np.mean(out["EmbeddingDistance"] == 0))
                del out
            rows.append(row)
            print(name, "scaling", json.dumps(row), flush=True)
        for a, b in zip(rows, rows[1:]):
            b["vertex_ratio_vs_previous"] = b["vertices"] / a["vertices"]
            for n in (1000, 3000):
                b[f"time_ratio_vs_previous_fe{n}"] = b[f"seconds_fe{n}"] / a[f"seconds_fe{n}"]
                b[f"per_vertex_time_ratio_vs_previous_fe{n}"] = (
                    b[f"per_vertex_seconds_fe{n}"] / a[f"per_vertex_seconds_fe{n}"]
                )
                b[f"iterations_ratio_vs_previous_fe{n}"] = (
                    b[f"mean_iterations_fe{n}"] / a[f"mean_iterations_fe{n}"]
                )
        for row in rows:
            row["time_ratio_fe3000_vs_fe1000"] = row["seconds_fe3000"] / row["seconds_fe1000"]
        results["scaling"][name] = rows
        # the growth over the whole 64x range, less sensitive to one noisy size than the
        # single 4x steps: the least-squares slope of log time against log vertices
        # (1 = linear; a 4x step of 3.5-4.5x time is a slope of 0.90-1.08)
        logn = np.log([r["vertices"] for r in rows])
        results["scaling_exponent"][name] = {
            f"{key}_fe{n}": float(np.polyfit(logn, np.log([r[f"{key}_fe{n}"] for r in rows]), 1)[0])
            for key in ("seconds", "per_vertex_seconds")
            for n in (1000, 3000)
        }
        print(name, "scaling exponent", json.dumps(results["scaling_exponent"][name]), flush=True)
        print(name, "scaling", json.dumps(rows, indent=1), flush=True)

    out_dir = ROOT / "Benchmarks" / "results"
    out_dir.mkdir(parents=True, exist_ok=True)
    (out_dir / "bench_embedding.json").write_text(json.dumps(results, indent=1))
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(5, 4))
        for name, rows in results["scaling"].items():
            v = [r["vertices"] for r in rows]
            for n, style in ((1000, "o-"), (3000, "s--")):
                ax.plot(v, [r[f"seconds_fe{n}"] for r in rows], style, label=f"{name}, ~{n} tet10")
        if results["scaling"]:
            rows = next(iter(results["scaling"].values()))
            v = np.array([r["vertices"] for r in rows], dtype=float)
            ax.plot(v, rows[-1]["seconds_fe1000"] * v / v[-1], ":", color="gray", label="linear")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("surface vertices")
        ax.set_ylabel("embedding time [s] (1 thread)")
        ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(out_dir / "bench_embedding.png", dpi=120)
    except ImportError:
        pass
    print(json.dumps(results))
    return 0


if __name__ == "__main__":
    sys.exit(main())
