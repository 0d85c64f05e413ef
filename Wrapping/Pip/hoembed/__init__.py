"""HOEmbed for pip VTK and pyvista: the embedding, the deformation transfer, the FE
stepper and time series.

The pip wheel's package (pyproject.toml at the repository root). Its functions take and
return pyvista objects like the VTK build's ``hoembed`` package, and run the same C++
drivers as the VTK filters (``hoembed._hoembed``, a nanobind module; no VTK C++ code).
``write_series`` runs vtkTimeSeriesWriter's series logic (hoembed::SeriesFiles: staging,
.pvd, atomic swap-in) and writes the frames with your pip VTK's XML writers.
Not in this wheel yet: ``tet10_mesh`` (it needs the VTK build: ``make build``).
"""
from ._errors import HOEmbedError
from .embedding import embed
from .transfer import transfer
from .simulation import simulate
from .series import write_series
from .models import thorny_tail
from ._hoembed import number_of_threads

__version__ = "0.1.0"

BACKEND = "pip"

__all__ = ["HOEmbedError", "embed", "transfer", "simulate", "write_series", "thorny_tail",
           "number_of_threads"]
