"""numpy views of the VTK arrays the drivers read (adapting only: no algorithm here)."""

import types

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkVersion

from ._hoembed import ARRAY_NAMES

# The array names of hoembedArrayNames.h, by their C++ names (N.EmbeddingCellId, ...):
# spelled once, in C++
N = types.SimpleNamespace(**ARRAY_NAMES)

EMPTY_IDS = np.zeros(0, dtype=np.int64)


def points(vtk_points):
    """The points as a C-contiguous (n, 3) float64 or float32 array (others: float64)."""
    a = vtk_to_numpy(vtk_points.GetData())
    if a.dtype not in (np.float64, np.float32):
        a = a.astype(np.float64)
    return np.ascontiguousarray(a).reshape(-1, 3)


def cells(cell_array):
    """(offsets, connectivity) of a vtkCellArray as int64 arrays (empty when none)."""
    if cell_array is None or cell_array.GetNumberOfCells() == 0:
        return EMPTY_IDS, EMPTY_IDS
    off = vtk_to_numpy(cell_array.GetOffsetsArray()).astype(np.int64, copy=False)
    conn = vtk_to_numpy(cell_array.GetConnectivityArray()).astype(np.int64, copy=False)
    return np.ascontiguousarray(off), np.ascontiguousarray(conn)


def cell_types(grid):
    """The cell types of an unstructured grid as contiguous uint8: VTK 9.6 made
    GetCellTypes() return that array and deprecated GetCellTypesArray(), which earlier
    VTK (the VTK build's 9.1) has instead."""
    if (vtkVersion.GetVTKMajorVersion(), vtkVersion.GetVTKMinorVersion()) >= (9, 6):
        a = grid.GetCellTypes()
    else:
        a = grid.GetCellTypesArray()
    return np.ascontiguousarray(vtk_to_numpy(a), dtype=np.uint8)


def higher_order_degrees(grid):
    """VTK's HigherOrderDegrees cell data of an unstructured grid as contiguous float64
    (3 per cell), or None when it has none (the drivers judge it)."""
    a = grid.GetCellData().GetHigherOrderDegrees()
    if (
        a is None
        or a.GetNumberOfComponents() != 3
        or a.GetNumberOfTuples() != grid.GetNumberOfCells()
    ):
        return None
    return np.ascontiguousarray(vtk_to_numpy(a), dtype=np.float64)


def doubles(vtk_array):
    """The values of a VTK data array (or a numpy array) as contiguous float64 (the VTK
    filters' copy)."""
    a = vtk_array if isinstance(vtk_array, np.ndarray) else vtk_to_numpy(vtk_array)
    return np.ascontiguousarray(a, dtype=np.float64)


def to_vtk(array, name, vtk_type=None):
    out = numpy_to_vtk(np.ascontiguousarray(array), deep=True, array_type=vtk_type)
    out.SetName(name)
    return out
