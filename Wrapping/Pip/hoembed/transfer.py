"""pyvista-level transfer() of the pip package: hoembed::TransferDriver through _hoembed.

The same arguments, outputs and errors as the VTK build's hoembed.transfer (which runs
vtkDeformationTransferFilter over the same driver). This only reads the surface's and the
mesh's VTK objects: the driver checks them (CheckMeshSize, CheckSurface: the filter's
messages) and says which arrays it reads (FrameArraysUsed)."""
import numpy as np
import pyvista
from vtkmodules.vtkCommonCore import VTK_FLOAT

from . import _arrays
from ._checks import transfer_arguments
from ._errors import HOEmbedError
from ._hoembed import TransferDriver

__all__ = ["transfer"]
# vtkDeformationTransferFilter's defaults
_FACE_TOLERANCE = 1e-6


def _field_string(fd, name):
    a = fd.GetAbstractArray(name) if fd is not None else None
    if a is None or not a.IsA("vtkStringArray") or a.GetNumberOfValues() == 0:
        return None
    return a.GetValue(0)


def _shape(a):
    """(components, tuples) of a VTK data array for the driver's checks; None: absent."""
    return None if a is None else (a.GetNumberOfComponents(), a.GetNumberOfTuples())


def _fail(message):
    raise HOEmbedError(f"transfer: {message}")


def transfer(embedded_surface, deformed_mesh, normals="recompute", compute_point_normals=False,
             warnings=None):
    """The deformed fine surface for a deformed FE mesh: v' = p' + d n' (paper eq. 4).

    See the VTK build's ``hoembed.transfer``: same parameters and output (the input
    surface's topology and data with deformed points, ``Embedding*`` point arrays
    removed, optional ``Normals``); the points are bit for bit the VTK filter's.
    """
    mode = transfer_arguments(embedded_surface, deformed_mesh, normals)
    surface, mesh = embedded_surface, deformed_mesh
    nmp, ncells = mesh.GetNumberOfPoints(), mesh.GetNumberOfCells()
    driver = TransferDriver()
    try:
        TransferDriver.check_mesh_size(nmp, ncells, mesh.GetCells() is not None)
        offsets, conn = _arrays.cells(mesh.GetCells())
        types = np.ascontiguousarray(_arrays.vtk_to_numpy(_arrays.cell_types(mesh)),
                                     dtype=np.uint8)
        driver.set_mesh_topology(nmp, types, offsets, conn)
    except RuntimeError as e:
        _fail(e)
    # reading only: the driver judges the field data and the arrays (check_surface)
    fd, pd = surface.GetFieldData(), surface.GetPointData()
    method = _field_string(fd, "EmbeddingMethod")
    nv = surface.GetNumberOfPoints()
    cell_ids, pcoords, dist, faces, fallback = (pd.GetArray(name) for name in (
        "EmbeddingCellId", "EmbeddingParametricCoords", "EmbeddingDistance", "EmbeddingFace",
        "EmbeddingFallbackOffset"))
    try:
        use_dist, use_faces, use_fallback = driver.check_surface(
            nv, method, _field_string(fd, "EmbeddingMeshFingerprint"), _shape(cell_ids),
            _shape(pcoords), _shape(dist), _shape(faces), _shape(fallback))
    except RuntimeError as e:
        _fail(e)
    d = _arrays.doubles
    mpd = mesh.GetPointData()
    m_disp, m_rot = mpd.GetArray("Displacement"), mpd.GetArray("NodalRotation")
    use_disp, use_rot = TransferDriver.frame_arrays_used(mode, nmp, _shape(m_disp), _shape(m_rot))
    disp = d(m_disp) if use_disp else None
    rot = d(m_rot) if use_rot else None
    float_out = surface.GetPoints() is not None and \
        surface.GetPoints().GetDataType() == VTK_FLOAT
    new_points = np.empty((nv, 3), dtype=np.float32 if float_out else np.float64)
    try:
        driver.build_plan(method, d(cell_ids), d(pcoords), d(dist) if use_dist else None,
                          d(faces) if use_faces else None,
                          d(fallback) if use_fallback else None,
                          _FACE_TOLERANCE, mesh.GetLength())
        frame_warnings = driver.evaluate_frame(d(mesh.GetPoints().GetData()), mode, disp, rot,
                                               True, new_points)
    except RuntimeError as e:
        _fail(e)
    if warnings is not None:
        warnings.extend(f"transfer: {w}" for w in frame_warnings)
    out = pyvista.wrap(surface).copy()
    out.points = new_points
    opd = out.GetPointData()
    for i in reversed(range(opd.GetNumberOfArrays())):
        name = opd.GetArrayName(i)
        if name and name.startswith("Embedding"):
            opd.RemoveArray(i)
    for data in (opd, out.GetCellData()):
        stale = data.GetNormals()
        if stale is not None:
            data.RemoveArray(stale.GetName())
            data.SetNormals(None)
    if compute_point_normals:
        poff, pconn = _arrays.cells(surface.GetPolys())
        nrm = np.empty((nv, 3), dtype=np.float32)
        driver.vertex_normals(poff, pconn, new_points, nrm)
        opd.SetNormals(_arrays.to_vtk(nrm, "Normals"))
    return out
