"""HOEmbed: curved tet10 finite elements that animate a fine triangle surface.

One package for both builds. The pyvista-level functions (``hoembed.tet10_mesh``,
``embed``, ``transfer``, ``simulate``, ``write_series``, ``thorny_tail``, ``live``, and
the ``hoembed`` command) take and return pyvista objects, raise
:class:`hoembed.HOEmbedError`, and run HOEmbed's C++ drivers through the compiled module
``hoembed._hoembed``; the VTK services they need (the mesher's decimation, smoothing and
locators; the XML writers) come from the VTK Python in use.

In the VTK build (Debian VTK 9.1, ``make build``) the wrapped VTK classes
(``hoembed.vtkTet10Mesher``, ...) are importable too, for VTK pipelines and ParaView;
they call the same compiled drivers as the functions. The pip wheel has no wrapped
classes (``hoembed.BACKEND`` says which build this is).
"""

import importlib.util as _util

# VTK 9.1 segfaults when a wrapped HOEmbed module is imported before the VTK modules it
# builds on: import those first.
import vtkmodules.vtkCommonCore  # noqa: F401
import vtkmodules.vtkCommonDataModel  # noqa: F401
import vtkmodules.vtkCommonExecutionModel  # noqa: F401

from ._errors import HOEmbedError
from ._hoembed import number_of_threads
from .embedding import embed
from .live import live
from .meshing import tet10_mesh
from .models import thorny_tail
from .series import write_series
from .simulation import simulate
from .transfer import transfer

__version__ = "0.1.0"

__all__ = [
    "HOEmbedError",
    "tet10_mesh",
    "embed",
    "transfer",
    "simulate",
    "write_series",
    "thorny_tail",
    "live",
    "number_of_threads",
]

# The wrapped classes exist in the VTK build only. Looked up, not imported under a
# try: a wrapped module that is there but fails to import is an error to see.
if _util.find_spec(".hoembedFiltersMeshing", __name__) is not None:
    from .hoembedFiltersEmbedding import vtkEmbeddingCoordinatesFilter
    from .hoembedFiltersMeshing import vtkTet10Mesher
    from .hoembedFiltersSimulation import vtkCorotationalFEMStepper
    from .hoembedFiltersTransfer import vtkDeformationTransferFilter
    from .hoembedIOSeries import vtkTimeSeriesWriter

    BACKEND = "vtk"
    __all__ += [
        "vtkTet10Mesher",
        "vtkEmbeddingCoordinatesFilter",
        "vtkDeformationTransferFilter",
        "vtkCorotationalFEMStepper",
        "vtkTimeSeriesWriter",
    ]
else:
    BACKEND = "pip"
