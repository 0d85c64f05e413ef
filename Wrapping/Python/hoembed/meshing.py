"""pyvista-level front end of vtkTet10Mesher."""

import pyvista

__all__ = ["tet10_mesh"]

from ._checks import mesh_arguments
from ._errors import run_filter
from .hoembedFiltersMeshing import vtkTet10Mesher


def tet10_mesh(surface, n_elements=1000, edge_length=0.0, order=2, curve_boundary=True,
               radius_edge_ratio=1.5, min_dihedral_angle=10.0, progress=None):
    """Mesh any triangle surface with coarse, curved, valid tet10 (or tet4) elements.

    Parameters
    ----------
    surface : pyvista.PolyData or vtkPolyData
        Any triangle surface: closed or open, one or several parts, non-manifold or
        self-intersecting (polygons and strips are triangulated). A surface that is not
        a clean closed manifold is meshed through its envelope (vtkTet10Mesher's
        EnvelopeTolerance; field data ``EnvelopeOffset``, ``EnvelopeNodeCount``).
    n_elements : int
        Approximate number of elements (default 1000); ignored if ``edge_length > 0``.
    edge_length : float
        Target edge length in surface units (default 0: from ``n_elements``).
    order : int
        2 for VTK_QUADRATIC_TETRA (default), 1 for VTK_TETRA.
    curve_boundary : bool
        Move boundary mid-edge nodes onto the surface (default True).
    radius_edge_ratio, min_dihedral_angle : float
        TetGen quality bounds (defaults 1.5 and 10 degrees).
    progress : callable, optional
        Called with a float in [0, 1] on the filter's progress events.

    Returns
    -------
    pyvista.UnstructuredGrid
        With cell data ``MinScaledJacobian`` and field data ``RelaxedNodeCount``,
        ``CurvedNodeCount``, ``EnvelopeNodeCount``, ``BoundaryCrossingsFound``,
        ``BoundaryCrossingsLeft``, ``MaxSurfaceDeviation`` and ``EnvelopeOffset``.

    Raises
    ------
    hoembed.HOEmbedError
        On bad input (empty, NaN, point ids out of range, no polygons, no triangle with
        an area), a TetGen failure, or a mesh estimated beyond the element limit. Bad
        arguments (``n_elements`` < 1, ``order`` other than 1 or 2, NaN or out-of-range
        quality bounds, a negative or NaN ``edge_length``, a surface that is not poly
        data) raise ``hoembed._errors.HOEmbedArgumentError`` (a HOEmbedError and a
        ValueError) before the filter runs.

    Examples
    --------
    >>> import pyvista as pv, hoembed
    >>> mesh = hoembed.tet10_mesh(pv.Sphere(), n_elements=500)
    """
    options = mesh_arguments(surface, n_elements, edge_length, order, curve_boundary,
                             radius_edge_ratio, min_dihedral_angle, progress)
    alg = vtkTet10Mesher()
    alg.SetInputData(surface)
    for name, value in options.items():
        getattr(alg, "Set" + name)(value)
    if progress is not None:
        alg.AddObserver("ProgressEvent", lambda o, e: progress(o.GetProgress()))
    out = run_filter(alg)
    return pyvista.wrap(out).copy()
