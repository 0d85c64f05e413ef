"""pyvista-level front end of vtkDeformationTransferFilter."""

import pyvista

__all__ = ["transfer"]

from ._checks import transfer_arguments
from ._errors import run_filter
from .hoembedFiltersTransfer import vtkDeformationTransferFilter


def transfer(embedded_surface, deformed_mesh, normals="recompute", compute_point_normals=False,
             warnings=None):
    """The deformed fine surface for a deformed FE mesh: v' = p' + d n' (paper eq. 4).

    Parameters
    ----------
    embedded_surface : pyvista.PolyData or vtkPolyData
        The surface with the embedding arrays (``EmbeddingCellId``,
        ``EmbeddingParametricCoords``, ``EmbeddingDistance``, optional ``EmbeddingFace``)
        and field data ``EmbeddingMethod`` / ``EmbeddingMeshFingerprint``, as written by
        ``hoembed.embed`` / vtkEmbeddingCoordinatesFilter.
    deformed_mesh : pyvista.UnstructuredGrid or vtkUnstructuredGrid
        The FE mesh the surface was embedded in (same points and cells, tet10 or tet4),
        with deformed coordinates.
    normals : {"recompute", "rotate", "deform"}
        ``"recompute"`` (default): smooth nodal normals of the deformed curved boundary.
        ``"rotate"``: rest nodal normals rotated by the mesh's ``NodalRotation`` point data
        (needs ``Displacement`` too; falls back to recompute with a warning otherwise).
        ``"deform"``: rest nodal normals pushed forward by the nodal deformation gradient
        (needs ``Displacement``): offsets follow the material lines that were normal to
        the rest surface, so a shear of the surface (a twist) tilts them too.
    compute_point_normals : bool
        Add area-weighted point normals ``Normals`` for rendering (default False).
    warnings : list, optional
        Receives the filter's warnings (e.g. inverted deformed elements).

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
        An unknown ``normals`` value.

    Examples
    --------
    >>> deformed_surface = hoembed.transfer(embedded, deformed_mesh)
    """
    mode = transfer_arguments(embedded_surface, deformed_mesh, normals)
    alg = vtkDeformationTransferFilter()
    alg.SetInputData(0, embedded_surface)
    alg.SetInputData(1, deformed_mesh)
    alg.SetNormalMode(mode)
    alg.SetComputePointNormals(bool(compute_point_normals))
    out = run_filter(alg, warnings=warnings)
    return pyvista.wrap(out).copy()
