"""Reference outputs of the VTK build (Debian VTK 9.1, vtkEmbeddingCoordinatesFilter and
vtkDeformationTransferFilter) for the pip package's tests (test_pip.py).

Run with the VTK build's Python (`.venv/bin/python`, `make test-pip` does):
    generate_reference.py OUTDIR
It writes, per case, the inputs (surface.vtp, mesh.vtu, deformed_<k>.vtu) and the
filters' outputs (embedded_<method>.vtp, transferred_<mode>_<k>.vtp) as binary VTK XML
(exact doubles), simulate()'s signature and docstring (simulate_api.json), the stepper's frames (stepper_<run>_<i>.vtu of hoembed.simulate on the
runs STEPPER_RUNS describes, on stepper_mesh.vtu), cases.json, write_series outputs
(series/, series_reference.py) and transfer()'s checks on broken inputs
(transfer_checks/, transfer_checks_reference.py). Cases: the built-in thorny tail meshed
with tet10 and tet4; bunny_lowres.obj from HOEMBED_DATA_DIR when that folder exists. For
the mesher (test_pip_mesher.py): mesher/<case>/surface.vtp and mesh.vtu of the surfaces
mesher_cases() builds, mesher/bad_<case>.vtp of bad inputs, and mesher/mesher.json with
the VTK build's element counts, quality quantiles and error sentences.
"""

import inspect
import json
import os
import sys

import hoembed
import live_reference
import numpy as np
import pyvista
import series_reference

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Python"))
import filter_routes  # noqa: E402  (the filters' route: the references are the filters')
import transfer_checks_reference


def rotation(axis, angle):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k


def frames(mesh):
    """Deformed copies of the rest mesh: a rigid motion, and a bend with a twist; each
    with Displacement and NodalRotation (what the stepper writes) for rotate/deform."""
    X = np.asarray(mesh.points, float)
    c = X.mean(axis=0)
    L = float(np.ptp(X, axis=0).max())
    out = []
    R = rotation((1, 2, 3), 0.7)
    x = (X - c) @ R.T + c + np.array([0.3, -0.1, 0.2]) * L
    out.append((x, np.tile(R.reshape(1, 9), (len(X), 1))))
    s = (X[:, 0] - X[:, 0].min()) / max(np.ptp(X[:, 0]), 1e-300)
    x = X.copy()
    rots = np.empty((len(X), 9))
    for i in range(len(X)):
        Ri = rotation((1, 0, 0), 0.6 * s[i]) @ rotation((0, 0, 1), 0.3 * s[i])
        x[i] = c + Ri @ (X[i] - c) + np.array([0, 0, 0.05 * L * s[i] ** 2])
        rots[i] = Ri.reshape(9)
    out.append((x, rots))
    return out


def stepper_runs(mesh):
    """The stepper runs (simulate() keyword arguments; "@Name" = the point array Name of
    stepper_mesh.vtu): clamped by a plane under gravity, by a mask array with nodal forces
    and an initial velocity (lumped mass), the static solve, and prescribed motion (the
    free end's nodes pulled: one 3-vector reached in the first step, per-node targets at a
    speed limit, and the static solve with them)."""
    X = np.asarray(mesh.points, float)
    lo, hi = X.min(axis=0), X.max(axis=0)
    L = float((hi - lo).max())
    ax = int(np.argmax(hi - lo))  # clamped at one end of the longest extent
    axis = [float(i == ax) for i in range(3)]
    origin = [float(lo[i] + 0.15 * (hi[i] - lo[i])) if i == ax else 0.0 for i in range(3)]
    stepper = mesh.copy()
    s = (X[:, ax] - lo[ax]) / (hi[ax] - lo[ax])
    stepper.point_data["Clamp"] = (s >= 0.85).astype(np.int32)
    # nodal forces scaled with the volume (the thorny tail: L ~ 3.3), so that every mesh
    # bends moderately instead of blowing up
    w = (L / 3.3) ** 3
    stepper.point_data["Push"] = np.c_[50.0 * w * s, 0 * s, -20.0 * w * s**2]
    stepper.point_data["Spin"] = np.c_[-0.2 * L * s, 0 * s, 0.1 * L * s]
    stepper.point_data["Grab"] = (s <= 0.05).astype(np.int32)
    stepper.point_data["Pull"] = np.c_[0 * s, 0.04 * L * (1 - s), 0.08 * L * (1 - s)]
    runs = {
        "plane": dict(steps=6, dt=0.01, young=2e4, every=2, fixed={"plane": [origin, axis]}),
        "mask": dict(
            steps=5,
            dt=0.005,
            young=5e4,
            poisson=0.45,
            gravity=[-3.0, 0.0, 0.0],
            fixed="@Clamp",
            external_force="@Push",
            initial_velocity="@Spin",
            lumped_mass=True,
            rayleigh_mass=0.5,
        ),
        "static": dict(static=True, young=2e7, fixed={"plane": [origin, axis]}),
        # CG run far past its default stop (1e-4), so that the two builds' round-off cannot
        # end it at different iterates (test_pip.py, CG_PATH)
        "prescribed": dict(
            steps=4,
            dt=0.01,
            young=2e4,
            fixed="@Clamp",
            prescribed=["@Grab", [0.0, 0.0, 0.03 * L]],
            solver_tolerance=1e-10,
        ),
        "prescribed_speed": dict(
            steps=5,
            dt=0.01,
            young=2e4,
            gravity=[0.0, 0.0, 0.0],
            fixed="@Clamp",
            prescribed=["@Grab", "@Pull"],
            prescribed_speed_limit=0.02 * L / 0.01 / 2,
        ),
        "prescribed_static": dict(
            static=True, young=2e7, fixed="@Clamp", prescribed=["@Grab", "@Pull"]
        ),
    }
    return stepper, runs


def resolve(kwargs, mesh):
    """simulate()'s keyword arguments with "@Name" replaced by that point array's name
    (fixed) or values (others, and the parts of prescribed)."""

    def values(v):
        if isinstance(v, str) and v.startswith("@"):
            return np.asarray(mesh.point_data[v[1:]])
        return v

    out = {}
    for k, v in kwargs.items():
        if k == "prescribed":
            v = tuple(values(p) for p in v)
        elif k == "fixed" and isinstance(v, str) and v.startswith("@"):
            v = v[1:]
        else:
            v = values(v)
        out[k] = v
    return out


def mesher_cases(data_dir=""):
    """Surfaces for the wheel's mesher (name -> (surface, tet10_mesh keyword arguments)):
    closed, open with a hole, a sheet, overlapping parts, quads with polygon caps, strips,
    the thorny tail, and bunny_lowres.obj of data_dir when present."""
    sphere = pyvista.Sphere(theta_resolution=40, phi_resolution=40)
    s = pyvista.Sphere(theta_resolution=30, phi_resolution=30).triangulate()
    keep = np.where(s.cell_centers().points[:, 2] < 0.35)[0]
    holed = s.extract_cells(keep).extract_surface()
    sheet = pyvista.Plane(i_resolution=24, j_resolution=24).triangulate()
    sheet.points[:, 2] = 0.1 * np.sin(3 * sheet.points[:, 0])
    overlapping = pyvista.Sphere().merge(pyvista.Sphere(center=(0.3, 0, 0)))
    cylinder = pyvista.Cylinder(resolution=24, height=2.0, capping=True)  # quads + 24-gons
    strips = pyvista.Sphere(theta_resolution=30, phi_resolution=20).strip()
    cases = {
        "sphere": (sphere, dict(n_elements=300)),
        "open_with_hole": (holed, dict(n_elements=300)),
        "sheet": (sheet, dict(n_elements=300)),
        "overlapping": (overlapping, dict(n_elements=300)),
        "quads_polygons": (cylinder, dict(n_elements=300)),
        "strips": (strips, dict(n_elements=300)),
        "tail_tet4": (hoembed.thorny_tail(), dict(n_elements=300, order=1)),
        "tail_edge": (hoembed.thorny_tail(), dict(edge_length=0.4)),
    }
    bunny = os.path.join(data_dir, "bunny_lowres.obj") if data_dir else ""
    if bunny and os.path.exists(bunny):
        cases["bunny"] = (pyvista.read(bunny), dict(n_elements=500))
    return cases


def bad_mesher_inputs():
    """Bad inputs of the mesher: name -> surface."""
    nan = pyvista.Sphere()
    nan.points[7] = np.nan
    ids = pyvista.PolyData(np.asarray(pyvista.Sphere().points)[:10], np.array([3, 0, 1, 42]))
    return {
        "empty": pyvista.PolyData(),
        "nan": nan,
        "ids": ids,
        "lines": pyvista.Line(),
        "zero_area": pyvista.PolyData(np.zeros((3, 3)), np.array([3, 0, 1, 2])),
    }


def mesher_stats(mesh):
    q = np.asarray(mesh.cell_data["MinScaledJacobian"], float)
    return {
        "cells": int(mesh.n_cells),
        "points": int(mesh.n_points),
        "quantiles": [float(v) for v in mesh.field_data["MinScaledJacobianQuantiles"][0]],
        "min": float(q.min()),
        "median": float(np.median(q)),
        "envelope_offset": float(mesh.field_data["EnvelopeOffset"][0]),
    }


def write_mesher_references(outdir, data_dir):
    root = os.path.join(outdir, "mesher")
    os.makedirs(root, exist_ok=True)
    import inspect

    info = {
        "cases": {},
        "errors": {},
        "signature": str(inspect.signature(hoembed.tet10_mesh)),
        "doc": inspect.getdoc(hoembed.tet10_mesh),
    }
    for name, (surface, kwargs) in mesher_cases(data_dir).items():
        d = os.path.join(root, name)
        os.makedirs(d, exist_ok=True)
        surface.save(os.path.join(d, "surface.vtp"))
        surface = pyvista.read(os.path.join(d, "surface.vtp"))
        mesh = filter_routes.tet10_mesh(surface, **kwargs)
        mesh.save(os.path.join(d, "mesh.vtu"))
        info["cases"][name] = dict(kwargs=kwargs, **mesher_stats(mesh))
        print(f"[reference] mesher {name}: {surface.n_points} points, {mesh.n_cells} cells")
    for name, surface in bad_mesher_inputs().items():
        if surface.n_points:  # (the empty one is made again by the test)
            path = os.path.join(root, f"bad_{name}.vtp")
            surface.save(path)
            surface = pyvista.read(path)
        try:
            filter_routes.tet10_mesh(surface, n_elements=300)
            info["errors"][name] = None
        except hoembed.HOEmbedError as e:  # "vtkTet10Mesher (0x...): sentence"
            info["errors"][name] = str(e).split("): ", 1)[-1]
    with open(os.path.join(root, "mesher.json"), "w") as f:
        json.dump(info, f, indent=1)


def main(outdir):
    os.makedirs(outdir, exist_ok=True)
    cases = {}
    tail = hoembed.thorny_tail()
    inputs = [
        ("tail_tet10", tail, dict(n_elements=300)),
        ("tail_tet4", tail, dict(n_elements=300, order=1)),
    ]
    data = os.environ.get("HOEMBED_DATA_DIR", "")
    bunny = os.path.join(data, "bunny_lowres.obj")
    if data and os.path.exists(bunny):
        inputs.append(("bunny_tet10", pyvista.read(bunny), dict(n_elements=500)))
    for name, surface, opts in inputs:
        d = os.path.join(outdir, name)
        os.makedirs(d, exist_ok=True)
        mesh = filter_routes.tet10_mesh(surface, **opts)
        surface.save(os.path.join(d, "surface.vtp"))
        mesh.save(os.path.join(d, "mesh.vtu"))
        info = {"methods": [], "frames": 0, "modes": ["recompute", "rotate", "deform"]}
        for method in ("normal-offset", "barycentric"):
            emb = filter_routes.embed(surface, mesh, method=method)
            emb.save(os.path.join(d, f"embedded_{method}.vtp"))
            info["methods"].append(method)
        emb = pyvista.read(os.path.join(d, "embedded_normal-offset.vtp"))
        for k, (x, rots) in enumerate(frames(mesh)):
            deformed = mesh.copy()
            deformed.points = x
            deformed.point_data["Displacement"] = x - np.asarray(mesh.points, float)
            deformed.point_data["NodalRotation"] = rots
            deformed.save(os.path.join(d, f"deformed_{k}.vtu"))
            deformed = pyvista.read(os.path.join(d, f"deformed_{k}.vtu"))
            for mode in info["modes"]:
                out = filter_routes.transfer(
                    emb, deformed, normals=mode, compute_point_normals=(mode == "recompute")
                )
                out.save(os.path.join(d, f"transferred_{mode}_{k}.vtp"))
            info["frames"] = k + 1
        stepper, runs = stepper_runs(mesh)
        stepper.save(os.path.join(d, "stepper_mesh.vtu"))
        stepper = pyvista.read(os.path.join(d, "stepper_mesh.vtu"))
        info["stepper"] = {}
        for run, kwargs in runs.items():
            out = filter_routes.simulate(stepper, **resolve(kwargs, stepper))
            for i, frame in enumerate(out):
                frame.save(os.path.join(d, f"stepper_{run}_{i}.vtu"))
            info["stepper"][run] = dict(kwargs=kwargs, frames=len(out))
        cases[name] = info
        print(f"[reference] {name}: {surface.n_points} surface points, {mesh.n_cells} cells")
    with open(os.path.join(outdir, "cases.json"), "w") as f:
        json.dump(cases, f, indent=1)
    # simulate()'s signature and docstring in the VTK build, for the wheel's to equal
    with open(os.path.join(outdir, "simulate_api.json"), "w") as f:
        json.dump(
            dict(signature=str(inspect.signature(hoembed.simulate)), doc=hoembed.simulate.__doc__),
            f,
            indent=1,
        )
    series_reference.write(outdir)  # write_series of these cases' frames (series/)
    transfer_checks_reference.write(outdir)  # transfer()'s checks (transfer_checks/)
    live_reference.write(outdir)  # the live loop's scripted run (live.npz)
    write_mesher_references(outdir, data)


if __name__ == "__main__":
    main(sys.argv[1])
