"""Broken embedded surfaces and meshes for transfer(): the checks of
hoembed::TransferDriver (CheckMeshSize, CheckSurface, FrameArraysUsed), run by
vtkDeformationTransferFilter in the VTK build and by the wheel's transfer.py.

generate_reference.py calls write(outdir): the VTK build's error message for each
broken case (transfer_checks/errors.json) and its output for the cases that must not
fail (arrays the plan or the frame does not read, or reads as missing:
transfer_checks/<key>.vtp). test_pip_transfer_checks.py runs the same cases on the wheel.
"""

import json
import os

import numpy as np

CASE = "tail_tet10"  # a case every reference has (the thorny tail, tet10)


def add_point_array(ds, name, values):
    """Replace the point array `name` with `values`, whatever its length (pyvista
    refuses an array of the wrong length; VTK keeps it)."""
    from vtkmodules.util.numpy_support import numpy_to_vtk

    ds.GetPointData().RemoveArray(name)
    a = numpy_to_vtk(np.ascontiguousarray(values, dtype=np.float64), deep=True)
    a.SetName(name)
    ds.GetPointData().AddArray(a)


def cases(pv, ref):
    """key -> (embedded surface, deformed mesh, normals mode), built from the reference
    files of CASE (and tail_tet4's mesh for a wrong mesh)."""
    d = os.path.join(ref, CASE)

    def surface(method="normal-offset"):
        return pv.read(os.path.join(d, f"embedded_{method}.vtp"))

    def mesh():
        return pv.read(os.path.join(d, "deformed_1.vtu"))

    def edit(s, fn):
        fn(s)
        return s

    def drop_field(name):
        return lambda s: s.GetFieldData().RemoveArray(name)

    def set_field(name, value):
        def fn(s):
            s.GetFieldData().RemoveArray(name)
            s.field_data[name] = np.array([value])

        return fn

    def set_point(name, values):
        def fn(s):
            add_point_array(s, name, values(s.n_points))

        return fn

    def mesh_arrays(**arrays):
        m = mesh()
        for name, values in arrays.items():
            add_point_array(m, name, values(m.n_points))
        return m

    out = {
        "no_method": (edit(surface(), drop_field("EmbeddingMethod")), mesh(), "recompute"),
        "unknown_method": (
            edit(surface(), set_field("EmbeddingMethod", "offset")),
            mesh(),
            "recompute",
        ),
        "no_fingerprint": (
            edit(surface(), drop_field("EmbeddingMeshFingerprint")),
            mesh(),
            "recompute",
        ),
        "other_mesh": (
            surface(),
            pv.read(os.path.join(ref, "tail_tet4", "deformed_1.vtu")),
            "recompute",
        ),
        "empty_mesh": (surface(), pv.UnstructuredGrid(), "recompute"),
        "no_cell_ids": (
            edit(surface(), lambda s: s.point_data.remove("EmbeddingCellId")),
            mesh(),
            "recompute",
        ),
        "pcoords_2": (
            edit(surface(), set_point("EmbeddingParametricCoords", lambda n: np.zeros((n, 2)))),
            mesh(),
            "recompute",
        ),
        "distance_short": (
            edit(surface(), set_point("EmbeddingDistance", lambda n: np.zeros(n - 1))),
            mesh(),
            "recompute",
        ),
        "face_3": (
            edit(surface(), set_point("EmbeddingFace", lambda n: np.zeros((n, 3)))),
            mesh(),
            "recompute",
        ),
        "fallback_1": (
            edit(surface(), set_point("EmbeddingFallbackOffset", lambda n: np.zeros(n))),
            mesh(),
            "recompute",
        ),
        "several": (
            edit(
                edit(surface(), lambda s: s.point_data.remove("EmbeddingCellId")),
                set_point("EmbeddingFace", lambda n: np.zeros((n, 2))),
            ),
            mesh(),
            "recompute",
        ),
        # not read, so not checked: a barycentric embedding's distance and fallback offsets
        "barycentric_bad_distance": (
            edit(
                edit(
                    surface("barycentric"),
                    set_point("EmbeddingDistance", lambda n: np.zeros((n, 2))),
                ),
                set_point("EmbeddingFallbackOffset", lambda n: np.zeros(n)),
            ),
            mesh(),
            "recompute",
        ),
        # the deformed mesh's arrays of a wrong shape are missing (rotate/deform fall back)
        "rotate_bad_rotations": (
            surface(),
            mesh_arrays(NodalRotation=lambda n: np.zeros((n, 4))),
            "rotate",
        ),
        "deform_bad_displacement": (
            surface(),
            mesh_arrays(Displacement=lambda n: np.zeros((n, 2))),
            "deform",
        ),
    }
    return out


def sentence(message):
    """The driver's sentence without who said it (VTK build: 'vtkDeformationTransferFilter
    (0x...): ', the wheel: 'transfer: ')."""
    message = message.strip()
    if message.startswith("vtkDeformationTransferFilter (") and "): " in message:
        return message.split("): ", 1)[1]
    if message.startswith("transfer: "):
        return message[len("transfer: ") :]
    return message


def write(outdir):
    import filter_routes  # the filter's checks are the reference (generate_reference.py)
    import hoembed
    import pyvista as pv

    if not os.path.exists(os.path.join(outdir, CASE)):
        return
    folder = os.path.join(outdir, "transfer_checks")
    os.makedirs(folder, exist_ok=True)
    errors = {}
    for key, (surface, mesh, normals) in cases(pv, outdir).items():
        try:
            out = filter_routes.transfer(surface, mesh, normals=normals)
        except hoembed.HOEmbedError as e:
            errors[key] = str(e)
        else:
            out.save(os.path.join(folder, f"{key}.vtp"))
    with open(os.path.join(folder, "errors.json"), "w") as f:
        json.dump(errors, f, indent=1)
    print(
        f"[reference] transfer checks: {len(errors)} errors, "
        f"{len(cases(pv, outdir)) - len(errors)} outputs"
    )
