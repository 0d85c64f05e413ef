"""Surface files VTK 9.1 alone does not turn into a surface, read by the CLI: PLY files
storing triangle strips (VTK's PLY reader drops the 'tristrips' element), glTF .glb
files (pyvista gives a multiblock) and OFF files (no VTK reader). The files are written
here from generated surfaces; the reference is the generated surface itself (its
triangles, area and volume)."""

import json
import struct
import subprocess
import sys

import numpy as np
import pytest
import pyvista as pv
from hoembed.cli import UsageError, _read_surface
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkFiltersCore import vtkStripper


def torus():
    return (
        pv.ParametricTorus(ringradius=1.0, crosssectionradius=0.4, u_res=40, v_res=24, w_res=2)
        .clean()
        .triangulate()
    )


def strips_of(surface):
    """The surface as triangle strips (VTK's stripper), as one -1-separated id list."""
    st = vtkStripper()
    st.SetInputData(surface)
    st.Update()
    out = pv.wrap(st.GetOutput())
    strips = out.GetStrips()
    offsets = vtk_to_numpy(strips.GetOffsetsArray())
    conn = vtk_to_numpy(strips.GetConnectivityArray())
    ids = []
    for a, b in zip(offsets[:-1], offsets[1:]):
        ids.extend(conn[a:b].tolist())
        ids.append(-1)
    assert out.GetNumberOfStrips() > 1 and out.GetNumberOfPolys() == 0
    return np.asarray(out.points), ids[:-1]


def write_strip_ply(path, surface, binary, corrupt=None):
    points, ids = strips_of(surface)
    if corrupt == "id":
        ids[5] = len(points) + 7
    fmt = "binary_little_endian" if binary else "ascii"
    head = (
        f"ply\nformat {fmt} 1.0\ncomment strips written by test_cli_readers\n"
        f"element vertex {len(points)}\nproperty float x\nproperty float y\n"
        f"property float z\nelement tristrips 1\nproperty list int int vertex_indices\n"
        "end_header\n"
    )
    with open(path, "wb") as fh:
        fh.write(head.encode())
        if binary:
            body = points.astype("<f4").tobytes() + np.array([len(ids)] + ids, "<i4").tobytes()
            fh.write(body[: len(body) // 2] if corrupt == "truncate" else body)
        else:
            for p in points.astype(np.float32):
                fh.write(f"{p[0]!r} {p[1]!r} {p[2]!r}\n".encode())
            fh.write((" ".join(str(i) for i in [len(ids)] + ids) + "\n").encode())


def write_glb(path, parts):
    """A binary glTF 2.0 file with one mesh (indexed triangles) per part, each in its
    own node (the format's specification; no VTK involved)."""
    blob, views, accessors, meshes = b"", [], [], []
    for points, tris in parts:
        p = np.ascontiguousarray(points, dtype="<f4").tobytes()
        i = np.ascontiguousarray(tris, dtype="<u4").ravel().tobytes()
        for data, kind in ((p, "VEC3"), (i, "SCALAR")):
            views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(data)})
            acc = {
                "bufferView": len(views) - 1,
                "componentType": 5126 if kind == "VEC3" else 5125,
                "count": len(data) // (12 if kind == "VEC3" else 4),
                "type": kind,
            }
            if kind == "VEC3":
                acc["min"] = np.min(points, 0).tolist()
                acc["max"] = np.max(points, 0).tolist()
            accessors.append(acc)
            blob += data + b"\0" * (-len(data) % 4)
        meshes.append(
            {
                "primitives": [
                    {
                        "attributes": {"POSITION": len(accessors) - 2},
                        "indices": len(accessors) - 1,
                        "mode": 4,
                    }
                ]
            }
        )
    gltf = {
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": list(range(len(parts)))}],
        "nodes": [{"mesh": k} for k in range(len(parts))],
        "meshes": meshes,
        "buffers": [{"byteLength": len(blob)}],
        "bufferViews": views,
        "accessors": accessors,
    }
    js = json.dumps(gltf).encode()
    js += b" " * (-len(js) % 4)
    body = (
        struct.pack("<II", len(js), 0x4E4F534A)
        + js
        + struct.pack("<II", len(blob), 0x004E4942)
        + blob
    )
    with open(path, "wb") as fh:
        fh.write(struct.pack("<III", 0x46546C67, 2, 12 + len(body)) + body)


def triangle_set(surface):
    """Triangles as sorted tuples of rounded corner coordinates, with their orientation
    (rotated to start at the smallest corner)."""
    pts = np.round(np.asarray(surface.points, dtype=np.float64), 5)
    tris = surface.faces.reshape(-1, 4)[:, 1:]
    out = set()
    for t in tris:
        c = [tuple(pts[i]) for i in t]
        k = c.index(min(c))
        out.add(tuple(c[k:] + c[:k]))
    return out


@pytest.mark.parametrize("binary", [True, False])
def test_ply_triangle_strips(tmp_path, binary):
    surface = torus()
    path = tmp_path / "strips.ply"
    write_strip_ply(path, surface, binary)
    got = _read_surface(path)
    assert got.n_cells == surface.n_cells
    # the same triangles, the same orientation (strips alternate their winding)
    assert triangle_set(got) == triangle_set(surface)
    assert got.area == pytest.approx(surface.area, rel=1e-6)
    assert got.volume == pytest.approx(surface.volume, rel=1e-6)


@pytest.mark.parametrize("corrupt,words", [("id", "names vertex"), ("truncate", "truncated")])
def test_bad_strip_ply_is_refused(tmp_path, corrupt, words):
    path = tmp_path / "bad.ply"
    write_strip_ply(path, torus(), True, corrupt=corrupt)
    with pytest.raises(UsageError, match=words):
        _read_surface(path)


def test_glb_parts(tmp_path):
    a = torus()
    b = pv.Sphere(radius=0.3, center=(3.0, 0.0, 0.0))
    path = tmp_path / "scene.glb"
    write_glb(path, [(p.points, p.faces.reshape(-1, 4)[:, 1:]) for p in (a, b)])
    got = _read_surface(path)
    assert got.n_cells == a.n_cells + b.n_cells
    assert triangle_set(got) == triangle_set(a) | triangle_set(b)
    assert got.volume == pytest.approx(a.volume + b.volume, rel=1e-5)


def write_off(path, points, faces, counts_inline=False):
    """An ASCII OFF file as geometry-processing data sets have them: a comment, the counts
    (on the OFF line or the next), vertex lines with an extra colour on every other one,
    polygon lines with a colour after the ids on some."""
    lines = ["# written by test_cli_readers"]
    head = f"{len(points)} {len(faces)} 0"
    lines += [f"COFF {head}"] if counts_inline else ["COFF", head]
    for k, p in enumerate(points):
        lines.append(" ".join(repr(float(x)) for x in p) + (" 255 0 0 255" if k % 2 else ""))
    for k, f in enumerate(faces):
        lines.append(
            f"{len(f)} " + " ".join(str(int(i)) for i in f) + (" 0.5 0.5 0.5" if k % 3 == 0 else "")
        )
    path.write_text("\n".join(lines) + "\n")


@pytest.mark.parametrize("counts_inline", [False, True])
def test_off(tmp_path, counts_inline):
    a = torus()
    path = tmp_path / "torus.off"
    write_off(path, a.points, a.faces.reshape(-1, 4)[:, 1:], counts_inline)
    got = _read_surface(path)
    assert triangle_set(got) == triangle_set(a)
    assert got.volume == pytest.approx(a.volume, rel=1e-6)
    # polygons: a unit cube of six quads (outward) -> twelve triangles, area 6, volume 1
    corners = [(x, y, z) for z in (0, 1) for y in (0, 1) for x in (0, 1)]
    quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    path = tmp_path / "cube.off"
    write_off(path, corners, quads)
    cube = _read_surface(path)
    assert cube.n_cells == 12
    assert cube.area == pytest.approx(6.0)
    assert cube.volume == pytest.approx(1.0)


@pytest.mark.parametrize(
    "body,words",
    [
        ("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n", "names vertex 7"),
        ("OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n", "ends early"),
        ("OFF\n3 1 0\n0 0 0\n1 0\n0 1 0\n3 0 1 2\n", "fewer than 3 numbers"),
        ("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4 0 1 2\n", "declares 4 vertices but lists 3"),
        ("4OFF\n3 1 0\n0 0 0 0\n1 0 0 0\n0 1 0 0\n3 0 1 2\n", "variant '4OFF'"),
        ("OFF BINARY\n\x03\x00\x00\x00", "binary OFF"),
        ("ply\nformat ascii 1.0\nend_header\n", "not an OFF file"),
    ],
)
def test_bad_off_is_refused(tmp_path, body, words):
    path = tmp_path / "bad.off"
    path.write_bytes(body.encode("latin-1"))
    with pytest.raises(UsageError, match=words):
        _read_surface(path)


def test_run_on_strip_ply_glb_and_off(tmp_path):
    """hoembed run takes them with no extra flag."""
    surface = pv.Sphere(radius=1.0, theta_resolution=40, phi_resolution=40)
    files = [tmp_path / "s.ply", tmp_path / "s.glb", tmp_path / "s.off"]
    write_strip_ply(files[0], surface, True)
    write_glb(files[1], [(surface.points, surface.faces.reshape(-1, 4)[:, 1:])])
    write_off(files[2], surface.points, surface.faces.reshape(-1, 4)[:, 1:])
    for f in files:
        out = subprocess.run(
            [
                sys.executable,
                "-m",
                "hoembed",
                "run",
                str(f),
                "--elements",
                "150",
                "--steps",
                "2",
                "--no-tet4",
                "--output",
                str(tmp_path / f.suffix[1:]),
            ],
            capture_output=True,
            encoding="utf-8",
            timeout=600,
        )
        assert out.returncode == 0, out.stderr
        summary = json.loads((tmp_path / f.suffix[1:] / "summary.json").read_text())
        assert summary["frames"] == 3
