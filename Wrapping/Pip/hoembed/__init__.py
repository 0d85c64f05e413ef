"""HOEmbed for pip VTK and pyvista: the tet10 mesher, the embedding, the deformation
transfer, the FE stepper and time series.

The pip wheel's package (pyproject.toml at the repository root). Its functions take and
return pyvista objects like the VTK build's ``hoembed`` package, and run the same C++
drivers as the VTK filters (``hoembed._hoembed``, a nanobind module; no VTK C++ code).
``write_series`` runs vtkTimeSeriesWriter's series logic (hoembed::SeriesFiles: staging,
.pvd, atomic swap-in) and writes the frames with your pip VTK's XML writers.
The mesher's VTK steps (decimation, smoothing, locators, cell validator, point merge)
run on the installed pip VTK, called from Python (``hoembed.meshing``).
"""
from ._errors import HOEmbedError
from .meshing import tet10_mesh
from .embedding import embed
from .transfer import transfer
from .simulation import simulate
from .series import write_series
from .models import thorny_tail
from ._hoembed import number_of_threads

__version__ = "0.1.0"

BACKEND = "pip"

__all__ = ["HOEmbedError", "tet10_mesh", "embed", "transfer", "simulate", "write_series",
           "thorny_tail", "number_of_threads"]
