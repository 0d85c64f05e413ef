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

from ._errors import HOEmbedError
from .hoembedFiltersMeshing import vtkTet10Mesher
from .hoembedFiltersEmbedding import vtkEmbeddingCoordinatesFilter
from .hoembedFiltersTransfer import vtkDeformationTransferFilter
from .hoembedFiltersSimulation import vtkCorotationalFEMStepper
from .hoembedIOSeries import vtkTimeSeriesWriter
from .meshing import tet10_mesh
from .embedding import embed
from .transfer import transfer
from .simulation import simulate
from .series import write_series
from .models import thorny_tail
from .live import live

__version__ = "0.1.0"

__all__ = [
    "HOEmbedError",
    "vtkTet10Mesher",
    "vtkEmbeddingCoordinatesFilter",
    "vtkDeformationTransferFilter",
    "vtkCorotationalFEMStepper",
    "vtkTimeSeriesWriter",
    "tet10_mesh",
    "embed",
    "transfer",
    "simulate",
    "write_series",
    "thorny_tail",
    "live",
]
