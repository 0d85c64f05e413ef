"""vtkEmbeddingCoordinatesFilter next to the paper's method: a bound-constrained
Levenberg–Marquardt per candidate face (Ceres, on faces evaluated by VTK's own cells;
Benchmarks/Cxx/hoembedCeresReference.h), speed and failures side by side.

For real surfaces of ../shared/data/meshes, hoembed.tet10_mesh at ~1000 elements, on
the tet10 mesh and on the same geometry re-expressed as order-3 Lagrange tetrahedra (the
quadratic map evaluated at vtkLagrangeTetra's nodes; run only where the filter takes that
cell type), the C++ tool build/bin/hoembedEmbeddingCeres embeds every vertex with the
filter and solves a sample of about 2000 vertices with the reference, both on one thread.
A "miss" is a closest distance more than 1e-10 of the diagonal above the other method's.

    .venv/bin/python Benchmarks/bench_embedding_ceres.py [surface names...]

JSON: Benchmarks/results/bench_embedding_ceres.json. Skips cleanly without the data
folder or without the tool (built only when Ceres is found).
"""

import json
import pathlib
import subprocess
import sys
import tempfile

import numpy as np
import pyvista as pv
import vtk

ROOT = pathlib.Path(__file__).resolve().parents[1]
import hoembed  # noqa: E402

DATA = ROOT.parent / "shared" / "data" / "meshes"
TOOL = ROOT / "build" / "bin" / "hoembedEmbeddingCeres"
SURFACES = ["bunny_watertight", "armadillo", "rocker-arm"]


def lagrange_nodes(order):
    """VTK_LAGRANGE_TETRAHEDRON's parametric coordinates of its nodes, for `order`."""
    n = (order + 1) * (order + 2) * (order + 3) // 6
    cell = vtk.vtkLagrangeTetra()
    cell.GetPointIds().SetNumberOfIds(n)
    cell.GetPoints().SetNumberOfPoints(n)
    cell.Initialize()
    pc = cell.GetParametricCoords()
    return np.array([pc[i] for i in range(3 * n)]).reshape(n, 3)


def as_lagrange(tet10, order=3):
    """The tet10 mesh re-expressed exactly as order-`order` Lagrange tetrahedra: each node
    is the quadratic map at vtkLagrangeTetra's parametric coordinates; nodes shared by cells
    are merged by (corner ids, lattice index), not by coordinates."""
    pcs = lagrange_nodes(order)
    quad = vtk.vtkQuadraticTetra()
    weights = np.zeros((len(pcs), 10))
    for a, pc in enumerate(pcs):
        w = [0.0] * 10
        quad.InterpolationFunctions(pc, w)
        weights[a] = w
    bary = np.rint(np.column_stack([1 - pcs.sum(axis=1), pcs]) * order).astype(int)
    cells = tet10.cells_dict[pv.CellType.QUADRATIC_TETRA]
    pts = np.asarray(tet10.points)
    index, points, conn = {}, [], []
    for c in cells:
        x = weights @ pts[c]
        ids = []
        for a in range(len(pcs)):
            key = tuple(sorted((int(c[v]), int(bary[a, v])) for v in range(4) if bary[a, v]))
            if key not in index:
                index[key] = len(points)
                points.append(x[a])
            ids.append(index[key])
        conn.append([len(pcs)] + ids)
    types = np.full(len(cells), pv.CellType.LAGRANGE_TETRAHEDRON, dtype=np.uint8)
    return pv.UnstructuredGrid(np.array(conn).ravel(), types, np.array(points))


def run(surface_file, mesh_file):
    out = subprocess.run(
        [str(TOOL), str(surface_file), str(mesh_file)], capture_output=True, text=True, timeout=3600
    )
    if out.returncode != 0:
        return {"error": out.stderr.strip().splitlines()[-1] if out.stderr.strip() else "failed"}
    return json.loads(out.stdout.strip().splitlines()[-1])


def main():
    if not DATA.is_dir():
        print("bench_embedding_ceres: ../shared/data not found, skipped")
        return
    if not TOOL.is_file():
        print(
            "bench_embedding_ceres: build/bin/hoembedEmbeddingCeres not built (no Ceres), skipped"
        )
        return
    names = sys.argv[1:] or SURFACES
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        tmp = pathlib.Path(tmp)
        for name in names:
            files = sorted(DATA.glob(name + ".*"))
            if not files:
                continue
            surface = pv.read(files[0]).triangulate().clean(tolerance=0.0)
            fe = hoembed.tet10_mesh(surface, n_elements=1000)
            surface.save(tmp / "surface.vtp")
            for label, mesh in (("tet10", fe), ("lagrange-tet-3", as_lagrange(fe, 3))):
                mesh.save(tmp / "mesh.vtu")
                row = {"surface": name, "mesh": label, **run(tmp / "surface.vtp", tmp / "mesh.vtu")}
                print(json.dumps(row), flush=True)
                rows.append(row)
    results = ROOT / "Benchmarks" / "results"
    results.mkdir(exist_ok=True)
    (results / "bench_embedding_ceres.json").write_text(json.dumps(rows, indent=1))


if __name__ == "__main__":
    main()
