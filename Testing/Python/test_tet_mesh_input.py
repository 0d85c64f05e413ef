"""The one FE-mesh reader (hoembed::TetMeshInput) as the three filters that read an FE mesh
see it, and the input checks of the stepper and the transfer (issue 19).

A bad node id used to be read unchecked by the stepper (a crash, or a heap overflow
reported as "inverted"): those cases run in a subprocess, so a crash fails only its test.
"""

import os
import subprocess
import sys
import textwrap

import hoembed
import numpy as np
import pytest
import pyvista as pv
from conftest import box_tet_mesh

HERE = os.path.dirname(os.path.abspath(__file__))


def run_isolated(body):
    """Run `body` (Python source using `mesh`, a 2x1x1 tet10 box) in a fresh interpreter;
    its stdout, or the test fails when it crashes."""
    src = textwrap.dedent("""
        import sys
        sys.path.insert(0, {here!r})
        import numpy as np
        import pyvista as pv
        import hoembed
        from conftest import box_tet_mesh
        mesh = box_tet_mesh((2, 1, 1), (2.0, 1.0, 1.0), 2)
    """).format(here=HERE) + textwrap.dedent(body)
    proc = subprocess.run(
        [sys.executable, "-c", src],
        capture_output=True,
        encoding="utf-8",
        timeout=300,
        env=dict(os.environ),
    )
    assert proc.returncode == 0, f"crashed or failed (rc {proc.returncode}): {proc.stderr[-2000:]}"
    return proc.stdout


@pytest.mark.parametrize("node", ["-1", "mesh.n_points", "mesh.n_points + 100000"])
@pytest.mark.parametrize("stage", ["simulate", "embed", "transfer"])
def test_node_id_out_of_range_is_refused(stage, node):
    call = {
        "simulate": "hoembed.simulate(bad, steps=1, fixed={'plane': ((0, 0, 0), (1, 0, 0))})",
        "embed": "hoembed.embed(pv.Sphere(radius=0.3, center=(1, 0.5, 0.5)), bad)",
        "transfer": "hoembed.transfer(hoembed.embed(pv.Sphere(radius=0.3, center=(1, 0.5, 0.5)), mesh), bad)",
    }[stage]
    out = run_isolated(f"""
        cells = mesh.cells.reshape(mesh.n_cells, -1).copy()
        cells[3, 1 + 7] = {node}
        bad = pv.UnstructuredGrid(cells.ravel(), mesh.celltypes, np.asarray(mesh.points), deep=True)
        try:
            {call}
            print("NO ERROR")
        except hoembed.HOEmbedError as e:
            print("ERROR", e)
    """)
    assert out.startswith("ERROR"), out
    assert "cell 3" in out and "out of range" in out, out
    if stage == "transfer":
        assert "ERROR transfer: " in out
    elif stage == "embed":
        assert "ERROR embed: " in out
    else:
        assert "ERROR simulate: " in out


def test_stepper_non_finite_node_is_not_called_inverted():
    mesh = box_tet_mesh((2, 1, 1), (2.0, 1.0, 1.0), 2)
    for value in (np.nan, np.inf):
        bad = mesh.copy()
        bad.points[4] = [value, 0.0, 0.0]
        with pytest.raises(hoembed.HOEmbedError, match=r"simulate: .*non-finite.*node 4"):
            hoembed.simulate(bad, steps=1, fixed={"plane": ((0, 0, 0), (1, 0, 0))})


def test_static_solve_without_load_returns_rest_state():
    mesh = box_tet_mesh((3, 1, 1), (3.0, 1.0, 1.0), 2)
    frames = hoembed.simulate(
        mesh, static=True, gravity=(0.0, 0.0, 0.0), fixed={"plane": ((0, 0, 0), (1, 0, 0))}
    )
    last = frames[-1]
    assert np.array_equal(last.point_data["Displacement"], np.zeros((mesh.n_points, 3)))
    assert np.array_equal(np.asarray(last.points), np.asarray(mesh.points))
    # a load still deflects it (the shortcut is for no load only)
    loaded = hoembed.simulate(
        mesh,
        static=True,
        gravity=(0.0, 0.0, -1.0),
        young=1e6,
        fixed={"plane": ((0, 0, 0), (1, 0, 0))},
    )[-1]
    assert loaded.point_data["Displacement"][:, 2].min() < 0.0


def test_fixed_array_of_the_wrong_kind_is_refused():
    mesh = box_tet_mesh((2, 1, 1), (2.0, 1.0, 1.0), 2)
    cells = mesh.copy()
    cells.cell_data["Fixed"] = np.ones(mesh.n_cells)
    with pytest.raises(hoembed.HOEmbedError, match="simulate: .*Fixed.*cell or field data"):
        hoembed.simulate(cells, steps=1)
    strings = mesh.copy()
    strings.point_data["Fixed"] = np.array(["1"] * mesh.n_points)
    with pytest.raises(hoembed.HOEmbedError, match="simulate: .*Fixed.*not numeric"):
        hoembed.simulate(strings, steps=1)
    named = mesh.copy()
    named.cell_data["Clamp"] = np.ones(mesh.n_cells)
    with pytest.raises(hoembed.HOEmbedError, match="Clamp.*cell or field data"):
        hoembed.simulate(named, steps=1, fixed="Clamp")
    # the right kind still clamps
    good = mesh.copy()
    good.point_data["Fixed"] = (np.asarray(mesh.points)[:, 0] <= 0).astype(np.uint8)
    u = hoembed.simulate(good, steps=2, dt=0.01)[-1].point_data["Displacement"]
    assert np.abs(u[good.point_data["Fixed"] == 1]).max() == 0.0
    assert np.abs(u).max() > 0.0


@pytest.fixture(scope="module")
def embedded():
    mesh = box_tet_mesh((3, 2, 2), (3.0, 2.0, 2.0), 2)
    surface = pv.Sphere(radius=1.1, center=(1.5, 1.0, 1.0), theta_resolution=16, phi_resolution=16)
    return mesh, {
        m: hoembed.embed(surface, mesh, method=m) for m in ("normal-offset", "barycentric")
    }


@pytest.mark.parametrize("method", ["normal-offset", "barycentric"])
def test_transfer_refuses_what_no_embedding_gives(embedded, method):
    mesh, surfaces = embedded
    surf = surfaces[method]
    assert hoembed.transfer(surf, mesh).n_points == surf.n_points  # the valid one passes

    def refused(name, index, value, match):
        s = surf.copy()
        a = np.array(s.point_data[name])
        if isinstance(value, float) and a.dtype.kind != "f":
            a = a.astype(float)
        a[index] = value
        s.point_data[name] = a
        with pytest.raises(hoembed.HOEmbedError, match=match):
            hoembed.transfer(s, mesh)

    far = 1e6
    refused("EmbeddingParametricCoords", (5, 0), far, "transfer: .*EmbeddingParametricCoords")
    refused("EmbeddingParametricCoords", (5, 1), -far, "EmbeddingParametricCoords")
    refused("EmbeddingCellId", 7, 2.5, "EmbeddingCellId")
    refused("EmbeddingCellId", 7, float(mesh.n_cells), "cell id outside")
    refused("EmbeddingCellId", 7, -1.0, "cell id outside")
    if method == "normal-offset":
        outside = int(np.flatnonzero(surf.point_data["EmbeddingDistance"] != 0)[0])
        refused("EmbeddingDistance", outside, 1e300, "EmbeddingDistance")
        # 1e12 is finite and fits a double, but no mesh carries a point that far faithfully:
        # refused (over 1e9 mesh diagonals), where 100 diagonals still passes
        diag = mesh.length
        refused(
            "EmbeddingDistance",
            outside,
            1e12 * diag,
            r"1 with EmbeddingParametricCoords over 1000 .* \|EmbeddingDistance\| over 1e\+09 mesh",
        )
        refused("EmbeddingDistance", outside, 1e12, r"EmbeddingDistance\| over 1e\+09 mesh")
        s = surf.copy()
        d = np.array(s.point_data["EmbeddingDistance"])
        d[outside] = 100.0 * diag
        s.point_data["EmbeddingDistance"] = d
        far_point = hoembed.transfer(s, mesh).points[outside]
        assert np.linalg.norm(far_point - surf.points[outside]) > 50.0 * diag
        refused("EmbeddingDistance", outside, np.inf, "non-finite")


def test_transfer_of_a_reloaded_embedding(embedded, tmp_path):
    """A .vtp round trip keeps a valid embedding valid, and an edited one is refused."""
    mesh, surfaces = embedded
    path = str(tmp_path / "embedded.vtp")
    surfaces["normal-offset"].save(path)
    back = pv.read(path)
    a = hoembed.transfer(surfaces["normal-offset"], mesh)
    b = hoembed.transfer(back, mesh)
    assert np.array_equal(np.asarray(a.points), np.asarray(b.points))
    d = np.array(back.point_data["EmbeddingDistance"])
    d[np.flatnonzero(d)[0]] = 1e200
    back.point_data["EmbeddingDistance"] = d
    with pytest.raises(hoembed.HOEmbedError, match="transfer: .*EmbeddingDistance"):
        hoembed.transfer(back, mesh)
