// The closest-point and map kernels of hoembedClosestPoint.h against references nobody
// here wrote: VTK's vtkQuadraticTetra / vtkTetra interpolation and shape functions, dense
// lattice sampling and constrained solves from several starts.
#include "hoembedQuadraticMapTestUtilities.h"
#include "hoembedEmbeddingTestUtilities.h"

#include "hoembedBoundaryNormals.h"
#include "hoembedClosestPoint.h"
#include "hoembedElementGeometry.h"
#include "hoembedEmbeddingFlood.h"
#include "hoembedBoxGrid.h"
#include "hoembedEmbeddingSearch.h"
#include "hoembedShapeFunctions.h"
#include "hoembedTetBarycentric.h"
#include "vtkEmbeddingCoordinatesFilter.h"
#include "vtkTet10Mesher.h"

#include "vtkAppendPolyData.h"
#include "vtkCallbackCommand.h"
#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCommand.h"
#include "vtkDoubleArray.h"
#include "vtkExecutive.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkOBJReader.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkQuadraticTetra.h"
#include "vtkSMPTools.h"
#include "vtkSignedCharArray.h"
#include "vtkSphereSource.h"
#include "vtkStringArray.h"
#include "vtkTetra.h"
#include "vtkTransform.h"
#include "vtkTransformPolyDataFilter.h"
#include "vtkXMLPolyDataReader.h"
#include "vtkXMLPolyDataWriter.h"

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>

using hoembed_test::MakeBoxTetMesh;

namespace
{

void TestKernels()
{
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  // tri6 patches: a flat triangle with perturbed mid-edge nodes
  int worse = 0, outside = 0, notLocal = 0, onEdge = 0;
  for (int trial = 0; trial < 40; ++trial)
  {
    double x[18] = { 0, 0, 0, 1, 0, 0, 0, 1, 0, 0.5, 0, 0, 0.5, 0.5, 0, 0, 0.5, 0 };
    for (int a = 3; a < 6; ++a)
      for (int d = 0; d < 3; ++d)
        x[3 * a + d] += 0.2 * U(rng);
    hoembed::QuadraticMap m;
    hoembed::MakeTriangleMap(x, 6, m);
    for (int q = 0; q < 10; ++q)
    {
      const double v[3] = { 0.5 + 1.2 * U(rng), 0.5 + 1.2 * U(rng), 0.8 * U(rng) };
      // best of the linear start and three starts near the corners (one start can end
      // in a local minimum of a strongly curved patch)
      const double starts[4][2] = { { 0, 0 }, { 0.8, 0.1 }, { 0.1, 0.8 }, { 0.1, 0.1 } };
      hoembed::ClosestPointResult r, rs;
      for (int k = 0; k < 4; ++k)
      {
        double st[2] = { starts[k][0], starts[k][1] };
        if (k == 0)
          hoembed::LinearStart(m, v, st);
        hoembed::ClosestPointOnMap(m, v, st, rs);
        if (rs.Param[0] < 0 || rs.Param[1] < 0 || rs.Param[0] + rs.Param[1] > 1.0 || !rs.Converged)
          ++outside;
        // every answer is a local minimum over the triangle: no nearer point around it
        // (this checks the multipliers of the edge and corner answers)
        const int bits = rs.Active & 7;
        onEdge += bits == 1 || bits == 2 || bits == 4;
        bool nearer = false;
        for (const double h : { 1e-5, 1e-4, 1e-3 })
          for (int a = 0; a < 16 && !nearer; ++a)
          {
            const double uv[2] = { rs.Param[0] + h * std::cos(0.3927 * a),
              rs.Param[1] + h * std::sin(0.3927 * a) };
            if (uv[0] < 0 || uv[1] < 0 || uv[0] + uv[1] > 1)
              continue;
            double y[3];
            hoembed::EvaluateMap(m, uv, y);
            const double d2 = (y[0] - v[0]) * (y[0] - v[0]) + (y[1] - v[1]) * (y[1] - v[1]) +
              (y[2] - v[2]) * (y[2] - v[2]);
            nearer = d2 < rs.Distance2 * (1.0 - 1e-12) - 1e-24;
          }
        notLocal += nearer;
        if (k == 0 || rs.Distance2 < r.Distance2)
          r = rs;
      }
      // dense sampling with the shared shape functions
      double best = 1e300;
      const int n = 200;
      for (int i = 0; i <= n; ++i)
        for (int j = 0; i + j <= n; ++j)
        {
          const double uv[2] = { double(i) / n, double(j) / n };
          double N[6], p[3];
          hoembed::Tri6Shape(uv, N);
          hoembed::Interpolate(6, N, x, p);
          const double d2 = (p[0] - v[0]) * (p[0] - v[0]) + (p[1] - v[1]) * (p[1] - v[1]) +
            (p[2] - v[2]) * (p[2] - v[2]);
          best = std::min(best, d2);
        }
      if (std::sqrt(r.Distance2) > std::sqrt(best) + 1e-12)
        ++worse;
    }
  }
  HOEMBED_CHECK(worse == 0, "tri6 closest point worse than dense sampling for %d queries", worse);
  HOEMBED_CHECK(
    outside == 0, "tri6 closest point left the triangle or did not converge %d times", outside);
  HOEMBED_CHECK(
    notLocal == 0, "tri6 closest point: %d answers with a nearer point around them", notLocal);
  HOEMBED_CHECK(
    onEdge >= 40, "tri6 closest point: only %d answers on an edge (test setup)", onEdge);
  std::printf("tri6 closest point: %d answers on an edge, %d not local minima\n", onEdge, notLocal);

  // tet10: the monomial map matches VTK's vtkQuadraticTetra; inside points are recovered;
  // outside points are no worse than dense sampling
  vtkNew<vtkQuadraticTetra> qt;
  int mapErr = 0, insideErr = 0, tetWorse = 0;
  for (int trial = 0; trial < 20; ++trial)
  {
    double x[30];
    for (int a = 0; a < 10; ++a)
    {
      for (int d = 0; d < 3; ++d)
        x[3 * a + d] = hoembed::Tet10NodeParametric[a][d] + (a >= 4 ? 0.06 * U(rng) : 0.0);
      qt->GetPoints()->SetPoint(a, x + 3 * a);
      qt->GetPointIds()->SetId(a, a);
    }
    hoembed::QuadraticMap m;
    hoembed::MakeTetMap(x, 10, m);
    for (int q = 0; q < 20; ++q)
    {
      double pc[3] = { 0.5 * (1 + U(rng)), 0.5 * (1 + U(rng)), 0.5 * (1 + U(rng)) };
      if (pc[0] + pc[1] + pc[2] > 0.999)
      {
        const double s = 0.999 / (pc[0] + pc[1] + pc[2]);
        pc[0] *= s;
        pc[1] *= s;
        pc[2] *= s;
      }
      double a[3], b[3], w[10];
      int sub;
      hoembed::EvaluateMap(m, pc, a);
      qt->EvaluateLocation(sub, pc, b, w);
      if (std::fabs(a[0] - b[0]) + std::fabs(a[1] - b[1]) + std::fabs(a[2] - b[2]) > 1e-13)
        ++mapErr;
      hoembed::ClosestPointResult r;
      hoembed::ClosestPointOnMap(m, a, nullptr, r);
      if (r.Distance2 > 1e-26 || std::fabs(r.Param[0] - pc[0]) > 1e-9)
        ++insideErr;
      const double v[3] = { 0.3 + 1.5 * U(rng), 0.3 + 1.5 * U(rng), 0.3 + 1.5 * U(rng) };
      hoembed::ClosestPointOnMap(m, v, nullptr, r);
      if (!r.Converged)
        ++tetWorse;
      const double best = LatticeDistance2(m, v, 40);
      if (std::sqrt(r.Distance2) > std::sqrt(best) + 1e-12)
        ++tetWorse;
    }
  }
  HOEMBED_CHECK(mapErr == 0, "tet10 monomial map differs from vtkQuadraticTetra %d times", mapErr);
  HOEMBED_CHECK(insideErr == 0, "inside points not recovered %d times", insideErr);
  HOEMBED_CHECK(tetWorse == 0, "tet10 closest point worse than sampling %d times", tetWorse);
}

// The closed-form tet10 map (MakeTetMap from the corner Jacobians) against the shape
// functions, and the fast validity test (Bernstein coefficients of det J) against
// hoembed::Tet10IsValid and a dense sample of det J: it may only accept valid elements.
void TestTet10Validity()
{
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  int accepted = 0, rejected = 0, wrongAccept = 0, notFull = 0;
  double mapErr = 0.0;
  for (int trial = 0; trial < 400; ++trial)
  {
    const double amp = 0.05 + 0.4 * (trial % 8) / 7.0;
    double x[30];
    for (int a = 0; a < 10; ++a)
      for (int d = 0; d < 3; ++d)
        x[3 * a + d] = RefTet10[a][d] + (a < 4 ? 0.3 : 1.0) * amp * U(rng);
    hoembed::QuadraticMap m;
    hoembed::MakeTetMap(x, 10, m);
    double minDet = std::numeric_limits<double>::infinity();
    const int n = 12;
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j)
        for (int k = 0; i + j + k <= n; ++k)
        {
          const double pc[3] = { double(i) / n, double(j) / n, double(k) / n };
          double N[10], p[3] = { 0, 0, 0 }, q[3], J[3][3];
          hoembed::Tet10Shape(pc, N);
          for (int a = 0; a < 10; ++a)
            for (int d = 0; d < 3; ++d)
              p[d] += N[a] * x[3 * a + d];
          hoembed::EvaluateMap(m, pc, q, J);
          for (int d = 0; d < 3; ++d)
            mapErr = std::max(mapErr, std::fabs(p[d] - q[d]));
          const double det = J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) -
            J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
            J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
          minDet = std::min(minDet, det);
        }
    const bool fast = hoembed::Tet10JacobianProvablyPositive(x);
    (fast ? accepted : rejected)++;
    if (fast && !(minDet > 0.0))
      ++wrongAccept;
    if (fast && !hoembed::Tet10IsValid(x))
      ++notFull;
  }
  HOEMBED_CHECK(mapErr <= 1e-13, "tet10 map: max deviation from the shape functions %g", mapErr);
  HOEMBED_CHECK(
    wrongAccept == 0, "fast tet10 validity: %d elements with det J <= 0 accepted", wrongAccept);
  HOEMBED_CHECK(
    notFull == 0, "fast tet10 validity: %d accepted elements Tet10IsValid rejects", notFull);
  HOEMBED_CHECK(accepted > 50 && rejected > 50,
    "fast tet10 validity: %d accepted, %d rejected (test setup)", accepted, rejected);
  std::printf("tet10 validity: %d accepted, %d not proven by the fast test; map error %.2g\n",
    accepted, rejected, mapErr);
}

// The closed-form monomial maps (MakeTriangleMap for tri3/tri6, MakeTetMap for
// tet4/tet10) against the shape functions and their derivatives at random parametric
// points of randomly perturbed elements: value and Jacobian. A wrong node in one
// coefficient puts the error at O(1).
void TestMonomialMaps()
{
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> U(-1.0, 1.0), P(0.0, 1.0);
  double worst[4] = { 0, 0, 0, 0 }; // tri3, tri6, tet4, tet10
  for (int trial = 0; trial < 50; ++trial)
    for (int kind = 0; kind < 4; ++kind)
    {
      const int dim = kind < 2 ? 2 : 3;
      const int n = kind == 0 ? 3 : (kind == 1 ? 6 : (kind == 2 ? 4 : 10));
      double x[30];
      for (int k = 0; k < 3 * n; ++k)
        x[k] = 2.0 * U(rng);
      hoembed::QuadraticMap m;
      if (dim == 2)
        hoembed::MakeTriangleMap(x, n, m);
      else
        hoembed::MakeTetMap(x, n, m);
      HOEMBED_CHECK(m.Dim == dim, "monomial map of %d nodes: Dim %d", n, m.Dim);
      for (int q = 0; q < 10; ++q)
      {
        double xi[3] = { P(rng), P(rng), dim == 3 ? P(rng) : 0.0 };
        double N[10], dN[30];
        if (kind == 0)
        {
          hoembed::Tri3Shape(xi, N);
          hoembed::Tri3Derivs(xi, dN);
        }
        else if (kind == 1)
        {
          hoembed::Tri6Shape(xi, N);
          hoembed::Tri6Derivs(xi, dN);
        }
        else if (kind == 2)
        {
          hoembed::Tet4Shape(xi, N);
          hoembed::Tet4Derivs(xi, dN);
        }
        else
        {
          hoembed::Tet10Shape(xi, N);
          hoembed::Tet10Derivs(xi, dN);
        }
        double p[3] = { 0, 0, 0 }, Jref[3][3] = {}, y[3], J[3][3];
        for (int a = 0; a < n; ++a)
          for (int d = 0; d < 3; ++d)
          {
            p[d] += N[a] * x[3 * a + d];
            for (int i = 0; i < dim; ++i)
              Jref[i][d] += dN[i * n + a] * x[3 * a + d];
          }
        hoembed::EvaluateMap(m, xi, y, J);
        for (int d = 0; d < 3; ++d)
        {
          worst[kind] = std::max(worst[kind], std::fabs(p[d] - y[d]));
          for (int i = 0; i < dim; ++i)
            worst[kind] = std::max(worst[kind], std::fabs(Jref[i][d] - J[i][d]));
        }
      }
    }
  const char* names[4] = { "tri3", "tri6", "tet4", "tet10" };
  for (int kind = 0; kind < 4; ++kind)
    HOEMBED_CHECK(worst[kind] <= 1e-12,
      "%s monomial map: max deviation from the shape functions %g", names[kind], worst[kind]);
  std::printf("monomial maps: max deviation tri3 %.2g, tri6 %.2g, tet4 %.2g, tet10 %.2g\n",
    worst[0], worst[1], worst[2], worst[3]);
}

// hoembed::TetMapExcludes (the rule that rejects a cell for a point the pseudo-normal puts
// outside) against the distance from x(eta) to the element by brute force (constrained
// solves from 5 starts and a dense sample): it may only exclude when that distance exceeds
// the reach, for reaches on both sides of it. The same for the radius of
// TetMapExclusionRadius with the element's precomputed TetMapExclusionRate.
void TestTetMapExcludes()
{
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  int excluded = 0, wrong = 0, tried = 0, byRate = 0, wrongRadius = 0;
  for (int trial = 0; trial < 60; ++trial)
  {
    // anisotropic scales from 1/20 to 20: a rule with the wrong scaling fails here
    double scale[3];
    for (double& sc : scale)
      sc = std::pow(20.0, U(rng));
    double x[30];
    for (int a = 0; a < 10; ++a)
      for (int d = 0; d < 3; ++d)
        x[3 * a + d] = scale[d] * (RefTet10[a][d] + (a < 4 ? 0.05 : 0.12) * U(rng));
    if (!hoembed::Tet10JacobianProvablyPositive(x))
      continue;
    hoembed::QuadraticMap m;
    hoembed::MakeTetMap(x, 10, m);
    const double rate = hoembed::TetMapExclusionRate(m);
    for (int q = 0; q < 40; ++q)
    {
      // a parametric point outside the element, near one of its faces or corners (the
      // first 20), or just beyond a face, where the element's rate serves (the others)
      double eta[3] = { 0.3 + 0.6 * U(rng), 0.3 + 0.6 * U(rng), 0.3 + 0.6 * U(rng) };
      if (q >= 20)
      {
        double L[4], sum = 0.0;
        for (double& l : L)
          sum += (l = 0.5 * (1.0 + U(rng)));
        const int face = q % 4;
        L[face] = -0.05 * (1.0 + U(rng)) * sum; // beyond the face L_face = 0, up to 0.1
        sum = L[0] + L[1] + L[2] + L[3];
        for (int i = 0; i < 3; ++i)
          eta[i] = L[i + 1] / sum;
      }
      if (eta[0] >= 0 && eta[1] >= 0 && eta[2] >= 0 && eta[0] + eta[1] + eta[2] <= 1)
        continue;
      double v[3];
      hoembed::EvaluateMap(m, eta, v);
      const double dist = BruteDistanceToTetMap(m, v);
      const double lmin = std::min({ eta[0], eta[1], eta[2], 1.0 - eta[0] - eta[1] - eta[2] });
      if (rate > 0.0 && 1.0 - 2.0 * lmin <= hoembed::ExclusionRateScale)
        ++byRate;
      if (hoembed::TetMapExclusionRadius(m, eta, rate) > dist)
        ++wrongRadius;
      for (const double f : { 0.0, 0.3, 0.9, 1.1, 3.0 })
      {
        ++tried;
        if (hoembed::TetMapExcludes(m, eta, f * dist))
        {
          ++excluded;
          if (f * dist >= dist)
            ++wrong;
        }
      }
    }
  }
  HOEMBED_CHECK(wrong == 0,
    "TetMapExcludes: %d exclusions with a point of the element "
    "within reach",
    wrong);
  HOEMBED_CHECK(
    excluded > tried / 10, "TetMapExcludes: only %d of %d excluded (test setup)", excluded, tried);
  HOEMBED_CHECK(
    wrongRadius == 0, "TetMapExclusionRadius: %d radii beyond the element's distance", wrongRadius);
  HOEMBED_CHECK(byRate >= 20,
    "TetMapExclusionRadius: the element's rate served only %d points "
    "(test setup)",
    byRate);
  std::printf("cell exclusion: %d of %d (point, reach) pairs excluded, none wrongly; %d radii "
              "from the element's rate\n",
    excluded, tried, byRate);
}

} // namespace

int main(int, char*[])
{
  TestKernels();
  TestTet10Validity();
  TestMonomialMaps();
  TestTetMapExcludes();
  return hoembed_test::Report("TestClosestPoint");
}
