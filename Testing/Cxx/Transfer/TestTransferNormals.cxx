// Area-weighted vertex normals of the transferred surface (hoembedTransferNormals): on a
// bumpy grid of triangles, non-planar quads and pentagons, with an isolated vertex, against
// a brute force written here (each polygon's vector area as a fan of cross products,
// scattered to its vertices), in double and float points, with the 32-bit and 64-bit
// incidence lists, and split into ranges as the threaded driver runs them.
#include "hoembedTestUtilities.h"
#include "hoembedTransferNormals.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

namespace
{
using I = std::int64_t;

struct Surface
{
  std::vector<double> Points;
  std::vector<I> Offsets{ 0 }, Conn;
  I NumberOfPoints = 0;
  I NumberOfPolys() const
  {
    return static_cast<I>(this->Offsets.size()) - 1;
  }
  void Add(std::initializer_list<I> ids)
  {
    this->Conn.insert(this->Conn.end(), ids);
    this->Offsets.push_back(static_cast<I>(this->Conn.size()));
  }
};

// An (n + 1) x (n + 1) grid with random heights; each cell is a quad, two triangles (either
// diagonal), or, every fifth cell, a pentagon with an extra vertex on its bottom edge (a
// T-junction with the cell below, harmless here: the brute force sees the same
// incidences). The last point is isolated.
Surface MakeSurface(int n)
{
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> h(-0.3, 0.3);
  std::uniform_int_distribution<int> kind(0, 2);
  Surface s;
  auto gid = [&](int i, int j) { return static_cast<I>(j * (n + 1) + i); };
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      s.Points.insert(s.Points.end(), { double(i), double(j), h(rng) });
  s.NumberOfPoints = (n + 1) * (n + 1);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
    {
      const I a = gid(i, j), b = gid(i + 1, j), c = gid(i + 1, j + 1), d = gid(i, j + 1);
      if ((i + 3 * j) % 5 == 0)
      {
        const I m = s.NumberOfPoints++;
        s.Points.insert(s.Points.end(), { i + 0.5, j + 0.0, h(rng) });
        s.Add({ a, m, b, c, d });
        continue;
      }
      switch (kind(rng))
      {
        case 0:
          s.Add({ a, b, c, d });
          break;
        case 1:
          s.Add({ a, b, c });
          s.Add({ a, c, d });
          break;
        default:
          s.Add({ a, b, d });
          s.Add({ b, c, d });
          break;
      }
    }
  s.Points.insert(s.Points.end(), { -5.0, -5.0, 1.0 });
  ++s.NumberOfPoints;
  return s;
}

std::vector<double> BruteForce(const Surface& s)
{
  std::vector<double> acc(3 * s.NumberOfPoints, 0.0), out(3 * s.NumberOfPoints, 0.0);
  for (I p = 0; p < s.NumberOfPolys(); ++p)
  {
    const I first = s.Offsets[p], last = s.Offsets[p + 1];
    const double* o = &s.Points[3 * s.Conn[first]];
    double area[3] = { 0.0, 0.0, 0.0 };
    for (I k = first + 1; k + 1 < last; ++k)
    {
      const double* u = &s.Points[3 * s.Conn[k]];
      const double* w = &s.Points[3 * s.Conn[k + 1]];
      const double e[3] = { u[0] - o[0], u[1] - o[1], u[2] - o[2] };
      const double f[3] = { w[0] - o[0], w[1] - o[1], w[2] - o[2] };
      area[0] += e[1] * f[2] - e[2] * f[1];
      area[1] += e[2] * f[0] - e[0] * f[2];
      area[2] += e[0] * f[1] - e[1] * f[0];
    }
    for (I k = first; k < last; ++k)
      for (int c = 0; c < 3; ++c)
        acc[3 * s.Conn[k] + c] += area[c];
  }
  for (I i = 0; i < s.NumberOfPoints; ++i)
  {
    const double len = std::sqrt(
      acc[3 * i] * acc[3 * i] + acc[3 * i + 1] * acc[3 * i + 1] + acc[3 * i + 2] * acc[3 * i + 2]);
    for (int c = 0; c < 3; ++c)
      out[3 * i + c] = len > 0.0 ? acc[3 * i + c] / len : 0.0;
  }
  return out;
}

template <typename Id, typename T>
std::vector<float> Kernel(const Surface& s, const T* points, I chunk)
{
  std::vector<I> incOffsets;
  std::vector<Id> incPolys;
  hoembed::BuildVertexPolygonIncidence(
    s.Offsets.data(), s.Conn.data(), s.NumberOfPolys(), s.NumberOfPoints, incOffsets, incPolys);
  std::vector<double> polyNormals(3 * s.NumberOfPolys());
  for (I b = 0; b < s.NumberOfPolys(); b += chunk)
    hoembed::ComputePolygonNormals(s.Offsets.data(), s.Conn.data(), points, b,
      std::min(b + chunk, s.NumberOfPolys()), polyNormals.data());
  std::vector<float> normals(3 * s.NumberOfPoints, -7.0f);
  for (I b = 0; b < s.NumberOfPoints; b += chunk)
    hoembed::ComputeVertexNormals(incOffsets.data(), incPolys.data(), polyNormals.data(), b,
      std::min(b + chunk, s.NumberOfPoints), normals.data());
  return normals;
}

double WorstDifference(const std::vector<float>& a, const std::vector<double>& b)
{
  double worst = 0.0;
  for (size_t k = 0; k < a.size(); ++k)
    worst = std::max(worst, std::fabs(double(a[k]) - b[k]));
  return worst;
}

void TestAgainstBruteForce()
{
  const Surface s = MakeSurface(40);
  const std::vector<double> ref = BruteForce(s);
  std::vector<float> floatPoints(s.Points.begin(), s.Points.end());
  Surface sf = s;
  for (size_t k = 0; k < s.Points.size(); ++k)
    sf.Points[k] = double(floatPoints[k]);
  const std::vector<double> refFloat = BruteForce(sf);

  const auto n32 = Kernel<std::int32_t>(s, s.Points.data(), 1 << 30);
  const auto n64 = Kernel<std::int64_t>(s, s.Points.data(), 1 << 30);
  const auto chunked = Kernel<std::int32_t>(s, s.Points.data(), 97);
  const auto f32 = Kernel<std::int32_t>(s, floatPoints.data(), 1 << 30);
  // float output of unit vectors: a few float ulps of 1
  HOEMBED_CHECK(WorstDifference(n32, ref) < 1e-6, "32-bit incidence vs brute force: %g",
    WorstDifference(n32, ref));
  HOEMBED_CHECK(WorstDifference(f32, refFloat) < 1e-6, "float points vs brute force: %g",
    WorstDifference(f32, refFloat));
  HOEMBED_CHECK(std::memcmp(n32.data(), n64.data(), 4 * n32.size()) == 0,
    "32-bit and 64-bit incidence lists disagree");
  HOEMBED_CHECK(std::memcmp(n32.data(), chunked.data(), 4 * n32.size()) == 0,
    "ranges of 97 disagree with one range");
  const I iso = s.NumberOfPoints - 1;
  HOEMBED_CHECK(n32[3 * iso] == 0.0f && n32[3 * iso + 1] == 0.0f && n32[3 * iso + 2] == 0.0f,
    "isolated vertex normal not (0, 0, 0)");
  // orientation: the grid's polygons are counter-clockwise seen from +z
  int down = 0;
  for (I i = 0; i < iso; ++i)
    down += n32[3 * i + 2] <= 0.0f;
  HOEMBED_CHECK(down == 0, "%d normals point down", down);
}

// A triangle's normal through the triangle path equals the same triangle given as a
// degenerate quad (a repeated vertex: the general loop; the extra edge adds exact zeros).
void TestTrianglePathMatchesGeneralLoop()
{
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-10.0, 10.0);
  std::vector<double> pts(3 * 300);
  for (double& x : pts)
    x = u(rng);
  std::vector<I> triOff{ 0 }, triConn, quadOff{ 0 }, quadConn;
  for (I t = 0; t < 100; ++t)
  {
    triConn.insert(triConn.end(), { 3 * t, 3 * t + 1, 3 * t + 2 });
    triOff.push_back(static_cast<I>(triConn.size()));
    quadConn.insert(quadConn.end(), { 3 * t, 3 * t + 1, 3 * t + 2, 3 * t + 2 });
    quadOff.push_back(static_cast<I>(quadConn.size()));
  }
  std::vector<double> a(300), b(300);
  hoembed::ComputePolygonNormals(triOff.data(), triConn.data(), pts.data(), 0, 100, a.data());
  hoembed::ComputePolygonNormals(quadOff.data(), quadConn.data(), pts.data(), 0, 100, b.data());
  HOEMBED_CHECK(std::memcmp(a.data(), b.data(), sizeof(double) * a.size()) == 0,
    "triangle path and general Newell loop differ");
}
} // namespace

int main(int, char*[])
{
  TestAgainstBruteForce();
  TestTrianglePathMatchesGeneralLoop();
  return hoembed_test::Report("TestTransferNormals");
}
