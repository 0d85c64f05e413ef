/**
 * @file hoembedTetMeshInputVTK.h
 * @brief Views of a vtkUnstructuredGrid's arrays for hoembed::TetMeshInput (header only).
 *
 * Used by the VTK filters (the VTK binding); the Core module itself stays VTK-free, so
 * this header is compiled only by modules that depend on VTK::CommonDataModel.
 */
#ifndef hoembedTetMeshInputVTK_h
#define hoembedTetMeshInputVTK_h

#include "hoembedTetMeshInput.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataSetAttributes.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkPoints.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include <vector>

namespace hoembed
{
/// The coordinates of `pts` without a copy when they are doubles or floats (`d` or `f`
/// set, the other null); other types are converted into `scratch` (`d` points there).
inline void ViewPoints(
  vtkPoints* pts, const double*& d, const float*& f, std::vector<double>& scratch)
{
  d = nullptr;
  f = nullptr;
  const vtkIdType n = pts ? pts->GetNumberOfPoints() : 0;
  if (n == 0)
  {
    return;
  }
  vtkDataArray* data = pts->GetData();
  if (auto* da = vtkDoubleArray::FastDownCast(data))
  {
    d = da->GetPointer(0);
  }
  else if (auto* fa = vtkFloatArray::FastDownCast(data))
  {
    f = fa->GetPointer(0);
  }
  else
  {
    scratch.resize(3 * static_cast<std::size_t>(n));
    for (vtkIdType i = 0; i < n; ++i)
    {
      pts->GetPoint(i, &scratch[3 * i]);
    }
    d = scratch.data();
  }
}

/// Fill `a` with views of `mesh` (cells always; points when `withPoints`). Points of a
/// type other than float or double are copied into `scratch`; the HigherOrderDegrees
/// cell data (3 components, one tuple per cell), when there, into `degrees`.
inline TetMeshArrays ViewTetMesh(vtkUnstructuredGrid* mesh, bool withPoints,
  std::vector<double>& scratch, std::vector<double>* degrees = nullptr)
{
  TetMeshArrays a;
  if (!mesh)
  {
    return a;
  }
  vtkPoints* pts = mesh->GetPoints();
  a.NumberOfPoints = pts ? pts->GetNumberOfPoints() : 0;
  if (withPoints && a.NumberOfPoints > 0)
  {
    ViewPoints(pts, a.PointsDouble, a.PointsFloat, scratch);
  }
  vtkCellArray* cells = mesh->GetCells();
  vtkUnsignedCharArray* types = mesh->GetCellTypesArray();
  a.NumberOfCells = cells && types ? mesh->GetNumberOfCells() : 0;
  static_assert(GhostDuplicateCell == vtkDataSetAttributes::DUPLICATECELL, "VTK's ghost bit");
  vtkUnsignedCharArray* ghosts = mesh->GetCellGhostArray();
  if (ghosts && ghosts->GetNumberOfTuples() == a.NumberOfCells && a.NumberOfCells > 0)
  {
    a.CellGhosts = ghosts->GetPointer(0);
  }
  vtkDataArray* orders = mesh->GetCellData()->GetHigherOrderDegrees();
  if (degrees && orders && orders->GetNumberOfComponents() == 3 &&
    orders->GetNumberOfTuples() == a.NumberOfCells && a.NumberOfCells > 0)
  {
    degrees->resize(3 * static_cast<std::size_t>(a.NumberOfCells));
    for (vtkIdType c = 0; c < a.NumberOfCells; ++c)
      orders->GetTuple(c, &(*degrees)[3 * c]);
    a.HigherOrderDegrees = degrees->data();
  }
  if (a.NumberOfCells > 0)
  {
    a.CellTypes = types->GetPointer(0);
    if (cells->IsStorage64Bit())
    {
      a.Offsets64 =
        reinterpret_cast<const std::int64_t*>(cells->GetOffsetsArray64()->GetPointer(0));
      a.Connectivity64 =
        reinterpret_cast<const std::int64_t*>(cells->GetConnectivityArray64()->GetPointer(0));
    }
    else
    {
      a.Offsets32 =
        reinterpret_cast<const std::int32_t*>(cells->GetOffsetsArray32()->GetPointer(0));
      a.Connectivity32 =
        reinterpret_cast<const std::int32_t*>(cells->GetConnectivityArray32()->GetPointer(0));
    }
  }
  return a;
}
} // namespace hoembed

#endif
