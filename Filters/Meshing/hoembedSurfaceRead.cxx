#include "hoembedSurfaceRead.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace hoembed
{
namespace
{
using Id = std::int64_t;

const double* Point(const SurfaceInput& s, Id i)
{
  return s.Points + 3 * i;
}

// Written as vtkMath::Distance2BetweenPoints is, so that the VTK build's quads split as
// they did when the filter called it.
double Distance2(const double a[3], const double b[3])
{
  return (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
    (a[2] - b[2]) * (a[2] - b[2]);
}

// Bounds as vtkPolyData::GetBounds gives them: over every point (used by a cell or not),
// NaN coordinates skipped, (1, -1) per axis for no points, (1e299, -1e299) for an axis
// with NaN only.
void Bounds(const SurfaceInput& s, double b[6])
{
  if (s.NumberOfPoints == 0)
  {
    for (int d = 0; d < 3; ++d)
    {
      b[2 * d] = 1.0;
      b[2 * d + 1] = -1.0;
    }
    return;
  }
  for (int d = 0; d < 3; ++d)
  {
    b[2 * d] = 1.0e299;
    b[2 * d + 1] = -1.0e299;
  }
  for (Id i = 0; i < s.NumberOfPoints; ++i)
    for (int d = 0; d < 3; ++d)
    {
      const double v = Point(s, i)[d];
      if (std::isnan(v))
        continue;
      b[2 * d] = std::min(b[2 * d], v);
      b[2 * d + 1] = std::max(b[2 * d + 1], v);
    }
}
// Lexicographic order of two points by their coordinates (x, then y, then z).
bool CoordinatesLess(const double* a, const double* b)
{
  return std::lexicographical_compare(a, a + 3, b, b + 3);
}

// The triangles in an order that depends on the surface alone, not on how it was stored:
// each triangle starts at its lexicographically smallest corner (a rotation, which keeps
// its orientation), and the triangles are sorted by their corners' coordinates. The merge
// service (vtkCleanPolyData) numbers the merged points in the order of first use and keeps
// the first point's coordinates of each cluster it merges, and decimation, locators and
// TetGen all depend on the order of what they are given: with this order, the same surface
// gives the same mesh bit for bit whatever its triangle and point order (issue 27; a
// permuted surface gave 465 against 515 nodes before). Comparisons of coordinates are kept
// by any positive scaling, so the order, too, is scale-invariant.
void CanonicalTriangleOrder(const SurfaceInput& s, std::vector<Id>& tris)
{
  const size_t nt = tris.size() / 3;
  auto corner = [&](size_t t, int k) { return Point(s, tris[3 * t + k]); };
  // the rotation whose corner sequence is lexicographically smallest
  auto rotationLess = [&](size_t t, int r, int q) {
    for (int k = 0; k < 3; ++k)
    {
      const double* a = corner(t, (r + k) % 3);
      const double* b = corner(t, (q + k) % 3);
      if (CoordinatesLess(a, b))
        return true;
      if (CoordinatesLess(b, a))
        return false;
    }
    return false;
  };
  for (size_t t = 0; t < nt; ++t)
  {
    int best = 0;
    for (int r = 1; r < 3; ++r)
      if (rotationLess(t, r, best))
        best = r;
    if (best != 0)
    {
      const Id rotated[3] = { tris[3 * t + best], tris[3 * t + (best + 1) % 3],
        tris[3 * t + (best + 2) % 3] };
      std::copy(rotated, rotated + 3, &tris[3 * t]);
    }
  }
  std::vector<Id> order(nt);
  for (size_t t = 0; t < nt; ++t)
    order[t] = static_cast<Id>(t);
  // stable: triangles with the same corner coordinates (duplicates) are the same geometry
  std::stable_sort(order.begin(), order.end(), [&](Id a, Id b) {
    for (int k = 0; k < 3; ++k)
    {
      const double* pa = corner(static_cast<size_t>(a), k);
      const double* pb = corner(static_cast<size_t>(b), k);
      if (CoordinatesLess(pa, pb))
        return true;
      if (CoordinatesLess(pb, pa))
        return false;
    }
    return false;
  });
  std::vector<Id> sorted(tris.size());
  for (size_t i = 0; i < nt; ++i)
    std::copy(&tris[3 * order[i]], &tris[3 * order[i]] + 3, &sorted[3 * i]);
  tris.swap(sorted);
}
} // namespace

std::string CheckSurfacePointIds(const SurfaceInput& s)
{
  const Id np = s.NumberOfPoints;
  const std::pair<const char*, const SurfaceCells*> kinds[] = { { "vertex", &s.Verts },
    { "line", &s.Lines }, { "polygon", &s.Polys }, { "triangle strip", &s.Strips } };
  for (const auto& kind : kinds)
  {
    const SurfaceCells& c = *kind.second;
    for (Id k = 0; k < c.NumberOfCells; ++k)
      for (Id j = c.Offsets[k]; j < c.Offsets[k + 1]; ++j)
      {
        const Id id = c.Connectivity[j];
        if (id < 0 || id >= np)
        {
          std::ostringstream msg;
          msg << kind.first << " " << k << " of the input names point id " << id
              << ", but the surface has " << np << " points (ids 0.." << np - 1 << ")";
          return msg.str();
        }
      }
  }
  return std::string();
}

double EstimatedElements(const SurfaceInput& s, double edge, int target)
{
  if (!(edge > 0.0))
    return static_cast<double>(target);
  // The volume to mesh: what the surface encloses (signed volume, taken about the
  // bounding-box centre so that an open surface's value does not depend on where the
  // origin is), or, when larger, the envelope of a sheet: its area times the envelope's
  // thickness (twice the default offset of a quarter of the element size). An open
  // surface encloses nothing meaningful; its signed volume can be 0 for a sheet through
  // the origin, which let any request through. Polygons are taken as fans (strips are
  // not counted).
  double bounds[6];
  Bounds(s, bounds);
  const double o[3] = { 0.5 * (bounds[0] + bounds[1]), 0.5 * (bounds[2] + bounds[3]),
    0.5 * (bounds[4] + bounds[5]) };
  double volume = 0.0, area = 0.0;
  for (Id k = 0; k < s.Polys.NumberOfCells; ++k)
  {
    const Id* ids = s.Polys.Connectivity + s.Polys.Offsets[k];
    const Id n = s.Polys.Offsets[k + 1] - s.Polys.Offsets[k];
    for (Id j = 1; j + 1 < n; ++j)
    {
      double a[3], b[3], c[3];
      for (int d = 0; d < 3; ++d)
      {
        a[d] = Point(s, ids[0])[d] - o[d];
        b[d] = Point(s, ids[j])[d] - o[d];
        c[d] = Point(s, ids[j + 1])[d] - o[d];
      }
      double ab[3], ac[3];
      for (int d = 0; d < 3; ++d)
      {
        ab[d] = b[d] - a[d];
        ac[d] = c[d] - a[d];
      }
      const double cross[3] = { ab[1] * ac[2] - ab[2] * ac[1], ab[2] * ac[0] - ab[0] * ac[2],
        ab[0] * ac[1] - ab[1] * ac[0] };
      area += 0.5 * std::sqrt(cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2]);
      volume += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                  a[2] * (b[0] * c[1] - b[1] * c[0])) /
        6.0;
    }
  }
  const double sheet = area * 0.5 * edge;
  return std::max(std::fabs(volume), sheet) * 6.0 * std::sqrt(2.0) / (edge * edge * edge);
}

std::string CheckEstimatedSize(
  const SurfaceInput& s, double edge, int target, Id maximum, const char* maximumName)
{
  const double estimate = EstimatedElements(s, edge, target);
  if (!(estimate > static_cast<double>(maximum)))
    return std::string();
  // Peak memory of the mesher per element, rounded up from a measurement
  // (Benchmarks/RESULTS.md, Mesher).
  const double bytesPerElement = 1.0e3;
  std::ostringstream msg;
  msg << "the mesh would have about " << static_cast<long long>(estimate) << " elements (about "
      << std::ceil(estimate * bytesPerElement / 1e9) << " GB of memory to mesh), more than "
      << maximumName << " = " << maximum
      << ": ask for fewer elements (or a longer TargetEdgeLength), or raise " << maximumName;
  return msg.str();
}

std::string ReadSurface(const SurfaceInput& s, const SurfaceReadServices& services,
  std::vector<double>& points, std::vector<Id>& tris)
{
  const Id numberOfCells =
    s.Verts.NumberOfCells + s.Lines.NumberOfCells + s.Polys.NumberOfCells + s.Strips.NumberOfCells;
  if (s.NumberOfPoints == 0 || numberOfCells == 0)
  {
    std::ostringstream msg;
    msg << "the input surface is empty (" << s.NumberOfPoints << " points, " << numberOfCells
        << " cells)";
    return msg.str();
  }
  for (Id i = 0; i < s.NumberOfPoints; ++i)
  {
    const double* x = Point(s, i);
    if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2]))
    {
      std::ostringstream msg;
      msg << "the input surface has a non-finite coordinate (NaN or Inf) at point " << i;
      return msg.str();
    }
  }
  if (s.Polys.NumberOfCells + s.Strips.NumberOfCells == 0)
    return "the input has no polygons (only points or lines), so nothing to enclose in a "
           "volume: give a triangle surface (reconstruct one from a point cloud first, e.g. "
           "with vtkSurfaceReconstructionFilter)";

  // Triangles of every polygon and strip. vtkTriangleFilter drops polygons its ear cut
  // cannot split (non-planar or degenerate quads of artist meshes, opening false holes):
  // a quad is split along its shorter diagonal, a larger polygon by the ear cut, else as
  // a fan from its first vertex.
  std::vector<Id> fineTris;
  std::vector<double> xyz;
  std::vector<Id> local;
  for (Id k = 0; k < s.Polys.NumberOfCells; ++k)
  {
    const Id* ids = s.Polys.Connectivity + s.Polys.Offsets[k];
    const Id n = s.Polys.Offsets[k + 1] - s.Polys.Offsets[k];
    if (n == 3)
    {
      fineTris.insert(fineTris.end(), ids, ids + 3);
      continue;
    }
    if (n == 4)
    {
      const bool d02 = Distance2(Point(s, ids[0]), Point(s, ids[2])) <=
        Distance2(Point(s, ids[1]), Point(s, ids[3]));
      const Id t[6] = { ids[0], ids[1], ids[d02 ? 2 : 3], d02 ? ids[0] : ids[1], ids[2], ids[3] };
      fineTris.insert(fineTris.end(), t, t + 6);
      continue;
    }
    if (n < 3)
      continue;
    xyz.resize(3 * n);
    for (Id j = 0; j < n; ++j)
      std::copy(Point(s, ids[j]), Point(s, ids[j]) + 3, &xyz[3 * j]);
    local.clear();
    if (services.EarCut && services.EarCut(ids, n, xyz.data(), local) &&
      static_cast<Id>(local.size()) == 3 * (n - 2))
    {
      for (Id j = 0; j < 3 * (n - 2); ++j)
        fineTris.push_back(ids[local[j]]);
    }
    else
      for (Id j = 1; j + 1 < n; ++j)
      {
        const Id t[3] = { ids[0], ids[j], ids[j + 1] };
        fineTris.insert(fineTris.end(), t, t + 3);
      }
  }
  // Strips as vtkTriangleStrip::DecomposeStrip splits them: every other triangle flipped,
  // so that all keep the strip's orientation.
  for (Id k = 0; k < s.Strips.NumberOfCells; ++k)
  {
    const Id* ids = s.Strips.Connectivity + s.Strips.Offsets[k];
    const Id n = s.Strips.Offsets[k + 1] - s.Strips.Offsets[k];
    for (Id j = 0; j + 2 < n; ++j)
    {
      const Id t[3] = { ids[j % 2 ? j + 1 : j], ids[j % 2 ? j : j + 1], ids[j + 2] };
      fineTris.insert(fineTris.end(), t, t + 3);
    }
  }
  CanonicalTriangleOrder(s, fineTris);
  points.clear();
  tris.clear();
  if (!services.Merge || !services.Merge(fineTris, points, tris) || tris.empty())
    return "the input has no usable triangles after triangulation";
  return std::string();
}
} // namespace hoembed
