// Regression test: the closest point on a strongly curved, non-convex boundary face.
//
// One tet10, the unit corner tet, whose bottom face (z = 0, outward normal -z) is bent:
// the mid-edge node of the hypotenuse (1,0,0)-(0,1,0) is pushed down to z = -0.45 (a ridge
// bulging out of the element) and the two other bottom mid-edge nodes are lifted to
// z = +0.15 (those edges sag into the element). Query points below and in front of the
// edge y = 0 see that edge's curve as a local minimum of the squared distance, while the
// ridge is nearer: a single constrained Newton solve from the usual initial guess (the
// closest point on the flat corner triangle, hoembed::LinearStart) stops on the edge or
// at a corner. The filter certifies every face whose lower bound leaves room, by the
// expansion at the local solution or, where that is not enough, a branch and bound over
// the face (hoembedClosestPointCertify.h; TestCertifyKernel and TestSolutionCertificate
// test both alone).
//
// References: dense sampling of the tet10 with VTK's own vtkQuadraticTetra interpolation
// (an upper bound; with 400 subdivisions per edge within ~1e-5 of the minimum) and the
// exhaustive multi-start hoembed::BruteForceDistance. The test first shows that the
// single start misses on at least a few of its points (so it can fail), then checks the
// filter on each point alone (an isolated vertex: no hint, the usual start) and on all
// of them as one triangulated patch (starts from the neighbours, paper Algorithm 2).
//
// The same one dimension up (TestCurvedCell): a strongly curved, valid tet10 where the
// inside test's solve from the straight tet's coordinates stops on the cell's border for
// points inside the cell (seen on bunny_watertight at ~1000 elements: a vertex 0.083
// inside reported outside). The points are built inside, x(pc) with VTK's own
// vtkQuadraticTetra; the filter must report distance 0 and recover the cell.
#include "hoembedEmbeddingTestUtilities.h"

#include "hoembedClosestPoint.h"
#include "hoembedClosestPointCertify.h"
#include "hoembedEmbeddingMesh.h"
#include "hoembedEmbeddingSearch.h"
#include "vtkEmbeddingCoordinatesFilter.h"

#include "vtkCellArray.h"
#include "vtkDoubleArray.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkQuadraticTetra.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace
{
// VTK tet10 node order: corners 0-3, mids of edges 01, 12, 20, 03, 13, 23.
const double Nodes[10][3] = { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 }, { 0.5, 0, 0.15 },
  { 0.5, 0.5, -0.45 }, { 0, 0.5, 0.15 }, { 0, 0, 0.5 }, { 0.5, 0, 0.5 }, { 0, 0.5, 0.5 } };

vtkSmartPointer<vtkUnstructuredGrid> MakeMesh()
{
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToDouble();
  vtkIdType ids[10];
  for (int a = 0; a < 10; ++a)
    ids[a] = pts->InsertNextPoint(Nodes[a]);
  grid->SetPoints(pts);
  grid->InsertNextCell(VTK_QUADRATIC_TETRA, 10, ids);
  return grid;
}

// Distance from v to the bottom face (r, s, t = 0) sampled densely with VTK's
// vtkQuadraticTetra (an upper bound of the true distance, tight to ~1e-5 here).
double SampledBottomDistance(vtkQuadraticTetra* qt, const double v[3])
{
  const int n = 400;
  double best = 1e300;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; i + j <= n; ++j)
    {
      const double pc[3] = { double(i) / n, double(j) / n, 0.0 };
      double x[3], w[10];
      int sub;
      qt->EvaluateLocation(sub, pc, x, w);
      best = std::min(best,
        (x[0] - v[0]) * (x[0] - v[0]) + (x[1] - v[1]) * (x[1] - v[1]) +
          (x[2] - v[2]) * (x[2] - v[2]));
    }
  return std::sqrt(best);
}

double ClosestDistanceOf(vtkPolyData* out, vtkIdType i)
{
  auto* a = vtkDoubleArray::SafeDownCast(out->GetPointData()->GetArray("EmbeddingClosestDistance"));
  return a && i < a->GetNumberOfTuples() ? a->GetValue(i) : std::nan("");
}

// The filter's closest distance for v alone (an isolated vertex: no hint from a flood).
double FilterDistanceAlone(const double v[3], vtkUnstructuredGrid* grid)
{
  vtkNew<vtkPolyData> one;
  vtkNew<vtkPoints> op;
  op->SetDataTypeToDouble();
  op->InsertNextPoint(v);
  one->SetPoints(op);
  return ClosestDistanceOf(RunEmbeddingFilter(one, grid), 0);
}
} // namespace

// Mid-edge nodes far from the straight edges (det J >= 0.15 over the cell, checked).
const double CurvedCell[10][3] = { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 },
  { 0.359, -0.404, -0.235 }, { 0.788, 0.748, -0.507 }, { 0.008, 0.597, -0.540 },
  { 0.248, -0.355, 0.558 }, { 0.863, -0.270, 0.953 }, { -0.196, 0.180, 0.058 } };

// Smallest det J of a quadratic tetra with `nodes`, sampled on a lattice of n + 1 points
// per edge with VTK's own shape-function derivatives.
double MinDetJ(vtkQuadraticTetra* qt, const double (*nodes)[3], int n = 12)
{
  double minDet = 1e300;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; i + j <= n; ++j)
      for (int k = 0; i + j + k <= n; ++k)
      {
        const double pc[3] = { double(i) / n, double(j) / n, double(k) / n };
        double d[30];
        qt->InterpolationDerivs(pc, d);
        double J[3][3] = {};
        for (int a = 0; a < 10; ++a)
          for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c)
              J[r][c] += d[10 * c + a] * nodes[a][r];
        minDet = std::min(minDet,
          J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) -
            J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
            J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]));
      }
  return minDet;
}

void TestCurvedCell()
{
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToDouble();
  vtkIdType ids[10];
  vtkNew<vtkQuadraticTetra> qt;
  for (int a = 0; a < 10; ++a)
  {
    ids[a] = pts->InsertNextPoint(CurvedCell[a]);
    qt->GetPoints()->SetPoint(a, CurvedCell[a]);
    qt->GetPointIds()->SetId(a, a);
  }
  grid->SetPoints(pts);
  grid->InsertNextCell(VTK_QUADRATIC_TETRA, 10, ids);
  const double minDet = MinDetJ(qt, CurvedCell);
  HOEMBED_CHECK(minDet > 0.1, "curved cell not valid: min det J %g", minDet);

  hoembed::EmbeddingMesh em;
  std::vector<hoembed::EmbeddingMesh::Id> conn = { 0, 1, 2, 3, 4, 5, 6, 7, 8, 9 };
  const std::string err = em.Build(&CurvedCell[0][0], 10, conn.data(), 1, 10);
  HOEMBED_CHECK(err.empty(), "curved cell: mesh build: %s", err.c_str());
  if (!err.empty())
    return;
  const double tol = 1e-11 * em.Diagonal;
  int points = 0, hard = 0, wrong = 0;
  const int n = 16;
  for (int i = 1; i < n; ++i)
    for (int j = 1; i + j < n; ++j)
      for (int k = 1; i + j + k < n; ++k)
      {
        const double pc[3] = { double(i) / n, double(j) / n, double(k) / n };
        double v[3], w[10];
        int sub;
        qt->EvaluateLocation(sub, pc, v, w); // inside by construction
        ++points;
        // the single solves of the inside test from the straight tet's coordinates
        double start[3];
        hoembed::LinearStart(em.CellMaps[0], v, start);
        double inv[3] = { start[0], start[1], start[2] };
        int its = 0;
        const double res = hoembed::InvertTetMap(em.CellMaps[0], v, inv, its, 8);
        const bool invOk =
          res <= tol && inv[0] >= 0 && inv[1] >= 0 && inv[2] >= 0 && inv[0] + inv[1] + inv[2] <= 1;
        hoembed::ClosestPointResult r;
        hoembed::ClosestPointOnMap(em.CellMaps[0], v, start, r);
        if (!invOk && r.Distance2 > tol * tol)
          ++hard;
        // the filter on the point alone
        const double d = FilterDistanceAlone(v, grid);
        if (d != 0.0)
        {
          ++wrong;
          std::fprintf(stderr,
            "curved cell: point at pc (%g %g %g) inside, filter distance %.12g\n", pc[0], pc[1],
            pc[2], d);
        }
      }
  std::printf(
    "curved cell: %d inside points; the solve from the straight tet misses %d\n", points, hard);
  HOEMBED_CHECK(hard >= 3, "only %d hard points in the curved cell (test setup)", hard);
  HOEMBED_CHECK(wrong == 0, "curved cell: %d inside points reported outside", wrong);
}

// Distance from v to the patch m by dense sampling of an n x n parametric grid (an upper
// bound of the true minimum).
double SampledPatchDistance(const hoembed::QuadraticMap& m, const double v[3], int n)
{
  double best = 1e300;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; i + j <= n; ++j)
    {
      const double uv[2] = { double(i) / n, double(j) / n };
      double p[3];
      hoembed::EvaluateMap(m, uv, p);
      best = std::min(best,
        (p[0] - v[0]) * (p[0] - v[0]) + (p[1] - v[1]) * (p[1] - v[1]) +
          (p[2] - v[2]) * (p[2] - v[2]));
    }
  return std::sqrt(best);
}

// The kernel alone: strongly curved tri6 patches (mid-edge nodes moved by up to 0.45 of
// the unit triangle) and points around them. After CertifyClosestPointOnPatch the
// distance is never above dense sampling (a 300 x 300 grid, an upper bound of the true
// minimum) and not below it by more than the sampling resolution; the single start alone
// is worse on some points (so this can fail).
void TestCertifyKernel()
{
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  int above = 0, below = 0, uncertified = 0, singleWorse = 0, queries = 0;
  for (int trial = 0; trial < 30; ++trial)
  {
    double x[18] = { 0, 0, 0, 1, 0, 0, 0, 1, 0, 0.5, 0, 0, 0.5, 0.5, 0, 0, 0.5, 0 };
    for (int a = 3; a < 6; ++a)
      for (int d = 0; d < 3; ++d)
        x[3 * a + d] += 0.45 * U(rng);
    hoembed::QuadraticMap m;
    hoembed::MakeTriangleMap(x, 6, m);
    for (int q = 0; q < 10; ++q, ++queries)
    {
      const double v[3] = { 0.4 + 1.2 * U(rng), 0.4 + 1.2 * U(rng), 1.2 * U(rng) };
      double start[2];
      hoembed::LinearStart(m, v, start);
      hoembed::ClosestPointResult r;
      hoembed::ClosestPointOnMap(m, v, start, r);
      const double single = std::sqrt(r.Distance2);
      bool certified = false;
      hoembed::CertifyClosestPointOnPatch(m, v, 1e300, 1e-12, r, &certified);
      uncertified += !certified;
      const double sampled = SampledPatchDistance(m, v, 300);
      const double d = std::sqrt(r.Distance2);
      above += d > sampled + 1e-12;
      below += d < sampled - 1e-4;
      singleWorse += single > sampled + 1e-6;
    }
  }
  std::printf("certify kernel: %d queries, the single start worse than sampling on %d\n", queries,
    singleWorse);
  HOEMBED_CHECK(
    singleWorse >= 3, "single start worse on only %d queries (test setup)", singleWorse);
  HOEMBED_CHECK(above == 0, "certified distance above dense sampling on %d queries", above);
  HOEMBED_CHECK(below == 0, "certified distance far below dense sampling on %d queries", below);
  HOEMBED_CHECK(uncertified == 0, "%d searches ran out of nodes", uncertified);
}

// The quick certificate alone (hoembed::SolutionCertified): tri6 patches from nearly
// flat to strongly curved (mid-edge nodes moved by up to 0.02 ... 0.45 of the unit
// triangle), points near and far, the local solution from the usual start. A claim
// "no point nearer than min(local, incumbent) - tol" must hold against dense sampling
// (an upper bound of the true minimum: a sample below the claim by more than round-off
// disproves it). The test needs both outcomes: local solutions that are not global
// (all must be refused) and a good share of certified ones (else the filter gains
// nothing).
void TestSolutionCertificate()
{
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  const double amplitudes[4] = { 0.02, 0.1, 0.25, 0.45 };
  int certified = 0, wrongClaims = 0, notGlobal = 0, queries = 0;
  for (int trial = 0; trial < 40; ++trial)
  {
    const double amp = amplitudes[trial % 4];
    double x[18] = { 0, 0, 0, 1, 0, 0, 0, 1, 0, 0.5, 0, 0, 0.5, 0.5, 0, 0, 0.5, 0 };
    for (int a = 3; a < 6; ++a)
      for (int d = 0; d < 3; ++d)
        x[3 * a + d] += amp * U(rng);
    hoembed::QuadraticMap m;
    hoembed::MakeTriangleMap(x, 6, m);
    for (int q = 0; q < 12; ++q, ++queries)
    {
      // half of the points within 0.05 of the patch plane (vertices of a fine surface
      // lie that close to the curved boundary), half up to 1 away
      const double h = q % 2 ? 0.05 * U(rng) : U(rng);
      const double v[3] = { 0.4 + 0.8 * U(rng), 0.4 + 0.8 * U(rng), h };
      double start[2];
      hoembed::LinearStart(m, v, start);
      hoembed::ClosestPointResult r;
      hoembed::ClosestPointOnMap(m, v, start, r);
      const double local = std::sqrt(r.Distance2);
      // a third of the queries with an incumbent from elsewhere, below the local distance
      const double incumbent = q % 3 == 0 ? 0.8 * local : 1e300;
      const double tol = 1e-12;
      const bool claim = hoembed::SolutionCertified(m, v, incumbent * incumbent, tol, r);
      const double sampled = SampledPatchDistance(m, v, 240);
      const bool global = sampled >= local - 1e-9;
      notGlobal += !global;
      certified += claim;
      wrongClaims += claim && sampled < std::min(local, incumbent) - tol - 1e-12;
    }
  }
  std::printf("solution certificate: %d queries, %d certified, %d local solutions not "
              "global\n",
    queries, certified, notGlobal);
  HOEMBED_CHECK(notGlobal >= 5, "only %d local solutions were not global (test setup)", notGlobal);
  HOEMBED_CHECK(wrongClaims == 0, "%d certificates disproved by sampling", wrongClaims);
  HOEMBED_CHECK(certified >= queries / 3, "only %d of %d certified", certified, queries);
}

int main(int, char*[])
{
  TestSolutionCertificate();
  TestCertifyKernel();
  TestCurvedCell();
  auto grid = MakeMesh();
  vtkNew<vtkQuadraticTetra> qt;
  for (int a = 0; a < 10; ++a)
  {
    qt->GetPoints()->SetPoint(a, Nodes[a]);
    qt->GetPointIds()->SetId(a, a);
  }
  // the element is valid (the filter would refuse it otherwise): det J > 0 on a grid
  {
    const double minDet = MinDetJ(qt, Nodes, 10);
    HOEMBED_CHECK(minDet > 0.1, "test element not valid: min det J %g", minDet);
  }

  hoembed::EmbeddingMesh em;
  std::vector<hoembed::EmbeddingMesh::Id> conn;
  for (int a = 0; a < 10; ++a)
    conn.push_back(a);
  const std::string err = em.Build(&Nodes[0][0], 10, conn.data(), 1, 10);
  HOEMBED_CHECK(err.empty(), "mesh build: %s", err.c_str());
  if (!err.empty())
    return hoembed_test::Report("TestEmbeddingNonConvexFace");
  hoembed::EmbeddingMesh::Id bottom = -1;
  for (hoembed::EmbeddingMesh::Id f = 0; f < em.Topology.GetNumberOfBoundaryFaces(); ++f)
    if (em.Topology.BoundaryFaceLocal[f] == 3) // face (0, 2, 1): z = 0
      bottom = f;
  HOEMBED_CHECK(bottom >= 0, "bottom face not found");
  const double diag = em.Diagonal;

  // a grid of query points in the plane y = -0.5, below the face (z < 0): a
  // triangulated patch, so the flood also walks it from neighbour to neighbour
  const int nx = 21, nz = 11;
  vtkNew<vtkPolyData> patch;
  vtkNew<vtkPoints> pp;
  pp->SetDataTypeToDouble();
  vtkNew<vtkCellArray> tris;
  for (int k = 0; k < nz; ++k)
    for (int i = 0; i < nx; ++i)
    {
      pp->InsertNextPoint(-0.2 + 0.07 * i, -0.5, -0.2 - 0.15 * k);
      if (i > 0 && k > 0)
      {
        const vtkIdType a = (k - 1) * nx + i - 1, b = a + 1, c = a + nx, d = c + 1;
        const vtkIdType t1[3] = { a, b, d }, t2[3] = { a, d, c };
        tris->InsertNextCell(3, t1);
        tris->InsertNextCell(3, t2);
      }
    }
  patch->SetPoints(pp);
  patch->SetPolys(tris);
  auto patchOut = RunEmbeddingFilter(patch, grid);

  int onBottom = 0, singleMisses = 0, aloneBad = 0, patchBad = 0, refBad = 0;
  double worstMiss = 0.0;
  for (vtkIdType q = 0; q < patch->GetNumberOfPoints(); ++q)
  {
    double v[3];
    patch->GetPoint(q, v);
    hoembed::EmbeddingMesh::Id bf = -1;
    const double brute = hoembed::BruteForceDistance(em, v, &bf);
    if (bf != bottom)
      continue; // closest point on another face: not this test's subject
    ++onBottom;
    // the two references agree (dense sampling is an upper bound, ~1e-5 loose)
    const double sampled = SampledBottomDistance(qt, v);
    if (!(brute <= sampled + 1e-12 && brute >= sampled - 1e-4))
    {
      ++refBad;
      std::fprintf(stderr, "point %lld: brute force %.12g, sampling %.12g\n",
        static_cast<long long>(q), brute, sampled);
    }
    // a single solve from the usual start
    double start[2];
    hoembed::LinearStart(em.FaceMaps[bottom], v, start);
    hoembed::ClosestPointResult r;
    hoembed::ClosestPointOnMap(em.FaceMaps[bottom], v, start, r);
    const double single = std::sqrt(r.Distance2);
    const bool missed = single > brute + 1e-3 * diag;
    if (missed)
    {
      ++singleMisses;
      worstMiss = std::max(worstMiss, single - brute);
    }
    // the filter, the point alone (an isolated vertex: no hint)
    const double alone = FilterDistanceAlone(v, grid);
    if (!(std::fabs(alone - brute) <= 1e-8 * diag))
    {
      ++aloneBad;
      std::fprintf(stderr,
        "point %lld alone: filter %.12g, brute force %.12g, single start %.12g\n",
        static_cast<long long>(q), alone, brute, single);
    }
    const double inPatch = ClosestDistanceOf(patchOut, q);
    if (!(std::fabs(inPatch - brute) <= 1e-8 * diag))
    {
      ++patchBad;
      std::fprintf(stderr, "point %lld in the patch: filter %.12g, brute force %.12g\n",
        static_cast<long long>(q), inPatch, brute);
    }
  }
  std::printf("%d of %lld points closest to the curved face; a single start from the flat "
              "triangle misses %d of them (by up to %.3g)\n",
    onBottom, static_cast<long long>(patch->GetNumberOfPoints()), singleMisses, worstMiss);
  HOEMBED_CHECK(onBottom >= 20, "only %d points closest to the curved face (test setup)", onBottom);
  HOEMBED_CHECK(singleMisses >= 5 && worstMiss > 0.1,
    "the single start misses only %d points by up to %g: the case is not hard (test setup)",
    singleMisses, worstMiss);
  HOEMBED_CHECK(refBad == 0, "%d points where brute force and dense sampling disagree", refBad);
  HOEMBED_CHECK(aloneBad == 0, "%d isolated points with the wrong distance", aloneBad);
  HOEMBED_CHECK(patchBad == 0, "%d patch points with the wrong distance", patchBad);
  return hoembed_test::Report("TestEmbeddingNonConvexFace");
}
