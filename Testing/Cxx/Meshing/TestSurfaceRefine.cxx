// hoembed::BisectLongEdges, the refinement of a low-poly boundary before TetGen: on a cube
// of 12 triangles, a long box and an icosahedron, every edge ends at most the bound long,
// the surface stays closed, manifold and consistently oriented, its area and enclosed
// volume do not change (the new points are on it), the smallest angle keeps Rivara's bound
// (half the input's), the work bound stops it with a valid surface, and the result is the
// same on a second run and under a power-of-two scaling.
#include "hoembedSurfaceRefine.h"
#include "hoembedTestUtilities.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

namespace
{
using Id = std::int64_t;

struct Surface
{
  std::vector<double> Points;
  std::vector<Id> Tris;
};

// An axis-aligned box [0, sx] x [0, sy] x [0, sz], 12 outward triangles.
Surface Box(double sx, double sy, double sz)
{
  Surface s;
  for (int i = 0; i < 8; ++i)
  {
    s.Points.push_back((i & 1) ? sx : 0.0);
    s.Points.push_back((i & 2) ? sy : 0.0);
    s.Points.push_back((i & 4) ? sz : 0.0);
  }
  s.Tris = { 0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4, 2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6,
    2, 1, 3, 7, 1, 7, 5 };
  return s;
}

// A regular icosahedron on the unit sphere, 20 outward triangles.
Surface Icosahedron()
{
  const double p = (1.0 + std::sqrt(5.0)) / 2.0, n = std::sqrt(1.0 + p * p);
  Surface s;
  const double v[12][3] = { { -1, p, 0 }, { 1, p, 0 }, { -1, -p, 0 }, { 1, -p, 0 }, { 0, -1, p },
    { 0, 1, p }, { 0, -1, -p }, { 0, 1, -p }, { p, 0, -1 }, { p, 0, 1 }, { -p, 0, -1 },
    { -p, 0, 1 } };
  for (const auto& c : v)
    for (double x : c)
      s.Points.push_back(x / n);
  s.Tris = { 0, 11, 5, 0, 5, 1, 0, 1, 7, 0, 7, 10, 0, 10, 11, 1, 5, 9, 5, 11, 4, 11, 10, 2, 10, 7,
    6, 7, 1, 8, 3, 9, 4, 3, 4, 2, 3, 2, 6, 3, 6, 8, 3, 8, 9, 4, 9, 5, 2, 4, 11, 6, 2, 10, 8, 6, 7,
    9, 8, 1 };
  return s;
}

const double* P(const Surface& s, Id i)
{
  return &s.Points[3 * i];
}

double Distance(const double* a, const double* b)
{
  return std::sqrt(
    (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

struct Measures
{
  double Area = 0.0, Volume = 0.0, LongestEdge = 0.0, SmallestAngle = M_PI;
  bool ClosedOriented = true; // every directed edge once, and its reverse once
};

Measures Measure(const Surface& s)
{
  Measures m;
  std::map<std::pair<Id, Id>, int> directed;
  for (size_t t = 0; t < s.Tris.size() / 3; ++t)
  {
    const double* c[3] = { P(s, s.Tris[3 * t]), P(s, s.Tris[3 * t + 1]), P(s, s.Tris[3 * t + 2]) };
    double e1[3], e2[3], cr[3];
    for (int d = 0; d < 3; ++d)
    {
      e1[d] = c[1][d] - c[0][d];
      e2[d] = c[2][d] - c[0][d];
    }
    cr[0] = e1[1] * e2[2] - e1[2] * e2[1];
    cr[1] = e1[2] * e2[0] - e1[0] * e2[2];
    cr[2] = e1[0] * e2[1] - e1[1] * e2[0];
    m.Area += 0.5 * std::sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]);
    m.Volume += (c[0][0] * cr[0] + c[0][1] * cr[1] + c[0][2] * cr[2]) / 6.0;
    for (int k = 0; k < 3; ++k)
    {
      const double a = Distance(c[k], c[(k + 1) % 3]), b = Distance(c[k], c[(k + 2) % 3]),
                   o = Distance(c[(k + 1) % 3], c[(k + 2) % 3]);
      m.LongestEdge = std::max(m.LongestEdge, a);
      m.SmallestAngle = std::min(
        m.SmallestAngle, std::acos(std::clamp((a * a + b * b - o * o) / (2 * a * b), -1.0, 1.0)));
      ++directed[{ s.Tris[3 * t + k], s.Tris[3 * t + (k + 1) % 3] }];
    }
  }
  for (const auto& d : directed)
  {
    const auto back = directed.find({ d.first.second, d.first.first });
    if (d.second != 1 || back == directed.end() || back->second != 1)
      m.ClosedOriented = false;
  }
  return m;
}

void CheckRefined(const char* name, Surface s, double bound)
{
  const Measures before = Measure(s);
  const Id points0 = static_cast<Id>(s.Points.size() / 3);
  Surface again = s;
  const Id splits = hoembed::BisectLongEdges(s.Points, s.Tris, bound, 1000000);
  const Measures after = Measure(s);
  HOEMBED_CHECK(splits > 0 && splits == static_cast<Id>(s.Points.size() / 3) - points0,
    "%s: %lld splits, %lld points added", name, static_cast<long long>(splits),
    static_cast<long long>(s.Points.size() / 3 - points0));
  HOEMBED_CHECK(after.LongestEdge <= bound, "%s: an edge of %.6g is left (bound %.6g)", name,
    after.LongestEdge, bound);
  HOEMBED_CHECK(after.ClosedOriented, "%s: no longer closed and consistently oriented", name);
  HOEMBED_CHECK(std::fabs(after.Area - before.Area) <= 1e-12 * before.Area &&
      std::fabs(after.Volume - before.Volume) <= 1e-12 * std::fabs(before.Volume),
    "%s: area %.17g -> %.17g, volume %.17g -> %.17g", name, before.Area, after.Area, before.Volume,
    after.Volume);
  HOEMBED_CHECK(after.SmallestAngle >= 0.5 * before.SmallestAngle - 1e-12,
    "%s: smallest angle %.4g deg, input's %.4g deg", name, after.SmallestAngle * 180 / M_PI,
    before.SmallestAngle * 180 / M_PI);
  // No split beyond need: a triangle is split only while it has an edge over the bound,
  // so each triangle with a new corner keeps an edge (a half) over half the bound.
  int overRefined = 0;
  for (size_t t = 0; t < s.Tris.size() / 3; ++t)
  {
    const Id* c = &s.Tris[3 * t];
    if (std::max({ c[0], c[1], c[2] }) < points0)
      continue;
    const double longest = std::max({ Distance(P(s, c[0]), P(s, c[1])),
      Distance(P(s, c[1]), P(s, c[2])), Distance(P(s, c[2]), P(s, c[0])) });
    overRefined += longest <= 0.5 * bound;
  }
  HOEMBED_CHECK(
    overRefined == 0, "%s: %d triangles with every edge under half the bound", name, overRefined);

  // Deterministic, and the same under a power-of-two scaling.
  Surface scaled = again;
  for (double& x : scaled.Points)
    x *= 0x1p-10;
  hoembed::BisectLongEdges(again.Points, again.Tris, bound, 1000000);
  hoembed::BisectLongEdges(scaled.Points, scaled.Tris, bound * 0x1p-10, 1000000);
  HOEMBED_CHECK(again.Tris == s.Tris && again.Points == s.Points, "%s: a second run differs", name);
  bool same = scaled.Tris == s.Tris && scaled.Points.size() == s.Points.size();
  for (size_t i = 0; same && i < s.Points.size(); ++i)
    same = scaled.Points[i] == s.Points[i] * 0x1p-10;
  HOEMBED_CHECK(same, "%s: not the scaled result under a scaling by 2^-10", name);
}
} // namespace

int main(int, char*[])
{
  CheckRefined("unit cube", Box(1, 1, 1), 0.3);
  CheckRefined("long box", Box(8, 1, 0.5), 0.7);
  CheckRefined("icosahedron", Icosahedron(), 0.25);

  // Nothing to do: nothing changes.
  Surface cube = Box(1, 1, 1);
  const Surface untouched = cube;
  HOEMBED_CHECK(hoembed::BisectLongEdges(cube.Points, cube.Tris, 2.0, 1000) == 0 &&
      cube.Points == untouched.Points && cube.Tris == untouched.Tris,
    "a cube with every edge under the bound should be left as it is");

  // The work bound stops it after that many splits with a valid surface.
  const Id splits = hoembed::BisectLongEdges(cube.Points, cube.Tris, 0.1, 7);
  const Measures m = Measure(cube);
  HOEMBED_CHECK(splits == 7 && m.ClosedOriented && std::fabs(m.Volume - 1.0) < 1e-14,
    "the work bound: %lld splits, closed %d, volume %.17g", static_cast<long long>(splits),
    m.ClosedOriented, m.Volume);

  // An open sheet (a square of two triangles): its border edges, in one triangle each, are
  // bisected too.
  Surface sheet;
  sheet.Points = { 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0 };
  sheet.Tris = { 0, 1, 2, 0, 2, 3 };
  hoembed::BisectLongEdges(sheet.Points, sheet.Tris, 0.4, 1000);
  const Measures ms = Measure(sheet);
  HOEMBED_CHECK(ms.LongestEdge <= 0.4 && std::fabs(ms.Area - 1.0) < 1e-14,
    "an open square: longest edge %.4g, area %.17g", ms.LongestEdge, ms.Area);
  return hoembed_test::Report("TestSurfaceRefine");
}
