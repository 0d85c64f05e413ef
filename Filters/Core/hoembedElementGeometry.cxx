#include "hoembedElementGeometry.h"
#include "hoembedVector3.h"
#include "hoembedLanes.h"
#include "hoembedShapeFunctions.h"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace hoembed
{
namespace
{
// The 20 multi-indices (i, j, k, l), i + j + k + l = 3, of the cubic Bernstein basis on a
// tet, with barycentric weights (L0, L1, L2, L3) = (i, j, k, l) / 3 at the lattice nodes.
struct CubicLattice
{
  std::array<std::array<int, 4>, 20> Index;
  Eigen::Matrix<double, 20, 20> LagrangeToBernstein; // c = M^-1 f

  CubicLattice()
  {
    int n = 0;
    for (int i = 3; i >= 0; --i)
      for (int j = 3 - i; j >= 0; --j)
        for (int k = 3 - i - j; k >= 0; --k)
          Index[n++] = { i, j, k, 3 - i - j - k };
    static const double fact[4] = { 1, 1, 2, 6 };
    Eigen::Matrix<double, 20, 20> M;
    for (int p = 0; p < 20; ++p)
    {
      double L[4];
      for (int a = 0; a < 4; ++a)
        L[a] = Index[p][a] / 3.0;
      for (int q = 0; q < 20; ++q)
      {
        double b = 6.0;
        for (int a = 0; a < 4; ++a)
          b *= std::pow(L[a], Index[q][a]) / fact[Index[q][a]];
        M(p, q) = b;
      }
    }
    LagrangeToBernstein = M.inverse();
  }
};

const CubicLattice& Lattice()
{
  static const CubicLattice lattice;
  return lattice;
}

// Parametric (r, s, t) of the lattice node p of the sub-tet with parametric corners c.
void LatticePoint(const CubicLattice& lat, int p, const double c[4][3], double pc[3])
{
  for (int d = 0; d < 3; ++d)
  {
    pc[d] = 0.0;
    for (int a = 0; a < 4; ++a)
      pc[d] += lat.Index[p][a] / 3.0 * c[a][d];
  }
}

// Bernstein coefficients of det J restricted to a parametric sub-tet; returns whether a
// lattice (sample) value is <= 0, i.e. the element is certainly invalid.
bool SubTetCoefficients(const double* x, const double c[4][3], double coef[20])
{
  const CubicLattice& lat = Lattice();
  Eigen::Matrix<double, 20, 1> f;
  bool sampledNonPositive = false;
  for (int p = 0; p < 20; ++p)
  {
    double pc[3];
    LatticePoint(lat, p, c, pc);
    f[p] = Tet10JacobianDeterminant(x, pc);
    sampledNonPositive |= !(f[p] > 0.0);
  }
  Eigen::Matrix<double, 20, 1> b = lat.LagrangeToBernstein * f;
  for (int q = 0; q < 20; ++q)
    coef[q] = b[q];
  return sampledNonPositive;
}

// 1e-12 of the largest coefficient: far above the round-off of computing the 20
// coefficients from sampled det J values, far below any element worth keeping.
double RoundOffAllowance(const double coef[20])
{
  double m = 0.0;
  for (int q = 0; q < 20; ++q)
    m = std::max(m, std::abs(coef[q]));
  return 1e-12 * m;
}

void Mid(const double a[3], const double b[3], double m[3])
{
  for (int d = 0; d < 3; ++d)
    m[d] = 0.5 * (a[d] + b[d]);
}

// The 8 children of a (parametric) sub-tet by edge midpoints: 4 corner tets and 4
// around the octahedron's diagonal m02-m13.
void SubdivideTet(const double c[4][3], double kids[8][4][3])
{
  double m01[3], m02[3], m03[3], m12[3], m13[3], m23[3];
  Mid(c[0], c[1], m01);
  Mid(c[0], c[2], m02);
  Mid(c[0], c[3], m03);
  Mid(c[1], c[2], m12);
  Mid(c[1], c[3], m13);
  Mid(c[2], c[3], m23);
  const double* corners[8][4] = { { c[0], m01, m02, m03 }, { m01, c[1], m12, m13 },
    { m02, m12, c[2], m23 }, { m03, m13, m23, c[3] }, { m02, m13, m01, m12 },
    { m02, m13, m12, m23 }, { m02, m13, m23, m03 }, { m02, m13, m03, m01 } };
  for (int k = 0; k < 8; ++k)
    for (int a = 0; a < 4; ++a)
      for (int d = 0; d < 3; ++d)
        kids[k][a][d] = corners[k][a][d];
}

// Lower bound of det J over the sub-tet c, refined by red subdivision up to `depth`.
double SubTetLowerBound(const double* x, const double c[4][3], int depth)
{
  double coef[20];
  const bool certainlyInvalid = SubTetCoefficients(x, c, coef);
  // Allow for the round-off of the samples and of the basis change, so that a bound that
  // is positive is positive for the exact polynomial too.
  const double lo = *std::min_element(coef, coef + 20) - RoundOffAllowance(coef);
  if (lo > 0.0 || certainlyInvalid || depth <= 0)
  {
    if (certainlyInvalid)
    {
      // min over the samples is an upper bound of the true minimum: report the smaller.
      return std::min(lo, 0.0);
    }
    return lo;
  }
  double kids[8][4][3];
  SubdivideTet(c, kids);
  double best = std::numeric_limits<double>::infinity();
  for (auto& k : kids)
  {
    best = std::min(best, SubTetLowerBound(x, k, depth - 1));
    if (!(best > 0.0) && best < lo)
    {
      break; // a non-positive bound that is already below the parent's: conclusive enough
    }
  }
  return std::max(best, lo); // the parent's bound is valid too
}

// Whether every sub-tet that SubTetLowerBound(x, c, depth) would look at, down to the
// leaves it stops at, has all its Bernstein coefficients above `margin` (computed from
// the corner Jacobians G of the whole element; the sub-tet's are their affine
// combinations). Same subdivision as SubTetLowerBound.
bool SubTetClearlyPositive(const double G[4][3][3], const double c[4][3], int depth, double margin)
{
  double S[4][3][3];
  for (int k = 0; k < 4; ++k)
  {
    const double L[4] = { 1.0 - c[k][0] - c[k][1] - c[k][2], c[k][0], c[k][1], c[k][2] };
    for (int i = 0; i < 3; ++i)
      for (int d = 0; d < 3; ++d)
        S[k][i][d] = L[0] * G[0][i][d] + L[1] * G[1][i][d] + L[2] * G[2][i][d] + L[3] * G[3][i][d];
  }
  if (DetBernsteinMin(S) > margin)
    return true;
  if (depth <= 0)
    return false;
  double kids[8][4][3];
  SubdivideTet(c, kids);
  for (auto& k : kids)
  {
    if (!SubTetClearlyPositive(G, k, depth - 1, margin))
      return false;
  }
  return true;
}

double Det3(const double J[3][3])
{
  return J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) -
    J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
    J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
}

// Scaled Jacobian at a point with Jacobian J (columns dx/dr, dx/ds, dx/dt), as Verdict
// defines it for a tet, independent of the node numbering: the six reference edges are
// mapped by J, and sqrt(2) det J is divided by the largest product of the three mapped
// edge lengths at a corner (every corner is tried, not only corner 0). For a straight tet
// this equals vtkMeshQuality's tet scaled Jacobian; a regular tet scores 1.
double ScaledJacobianOf(const double J[3][3])
{
  static const int edgeDir[6][3] = { { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 }, { -1, 1, 0 },
    { -1, 0, 1 }, { 0, -1, 1 } }; // edges 01, 02, 03, 12, 13, 23
  double len[6];
  for (int e = 0; e < 6; ++e)
  {
    double v[3];
    for (int i = 0; i < 3; ++i)
      v[i] = J[i][0] * edgeDir[e][0] + J[i][1] * edgeDir[e][1] + J[i][2] * edgeDir[e][2];
    len[e] = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  }
  const double det = Det3(J);
  // Corners 0..3 and their incident edges.
  const double prod = std::max(std::max(len[0] * len[1] * len[2], len[0] * len[3] * len[4]),
    std::max(len[1] * len[3] * len[5], len[2] * len[4] * len[5]));
  if (!(prod > 0.0))
  {
    return -1.0; // degenerate
  }
  return std::sqrt(2.0) * det / std::max(prod, std::abs(det));
}
} // namespace

double Determinant3(const double J[3][3])
{
  return J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) -
    J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
    J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
}

void Tet10Jacobian(const double* x, const double pc[3], double J[3][3])
{
  double dN[30];
  Tet10Derivs(pc, dN);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
    {
      double s = 0.0;
      for (int n = 0; n < 10; ++n)
        s += dN[10 * j + n] * x[3 * n + i];
      J[i][j] = s;
    }
}

double Tet10JacobianDeterminant(const double* x, const double pc[3])
{
  double J[3][3];
  Tet10Jacobian(x, pc, J);
  return Determinant3(J);
}

double Tet4JacobianDeterminant(const double* x)
{
  double a[3], b[3], c[3], n[3];
  for (int d = 0; d < 3; ++d)
  {
    a[d] = x[3 + d] - x[d];
    b[d] = x[6 + d] - x[d];
    c[d] = x[9 + d] - x[d];
  }
  Cross(b, c, n);
  return a[0] * n[0] + a[1] * n[1] + a[2] * n[2];
}

void Tet10JacobianBounds(const double* x, double& minBound, double& maxBound, int depth)
{
  static const double corners[4][3] = { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } };
  double coef[20];
  SubTetCoefficients(x, corners, coef);
  maxBound = *std::max_element(coef, coef + 20) + RoundOffAllowance(coef);
  minBound = SubTetLowerBound(x, corners, depth);
}

bool Tet10IsValid(const double* x, int depth)
{
  // The lower bound alone (Tet10JacobianBounds also computes the upper one).
  static const double corners[4][3] = { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } };
  // Shortcut with the same answer: the Bernstein coefficients from the corner Jacobians
  // (a few hundred flops per sub-tet instead of 20 sampled Jacobians and a 20 x 20
  // product), accepted only when every sub-tet SubTetLowerBound would visit is positive
  // by a margin far above the round-off of either computation. Round-off: Jacobian
  // entries ~1e2 eps |x| and 1e1 eps |G| per column, det ~1e1 of that times |G|^2, the
  // basis change multiplies by ||M^-1||_inf = 10, the allowance is 1e-12 of the largest
  // coefficient (<= 6 |G|^3): all far below 1e-8 |G|^2 (|G| + |x|). Then
  // SubTetLowerBound finds every coefficient (and sample) of those sub-tets positive too,
  // so it returns a positive bound; an element not clearly positive takes the full test.
  double G[4][3][3];
  Tet10CornerJacobians(x, G);
  double gn = 0.0, xn = 0.0;
  bool finite = true;
  for (int k = 0; k < 4; ++k)
    for (int i = 0; i < 3; ++i)
    {
      const double* g = G[k][i];
      gn = std::max(gn, std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]));
    }
  for (int n = 0; n < 30; ++n)
  {
    finite = finite && std::isfinite(x[n]);
    xn = std::max(xn, std::fabs(x[n]));
  }
  const double margin = 1e-8 * gn * gn * (gn + xn);
  if (finite && std::isfinite(margin) && SubTetClearlyPositive(G, corners, depth, margin))
    return true;
  return SubTetLowerBound(x, corners, depth) > 0.0;
}

double Tet10SampledScaledJacobian(const double* x)
{
  const CubicLattice& lat = Lattice();
  static const double corners[4][3] = { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } };
  double best = std::numeric_limits<double>::infinity();
  for (int p = 0; p < 20; ++p)
  {
    double pc[3], J[3][3];
    LatticePoint(lat, p, corners, pc);
    Tet10Jacobian(x, pc, J);
    best = std::min(best, ScaledJacobianOf(J));
  }
  return std::min(best, 1.0);
}

double Tet10MinScaledJacobian(const double* x)
{
  double best = Tet10SampledScaledJacobian(x);
  if (best > 0.0 && !Tet10IsValid(x))
  {
    best = 0.0; // positive at the samples but not provably positive everywhere
  }
  return std::min(best, 1.0);
}

double Tet4ScaledJacobian(const double* x)
{
  double J[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      J[i][j] = x[3 * (j + 1) + i] - x[i];
  return std::min(1.0, ScaledJacobianOf(J));
}

double Tet10Volume(const double* x)
{
  static const double corners[4][3] = { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } };
  double coef[20];
  SubTetCoefficients(x, corners, coef);
  double s = 0.0;
  for (double c : coef)
    s += c;
  return s / 20.0 / 6.0; // each cubic Bernstein polynomial integrates to 1/20 of the volume
}

double Tet4Volume(const double* x)
{
  return Tet4JacobianDeterminant(x) / 6.0;
}
void Tet10CornerJacobians(const double* x, double G[4][3][3])
{
  // mid-edge node of corners a, b (VTK order: 01, 12, 02, 03, 13, 23)
  static const int MidNode[4][4] = { { -1, 4, 6, 7 }, { 4, -1, 5, 8 }, { 6, 5, -1, 9 },
    { 7, 8, 9, -1 } };
  for (int k = 0; k < 4; ++k)
  {
    // dx/dlambda_a at corner k (lambda as independent variables): 3 x_k for a = k, else
    // 4 x_ak - x_a; then dx/dxi_i = dx/dlambda_i - dx/dlambda_0
    double D[4][3];
    for (int a = 0; a < 4; ++a)
      for (int d = 0; d < 3; ++d)
        D[a][d] = a == k ? 3.0 * x[3 * k + d] : 4.0 * x[3 * MidNode[a][k] + d] - x[3 * a + d];
    for (int i = 0; i < 3; ++i)
      for (int d = 0; d < 3; ++d)
        G[k][i][d] = D[i + 1][d] - D[0][d];
  }
}

namespace
{
// det of the 3 x 3 matrix a (row major)
inline double Det9(const double* a)
{
  return a[0] * (a[4] * a[8] - a[5] * a[7]) + a[1] * (a[5] * a[6] - a[3] * a[8]) +
    a[2] * (a[3] * a[7] - a[4] * a[6]);
}
} // namespace

void DetBernsteinCoefficients(const double G[4][3][3], double b[20])
{
  // det(sum_a lambda_a G_a) is a cubic form in lambda whose Bernstein coefficient of
  // multi-index alpha is the polarised (symmetric trilinear) form T of det at the
  // matrices alpha names: b(3a) = det G_a, b(2a + c) = T(a, a, c), b(a + c + e) =
  // T(a, c, e). Polarisation from determinants of sums (20 determinants, where the
  // trilinear expansion takes 64 triple products):
  //   det(A + C) = det A + 3 T(a,a,c) + 3 T(a,c,c) + det C,
  //   det(A - C) = det A - 3 T(a,a,c) + 3 T(a,c,c) - det C,
  //   det(A + C + E) = det A + det C + det E + 3 (the six T(x,x,y)) + 6 T(a,c,e).
  const double* g[4] = { &G[0][0][0], &G[1][0][0], &G[2][0][0], &G[3][0][0] };
  double P[4];
  for (int a = 0; a < 4; ++a)
    P[a] = Det9(g[a]);
  static const int Pairs[6][2] = { { 0, 1 }, { 0, 2 }, { 0, 3 }, { 1, 2 }, { 1, 3 }, { 2, 3 } };
  double T2[4][4]; // T2[a][c] = T(a, a, c)
  double S[6][9];  // the pair sums
  for (int p = 0; p < 6; ++p)
  {
    const int a = Pairs[p][0], c = Pairs[p][1];
    double D[9];
    for (int i = 0; i < 9; ++i)
    {
      S[p][i] = g[a][i] + g[c][i];
      D[i] = g[a][i] - g[c][i];
    }
    const double plus = Det9(S[p]), minus = Det9(D);
    T2[a][c] = (plus - minus - 2.0 * P[c]) / 6.0;
    T2[c][a] = (plus + minus - 2.0 * P[a]) / 6.0;
  }
  // T(x, y, z) from the sum of the pair (x, y), x < y, and z
  static const int PairOf[4][4] = { { -1, 0, 1, 2 }, { 0, -1, 3, 4 }, { 1, 3, -1, 5 },
    { 2, 4, 5, -1 } };
  auto triple = [&](int x, int y, int z) {
    const double* s = S[PairOf[x][y]];
    double A[9];
    for (int i = 0; i < 9; ++i)
      A[i] = s[i] + g[z][i];
    return (Det9(A) - P[x] - P[y] - P[z] -
             3.0 * (T2[x][y] + T2[y][x] + T2[x][z] + T2[z][x] + T2[y][z] + T2[z][y])) /
      6.0;
  };
  // multi-indices (counts of corners 0..3) in the documented order
  b[0] = P[0];             // 3000
  b[1] = T2[0][3];         // 2001
  b[2] = T2[3][0];         // 1002
  b[3] = P[3];             // 0003
  b[4] = T2[0][2];         // 2010
  b[5] = triple(0, 2, 3);  // 1011
  b[6] = T2[3][2];         // 0012
  b[7] = T2[2][0];         // 1020
  b[8] = T2[2][3];         // 0021
  b[9] = P[2];             // 0030
  b[10] = T2[0][1];        // 2100
  b[11] = triple(0, 1, 3); // 1101
  b[12] = T2[3][1];        // 0102
  b[13] = triple(0, 1, 2); // 1110
  b[14] = triple(1, 2, 3); // 0111
  b[15] = T2[2][1];        // 0120
  b[16] = T2[1][0];        // 1200
  b[17] = T2[1][3];        // 0201
  b[18] = T2[1][2];        // 0210
  b[19] = P[1];            // 0300
}

double DetBernsteinMin(const double G[4][3][3], double* hiOut)
{
  double b[20];
  DetBernsteinCoefficients(G, b);
  // pairwise minima and maxima (two lanes of a vector register; no chain of dependent
  // compares); a NaN coefficient makes the minimum NaN (never clearly positive)
  using lanes::Mask;
  using lanes::Pair;
  const Pair sign = { -0.0, -0.0 };
  Pair lo = { b[0], b[1] }, hi = { 0.0, 0.0 };
  Mask nan = { 0, 0 };
  for (int k = 0; k < 20; k += 2)
  {
    const Pair c = lanes::Load(b + k);
    const Pair a = (Pair)((Mask)c & ~(Mask)sign); // |c|
    nan |= c != c;
    lo = c < lo ? c : lo;
    hi = a > hi ? a : hi;
  }
  if (hiOut)
    *hiOut = std::max(hi[0], hi[1]);
  return (nan[0] | nan[1]) ? std::numeric_limits<double>::quiet_NaN() : std::min(lo[0], lo[1]);
}

} // namespace hoembed
