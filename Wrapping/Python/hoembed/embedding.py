"""pyvista-level front end of vtkEmbeddingCoordinatesFilter."""

import pyvista

__all__ = ["embed"]

from ._checks import embed_arguments
from ._errors import run_filter
from .hoembedFiltersEmbedding import vtkEmbeddingCoordinatesFilter


def embed(surface, fe_mesh, method="normal-offset", n_partitions=0, progress=None):
    """Embedding coordinates of a fine triangle surface in a (curved) tet FE mesh.

    Parameters
    ----------
    surface : pyvista.PolyData or vtkPolyData
        The fine surface; its triangles drive the flood (vertices in no triangle and
        several components are fine).
    fe_mesh : pyvista.UnstructuredGrid or vtkUnstructuredGrid
        The rest mesh: VTK_QUADRATIC_TETRA cells, or VTK_TETRA (not mixed).
    method : str
        ``"normal-offset"`` (default; the paper's v = p + d n) or ``"barycentric"``.
    n_partitions : int
        Surface patches flooded in parallel (0: automatic).
    progress : callable, optional
        Called with a float in [0, 1] on the filter's progress events.

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
    """
    method_value, n_partitions = embed_arguments(surface, fe_mesh, method, n_partitions,
                                                 progress)
    alg = vtkEmbeddingCoordinatesFilter()
    alg.SetInputData(0, surface)
    alg.SetMeshData(fe_mesh)
    alg.SetMethod(method_value)
    alg.SetNumberOfPartitions(n_partitions)
    if progress is not None:
        alg.AddObserver("ProgressEvent", lambda o, e: progress(o.GetProgress()))
    out = run_filter(alg)
    return pyvista.wrap(out).copy()
