// The embedding on hexahedra (hoembedLagrangeHexEmbedding.h): VTK_LAGRANGE_HEXAHEDRON of
// order 1-3, VTK_TRIQUADRATIC_HEXAHEDRON and VTK_QUADRATIC_HEXAHEDRON (serendipity), on a
// mildly and a strongly curved box of 2 x 2 x 2 cells, against references that work
// differently:
//  - closest distances: a brute force over every boundary face through the cells' own
//    shape functions in VTK's node order (hoembed::LagrangeHexShape, checked against
//    VTK's cells in TestLagrangeHex; no Bernstein nets, no bounds, no Newton): a lattice
//    of each face, the best candidates refined by zooming lattices; excess <= 1e-8 of
//    the diagonal on every point, no uncertified point; residuals <= 1e-10;
//  - inside points: images of random parameters located, mapped back to 1e-10;
//  - rigid motion: x'(pc) + d n'(pc) / |n'| of the moved mesh rebuilds R v + t to 1e-9;
//  - the barycentric baseline: VTK-order shape functions at its (cell, parameters) rebuild
//    the point to 1e-10;
//  - the triquadratic cell and the order 2 Lagrange cell on one geometry: the same
//    distances; validity: a folded cell is refused.
#include "hoembedEmbeddingFlood.h" // EMBED_NORMAL_OFFSET
#include "hoembedLagrangeHexEmbedding.h"
#include "hoembedHexTestUtilities.h"
#include "hoembedTestUtilities.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <vector>

using namespace hoembed_test;

namespace
{
// The brute-force distance from v to the mesh boundary (the box's faces).
double BruteDistance(const HexMesh& m, const hoembed::LagrangeHexBasis& b, const double v[3])
{
  struct Candidate
  {
    double D2;
    Id Cell;
    int Fixed;
    double FixedValue, U, V;
  };
  std::vector<Candidate> all;
  const int n = 16;
  for (int cz = 0; cz < Cells; ++cz)
    for (int cy = 0; cy < Cells; ++cy)
      for (int cx = 0; cx < Cells; ++cx)
      {
        const Id c = (cz * Cells + cy) * Cells + cx;
        const int cc[3] = { cx, cy, cz };
        for (int fixed = 0; fixed < 3; ++fixed)
          for (int side = 0; side < 2; ++side)
          {
            if (cc[fixed] != (side ? Cells - 1 : 0))
              continue;
            for (int i = 0; i <= n; ++i)
              for (int j = 0; j <= n; ++j)
              {
                double pc[3], x[3];
                pc[fixed] = side;
                pc[(fixed + 1) % 3] = double(i) / n;
                pc[(fixed + 2) % 3] = double(j) / n;
                CellMap(m, b, c, pc, x);
                const double d2 = (x[0] - v[0]) * (x[0] - v[0]) + (x[1] - v[1]) * (x[1] - v[1]) +
                  (x[2] - v[2]) * (x[2] - v[2]);
                all.push_back({ d2, c, fixed, double(side), double(i) / n, double(j) / n });
              }
          }
      }
  std::sort(
    all.begin(), all.end(), [](const Candidate& x, const Candidate& y) { return x.D2 < y.D2; });
  double best = HUGE_VAL;
  for (std::size_t k = 0; k < std::min<std::size_t>(6, all.size()); ++k)
  {
    Candidate c = all[k];
    double h = 1.0 / n;
    for (int round = 0; round < 40; ++round)
    {
      Candidate bestHere = c;
      for (int i = -4; i <= 4; ++i)
        for (int j = -4; j <= 4; ++j)
        {
          const double u = std::min(1.0, std::max(0.0, c.U + h * i / 4));
          const double w = std::min(1.0, std::max(0.0, c.V + h * j / 4));
          double pc[3], x[3];
          pc[c.Fixed] = c.FixedValue;
          pc[(c.Fixed + 1) % 3] = u;
          pc[(c.Fixed + 2) % 3] = w;
          CellMap(m, b, c.Cell, pc, x);
          const double d2 = (x[0] - v[0]) * (x[0] - v[0]) + (x[1] - v[1]) * (x[1] - v[1]) +
            (x[2] - v[2]) * (x[2] - v[2]);
          if (d2 < bestHere.D2)
            bestHere = c, bestHere.D2 = d2, bestHere.U = u, bestHere.V = w;
        }
      c = bestHere;
      h *= 0.5;
    }
    best = std::min(best, c.D2);
  }
  return std::sqrt(best);
}

void TestType(int type, int npc, double a)
{
  const hoembed::LagrangeHexBasis& b = *hoembed::GetLagrangeHexBasis(type, npc);
  const HexMesh m = MakeMesh(type, npc, a);
  hoembed::LagrangeHexEmbeddingMesh mesh;
  Id invalid = -1;
  const std::string err = mesh.Build(m.Points, m.Conn, type, npc, &invalid);
  HOEMBED_CHECK(err.empty(), "type %d n %d: %s", type, npc, err.c_str());
  if (!err.empty())
    return;
  HOEMBED_CHECK(invalid == Id(Cells * Cells * Cells), "type %d n %d a %g: cell %lld refused", type,
    npc, a, (long long)invalid);
  HOEMBED_CHECK(mesh.FaceCell.size() == std::size_t(6 * Cells * Cells), "boundary faces %zu",
    mesh.FaceCell.size());
  const double diag = mesh.Diagonal;
  // the moved mesh (a rotation and a translation)
  const double ang = 0.7, ca = std::cos(ang), sa = std::sin(ang);
  const double R[3][3] = { { ca, -sa, 0 }, { sa * 0.6, ca * 0.6, 0.8 },
    { -sa * 0.8, -ca * 0.8, 0.6 } };
  const double T[3] = { 0.3, -1.2, 2.0 };
  auto move = [&](const double x[3], double y[3]) {
    for (int r = 0; r < 3; ++r)
      y[r] = R[r][0] * x[0] + R[r][1] * x[1] + R[r][2] * x[2] + T[r];
  };
  std::vector<double> moved(m.Points.size());
  for (std::size_t i = 0; i < m.Points.size() / 3; ++i)
    move(&m.Points[3 * i], &moved[3 * i]);
  hoembed::LagrangeHexEmbeddingMesh movedMesh;
  movedMesh.Build(moved, m.Conn, type, npc);
  std::mt19937 rng(3 + npc);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double worstExcess = 0, worstRes = 0, worstRigid = 0, worstBary = 0;
  int outside = 0, fallback = 0;
  for (int s = 0; s < 60; ++s)
  {
    double v[3];
    for (int d = 0; d < 3; ++d)
      v[d] = -0.4 * Box[d] + 1.8 * Box[d] * unit(rng);
    hoembed::VertexEmbedding r, bary;
    mesh.Embed(v, hoembed::EMBED_NORMAL_OFFSET, r);
    worstRes = std::max(worstRes, r.Residual / diag);
    // the barycentric baseline: the closest cell's map extrapolated, rebuilt by VTK's
    // shape functions of that cell at its parameters
    mesh.Embed(v, hoembed::EMBED_BARYCENTRIC, bary);
    {
      double y[3];
      CellMap(m, b, bary.Cell, bary.PC, y);
      const double back = std::sqrt((y[0] - v[0]) * (y[0] - v[0]) + (y[1] - v[1]) * (y[1] - v[1]) +
        (y[2] - v[2]) * (y[2] - v[2]));
      worstBary = std::max(worstBary, back / diag);
    }
    HOEMBED_CHECK(!r.Uncertified, "type %d n %d: uncertified", type, npc);
    if (!r.Inside)
    {
      ++outside;
      const double brute = BruteDistance(m, b, v);
      // both ways: ours above the brute force (not the global minimum), or below it (a
      // point off the surface)
      worstExcess = std::max(worstExcess, std::abs(r.ClosestDistance - brute) / diag);
      fallback += r.Fallback;
    }
    // rigid motion: the moved mesh's map and normal field at (cell, pc)
    double x[3], J[3][3], want[3];
    movedMesh.CellPoint(r.Cell, r.PC, x, J);
    if (r.Fallback)
    {
      double q[3];
      mesh.Offset(r.Cell, r.PC, v, q);
      for (int d = 0; d < 3; ++d)
        x[d] += J[0][d] * q[0] + J[1][d] * q[1] + J[2][d] * q[2];
    }
    else if (r.Distance != 0.0)
    {
      double n[3], Jn[3][3];
      movedMesh.CellNormal(r.Cell, r.PC, n, Jn);
      const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      for (int d = 0; d < 3; ++d)
        x[d] += r.Distance * n[d] / len;
    }
    move(v, want);
    worstRigid = std::max(worstRigid,
      std::sqrt((x[0] - want[0]) * (x[0] - want[0]) + (x[1] - want[1]) * (x[1] - want[1]) +
        (x[2] - want[2]) * (x[2] - want[2])) /
        diag);
  }
  // inside: images of random parameters
  for (int s = 0; s < 20; ++s)
  {
    const Id c = static_cast<Id>(unit(rng) * Cells * Cells * Cells) % (Cells * Cells * Cells);
    const double pc[3] = { 0.05 + 0.9 * unit(rng), 0.05 + 0.9 * unit(rng), 0.05 + 0.9 * unit(rng) };
    double v[3];
    CellMap(m, b, c, pc, v);
    hoembed::VertexEmbedding r;
    mesh.Embed(v, hoembed::EMBED_NORMAL_OFFSET, r);
    HOEMBED_CHECK(r.Inside, "type %d n %d: an inside point not located", type, npc);
    double x[3];
    CellMap(m, b, r.Cell, r.PC, x);
    const double back = std::sqrt((x[0] - v[0]) * (x[0] - v[0]) + (x[1] - v[1]) * (x[1] - v[1]) +
      (x[2] - v[2]) * (x[2] - v[2]));
    HOEMBED_CHECK(
      back <= 1e-10 * diag, "type %d n %d: inside maps back to %g", type, npc, back / diag);
  }
  std::printf("type %d, %d nodes, curvature %.2f: %d outside (%d fallback), max excess %.2e, "
              "residual %.2e, rigid %.2e (of the diagonal)\n",
    type, npc, a, outside, fallback, worstExcess, worstRes, worstRigid);
  HOEMBED_CHECK(worstExcess <= 1e-8, "type %d n %d: excess %g", type, npc, worstExcess);
  HOEMBED_CHECK(worstRes <= 1e-10, "type %d n %d: residual %g", type, npc, worstRes);
  HOEMBED_CHECK(
    worstBary <= 1e-10, "type %d n %d: barycentric rebuilt to %g", type, npc, worstBary);
  HOEMBED_CHECK(worstRigid <= 1e-9, "type %d n %d: rigid %g", type, npc, worstRigid);
  HOEMBED_CHECK(outside > 20, "type %d n %d: only %d outside points", type, npc, outside);
  // a folded cell: an edge node (a corner for 8 nodes) of cell 0 far through the cell
  std::vector<double> folded = m.Points;
  const Id node = m.Conn[npc > 8 ? 8 : 0];
  folded[3 * node + 1] += 2.0;
  folded[3 * node + 2] += 2.0;
  hoembed::LagrangeHexEmbeddingMesh bad;
  Id firstBad = -1;
  bad.Build(folded, m.Conn, type, npc, &firstBad);
  HOEMBED_CHECK(
    firstBad == 0, "type %d n %d: folded cell: first invalid %lld", type, npc, (long long)firstBad);
}

// The triquadratic cell and the order 2 Lagrange cell: the same nodes, the same map.
void TestTriquadraticIsOrder2()
{
  const HexMesh tri = MakeMesh(hoembed::TriQuadraticHexahedronCellType, 27, 0.2);
  const HexMesh lag = MakeMesh(hoembed::LagrangeHexahedronCellType, 27, 0.2);
  hoembed::LagrangeHexEmbeddingMesh a, b;
  a.Build(tri.Points, tri.Conn, tri.Type, 27);
  b.Build(lag.Points, lag.Conn, lag.Type, 27);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(-1.0, 3.0);
  double worst = 0.0;
  for (int s = 0; s < 30; ++s)
  {
    const double v[3] = { unit(rng), unit(rng), unit(rng) };
    hoembed::VertexEmbedding ra, rb;
    a.Embed(v, hoembed::EMBED_NORMAL_OFFSET, ra);
    b.Embed(v, hoembed::EMBED_NORMAL_OFFSET, rb);
    worst = std::max(worst, std::abs(ra.ClosestDistance - rb.ClosestDistance));
  }
  HOEMBED_CHECK(worst <= 1e-10 * a.Diagonal, "hex27 vs Lagrange order 2: %g", worst);
}
} // namespace

int main(int, char*[])
{
  for (double a : { 0.05, 0.2 })
  {
    for (int p = 1; p <= 3; ++p)
      TestType(hoembed::LagrangeHexahedronCellType, (p + 1) * (p + 1) * (p + 1), a);
    TestType(hoembed::TriQuadraticHexahedronCellType, 27, a);
    TestType(hoembed::QuadraticHexahedronCellType, 20, a);
  }
  TestTriquadraticIsOrder2();
  return Report("TestLagrangeHexahedra");
}
