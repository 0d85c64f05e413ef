"""pyvista-level embed() of the pip package: hoembed::EmbeddingDriver through _hoembed.

The same arguments, outputs and errors as the VTK build's hoembed.embed (which runs
vtkEmbeddingCoordinatesFilter over the same driver)."""
import warnings as _warnings

import numpy as np
import pyvista
from vtkmodules.vtkCommonCore import (VTK_DOUBLE, VTK_ID_TYPE, VTK_INT, VTK_SIGNED_CHAR,
                                      VTK_UNSIGNED_CHAR, vtkIdTypeArray, vtkStringArray)

from . import _arrays
from ._checks import embed_arguments
from ._errors import HOEmbedError
from ._hoembed import EmbeddingDriver

__all__ = ["embed"]


def embed(surface, fe_mesh, method="normal-offset", n_partitions=0, progress=None):
    """Embedding coordinates of a fine triangle surface in a (curved) tet FE mesh.

    See the VTK build's ``hoembed.embed``: same parameters, same point data
    (``EmbeddingCellId``, ``EmbeddingParametricCoords``, ``EmbeddingDistance``,
    ``EmbeddingResidual``, ``EmbeddingFace``, ``EmbeddingIterations``,
    ``EmbeddingElementsVisited``, ``EmbeddingClosestDistance``, ``EmbeddingFallback``,
    ``EmbeddingFallbackOffset`` when needed) and field data (``EmbeddingMethod``,
    ``EmbeddingMeshFingerprint``, ``NumberOfFallbackPoints``), same values bit for bit.
    Warnings (uncertified or fallback points) go through Python's ``warnings``.
    """
    method_value, n_partitions = embed_arguments(surface, fe_mesh, method, n_partitions,
                                                 progress)
    if surface.GetNumberOfPoints() == 0:
        raise HOEmbedError("embed: the surface is empty: it has no points.")
    if fe_mesh.GetNumberOfPoints() == 0 or fe_mesh.GetNumberOfCells() == 0:
        raise HOEmbedError("embed: the FE mesh is empty: it needs points and tet4 or tet10 cells.")
    driver = EmbeddingDriver()
    try:
        driver.set_surface(_arrays.points(surface.GetPoints()), *_arrays.cells(surface.GetPolys()),
                           *_arrays.cells(surface.GetStrips()))
        offsets, conn = _arrays.cells(fe_mesh.GetCells())
        types = np.ascontiguousarray(_arrays.vtk_to_numpy(_arrays.cell_types(fe_mesh)),
                                     dtype=np.uint8)
        driver.prepare_and_order(fe_mesh.GetNumberOfPoints(), _arrays.points(fe_mesh.GetPoints()),
                                 types, offsets, conn, True, n_partitions)
        if progress is not None:
            progress(0.1)
        driver.embed(method_value,
                     None if progress is None else (lambda x: progress(0.1 + 0.9 * x)))
        n = surface.GetNumberOfPoints()
        out = {"EmbeddingCellId": (np.empty(n, np.int64), VTK_ID_TYPE),
               "EmbeddingParametricCoords": (np.empty((n, 3)), VTK_DOUBLE),
               "EmbeddingDistance": (np.empty(n), VTK_DOUBLE),
               "EmbeddingResidual": (np.empty(n), VTK_DOUBLE),
               "EmbeddingFace": (np.empty(n, np.int8), VTK_SIGNED_CHAR),
               "EmbeddingIterations": (np.empty(n, np.int32), VTK_INT),
               "EmbeddingElementsVisited": (np.empty(n, np.int32), VTK_INT),
               "EmbeddingClosestDistance": (np.empty(n), VTK_DOUBLE),
               "EmbeddingFallback": (np.empty(n, np.uint8), VTK_UNSIGNED_CHAR)}
        a = {k: v[0] for k, v in out.items()}
        uncertified, first_uncertified, fallbacks, first_fallback = driver.write_arrays(
            a["EmbeddingCellId"], a["EmbeddingParametricCoords"], a["EmbeddingDistance"],
            a["EmbeddingResidual"], a["EmbeddingClosestDistance"], a["EmbeddingFace"],
            a["EmbeddingIterations"], a["EmbeddingElementsVisited"], a["EmbeddingFallback"])
        if fallbacks > 0:
            q = np.empty((n, 3))
            driver.write_fallback_offsets(q)
            out["EmbeddingFallbackOffset"] = (q, VTK_DOUBLE)
    except RuntimeError as e:
        raise HOEmbedError(f"embed: {e}") from None
    if uncertified > 0:
        _warnings.warn(f"embed: {uncertified} surface point(s) (e.g. point {first_uncertified}): "
                       "the closest-point search on a curved boundary face ran out of its "
                       "budget; their distance may be a local minimum only.", RuntimeWarning)
    if fallbacks > 0:
        _warnings.warn(f"embed: {fallbacks} surface point(s) (e.g. point {first_fallback}) have "
                       "no normal offset v = p + d n: they use their closest point p and the "
                       "offset v - p instead (EmbeddingFallback = 1).", RuntimeWarning)
    result = pyvista.wrap(surface).copy()
    pd = result.GetPointData()
    for name, (values, vtk_type) in out.items():
        pd.AddArray(_arrays.to_vtk(values, name, vtk_type))
    fd = result.GetFieldData()
    for name, value in (("EmbeddingMethod", method),
                        ("EmbeddingMeshFingerprint", driver.fingerprint)):
        s = vtkStringArray()
        s.SetName(name)
        s.InsertNextValue(value)
        fd.AddArray(s)
    count = vtkIdTypeArray()
    count.SetName("NumberOfFallbackPoints")
    count.InsertNextValue(fallbacks)
    fd.AddArray(count)
    if progress is not None:
        progress(1.0)
    return result
