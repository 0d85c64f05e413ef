"""pyvista-level transfer(): hoembed::TransferDriver through _hoembed (the driver
vtkDeformationTransferFilter runs; the same points bit for bit). This only reads the
surface's and the mesh's VTK objects: the driver checks them (CheckMeshSize,
CheckSurface: the filter's messages) and says which arrays it reads (FrameArraysUsed)."""

import numpy as np
import pyvista
from vtkmodules.vtkCommonCore import VTK_FLOAT

from . import _arrays
from ._arrays import N
from ._checks import (
    NORMAL_MODE_NAMES,
    POINT_NORMALS_MODE_NAMES,
    POINT_NORMALS_MODES,
    point_normals_argument,
    transfer_arguments,
)
from ._errors import HOEmbedError
from ._hoembed import DEFAULTS, TransferDriver

__all__ = ["transfer", "TransferPlan"]
# the defaults: vtkDeformationTransferFilter's, which are the driver's
# (hoembed::TransferOptions)
_D = DEFAULTS["transfer"]


def _field_string(fd, name):
    a = fd.GetAbstractArray(name) if fd is not None else None
    if a is None or not a.IsA("vtkStringArray") or a.GetNumberOfValues() == 0:
        return None
    return a.GetValue(0)


def _shape(a):
    """(components, tuples) of a VTK data array (or a numpy array) for the driver's
    checks; None: absent."""
    if a is None:
        return None
    if isinstance(a, np.ndarray):
        return (1 if a.ndim == 1 else int(np.prod(a.shape[1:])), a.shape[0])
    return (a.GetNumberOfComponents(), a.GetNumberOfTuples())


def _fail(message):
    raise HOEmbedError(f"transfer: {message}")


def transfer(
    embedded_surface,
    deformed_mesh,
    normals=NORMAL_MODE_NAMES[_D["NormalMode"]],
    compute_point_normals=_D["ComputePointNormals"],
    warnings=None,
):
    """The deformed fine surface for a deformed FE mesh: v' = p' + d n' (paper eq. 4).

    Parameters
    ----------
    embedded_surface : pyvista.PolyData or vtkPolyData
        The surface with the embedding arrays (``EmbeddingCellId``,
        ``EmbeddingParametricCoords``, ``EmbeddingDistance``, optional ``EmbeddingFace``)
        and field data ``EmbeddingMethod`` / ``EmbeddingMeshFingerprint``, as written by
        ``hoembed.embed`` / vtkEmbeddingCoordinatesFilter.
    deformed_mesh : pyvista.UnstructuredGrid or vtkUnstructuredGrid
        The FE mesh the surface was embedded in (same points and cells, tet10, tet4,
        Lagrange tets of order 1-4, or hexahedra: Lagrange of order 1-3, triquadratic,
        quadratic serendipity; Lagrange tets of order 3-4 and hexahedra recompute the
        normals whatever ``normals`` says, with a warning), with deformed coordinates.
    normals : {"recompute", "rotate", "deform"}
        ``"recompute"`` (default): smooth nodal normals of the deformed curved boundary.
        ``"rotate"``: rest nodal normals rotated by the mesh's ``NodalRotation`` point data
        (needs ``Displacement`` too; falls back to recompute with a warning otherwise).
        ``"deform"``: rest nodal normals pushed forward by the nodal deformation gradient
        (needs ``Displacement``): offsets follow the material lines that were normal to
        the rest surface, so a shear of the surface (a twist) tilts them too.
    compute_point_normals : bool or {"recompute", "transform"}
        Add unit point normals ``Normals`` for rendering (default False), as
        vtkDeformationTransferFilter's PointNormalsMode: ``"recompute"`` (or True):
        area-weighted normals of the deformed polygons; ``"transform"``: the rest
        surface's normals carried by the deformation (cof(F) n0, needs the mesh's
        ``Displacement``; recomputed where the map folds, and everywhere, with a warning,
        without ``Displacement``).
    warnings : list, optional
        Receives the driver's warnings (e.g. inverted deformed elements).

    Returns
    -------
    pyvista.PolyData
        The input surface's topology and data with deformed points (the ``Embedding*``
        point arrays removed).

    Raises
    ------
    hoembed.HOEmbedError
        Missing embedding arrays, a mesh that is not the embedding's (fingerprint), NaN
        coordinates, unsupported cells.
    ValueError
        An unknown ``normals`` or ``compute_point_normals`` value.

    Examples
    --------
    >>> deformed_surface = hoembed.transfer(embedded, deformed_mesh)
    """
    mode = transfer_arguments(embedded_surface, deformed_mesh, normals)
    pn_mode = point_normals_argument(
        "transfer", compute_point_normals, POINT_NORMALS_MODE_NAMES[_D["PointNormalsMode"]]
    )
    plan = TransferPlan(embedded_surface, deformed_mesh, mode)
    mesh = deformed_mesh
    mpd = mesh.GetPointData()
    nrm = (
        None
        if pn_mode is None
        else np.empty((embedded_surface.GetNumberOfPoints(), 3), dtype=np.float32)
    )
    frame_warnings = plan.evaluate(
        mesh.GetPoints().GetData(),
        mpd.GetArray(N.Displacement),
        mpd.GetArray(N.NodalRotation),
        nrm,
        pn_mode or 0,
    )
    if warnings is not None:
        warnings.extend(f"transfer: {w}" for w in frame_warnings)
    out = plan.output(False)
    if nrm is not None:
        out.GetPointData().SetNormals(_arrays.to_vtk(nrm, N.Normals))
    return out


class TransferPlan:
    """The transfer set up once for an embedded surface and a mesh's topology (the
    driver's checks and plan), then evaluated on deformed states of that mesh: transfer()
    makes one per call, the live loop (hoembed.live) one per session."""

    def __init__(self, embedded_surface, mesh, mode):
        surface = embedded_surface
        self.surface, self.mode = surface, mode
        self.nmp, ncells = mesh.GetNumberOfPoints(), mesh.GetNumberOfCells()
        driver = self.driver = TransferDriver()
        try:
            TransferDriver.check_mesh_size(self.nmp, ncells, mesh.GetCells() is not None)
            offsets, conn = _arrays.cells(mesh.GetCells())
            types = _arrays.cell_types(mesh)
            driver.set_mesh_topology(
                self.nmp, types, offsets, conn, _arrays.higher_order_degrees(mesh)
            )
        except RuntimeError as e:
            _fail(e)
        # reading only: the driver judges the field data and the arrays (check_surface)
        fd, pd = surface.GetFieldData(), surface.GetPointData()
        method = _field_string(fd, N.EmbeddingMethod)
        nv = surface.GetNumberOfPoints()
        cell_ids, pcoords, dist, faces, fallback = (
            pd.GetArray(name)
            for name in (
                N.EmbeddingCellId,
                N.EmbeddingParametricCoords,
                N.EmbeddingDistance,
                N.EmbeddingFace,
                N.EmbeddingFallbackOffset,
            )
        )
        try:
            use_dist, use_faces, use_fallback = driver.check_surface(
                nv,
                method,
                _field_string(fd, N.EmbeddingMeshFingerprint),
                _shape(cell_ids),
                _shape(pcoords),
                _shape(dist),
                _shape(faces),
                _shape(fallback),
            )
        except RuntimeError as e:
            _fail(e)
        d = _arrays.doubles
        float_out = (
            surface.GetPoints() is not None and surface.GetPoints().GetDataType() == VTK_FLOAT
        )
        self.points = np.empty((nv, 3), dtype=np.float32 if float_out else np.float64)
        try:
            driver.build_plan(
                method,
                d(cell_ids),
                d(pcoords),
                d(dist) if use_dist else None,
                d(faces) if use_faces else None,
                d(fallback) if use_fallback else None,
                _D["FaceTolerance"],
                mesh.GetLength(),
            )
        except RuntimeError as e:
            _fail(e)

    def evaluate(
        self,
        points,
        displacements=None,
        rotations=None,
        point_normals=None,
        point_normals_mode=_D["PointNormalsMode"],
    ):
        """The deformed surface points into self.points for the mesh's deformed `points`
        (a VTK data array or an (n, 3) array) and, when the normal modes read them, its
        Displacement and NodalRotation (VTK arrays, arrays or None). With
        `point_normals` (float32 (nv, 3)) the same pass writes the unit point normals, in
        `point_normals_mode` (the driver's TransferPointNormals;
        transform sets the rest surface points once). Returns the driver's warnings."""
        d = _arrays.doubles
        # without point normals the frame reads no more than recompute's (nothing extra)
        mode = point_normals_mode if point_normals is not None else POINT_NORMALS_MODES["recompute"]
        if point_normals is not None:
            self._prepare_normals(mode)
        use_disp, use_rot = TransferDriver.frame_arrays_used(
            self.mode, self.nmp, _shape(displacements), _shape(rotations), mode
        )
        try:
            return self.driver.evaluate_frame(
                d(points),
                self.mode,
                d(displacements) if use_disp else None,
                d(rotations) if use_rot else None,
                _D["CheckInvertedElements"],
                self.points,
                point_normals,
                mode,
            )
        except RuntimeError as e:
            _fail(e)

    @property
    def folded_normals(self):
        """Transform point normals: vertices of the last frame recomputed where the map
        folds (the driver's count)."""
        return self.driver.number_of_folded_normals

    def _prepare_normals(self, mode):
        """The polygons once, and for transform the rest surface's points once (what
        vtkDeformationTransferFilter gives the driver; set_polygons forgets them)."""
        if not hasattr(self, "_polys"):
            self._polys = _arrays.cells(self.surface.GetPolys())
            self.driver.set_polygons(*self._polys)
        if mode == POINT_NORMALS_MODES["transform"] and not self.driver.has_rest_surface_normals:
            rest = self.surface.GetPoints()
            if rest is not None:  # else the driver falls back to recompute, with a warning
                self.driver.set_rest_surface_points(_arrays.points(rest))

    def output(self, compute_point_normals=False):
        """A new surface: the input's topology and data with the deformed points, the
        embedding arrays and stale normals dropped, point normals when asked for."""
        surface = self.surface
        out = pyvista.wrap(surface).copy()
        out.points = self.points.copy()
        opd = out.GetPointData()
        for i in reversed(range(opd.GetNumberOfArrays())):
            name = opd.GetArrayName(i)
            if name and name.startswith(N.EmbeddingPrefix):
                opd.RemoveArray(i)
        for data in (opd, out.GetCellData()):
            stale = data.GetNormals()
            if stale is not None:
                data.RemoveArray(stale.GetName())
                data.SetNormals(None)
        if compute_point_normals:
            opd.SetNormals(_arrays.to_vtk(self.point_normals(self.points), N.Normals))
        return out

    def point_normals(self, points, out=None):
        """Area-weighted point normals (float32) of the surface's polygons at `points`."""
        self._prepare_normals(POINT_NORMALS_MODES["recompute"])
        nv = self.surface.GetNumberOfPoints()
        nrm = np.empty((nv, 3), dtype=np.float32) if out is None else out
        self.driver.compute_vertex_normals(points, nrm)
        return nrm
