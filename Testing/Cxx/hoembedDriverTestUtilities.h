// Plain arrays for the drivers' direct tests (TestEmbeddingDriver, TestTransferDriver):
// a generated FE mesh as hoembed::TetMeshArrays and a triangulated patch of surface
// points, what a binding hands the drivers (no VTK filter in the loop).
#ifndef hoembedDriverTestUtilities_h
#define hoembedDriverTestUtilities_h

#include "hoembedSurfaceTriangles.h"
#include "hoembedTetMeshInput.h"

#include "vtkUnstructuredGrid.h"

#include <cstdint>
#include <functional>
#include <vector>

namespace hoembed_test
{
/// An FE mesh's arrays (points as doubles, 64-bit cells) and their view.
struct PlainTetMesh
{
  std::vector<double> Points;
  std::vector<unsigned char> Types;
  std::vector<std::int64_t> Offsets, Connectivity;

  explicit PlainTetMesh(vtkUnstructuredGrid* g)
  {
    for (vtkIdType p = 0; p < g->GetNumberOfPoints(); ++p)
    {
      double x[3];
      g->GetPoint(p, x);
      this->Points.insert(this->Points.end(), x, x + 3);
    }
    this->Offsets.push_back(0);
    for (vtkIdType c = 0; c < g->GetNumberOfCells(); ++c)
    {
      this->Types.push_back(static_cast<unsigned char>(g->GetCellType(c)));
      vtkIdType n;
      const vtkIdType* ids;
      g->GetCellPoints(c, n, ids);
      this->Connectivity.insert(this->Connectivity.end(), ids, ids + n);
      this->Offsets.push_back(static_cast<std::int64_t>(this->Connectivity.size()));
    }
  }
  std::int64_t NumberOfPoints() const
  {
    return static_cast<std::int64_t>(this->Points.size() / 3);
  }
  hoembed::TetMeshArrays View() const
  {
    hoembed::TetMeshArrays m;
    m.NumberOfPoints = this->NumberOfPoints();
    m.PointsDouble = this->Points.data();
    m.NumberOfCells = static_cast<std::int64_t>(this->Types.size());
    m.CellTypes = this->Types.data();
    m.Offsets64 = this->Offsets.data();
    m.Connectivity64 = this->Connectivity.data();
    return m;
  }
};

/// A patch of m x m surface points, (u, v) in [u0, u1] x [v0, v1], placed by `at`, in
/// 2 (m - 1)^2 triangles (VTK offsets/connectivity layout).
struct SurfacePatch
{
  std::vector<double> Points;
  std::vector<std::int64_t> Offsets{ 0 }, Connectivity;

  SurfacePatch(int m, double u0, double u1, double v0, double v1,
    const std::function<void(double u, double v, double x[3])>& at)
  {
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i)
      {
        double x[3];
        at(u0 + (u1 - u0) * i / (m - 1), v0 + (v1 - v0) * j / (m - 1), x);
        this->Points.insert(this->Points.end(), x, x + 3);
      }
    for (int j = 0; j + 1 < m; ++j)
      for (int i = 0; i + 1 < m; ++i)
      {
        const std::int64_t a = j * m + i, b = a + 1, c = a + m, d = c + 1;
        for (std::int64_t id : { a, b, d, a, d, c })
        {
          this->Connectivity.push_back(id);
          if (this->Connectivity.size() % 3 == 0)
            this->Offsets.push_back(static_cast<std::int64_t>(this->Connectivity.size()));
        }
      }
  }
  std::int64_t NumberOfPoints() const
  {
    return static_cast<std::int64_t>(this->Points.size() / 3);
  }
  hoembed::CellArrayView Polygons() const
  {
    hoembed::CellArrayView v;
    v.NumberOfCells = static_cast<std::int64_t>(this->Offsets.size()) - 1;
    v.Offsets64 = this->Offsets.data();
    v.Connectivity64 = this->Connectivity.data();
    return v;
  }
};
} // namespace hoembed_test

#endif
