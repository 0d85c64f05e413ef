"""vtkTet10Mesher on the real meshes: time, size, validity, boundary on the surface, volume.

    .venv/bin/python Benchmarks/bench_mesher.py [--sizes 1000 3000] [--meshes a b ...]

Writes Benchmarks/results/bench_mesher.json (and prints it). Skips when ../shared is absent.
"""

import argparse
import json
import pathlib
import sys
import time

import numpy as np
import pyvista as pv

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "Testing" / "Python"))
import hoembed  # noqa: E402
from boundary_crossings import crossing_face_pairs  # noqa: E402
from mesh_checks import (  # noqa: E402
    boundary_mid_nodes,
    distances_to_surface,
    straight_volumes,
    surface_volume,
    tet10_volumes,
)

DATA = HERE.parent.parent / "shared" / "data" / "meshes"
MESHES = [
    "bunny_watertight",
    "armadillo",
    "fertility",
    "rocker-arm",
    "scorpion_low_resolution",
    "dragon",
]


def field(mesh, name):
    """A field-data count; -1 when the build measured lacks it (an older baseline)."""
    return int(mesh.field_data[name][0]) if name in mesh.field_data.keys() else -1


def measure(name, surface, n):
    t0 = time.perf_counter()
    warnings = []
    alg = hoembed.vtkTet10Mesher()
    alg.SetInputData(surface)
    alg.SetTargetNumberOfElements(n)
    try:
        out = hoembed._errors.run_filter(alg, warnings)
    except hoembed.HOEmbedError as err:
        return dict(mesh=name, target=n, error=str(err))
    seconds = time.perf_counter() - t0
    mesh = pv.wrap(out)
    diag = surface.length
    mids = boundary_mid_nodes(mesh)
    d = distances_to_surface(surface, mesh.points[mids])
    v_fine = surface_volume(surface)
    v_curved = float(tet10_volumes(mesh).sum())
    v_straight = float(straight_volumes(mesh).sum())
    return dict(
        mesh=name,
        target=n,
        seconds=round(seconds, 3),
        cells=mesh.n_cells,
        points=mesh.n_points,
        surface_triangles=surface.n_cells,
        min_scaled_jacobian=float(mesh.cell_data["MinScaledJacobian"].min()),
        # per-cell minimum over the cubic lattice (20 points) of the curved tet10, det J > 0
        # proven by the Bernstein bound: minimum, 1st percentile, median
        scaled_jacobian_min_p1_median=[
            float(x) for x in np.percentile(mesh.cell_data["MinScaledJacobian"], [0, 1, 50])
        ],
        cells_below_0_05=int(np.sum(mesh.cell_data["MinScaledJacobian"] < 0.05)),
        cell_ratio_to_target=round(mesh.n_cells / n, 3),
        boundary_mid_nodes=int(len(mids)),
        on_surface_fraction=float(np.mean(d <= 1e-6 * diag)),
        relaxed_nodes=field(mesh, "RelaxedNodeCount"),
        boundary_crossings_found=field(mesh, "BoundaryCrossingsFound"),
        boundary_crossings_left=field(mesh, "BoundaryCrossingsLeft"),
        vtk_boundary_crossings=len(crossing_face_pairs(mesh)),
        max_surface_deviation=float(mesh.field_data["MaxSurfaceDeviation"][0]),
        volume_error_curved=(v_curved - v_fine) / v_fine,
        volume_error_straight=(v_straight - v_fine) / v_fine,
        warnings=warnings,
    )


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--sizes", type=int, nargs="+", default=[1000, 3000])
    ap.add_argument("--meshes", nargs="+", default=MESHES)
    ap.add_argument("--out", default=str(HERE / "results" / "bench_mesher.json"))
    args = ap.parse_args()
    if not DATA.is_dir():
        print(f"skipped: {DATA} not found")
        return 0
    rows = []
    for name in args.meshes:
        surface = pv.read(DATA / f"{name}.obj")
        for n in args.sizes:
            row = measure(name, surface, n)
            rows.append(row)
            print(json.dumps(row), flush=True)
    out = pathlib.Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(dict(benchmark="mesher", rows=rows), indent=1))
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
