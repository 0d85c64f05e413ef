"""Shape preservation of the deformation transfer (the paper's Figs. 3-5 as numbers).

A beam FE mesh carries a fine surface with thorns. A smooth deformation phi of all of
space (twist about the beam axis, then bend onto an arc) moves the FE nodes; the fine
surface is transferred and compared with phi applied to each fine vertex directly:
position error (RMS, max) and the angle between transferred and exact triangle normals,
for a bend, a twist and both.

Variants (all on the same fine surface):
- normal-offset on tet10 (8x4x4 cubes of 6 Kuhn tets: 768 cells, 17*9*9 = 1377 nodes),
- barycentric on the same tet10 mesh,
- barycentric on tet4 with the same number of nodes (16x8x8 cubes: 6144 cells, 1377
  nodes),
- normal-offset on that tet4 mesh (for reference),
- normal-offset on tet10 with the other two nodal-normal modes of
  vtkDeformationTransferFilter: "rotate" (rest normals rotated by `NodalRotation`, here the
  polar rotation of D phi at each node, as an ideal stepper would give) and "deform" (rest
  normals pushed forward by the nodal deformation gradient of the FE mesh).

A twist shears the surface layer: phi tilts the lines that were normal to the rest
surface, so the thorns lean. The paper's normal-offset (recomputed normals) keeps them
normal to the deformed surface, so its error has a floor that no FE resolution removes
(`normal_offset_model_floor`: phi(p) + d n_exact); the "deform" mode follows the material
lines and has no such floor.

The embeddings are built analytically (Benchmarks/thorny_beam.py: orthogonal projection on
a straight box mesh, exact), or with vtkEmbeddingCoordinatesFilter (hoembed.embed) when
run with --embedding-filter (results then in bench_transfer_shape_filter.json).

Writes Benchmarks/results/bench_transfer_shape.json (and a .png picture when rendering
works) and prints the JSON.
"""

import json
import os
import pathlib
import sys

import numpy as np
import pyvista as pv

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import hoembed  # noqa: E402
import thorny_beam as tb  # noqa: E402

LENGTH, WIDTH = 8.0, 1.0
SIZE = (LENGTH, WIDTH, WIDTH)
RESULTS = pathlib.Path(__file__).resolve().parent / "results"


def triangle_normals(points, tris):
    n = np.cross(points[tris[:, 1]] - points[tris[:, 0]], points[tris[:, 2]] - points[tris[:, 0]])
    return n / np.linalg.norm(n, axis=1)[:, None]


def errors(out, exact, tris, thorn_vertex, thorn_tri, diag):
    e = np.linalg.norm(out - exact, axis=1)
    cosang = np.clip(
        np.einsum("ij,ij->i", triangle_normals(out, tris), triangle_normals(exact, tris)), -1.0, 1.0
    )
    ang = np.degrees(np.arccos(cosang))
    return {
        "rms_error": float(np.sqrt(np.mean(e**2))),
        "max_error": float(e.max()),
        "rms_error_thorns": float(np.sqrt(np.mean(e[thorn_vertex] ** 2))),
        "max_error_thorns": float(e[thorn_vertex].max()),
        "rms_error_rel_diag": float(np.sqrt(np.mean(e**2)) / diag),
        "max_error_rel_diag": float(e.max() / diag),
        "normal_rms_deg": float(np.sqrt(np.mean(ang**2))),
        "normal_max_deg": float(ang.max()),
        "normal_rms_deg_thorns": float(np.sqrt(np.mean(ang[thorn_tri] ** 2))),
        "normal_max_deg_thorns": float(ang[thorn_tri].max()),
    }


DEFORMATIONS = {
    "bend": dict(radius=3.0, twist=0.0),
    "strong bend": dict(radius=1.5, twist=0.0),
    "twist": dict(radius=float("inf"), twist=0.2),
    "bend+twist": dict(radius=3.0, twist=0.2),
}


def phi(x, radius, twist):
    return tb.bend_twist(x, LENGTH, WIDTH, radius=radius, twist=twist)


def normal_offset_floor(p, nrm, d, kw, eps=1e-6):
    """phi(p) + d * (unit normal of the exactly deformed surface at p): what an exact
    normal-offset transfer gives. Its distance to phi(p + d n) is the part of the
    normal-offset error that comes from the model (phi moving material normal lines off
    the surface normal, e.g. the shear of a twist), not from the FE approximation."""
    J = jacobians(p, kw, eps)  # J[i] = D phi at p_i
    n_def = np.einsum("ikj,ik->ij", np.linalg.inv(J), nrm)  # rows: J^-T n
    n_def /= np.linalg.norm(n_def, axis=1)[:, None]
    return phi(p, **kw) + d[:, None] * n_def


def jacobians(x, kw, eps=1e-6):
    """D phi at the points x (central differences), shape (n, 3, 3)."""
    return np.stack(
        [(phi(x + eps * e, **kw) - phi(x - eps * e, **kw)) / (2 * eps) for e in np.eye(3)], axis=2
    )


def deformed_mesh(mesh, kw):
    """The FE mesh moved by phi, with the point data a stepper gives: Displacement and
    NodalRotation (here the exact polar rotation of D phi at each node)."""
    x = np.asarray(mesh.points, dtype=float)
    out = mesh.copy()
    out.points = phi(x, **kw)
    U, _, Vt = np.linalg.svd(jacobians(x, kw))
    R = U @ Vt
    out.point_data["Displacement"] = np.asarray(out.points) - x
    out.point_data["NodalRotation"] = R.reshape(-1, 9)
    return out


# (label, embedding key, normals mode of the transfer)
TRANSFERS = [
    ("normal-offset tet10", "normal-offset tet10", "recompute"),
    ("barycentric tet10", "barycentric tet10", "recompute"),
    ("barycentric tet4", "barycentric tet4", "recompute"),
    ("normal-offset tet4", "normal-offset tet4", "recompute"),
    ("normal-offset tet10, rotated normals", "normal-offset tet10", "rotate"),
    ("normal-offset tet10, deformed normals", "normal-offset tet10", "deform"),
]


def main(spacing=0.0125, height=0.3, render=True, use_filter=False):
    v, p, nrm, d, tris = tb.thorny_beam_surface(LENGTH, WIDTH, spacing=spacing, height=height)
    thorn_vertex = d > 0
    thorn_tri = thorn_vertex[tris].any(axis=1)
    meshes = {
        "tet10": ((8, 4, 4), tb.box_mesh((8, 4, 4), SIZE, 2)),
        "tet4": ((16, 8, 8), tb.box_mesh((16, 8, 8), SIZE, 1)),
    }
    variants = [
        ("normal-offset", "tet10"),
        ("barycentric", "tet10"),
        ("barycentric", "tet4"),
        ("normal-offset", "tet4"),
    ]
    diag = float(np.linalg.norm(v.max(axis=0) - v.min(axis=0)))
    result = {
        "setting": {
            "beam": list(SIZE),
            "fine_vertices": int(len(v)),
            "fine_triangles": int(len(tris)),
            "thorn_vertices": int(thorn_vertex.sum()),
            "thorn_height": height,
            "thorns": "cones of radius 0.1, 2 rows per long face, pitch 0.25 (smaller than an "
            "element: tet10 cells span 1 x 0.25 x 0.25)",
            "deformations": {
                k: {"bend_radius": kw["radius"], "twist_rad_per_unit": kw["twist"]}
                for k, kw in DEFORMATIONS.items()
            },
            "meshes": {
                k: {"cubes": list(n), "cells": int(m.n_cells), "nodes": int(m.n_points)}
                for k, (n, m) in meshes.items()
            },
            "embedding": (
                "vtkEmbeddingCoordinatesFilter (hoembed.embed)"
                if use_filter
                else "analytic (orthogonal projection on a straight box mesh; thorns "
                "only over faces whose smooth normal is the exact face normal), "
                "not vtkEmbeddingCoordinatesFilter"
            ),
            "bbox_diagonal": diag,
        },
        "identity_error_rel_diag": {},
        "deformations": {},
    }
    surfaces = {}
    for method, kind in variants:
        n, mesh = meshes[kind]
        if use_filter:
            fine = pv.PolyData(
                v, faces=np.hstack([np.full((len(tris), 1), 3), tris]).ravel(), deep=True
            )
            surf = hoembed.embed(fine, mesh, method=method)
            result.setdefault("embedding_max_residual_rel_diag", {})[f"{method} {kind}"] = float(
                np.max(surf.point_data["EmbeddingResidual"]) / diag
            )
        else:
            surf = tb.embed(mesh, n, SIZE, v, p, nrm, d, tris, method)
        rest = hoembed.transfer(surf, mesh)
        result["identity_error_rel_diag"][f"{method} {kind}"] = float(
            np.abs(np.asarray(rest.points) - v).max() / diag
        )
        surfaces[f"{method} {kind}"] = (mesh, surf)
    outputs = {}
    for name, kw in DEFORMATIONS.items():
        exact = phi(v, **kw)
        res = {"variants": {}}
        moved = {key: deformed_mesh(mesh, kw) for key, (mesh, _) in surfaces.items()}
        for label, key, normals in TRANSFERS:
            warn = []
            out = np.asarray(
                hoembed.transfer(
                    surfaces[key][1], moved[key], normals=normals, warnings=warn
                ).points
            )
            if warn:
                raise RuntimeError(f"{label}: {warn}")
            outputs[(name, label)] = out
            res["variants"][label] = errors(out, exact, tris, thorn_vertex, thorn_tri, diag)
        floor = normal_offset_floor(p, nrm, d, kw)
        res["normal_offset_model_floor"] = errors(floor, exact, tris, thorn_vertex, thorn_tri, diag)
        ref = res["variants"]["normal-offset tet10"]
        res["ratios_vs_normal_offset_tet10"] = {
            k: {
                m: (s[m] / ref[m] if ref[m] > 0 else None)
                for m in (
                    "rms_error",
                    "max_error",
                    "max_error_thorns",
                    "normal_rms_deg",
                    "normal_max_deg",
                )
            }
            for k, s in res["variants"].items()
            if k != "normal-offset tet10"
        }
        result["deformations"][name] = res
    RESULTS.mkdir(exist_ok=True)
    if render and not os.environ.get("DISPLAY"):
        result["picture"] = "not rendered: no display (run under xvfb-run)"
    elif render:
        try:
            result["picture"] = str(
                picture(
                    v,
                    tris,
                    phi(v, **DEFORMATIONS["strong bend"]),
                    {k: outputs[("strong bend", k)] for k in surfaces},
                    RESULTS,
                )
            )
        except Exception as exc:  # rendering problems must not lose the numbers
            result["picture"] = f"not rendered: {exc}"
    path = RESULTS / (
        "bench_transfer_shape_filter.json" if use_filter else "bench_transfer_shape.json"
    )
    path.write_text(json.dumps(result, indent=2))
    print(json.dumps(result, indent=2))
    return result


def picture(v, tris, exact, outputs, folder):
    """The middle of the bent beam, coloured by the distance to phi(v), per variant."""
    import pyvista as pv

    keys = ["normal-offset tet10", "barycentric tet10", "barycentric tet4"]
    pl = pv.Plotter(off_screen=True, shape=(1, 3), window_size=(1800, 650))
    sel = (v[:, 0] > 3.0) & (v[:, 0] < 5.0)
    keep = sel[tris].all(axis=1)
    sub_faces = np.hstack([np.full((keep.sum(), 1), 3), tris[keep]]).ravel()
    clim = [0.0, max(float(np.linalg.norm(outputs[k] - exact, axis=1)[sel].max()) for k in keys)]
    for i, k in enumerate(keys):
        pl.subplot(0, i)
        m = pv.PolyData(outputs[k], faces=sub_faces, deep=True)
        m.point_data["error"] = np.linalg.norm(outputs[k] - exact, axis=1)
        pl.add_mesh(
            m,
            scalars="error",
            clim=clim,
            cmap="viridis",
            smooth_shading=False,
            show_scalar_bar=(i == 2),
        )
        pl.add_text(k, font_size=12)
        pl.view_xz()
        pl.camera.zoom(1.3)
    out = folder / "bench_transfer_shape.png"  # (same picture for both embeddings)
    pl.screenshot(str(out))
    pl.close()
    return out


if __name__ == "__main__":
    # --embedding-filter: embed with vtkEmbeddingCoordinatesFilter instead of analytically.
    main(use_filter="--embedding-filter" in sys.argv[1:])
