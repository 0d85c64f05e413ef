"""HOEmbed: curved tet10 finite elements that animate a fine triangle surface.

The wrapped VTK classes (``hoembed.vtkTet10Mesher``, ...) work in plain VTK pipelines;
the pyvista-level functions (``hoembed.tet10_mesh``, ...) take and return pyvista
objects and raise :class:`hoembed.HOEmbedError` when a filter reports an error.
"""
import importlib as _importlib
import importlib.util as _util

# VTK 9.1 segfaults when a wrapped HOEmbed module is imported before the VTK modules it
# builds on: import those first.
import vtkmodules.vtkCommonCore  # noqa: F401
import vtkmodules.vtkCommonDataModel  # noqa: F401
import vtkmodules.vtkCommonExecutionModel  # noqa: F401

from ._errors import HOEmbedError  # noqa: F401

__version__ = "0.1.0"

# Wrapped modules: every vtk* class they hold becomes hoembed.<class>.
_WRAPPED = ("hoembedFiltersMeshing", "hoembedFiltersEmbedding", "hoembedFiltersSimulation",
            "hoembedIOSeries")
# pyvista-level front ends: each module's __all__ is re-exported.
_FRONT_ENDS = ("meshing", "embedding", "transfer", "simulation", "series", "models")

for _name in _WRAPPED:
    if _util.find_spec(f"{__name__}.{_name}") is None:
        continue  # module not built in this configuration
    _mod = _importlib.import_module(f".{_name}", __name__)
    for _cls in dir(_mod):
        if _cls.startswith("vtk"):
            globals()[_cls] = getattr(_mod, _cls)

for _name in _FRONT_ENDS:
    if _util.find_spec(f"{__name__}.{_name}") is None:
        continue
    _mod = _importlib.import_module(f".{_name}", __name__)
    for _fn in getattr(_mod, "__all__", ()):
        globals()[_fn] = getattr(_mod, _fn)
