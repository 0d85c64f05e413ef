"""pyvista-level embed(): hoembed::EmbeddingDriver through _hoembed (the driver
vtkEmbeddingCoordinatesFilter runs; the same outputs bit for bit, Testing/Python/
test_two_routes.py)."""

import warnings as _warnings

import numpy as np
import pyvista
from vtkmodules.vtkCommonCore import (
    VTK_DOUBLE,
    VTK_ID_TYPE,
    VTK_INT,
    VTK_SIGNED_CHAR,
    VTK_UNSIGNED_CHAR,
    vtkIdTypeArray,
    vtkStringArray,
)

from . import _arrays
from ._arrays import N
from ._checks import EMBED_METHOD_NAMES, embed_arguments
from ._errors import HOEmbedError
from ._hoembed import DEFAULTS, EmbeddingDriver

__all__ = ["embed"]


# the keyword defaults: vtkEmbeddingCoordinatesFilter's, which are the driver's
# (hoembed::EmbeddingOptions)
_D = DEFAULTS["embedding"]


def embed(
    surface,
    fe_mesh,
    method=EMBED_METHOD_NAMES[_D["Method"]],
    n_partitions=_D["NumberOfPartitions"],
    progress=None,
):
    """Embedding coordinates of a fine triangle surface in a (curved) tet FE mesh.

    Parameters
    ----------
    surface : pyvista.PolyData or vtkPolyData
        The fine surface; its triangles drive the flood (vertices in no triangle and
        several components are fine).
    fe_mesh : pyvista.UnstructuredGrid or vtkUnstructuredGrid
        The rest mesh: VTK_QUADRATIC_TETRA cells, or VTK_TETRA, or VTK_LAGRANGE_TETRAHEDRON
        of order 1-4, or VTK_LAGRANGE_HEXAHEDRON of order 1-3, VTK_TRIQUADRATIC_HEXAHEDRON
        or VTK_QUADRATIC_HEXAHEDRON (one cell type; Lagrange tets of order 3-4 and the
        hexahedra by a slower per-vertex search).
    method : str
        ``"normal-offset"`` (default; the paper's v = p + d n) or ``"barycentric"``.
    n_partitions : int
        Surface patches flooded in parallel (0: automatic).
    progress : callable, optional
        Called with a float in [0, 1] as the embedding progresses.

    Returns
    -------
    pyvista.PolyData
        A copy of the surface with point data ``EmbeddingCellId``,
        ``EmbeddingParametricCoords``, ``EmbeddingDistance``, ``EmbeddingResidual``,
        ``EmbeddingFace``, ``EmbeddingIterations``, ``EmbeddingElementsVisited``,
        ``EmbeddingClosestDistance``, ``EmbeddingFallback`` (1 where v = p + d n has no
        solution and v = p + J q with the closest point p is used instead; their q in
        ``EmbeddingFallbackOffset``, present only when there are any; see
        vtkEmbeddingCoordinatesFilter) and field data ``EmbeddingMethod``,
        ``EmbeddingMeshFingerprint``, ``NumberOfFallbackPoints``.

    Raises
    ------
    ValueError
        For an unknown ``method``, a negative ``n_partitions`` or inputs of the wrong
        type (``hoembed._errors.HOEmbedArgumentError``, also a HOEmbedError).
    hoembed.HOEmbedError
        On bad input (empty surface or mesh, NaN coordinates, cells other than tet4/tet10,
        inverted or degenerate elements).

    Warns
    -----
    RuntimeWarning
        Uncertified closest points (a curved boundary face's search ran out of its
        budget), points that use the fallback offset, and points their embedding does
        not reproduce (``EmbeddingResidual`` over 1e-6 of the mesh's diagonal: the
        barycentric method outside a curved mesh), through Python's ``warnings``.
    """
    method_value, n_partitions = embed_arguments(surface, fe_mesh, method, n_partitions, progress)
    if surface.GetNumberOfPoints() == 0:
        raise HOEmbedError("embed: the surface is empty: it has no points.")
    if fe_mesh.GetNumberOfPoints() == 0 or fe_mesh.GetNumberOfCells() == 0:
        raise HOEmbedError("embed: the FE mesh is empty: it needs points and tet4 or tet10 cells.")
    driver = EmbeddingDriver()
    try:
        driver.set_surface(
            _arrays.points(surface.GetPoints()),
            *_arrays.cells(surface.GetPolys()),
            *_arrays.cells(surface.GetStrips()),
        )
        offsets, conn = _arrays.cells(fe_mesh.GetCells())
        types = _arrays.cell_types(fe_mesh)
        driver.prepare_and_order(
            fe_mesh.GetNumberOfPoints(),
            _arrays.points(fe_mesh.GetPoints()),
            types,
            offsets,
            conn,
            _D["ValidateElements"],
            n_partitions,
            _arrays.higher_order_degrees(fe_mesh),
        )
        if progress is not None:
            progress(0.1)
        driver.embed(
            method_value, None if progress is None else (lambda x: progress(0.1 + 0.9 * x))
        )
        n = surface.GetNumberOfPoints()
        out = {
            N.EmbeddingCellId: (np.empty(n, np.int64), VTK_ID_TYPE),
            N.EmbeddingParametricCoords: (np.empty((n, 3)), VTK_DOUBLE),
            N.EmbeddingDistance: (np.empty(n), VTK_DOUBLE),
            N.EmbeddingResidual: (np.empty(n), VTK_DOUBLE),
            N.EmbeddingFace: (np.empty(n, np.int8), VTK_SIGNED_CHAR),
            N.EmbeddingIterations: (np.empty(n, np.int32), VTK_INT),
            N.EmbeddingElementsVisited: (np.empty(n, np.int32), VTK_INT),
            N.EmbeddingClosestDistance: (np.empty(n), VTK_DOUBLE),
            N.EmbeddingFallback: (np.empty(n, np.uint8), VTK_UNSIGNED_CHAR),
        }
        a = {k: v[0] for k, v in out.items()}
        uncertified, fallbacks, warnings = driver.write_arrays(
            a[N.EmbeddingCellId],
            a[N.EmbeddingParametricCoords],
            a[N.EmbeddingDistance],
            a[N.EmbeddingResidual],
            a[N.EmbeddingClosestDistance],
            a[N.EmbeddingFace],
            a[N.EmbeddingIterations],
            a[N.EmbeddingElementsVisited],
            a[N.EmbeddingFallback],
        )
        if fallbacks > 0:
            q = np.empty((n, 3))
            driver.write_fallback_offsets(q)
            out[N.EmbeddingFallbackOffset] = (q, VTK_DOUBLE)
    except RuntimeError as e:
        raise HOEmbedError(f"embed: {e}") from None
    for w in warnings:
        _warnings.warn(f"embed: {w}", RuntimeWarning)
    result = pyvista.wrap(surface).copy()
    pd = result.GetPointData()
    for name, (values, vtk_type) in out.items():
        pd.AddArray(_arrays.to_vtk(values, name, vtk_type))
    fd = result.GetFieldData()
    for name, value in (
        (N.EmbeddingMethod, method),
        (N.EmbeddingMeshFingerprint, driver.fingerprint),
    ):
        s = vtkStringArray()
        s.SetName(name)
        s.InsertNextValue(value)
        fd.AddArray(s)
    count = vtkIdTypeArray()
    count.SetName(N.NumberOfFallbackPoints)
    count.InsertNextValue(fallbacks)
    fd.AddArray(count)
    if progress is not None:
        progress(1.0)
    return result
