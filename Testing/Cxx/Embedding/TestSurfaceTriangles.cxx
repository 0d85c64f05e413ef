// hoembed::AppendSurfaceTriangles / CheckSurfaceTriangles against VTK's own: strips split
// as vtkTriangleStrip::DecomposeStrip splits them (same triangles, as id sets), convex
// polygons fanned into triangles whose areas sum to vtkPolygon::ComputeArea, for 32- and
// 64-bit cell storage; ids out of range are refused.
#include "hoembedSurfaceTriangles.h"
#include "hoembedTestUtilities.h"

#include "vtkCellArray.h"
#include "vtkIdList.h"
#include "vtkMath.h"
#include "vtkNew.h"
#include "vtkPoints.h"
#include "vtkPolygon.h"
#include "vtkTriangle.h"
#include "vtkTriangleStrip.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <vector>

namespace
{
hoembed::CellArrayView View(vtkCellArray* ca)
{
  hoembed::CellArrayView v;
  v.NumberOfCells = ca->GetNumberOfCells();
  if (ca->IsStorage64Bit())
  {
    v.Offsets64 = reinterpret_cast<const std::int64_t*>(ca->GetOffsetsArray64()->GetPointer(0));
    v.Connectivity64 =
      reinterpret_cast<const std::int64_t*>(ca->GetConnectivityArray64()->GetPointer(0));
  }
  else
  {
    v.Offsets32 = reinterpret_cast<const std::int32_t*>(ca->GetOffsetsArray32()->GetPointer(0));
    v.Connectivity32 =
      reinterpret_cast<const std::int32_t*>(ca->GetConnectivityArray32()->GetPointer(0));
  }
  return v;
}

void Run(bool use32)
{
  // points on a circle (convex polygons of any size) and a zig-zag band (strips)
  vtkNew<vtkPoints> pts;
  const int nCircle = 12;
  for (int i = 0; i < nCircle; ++i)
    pts->InsertNextPoint(
      std::cos(2 * vtkMath::Pi() * i / nCircle), std::sin(2 * vtkMath::Pi() * i / nCircle), 0.0);
  for (int i = 0; i < 10; ++i)
    pts->InsertNextPoint(0.5 * i, (i % 2) ? 1.0 : 0.0, 1.0);
  vtkNew<vtkCellArray> polys, strips, empty;
  std::vector<std::vector<vtkIdType>> polyIds = { { 0, 1, 2 }, { 0, 2, 4, 6, 8, 10 },
    { 1, 3, 5, 7, 9, 11, 0 }, { 3, 4 } /* degenerate: no triangle */ };
  for (auto& p : polyIds)
    polys->InsertNextCell(static_cast<vtkIdType>(p.size()), p.data());
  std::vector<std::vector<vtkIdType>> stripIds = { { 12, 13, 14, 15, 16 },
    { 16, 17, 18, 19, 20, 21 }, { 12, 13, 14 } };
  for (auto& s : stripIds)
    strips->InsertNextCell(static_cast<vtkIdType>(s.size()), s.data());
  if (use32)
  {
    polys->ConvertTo32BitStorage();
    strips->ConvertTo32BitStorage();
    empty->ConvertTo32BitStorage();
  }
  // polygons only: one fan per polygon, k - 2 triangles, areas sum to the polygon's
  std::vector<std::int64_t> tris;
  hoembed::AppendSurfaceTriangles(View(polys), View(empty), tris);
  size_t expected = 0;
  for (auto& p : polyIds)
    expected += p.size() >= 3 ? p.size() - 2 : 0;
  HOEMBED_CHECK(
    tris.size() == 3 * expected, "%zu polygon triangles, expected %zu", tris.size() / 3, expected);
  size_t t = 0;
  for (auto& p : polyIds)
  {
    if (p.size() < 3)
      continue;
    double normal[3];
    const double ref =
      vtkPolygon::ComputeArea(pts, static_cast<vtkIdType>(p.size()), p.data(), normal);
    double sum = 0.0;
    for (size_t k = 0; k + 2 < p.size(); ++k, ++t)
    {
      double a[3], b[3], c[3];
      pts->GetPoint(tris[3 * t], a);
      pts->GetPoint(tris[3 * t + 1], b);
      pts->GetPoint(tris[3 * t + 2], c);
      sum += vtkTriangle::TriangleArea(a, b, c);
    }
    HOEMBED_CHECK(std::fabs(sum - ref) < 1e-12, "fan area %g, vtkPolygon area %g", sum, ref);
  }
  // strips only: the same triangles as VTK's decomposition (as id sets, in order)
  tris.clear();
  hoembed::AppendSurfaceTriangles(View(empty), View(strips), tris);
  vtkNew<vtkCellArray> ref;
  for (auto& s : stripIds)
    vtkTriangleStrip::DecomposeStrip(static_cast<int>(s.size()), s.data(), ref);
  HOEMBED_CHECK(tris.size() == 3 * static_cast<size_t>(ref->GetNumberOfCells()),
    "%zu strip triangles, VTK %lld", tris.size() / 3,
    static_cast<long long>(ref->GetNumberOfCells()));
  vtkNew<vtkIdList> cell;
  for (vtkIdType c = 0; c < ref->GetNumberOfCells() && 3 * static_cast<size_t>(c) < tris.size();
       ++c)
  {
    ref->GetCellAtId(c, cell);
    std::multiset<std::int64_t> a(tris.begin() + 3 * c, tris.begin() + 3 * c + 3);
    std::multiset<std::int64_t> b(cell->GetPointer(0), cell->GetPointer(0) + 3);
    HOEMBED_CHECK(a == b, "strip triangle %lld differs from VTK's", static_cast<long long>(c));
  }
  // both: polygons first, then strips
  std::vector<std::int64_t> both;
  hoembed::AppendSurfaceTriangles(View(polys), View(strips), both);
  HOEMBED_CHECK(both.size() == 3 * expected + tris.size() &&
      std::equal(tris.begin(), tris.end(), both.end() - tris.size()),
    "polygons then strips: wrong order or count");
  HOEMBED_CHECK(
    hoembed::CheckSurfaceTriangles(both, pts->GetNumberOfPoints()).empty(), "valid ids refused");
  const std::string err = hoembed::CheckSurfaceTriangles(both, 20);
  HOEMBED_CHECK(
    err.find("out of range [0, 20)") != std::string::npos, "id 21 of 20 points: '%s'", err.c_str());
  std::vector<std::int64_t> negative = { 0, -1, 2 };
  HOEMBED_CHECK(!hoembed::CheckSurfaceTriangles(negative, 3).empty(), "negative id accepted");
}
} // namespace

int main(int, char*[])
{
  Run(false);
  Run(true);
  return hoembed_test::Report("TestSurfaceTriangles");
}
