"""HOEmbed for pip VTK and pyvista: the tet10 mesher, the embedding, the deformation
transfer and the FE stepper.

The pip wheel's package (pyproject.toml at the repository root). Its functions take and
return pyvista objects like the VTK build's ``hoembed`` package, and run the same C++
drivers as the VTK filters (``hoembed._hoembed``, a nanobind module; no VTK C++ code).
The mesher's VTK steps (decimation, smoothing, locators, cell validator, point merge)
run on the installed pip VTK, called from Python (``hoembed.meshing``).
Not in this wheel yet: ``write_series`` (it needs the VTK build: ``make build``; it runs
the VTK build's vtkTimeSeriesWriter).
"""
from ._errors import HOEmbedError
from .meshing import tet10_mesh
from .embedding import embed
from .transfer import transfer
from .simulation import simulate
from .models import thorny_tail
from ._hoembed import number_of_threads

__version__ = "0.1.0"

BACKEND = "pip"

__all__ = ["HOEmbedError", "tet10_mesh", "embed", "transfer", "simulate", "thorny_tail", "number_of_threads"]
