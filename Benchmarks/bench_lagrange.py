"""Throughput of the embedding and the transfer on VTK_LAGRANGE_TETRAHEDRON meshes of
order 2 (the tet10 path), 3 and 4, against VTK's own vtkProbeFilter on the same cells and
points, measured in the same run (the machine is shared: compare the ratios).

Mesh: the curved Kuhn box of Testing/Python/test_lagrange.py (n^3 unit cubes, 6 n^3
cells); surface: a sphere through the box (inside and outside points). Embedding: the
best of 3 calls of hoembed.embed (mesh preparation included); vtkProbeFilter: the best of
3 Updates (a vtkStaticCellLocator built in each; inside points only get values);
transfer: the best of 3 calls of hoembed.transfer on a rigidly moved mesh. Then order 3
on boxes of 2-5 cubes a side (48-750 cells), the surface scaled with the box: the
embedding's speed against the mesh size. Prints JSON.
"""

import json
import pathlib
import sys
import time

import numpy as np
import pyvista as pv
import vtkmodules.vtkFiltersCore as fc

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / "Testing" / "Python"))
import hoembed  # noqa: E402
from test_lagrange import lagrange_box  # noqa: E402
from test_lagrange_hex import KINDS, hex_box  # noqa: E402


def best(f, repeat=3):
    t = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        f()
        t.append(time.perf_counter() - t0)
    return min(t)


def main(n=3, resolution=60):
    surface = pv.Sphere(
        radius=0.68 * n, center=(n / 2,) * 3, theta_resolution=resolution, phi_resolution=resolution
    )
    out = {"cubes_per_side": n, "surface_vertices": surface.n_points, "orders": {}}
    for order in (2, 3, 4):
        mesh = lagrange_box(order, n=n)
        if order == 2:  # the same cells as VTK_QUADRATIC_TETRA: the tet10 path
            mesh = pv.UnstructuredGrid(mesh.cells, np.full(mesh.n_cells, 24, np.uint8), mesh.points)
        t_embed = best(lambda: hoembed.embed(surface, mesh))
        embedded = hoembed.embed(surface, mesh)
        moved = mesh.copy()
        moved.points = mesh.points[:, [1, 0, 2]] * [1, -1, 1]  # a rotation by 90 degrees

        def probe():
            p = fc.vtkProbeFilter()
            p.SetInputData(surface)
            p.SetSourceData(mesh)
            p.Update()
            return p

        t_probe = best(probe)
        t_transfer = best(lambda: hoembed.transfer(embedded, moved))
        inside = int((embedded["EmbeddingClosestDistance"] == 0).sum())
        nv = surface.n_points
        out["orders"][order] = {
            "cells": mesh.n_cells,
            "inside_vertices": inside,
            "embed_vertices_per_s": nv / t_embed,
            "probe_vertices_per_s": nv / t_probe,
            "embed_over_probe_time": t_embed / t_probe,
            "transfer_vertices_per_s": nv / t_transfer,
            "max_residual_over_diagonal": float(embedded["EmbeddingResidual"].max() / mesh.length),
            "fallbacks": int(embedded["EmbeddingFallback"].sum()),
        }
        print(order, json.dumps(out["orders"][order]), flush=True)
    print(json.dumps(out, indent=1))
    return out


def mesh_size(order=3, sizes=(2, 3, 4, 5), resolution=60, hexahedron=None):
    """Embedding time of the same surface (scaled with the box) against the number of
    cells: the per-vertex search should barely depend on it. `hexahedron`: a kind of
    test_lagrange_hex.KINDS instead of the Lagrange tets of `order`."""
    rows = []
    for n in sizes:
        mesh = hex_box(hexahedron, n=n) if hexahedron else lagrange_box(order, n=n)
        surface = pv.Sphere(
            radius=0.68 * n,
            center=(n / 2,) * 3,
            theta_resolution=resolution,
            phi_resolution=resolution,
        )
        t = best(lambda: hoembed.embed(surface, mesh))
        # the search alone: the filter keeps its prepared mesh (ReuseMeshPreparation) and
        # re-embeds the surface, marked modified
        f = hoembed.vtkEmbeddingCoordinatesFilter()
        f.SetInputData(0, surface)
        f.SetMeshData(mesh)
        f.Update()

        def search():
            surface.GetPoints().Modified()
            f.Update()

        t_search = best(search)
        rows.append(
            {
                "cubes_per_side": n,
                "cells": mesh.n_cells,
                "vertices_per_s": surface.n_points / t,
                "search_vertices_per_s": surface.n_points / t_search,
            }
        )
        print(json.dumps(rows[-1]), flush=True)
    return rows


def hexahedra(n=3, resolution=60):
    """The hexahedra (Lagrange order 1-3, hex27, hex20) on the same box and sphere, with
    Lagrange tets of order 3 as the peer measured in the same run."""
    surface = pv.Sphere(
        radius=0.68 * n, center=(n / 2,) * 3, theta_resolution=resolution, phi_resolution=resolution
    )
    rows = {}
    meshes = {kind: hex_box(kind, n=n) for kind in KINDS}
    meshes["lagrange-tet-3"] = lagrange_box(3, n=n)
    for kind, mesh in meshes.items():
        t_embed = best(lambda: hoembed.embed(surface, mesh))
        embedded = hoembed.embed(surface, mesh)
        moved = mesh.copy()
        moved.points = mesh.points[:, [1, 0, 2]] * [1, -1, 1]

        def probe():
            p = fc.vtkProbeFilter()
            p.SetInputData(surface)
            p.SetSourceData(mesh)
            p.Update()
            return p

        t_probe = best(probe)
        t_transfer = best(lambda: hoembed.transfer(embedded, moved))
        nv = surface.n_points
        rows[kind] = {
            "cells": mesh.n_cells,
            "embed_vertices_per_s": nv / t_embed,
            "probe_vertices_per_s": nv / t_probe,
            "embed_over_probe_time": t_embed / t_probe,
            "transfer_vertices_per_s": nv / t_transfer,
            "max_residual_over_diagonal": float(embedded["EmbeddingResidual"].max() / mesh.length),
            "fallbacks": int(embedded["EmbeddingFallback"].sum()),
        }
        print(kind, json.dumps(rows[kind]), flush=True)
    return rows


if __name__ == "__main__":
    if sys.argv[1:] == ["hexahedra"]:
        hexahedra()
        mesh_size(sizes=(2, 4, 6, 8), hexahedron="lagrange-2")
        sys.exit(0)
    main()
    mesh_size()
    hexahedra()
