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
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkPoints.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include <vector>

namespace hoembed
{
/// Fill `a` with views of `mesh` (cells always; points when `withPoints`). Points of a
/// type other than float or double are copied into `scratch`.
inline TetMeshArrays ViewTetMesh(
  vtkUnstructuredGrid* mesh, bool withPoints, std::vector<double>& scratch)
{
  TetMeshArrays a;
  if (!mesh)
  {
    return a;
  }
  vtkPoints* pts = mesh->GetPoints();
  a.NumberOfPoints = pts ? pts->GetNumberOfPoints() : 0;
  if (withPoints && pts && a.NumberOfPoints > 0)
  {
    vtkDataArray* data = pts->GetData();
    if (auto* d = vtkDoubleArray::FastDownCast(data))
    {
      a.PointsDouble = d->GetPointer(0);
    }
    else if (auto* f = vtkFloatArray::FastDownCast(data))
    {
      a.PointsFloat = f->GetPointer(0);
    }
    else
    {
      scratch.resize(3 * static_cast<std::size_t>(a.NumberOfPoints));
      for (vtkIdType i = 0; i < a.NumberOfPoints; ++i)
      {
        pts->GetPoint(i, &scratch[3 * i]);
      }
      a.PointsDouble = scratch.data();
    }
  }
  vtkCellArray* cells = mesh->GetCells();
  vtkUnsignedCharArray* types = mesh->GetCellTypesArray();
  a.NumberOfCells = cells && types ? mesh->GetNumberOfCells() : 0;
  if (a.NumberOfCells > 0)
  {
    a.CellTypes = types->GetPointer(0);
    if (cells->IsStorage64Bit())
    {
      a.Offsets64 = reinterpret_cast<const std::int64_t*>(cells->GetOffsetsArray64()->GetPointer(0));
      a.Connectivity64 =
        reinterpret_cast<const std::int64_t*>(cells->GetConnectivityArray64()->GetPointer(0));
    }
    else
    {
      a.Offsets32 = reinterpret_cast<const std::int32_t*>(cells->GetOffsetsArray32()->GetPointer(0));
      a.Connectivity32 =
        reinterpret_cast<const std::int32_t*>(cells->GetConnectivityArray32()->GetPointer(0));
    }
  }
  return a;
}
} // namespace hoembed

#endif
