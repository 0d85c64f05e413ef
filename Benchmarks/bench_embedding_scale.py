"""Scale invariance of vtkEmbeddingCoordinatesFilter (issue 19): a surface and its FE mesh
(hoembed.tet10_mesh, ~1000 elements, meshed once at scale 1) scaled together by s, from
1e-9 to 1e9, embedded, and compared with scale 1 in units of the diagonal: largest
residual, largest change of the distance and of the closest distance, vertices whose
cell changed (a closest point on a face shared by two cells may change cell), fallback
vertices. Powers of two (exact scaling) must give bitwise the same relative results.
Benchmarks decide nothing: the JSON says.

    .venv/bin/python Benchmarks/bench_embedding_scale.py [surface names...]

JSON: Benchmarks/results/bench_embedding_scale.json. The real surfaces are skipped
without the data folder (the built-in thorny tail always runs).
"""

import json
import pathlib
import sys

import numpy as np
import pyvista as pv

ROOT = pathlib.Path(__file__).resolve().parents[1]
import hoembed  # noqa: E402
from hoembed._errors import run_filter  # noqa: E402
from hoembed.hoembedFiltersEmbedding import vtkEmbeddingCoordinatesFilter  # noqa: E402

DATA = ROOT.parent / "shared" / "data" / "meshes"
SCALES = [1e-9, 1e-7, 3e-7, 1e-5, 1e-3, 1e3, 1e5, 1e7, 1e9, 2.0**-30, 2.0**30]


def embed(surface, mesh):
    alg = vtkEmbeddingCoordinatesFilter()
    alg.SetInputData(0, surface)
    alg.SetMeshData(mesh)
    return pv.wrap(run_filter(alg, [])).copy()


def scaled(data, s):
    out = data.copy()
    out.points = np.asarray(data.points, dtype=float) * s
    return out


def run(name, surface):
    surface = pv.PolyData(np.asarray(surface.points, dtype=float), faces=surface.faces)
    mesh = hoembed.tet10_mesh(surface, n_elements=1000)
    diag = mesh.length
    ref = embed(surface, mesh)
    rows = []
    for s in SCALES:
        out = embed(scaled(surface, s), scaled(mesh, s))
        row = {
            "scale": s,
            "max_residual": float(out["EmbeddingResidual"].max() / (s * diag)),
            "max_distance_change": float(
                np.abs(out["EmbeddingDistance"] / s - ref["EmbeddingDistance"]).max() / diag
            ),
            "max_closest_distance_change": float(
                np.abs(out["EmbeddingClosestDistance"] / s - ref["EmbeddingClosestDistance"]).max()
                / diag
            ),
            "cells_changed": int((out["EmbeddingCellId"] != ref["EmbeddingCellId"]).sum()),
            "fallback": int(out["EmbeddingFallback"].sum()),
        }
        if np.log2(s) == round(np.log2(s)):
            row["bitwise_identical"] = bool(
                all(
                    np.array_equal(out[a], ref[a])
                    for a in ["EmbeddingCellId", "EmbeddingParametricCoords", "EmbeddingFace"]
                )
                and all(
                    np.array_equal(out[a] / s, ref[a])
                    for a in ["EmbeddingDistance", "EmbeddingResidual", "EmbeddingClosestDistance"]
                )
            )
        rows.append(row)
        print(name, row, flush=True)
    return {
        "surface": name,
        "vertices": surface.n_points,
        "cells": mesh.n_cells,
        "scale_1_max_residual": float(ref["EmbeddingResidual"].max() / diag),
        "scales": rows,
    }


def main(names):
    results = [run("thorny_tail", hoembed.thorny_tail())]
    for name in names or ["bunny_lowres", "armadillo_lowres"]:
        path = DATA / f"{name}.obj"
        if not path.exists():
            print(f"skipped {name}: {path} absent")
            continue
        results.append(run(name, pv.read(path).extract_surface().triangulate()))
    out = ROOT / "Benchmarks" / "results"
    out.mkdir(exist_ok=True)
    (out / "bench_embedding_scale.json").write_text(json.dumps(results, indent=1))


if __name__ == "__main__":
    main(sys.argv[1:])
