#include "hoembedLagrangeHex.h"

#include "hoembedElementGeometry.h" // Determinant3

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <map>
#include <cmath>
#include <memory>
#include <mutex>

namespace hoembed
{
namespace
{
// vtkHigherOrderHexahedron's node number of lattice point (i, j, k) of a uniform order p:
// corners, then the edges (the 4 along r at (s, t) = (0, 0), (1, 0), (0, 1), (1, 1)...
// in VTK's edge order 0-11), the faces (r = 0, r = 1, s = 0, s = 1, t = 0, t = 1, each
// row by row) and the body, every run of nodes in increasing lattice index.
int VTKHexNode(int i, int j, int k, int p)
{
  const bool ib = i == 0 || i == p, jb = j == 0 || j == p, kb = k == 0 || k == p;
  const int nb = int(ib) + int(jb) + int(kb);
  const int m = p - 1;
  if (nb == 3)
    return (i ? (j ? 2 : 1) : (j ? 3 : 0)) + (k ? 4 : 0);
  int offset = 8;
  if (nb == 2)
  {
    if (!ib) // along r: edges 0 (s = 0), 2 (s = 1), 4, 6 at t = 1
      return offset + (i - 1) + (j ? 2 * m : 0) + (k ? 4 * m : 0);
    if (!jb) // along s: edges 3 (r = 0), 1 (r = 1), 7, 5 at t = 1
      return offset + (j - 1) + (i ? m : 3 * m) + (k ? 4 * m : 0);
    offset += 8 * m; // along t: edges 8-11 at the corners 0, 1, 2, 3
    return offset + (k - 1) + m * (i ? (j ? 2 : 1) : (j ? 3 : 0));
  }
  offset += 12 * m;
  if (nb == 1)
  {
    if (ib)
      return offset + (j - 1) + m * (k - 1) + (i ? m * m : 0);
    offset += 2 * m * m;
    if (jb)
      return offset + (i - 1) + m * (k - 1) + (j ? m * m : 0);
    offset += 2 * m * m;
    return offset + (i - 1) + m * (j - 1) + (k ? m * m : 0);
  }
  offset += 6 * m * m;
  return offset + (i - 1) + m * ((j - 1) + m * (k - 1));
}

// vtkQuadraticHexahedron's 20 nodes at lattice (0..2)^3: corners, edges 01, 12, 32, 03,
// the same at t = 1, then the vertical edges at corners 0, 1, 2, 3.
const int Hex20Lattice[20][3] = { { 0, 0, 0 }, { 2, 0, 0 }, { 2, 2, 0 }, { 0, 2, 0 }, { 0, 0, 2 },
  { 2, 0, 2 }, { 2, 2, 2 }, { 0, 2, 2 }, { 1, 0, 0 }, { 2, 1, 0 }, { 1, 2, 0 }, { 0, 1, 0 },
  { 1, 0, 2 }, { 2, 1, 2 }, { 1, 2, 2 }, { 0, 1, 2 }, { 0, 0, 1 }, { 2, 0, 1 }, { 2, 2, 1 },
  { 0, 2, 1 } };

// The 20-node serendipity functions at pc (xi = 2 r - 1 etc.).
void SerendipityShape(const double pc[3], double* N)
{
  const double x[3] = { 2 * pc[0] - 1, 2 * pc[1] - 1, 2 * pc[2] - 1 };
  for (int k = 0; k < 20; ++k)
  {
    double a[3];
    for (int d = 0; d < 3; ++d)
      a[d] = Hex20Lattice[k][d] - 1.0; // -1, 0, 1
    if (k < 8)
      N[k] = 0.125 * (1 + x[0] * a[0]) * (1 + x[1] * a[1]) * (1 + x[2] * a[2]) *
        (x[0] * a[0] + x[1] * a[1] + x[2] * a[2] - 2);
    else
    {
      double v = 0.25;
      for (int d = 0; d < 3; ++d)
        v *= a[d] == 0.0 ? (1 - x[d] * x[d]) : (1 + x[d] * a[d]);
      N[k] = v;
    }
  }
}

// The 1D Lagrange functions of nodes a / n (a = 0..n) at x: values, first, second
// derivatives.
void Lagrange1D(int n, double x, double* l, double* dl, double* ddl)
{
  for (int a = 0; a <= n; ++a)
  {
    // prod_{b != a} (x - b / n) / ((a - b) / n) = prod (n x - b) / (a - b)
    double v = 1.0, d1 = 0.0, d2 = 0.0; // the product and its derivatives, built up
    for (int b = 0; b <= n; ++b)
    {
      if (b == a)
        continue;
      const double g = (n * x - b) / (a - b), dg = double(n) / (a - b);
      d2 = d2 * g + 2.0 * d1 * dg;
      d1 = d1 * g + v * dg;
      v *= g;
    }
    l[a] = v;
    if (dl)
      dl[a] = d1;
    if (ddl)
      ddl[a] = d2;
  }
}

double Binomial(int n, int k)
{
  double v = 1.0;
  for (int i = 1; i <= k; ++i)
    v = v * (n - k + i) / i;
  return v;
}

// Inverse of the 1D collocation M[a][b] = B_b^n(a / n).
std::vector<double> Collocation1D(int n)
{
  Eigen::MatrixXd M(n + 1, n + 1);
  for (int a = 0; a <= n; ++a)
    for (int b = 0; b <= n; ++b)
    {
      const double x = n > 0 ? double(a) / n : 0.5;
      M(a, b) = Binomial(n, b) * std::pow(x, b) * std::pow(1 - x, n - b);
    }
  const Eigen::MatrixXd inv = M.fullPivLu().inverse();
  std::vector<double> out((n + 1) * (n + 1));
  for (int a = 0; a <= n; ++a)
    for (int b = 0; b <= n; ++b)
      out[a * (n + 1) + b] = inv(a, b);
  return out;
}

// Apply a 1D matrix (q x q) along each of the 3 axes of a q^3 tensor of `dim` values.
void ApplyTensor(const std::vector<double>& A, int q, int dim, double* v)
{
  std::vector<double> tmp(static_cast<std::size_t>(q) * q * q * dim);
  for (int axis = 0; axis < 3; ++axis)
  {
    const int stride = axis == 0 ? 1 : (axis == 1 ? q : q * q);
    std::fill(tmp.begin(), tmp.end(), 0.0);
    for (int l = 0; l < q * q * q; ++l)
    {
      const int a = (l / stride) % q;
      const int base = l - a * stride;
      for (int b = 0; b < q; ++b)
      {
        const double w = A[a * q + b];
        for (int d = 0; d < dim; ++d)
          tmp[l * dim + d] += w * v[(base + b * stride) * dim + d];
      }
    }
    std::copy(tmp.begin(), tmp.end(), v);
  }
}

std::unique_ptr<LagrangeHexBasis> MakeBasis(int type, int p, int nodes)
{
  auto b = std::make_unique<LagrangeHexBasis>();
  b->CellType = type;
  b->Order = p;
  b->NumberOfNodes = nodes;
  const int q = p + 1;
  b->TensorNodes = q * q * q;
  b->Lattice.resize(3 * nodes);
  if (type == QuadraticHexahedronCellType)
  {
    for (int k = 0; k < 20; ++k)
      std::copy(Hex20Lattice[k], Hex20Lattice[k] + 3, &b->Lattice[3 * k]);
    b->ToTensor.resize(27 * 20);
    for (int l = 0; l < 27; ++l)
    {
      const double pc[3] = { 0.5 * (l % 3), 0.5 * ((l / 3) % 3), 0.5 * (l / 9) };
      SerendipityShape(pc, &b->ToTensor[20 * l]);
    }
  }
  else
  {
    b->TensorNode.resize(b->TensorNodes);
    for (int k = 0; k <= p; ++k)
      for (int j = 0; j <= p; ++j)
        for (int i = 0; i <= p; ++i)
        {
          const int node = VTKHexNode(i, j, k, p);
          b->TensorNode[(k * q + j) * q + i] = node;
          b->Lattice[3 * node] = i;
          b->Lattice[3 * node + 1] = j;
          b->Lattice[3 * node + 2] = k;
        }
  }
  b->ToBernstein1D = Collocation1D(p);
  b->DetDegree = 3 * p - 1;
  b->DetToBernstein1D = Collocation1D(b->DetDegree);
  return b;
}
} // namespace

const LagrangeHexBasis* GetLagrangeHexBasis(int cellType, int nodesPerCell)
{
  // 0-2: Lagrange order 1-3 (VTK_HEXAHEDRON is order 1 node for node), 3: triquadratic,
  // 4: serendipity
  static std::unique_ptr<LagrangeHexBasis> bases[5];
  static std::once_flag once[5];
  int slot = -1, type = cellType, p = 0;
  if ((cellType == LagrangeHexahedronCellType || cellType == HexahedronCellType) &&
    nodesPerCell == 8)
    slot = 0, p = 1, type = LagrangeHexahedronCellType;
  else if (cellType == LagrangeHexahedronCellType && nodesPerCell == 27)
    slot = 1, p = 2;
  else if (cellType == LagrangeHexahedronCellType && nodesPerCell == 64)
    slot = 2, p = 3;
  else if (cellType == TriQuadraticHexahedronCellType && nodesPerCell == 27)
    slot = 3, p = 2;
  else if (cellType == QuadraticHexahedronCellType && nodesPerCell == 20)
    slot = 4, p = 2;
  if (slot < 0)
    return nullptr;
  std::call_once(once[slot], [&] { bases[slot] = MakeBasis(type, p, nodesPerCell); });
  return bases[slot].get();
}

std::string HexahedronTypeName(int cellType, int nodesPerCell)
{
  if (cellType == QuadraticHexahedronCellType)
    return "VTK_QUADRATIC_HEXAHEDRON";
  if (cellType == TriQuadraticHexahedronCellType)
    return "VTK_TRIQUADRATIC_HEXAHEDRON";
  if (cellType == HexahedronCellType)
    return "VTK_HEXAHEDRON";
  const int p = nodesPerCell == 8 ? 1 : (nodesPerCell == 27 ? 2 : (nodesPerCell == 64 ? 3 : -1));
  return "VTK_LAGRANGE_HEXAHEDRON of order " + std::to_string(p);
}

void LagrangeHexNodeParametric(const LagrangeHexBasis& b, int k, double pc[3])
{
  for (int d = 0; d < 3; ++d)
    pc[d] = double(b.Lattice[3 * k + d]) / b.Order;
}

void LagrangeHexShape(const LagrangeHexBasis& b, const double pc[3], double* N)
{
  if (b.CellType == QuadraticHexahedronCellType)
  {
    SerendipityShape(pc, N);
    return;
  }
  const int p = b.Order;
  double l[3][4];
  for (int d = 0; d < 3; ++d)
    Lagrange1D(p, pc[d], l[d], nullptr, nullptr);
  for (int k = 0; k < b.NumberOfNodes; ++k)
  {
    const int* a = &b.Lattice[3 * k];
    N[k] = l[0][a[0]] * l[1][a[1]] * l[2][a[2]];
  }
}

void LagrangeHexToTensor(const LagrangeHexBasis& b, const double* y, double* t)
{
  if (!b.ToTensor.empty())
  {
    const int n = b.NumberOfNodes;
    for (int l = 0; l < b.TensorNodes; ++l)
    {
      double v[3] = { 0, 0, 0 };
      const double* row = &b.ToTensor[static_cast<std::size_t>(n) * l];
      for (int k = 0; k < n; ++k)
        for (int d = 0; d < 3; ++d)
          v[d] += row[k] * y[3 * k + d];
      std::copy(v, v + 3, t + 3 * l);
    }
    return;
  }
  for (int l = 0; l < b.TensorNodes; ++l)
    std::copy(y + 3 * b.TensorNode[l], y + 3 * b.TensorNode[l] + 3, t + 3 * l);
}

void EvaluateTensorHex(
  int p, const double* t, const double pc[3], double x[3], double J[3][3], double (*H)[3][3])
{
  double l[3][4], dl[3][4], ddl[3][4];
  for (int d = 0; d < 3; ++d)
    Lagrange1D(p, pc[d], l[d], dl[d], ddl[d]);
  for (int c = 0; c < 3; ++c)
  {
    x[c] = 0.0;
    for (int i = 0; i < 3; ++i)
    {
      J[i][c] = 0.0;
      if (H)
        for (int j = 0; j < 3; ++j)
          H[i][j][c] = 0.0;
    }
  }
  const int q = p + 1;
  for (int k = 0; k < q; ++k)
    for (int j = 0; j < q; ++j)
      for (int i = 0; i < q; ++i)
      {
        const double* y = t + 3 * ((k * q + j) * q + i);
        const double f[3] = { l[0][i], l[1][j], l[2][k] };
        const double df[3] = { dl[0][i], dl[1][j], dl[2][k] };
        const double n = f[0] * f[1] * f[2];
        const double g[3] = { df[0] * f[1] * f[2], f[0] * df[1] * f[2], f[0] * f[1] * df[2] };
        for (int c = 0; c < 3; ++c)
        {
          x[c] += n * y[c];
          for (int a = 0; a < 3; ++a)
            J[a][c] += g[a] * y[c];
        }
        if (H)
        {
          const double ddf[3] = { ddl[0][i], ddl[1][j], ddl[2][k] };
          double h[3][3];
          h[0][0] = ddf[0] * f[1] * f[2];
          h[1][1] = f[0] * ddf[1] * f[2];
          h[2][2] = f[0] * f[1] * ddf[2];
          h[0][1] = h[1][0] = df[0] * df[1] * f[2];
          h[0][2] = h[2][0] = df[0] * f[1] * df[2];
          h[1][2] = h[2][1] = f[0] * df[1] * df[2];
          for (int a = 0; a < 3; ++a)
            for (int bb = 0; bb < 3; ++bb)
              for (int c = 0; c < 3; ++c)
                H[a][bb][c] += h[a][bb] * y[c];
        }
      }
}

void TensorHexToBernstein(const LagrangeHexBasis& b, const double* t, double* control)
{
  std::copy(t, t + 3 * b.TensorNodes, control);
  ApplyTensor(b.ToBernstein1D, b.Order + 1, 3, control);
}

namespace
{
// The smallest Bernstein coefficient of det J over the parametric box [lo, lo + h]^3 and
// the largest magnitude (hi); sampleMin: the smallest collocated value.
double SubBoxDetMin(const LagrangeHexBasis& b, const double* t, const double lo[3], double h,
  double& hi, double& sampleMin)
{
  const int D = b.DetDegree, q = D + 1;
  std::vector<double> v(static_cast<std::size_t>(q) * q * q);
  sampleMin = HUGE_VAL;
  for (int k = 0; k < q; ++k)
    for (int j = 0; j < q; ++j)
      for (int i = 0; i < q; ++i)
      {
        const double pc[3] = { lo[0] + h * i / D, lo[1] + h * j / D, lo[2] + h * k / D };
        double x[3], J[3][3], Jt[3][3];
        EvaluateTensorHex(b.Order, t, pc, x, J);
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c)
            Jt[r][c] = J[c][r];
        const double det = Determinant3(Jt);
        v[(k * q + j) * q + i] = det;
        sampleMin = std::isnan(det) ? det : std::min(sampleMin, det);
      }
  ApplyTensor(b.DetToBernstein1D, q, 1, v.data());
  double low = HUGE_VAL;
  hi = 0.0;
  for (double c : v)
  {
    low = std::isnan(c) ? c : std::min(low, c);
    hi = std::max(hi, std::abs(c));
  }
  return low;
}

// 1: proven, 0: counterexample, -1: not settled within `depth` splits.
int SubBoxValid(
  const LagrangeHexBasis& b, const double* t, const double lo[3], double h, double scale, int depth)
{
  double hi = 0.0, sampleMin = 0.0;
  const double low = SubBoxDetMin(b, t, lo, h, hi, sampleMin);
  if (!(sampleMin > 0.0))
    return 0;
  if (low > 1e-9 * scale)
    return 1;
  if (depth == 0)
    return -1;
  int result = 1;
  for (int kid = 0; kid < 8; ++kid)
  {
    const double o[3] = { lo[0] + 0.5 * h * (kid & 1), lo[1] + 0.5 * h * ((kid >> 1) & 1),
      lo[2] + 0.5 * h * ((kid >> 2) & 1) };
    const int r = SubBoxValid(b, t, o, 0.5 * h, scale, depth - 1);
    if (r == 0)
      return 0;
    if (r < 0)
      result = -1;
  }
  return result;
}
} // namespace

bool LagrangeHexIsValid(const LagrangeHexBasis& b, const double* tensor)
{
  const double lo[3] = { 0, 0, 0 };
  double hi = 0.0, sampleMin = 0.0;
  SubBoxDetMin(b, tensor, lo, 1.0, hi, sampleMin);
  if (!(hi > 0.0))
    return false;
  return SubBoxValid(b, tensor, lo, 1.0, hi, 3) == 1;
}
const int HexFaceCorners[6][4] = { { 0, 4, 7, 3 }, { 1, 2, 6, 5 }, { 0, 1, 5, 4 }, { 3, 7, 6, 2 },
  { 0, 3, 2, 1 }, { 4, 5, 6, 7 } };
const int HexFaceU[6] = { 2, 1, 0, 2, 1, 0 };
const int HexFaceV[6] = { 1, 2, 2, 0, 0, 1 };

void HexFaceToParametric(int lf, const double uv[2], double pc[3])
{
  // the face's (0, 0) corner: its fixed parameter at 0 or 1, the others at 0
  const int fixed = 3 - HexFaceU[lf] - HexFaceV[lf];
  pc[0] = pc[1] = pc[2] = 0.0;
  pc[fixed] = lf & 1 ? 1.0 : 0.0;
  pc[HexFaceU[lf]] = uv[0];
  pc[HexFaceV[lf]] = uv[1];
}

std::string FindHexBoundaryFaces(const std::int64_t* conn, std::int64_t ncells, int npc,
  std::vector<std::int64_t>& faceCell, std::vector<int>& faceLocal,
  std::vector<std::int64_t>& cellFace)
{
  // faces by their sorted corners -> (cell, local); cell -1 once shared
  std::map<std::array<std::int64_t, 4>, std::pair<std::int64_t, int>> faces;
  for (std::int64_t c = 0; c < ncells; ++c)
    for (int lf = 0; lf < 6; ++lf)
    {
      std::array<std::int64_t, 4> key;
      for (int k = 0; k < 4; ++k)
        key[k] = conn[npc * c + HexFaceCorners[lf][k]];
      std::sort(key.begin(), key.end());
      if (key[0] == key[1] || key[1] == key[2] || key[2] == key[3])
        return "cell " + std::to_string(c) + " has a face with a repeated corner";
      auto it = faces.find(key);
      if (it == faces.end())
        faces.emplace(key, std::make_pair(c, lf));
      else if (it->second.first < 0)
        return "a face of cell " + std::to_string(c) + " is shared by more than two cells";
      else
        it->second.first = -1;
    }
  std::vector<std::pair<std::int64_t, int>> boundary;
  for (const auto& kv : faces)
    if (kv.second.first >= 0)
      boundary.push_back(kv.second);
  std::sort(boundary.begin(), boundary.end());
  faceCell.clear();
  faceLocal.clear();
  cellFace.assign(6 * ncells, -1);
  for (const auto& fl : boundary)
  {
    cellFace[6 * fl.first + fl.second] = static_cast<std::int64_t>(faceCell.size());
    faceCell.push_back(fl.first);
    faceLocal.push_back(fl.second);
  }
  return std::string();
}

void ComputeHexBoundaryNormals(const LagrangeHexBasis& b, const std::vector<std::int64_t>& faceCell,
  const std::vector<int>& faceLocal, const double* points, std::int64_t npts,
  const std::int64_t* conn, double* normals)
{
  const int npc = b.NumberOfNodes, p = b.Order;
  std::fill(normals, normals + 3 * npts, 0.0);
  std::vector<double> weight(npts, 0.0);
  const double pi = 3.14159265358979323846;
  double x[3 * MaxLagrangeHexNodes], t[3 * MaxLagrangeHexNodes];
  auto dot = [](const double* a, const double* c) {
    return a[0] * c[0] + a[1] * c[1] + a[2] * c[2];
  };
  for (std::size_t f = 0; f < faceCell.size(); ++f)
  {
    const std::int64_t c = faceCell[f];
    const int lf = faceLocal[f];
    const int iu = HexFaceU[lf], iv = HexFaceV[lf], fixed = 3 - iu - iv;
    const int fixedValue = lf & 1 ? p : 0;
    for (int k = 0; k < npc; ++k)
      for (int d = 0; d < 3; ++d)
        x[3 * k + d] = points[3 * conn[npc * c + k] + d];
    LagrangeHexToTensor(b, x, t);
    for (int k = 0; k < npc; ++k)
    {
      const int* a = &b.Lattice[3 * k];
      if (a[fixed] != fixedValue)
        continue; // not on this face
      double pc[3], pos[3], J[3][3];
      LagrangeHexNodeParametric(b, k, pc);
      EvaluateTensorHex(p, t, pc, pos, J);
      const double* tu = J[iu];
      const double* tv = J[iv];
      const double nrm[3] = { tu[1] * tv[2] - tu[2] * tv[1], tu[2] * tv[0] - tu[0] * tv[2],
        tu[0] * tv[1] - tu[1] * tv[0] };
      const double len = std::sqrt(dot(nrm, nrm));
      if (!(len > 0.0))
        continue;
      double w = pi;
      if ((a[iu] == 0 || a[iu] == p) && (a[iv] == 0 || a[iv] == p))
      {
        // a corner: the angle between the two edges leaving it
        const double su = a[iu] == 0 ? 1.0 : -1.0, sv = a[iv] == 0 ? 1.0 : -1.0;
        const double e1[3] = { su * tu[0], su * tu[1], su * tu[2] };
        const double e2[3] = { sv * tv[0], sv * tv[1], sv * tv[2] };
        const double cr[3] = { e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
          e1[0] * e2[1] - e1[1] * e2[0] };
        w = std::atan2(std::sqrt(dot(cr, cr)), dot(e1, e2));
      }
      const std::int64_t node = conn[npc * c + k];
      for (int d = 0; d < 3; ++d)
        normals[3 * node + d] += w * nrm[d] / len;
      weight[node] += w;
    }
  }
  for (std::int64_t i = 0; i < npts; ++i)
  {
    double* n = normals + 3 * i;
    const double len = std::sqrt(dot(n, n));
    // contributions that cancel (a fold) give a direction of round-off: none
    if (weight[i] > 0.0 && len > 1e-8 * weight[i])
      n[0] /= len, n[1] /= len, n[2] /= len;
    else
      n[0] = n[1] = n[2] = 0.0;
  }
}
} // namespace hoembed
