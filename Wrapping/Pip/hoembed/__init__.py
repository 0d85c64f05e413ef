"""HOEmbed for pip VTK and pyvista: the embedding, the deformation transfer and the FE
stepper.

The pip wheel's package (pyproject.toml at the repository root). Its functions take and
return pyvista objects like the VTK build's ``hoembed`` package, and run the same C++
drivers as the VTK filters (``hoembed._hoembed``, a nanobind module; no VTK C++ code).
Not in this wheel yet: ``tet10_mesh`` and ``write_series`` (they need the VTK build:
``make build``; write_series runs the VTK build's vtkTimeSeriesWriter).
"""
from ._errors import HOEmbedError
from .embedding import embed
from .transfer import transfer
from .simulation import simulate
from .models import thorny_tail
from ._hoembed import number_of_threads

__version__ = "0.1.0"

BACKEND = "pip"

__all__ = ["HOEmbedError", "embed", "transfer", "simulate", "thorny_tail", "number_of_threads"]
