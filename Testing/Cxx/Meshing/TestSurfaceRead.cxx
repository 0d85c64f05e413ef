// hoembed::ReadSurface and the checks of the mesher's read step against VTK's own: strips
// split into the very triangles (same ids, same order) vtkTriangleStrip::DecomposeStrip
// gives, a polygon of more than 4 points through vtkPolygon::Triangulate as the ear-cut
// service (and a fan when the service refuses), quads along the shorter diagonal (both
// diagonals tried), errors in the order and words the filter reports them, the size
// estimate against an analytic volume; and hoembedVector3.h's Distance2, Normalize and
// Perpendiculars bit for bit against vtkMath on random and axis-aligned vectors (the
// mesher's curving moved from vtkMath to them).
#include "hoembedSurfaceRead.h"
#include "hoembedTestUtilities.h"
#include "hoembedVector3.h"

#include "vtkCellArray.h"
#include "vtkIdList.h"
#include "vtkMath.h"
#include "vtkNew.h"
#include "vtkPoints.h"
#include "vtkPolygon.h"
#include "vtkTriangleStrip.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

namespace
{
using Id = std::int64_t;

bool SameBits(const double* a, const double* b, int n)
{
  return std::memcmp(a, b, sizeof(double) * n) == 0;
}

void VectorMath()
{
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  std::vector<std::array<double, 3>> vs = { { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 }, { 0, 0, -2 },
    { 1, 1, 0 }, { 1, 1, 1 }, { -1, 1e-9, 0 }, { 0, 0, 0 } };
  for (int i = 0; i < 2000; ++i)
    vs.push_back({ u(rng), u(rng), u(rng) * (i % 3 == 0 ? 1e-6 : 1.0) });
  int bad = 0;
  for (size_t i = 0; i + 1 < vs.size(); ++i)
  {
    const double* a = vs[i].data();
    const double* b = vs[i + 1].data();
    const double d2 = hoembed::Distance2(a, b), ref2 = vtkMath::Distance2BetweenPoints(a, b);
    double n[3] = { a[0], a[1], a[2] }, nr[3] = { a[0], a[1], a[2] };
    const double len = hoembed::Normalize(n), lenr = vtkMath::Normalize(nr);
    bad += !SameBits(&d2, &ref2, 1) || !SameBits(n, nr, 3) || !SameBits(&len, &lenr, 1);
    if (len == 0.0)
      continue;
    double p[3], q[3], pr[3], qr[3];
    hoembed::Perpendiculars(a, p, q);
    vtkMath::Perpendiculars(a, pr, qr, 0.0);
    bad += !SameBits(p, pr, 3) || !SameBits(q, qr, 3);
    // and what they are for: an orthonormal frame with a / |a|
    HOEMBED_CHECK(std::fabs(hoembed::Dot(p, n)) < 1e-12 && std::fabs(hoembed::Dot(q, n)) < 1e-12 &&
        std::fabs(hoembed::Dot(p, q)) < 1e-12 && std::fabs(hoembed::Dot(p, p) - 1) < 1e-12 &&
        std::fabs(hoembed::Dot(q, q) - 1) < 1e-12,
      "vector %zu: not an orthonormal frame", i);
  }
  HOEMBED_CHECK(bad == 0, "%d results differ from vtkMath's bits", bad);
}

struct Cells
{
  std::vector<Id> Offsets{ 0 };
  std::vector<Id> Conn;
  void Add(std::initializer_list<Id> ids)
  {
    this->Conn.insert(this->Conn.end(), ids);
    this->Offsets.push_back(static_cast<Id>(this->Conn.size()));
  }
  hoembed::SurfaceCells View() const
  {
    hoembed::SurfaceCells c;
    c.NumberOfCells = static_cast<Id>(this->Offsets.size()) - 1;
    c.Offsets = this->Offsets.data();
    c.Connectivity = this->Conn.data();
    return c;
  }
};

// Services: VTK's ear cut (as vtkTet10Mesher calls it) or none, and a merge that keeps
// the triangles as they are (so that the triangulation itself is seen).
hoembed::SurfaceReadServices Services(bool earCut, std::vector<Id>& seen)
{
  hoembed::SurfaceReadServices s;
  if (earCut)
    s.EarCut = [](const Id* ids, Id n, const double* xyz, std::vector<Id>& local) {
      vtkNew<vtkPolygon> polygon;
      vtkNew<vtkIdList> out;
      polygon->GetPointIds()->SetNumberOfIds(n);
      polygon->GetPoints()->SetNumberOfPoints(n);
      for (Id k = 0; k < n; ++k)
      {
        polygon->GetPointIds()->SetId(k, ids[k]);
        polygon->GetPoints()->SetPoint(k, xyz + 3 * k);
      }
      if (!polygon->Triangulate(out))
        return false;
      local.assign(out->GetPointer(0), out->GetPointer(0) + out->GetNumberOfIds());
      return true;
    };
  s.Merge = [&seen](const std::vector<Id>& tris, std::vector<double>& pts, std::vector<Id>& out) {
    seen = tris;
    out = tris;
    pts.assign(3, 0.0);
    return true;
  };
  return s;
}

void Triangulation()
{
  // points: a strip zig-zag (0..7), a quad (8..11) whose 1-3 diagonal is shorter, a
  // non-convex hexagon (12..17; an L shape: a fan from 12 would leave it)
  std::vector<double> pts;
  for (int i = 0; i < 8; ++i)
    pts.insert(pts.end(), { 0.5 * i, static_cast<double>(i % 2), 0.0 });
  pts.insert(pts.end(), { 0, 0, 1, 2, -0.1, 1, 2.1, 0.9, 1, 0, 1, 1 });
  pts.insert(pts.end(), { 0, 0, 2, 2, 0, 2, 2, 1, 2, 1, 1, 2, 1, 2, 2, 0, 2, 2 });
  hoembed::SurfaceInput in;
  in.NumberOfPoints = static_cast<Id>(pts.size() / 3);
  in.Points = pts.data();
  Cells polys, strips, lines;
  polys.Add({ 8, 9, 10, 11 });
  polys.Add({ 9, 10, 11, 8 }); // the same quad from another corner: the other diagonal
  polys.Add({ 13, 14, 15, 16, 17, 12 });
  polys.Add({ 0, 1 }); // fewer than 3 points: dropped
  strips.Add({ 0, 1, 2, 3, 4, 5, 6, 7 });
  lines.Add({ 0, 7 }); // dropped
  in.Polys = polys.View();
  in.Strips = strips.View();
  in.Lines = lines.View();
  HOEMBED_CHECK(hoembed::CheckSurfacePointIds(in).empty(), "valid ids refused");

  std::vector<Id> tris, seen;
  std::vector<double> merged;
  HOEMBED_CHECK(
    hoembed::ReadSurface(in, Services(true, seen), merged, tris).empty(), "read failed");
  // The read step hands the triangles to the merge in an order of the geometry alone
  // (checked below): the triangles themselves are compared up to order and rotation.
  // quad: shorter diagonal 9-11 (|p9 - p11| < |p8 - p10|)
  const std::vector<Id> quad = { 8, 9, 11, 9, 10, 11, 9, 10, 11, 9, 11, 8 };
  // hexagon: VTK's ear cut of the same polygon, mapped to global ids
  vtkNew<vtkPolygon> polygon;
  const Id hex[6] = { 13, 14, 15, 16, 17, 12 };
  polygon->GetPointIds()->SetNumberOfIds(6);
  polygon->GetPoints()->SetNumberOfPoints(6);
  for (int k = 0; k < 6; ++k)
  {
    polygon->GetPointIds()->SetId(k, hex[k]);
    polygon->GetPoints()->SetPoint(k, &pts[3 * hex[k]]);
  }
  vtkNew<vtkIdList> local;
  HOEMBED_CHECK(polygon->Triangulate(local) && local->GetNumberOfIds() == 12, "VTK ear cut failed");
  std::vector<Id> earCut;
  for (int j = 0; j < 12; ++j)
    earCut.push_back(hex[local->GetId(j)]);
  // strip: exactly vtkTriangleStrip::DecomposeStrip's triangles
  vtkNew<vtkCellArray> ref;
  const vtkIdType strip[8] = { 0, 1, 2, 3, 4, 5, 6, 7 };
  vtkTriangleStrip::DecomposeStrip(8, strip, ref);
  std::vector<Id> stripTris;
  vtkNew<vtkIdList> cell;
  for (vtkIdType c = 0; c < ref->GetNumberOfCells(); ++c)
  {
    ref->GetCellAtId(c, cell);
    for (int k = 0; k < 3; ++k)
      stripTris.push_back(cell->GetId(k));
  }
  // each triangle from its smallest id (a rotation keeps the orientation), then sorted
  auto normalised = [](std::vector<Id> t) {
    std::vector<std::array<Id, 3>> v;
    for (size_t i = 0; i + 2 < t.size(); i += 3)
    {
      int r = 0;
      for (int k = 1; k < 3; ++k)
        if (t[i + k] < t[i + r])
          r = k;
      v.push_back({ t[i + r], t[i + (r + 1) % 3], t[i + (r + 2) % 3] });
    }
    std::sort(v.begin(), v.end());
    return v;
  };
  // the order: each triangle starts at its corner of smallest coordinates (x, then y,
  // then z) and the triangles are sorted by their corners' coordinates
  auto canonical = [&pts](const std::vector<Id>& t) {
    auto less = [&pts](Id a, Id b) {
      return std::lexicographical_compare(
        &pts[3 * a], &pts[3 * a] + 3, &pts[3 * b], &pts[3 * b] + 3);
    };
    for (size_t i = 0; i + 2 < t.size(); i += 3)
      if (less(t[i + 1], t[i]) || less(t[i + 2], t[i]))
        return false;
    for (size_t i = 3; i + 2 < t.size(); i += 3)
      for (int k = 0; k < 3; ++k)
      {
        if (less(t[i - 3 + k], t[i + k]))
          break;
        if (less(t[i + k], t[i - 3 + k]))
          return false;
      }
    return true;
  };
  std::vector<Id> expected = quad;
  expected.insert(expected.end(), earCut.begin(), earCut.end());
  expected.insert(expected.end(), stripTris.begin(), stripTris.end());
  HOEMBED_CHECK(normalised(seen) == normalised(expected),
    "triangles differ from the quads' shorter diagonals, VTK's ear cut and strip split "
    "(%zu triangles, %zu expected)",
    seen.size() / 3, expected.size() / 3);
  HOEMBED_CHECK(canonical(seen), "triangles not in the order of their coordinates");
  // no ear cut: the hexagon becomes a fan from its first point
  HOEMBED_CHECK(
    hoembed::ReadSurface(in, Services(false, seen), merged, tris).empty(), "read failed");
  const std::vector<Id> fan = { 13, 14, 15, 13, 15, 16, 13, 16, 17, 13, 17, 12 };
  expected = quad;
  expected.insert(expected.end(), fan.begin(), fan.end());
  expected.insert(expected.end(), stripTris.begin(), stripTris.end());
  HOEMBED_CHECK(normalised(seen) == normalised(expected), "fan fallback");
  HOEMBED_CHECK(canonical(seen), "fan fallback: triangles not in the order of their coordinates");
}

void Errors()
{
  std::vector<Id> seen;
  std::vector<double> pts = { 0, 0, 0, 1, 0, 0, 0, 1, 0 }, merged;
  std::vector<Id> tris;
  hoembed::SurfaceInput in;
  auto read = [&]() { return hoembed::ReadSurface(in, Services(true, seen), merged, tris); };
  HOEMBED_CHECK(
    read() == "the input surface is empty (0 points, 0 cells)", "empty: %s", read().c_str());
  in.NumberOfPoints = 3;
  in.Points = pts.data();
  Cells lines, polys;
  lines.Add({ 0, 1 });
  in.Lines = lines.View();
  HOEMBED_CHECK(read().rfind("the input has no polygons (only points or lines)", 0) == 0,
    "lines only: %s", read().c_str());
  polys.Add({ 0, 1, 5 });
  in.Polys = polys.View();
  const std::string ids = hoembed::CheckSurfacePointIds(in);
  HOEMBED_CHECK(ids ==
      "polygon 0 of the input names point id 5, but the surface has 3 points "
      "(ids 0..2)",
    "ids: %s", ids.c_str());
  polys.Conn[2] = 2;
  pts[4] = std::nan("");
  HOEMBED_CHECK(read() == "the input surface has a non-finite coordinate (NaN or Inf) at point 1",
    "NaN: %s", read().c_str());
  pts[4] = 0.0;
  hoembed::SurfaceReadServices none = Services(true, seen);
  none.Merge = [](const std::vector<Id>&, std::vector<double>&, std::vector<Id>&) { return false; };
  HOEMBED_CHECK(hoembed::ReadSurface(in, none, merged, tris) ==
      "the input has no usable triangles after triangulation",
    "merge failure");
}

// A closed unit cube of 12 triangles: EstimatedElements(edge) = 6 sqrt(2) / edge^3.
void Estimate()
{
  std::vector<double> pts;
  for (int i = 0; i < 8; ++i)
    pts.insert(pts.end(), { double(i & 1), double((i >> 1) & 1), double((i >> 2) & 1) });
  Cells polys;
  for (const auto& q : std::vector<std::array<Id, 4>>{ { 0, 2, 3, 1 }, { 4, 5, 7, 6 },
         { 0, 1, 5, 4 }, { 2, 6, 7, 3 }, { 0, 4, 6, 2 }, { 1, 3, 7, 5 } })
  {
    polys.Add({ q[0], q[1], q[2] });
    polys.Add({ q[0], q[2], q[3] });
  }
  hoembed::SurfaceInput in;
  in.NumberOfPoints = 8;
  in.Points = pts.data();
  in.Polys = polys.View();
  const double e = hoembed::EstimatedElements(in, 0.1, 7);
  HOEMBED_CHECK(std::fabs(e - 6.0 * std::sqrt(2.0) * 1000.0) < 1e-9 * e, "estimate %g", e);
  HOEMBED_CHECK(hoembed::EstimatedElements(in, 0.0, 7) == 7.0, "no edge: the target");
  HOEMBED_CHECK(hoembed::CheckEstimatedSize(in, 0.1, 7, 9000, "Max").empty(), "8485 <= 9000");
  const std::string msg = hoembed::CheckEstimatedSize(in, 0.1, 7, 8000, "Max");
  HOEMBED_CHECK(msg.rfind("the mesh would have about 8485 elements", 0) == 0 &&
      msg.find("more than Max = 8000") != std::string::npos,
    "size: %s", msg.c_str());
}
} // namespace

int main(int, char*[])
{
  VectorMath();
  Triangulation();
  Errors();
  Estimate();
  return hoembed_test::Report("TestSurfaceRead");
}
