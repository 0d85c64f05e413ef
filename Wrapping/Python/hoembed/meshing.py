"""pyvista-level tet10_mesh(): the mesher's read step and hoembed::RunMesher (the
functions vtkTet10Mesher calls) through _hoembed.mesh_surface.

The mesher needs geometry services on the fine surface; vtkTet10Mesher takes them from
the VTK it is compiled against (its VTKServices). Here _VTKServices gives them from the
VTK Python in use: the same classes with the same settings, called from Python (adapting
only: the algorithm, its order of steps, retries and acceptance tests are the C++
driver's). In the VTK build (Debian VTK 9.1) that is the same VTK as the filter's; a pip
VTK 9.3 or later decimates, smooths and locates with other round-off and tie-breaks, so
the wheel's mesh may differ from the VTK build's in its details (element count and
quality close, not equal; every mesh valid and covering the surface either way).
"""

import math
import warnings as _warnings

import numpy as np
import pyvista
from vtkmodules.util.numpy_support import numpy_to_vtk
from vtkmodules.vtkCommonCore import (
    VTK_DOUBLE,
    VTK_ID_TYPE,
    VTK_UNSIGNED_CHAR,
    reference,
    vtkDoubleArray,
    vtkIdList,
    vtkIdTypeArray,
    vtkPoints,
    vtkSMPTools,
)
from vtkmodules.vtkCommonDataModel import (
    VTK_QUADRATIC_TETRA,
    VTK_TETRA,
    vtkCellArray,
    vtkGenericCell,
    vtkPolyData,
    vtkPolygon,
    vtkQuadraticTetra,
    vtkStaticCellLocator,
    vtkStaticPointLocator,
    vtkUnstructuredGrid,
)
from vtkmodules.vtkFiltersCore import (
    vtkCleanPolyData,
    vtkQuadricDecimation,
    vtkWindowedSincPolyDataFilter,
)
from vtkmodules.vtkFiltersGeneral import vtkCellValidator

from . import _arrays
from ._arrays import N
from ._checks import MESH_DOC, mesh_arguments
from ._errors import HOEmbedError
from ._hoembed import DEFAULTS, mesh_surface
from ._hoembed import MESHER_SERVICE_SETTINGS as _SETTINGS

__all__ = ["tet10_mesh"]

# vtkTet10Mesher's properties that tet10_mesh does not set (their defaults), and the
# services' settings: the driver's (hoembed::MesherServiceSettings)
MERGE_TOLERANCE = _SETTINGS["merge_tolerance"]
MAXIMUM_NUMBER_OF_ELEMENTS = _SETTINGS["maximum_number_of_elements"]

# the validator's verdicts that refuse a curved cell (bits of vtkCellValidator::State, or
# of vtkCellStatus in later VTK; the same values)
_BAD_CELL = _SETTINGS["refused_cell_states"]


def _triangles(tris):
    """A vtkCellArray of the (n, 3) int64 triangles."""
    tris = np.ascontiguousarray(tris, dtype=np.int64).reshape(-1)
    cells = vtkCellArray()
    offsets = np.arange(0, tris.size + 1, 3, dtype=np.int64)
    cells.SetData(
        numpy_to_vtk(offsets, deep=True, array_type=VTK_ID_TYPE),
        numpy_to_vtk(tris, deep=True, array_type=VTK_ID_TYPE),
    )
    return cells


def _poly(points, tris):
    """vtkPolyData of float64 points (n, 3) and triangles."""
    pts = vtkPoints()
    pts.SetData(
        numpy_to_vtk(np.ascontiguousarray(points, dtype=np.float64).reshape(-1, 3), deep=True)
    )
    pd = vtkPolyData()
    pd.SetPoints(pts)
    pd.SetPolys(_triangles(tris))
    return pd


def _to_arrays(pd):
    """(points float64, triangles int64) of poly data, or None if a polygon is not a
    triangle (vtkTet10Mesher's ToArrays)."""
    pts = (
        np.ascontiguousarray(_arrays.points(pd.GetPoints()), dtype=np.float64)
        if pd.GetNumberOfPoints()
        else np.zeros((0, 3))
    )
    off, conn = _arrays.cells(pd.GetPolys())
    if off.size > 1 and np.any(np.diff(off) != 3):
        return None
    return pts, np.ascontiguousarray(conn, dtype=np.int64)


def _build_deterministically(locator):
    """BuildLocator on VTK's sequential backend (vtkTet10Mesher's
    BuildLocatorDeterministically: under TBB the order of the cells in a bin, and so which
    of two equidistant triangles a closest-point query returns, changes from build to
    build). The pip wheels' VTK is sequential already."""
    backend = vtkSMPTools.GetBackend()
    if backend == "Sequential":
        locator.BuildLocator()
        return
    vtkSMPTools.SetBackend("Sequential")
    try:
        locator.BuildLocator()
    finally:
        vtkSMPTools.SetBackend(backend)


class _Locator:
    """Closest points, normals and ray crossings on triangles (vtkStaticCellLocator, as
    vtkTet10Mesher's SurfaceProjector)."""

    def __init__(self, pd):
        self.pd = pd
        self.locator = vtkStaticCellLocator()
        self.locator.SetDataSet(pd)
        _build_deterministically(self.locator)
        self.cell = vtkGenericCell()
        self.cell_id, self.sub_id, self.d2 = reference(0), reference(0), reference(0.0)
        self.t, self.pcoords, self.hit = reference(0.0), [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]
        self.cp = [0.0, 0.0, 0.0]

    def closest(self, x):
        self.locator.FindClosestPoint(x, self.cp, self.cell, self.cell_id, self.sub_id, self.d2)
        return self.cp

    def normal(self, x):
        self.closest(x)
        n = [0.0, 0.0, 0.0]
        if int(self.cell_id) >= 0 and self.cell.GetNumberOfPoints() >= 3:
            vtkPolygon.ComputeNormal(self.cell.GetPoints(), n)
        return n

    def ray(self, a, b):
        if not self.locator.IntersectWithLine(
            a, b, 0.0, self.t, self.hit, self.pcoords, self.sub_id, self.cell_id, self.cell
        ):
            return None
        return tuple(self.hit)


class _VTKServices:
    """The mesher's services (see hoembedPipMesher.cxx) from the pip VTK: the same classes
    and settings as vtkTet10Mesher's read step and VTKServices. Counts its calls."""

    def __init__(self, input_points):
        self.input_points = input_points  # the surface's own vtkPoints (as the filter)
        self.calls = {}
        self.fine = None

    def _count(self, name):
        self.calls[name] = self.calls.get(name, 0) + 1

    # -- read step ---------------------------------------------------------------------
    def ear_cut(self, ids, xyz):
        self._count("ear_cut")
        n = len(ids)
        polygon = vtkPolygon()
        polygon.GetPointIds().SetNumberOfIds(n)
        polygon.GetPoints().SetNumberOfPoints(n)
        for k in range(n):
            polygon.GetPointIds().SetId(k, int(ids[k, 0]))
            polygon.GetPoints().SetPoint(k, xyz[k])
        local = vtkIdList()
        # VTK 9.3 renamed vtkPolygon::Triangulate(vtkIdList*) (the ear cut, local ids)
        triangulate = getattr(polygon, "TriangulateLocalIds", None)
        if not (triangulate(0, local) if triangulate else polygon.Triangulate(local)):
            return None
        return np.array([local.GetId(k) for k in range(local.GetNumberOfIds())], np.int64)

    def merge(self, tris):
        self._count("merge")
        triangles = vtkPolyData()
        triangles.SetPoints(self.input_points)
        triangles.SetPolys(_triangles(tris))
        clean = vtkCleanPolyData()
        clean.SetInputData(triangles)
        clean.PointMergingOn()
        # relative to the bounding-box diagonal, as vtkTet10Mesher's MergeTolerance
        clean.ToleranceIsAbsoluteOff()
        clean.SetTolerance(MERGE_TOLERANCE)
        clean.ConvertLinesToPointsOff()
        clean.ConvertPolysToLinesOff()
        clean.ConvertStripsToPolysOff()
        clean.Update()
        self.fine = vtkPolyData()
        self.fine.ShallowCopy(clean.GetOutput())
        arrays = _to_arrays(self.fine)
        if arrays is None:
            return None
        self._prepare()
        return arrays

    def _prepare(self):
        fine = self.fine
        self.diagonal = fine.GetLength()
        self.unit = None
        # the queries run on the surface scaled to a unit diagonal (vtkTet10Mesher's
        # VTKServices: the locators' bins do not depend on the surface's size)
        self.projector = _Locator(self._unit())
        self.vertex_locator = vtkStaticPointLocator()
        self.vertex_locator.SetDataSet(self._unit())
        _build_deterministically(self.vertex_locator)
        self.fine_points = (
            np.ascontiguousarray(_arrays.points(fine.GetPoints()), dtype=np.float64)
            if fine.GetNumberOfPoints()
            else np.zeros((0, 3))
        )
        self.near = vtkIdList()
        self.smoothed = None
        self.check = vtkQuadraticTetra()
        self.check.GetPoints().SetNumberOfPoints(10)
        for i in range(10):
            self.check.GetPointIds().SetId(i, i)

    # -- mesher ------------------------------------------------------------------------
    def decimate(self, reduction, smoothed):
        self._count("decimate")
        decimate = vtkQuadricDecimation()
        decimate.SetInputData(self._smoothed() if smoothed else self._unit())
        decimate.SetTargetReduction(reduction)
        decimate.VolumePreservationOff()
        decimate.AttributeErrorMetricOff()
        decimate.Update()
        arrays = _to_arrays(decimate.GetOutput())
        if arrays is not None:
            points, tris = arrays
            arrays = (np.ldexp(points, self.exponent), tris)
        return arrays

    def _unit(self):
        # the fine surface scaled by a power of two to a diagonal in [0.5, 1), made once
        # (vtkTet10Mesher's Unit(), for the same reason: vtkQuadricDecimation's thresholds
        # are absolute, and a power of two scales exactly, so a surface scaled by 2^k is
        # decimated into the same coarse surface, scaled)
        if self.unit is None:
            self.exponent = math.frexp(self.diagonal)[1]
            pts = (
                _arrays.points(self.fine.GetPoints())
                if self.fine.GetNumberOfPoints()
                else np.zeros((0, 3))
            )
            scaled = vtkPoints()
            scaled.SetData(
                numpy_to_vtk(np.ldexp(np.asarray(pts, dtype=np.float64), -self.exponent), deep=True)
            )
            self.unit = vtkPolyData()
            self.unit.ShallowCopy(self.fine)
            self.unit.SetPoints(scaled)
        return self.unit

    def _smoothed(self):
        # the low-pass filtered fine surface (windowed sinc keeps the volume), made once
        if self.smoothed is None:
            smooth = vtkWindowedSincPolyDataFilter()
            smooth.SetInputData(self._unit())
            smooth.SetNumberOfIterations(_SETTINGS["smoothing_iterations"])
            smooth.SetPassBand(_SETTINGS["smoothing_pass_band"])
            smooth.NormalizeCoordinatesOn()
            smooth.BoundarySmoothingOff()
            smooth.FeatureEdgeSmoothingOff()
            smooth.NonManifoldSmoothingOff()
            # VTK 9.2 made the window selectable with Nuttall as default; 9.1 (the VTK
            # build's, and vtkTet10Mesher's setting) has Hamming's: the same output
            # bit for bit (checked on the thorny tail), where Nuttall's moves points by
            # 0.6% of the diagonal and changes which coarsenings fold
            if hasattr(smooth, "SetWindowFunctionToHamming"):
                smooth.SetWindowFunctionToHamming()
            smooth.Update()
            self.smoothed = vtkPolyData()
            self.smoothed.ShallowCopy(smooth.GetOutput())
        return self.smoothed

    def closest(self, x, y, z):
        self._count("closest")
        return tuple(math.ldexp(c, self.exponent) for c in self.projector.closest(self._u(x, y, z)))

    def _u(self, x, y, z):
        e = -self.exponent
        return (math.ldexp(x, e), math.ldexp(y, e), math.ldexp(z, e))

    def ray(self, ax, ay, az, bx, by, bz):
        self._count("ray")
        hit = self.projector.ray(self._u(ax, ay, az), self._u(bx, by, bz))
        return None if hit is None else tuple(math.ldexp(c, self.exponent) for c in hit)

    def vertices_within(self, x, y, z, r):
        self._count("vertices_within")
        self.vertex_locator.FindPointsWithinRadius(
            math.ldexp(r, -self.exponent), self._u(x, y, z), self.near
        )
        n = self.near.GetNumberOfIds()
        ids = [self.near.GetId(k) for k in range(n)]
        return np.ascontiguousarray(self.fine_points[ids], dtype=np.float64)

    def normal_at(self, x, y, z):
        self._count("normal_at")
        return tuple(self.projector.normal(self._u(x, y, z)))

    def max_distance(self, points, tris, query):
        """Largest distance from the query points to the triangles (vtkTet10Mesher's
        MaxDistanceToTriangles: closest points of a vtkStaticCellLocator)."""
        self._count("max_distance")
        target = _Locator(_poly(points, tris))
        worst = 0.0
        for x in query:
            target.closest(x)
            worst = max(worst, math.sqrt(float(target.d2)))
        return worst

    def check_cell(self, x10):
        """VTK's cell validator on the curved cell, scaled to a unit diagonal of the surface
        (vtkTet10Mesher's ExtraCheck: the validator's tolerances are absolute)."""
        self._count("check_cell")
        scale = 1.0 / self.diagonal if self.diagonal > 0.0 else 1.0
        p = (x10 - x10[0]) * scale
        pts = self.check.GetPoints()
        for i in range(10):
            pts.SetPoint(i, p[i])
        state = vtkCellValidator.Check(self.check, _SETTINGS["cell_check_tolerance"])
        return (int(state) & _BAD_CELL) == 0


def _grid(r):
    """The driver's result as vtkTet10Mesher's WriteOutput writes it."""
    npc = r["nodes_per_cell"]
    conn = np.asarray(r["connectivity"], dtype=np.int64)
    n = conn.shape[0]
    grid = vtkUnstructuredGrid()
    pts = vtkPoints()
    pts.SetData(numpy_to_vtk(np.ascontiguousarray(r["points"]), deep=True))
    grid.SetPoints(pts)
    cells = vtkCellArray()
    cells.SetData(
        numpy_to_vtk(
            np.arange(0, npc * n + 1, npc, dtype=np.int64), deep=True, array_type=VTK_ID_TYPE
        ),
        numpy_to_vtk(conn.reshape(-1), deep=True, array_type=VTK_ID_TYPE),
    )
    grid.SetCells(VTK_QUADRATIC_TETRA if npc == 10 else VTK_TETRA, cells)
    grid.GetCellData().AddArray(
        _arrays.to_vtk(
            np.asarray(r[N.MinScaledJacobian]).reshape(-1), N.MinScaledJacobian, VTK_DOUBLE
        )
    )
    grid.GetPointData().AddArray(
        _arrays.to_vtk(np.asarray(r[N.BoundaryNode]).reshape(-1), N.BoundaryNode, VTK_UNSIGNED_CHAR)
    )
    fd = grid.GetFieldData()
    for name in (
        N.RelaxedNodeCount,
        N.CurvedNodeCount,
        N.EnvelopeNodeCount,
        N.BoundaryCrossingsFound,
        N.BoundaryCrossingsLeft,
        N.PoorElementCount,
    ):
        a = vtkIdTypeArray()
        a.SetName(name)
        a.InsertNextValue(int(r[name]))
        fd.AddArray(a)
    q = vtkDoubleArray()
    q.SetName(N.MinScaledJacobianQuantiles)
    q.SetNumberOfComponents(3)
    q.InsertNextTuple(tuple(r[N.MinScaledJacobianQuantiles]))
    fd.AddArray(q)
    for name in (N.MaxSurfaceDeviation, N.EnvelopeOffset):
        a = vtkDoubleArray()
        a.SetName(name)
        a.InsertNextValue(float(r[name]))
        fd.AddArray(a)
    return grid


# the keyword defaults: vtkTet10Mesher's, which are the driver's (hoembed::MesherOptions)
_D = DEFAULTS["mesher"]


def tet10_mesh(
    surface,
    n_elements=_D["TargetNumberOfElements"],
    edge_length=_D["TargetEdgeLength"],
    order=_D["ElementOrder"],
    curve_boundary=_D["CurveBoundary"],
    radius_edge_ratio=_D["RadiusEdgeRatio"],
    min_dihedral_angle=_D["MinDihedralAngle"],
    progress=None,
    quality_target=_D["CurvedQualityTarget"],
    minimum_quality=_D["MinimumQuality"],
):
    options = mesh_arguments(
        surface,
        n_elements,
        edge_length,
        order,
        curve_boundary,
        radius_edge_ratio,
        min_dihedral_angle,
        progress,
        quality_target,
        minimum_quality,
    )
    r = _run(surface, options, progress)[0]
    if progress is not None:
        progress(1.0)
    return pyvista.wrap(_grid(r))


tet10_mesh.__doc__ = (
    MESH_DOC
    + """
The errors read "tet10_mesh: " and vtkTet10Mesher's sentence, and the mesher's warnings go
through Python's ``warnings`` (RuntimeWarning). The C++ algorithm is vtkTet10Mesher's; its
decimation, smoothing, locators and cell validator come from the VTK Python in use: in
the VTK build the mesh equals vtkTet10Mesher's bit for bit, with a pip VTK it can differ
from it in its details (Benchmarks/RESULTS.md, pip section).
"""
)


def _run(surface, options, progress=None):
    """mesh_surface on the surface's arrays; returns (result dict, services)."""
    n = surface.GetNumberOfPoints()
    points = (
        np.ascontiguousarray(_arrays.points(surface.GetPoints()), dtype=np.float64)
        if n
        else np.zeros((0, 3))
    )
    services = _VTKServices(surface.GetPoints())
    cells = []
    for ca in (surface.GetVerts(), surface.GetLines(), surface.GetPolys(), surface.GetStrips()):
        cells.extend(_arrays.cells(ca))
    try:
        r = mesh_surface(points, *cells, options, MAXIMUM_NUMBER_OF_ELEMENTS, services, progress)
    except RuntimeError as e:
        raise HOEmbedError(f"tet10_mesh: {e}") from None
    for w in r["warnings"]:
        _warnings.warn(f"tet10_mesh: {w}", RuntimeWarning)
    if r["error"]:
        raise HOEmbedError(f"tet10_mesh: {r['error']}")
    return r, services
