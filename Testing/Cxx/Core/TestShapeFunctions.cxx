// Shape functions of hoembed (tet4, tet10, tri3, tri6) against VTK's own cells:
// values and derivatives at random points, node parametric coordinates, partition of
// unity, face/edge tables and the face -> tet parametric map.
#include "hoembedShapeFunctions.h"
#include "hoembedTestUtilities.h"

#include "vtkNew.h"
#include "vtkQuadraticTetra.h"
#include "vtkQuadraticTriangle.h"
#include "vtkTetra.h"
#include "vtkTriangle.h"

#include <cmath>
#include <random>

namespace
{
const double Tol = 1e-12;

double MaxDiff(const double* a, const double* b, int n)
{
  double m = 0.0;
  for (int i = 0; i < n; ++i)
    m = std::max(m, std::abs(a[i] - b[i]));
  return m;
}

double Sum(const double* a, int n)
{
  double s = 0.0;
  for (int i = 0; i < n; ++i)
    s += a[i];
  return s;
}

// A random point in the reference tet (or, when `outside`, anywhere near it: polynomials
// must agree everywhere, not only inside).
void RandomTetPoint(std::mt19937& rng, bool outside, double pc[3])
{
  std::uniform_real_distribution<double> u(outside ? -0.5 : 0.0, outside ? 1.5 : 1.0);
  do
  {
    pc[0] = u(rng);
    pc[1] = u(rng);
    pc[2] = u(rng);
  } while (!outside && pc[0] + pc[1] + pc[2] > 1.0);
}

void TestTetFunctions(std::mt19937& rng)
{
  double worst4 = 0.0, worst10 = 0.0;
  for (int trial = 0; trial < 2000; ++trial)
  {
    double pc[3];
    RandomTetPoint(rng, trial % 4 == 3, pc);
    double N[10], Nv[10], dN[30], dNv[30];
    hoembed::Tet4Shape(pc, N);
    vtkTetra::InterpolationFunctions(pc, Nv);
    worst4 = std::max(worst4, MaxDiff(N, Nv, 4));
    HOEMBED_CHECK(std::abs(Sum(N, 4) - 1.0) < Tol, "tet4 partition of unity %g", Sum(N, 4));
    hoembed::Tet4Derivs(pc, dN);
    vtkTetra::InterpolationDerivs(pc, dNv);
    worst4 = std::max(worst4, MaxDiff(dN, dNv, 12));
    for (int d = 0; d < 3; ++d)
      HOEMBED_CHECK(std::abs(Sum(dN + 4 * d, 4)) < Tol, "tet4 derivative sum %d", d);

    hoembed::Tet10Shape(pc, N);
    vtkQuadraticTetra::InterpolationFunctions(pc, Nv);
    worst10 = std::max(worst10, MaxDiff(N, Nv, 10));
    HOEMBED_CHECK(std::abs(Sum(N, 10) - 1.0) < Tol, "tet10 partition of unity %g", Sum(N, 10));
    hoembed::Tet10Derivs(pc, dN);
    vtkQuadraticTetra::InterpolationDerivs(pc, dNv);
    worst10 = std::max(worst10, MaxDiff(dN, dNv, 30));
    for (int d = 0; d < 3; ++d)
      HOEMBED_CHECK(std::abs(Sum(dN + 10 * d, 10)) < Tol, "tet10 derivative sum %d", d);

    // Derivatives against central differences of the shape functions (independent of VTK).
    const double h = 1e-6;
    for (int d = 0; d < 3; ++d)
    {
      double p[3] = { pc[0], pc[1], pc[2] }, m[3] = { pc[0], pc[1], pc[2] };
      p[d] += h;
      m[d] -= h;
      double Np[10], Nm[10];
      hoembed::Tet10Shape(p, Np);
      hoembed::Tet10Shape(m, Nm);
      for (int i = 0; i < 10; ++i)
        HOEMBED_CHECK(std::abs((Np[i] - Nm[i]) / (2 * h) - dN[10 * d + i]) < 1e-7,
          "tet10 dN%d/d%d vs finite differences", i, d);
    }
  }
  std::printf("tet4 max |hoembed - vtkTetra| = %.3g\n", worst4);
  std::printf("tet10 max |hoembed - vtkQuadraticTetra| = %.3g\n", worst10);
  HOEMBED_CHECK(worst4 < Tol, "tet4 differs from vtkTetra by %g", worst4);
  HOEMBED_CHECK(worst10 < Tol, "tet10 differs from vtkQuadraticTetra by %g", worst10);
}

void TestTriFunctions(std::mt19937& rng)
{
  std::uniform_real_distribution<double> u(-0.25, 1.25);
  double worst3 = 0.0, worst6 = 0.0;
  for (int trial = 0; trial < 2000; ++trial)
  {
    double pc[3] = { u(rng), u(rng), 0.0 };
    double N[6], Nv[6], dN[12], dNv[12];
    hoembed::Tri3Shape(pc, N);
    vtkTriangle::InterpolationFunctions(pc, Nv);
    worst3 = std::max(worst3, MaxDiff(N, Nv, 3));
    HOEMBED_CHECK(std::abs(Sum(N, 3) - 1.0) < Tol, "tri3 partition of unity");
    hoembed::Tri3Derivs(pc, dN);
    vtkTriangle::InterpolationDerivs(pc, dNv);
    worst3 = std::max(worst3, MaxDiff(dN, dNv, 6));

    hoembed::Tri6Shape(pc, N);
    vtkQuadraticTriangle::InterpolationFunctions(pc, Nv);
    worst6 = std::max(worst6, MaxDiff(N, Nv, 6));
    HOEMBED_CHECK(std::abs(Sum(N, 6) - 1.0) < Tol, "tri6 partition of unity");
    hoembed::Tri6Derivs(pc, dN);
    vtkQuadraticTriangle::InterpolationDerivs(pc, dNv);
    worst6 = std::max(worst6, MaxDiff(dN, dNv, 12));
    for (int d = 0; d < 2; ++d)
      HOEMBED_CHECK(std::abs(Sum(dN + 6 * d, 6)) < Tol, "tri6 derivative sum %d", d);
  }
  std::printf("tri3 max |hoembed - vtkTriangle| = %.3g\n", worst3);
  std::printf("tri6 max |hoembed - vtkQuadraticTriangle| = %.3g\n", worst6);
  HOEMBED_CHECK(worst3 < Tol, "tri3 differs from vtkTriangle by %g", worst3);
  HOEMBED_CHECK(worst6 < Tol, "tri6 differs from vtkQuadraticTriangle by %g", worst6);
}

void TestNodes()
{
  vtkNew<vtkQuadraticTetra> qt;
  vtkNew<vtkTetra> lt;
  const double* pq = qt->GetParametricCoords();
  const double* pl = lt->GetParametricCoords();
  for (int i = 0; i < 10; ++i)
  {
    for (int d = 0; d < 3; ++d)
    {
      HOEMBED_CHECK(hoembed::Tet10NodeParametric[i][d] == pq[3 * i + d],
        "tet10 node %d coordinate %d: %g vs VTK %g", i, d, hoembed::Tet10NodeParametric[i][d],
        pq[3 * i + d]);
      if (i < 4)
        HOEMBED_CHECK(hoembed::Tet10NodeParametric[i][d] == pl[3 * i + d], "tet4 node %d", i);
    }
    // Kronecker property at the nodes.
    double N[10];
    hoembed::Tet10Shape(hoembed::Tet10NodeParametric[i], N);
    for (int j = 0; j < 10; ++j)
      HOEMBED_CHECK(
        std::abs(N[j] - (i == j ? 1.0 : 0.0)) < Tol, "tet10 N%d(node %d) = %g", j, i, N[j]);
  }
  vtkNew<vtkQuadraticTriangle> q6;
  const double* p6 = q6->GetParametricCoords();
  for (int i = 0; i < 6; ++i)
  {
    double N[6];
    hoembed::Tri6Shape(p6 + 3 * i, N);
    for (int j = 0; j < 6; ++j)
      HOEMBED_CHECK(
        std::abs(N[j] - (i == j ? 1.0 : 0.0)) < Tol, "tri6 N%d(node %d) = %g", j, i, N[j]);
  }
  // Mid-edge nodes sit on the edges TetEdgeCorners says, as VTK's edge table says.
  for (int e = 0; e < 6; ++e)
  {
    const vtkIdType* ve = vtkQuadraticTetra::GetEdgeArray(e);
    HOEMBED_CHECK(ve[0] == hoembed::TetEdgeCorners[e][0] &&
        ve[1] == hoembed::TetEdgeCorners[e][1] && ve[2] == 4 + e,
      "edge %d: hoembed (%d %d %d) vs VTK (%lld %lld %lld)", e, hoembed::TetEdgeCorners[e][0],
      hoembed::TetEdgeCorners[e][1], 4 + e, (long long)ve[0], (long long)ve[1], (long long)ve[2]);
    for (int d = 0; d < 3; ++d)
    {
      const double mid = 0.5 *
        (hoembed::Tet10NodeParametric[hoembed::TetEdgeCorners[e][0]][d] +
          hoembed::Tet10NodeParametric[hoembed::TetEdgeCorners[e][1]][d]);
      HOEMBED_CHECK(hoembed::Tet10NodeParametric[4 + e][d] == mid, "mid node %d", 4 + e);
    }
  }
}

void TestFaces(std::mt19937& rng)
{
  for (int f = 0; f < 4; ++f)
  {
    const vtkIdType* q = vtkQuadraticTetra::GetFaceArray(f);
    const vtkIdType* l = vtkTetra::GetFaceArray(f);
    for (int a = 0; a < 6; ++a)
      HOEMBED_CHECK(q[a] == hoembed::TetFaceNodes[f][a], "face %d node %d: %d vs VTK %lld", f, a,
        hoembed::TetFaceNodes[f][a], (long long)q[a]);
    for (int a = 0; a < 3; ++a)
      HOEMBED_CHECK(l[a] == hoembed::TetFaceNodes[f][a], "tet4 face %d node %d: %d vs VTK %lld", f,
        a, hoembed::TetFaceNodes[f][a], (long long)l[a]);
    // Mid nodes are the mids of ab, bc, ca.
    for (int e = 0; e < 3; ++e)
    {
      const int a = hoembed::TetFaceNodes[f][e], b = hoembed::TetFaceNodes[f][(e + 1) % 3];
      const int m = hoembed::TetFaceNodes[f][3 + e];
      const int ce0 = hoembed::TetEdgeCorners[m - 4][0], ce1 = hoembed::TetEdgeCorners[m - 4][1];
      HOEMBED_CHECK((ce0 == a && ce1 == b) || (ce0 == b && ce1 == a),
        "face %d mid %d is not on edge (%d, %d)", f, m, a, b);
    }
    // The opposite corner is not on the face.
    for (int a = 0; a < 3; ++a)
      HOEMBED_CHECK(hoembed::TetFaceNodes[f][a] != hoembed::TetFaceOpposite[f], "opposite %d", f);
  }

  // Outward for positive tets (the reference tet and random positive ones).
  for (int trial = 0; trial < 200; ++trial)
  {
    double x[4][3] = { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } };
    if (trial > 0)
    {
      std::uniform_real_distribution<double> u(-1, 1);
      for (auto& p : x)
        for (double& c : p)
          c = u(rng);
    }
    double e[3][3];
    for (int r = 0; r < 3; ++r)
      for (int d = 0; d < 3; ++d)
        e[r][d] = x[r + 1][d] - x[0][d];
    const double det = e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
      e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
      e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]);
    if (std::abs(det) < 1e-3)
      continue;
    if (det < 0)
      std::swap(x[1], x[2]);
    for (int f = 0; f < 4; ++f)
    {
      const double* a = x[hoembed::TetFaceNodes[f][0]];
      const double* b = x[hoembed::TetFaceNodes[f][1]];
      const double* c = x[hoembed::TetFaceNodes[f][2]];
      const double* o = x[hoembed::TetFaceOpposite[f]];
      const double u[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] };
      const double v[3] = { c[0] - a[0], c[1] - a[1], c[2] - a[2] };
      const double n[3] = { u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0] };
      const double w[3] = { a[0] - o[0], a[1] - o[1], a[2] - o[2] };
      HOEMBED_CHECK(n[0] * w[0] + n[1] * w[1] + n[2] * w[2] > 0.0,
        "face %d normal points inward (trial %d)", f, trial);
    }
  }

  // The face map sends face nodes onto the right tet nodes, and the tet10 shape functions
  // restricted to a face are the face's tri6 shape functions.
  const double faceUV[6][2] = { { 0, 0 }, { 1, 0 }, { 0, 1 }, { 0.5, 0 }, { 0.5, 0.5 },
    { 0, 0.5 } };
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  for (int f = 0; f < 4; ++f)
  {
    for (int k = 0; k < 6; ++k)
    {
      double pc[3];
      hoembed::TetFaceToTetParametric(f, faceUV[k], pc);
      const double* want = hoembed::Tet10NodeParametric[hoembed::TetFaceNodes[f][k]];
      HOEMBED_CHECK(MaxDiff(pc, want, 3) < Tol, "face %d node %d maps to (%g %g %g)", f, k, pc[0],
        pc[1], pc[2]);
    }
    for (int trial = 0; trial < 200; ++trial)
    {
      double uv[2] = { u01(rng), u01(rng) };
      if (uv[0] + uv[1] > 1)
      {
        uv[0] = 1 - uv[0];
        uv[1] = 1 - uv[1];
      }
      double pc[3], Nt[10], Nf[6];
      hoembed::TetFaceToTetParametric(f, uv, pc);
      hoembed::Tet10Shape(pc, Nt);
      hoembed::Tri6Shape(uv, Nf);
      double onFace = 0.0;
      for (int k = 0; k < 6; ++k)
      {
        HOEMBED_CHECK(std::abs(Nt[hoembed::TetFaceNodes[f][k]] - Nf[k]) < Tol,
          "face %d: tet10 N%d != tri6 N%d", f, hoembed::TetFaceNodes[f][k], k);
        onFace += Nt[hoembed::TetFaceNodes[f][k]];
      }
      HOEMBED_CHECK(std::abs(onFace - 1.0) < Tol, "face %d: off-face shape functions nonzero", f);
      HOEMBED_CHECK(std::abs(Nt[hoembed::TetFaceOpposite[f]]) < Tol, "opposite corner nonzero");
    }
  }
}

void TestInterpolate(std::mt19937& rng)
{
  // Interpolating the nodes of a straight tet10 reproduces the affine map exactly.
  std::uniform_real_distribution<double> u(-1, 1);
  double x[30];
  for (int i = 0; i < 12; ++i)
    x[i] = u(rng);
  for (int e = 0; e < 6; ++e)
    for (int d = 0; d < 3; ++d)
      x[3 * (4 + e) + d] =
        0.5 * (x[3 * hoembed::TetEdgeCorners[e][0] + d] + x[3 * hoembed::TetEdgeCorners[e][1] + d]);
  for (int trial = 0; trial < 100; ++trial)
  {
    double pc[3], N[10], y[3], z[3];
    RandomTetPoint(rng, false, pc);
    hoembed::Tet10Shape(pc, N);
    hoembed::Interpolate(10, N, x, y);
    hoembed::Tet4Shape(pc, N);
    hoembed::Interpolate(4, N, x, z);
    HOEMBED_CHECK(MaxDiff(y, z, 3) < Tol, "straight tet10 is not affine");
  }
}
} // namespace

int main(int, char*[])
{
  std::mt19937 rng(12345);
  TestTetFunctions(rng);
  TestTriFunctions(rng);
  TestNodes();
  TestFaces(rng);
  TestInterpolate(rng);
  return hoembed_test::Report("TestShapeFunctions");
}
