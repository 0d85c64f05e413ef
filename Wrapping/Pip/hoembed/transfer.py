"""pyvista-level transfer() of the pip package: hoembed::TransferDriver through _hoembed.

The same arguments, outputs and errors as the VTK build's hoembed.transfer (which runs
vtkDeformationTransferFilter over the same driver). Reading the embedding's field data
and point arrays is the binding's part, as in the filter (its messages are the filter's)."""
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


def _point_array(pd, name, nc, n):
    a = pd.GetArray(name)
    return a if a is not None and a.GetNumberOfComponents() == nc and \
        a.GetNumberOfTuples() == n else None


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
    if nmp < 4 or ncells < 1 or mesh.GetCells() is None:
        _fail("the deformed FE mesh (port 1) is empty")
    driver = TransferDriver()
    offsets, conn = _arrays.cells(mesh.GetCells())
    types = np.ascontiguousarray(_arrays.vtk_to_numpy(mesh.GetCellTypesArray()), dtype=np.uint8)
    try:
        driver.set_mesh_topology(nmp, types, offsets, conn)
    except RuntimeError as e:
        _fail(e)
    fd = surface.GetFieldData()
    method = _field_string(fd, "EmbeddingMethod")
    if method is None:
        _fail("the surface (port 0) has no field data EmbeddingMethod: is it the output of "
              "vtkEmbeddingCoordinatesFilter?")
    fingerprint = _field_string(fd, "EmbeddingMeshFingerprint")
    if fingerprint is None:
        _fail("the surface (port 0) has no field data EmbeddingMeshFingerprint")
    if fingerprint != driver.fingerprint:
        _fail(f"the FE mesh (port 1) is not the mesh the surface was embedded in: mesh "
              f"fingerprint {driver.fingerprint} ({nmp} points, {ncells} cells), embedding "
              f"fingerprint {fingerprint}")
    nv = surface.GetNumberOfPoints()
    pd = surface.GetPointData()
    offset = method == "normal-offset"
    cell_ids = _point_array(pd, "EmbeddingCellId", 1, nv)
    pcoords = _point_array(pd, "EmbeddingParametricCoords", 3, nv)
    dist = _point_array(pd, "EmbeddingDistance", 1, nv)
    faces = pd.GetArray("EmbeddingFace")
    fallback = pd.GetArray("EmbeddingFallbackOffset") if offset else None
    missing = ""
    if cell_ids is None:
        missing += " EmbeddingCellId (1 component)"
    if pcoords is None:
        missing += " EmbeddingParametricCoords (3 components)"
    if offset and dist is None:
        missing += " EmbeddingDistance (1 component)"
    if faces is not None and _point_array(pd, "EmbeddingFace", 1, nv) is None:
        missing += " EmbeddingFace (1 component)"
    if fallback is not None and _point_array(pd, "EmbeddingFallbackOffset", 3, nv) is None:
        missing += " EmbeddingFallbackOffset (3 components)"
    if missing:
        _fail("the surface (port 0) lacks point data arrays, or they do not have one tuple "
              "per point:" + missing)
    d = _arrays.doubles
    disp = rot = None
    if mode != 0:
        mpd = mesh.GetPointData()
        a = _point_array(mpd, "Displacement", 3, nmp)
        disp = d(a) if a is not None else None
        a = _point_array(mpd, "NodalRotation", 9, nmp)
        rot = d(a) if a is not None and mode == 1 else None
    float_out = surface.GetPoints() is not None and \
        surface.GetPoints().GetDataType() == VTK_FLOAT
    new_points = np.empty((nv, 3), dtype=np.float32 if float_out else np.float64)
    try:
        driver.build_plan(method, d(cell_ids), d(pcoords), d(dist) if offset else None,
                          d(faces) if faces is not None else None,
                          d(fallback) if fallback is not None else None,
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
