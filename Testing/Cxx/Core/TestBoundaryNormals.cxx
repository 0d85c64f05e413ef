// Smooth boundary normals (paper eq. 6-7) on a ball (nodal normals ~ radial, converging
// with refinement) and on a straight box (exact face normals, exact angle-weighted
// normals at box edges and corners), continuity across boundary edges, the boundary
// face evaluation against finite differences; and the mesh fingerprint.
#include "hoembedBoundaryNormals.h"
#include "hoembedMeshFingerprint.h"
#include "hoembedShapeFunctions.h"
#include "hoembedTestUtilities.h"
#include "hoembedTetMeshTopology.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

namespace
{
using Id = hoembed::TetMeshTopology::Id;

struct Mesh
{
  std::vector<Id> Conn;
  std::vector<double> Points;
  int NodesPerCell = 4;
  hoembed::TetMeshTopology Topo;
  std::vector<double> Normals;
};

void Load(vtkUnstructuredGrid* grid, Mesh& m)
{
  const auto conn = hoembed_test::MeshConnectivity(grid, m.NodesPerCell);
  m.Conn.assign(conn.begin(), conn.end());
  m.Points = hoembed_test::PointsOf(grid);
  const std::string err = m.Topo.Build(
    m.Conn.data(), grid->GetNumberOfCells(), m.NodesPerCell, grid->GetNumberOfPoints());
  HOEMBED_CHECK(err.empty(), "Build: %s", err.c_str());
  m.Normals.assign(m.Points.size(), -7.0);
  hoembed::ComputeBoundaryNodeNormals(m.Topo, m.Points.data(), m.Normals.data());
}

double Dot(const double* a, const double* b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

double Norm(const double* a)
{
  return std::sqrt(Dot(a, a));
}

double AngleDeg(const double* a, const double* b)
{
  const double c[3] = { a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
    a[0] * b[1] - a[1] * b[0] };
  return std::atan2(Norm(c), Dot(a, b)) * 180.0 / M_PI;
}

// The cube [-1, 1]^3 mapped onto the unit ball: each node pushed radially so that the
// cube's surface lands on the sphere.
void Ball(double p[3])
{
  const double c[3] = { 2 * p[0] - 1, 2 * p[1] - 1, 2 * p[2] - 1 };
  const double inf = std::max({ std::abs(c[0]), std::abs(c[1]), std::abs(c[2]) });
  const double r = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
  for (int d = 0; d < 3; ++d)
    p[d] = r > 0 ? c[d] * inf / r : 0.0;
}

// Max and mean angle (degrees) between nodal normals and the radial direction, and max
// angle of the interpolated normal at random face points to the radial direction there.
void BallErrors(int n, int order, double& nodalMax, double& nodalMean, double& fieldMax)
{
  Mesh m;
  Load(hoembed_test::MakeBoxTetMesh(n, n, n, 1, 1, 1, order, Ball), m);
  nodalMax = nodalMean = fieldMax = 0.0;
  int count = 0;
  const Id np = static_cast<Id>(m.Points.size() / 3);
  for (Id i = 0; i < np; ++i)
  {
    const double* nn = &m.Normals[3 * i];
    if (!m.Topo.IsBoundaryNode(i))
    {
      HOEMBED_CHECK(
        nn[0] == 0 && nn[1] == 0 && nn[2] == 0, "interior node %lld has a normal", (long long)i);
      continue;
    }
    HOEMBED_CHECK(std::abs(Norm(nn) - 1) < 1e-14, "nodal normal not unit (%g)", Norm(nn));
    const double a = AngleDeg(nn, &m.Points[3 * i]);
    nodalMax = std::max(nodalMax, a);
    nodalMean += a;
    ++count;
  }
  nodalMean /= std::max(count, 1);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  for (Id b = 0; b < m.Topo.GetNumberOfBoundaryFaces(); ++b)
    for (int k = 0; k < 5; ++k)
    {
      double uv[2] = { u(rng), u(rng) };
      if (uv[0] + uv[1] > 1)
      {
        uv[0] = 1 - uv[0];
        uv[1] = 1 - uv[1];
      }
      double x[3], xu[3], xv[3], nrm[3], s[3];
      hoembed::EvaluateBoundaryFace(m.Topo, m.Points.data(), b, uv, x, xu, xv);
      const double len =
        hoembed::InterpolateBoundaryNormal(m.Topo, m.Normals.data(), b, uv, nrm, s);
      HOEMBED_CHECK(len > 0.5 && std::abs(len - Norm(s)) < 1e-15, "normal sum length %g", len);
      for (int d = 0; d < 3; ++d)
        HOEMBED_CHECK(std::abs(nrm[d] - s[d] / len) < 1e-15, "normalisation");
      fieldMax = std::max(fieldMax, AngleDeg(nrm, x));
      // The exact patch normal points outward too.
      const double pn[3] = { xu[1] * xv[2] - xu[2] * xv[1], xu[2] * xv[0] - xu[0] * xv[2],
        xu[0] * xv[1] - xu[1] * xv[0] };
      HOEMBED_CHECK(Dot(pn, x) > 0, "patch normal points inward");
    }
}

void TestBall()
{
  double prev = 1e9;
  for (int order = 2; order >= 1; --order)
  {
    for (int n : { 4, 8, 16 })
    {
      double nmax, nmean, fmax;
      BallErrors(n, order, nmax, nmean, fmax);
      std::printf("ball tet%d %d^3: nodal normal vs radial: max %.3f deg, mean %.3f deg; "
                  "interpolated normal vs radial: max %.3f deg\n",
        order == 2 ? 10 : 4, n, nmax, nmean, fmax);
      if (order == 2)
      {
        // Second-order convergence (each halving of h divides the error by about 4).
        HOEMBED_CHECK(
          nmax < 0.4 * prev, "tet10 nodal normal error %g does not converge (was %g)", nmax, prev);
        prev = nmax;
        if (n >= 8)
          HOEMBED_CHECK(
            nmax < 1.5 && fmax < 1.5, "tet10 %d^3: normals off by %g / %g deg", n, nmax, fmax);
      }
    }
    prev = 1e9;
  }
}

// Straight box [0,2]x[0,1]x[0,1]: normals inside the sides are the side normals, at box
// edges the bisector and at box corners (1,1,1)/sqrt(3) up to signs (angle weighting).
void TestBox(int order)
{
  Mesh m;
  const double L[3] = { 2, 1, 1 };
  Load(hoembed_test::MakeBoxTetMesh(4, 3, 3, L[0], L[1], L[2], order), m);
  const Id np = static_cast<Id>(m.Points.size() / 3);
  auto expected = [&](const double* x, double n[3]) {
    int sides = 0;
    for (int d = 0; d < 3; ++d)
    {
      n[d] = x[d] == 0 ? -1.0 : (x[d] == L[d] ? 1.0 : 0.0);
      sides += n[d] != 0;
    }
    for (int d = 0; d < 3; ++d)
      n[d] /= std::sqrt(double(std::max(sides, 1)));
    return sides;
  };
  int counts[4] = { 0, 0, 0, 0 };
  for (Id i = 0; i < np; ++i)
  {
    double e[3];
    const int sides = expected(&m.Points[3 * i], e);
    HOEMBED_CHECK((sides > 0) == m.Topo.IsBoundaryNode(i), "boundary node %lld", (long long)i);
    if (sides == 0)
      continue;
    ++counts[sides];
    const double* nn = &m.Normals[3 * i];
    for (int d = 0; d < 3; ++d)
      HOEMBED_CHECK(std::abs(nn[d] - e[d]) < 1e-14,
        "tet%d box node %lld (%d sides): normal "
        "(%g %g %g), expected (%g %g %g)",
        order == 2 ? 10 : 4, (long long)i, sides, nn[0], nn[1], nn[2], e[0], e[1], e[2]);
  }
  HOEMBED_CHECK(counts[3] == 8 && counts[2] > 0 && counts[1] > 0, "box node classes %d %d %d",
    counts[1], counts[2], counts[3]);

  // Interpolated normals inside faces whose nodes are all inside one side: exact.
  const int npf = m.Topo.GetNodesPerFace();
  int flat = 0;
  for (Id b = 0; b < m.Topo.GetNumberOfBoundaryFaces(); ++b)
  {
    bool inside = true;
    double e[3];
    for (int k = 0; k < npf && inside; ++k)
      inside = expected(&m.Points[3 * m.Topo.BoundaryFaceNodes[b * npf + k]], e) == 1;
    if (!inside)
      continue;
    ++flat;
    for (double uv0 : { 0.1, 0.3, 0.6 })
      for (double uv1 : { 0.05, 0.3 })
      {
        const double uv[2] = { uv0, uv1 };
        double x[3], xu[3], xv[3], n[3];
        hoembed::EvaluateBoundaryFace(m.Topo, m.Points.data(), b, uv, x, xu, xv);
        hoembed::InterpolateBoundaryNormal(m.Topo, m.Normals.data(), b, uv, n);
        double side[3]; // the side all the face's nodes are on
        expected(&m.Points[3 * m.Topo.BoundaryFaceNodes[b * npf]], side);
        for (int d = 0; d < 3; ++d)
          HOEMBED_CHECK(std::abs(n[d] - side[d]) < 1e-14, "flat face %lld: normal (%g %g %g)",
            (long long)b, n[0], n[1], n[2]);
      }
  }
  HOEMBED_CHECK(flat > 10, "only %d faces inside the sides", flat);
  std::printf("box tet%d: %d side / %d edge / %d corner nodes exact, %d flat faces exact\n",
    order == 2 ? 10 : 4, counts[1], counts[2], counts[3], flat);
}

// Positions and normals agree from both sides of every boundary edge; tangents agree with
// finite differences of the position.
void TestContinuity(int order)
{
  Mesh m;
  auto wavy = [](double p[3]) {
    Ball(p);
    const double s = 1 + 0.1 * std::sin(3 * p[0]) * std::cos(2 * p[1]);
    for (int d = 0; d < 3; ++d)
      p[d] *= s;
  };
  Load(hoembed_test::MakeBoxTetMesh(5, 4, 3, 1, 1, 1, order, wavy), m);
  const int npf = m.Topo.GetNodesPerFace();
  const double edgeUV[3][2][2] = { { { 0, 0 }, { 1, 0 } }, { { 1, 0 }, { 0, 1 } },
    { { 0, 1 }, { 0, 0 } } }; // ab, bc, ca in face coordinates
  double worstX = 0, worstN = 0, worstFd = 0;
  for (Id b = 0; b < m.Topo.GetNumberOfBoundaryFaces(); ++b)
  {
    for (int e = 0; e < 3; ++e)
    {
      const Id nb = m.Topo.BoundaryFaceNeighbor[3 * b + e];
      HOEMBED_CHECK(nb >= 0, "no neighbour");
      if (nb < 0)
        continue;
      int e2 = 0;
      const Id p = m.Topo.BoundaryFaceNodes[b * npf + e];
      for (; e2 < 3; ++e2)
        if (m.Topo.BoundaryFaceNodes[nb * npf + (e2 + 1) % 3] == p)
          break;
      for (double t : { 0.1, 0.37, 0.5, 0.81 })
      {
        double uvA[2], uvB[2];
        for (int d = 0; d < 2; ++d)
        {
          uvA[d] = (1 - t) * edgeUV[e][0][d] + t * edgeUV[e][1][d];
          uvB[d] = t * edgeUV[e2][0][d] + (1 - t) * edgeUV[e2][1][d]; // reversed
        }
        double xa[3], xb[3], ua[3], va[3], ub[3], vb[3], na[3], nbv[3];
        hoembed::EvaluateBoundaryFace(m.Topo, m.Points.data(), b, uvA, xa, ua, va);
        hoembed::EvaluateBoundaryFace(m.Topo, m.Points.data(), nb, uvB, xb, ub, vb);
        hoembed::InterpolateBoundaryNormal(m.Topo, m.Normals.data(), b, uvA, na);
        hoembed::InterpolateBoundaryNormal(m.Topo, m.Normals.data(), nb, uvB, nbv);
        for (int d = 0; d < 3; ++d)
        {
          worstX = std::max(worstX, std::abs(xa[d] - xb[d]));
          worstN = std::max(worstN, std::abs(na[d] - nbv[d]));
        }
        // Finite differences of x(u, v) on face b.
        const double h = 1e-6;
        for (int dir = 0; dir < 2; ++dir)
        {
          double up[2] = { uvA[0], uvA[1] }, um[2] = { uvA[0], uvA[1] };
          up[dir] += h;
          um[dir] -= h;
          double xp[3], xm[3], t1[3], t2[3];
          hoembed::EvaluateBoundaryFace(m.Topo, m.Points.data(), b, up, xp, t1, t2);
          hoembed::EvaluateBoundaryFace(m.Topo, m.Points.data(), b, um, xm, t1, t2);
          for (int d = 0; d < 3; ++d)
            worstFd =
              std::max(worstFd, std::abs((xp[d] - xm[d]) / (2 * h) - (dir ? va[d] : ua[d])));
        }
      }
    }
  }
  std::printf("continuity tet%d: max position jump %.3g, max normal jump %.3g across boundary "
              "edges; tangents vs finite differences %.3g\n",
    order == 2 ? 10 : 4, worstX, worstN, worstFd);
  HOEMBED_CHECK(worstX < 1e-14, "position jumps by %g across a boundary edge", worstX);
  HOEMBED_CHECK(worstN < 1e-14, "normal jumps by %g across a boundary edge", worstN);
  HOEMBED_CHECK(worstFd < 1e-8, "tangents differ from finite differences by %g", worstFd);
}

// --- fingerprint --------------------------------------------------------------------
// FNV-1a 64 over bytes, written from the specification (checked on its test vectors).
std::uint64_t Fnv1a(const std::vector<unsigned char>& bytes)
{
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (unsigned char c : bytes)
  {
    h ^= c;
    h *= 0x100000001b3ull;
  }
  return h;
}

void PushLE(std::vector<unsigned char>& bytes, std::int64_t v)
{
  const std::uint64_t u = static_cast<std::uint64_t>(v);
  for (int b = 0; b < 8; ++b)
    bytes.push_back(static_cast<unsigned char>((u >> (8 * b)) & 0xff));
}

std::string Fingerprint(vtkUnstructuredGrid* grid)
{
  hoembed::MeshFingerprint fp(grid->GetNumberOfPoints(), grid->GetNumberOfCells());
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
  {
    vtkIdType npts;
    const vtkIdType* pts;
    grid->GetCellPoints(c, npts, pts);
    std::vector<std::int64_t> ids(pts, pts + npts);
    fp.AddCell(grid->GetCellType(c), ids.data(), static_cast<int>(npts));
  }
  return fp.Hex();
}

void TestFingerprint()
{
  HOEMBED_CHECK(Fnv1a({}) == 0xcbf29ce484222325ull, "FNV-1a of the empty string");
  HOEMBED_CHECK(Fnv1a({ 'a' }) == 0xaf63dc4c8601ec8cull, "FNV-1a of 'a'");
  HOEMBED_CHECK(
    Fnv1a({ 'f', 'o', 'o', 'b', 'a', 'r' }) == 0x85944171f73967e8ull, "FNV-1a of 'foobar'");

  auto a = hoembed_test::MakeBoxTetMesh(3, 2, 2, 1, 1, 1, 2);
  auto b = hoembed_test::MakeBoxTetMesh(3, 2, 2, 1, 1, 1, 2);
  auto curved = hoembed_test::MakeBoxTetMesh(3, 2, 2, 1, 1, 1, 2, Ball);
  auto linear = hoembed_test::MakeBoxTetMesh(3, 2, 2, 1, 1, 1, 1);
  const std::string ha = Fingerprint(a);
  std::printf("fingerprint of a tet10 box: %s\n", ha.c_str());
  HOEMBED_CHECK(ha.size() == 16 && ha.find_first_not_of("0123456789abcdef") == std::string::npos,
    "not 16 lowercase hex digits: %s", ha.c_str());
  HOEMBED_CHECK(ha == Fingerprint(b), "same mesh, different fingerprints");
  HOEMBED_CHECK(ha == Fingerprint(curved), "moved nodes changed the fingerprint");
  HOEMBED_CHECK(ha != Fingerprint(linear), "tet4 and tet10 meshes share a fingerprint");

  // The specified byte stream.
  std::vector<unsigned char> bytes;
  PushLE(bytes, a->GetNumberOfPoints());
  PushLE(bytes, a->GetNumberOfCells());
  for (vtkIdType c = 0; c < a->GetNumberOfCells(); ++c)
  {
    vtkIdType npts;
    const vtkIdType* pts;
    a->GetCellPoints(c, npts, pts);
    PushLE(bytes, a->GetCellType(c));
    for (vtkIdType k = 0; k < npts; ++k)
      PushLE(bytes, pts[k]);
  }
  char hex[17];
  std::snprintf(hex, sizeof(hex), "%016llx", static_cast<unsigned long long>(Fnv1a(bytes)));
  HOEMBED_CHECK(ha == hex, "fingerprint %s, FNV-1a of the documented stream %s", ha.c_str(), hex);

  // One id swapped (two nodes of one cell exchanged) -> different.
  vtkIdType npts;
  const vtkIdType* pts;
  a->GetCellPoints(5, npts, pts);
  std::vector<vtkIdType> ids(pts, pts + npts);
  std::swap(ids[1], ids[2]);
  a->GetCells()->ReplaceCellAtId(5, npts, ids.data());
  HOEMBED_CHECK(Fingerprint(a) != ha, "swapping two ids kept the fingerprint");
  std::swap(ids[1], ids[2]);
  a->GetCells()->ReplaceCellAtId(5, npts, ids.data());
  HOEMBED_CHECK(Fingerprint(a) == ha, "restoring the ids did not restore the fingerprint");
  // One id changed to another point -> different; an extra point -> different.
  ids[7] = 0;
  a->GetCells()->ReplaceCellAtId(5, npts, ids.data());
  HOEMBED_CHECK(Fingerprint(a) != ha, "changing an id kept the fingerprint");
  // Ids of every byte width (the small ones take a shortcut) and negative values, against
  // the byte stream.
  {
    const std::int64_t odd[] = { 0, 1, 255, 256, 65535, 65536, 70000, 1ll << 40,
      std::int64_t(0x7fffffffffffffffll), -1, -65536 };
    const int n = static_cast<int>(sizeof(odd) / sizeof(odd[0]));
    hoembed::MeshFingerprint f(65536, -3);
    f.AddCell(24, odd, n);
    f.AddCell(-7, odd + 3, 4);
    std::vector<unsigned char> s;
    PushLE(s, 65536);
    PushLE(s, -3);
    PushLE(s, 24);
    for (int k = 0; k < n; ++k)
      PushLE(s, odd[k]);
    PushLE(s, -7);
    for (int k = 3; k < 7; ++k)
      PushLE(s, odd[k]);
    HOEMBED_CHECK(f.Value() == Fnv1a(s),
      "fingerprint of wide / negative ids %016llx, stream %016llx",
      static_cast<unsigned long long>(f.Value()), static_cast<unsigned long long>(Fnv1a(s)));
  }
  hoembed::MeshFingerprint f1(10, 0), f2(11, 0);
  HOEMBED_CHECK(f1.Hex() != f2.Hex(), "point count not in the fingerprint");
  HOEMBED_CHECK(f1.Value() == std::stoull(f1.Hex(), nullptr, 16), "Value() and Hex() disagree");
}
} // namespace

int main(int, char*[])
{
  TestBall();
  TestBox(2);
  TestBox(1);
  TestContinuity(2);
  TestContinuity(1);
  TestFingerprint();
  return hoembed_test::Report("TestBoundaryNormals");
}
