"""Reference outputs of the VTK build (Debian VTK 9.1, vtkEmbeddingCoordinatesFilter and
vtkDeformationTransferFilter) for the pip package's tests (test_pip.py).

Run with the VTK build's Python (`.venv/bin/python`, `make test-pip` does):
    generate_reference.py OUTDIR
It writes, per case, the inputs (surface.vtp, mesh.vtu, deformed_<k>.vtu) and the
filters' outputs (embedded_<method>.vtp, transferred_<mode>_<k>.vtp) as binary VTK XML
(exact doubles), and cases.json. Cases: the built-in thorny tail meshed with tet10 and
tet4; bunny_lowres.obj from HOEMBED_DATA_DIR when that folder exists.
"""
import json
import os
import sys

import numpy as np
import pyvista

import hoembed


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


def main(outdir):
    os.makedirs(outdir, exist_ok=True)
    cases = {}
    tail = hoembed.thorny_tail()
    inputs = [("tail_tet10", tail, dict(n_elements=300)),
              ("tail_tet4", tail, dict(n_elements=300, order=1))]
    data = os.environ.get("HOEMBED_DATA_DIR", "")
    bunny = os.path.join(data, "bunny_lowres.obj")
    if data and os.path.exists(bunny):
        inputs.append(("bunny_tet10", pyvista.read(bunny), dict(n_elements=500)))
    for name, surface, opts in inputs:
        d = os.path.join(outdir, name)
        os.makedirs(d, exist_ok=True)
        mesh = hoembed.tet10_mesh(surface, **opts)
        surface.save(os.path.join(d, "surface.vtp"))
        mesh.save(os.path.join(d, "mesh.vtu"))
        info = {"methods": [], "frames": 0, "modes": ["recompute", "rotate", "deform"]}
        for method in ("normal-offset", "barycentric"):
            emb = hoembed.embed(surface, mesh, method=method)
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
                out = hoembed.transfer(emb, deformed, normals=mode,
                                       compute_point_normals=(mode == "recompute"))
                out.save(os.path.join(d, f"transferred_{mode}_{k}.vtp"))
            info["frames"] = k + 1
        cases[name] = info
        print(f"[reference] {name}: {surface.n_points} surface points, {mesh.n_cells} cells")
    with open(os.path.join(outdir, "cases.json"), "w") as f:
        json.dump(cases, f, indent=1)


if __name__ == "__main__":
    main(sys.argv[1])
