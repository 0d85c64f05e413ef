"""pyvista-level front end of vtkTet10Mesher."""

import pyvista

__all__ = ["tet10_mesh"]

from ._checks import MESH_DOC, mesh_arguments
from ._errors import run_filter
from .hoembedFiltersMeshing import vtkTet10Mesher


def tet10_mesh(surface, n_elements=1000, edge_length=0.0, order=2, curve_boundary=True,
               radius_edge_ratio=1.5, min_dihedral_angle=10.0, progress=None):
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


tet10_mesh.__doc__ = MESH_DOC
