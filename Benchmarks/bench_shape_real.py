"""Shape preservation on real meshes (the paper's Figs. 3-5, measured).

For each real surface (armadillo, scorpion, dragon from ../shared/data/meshes):
- a curved tet10 mesh of ~1000 elements and a tet4 mesh with about as many nodes
  (hoembed.tet10_mesh, order=1, more elements);
- the fine surface embedded: normal-offset in the tet10 mesh, barycentric in the tet4
  mesh, and barycentric in the same tet10 mesh (same FE deformation: isolates the mapping
  from the FE discretisation);
- a static co-rotated equilibrium under gravity with one part clamped (hoembed.simulate,
  nu = 0.49). Young's modulus is chosen so that the tet10 mesh's largest nodal
  displacement is TARGET_DISPLACEMENT of the surface's bounding-box diagonal. The tet4
  mesh locks (nu = 0.49), so, as the paper did, its load is raised: gravity is scaled until
  the tet4 mesh's largest nodal displacement matches the tet10 one (factor reported);
- the deformation transferred (hoembed.transfer).

Shape distortion (independent of the global motion): for every fine vertex, its one-ring
edge vectors before (e: the variant's own rest state, i.e. the surface transferred onto
the undeformed FE mesh, what it shows at t = 0) and after (e') are compared after
removing the best local rotation R (Kabsch / polar fit of sum e e'^T):
    distortion_i = sqrt(mean_j |R e_j - e'_j|^2) / sqrt(mean_j |e_j|^2)
(relative to the vertex's rest edge length (RMS over the one-ring), so a uniform scaling
by s reads |s - 1|; RMS, 95th percentile and max over the vertices reported), and
the normal change of every triangle: the angle between its deformed normal and its rest
normal rotated by R fitted on the union of its three vertices' one-rings.
The real elastic strain of the deformation contributes too (the same for all methods on
the same FE deformation); mapping artifacts (kinks at element boundaries, sheared
features outside the FE mesh) add to it. The same numbers measured from the input surface
instead (`vs_input_surface`) add the rest-state error of a mapping that does not
reproduce the input at rest (barycentric extrapolation on curved tet10 cells).

Accuracy against a finer simulation (`vs_fine_reference`): the distortion numbers above
cannot tell mapping artifacts from real strain, and tet4 and tet10 deform differently. So
the same body is also meshed with REFERENCE_FACTOR x as many tet10 elements, solved under
the same load as the ~1000-element tet10 mesh, and the fine surface carried by it (its
embedding distances are much smaller, so the mapping matters much less there) is the
reference. Each variant's deformed surface is compared with it: vertex position error
(RMS, p95, max, / bounding-box diagonal, and / the reference's largest displacement),
local shape error (the one-ring measure above, from the reference deformed surface to the
variant's) and triangle normal error. tet4 is compared twice: under the same load
(`tet4 + barycentric, same load`: the locking error included) and with its load raised
as above (`tet4 + barycentric`). The reference is built with both mappings
(normal-offset and barycentric on the fine mesh); their difference is reported as the
reference's own uncertainty (`reference_mapping_difference`).

Writes Benchmarks/results/bench_shape_real.json and, under a display (xvfb-run -a),
Benchmarks/results/bench_shape_real_<mesh>.png (tet4 + barycentric, tet10 + barycentric,
tet10 + normal-offset side by side, coloured by the local distortion). Prints the JSON.
Skips cleanly (exit 0, a note in the JSON) when the mesh folder is absent.

Usage: .venv/bin/python Benchmarks/bench_shape_real.py [mesh ...]
"""

import json
import os
import pathlib
import sys
import time

import hoembed
import numpy as np
import pyvista as pv

HERE = pathlib.Path(__file__).resolve().parent
RESULTS = HERE / "results"
MESH_DIR = HERE.parent.parent / "shared" / "data" / "meshes"

N_ELEMENTS = 1000  # tet10 elements
REFERENCE_FACTOR = 8  # the fine reference mesh has this many times more tet10 elements
TARGET_DISPLACEMENT = 0.10  # largest tet10 nodal displacement / bbox diagonal
NU, RHO, G = 0.49, 1000.0, 9.81
FAR = 0.01  # "far outside": closest distance to the FE mesh > FAR * diagonal

# Which part is clamped (nodes within `fraction` of the extent from one end of `axis`)
# and where gravity points, per mesh (the models' own frames: y is up in all three).
CASES = {
    "armadillo": dict(
        axis=1,
        side="min",
        fraction=0.12,
        gravity=(0.0, 0.0, -1.0),
        view=((1.0, 0.3, 0.4), (0.0, 1.0, 0.0)),
        what="feet clamped (lowest 12% in y), gravity along -z: the body leans forward",
    ),
    "scorpion_low_resolution": dict(
        axis=1,
        side="min",
        fraction=0.10,
        gravity=(0.0, -1.0, 0.0),
        view=((1.0, 0.5, 0.6), (0.0, 1.0, 0.0)),
        what="legs clamped (lowest 10% in y), gravity along -y: the raised tail and claws sag",
    ),
    "dragon": dict(
        axis=2,
        side="min",
        fraction=0.15,
        gravity=(0.0, -1.0, 0.0),
        view=((1.0, 0.3, 0.1), (0.0, 1.0, 0.0)),
        what="one end clamped (lowest 15% in z), gravity along -y: a cantilever",
    ),
}

# (label, FE mesh, embedding method, normals mode of the transfer)
VARIANTS = [
    ("tet4 + barycentric", "tet4", "barycentric", "recompute"),
    ("tet10 + barycentric", "tet10", "barycentric", "recompute"),
    ("tet10 + normal-offset", "tet10", "normal-offset", "recompute"),
    ("tet10 + normal-offset, deformed normals", "tet10", "normal-offset", "deform"),
]


# ---------------------------------------------------------------- shape distortion


def triangles_of(surface):
    faces = np.asarray(surface.faces).reshape(-1, 4)
    if not np.all(faces[:, 0] == 3):
        raise ValueError("the surface must be triangles only")
    return faces[:, 1:].astype(np.int64)


def directed_edges(tris):
    e = np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]])
    e = np.unique(np.sort(e, axis=1), axis=0)
    return np.concatenate([e, e[:, ::-1]])  # (i, j): j in the one-ring of i


def best_rotations(H):
    """R (n, 3, 3) minimising sum |R a - b|^2 for H = sum a b^T (Kabsch, det R = +1)."""
    U, _, Vt = np.linalg.svd(H)
    V = np.transpose(Vt, (0, 2, 1))
    d = np.sign(np.linalg.det(V @ np.transpose(U, (0, 2, 1))))
    d[d == 0] = 1.0
    D = np.zeros_like(H)
    D[:, 0, 0] = 1.0
    D[:, 1, 1] = 1.0
    D[:, 2, 2] = d
    return V @ D @ np.transpose(U, (0, 2, 1))


def unit_normals(points, tris):
    n = np.cross(points[tris[:, 1]] - points[tris[:, 0]], points[tris[:, 2]] - points[tris[:, 0]])
    length = np.linalg.norm(n, axis=1)
    return n / np.where(length > 0, length, 1.0)[:, None], length > 0


class ShapeDistortion:
    """Local shape distortion of a deformed copy of a rest triangle surface."""

    def __init__(self, rest_points, tris):
        self.x = np.asarray(rest_points, dtype=float)
        self.tris = tris
        self.edges = directed_edges(tris)
        i, j = self.edges[:, 0], self.edges[:, 1]
        self.a = self.x[j] - self.x[i]
        n = len(self.x)
        self.degree = np.bincount(i, minlength=n)
        self.used = self.degree > 0
        deg = np.maximum(self.degree, 1)
        # RMS rest edge length of the one-ring: a uniform scaling by s then reads |s - 1|
        self.edge_scale = np.sqrt(
            np.bincount(i, weights=np.einsum("ea,ea->e", self.a, self.a), minlength=n) / deg
        )
        self.rest_normals, self.good_tris = unit_normals(self.x, tris)

    def __call__(self, deformed_points):
        y = np.asarray(deformed_points, dtype=float)
        i, j = self.edges[:, 0], self.edges[:, 1]
        b = y[j] - y[i]
        n = len(self.x)
        H = np.zeros((n, 3, 3))
        outer = np.einsum("ea,eb->eab", self.a, b)
        for r in range(3):
            for c in range(3):
                H[:, r, c] = np.bincount(i, weights=outer[:, r, c], minlength=n)
        R = best_rotations(H)
        res = np.einsum("eab,eb->ea", R[i], self.a) - b
        deg = np.maximum(self.degree, 1)
        msq = np.bincount(i, weights=np.einsum("ea,ea->e", res, res), minlength=n) / deg
        scale = np.where(self.edge_scale > 0, self.edge_scale, 1.0)
        vertex = np.sqrt(msq) / scale
        vertex[~self.used] = 0.0
        Rt = best_rotations(H[self.tris].sum(axis=1))
        dn, ok = unit_normals(y, self.tris)
        cosang = np.einsum("ta,ta->t", np.einsum("tab,tb->ta", Rt, self.rest_normals), dn)
        angle = np.degrees(np.arccos(np.clip(cosang, -1.0, 1.0)))
        angle[~(ok & self.good_tris)] = 0.0
        return vertex, angle


def summary(values, mask=None):
    v = values if mask is None else values[mask]
    if v.size == 0:
        return None
    return {
        "rms": float(np.sqrt(np.mean(v**2))),
        "p95": float(np.percentile(v, 95)),
        "max": float(v.max()),
    }


# ---------------------------------------------------------------- pipeline pieces


def cells_without_face_neighbour(mesh):
    """Ids of cells that share no corner face with another cell (attached to the rest by
    an edge or a node at most: a zero-energy hinge mode)."""
    npc = 10 if mesh.celltypes[0] == pv.CellType.QUADRATIC_TETRA else 4
    corners = np.asarray(mesh.cells).reshape(-1, npc + 1)[:, 1:5]
    faces = np.concatenate(
        [np.sort(corners[:, f], axis=1) for f in ([0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3])]
    )
    _, inverse, counts = np.unique(faces, axis=0, return_inverse=True, return_counts=True)
    shared = (counts[inverse.reshape(-1)] > 1).reshape(4, -1).any(axis=0)
    return np.flatnonzero(~shared).tolist() if len(corners) > 1 else []


def timed(fn, *args, **kw):
    t0 = time.perf_counter()
    out = fn(*args, **kw)
    return out, time.perf_counter() - t0


def clamp_mask(mesh, case):
    pts = np.asarray(mesh.points)
    ax = case["axis"]
    lo, hi = pts[:, ax].min(), pts[:, ax].max()
    cut = case["fraction"] * (hi - lo)
    mask = pts[:, ax] <= lo + cut if case["side"] == "min" else pts[:, ax] >= hi - cut
    return mask.astype(np.uint8)


def static_solve(mesh, mask, young, gravity_scale, case):
    g = tuple(G * gravity_scale * c for c in case["gravity"])
    frame = hoembed.simulate(
        mesh, young=young, poisson=NU, density=RHO, gravity=g, fixed=mask, static=True
    )[0]
    return frame, float(np.linalg.norm(frame.point_data["Displacement"], axis=1).max())


def matched_solve(mesh, mask, young, case, target, scale0=1.0, tries=4):
    """Scale gravity until the largest nodal displacement is `target` (within 2%).
    Small loads: displacement ~ load; the co-rotated response is mildly nonlinear, so a few
    secant steps on the scale."""
    scale = scale0
    history = []
    frame, umax = static_solve(mesh, mask, young, scale, case)
    history.append((scale, umax))
    for _ in range(tries):
        if abs(umax / target - 1.0) < 0.02:
            break
        if len(history) >= 2 and history[-1][1] != history[-2][1]:
            (s0, u0), (s1, u1) = history[-2], history[-1]
            scale = s1 + (target - u1) * (s1 - s0) / (u1 - u0)
        else:
            scale = scale * target / umax
        frame, umax = static_solve(mesh, mask, young, scale, case)
        history.append((scale, umax))
    return frame, umax, scale, history


def run_case(name, case, render):
    path = MESH_DIR / f"{name}.obj"
    surface = pv.read(str(path)).triangulate()
    x = np.asarray(surface.points, dtype=float)
    tris = triangles_of(surface)
    diag = float(np.linalg.norm(x.max(axis=0) - x.min(axis=0)))
    out = {
        "surface": {
            "file": path.name,
            "points": int(surface.n_points),
            "triangles": int(surface.n_cells),
            "bbox_diagonal": diag,
        },
        "load_case": case["what"],
        "seconds": {},
    }
    sec = out["seconds"]

    notes = out.setdefault("notes", [])

    def fe_mesh(n, order, what):
        """hoembed.tet10_mesh; a mesh with a cell that shares no face with the rest (a
        hinge: singular stiffness) is remeshed with 3% more elements (noted)."""
        t = 0.0
        for _ in range(4):
            mesh, dt = timed(hoembed.tet10_mesh, surface, n_elements=n, order=order)
            t += dt
            bad = cells_without_face_neighbour(mesh)
            if not bad:
                return mesh, t
            notes.append(
                f"{what} mesh for n_elements={n}: {len(bad)} cell(s) sharing no face "
                f"with any other cell (e.g. cell {bad[0]}): remeshed"
            )
            n = int(round(n * 1.03))
        raise RuntimeError(f"{what} mesh: cells attached by less than a face")

    mesh10, sec["mesh_tet10"] = fe_mesh(N_ELEMENTS, 2, "tet10")
    # tet4 with about as many nodes: a tet4 mesh has ~ n_cells / 3 to / 4 nodes, a tet10
    # one ~ 2 n_cells; guess, then correct once by the node ratio.
    guess = int(7.0 * mesh10.n_cells)
    mesh4, t4 = fe_mesh(guess, 1, "tet4")
    ratio = mesh10.n_points / mesh4.n_points
    if abs(ratio - 1.0) > 0.15:
        mesh4, t4b = fe_mesh(int(guess * ratio), 1, "tet4")
        t4 += t4b
    sec["mesh_tet4"] = t4
    meshes = {"tet10": mesh10, "tet4": mesh4}
    out["fe_meshes"] = {
        k: {"cells": int(m.n_cells), "nodes": int(m.n_points), "dof": 3 * int(m.n_points)}
        for k, m in meshes.items()
    }

    embedded = {}
    for label, kind, method, _ in VARIANTS:
        if (kind, method) not in embedded:
            embedded[kind, method], sec[f"embed {kind} {method}"] = timed(
                hoembed.embed, surface, meshes[kind], method=method
            )

    # Loads: Young's modulus from a probe solve of the tet10 mesh (linear regime), then
    # gravity scaled on each mesh to hit the target displacement exactly.
    masks = {k: clamp_mask(m, case) for k, m in meshes.items()}
    target = TARGET_DISPLACEMENT * diag
    t0 = time.perf_counter()
    probe_e = 1.0e9
    _, u_probe = static_solve(mesh10, masks["tet10"], probe_e, 1.0, case)
    young = probe_e * u_probe / target
    frame10, u10, s10, hist10 = matched_solve(mesh10, masks["tet10"], young, case, target)
    frame4_same, u4_same = static_solve(mesh4, masks["tet4"], young, s10, case)
    frame4, u4, s4, hist4 = matched_solve(
        mesh4, masks["tet4"], young, case, u10, scale0=s10 * u10 / u4_same
    )
    sec["simulate (static, all solves)"] = time.perf_counter() - t0
    frames = {"tet10": frame10, "tet4": frame4}
    out["load"] = {
        "young_modulus": young,
        "poisson": NU,
        "density": RHO,
        "gravity_direction": list(case["gravity"]),
        "clamped_nodes": {k: int(m.sum()) for k, m in masks.items()},
        "target_max_displacement_rel_diag": TARGET_DISPLACEMENT,
        "tet10_gravity": G * s10,
        "tet10_max_displacement_rel_diag": u10 / diag,
        "tet4_max_displacement_same_load_rel_diag": u4_same / diag,
        "tet4_gravity": G * s4,
        "tet4_load_factor": s4 / s10,
        "tet4_max_displacement_rel_diag": u4 / diag,
        "secant_history": {"tet10": hist10, "tet4": hist4},
        "note": "tet4 locks at nu = 0.49: its gravity is raised by tet4_load_factor so that "
        "its largest nodal displacement equals the tet10 one (as the paper raised "
        "the force on its linear meshes)",
    }

    from_input = ShapeDistortion(x, tris)
    out["variants"] = {}
    deformed, fields = {}, {}
    for label, kind, method, normals in VARIANTS:
        emb = embedded[kind, method]
        warn = []
        rest, _ = timed(hoembed.transfer, emb, meshes[kind])
        moved, sec[f"transfer {label}"] = timed(
            hoembed.transfer, emb, frames[kind], normals=normals, warnings=warn
        )
        r0 = np.asarray(rest.points, dtype=float)
        y = np.asarray(moved.points, dtype=float)
        # the deformation's distortion: from this variant's own rest state (what it shows
        # at t = 0) to the deformed state
        from_rest = ShapeDistortion(r0, tris)
        vd, na = from_rest(y)
        vd_in, na_in = from_input(y)
        vd_rest, na_rest = from_input(r0)
        closest = np.asarray(emb.point_data["EmbeddingClosestDistance"])
        outside = closest > 1e-9 * diag
        far = closest > FAR * diag
        outside_t = outside[tris].any(axis=1)
        used, good = from_input.used, from_input.good_tris
        disp = np.linalg.norm(y - r0, axis=1)
        resid = np.asarray(emb.point_data["EmbeddingResidual"])
        out["variants"][label] = {
            "fe": kind,
            "mapping": method,
            "max_embedding_residual_rel_diag": float(resid.max() / diag),
            "vertices_with_residual_above_1e-8_diag": int((resid > 1e-8 * diag).sum()),
            "identity_transfer_max_error_rel_diag": float(np.abs(r0 - x).max() / diag),
            "vertices_outside_fe_mesh": int(outside.sum()),
            "surface_max_displacement_rel_diag": float(disp.max() / diag),
            "surface_rms_displacement_rel_diag": float(np.sqrt(np.mean(disp**2)) / diag),
            "local_distortion_rel_edge": summary(vd[used]),
            "local_distortion_rel_edge_outside_vertices": summary(vd, outside & used),
            "vertices_far_outside": int(far.sum()),
            "local_distortion_rel_edge_far_vertices": summary(vd, far & used),
            "normal_change_deg": summary(na[good]),
            "normal_change_deg_outside_triangles": summary(na, outside_t & good),
            "vs_input_surface": {
                "local_distortion_rel_edge": summary(vd_in[used]),
                "normal_change_deg": summary(na_in[good]),
                "rest_state_local_distortion_rel_edge": summary(vd_rest[used]),
                "rest_state_normal_change_deg": summary(na_rest[good]),
            },
            "transfer_warnings": warn,
        }
        deformed[label] = moved
        fields[label] = vd
    ref = out["variants"]["tet10 + normal-offset"]
    out["ratios_vs_tet10_normal_offset"] = {
        label: {
            f"{q} {s}": v[q][s] / ref[q][s] if ref[q][s] > 0 else None
            for q in ("local_distortion_rel_edge", "normal_change_deg")
            for s in ("rms", "p95")
        }
        for label, v in out["variants"].items()
        if label != "tet10 + normal-offset"
    }

    runs = [
        (label, embedded[kind, method], frames[kind], normals)
        for label, kind, method, normals in VARIANTS
    ]
    runs.append(
        ("tet4 + barycentric, same load", embedded["tet4", "barycentric"], frame4_same, "recompute")
    )
    ref_fields, out["vs_fine_reference"] = fine_reference(
        surface, case, young, s10, fe_mesh, runs, diag, sec
    )

    if render:
        try:
            out["picture"] = str(picture(name, surface, deformed, fields, ref_fields, frames, out))
        except Exception as exc:  # rendering problems must not lose the numbers
            out["picture"] = f"not rendered: {exc}"
    return out


def fine_reference(surface, case, young, gravity_scale, fe_mesh, runs, diag, sec):
    """Compare each variant's deformed surface with the surface carried by a simulation on
    a REFERENCE_FACTOR x finer tet10 mesh under the same load (see the module docstring)."""
    ref_mesh, sec["mesh_reference"] = fe_mesh(REFERENCE_FACTOR * N_ELEMENTS, 2, "reference")
    t0 = time.perf_counter()
    ref_frame, u_ref = static_solve(
        ref_mesh, clamp_mask(ref_mesh, case), young, gravity_scale, case
    )
    sec["simulate reference (static)"] = time.perf_counter() - t0
    ref_surfaces = {}
    for method in ("normal-offset", "barycentric"):
        emb = hoembed.embed(surface, ref_mesh, method=method)
        ref_surfaces[method] = np.asarray(hoembed.transfer(emb, ref_frame).points, dtype=float)
    y_ref = ref_surfaces["normal-offset"]
    tris = triangles_of(surface)
    shape = ShapeDistortion(y_ref, tris)

    fields = {}

    def compare(y, label=None):
        err = np.linalg.norm(y - y_ref, axis=1)
        vd, na = shape(y)
        if label:
            fields[label] = vd
        return {
            "position_error_rel_diag": summary(err / diag),
            "position_error_rel_max_displacement": summary(err / u_ref),
            "local_shape_error_rel_edge": summary(vd[shape.used]),
            "normal_error_deg": summary(na[shape.good_tris]),
        }

    variants = {}
    for label, emb, frame, normals in runs:
        y = np.asarray(hoembed.transfer(emb, frame, normals=normals).points, dtype=float)
        variants[label] = compare(y, label)
    return fields, {
        "reference_mesh": {
            "cells": int(ref_mesh.n_cells),
            "nodes": int(ref_mesh.n_points),
            "dof": 3 * int(ref_mesh.n_points),
        },
        "reference_max_displacement_rel_diag": u_ref / diag,
        "reference_mapping_difference": compare(ref_surfaces["barycentric"]),
        "variants": variants,
        "ratios_vs_tet10_normal_offset": {
            label: {
                q: v[q]["rms"] / variants["tet10 + normal-offset"][q]["rms"]
                for q in (
                    "position_error_rel_diag",
                    "local_shape_error_rel_edge",
                    "normal_error_deg",
                )
            }
            for label, v in variants.items()
            if label != "tet10 + normal-offset"
        },
    }


def picture(name, surface, deformed, fields, ref_fields, frames, out):
    """Three views side by side, same camera, two rows: the deformed surface coloured by
    the local distortion from its rest state (top; real strain included) and by the local
    shape error against the fine reference simulation (bottom); the deformed FE mesh's
    edges faintly, and the rest surface as a ghost."""
    pv.OFF_SCREEN = True
    rows = [
        (
            "distortion",
            fields,
            "local_distortion_rel_edge",
            "distortion / edge",
            lambda label: out["variants"][label],
        ),
        (
            "shape error vs fine reference",
            ref_fields,
            "local_shape_error_rel_edge",
            "shape error / edge",
            lambda label: out["vs_fine_reference"]["variants"][label],
        ),
    ]
    pl = pv.Plotter(
        off_screen=True, shape=(2, len(VARIANTS)), window_size=(3200, 1600), border=False
    )
    view, up = CASES[name]["view"]
    for row, (what, values, key, bar, stats) in enumerate(rows):
        # colour range from the two methods the paper compares (tet10 + barycentric, with
        # its rest-state error, saturates)
        clim = [
            0.0,
            max(
                float(np.percentile(values[label], 99.0))
                for label in ("tet4 + barycentric", "tet10 + normal-offset")
            ),
        ]
        for col, (label, kind, _, _) in enumerate(VARIANTS):
            pl.subplot(row, col)
            s = deformed[label].copy()
            s.clear_data()
            s.point_data[what] = values[label]
            pl.add_mesh(surface, color="white", opacity=0.12)
            pl.add_mesh(
                s,
                scalars=what,
                clim=clim,
                cmap="inferno",
                smooth_shading=True,
                show_scalar_bar=(col == len(VARIANTS) - 1),
                scalar_bar_args=dict(title=bar, n_labels=4, fmt="%.3f", position_x=0.25, width=0.5),
            )
            pl.add_mesh(
                frames[kind].extract_all_edges(), color="steelblue", opacity=0.08, line_width=1
            )
            st = stats(label)[key]
            fe = out["fe_meshes"][kind]
            pl.add_text(
                f"{label} ({fe['cells']} cells, {fe['nodes']} nodes)\n"
                f"{what}: RMS {st['rms']:.4f}, p95 {st['p95']:.4f}",
                font_size=10,
            )
            pl.view_vector(view, viewup=up)
            pl.reset_camera()
            pl.camera.zoom(1.25)
    pl.link_views()
    path = RESULTS / f"bench_shape_real_{name}.png"
    pl.screenshot(str(path))
    pl.close()
    return path


def main(names=None):
    names = names or list(CASES)
    RESULTS.mkdir(exist_ok=True)
    result = {
        "setting": {
            "tet10_elements_target": N_ELEMENTS,
            "poisson": NU,
            "target_max_displacement_rel_diag": TARGET_DISPLACEMENT,
            "solve": "static co-rotated equilibrium (hoembed.simulate(static=True))",
            "metrics": {
                "local_distortion_rel_edge": "per fine vertex: RMS over its one-ring edges of "
                "|R e - e'| after the best local rotation R "
                "(Kabsch), / the RMS length of those rest edges; "
                "rest = the variant's own transfer onto the "
                "undeformed FE mesh",
                "normal_change_deg": "per fine triangle: angle between the deformed normal and "
                "the rest normal rotated by the rotation fitted on its "
                "three vertices' one-rings",
                "vs_input_surface": "the same from the input surface (adds the rest-state error)",
                "vs_fine_reference": f"errors against the fine surface carried by a "
                f"{REFERENCE_FACTOR}x finer tet10 simulation under the "
                "same load: vertex positions, one-ring shape (as above, "
                "from the reference to the variant), triangle normals",
                "outside": "vertices whose closest point on their FE mesh is at a positive "
                "distance (not inside the FE mesh); triangles with such a vertex",
                "far": f"vertices farther than {FAR} x the bounding-box diagonal from their FE "
                "mesh (surface detail the FE mesh does not cover)",
            },
        },
        "meshes": {},
    }
    if not MESH_DIR.is_dir():
        result["skipped"] = f"mesh folder {MESH_DIR} absent"
        print(json.dumps(result, indent=2))
        return result
    render = bool(os.environ.get("DISPLAY"))
    if not render:
        result["setting"]["picture"] = "not rendered: no display (run under xvfb-run -a)"
    t0 = time.perf_counter()
    for name in names:
        if not (MESH_DIR / f"{name}.obj").is_file():
            result["meshes"][name] = {"skipped": "file absent"}
            continue
        print(f"[bench_shape_real] {name} ...", file=sys.stderr, flush=True)
        try:
            result["meshes"][name] = run_case(name, CASES[name], render)
        except (hoembed.HOEmbedError, RuntimeError) as exc:
            result["meshes"][name] = {"failed": str(exc)}
    result["seconds_total"] = time.perf_counter() - t0
    (RESULTS / "bench_shape_real.json").write_text(json.dumps(result, indent=2))
    print(json.dumps(result, indent=2))
    return result


if __name__ == "__main__":
    main(sys.argv[1:])
