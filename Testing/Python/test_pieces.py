"""The piece protocol in one process (VTK 9.1 build): a piece asked of the embedding gets
that piece of the surface embedded in the whole mesh, a piece asked of the mesher still
meshes the whole surface, and the transfer moves a piece with the whole deformed mesh.
Reference: the same filters run on the whole surface (no pieces). The multi-process
runs are tested with the ParaView plugin (Plugin/Testing, `make test-paraview`)."""

import hoembed
import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkFiltersSources import vtkSphereSource


def sphere():
    s = vtkSphereSource()
    s.SetThetaResolution(48)
    s.SetPhiResolution(32)
    return s


def keep(obj):
    KEEP.append(obj)
    return obj


def matched(piece, whole, name):
    """The array `name` of a piece and of the whole run at the same points (the sphere
    source's pieces compute their coordinates anew: equal to ~1e-16, not bitwise)."""
    from scipy.spatial import cKDTree

    pp = vtk_to_numpy(piece.GetPoints().GetData())
    wp = vtk_to_numpy(whole.GetPoints().GetData())
    dist, idx = cKDTree(wp).query(pp)
    assert dist.max() < 1e-12
    return (
        vtk_to_numpy(piece.GetPointData().GetArray(name)),
        vtk_to_numpy(whole.GetPointData().GetArray(name))[idx],
    )


KEEP = []  # the sources stay alive as long as the pipelines that use them


def mesher_of(source):
    KEEP.append(source)
    m = hoembed.vtkTet10Mesher()
    m.SetInputConnection(source.GetOutputPort())
    m.SetTargetNumberOfElements(150)
    return m


def test_piece_of_mesher_is_whole_mesh():
    whole = mesher_of(sphere())
    whole.Update()
    piece = mesher_of(sphere())
    piece.UpdatePiece(1, 2, 0)  # half a sphere would be refused as open
    assert piece.GetOutput().GetNumberOfCells() == whole.GetOutput().GetNumberOfCells() > 0
    assert np.array_equal(
        vtk_to_numpy(piece.GetOutput().GetPoints().GetData()),
        vtk_to_numpy(whole.GetOutput().GetPoints().GetData()),
    )


def test_embedding_and_transfer_of_a_piece_use_the_whole_mesh():
    mesher = mesher_of(sphere())  # its own source: the mesh port is asked for the whole
    ref = hoembed.vtkEmbeddingCoordinatesFilter()
    ref.SetInputConnection(0, keep(sphere()).GetOutputPort())
    ref.SetInputConnection(1, mesher.GetOutputPort())
    ref.Update()
    n_all = ref.GetOutput().GetNumberOfPoints()

    pieces = []
    for k in range(2):
        emb = hoembed.vtkEmbeddingCoordinatesFilter()
        emb.SetInputConnection(0, keep(sphere()).GetOutputPort())
        emb.SetInputConnection(1, mesher.GetOutputPort())
        emb.UpdatePiece(k, 2, 0)
        out = emb.GetOutput()
        assert 0 < out.GetNumberOfPoints() < n_all  # a piece of the surface ...
        assert mesher.GetOutput().GetNumberOfCells() > 100  # ... in the whole mesh
        pieces.append(out)
        # every vertex of the piece is embedded (a vertex far from the piece's mesh part
        # would be outside a half mesh): its closest distance equals the whole run's.
        got, want = matched(out, ref.GetOutput(), "EmbeddingClosestDistance")
        assert np.abs(got - want).max() < 1e-12 and want.max() > 1e-3

    # The transfer of a piece with a moved (rigidly translated) mesh moves it rigidly.
    from vtkmodules.vtkCommonTransforms import vtkTransform
    from vtkmodules.vtkFiltersGeneral import vtkTransformFilter

    t = vtkTransform()
    t.Translate(0.3, -0.2, 0.1)
    moved = vtkTransformFilter()
    moved.SetTransform(t)
    moved.SetInputConnection(mesher.GetOutputPort())
    emb = hoembed.vtkEmbeddingCoordinatesFilter()
    emb.SetInputConnection(0, keep(sphere()).GetOutputPort())
    emb.SetInputConnection(1, mesher.GetOutputPort())
    tr = hoembed.vtkDeformationTransferFilter()
    tr.SetInputConnection(0, emb.GetOutputPort())
    tr.SetInputConnection(1, moved.GetOutputPort())
    tr.UpdatePiece(1, 2, 0)
    out = tr.GetOutput()
    assert 0 < out.GetNumberOfPoints() < n_all
    d = vtk_to_numpy(out.GetPoints().GetData()) - vtk_to_numpy(
        emb.GetOutput().GetPoints().GetData()
    )
    assert np.abs(d - np.array([0.3, -0.2, 0.1])).max() < 1e-6  # float32 points
