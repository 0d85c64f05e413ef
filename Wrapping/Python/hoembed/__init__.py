"""HOEmbed: curved tet10 finite elements that animate a fine triangle surface.

The wrapped VTK classes (``hoembed.vtkTet10Mesher``, ...) work in plain VTK pipelines;
the pyvista-level functions (``hoembed.tet10_mesh``, ...) take and return pyvista
objects and raise :class:`hoembed.HOEmbedError` when a filter reports an error.
"""

# VTK 9.1 segfaults when a wrapped HOEmbed module is imported before the VTK modules it
# builds on: import those first.
import vtkmodules.vtkCommonCore  # noqa: F401
import vtkmodules.vtkCommonDataModel  # noqa: F401
import vtkmodules.vtkCommonExecutionModel  # noqa: F401

from .hoembedFiltersMeshing import vtkTet10Mesher  # noqa: F401

from ._errors import HOEmbedError  # noqa: F401
from .meshing import tet10_mesh  # noqa: F401

__version__ = "0.1.0"
