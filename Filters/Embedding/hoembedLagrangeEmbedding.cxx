#include "hoembedLagrangeEmbedding.h"

#include "hoembedEmbeddingFlood.h" // EMBED_* values
#include "hoembedLagrangeEmbeddingInternal.h"
#include "hoembedParallel.h"
#include "hoembedShapeFunctions.h"

#include <algorithm>
#include <cmath>

namespace hoembed
{
using lagrange_detail::Dot;
using lagrange_detail::ProjectTriangle;
using lagrange_detail::Solve3;
namespace
{
using Id = LagrangeEmbeddingMesh::Id;

// Gauss-Jordan inverse of an n x n matrix (row-major, n <= 15), partial pivoting.
std::vector<double> Inverse(std::vector<double> a, int n)
{
  std::vector<double> inv(static_cast<std::size_t>(n) * n, 0.0);
  for (int i = 0; i < n; ++i)
    inv[i * n + i] = 1.0;
  for (int c = 0; c < n; ++c)
  {
    int piv = c;
    for (int r = c + 1; r < n; ++r)
      if (std::abs(a[r * n + c]) > std::abs(a[piv * n + c]))
        piv = r;
    for (int k = 0; k < n; ++k)
    {
      std::swap(a[c * n + k], a[piv * n + k]);
      std::swap(inv[c * n + k], inv[piv * n + k]);
    }
    const double d = a[c * n + c];
    for (int k = 0; k < n; ++k)
    {
      a[c * n + k] /= d;
      inv[c * n + k] /= d;
    }
    for (int r = 0; r < n; ++r)
    {
      if (r == c)
        continue;
      const double f = a[r * n + c];
      for (int k = 0; k < n; ++k)
      {
        a[r * n + k] -= f * a[c * n + k];
        inv[r * n + k] -= f * inv[c * n + k];
      }
    }
  }
  return inv;
}

double Fact(int n)
{
  double f = 1.0;
  for (int i = 2; i <= n; ++i)
    f *= i;
  return f;
}

// Face (u, v) -> the cell's parametric point, and the parametric directions of u and v.
void FaceFrame(int lf, double du[3], double dv[3])
{
  const double* Pa = Tet10NodeParametric[TetFaceNodes[lf][0]];
  const double* Pb = Tet10NodeParametric[TetFaceNodes[lf][1]];
  const double* Pc = Tet10NodeParametric[TetFaceNodes[lf][2]];
  for (int i = 0; i < 3; ++i)
  {
    du[i] = Pb[i] - Pa[i];
    dv[i] = Pc[i] - Pa[i];
  }
}
} // namespace

std::string LagrangeEmbeddingMesh::Build(
  std::vector<double> points, std::vector<Id> conn, int nodesPerCell, Id* firstInvalidCell)
{
  const int order = LagrangeTetOrder(nodesPerCell);
  this->Basis = GetLagrangeTetBasis(order);
  if (!this->Basis)
    return "a Lagrange tetrahedron needs 4, 10, 20 or 35 nodes";
  this->NodesPerCell = nodesPerCell;
  this->Points = std::move(points);
  this->Connectivity = std::move(conn);
  const Id npts = static_cast<Id>(this->Points.size() / 3);
  const Id ncells = static_cast<Id>(this->Connectivity.size() / nodesPerCell);
  std::vector<Id> corners(4 * ncells);
  for (Id c = 0; c < ncells; ++c)
    for (int k = 0; k < 4; ++k)
      corners[4 * c + k] = this->Connectivity[nodesPerCell * c + k];
  const std::string err = this->Corners.Build(corners.data(), ncells, 4, npts);
  if (!err.empty())
    return err;
  const Id nfaces = this->Corners.GetNumberOfBoundaryFaces();
  if (nfaces == 0)
    return "the mesh has no boundary faces";
  const LagrangeTetBasis& b = *this->Basis;
  // the diagonal of the nodes' box
  double lo[3] = { HUGE_VAL, HUGE_VAL, HUGE_VAL }, hi[3] = { -HUGE_VAL, -HUGE_VAL, -HUGE_VAL };
  for (Id i = 0; i < npts; ++i)
    for (int d = 0; d < 3; ++d)
    {
      lo[d] = std::min(lo[d], this->Points[3 * i + d]);
      hi[d] = std::max(hi[d], this->Points[3 * i + d]);
    }
  this->Diagonal = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
    (hi[2] - lo[2]) * (hi[2] - lo[2]));
  // cells: control-point boxes and validity
  std::vector<double> cellBoxes(6 * ncells);
  std::vector<unsigned char> invalid(ncells, 0);
  ParallelLoop(Id(0), ncells, [&](Id cb, Id ce) {
    double x[3 * MaxLagrangeTetNodes], ctrl[3 * MaxLagrangeTetNodes];
    for (Id c = cb; c < ce; ++c)
    {
      GatherCell(this->Points.data(), this->Connectivity.data(), nodesPerCell, c, x);
      LagrangeTetToBernstein(b, x, ctrl);
      lagrange_detail::ControlPointBox(ctrl, nodesPerCell, &cellBoxes[6 * c]);
      if (firstInvalidCell)
        invalid[c] = LagrangeTetIsValid(b, x) ? 0 : 1;
    }
  });
  if (firstInvalidCell)
    *firstInvalidCell = lagrange_detail::FirstFlagged(invalid, ncells);
  this->CellTree.Build(cellBoxes);
  // the triangle's Bernstein collocation of degree p (faces and their sub-patches)
  const int p = b.Order;
  this->TriLattice.clear();
  for (int i1 = 0; i1 <= p; ++i1)
    for (int i2 = 0; i1 + i2 <= p; ++i2)
      this->TriLattice.insert(this->TriLattice.end(), { p - i1 - i2, i1, i2 });
  const int nt = static_cast<int>(this->TriLattice.size() / 3);
  std::vector<double> M(static_cast<std::size_t>(nt) * nt);
  for (int i = 0; i < nt; ++i)
    for (int j = 0; j < nt; ++j)
    {
      double v = Fact(p);
      for (int m = 0; m < 3; ++m)
        v *= std::pow(double(this->TriLattice[3 * i + m]) / p, this->TriLattice[3 * j + m]) /
          Fact(this->TriLattice[3 * j + m]);
      M[i * nt + j] = v;
    }
  this->TriToBernstein = Inverse(M, nt);
  // nodal normals and the face boxes
  this->NodalNormals.assign(3 * npts, 0.0);
  ComputeLagrangeBoundaryNormals(
    b, this->Corners, this->Points.data(), this->Connectivity.data(), this->NodalNormals.data());
  std::vector<double> faceBoxes(6 * nfaces);
  this->FaceNets.assign(static_cast<std::size_t>(3 * nt) * nfaces, 0.0);
  ParallelLoop(Id(0), nfaces, [&](Id fb, Id fe) {
    double x[3 * MaxLagrangeTetNodes], ctrl[3 * MaxLagrangeTetNodes];
    for (Id f = fb; f < fe; ++f)
    {
      const Id c = this->Corners.BoundaryFaceCell[f];
      const int opposite = TetFaceOpposite[this->Corners.BoundaryFaceLocal[f]];
      GatherCell(this->Points.data(), this->Connectivity.data(), nodesPerCell, c, x);
      LagrangeTetToBernstein(b, x, ctrl);
      double* box = &faceBoxes[6 * f];
      for (int d = 0; d < 3; ++d)
      {
        box[d] = HUGE_VAL;
        box[d + 3] = -HUGE_VAL;
      }
      // the face's control points are the cell's with no weight on the opposite corner;
      // kept in the face's own lattice order (weights on its corners a, b, c)
      const int* fc = TetFaceNodes[this->Corners.BoundaryFaceLocal[f]];
      double* net = &this->FaceNets[static_cast<std::size_t>(3 * nt) * f];
      for (int i = 0; i < nt; ++i)
      {
        int alpha[4] = { 0, 0, 0, 0 };
        for (int m = 0; m < 3; ++m)
          alpha[fc[m]] = this->TriLattice[3 * i + m];
        const int k = b.NodeIndex(alpha[1], alpha[2], alpha[3]);
        for (int d = 0; d < 3; ++d)
        {
          net[3 * i + d] = ctrl[3 * k + d];
          box[d] = std::min(box[d], ctrl[3 * k + d]);
          box[d + 3] = std::max(box[d + 3], ctrl[3 * k + d]);
        }
      }
      (void)opposite;
    }
  });
  this->FaceTree.Build(faceBoxes);
  return std::string();
}

void LagrangeEmbeddingMesh::CellPoint(Id c, const double pc[3], double x[3]) const
{
  double nodes[3 * MaxLagrangeTetNodes], J[3][3];
  GatherCell(this->Points.data(), this->Connectivity.data(), this->NodesPerCell, c, nodes);
  EvaluateLagrangeTet(*this->Basis, nodes, pc, x, J);
}

void LagrangeEmbeddingMesh::FacePoint(
  Id f, const double uv[2], double x[3], double xu[3], double xv[3], double (*H)[3]) const
{
  // the face's Bernstein form (FaceNets): a triangle of degree p, a fraction of the cost
  // of the cell's shape functions; derivatives from the differences of the net
  const int p = this->Basis->Order;
  const int nt = static_cast<int>(this->TriLattice.size() / 3);
  const double* net = &this->FaceNets[static_cast<std::size_t>(3 * nt) * f];
  const double l[3] = { 1.0 - uv[0] - uv[1], uv[0], uv[1] };
  double pw[3][5];
  for (int m = 0; m < 3; ++m)
  {
    pw[m][0] = 1.0;
    for (int k = 0; k < p; ++k)
      pw[m][k + 1] = pw[m][k] * l[m];
  }
  static const double fact[5] = { 1, 1, 2, 6, 24 };
  auto B = [&](int n, int i1, int i2) {
    const int i0 = n - i1 - i2;
    return fact[n] / (fact[i0] * fact[i1] * fact[i2]) * pw[0][i0] * pw[1][i1] * pw[2][i2];
  };
  // position of (p - i1 - i2, i1, i2) in the net (i1 outer, i2 inner)
  auto P = [&](int i1, int i2) { return 3 * (i1 * (2 * p + 3 - i1) / 2 + i2); };
  x[0] = x[1] = x[2] = 0.0;
  for (int i1 = 0; i1 <= p; ++i1)
    for (int i2 = 0; i1 + i2 <= p; ++i2)
    {
      const double w = B(p, i1, i2);
      const double* c = net + P(i1, i2);
      x[0] += w * c[0];
      x[1] += w * c[1];
      x[2] += w * c[2];
    }
  if (xu || xv)
  {
    double a[3] = { 0, 0, 0 }, bv[3] = { 0, 0, 0 };
    for (int i1 = 0; i1 < p; ++i1)
      for (int i2 = 0; i1 + i2 < p; ++i2)
      {
        const double w = p * B(p - 1, i1, i2);
        const double* c0 = net + P(i1, i2);
        const double* c1 = net + P(i1 + 1, i2);
        const double* c2 = net + P(i1, i2 + 1);
        for (int d = 0; d < 3; ++d)
        {
          a[d] += w * (c1[d] - c0[d]);
          bv[d] += w * (c2[d] - c0[d]);
        }
      }
    for (int d = 0; d < 3; ++d)
    {
      if (xu)
        xu[d] = a[d];
      if (xv)
        xv[d] = bv[d];
    }
  }
  if (H) // H[0] = x_uu, H[1] = x_uv, H[2] = x_vv
  {
    for (int k = 0; k < 3; ++k)
      H[k][0] = H[k][1] = H[k][2] = 0.0;
    for (int i1 = 0; i1 + 2 <= p; ++i1)
      for (int i2 = 0; i1 + i2 + 2 <= p; ++i2)
      {
        const double w = p * (p - 1) * B(p - 2, i1, i2);
        const double* c00 = net + P(i1, i2);
        const double* c10 = net + P(i1 + 1, i2);
        const double* c01 = net + P(i1, i2 + 1);
        const double* c20 = net + P(i1 + 2, i2);
        const double* c11 = net + P(i1 + 1, i2 + 1);
        const double* c02 = net + P(i1, i2 + 2);
        for (int d = 0; d < 3; ++d)
        {
          H[0][d] += w * (c20[d] - 2 * c10[d] + c00[d]);
          H[1][d] += w * (c11[d] - c10[d] - c01[d] + c00[d]);
          H[2][d] += w * (c02[d] - 2 * c01[d] + c00[d]);
        }
      }
  }
}

namespace
{
// The tetrahedra for the per-vertex embedding (lagrange_detail::EmbedVertex).
struct TetCells : lagrange_detail::MeshCells<LagrangeEmbeddingMesh>
{
  using Face = lagrange_detail::TriangleDomain;
  static constexpr double CellCentre = 0.25;
  static constexpr int StartCorners[4] = { 0, 1, 2, 3 };
  static bool InsideCell(const double q[3], double m)
  {
    return q[0] >= -m && q[1] >= -m && q[2] >= -m && 1 - q[0] - q[1] - q[2] >= -m;
  }
  static bool FarOutside(const double q[3])
  {
    return q[0] < -1 || q[1] < -1 || q[2] < -1 || q[0] + q[1] + q[2] > 2;
  }
  static void ClampIntoCell(double pc[3])
  {
    double lsum = 0;
    for (int i = 0; i < 3; ++i)
    {
      pc[i] = std::max(0.0, pc[i]);
      lsum += pc[i];
    }
    if (lsum > 1)
      for (int i = 0; i < 3; ++i)
        pc[i] /= lsum;
  }

  // one cell's nodes (and nodal normals), gathered once for the evaluations
  struct Bound
  {
    const LagrangeTetBasis* B;
    double X[3 * MaxLagrangeTetNodes], N[3 * MaxLagrangeTetNodes];
    void Point(const double pc[3], double x[3], double J[3][3]) const
    {
      EvaluateLagrangeTet(*B, X, pc, x, J);
    }
    void Normal(const double pc[3], double s[3], double J[3][3]) const
    {
      EvaluateLagrangeTet(*B, N, pc, s, J);
    }
  };
  Bound Bind(Id c, bool normals) const
  {
    Bound b;
    b.B = M.Basis;
    GatherCell(M.Points.data(), M.Connectivity.data(), M.NodesPerCell, c, b.X);
    if (normals)
      GatherCell(M.NodalNormals.data(), M.Connectivity.data(), M.NodesPerCell, c, b.N);
    return b;
  }

  Id FaceCell(Id f) const
  {
    return M.Corners.BoundaryFaceCell[f];
  }
  int FaceLocal(Id f) const
  {
    return M.Corners.BoundaryFaceLocal[f];
  }
  static void FaceToParametric(int lf, const double uv[2], double pc[3])
  {
    TetFaceToTetParametric(lf, uv, pc);
  }
  static void FaceTangents(int lf, const double J[3][3], double xu[3], double xv[3])
  {
    double du[3], dv[3];
    FaceFrame(lf, du, dv);
    for (int k = 0; k < 3; ++k)
    {
      xu[k] = J[0][k] * du[0] + J[1][k] * du[1] + J[2][k] * du[2];
      xv[k] = J[0][k] * dv[0] + J[1][k] * dv[1] + J[2][k] * dv[2];
    }
  }
  Id Neighbor(Id f, int e) const
  {
    return M.Corners.BoundaryFaceNeighbor[3 * f + e];
  }
  Id Corner(Id f, int e) const
  {
    return M.Corners.BoundaryFaceNodes[3 * f + e];
  }
  Id NodeFacesBegin(Id n) const
  {
    return M.Corners.NodeFaceOffsets[n];
  }
  Id NodeFacesEnd(Id n) const
  {
    return M.Corners.NodeFaceOffsets[n + 1];
  }
  Id NodeFace(Id i) const
  {
    return M.Corners.NodeFaces[i];
  }
};
} // namespace

bool LagrangeEmbeddingMesh::Offset(Id c, const double pc[3], const double v[3], double q[3]) const
{
  return lagrange_detail::OffsetInCell(TetCells{ { *this, this->CellTree } }, c, pc, v, q);
}

void LagrangeEmbeddingMesh::Embed(const double v[3], int method, VertexEmbedding& r) const
{
  lagrange_detail::EmbedVertex(TetCells{ { *this, this->CellTree } }, v, method, r);
}
} // namespace hoembed
