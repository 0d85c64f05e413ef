#include "hoembedQuadraticMap.h"

#include "hoembedElementGeometry.h"
#include "hoembedVector3.h"

#include <algorithm>
#include <cmath>

namespace hoembed
{
using detail::Eval;

void MakeTriangleMap(const double* x, int n, QuadraticMap& m)
{
  // Monomial coefficients of x(u, v) = sum_a N_a(u, v) x_a, read off the expanded shape
  // functions (VTK order: corners 0, 1, 2; mid-edge nodes 3 (01), 4 (12), 5 (20)):
  //   tri6: L_u = 4 x3 - 3 x0 - x1, L_v = 4 x5 - 3 x0 - x2, Q_uu = 4 (x0 + x1) - 8 x3,
  //         Q_vv = 4 (x0 + x2) - 8 x5, Q_uv = 4 (x0 - x3 + x4 - x5);
  //   tri3: L_u = x1 - x0, L_v = x2 - x0, Q = 0.
  m = QuadraticMap();
  m.Dim = 2;
  const double* x0 = x;
  const double* x1 = x + 3;
  const double* x2 = x + 6;
  for (int d = 0; d < 3; ++d)
  {
    m.C[d] = x0[d];
    if (n == 6)
    {
      const double* x3 = x + 9;
      const double* x4 = x + 12;
      const double* x5 = x + 15;
      m.L[0][d] = 4.0 * x3[d] - 3.0 * x0[d] - x1[d];
      m.L[1][d] = 4.0 * x5[d] - 3.0 * x0[d] - x2[d];
      m.Q[0][0][d] = 4.0 * (x0[d] + x1[d]) - 8.0 * x3[d];
      m.Q[1][1][d] = 4.0 * (x0[d] + x2[d]) - 8.0 * x5[d];
      m.Q[0][1][d] = m.Q[1][0][d] = 4.0 * ((x0[d] - x3[d]) + (x4[d] - x5[d]));
    }
    else
    {
      m.L[0][d] = x1[d] - x0[d];
      m.L[1][d] = x2[d] - x0[d];
    }
  }
}

namespace
{
// b / F^2 for the Jacobians G at the 4 corners of a tet over which J is affine: b the
// smallest Bernstein coefficient of det J, F^2 the largest squared Frobenius norm (|J|_F^2
// is convex, so it peaks at a corner). Every singular value of J there is >= 2 b / F^2:
// det = s1 s2 s3 and s1 s2 <= (s1^2 + s2^2) / 2 <= F^2 / 2. 0 when b is not clear of
// round-off (1e-6 of the largest coefficient).
double SingularValueBound(const double G[4][3][3])
{
  double F2 = 0.0;
  for (int k = 0; k < 4; ++k)
  {
    double f2 = 0.0;
    for (int i = 0; i < 3; ++i)
      f2 += Dot(G[k][i], G[k][i]);
    F2 = std::max(F2, f2);
  }
  double hi = 0.0;
  const double b = DetBernsteinMin(G, &hi);
  if (!(b > 1e-6 * hi) || !(F2 > 0.0))
    return 0.0;
  return 2.0 * b / F2;
}

// Jacobians of the map at the corners centre + scale (e_k - centre) of the reference tet
// T scaled about its centroid, or of (T + eta) / 2 when eta is given.
void CornerJacobians(const QuadraticMap& m, const double* eta, double scale, double G[4][3][3])
{
  // J is affine in xi, so at the corner a + s (e_k - a) (anchor a: the centroid, or eta
  // with s = 1/2) it is (1 - s) J(a) + s J(e_k), where J(e_0) = L and J(e_j) = L + Q_j
  static const double Centre[3] = { 0.25, 0.25, 0.25 };
  const double* a = eta ? eta : Centre;
  const double s = eta ? 0.5 : scale;
  double A[3][3];
  for (int i = 0; i < 3; ++i)
    for (int d = 0; d < 3; ++d)
      A[i][d] = m.L[i][d] + m.Q[i][0][d] * a[0] + m.Q[i][1][d] * a[1] + m.Q[i][2][d] * a[2];
  for (int i = 0; i < 3; ++i)
    for (int d = 0; d < 3; ++d)
    {
      const double anchor = (1.0 - s) * A[i][d];
      G[0][i][d] = anchor + s * m.L[i][d];
      for (int k = 1; k < 4; ++k)
        G[k][i][d] = anchor + s * (m.L[i][d] + m.Q[i][k - 1][d]);
    }
}

// dist(eta, T) from below: the largest violated face inequality (normals of the faces
// u = 0, v = 0, w = 0 and u + v + w = 1 have lengths 1, 1, 1, sqrt(3))
double DistanceToReferenceTet(const double eta[3])
{
  return std::max({ -eta[0], -eta[1], -eta[2], (eta[0] + eta[1] + eta[2] - 1.0) / std::sqrt(3.0) });
}
} // namespace

bool Tet10JacobianProvablyPositive(const QuadraticMap& m)
{
  // J is affine in xi: the corner Jacobians are J(0) = L and J(e_j) = L + Q_j
  double G[4][3][3], hi = 0.0;
  CornerJacobians(m, nullptr, 1.0, G);
  const double lo = DetBernsteinMin(G, &hi);
  return lo > 1e-12 * hi;
}

bool Tet10JacobianProvablyPositive(const double* x)
{
  QuadraticMap m;
  MakeTetMap(x, 10, m);
  return Tet10JacobianProvablyPositive(m);
}

double TetMapExclusionRate(const QuadraticMap& m)
{
  double G[4][3][3];
  CornerJacobians(m, nullptr, ExclusionRateScale, G);
  return SingularValueBound(G);
}

double TetMapExclusionRadius(const QuadraticMap& m, const double eta[3], double rate)
{
  const double dT = DistanceToReferenceTet(eta);
  if (!(dT > 0.0))
    return 0.0;
  // eta in the reference tet scaled by s about its centroid, s = 1 - 4 min lambda: then
  // S = (T + eta) / 2 lies in T scaled by (1 + s) / 2, where `rate` holds
  const double lmin = std::min({ eta[0], eta[1], eta[2], 1.0 - eta[0] - eta[1] - eta[2] });
  if (rate > 0.0 && 0.5 * (2.0 - 4.0 * lmin) <= ExclusionRateScale)
    return rate * dT / (1.0 + 1e-6);
  double G[4][3][3];
  CornerJacobians(m, eta, 0.0, G);
  return SingularValueBound(G) * dT / (1.0 + 1e-6);
}

bool TetMapExcludes(const QuadraticMap& m, const double eta[3], double reach)
{
  return TetMapExclusionRadius(m, eta) > reach;
}

void MakeTetMap(const double* x, int n, QuadraticMap& m)
{
  // Monomial coefficients of x(xi) = sum_a N_a(xi) x_a in xi = (lambda_1, lambda_2,
  // lambda_3), read off the expanded shape functions. Corner k = i + 1 of xi_i, M0[i] its
  // mid-edge node with corner 0, Mid[i][j] the mid-edge node of corners i + 1, j + 1
  // (VTK order: 4 (01), 5 (12), 6 (02), 7 (03), 8 (13), 9 (23)):
  //   tet10: L_i = 4 x_M0[i] - 3 x0 - x_k, Q_ii = 4 (x0 + x_k) - 8 x_M0[i],
  //          Q_ij = 4 (x0 - x_M0[i] - x_M0[j] + x_Mid[i][j]);
  //   tet4:  L_i = x_k - x0, Q = 0.
  static const int M0[3] = { 4, 6, 7 };
  static const int Mid[3][3] = { { -1, 5, 8 }, { 5, -1, 9 }, { 8, 9, -1 } };
  m = QuadraticMap();
  m.Dim = 3;
  const double* x0 = x;
  for (int d = 0; d < 3; ++d)
  {
    m.C[d] = x0[d];
    for (int i = 0; i < 3; ++i)
    {
      const double xk = x[3 * (i + 1) + d];
      if (n != 10)
      {
        m.L[i][d] = xk - x0[d];
        continue;
      }
      const double mi = x[3 * M0[i] + d];
      m.L[i][d] = 4.0 * mi - 3.0 * x0[d] - xk;
      m.Q[i][i][d] = 4.0 * (x0[d] + xk) - 8.0 * mi;
      for (int j = 0; j < i; ++j)
        m.Q[i][j][d] = m.Q[j][i][d] =
          4.0 * ((x0[d] - mi) + (x[3 * Mid[i][j] + d] - x[3 * M0[j] + d]));
    }
  }
}

void EvaluateMap(const QuadraticMap& m, const double* xi, double x[3], double (*J)[3])
{
  double Jl[3][3];
  if (m.Dim == 2)
    Eval<2>(m, xi, x, Jl);
  else
    Eval<3>(m, xi, x, Jl);
  if (J)
    for (int i = 0; i < m.Dim; ++i)
      for (int d = 0; d < 3; ++d)
        J[i][d] = Jl[i][d];
}

bool TetIsValid(const double* x, int nodesPerCell, const QuadraticMap& m)
{
  if (nodesPerCell == 10)
    return Tet10JacobianProvablyPositive(m) || Tet10IsValid(x);
  double l = 0.0;
  for (int a = 1; a < 4; ++a)
    for (int d = 0; d < 3; ++d)
      l = std::max(l, std::fabs(x[3 * a + d] - x[d]));
  return Tet4JacobianDeterminant(x) > 1e-12 * l * l * l;
}

bool TetIsValid(const double* x, int nodesPerCell)
{
  QuadraticMap m;
  MakeTetMap(x, nodesPerCell, m);
  return TetIsValid(x, nodesPerCell, m);
}
} // namespace hoembed
