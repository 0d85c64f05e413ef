#include "hoembedLagrangeTet.h"

#include "hoembedElementGeometry.h" // Determinant3
#include "hoembedShapeFunctions.h"  // TetFaceNodes

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <memory>
#include <mutex>

namespace hoembed
{
namespace
{
// (r, s, t) * p of every node in vtkLagrangeTetra's order (corners; edges 01, 12, 20, 03,
// 13, 23; faces (0 1 3), (1 2 3), (0 2 3), (0 1 2), each face's own nodes ordered from
// the face's rotated first corner; body). Written out rather than generated: the face
// nodes of order 4 follow VTK's recursive numbering, which a table states plainly.
// TestLagrangeTet compares every node with vtkLagrangeTetra's parametric coordinates.
const int Order1[] = { 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1 };
const int Order2[] = { 0, 0, 0, 2, 0, 0, 0, 2, 0, 0, 0, 2, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0,
  1, 0, 1, 1 };
const int Order3[] = { 0, 0, 0, 3, 0, 0, 0, 3, 0, 0, 0, 3, 1, 0, 0, 2, 0, 0, 2, 1, 0, 1, 2, 0, 0, 2,
  0, 0, 1, 0, 0, 0, 1, 0, 0, 2, 2, 0, 1, 1, 0, 2, 0, 2, 1, 0, 1, 2, 1, 0, 1, 1, 1, 1, 0, 1, 1, 1, 1,
  0 };
const int Order4[] = { 0, 0, 0, 4, 0, 0, 0, 4, 0, 0, 0, 4, 1, 0, 0, 2, 0, 0, 3, 0, 0, 3, 1, 0, 2, 2,
  0, 1, 3, 0, 0, 3, 0, 0, 2, 0, 0, 1, 0, 0, 0, 1, 0, 0, 2, 0, 0, 3, 3, 0, 1, 2, 0, 2, 1, 0, 3, 0, 3,
  1, 0, 2, 2, 0, 1, 3, 1, 0, 1, 2, 0, 1, 1, 0, 2, 1, 2, 1, 1, 1, 2, 2, 1, 1, 0, 1, 1, 0, 1, 2, 0, 2,
  1, 1, 1, 0, 1, 2, 0, 2, 1, 0, 1, 1, 1 };

double Factorial(int n)
{
  double f = 1.0;
  for (int i = 2; i <= n; ++i)
    f *= i;
  return f;
}

// Bernstein polynomial of degree n, multi-index a (sum n), at barycentric l.
double Bernstein(int n, const int a[4], const double l[4])
{
  double v = Factorial(n);
  for (int m = 0; m < 4; ++m)
    v *= std::pow(l[m], a[m]) / Factorial(a[m]);
  return v;
}

// The multi-indices of degree n (any fixed order).
std::vector<int> Multi(int n)
{
  std::vector<int> out;
  for (int a1 = 0; a1 <= n; ++a1)
    for (int a2 = 0; a1 + a2 <= n; ++a2)
      for (int a3 = 0; a1 + a2 + a3 <= n; ++a3)
        out.insert(out.end(), { n - a1 - a2 - a3, a1, a2, a3 });
  return out;
}

// Inverse of the collocation matrix M[i][j] = B_j(lattice_i / n) (row-major).
std::vector<double> CollocationInverse(int n, const std::vector<int>& lattice)
{
  const int k = static_cast<int>(lattice.size() / 4);
  Eigen::MatrixXd M(k, k);
  for (int i = 0; i < k; ++i)
  {
    double l[4];
    for (int m = 0; m < 4; ++m)
      l[m] = n > 0 ? double(lattice[4 * i + m]) / n : 0.25;
    for (int j = 0; j < k; ++j)
      M(i, j) = Bernstein(n, &lattice[4 * j], l);
  }
  const Eigen::MatrixXd inv = M.fullPivLu().inverse();
  std::vector<double> out(static_cast<std::size_t>(k) * k);
  for (int i = 0; i < k; ++i)
    for (int j = 0; j < k; ++j)
      out[static_cast<std::size_t>(i) * k + j] = inv(i, j);
  return out;
}

std::unique_ptr<LagrangeTetBasis> MakeBasis(int p)
{
  const int* table[] = { Order1, Order2, Order3, Order4 };
  auto b = std::make_unique<LagrangeTetBasis>();
  b->Order = p;
  b->NumberOfNodes = (p + 1) * (p + 2) * (p + 3) / 6;
  const int q = p + 1;
  b->Index.assign(q * q * q, -1);
  for (int k = 0; k < b->NumberOfNodes; ++k)
  {
    const int* rst = table[p - 1] + 3 * k;
    b->Lattice.insert(b->Lattice.end(), { p - rst[0] - rst[1] - rst[2], rst[0], rst[1], rst[2] });
    b->Index[(rst[0] * q + rst[1]) * q + rst[2]] = k;
  }
  b->ToBernstein = CollocationInverse(p, b->Lattice);
  const int d = 3 * (p - 1);
  const std::vector<int> det = Multi(d);
  b->NumberOfDetNodes = static_cast<int>(det.size() / 4);
  for (int i = 0; i < b->NumberOfDetNodes; ++i)
    for (int m = 1; m < 4; ++m)
      b->DetNodes.push_back(d > 0 ? double(det[4 * i + m]) / d : 0.25);
  b->DetToBernstein = CollocationInverse(d, det);
  return b;
}

// l_a(x), l_a'(x), l_a''(x) for a = 0..p (the 1D factors of the shape functions).
void Factors(int p, double x, double* l, double* dl, double* ddl)
{
  l[0] = 1.0;
  dl[0] = ddl[0] = 0.0;
  for (int a = 0; a < p; ++a)
  {
    const double g = (p * x - a) / (a + 1), dg = double(p) / (a + 1);
    l[a + 1] = l[a] * g;
    dl[a + 1] = dl[a] * g + l[a] * dg;
    ddl[a + 1] = ddl[a] * g + 2.0 * dl[a] * dg;
  }
}
} // namespace

int LagrangeTetOrder(int nodesPerCell)
{
  switch (nodesPerCell)
  {
    case 4:
      return 1;
    case 10:
      return 2;
    case 20:
      return 3;
    case 35:
      return 4;
    default:
      return -1;
  }
}

const LagrangeTetBasis* GetLagrangeTetBasis(int order)
{
  static std::unique_ptr<LagrangeTetBasis> bases[4];
  static std::once_flag once[4];
  if (order < 1 || order > 4)
    return nullptr;
  std::call_once(once[order - 1], [order] { bases[order - 1] = MakeBasis(order); });
  return bases[order - 1].get();
}

void LagrangeTetNodeParametric(const LagrangeTetBasis& b, int k, double pc[3])
{
  for (int i = 0; i < 3; ++i)
    pc[i] = double(b.Lattice[4 * k + 1 + i]) / b.Order;
}

void LagrangeTetShape(const LagrangeTetBasis& b, const double pc[3], double* N)
{
  const int p = b.Order;
  const double lam[4] = { 1.0 - pc[0] - pc[1] - pc[2], pc[0], pc[1], pc[2] };
  double l[4][5], dl[4][5], ddl[4][5];
  for (int m = 0; m < 4; ++m)
    Factors(p, lam[m], l[m], dl[m], ddl[m]);
  for (int k = 0; k < b.NumberOfNodes; ++k)
  {
    const int* a = &b.Lattice[4 * k];
    N[k] = l[0][a[0]] * l[1][a[1]] * l[2][a[2]] * l[3][a[3]];
  }
}

void EvaluateLagrangeTet(const LagrangeTetBasis& b, const double* y, const double pc[3],
  double x[3], double J[3][3], double (*H)[3][3])
{
  const int p = b.Order;
  const double lam[4] = { 1.0 - pc[0] - pc[1] - pc[2], pc[0], pc[1], pc[2] };
  double l[4][5], dl[4][5], ddl[4][5];
  for (int m = 0; m < 4; ++m)
    Factors(p, lam[m], l[m], dl[m], ddl[m]);
  // value, gradient and Hessian in the (dependent) barycentric coordinates
  double v[3] = { 0, 0, 0 }, g[4][3] = {}, h[4][4][3] = {};
  for (int k = 0; k < b.NumberOfNodes; ++k)
  {
    const int* a = &b.Lattice[4 * k];
    const double f[4] = { l[0][a[0]], l[1][a[1]], l[2][a[2]], l[3][a[3]] };
    const double df[4] = { dl[0][a[0]], dl[1][a[1]], dl[2][a[2]], dl[3][a[3]] };
    const double* yk = y + 3 * k;
    const double n = f[0] * f[1] * f[2] * f[3];
    double gk[4];
    for (int m = 0; m < 4; ++m)
    {
      double o = 1.0;
      for (int q = 0; q < 4; ++q)
        o *= q == m ? df[q] : f[q];
      gk[m] = o;
    }
    for (int c = 0; c < 3; ++c)
    {
      v[c] += n * yk[c];
      for (int m = 0; m < 4; ++m)
        g[m][c] += gk[m] * yk[c];
    }
    if (H)
    {
      for (int m = 0; m < 4; ++m)
        for (int mm = m; mm < 4; ++mm)
        {
          double o = 1.0;
          for (int q = 0; q < 4; ++q)
          {
            if (q == m && q == mm)
              o *= ddl[q][a[q]];
            else if (q == m || q == mm)
              o *= df[q];
            else
              o *= f[q];
          }
          for (int c = 0; c < 3; ++c)
            h[m][mm][c] += o * yk[c];
        }
    }
  }
  for (int c = 0; c < 3; ++c)
  {
    x[c] = v[c];
    for (int i = 0; i < 3; ++i)
      J[i][c] = g[i + 1][c] - g[0][c];
  }
  if (H)
  {
    auto hh = [&](int m, int mm, int c) { return m <= mm ? h[m][mm][c] : h[mm][m][c]; };
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        for (int c = 0; c < 3; ++c)
          H[i][j][c] = hh(i + 1, j + 1, c) - hh(i + 1, 0, c) - hh(0, j + 1, c) + hh(0, 0, c);
  }
}

void LagrangeTetToBernstein(const LagrangeTetBasis& b, const double* y, double* control)
{
  const int n = b.NumberOfNodes;
  for (int i = 0; i < n; ++i)
  {
    double c[3] = { 0, 0, 0 };
    const double* row = &b.ToBernstein[static_cast<std::size_t>(i) * n];
    for (int k = 0; k < n; ++k)
      for (int d = 0; d < 3; ++d)
        c[d] += row[k] * y[3 * k + d];
    for (int d = 0; d < 3; ++d)
      control[3 * i + d] = c[d];
  }
}

namespace
{
// Bernstein coefficients of det J over the sub-tet of parametric corners P (4 x 3): det J
// at the sub-tet's lattice of degree 3 (p - 1), collocated. `sampleMin` receives the
// smallest of those values (actual values of det J). Returns the smallest coefficient,
// `hi` the largest magnitude.
double SubTetDetMin(
  const LagrangeTetBasis& b, const double* x, const double P[4][3], double& hi, double& sampleMin)
{
  const int n = b.NumberOfDetNodes;
  double values[220];
  sampleMin = HUGE_VAL;
  for (int i = 0; i < n; ++i)
  {
    const double* l = &b.DetNodes[3 * i];
    const double w[4] = { 1.0 - l[0] - l[1] - l[2], l[0], l[1], l[2] };
    double pc[3];
    for (int d = 0; d < 3; ++d)
      pc[d] = w[0] * P[0][d] + w[1] * P[1][d] + w[2] * P[2][d] + w[3] * P[3][d];
    double pos[3], J[3][3], Jt[3][3];
    EvaluateLagrangeTet(b, x, pc, pos, J);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        Jt[r][c] = J[c][r];
    values[i] = Determinant3(Jt);
    sampleMin = std::min(sampleMin, values[i]);
  }
  double lo = HUGE_VAL;
  hi = 0.0;
  for (int i = 0; i < n; ++i)
  {
    double c = 0.0;
    const double* row = &b.DetToBernstein[static_cast<std::size_t>(i) * n];
    for (int k = 0; k < n; ++k)
      c += row[k] * values[k];
    if (std::isnan(c))
      lo = c;
    else if (!std::isnan(lo))
      lo = std::min(lo, c);
    hi = std::max(hi, std::abs(c));
  }
  return lo;
}

// 1: det J > 0 proven on the sub-tet, 0: a value <= 0 found (invalid), -1: not settled
// within `depth` red refinements.
int SubTetValid(
  const LagrangeTetBasis& b, const double* x, const double P[4][3], double scale, int depth)
{
  double hi = 0.0, sampleMin = 0.0;
  const double lo = SubTetDetMin(b, x, P, hi, sampleMin);
  if (!(sampleMin > 0.0))
    return 0;
  if (lo > 1e-9 * scale)
    return 1;
  if (depth == 0)
    return -1;
  double m[4][4][3]; // edge midpoints (m[i][i] = corner i)
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int d = 0; d < 3; ++d)
        m[i][j][d] = 0.5 * (P[i][d] + P[j][d]);
  // red refinement: four corner tets and the octahedron split along m02 - m13
  const int kids[8][4][2] = { { { 0, 0 }, { 0, 1 }, { 0, 2 }, { 0, 3 } },
    { { 0, 1 }, { 1, 1 }, { 1, 2 }, { 1, 3 } }, { { 0, 2 }, { 1, 2 }, { 2, 2 }, { 2, 3 } },
    { { 0, 3 }, { 1, 3 }, { 2, 3 }, { 3, 3 } }, { { 0, 1 }, { 0, 2 }, { 0, 3 }, { 1, 3 } },
    { { 0, 1 }, { 0, 2 }, { 1, 2 }, { 1, 3 } }, { { 0, 2 }, { 0, 3 }, { 1, 3 }, { 2, 3 } },
    { { 0, 2 }, { 1, 2 }, { 1, 3 }, { 2, 3 } } };
  int result = 1;
  for (const auto& kid : kids)
  {
    double Q[4][3];
    for (int k = 0; k < 4; ++k)
      for (int d = 0; d < 3; ++d)
        Q[k][d] = m[kid[k][0]][kid[k][1]][d];
    const int r = SubTetValid(b, x, Q, scale, depth - 1);
    if (r == 0)
      return 0;
    if (r < 0)
      result = -1;
  }
  return result;
}

const double ReferenceCorners[4][3] = { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } };
} // namespace

double LagrangeTetDetBernsteinMin(const LagrangeTetBasis& b, const double* x, double* hi)
{
  double big = 0.0, sampleMin = 0.0;
  const double lo = SubTetDetMin(b, x, ReferenceCorners, big, sampleMin);
  if (hi)
    *hi = big;
  return lo;
}

bool LagrangeTetIsValid(const LagrangeTetBasis& b, const double* x)
{
  double hi = 0.0, sampleMin = 0.0;
  SubTetDetMin(b, x, ReferenceCorners, hi, sampleMin);
  if (!(hi > 0.0))
    return false;
  return SubTetValid(b, x, ReferenceCorners, hi, 3) == 1;
}

void ComputeLagrangeBoundaryNormals(const LagrangeTetBasis& b, const TetMeshTopology& corners,
  const double* points, const std::int64_t* conn, double* normals)
{
  const int npc = b.NumberOfNodes, p = b.Order;
  std::fill(normals, normals + 3 * corners.NumberOfPoints, 0.0);
  std::vector<double> weightSum(corners.NumberOfPoints, 0.0);
  const double pi = 3.14159265358979323846;
  double x[3 * MaxLagrangeTetNodes];
  for (TetMeshTopology::Id f = 0; f < corners.GetNumberOfBoundaryFaces(); ++f)
  {
    const TetMeshTopology::Id c = corners.BoundaryFaceCell[f];
    const int lf = corners.BoundaryFaceLocal[f];
    const int* fc = TetFaceNodes[lf]; // corners a, b, c of the face
    const int opposite = TetFaceOpposite[lf];
    GatherCell(points, conn, npc, c, x);
    for (int k = 0; k < npc; ++k)
    {
      const int* a = &b.Lattice[4 * k];
      if (a[opposite] != 0)
        continue; // not on this face
      double pc[3], pos[3], J[3][3];
      LagrangeTetNodeParametric(b, k, pc);
      EvaluateLagrangeTet(b, x, pc, pos, J);
      // tangents along the face's u (a -> b) and v (a -> c) directions
      double tu[3], tv[3];
      const double* Pa = Tet10NodeParametric[fc[0]];
      const double* Pb = Tet10NodeParametric[fc[1]];
      const double* Pc = Tet10NodeParametric[fc[2]];
      for (int d = 0; d < 3; ++d)
      {
        tu[d] = tv[d] = 0.0;
        for (int i = 0; i < 3; ++i)
        {
          tu[d] += J[i][d] * (Pb[i] - Pa[i]);
          tv[d] += J[i][d] * (Pc[i] - Pa[i]);
        }
      }
      double nrm[3] = { tu[1] * tv[2] - tu[2] * tv[1], tu[2] * tv[0] - tu[0] * tv[2],
        tu[0] * tv[1] - tu[1] * tv[0] };
      const double len = std::sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
      if (!(len > 0.0))
        continue;
      // the face's angle at the node: between its edge tangents at a corner, pi elsewhere
      double e1[3], e2[3];
      bool corner = true;
      if (a[fc[0]] == p)
        for (int d = 0; d < 3; ++d)
          e1[d] = tu[d], e2[d] = tv[d];
      else if (a[fc[1]] == p)
        for (int d = 0; d < 3; ++d)
          e1[d] = -tu[d], e2[d] = tv[d] - tu[d];
      else if (a[fc[2]] == p)
        for (int d = 0; d < 3; ++d)
          e1[d] = -tv[d], e2[d] = tu[d] - tv[d];
      else
        corner = false;
      double w = pi;
      if (corner)
      {
        const double cr[3] = { e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
          e1[0] * e2[1] - e1[1] * e2[0] };
        w = std::atan2(std::sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]),
          e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2]);
      }
      const std::int64_t node = conn[static_cast<std::int64_t>(npc) * c + k];
      for (int d = 0; d < 3; ++d)
        normals[3 * node + d] += w * nrm[d] / len;
      weightSum[node] += w;
    }
  }
  for (TetMeshTopology::Id i = 0; i < corners.NumberOfPoints; ++i)
  {
    double* n = normals + 3 * i;
    const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    // contributions that cancel (a fold) give a direction of round-off: none
    if (len > 1e-8 * weightSum[i] && weightSum[i] > 0.0)
      n[0] /= len, n[1] /= len, n[2] /= len;
    else
      n[0] = n[1] = n[2] = 0.0;
  }
}
} // namespace hoembed
