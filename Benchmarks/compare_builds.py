"""Compare every output array of two HOEmbed builds, bitwise.

Dump the outputs of one build (run with that build's Python, or name it with --python):

    .venv/bin/python Benchmarks/compare_builds.py dump after.npz
    .venv/bin/python Benchmarks/compare_builds.py dump before.npz --python /work/main/.venv/bin/python

then compare two dumps:

    .venv/bin/python Benchmarks/compare_builds.py compare before.npz after.npz

A dump runs, on the built-in model and on real surfaces of ../shared/data/meshes (those
present), the mesher (tet10, and tet4 on the first surface), the embedding (normal-offset
and barycentric), the stepper (a few dynamic steps and a static solve) and the transfer
(recompute, rotate, deform) and saves every point, cell and field array plus points and
connectivity. Then the mesher's read step on surfaces given as they are (quads, polygons,
strips, float32 points; not cleaned first) and its error messages on bad inputs.
`compare` prints each array that differs (bit patterns, NaN included) or is
missing on one side, and exits 1 if any does.
"""

import argparse
import json
import os
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_DATA = os.path.normpath(os.path.join(HERE, "..", "..", "shared", "data", "meshes"))
# surface -> elements asked of the mesher (thin parts need more to mesh at all)
SURFACES = {
    "bunny_lowres.obj": 1,
    "fertility.obj": 1,
    "rocker-arm.obj": 1,
    "scorpion_low_resolution.obj": 3,
}


def _arrays(prefix, ds, out):
    """Every array of a VTK/pyvista dataset under prefix/..."""
    import pyvista
    from vtkmodules.util.numpy_support import vtk_to_numpy

    ds = pyvista.wrap(ds)
    out[f"{prefix}/points"] = np.array(ds.points)
    if isinstance(ds, pyvista.UnstructuredGrid):
        out[f"{prefix}/cells"] = np.array(ds.cells)
        out[f"{prefix}/celltypes"] = np.array(ds.celltypes)
    elif isinstance(ds, pyvista.PolyData):
        out[f"{prefix}/faces"] = np.array(ds.faces)
    for kind, data in (
        ("point", ds.GetPointData()),
        ("cell", ds.GetCellData()),
        ("field", ds.GetFieldData()),
    ):
        for i in range(data.GetNumberOfArrays()):
            arr = data.GetAbstractArray(i)
            name = arr.GetName()
            key = f"{prefix}/{kind}/{name}"
            if arr.IsA("vtkDataArray"):
                out[key] = vtk_to_numpy(arr).copy()
            else:  # string array: its values, joined
                out[key] = np.array([arr.GetValue(j) for j in range(arr.GetNumberOfValues())])


def _dump(path, data_dir, elements):
    import hoembed
    import pyvista

    out = {}
    cases = [("thorny", hoembed.thorny_tail(rings=120, sectors=48), elements)]
    if os.path.isdir(data_dir):
        for name in SURFACES:
            f = os.path.join(data_dir, name)
            if os.path.exists(f):
                cases.append(
                    (os.path.splitext(name)[0], pyvista.read(f), SURFACES[name] * elements)
                )
    for index, (name, surface, n_elements) in enumerate(cases):
        surface = surface.triangulate().clean()
        orders = (2, 1) if index == 0 else (2,)
        for order in orders:
            tag = f"{name}/o{order}"
            fe = hoembed.tet10_mesh(surface, n_elements=n_elements, order=order)
            _arrays(f"{tag}/mesh", fe, out)
            lo, hi = fe.bounds[4], fe.bounds[5]
            box = (*fe.bounds[:4], lo, lo + 0.2 * (hi - lo))
            box = (box[0] - 1, box[1] + 1, box[2] - 1, box[3] + 1, box[4] - 1, box[5])
            size = max(np.ptp(np.asarray(fe.points), axis=0))
            frames = hoembed.simulate(
                fe,
                steps=3,
                dt=0.02,
                young=3e4,
                poisson=0.45,
                density=1000.0,
                gravity=(0.0, 0.0, -9.81 * size),
                fixed={"box": box},
            )
            for k, frame in enumerate(frames):
                _arrays(f"{tag}/step{k}", frame, out)
            try:
                static = hoembed.simulate(
                    fe,
                    young=1e6,
                    poisson=0.45,
                    static=True,
                    gravity=(0.0, 0.0, -0.02 * size),
                    fixed={"box": box},
                )
                _arrays(f"{tag}/static", static[-1], out)
            except hoembed.HOEmbedError as e:  # an error is an output too (address dropped)
                out[f"{tag}/static/error"] = np.array([str(e).split("): ", 1)[-1]])
            print(tag, file=sys.stderr)
            methods = ("normal-offset", "barycentric") if order == 2 else ("barycentric",)
            for method in methods:
                embedded = hoembed.embed(surface, fe, method=method)
                _arrays(f"{tag}/{method}/embedded", embedded, out)
                for mode in ("recompute", "rotate", "deform"):
                    moved = hoembed.transfer(
                        embedded, frames[-1], normals=mode, compute_point_normals=True, warnings=[]
                    )
                    _arrays(f"{tag}/{method}/transfer-{mode}", moved, out)
    _read_step(out)
    np.savez_compressed(path, **out)
    print(json.dumps({"dump": path, "arrays": len(out), "cases": [c[0] for c in cases]}))


def read_step_surfaces():
    """Surfaces that exercise the mesher's read step: quads (split along the shorter
    diagonal), polygons of more than 4 points (ear cut), strips (decomposed), float32
    points with an unused far point and a point merge; and bad inputs."""
    import hoembed
    import pyvista

    cube = pyvista.Cube(x_length=1.0, y_length=0.7, z_length=0.5)
    quads = pyvista.Box(level=3, quads=True)
    cylinder = pyvista.Cylinder(resolution=12, capping=True)  # 12-gon caps
    strips = pyvista.Sphere(theta_resolution=24, phi_resolution=16).strip()
    f32 = hoembed.thorny_tail(rings=40, sectors=16)
    pts = np.vstack([np.asarray(f32.points), [[50.0, 0.0, 0.0]]]).astype(np.float32)
    f32 = pyvista.PolyData(pts, f32.faces)
    good = {
        "cube_quads": cube,
        "box_quads": quads,
        "cylinder_polygons": cylinder,
        "sphere_strips": strips,
        "tail_float32": f32,
    }
    nan = pyvista.Sphere()
    nan.points[5] = np.nan
    bad_ids = pyvista.PolyData(np.asarray(pyvista.Sphere().points)[:10], np.array([3, 0, 1, 42]))
    bad = {
        "empty": pyvista.PolyData(),
        "nan": nan,
        "ids": bad_ids,
        "lines": pyvista.Line(),
        "degenerate": pyvista.PolyData(np.zeros((3, 3)), np.array([3, 0, 1, 2])),
    }
    return good, bad


def _read_step(out):
    import hoembed

    good, bad = read_step_surfaces()
    for name, surface in good.items():
        fe = hoembed.tet10_mesh(surface, n_elements=200)
        _arrays(f"read/{name}", fe, out)
    for name, surface in bad.items():
        try:
            hoembed.tet10_mesh(surface, n_elements=200)
            out[f"read/{name}/error"] = np.array(["no error"])
        except hoembed.HOEmbedError as e:
            out[f"read/{name}/error"] = np.array([str(e).split("): ", 1)[-1]])
    try:  # the size estimate's error
        hoembed.tet10_mesh(good["box_quads"], edge_length=1e-3)
    except hoembed.HOEmbedError as e:
        out["read/too_many/error"] = np.array([str(e).split("): ", 1)[-1]])


def _bits(a):
    a = np.ascontiguousarray(a)
    if a.dtype.kind in "fiub":
        return a.dtype.str, a.shape, a.tobytes()
    return a.dtype.str, a.shape, a.tolist()


def _compare(a_path, b_path):
    a, b = np.load(a_path), np.load(b_path)
    keys = sorted(set(a.files) | set(b.files))
    differ = []
    for k in keys:
        if k not in a.files or k not in b.files:
            differ.append((k, "only in " + (a_path if k in a.files else b_path)))
            continue
        x, y = a[k], b[k]
        if _bits(x) != _bits(y):
            why = f"dtype/shape {x.dtype}{x.shape} vs {y.dtype}{y.shape}"
            if x.shape == y.shape and x.dtype.kind == "f" and y.dtype.kind == "f":
                d = np.abs(x.astype(float) - y.astype(float))
                why = f"{int(np.count_nonzero(~(x == y)))} values differ, max |diff| {np.nanmax(d):.3g}"
            elif x.shape == y.shape:
                why = f"{int(np.count_nonzero(x != y))} values differ"
            differ.append((k, why))
    for k, why in differ:
        print(f"DIFFERS {k}: {why}")
    print(json.dumps({"arrays": len(keys), "differ": len(differ)}))
    return 1 if differ else 0


def main(argv=None):
    p = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    sub = p.add_subparsers(dest="cmd", required=True)
    d = sub.add_parser("dump", help="run the stages and save every array to an .npz")
    d.add_argument("output")
    d.add_argument("--python", help="interpreter whose `import hoembed` is the build to dump")
    d.add_argument("--data", default=DEFAULT_DATA)
    d.add_argument("--elements", type=int, default=300)
    c = sub.add_parser("compare", help="diff two dumps bitwise")
    c.add_argument("a")
    c.add_argument("b")
    args = p.parse_args(argv)
    if args.cmd == "compare":
        return _compare(args.a, args.b)
    if args.python and os.path.abspath(args.python) != os.path.abspath(sys.executable):
        return subprocess.call(
            [
                args.python,
                os.path.abspath(__file__),
                "dump",
                args.output,
                "--data",
                args.data,
                "--elements",
                str(args.elements),
            ]
        )
    _dump(args.output, args.data, args.elements)
    return 0


if __name__ == "__main__":
    sys.exit(main())
