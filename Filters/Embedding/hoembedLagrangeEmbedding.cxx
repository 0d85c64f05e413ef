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
      double* box = &cellBoxes[6 * c];
      for (int d = 0; d < 3; ++d)
      {
        box[d] = HUGE_VAL;
        box[d + 3] = -HUGE_VAL;
      }
      for (int k = 0; k < nodesPerCell; ++k)
        for (int d = 0; d < 3; ++d)
        {
          box[d] = std::min(box[d], ctrl[3 * k + d]);
          box[d + 3] = std::max(box[d + 3], ctrl[3 * k + d]);
        }
      if (firstInvalidCell)
        invalid[c] = LagrangeTetIsValid(b, x) ? 0 : 1;
    }
  });
  if (firstInvalidCell)
  {
    *firstInvalidCell = ncells;
    for (Id c = 0; c < ncells; ++c)
      if (invalid[c])
      {
        *firstInvalidCell = c;
        break;
      }
  }
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

bool LagrangeEmbeddingMesh::Locate(const double v[3], Id& cell, double pc[3]) const
{
  const LagrangeTetBasis& b = *this->Basis;
  const double tiny = 1e-300;
  double reach2 = std::max(tiny, 1e-24 * this->Diagonal * this->Diagonal);
  bool found = false;
  this->CellTree.VisitNearer(v, reach2, [&](Id c) {
    if (found)
      return;
    double x[3 * MaxLagrangeTetNodes];
    GatherCell(this->Points.data(), this->Connectivity.data(), this->NodesPerCell, c, x);
    // starts: the straight tet's barycentric coordinates of v, the centroid
    double starts[2][3] = { { 0.25, 0.25, 0.25 }, { 0.25, 0.25, 0.25 } };
    {
      double A[3][3], r[3];
      for (int i = 0; i < 3; ++i)
      {
        for (int d = 0; d < 3; ++d)
          A[d][i] = x[3 * (i + 1) + d] - x[d];
        r[i] = v[i] - x[i];
      }
      double s[3];
      if (Solve3(A, r, s))
        std::copy(s, s + 3, starts[0]);
    }
    for (int k = 0; k < 2 && !found; ++k)
    {
      double q[3] = { starts[k][0], starts[k][1], starts[k][2] };
      double y[3], J[3][3];
      EvaluateLagrangeTet(b, x, q, y, J);
      double r = std::sqrt((y[0] - v[0]) * (y[0] - v[0]) + (y[1] - v[1]) * (y[1] - v[1]) +
        (y[2] - v[2]) * (y[2] - v[2]));
      for (int it = 0; it < 60 && r > 1e-15 * this->Diagonal; ++it)
      {
        double A[3][3], rhs[3], step[3];
        for (int d = 0; d < 3; ++d)
        {
          for (int i = 0; i < 3; ++i)
            A[d][i] = J[i][d];
          rhs[d] = v[d] - y[d];
        }
        if (!Solve3(A, rhs, step))
          break;
        double alpha = 1.0;
        bool better = false;
        for (int ls = 0; ls < 30; ++ls, alpha *= 0.5)
        {
          const double t[3] = { q[0] + alpha * step[0], q[1] + alpha * step[1],
            q[2] + alpha * step[2] };
          double yn[3], Jn[3][3];
          EvaluateLagrangeTet(b, x, t, yn, Jn);
          const double rn = std::sqrt((yn[0] - v[0]) * (yn[0] - v[0]) +
            (yn[1] - v[1]) * (yn[1] - v[1]) + (yn[2] - v[2]) * (yn[2] - v[2]));
          if (rn < r)
          {
            std::copy(t, t + 3, q);
            std::copy(yn, yn + 3, y);
            for (int i = 0; i < 3; ++i)
              std::copy(Jn[i], Jn[i] + 3, J[i]);
            r = rn;
            better = true;
            break;
          }
        }
        if (!better)
          break;
        // far outside the reference tet: not this cell
        if (q[0] < -1 || q[1] < -1 || q[2] < -1 || q[0] + q[1] + q[2] > 2)
          break;
      }
      const double m = -1e-10;
      if (r <= 1e-12 * this->Diagonal && q[0] >= m && q[1] >= m && q[2] >= m &&
        1 - q[0] - q[1] - q[2] >= m)
      {
        found = true;
        cell = c;
        std::copy(q, q + 3, pc);
        reach2 = 0.0; // stops the traversal
      }
    }
  });
  return found;
}

bool LagrangeEmbeddingMesh::Offset(Id c, const double pc[3], const double v[3], double q[3]) const
{
  double nodes[3 * MaxLagrangeTetNodes], x[3], J[3][3], A[3][3], r[3];
  GatherCell(this->Points.data(), this->Connectivity.data(), this->NodesPerCell, c, nodes);
  EvaluateLagrangeTet(*this->Basis, nodes, pc, x, J);
  for (int d = 0; d < 3; ++d)
  {
    for (int i = 0; i < 3; ++i)
      A[d][i] = J[i][d];
    r[d] = v[d] - x[d];
  }
  if (Solve3(A, r, q))
    return true;
  q[0] = q[1] = q[2] = 0.0;
  return false;
}

int LagrangeEmbeddingMesh::NormalOffset(
  const double p[3], Id& f, double uv[2], double& d, int& iterations) const
{
  const LagrangeTetBasis& b = *this->Basis;
  const double tolF = 1e-13 * this->Diagonal;
  int lastEdge = -1;
  for (int hop = 0; hop < 16; ++hop)
  {
    const Id c = this->Corners.BoundaryFaceCell[f];
    const int lf = this->Corners.BoundaryFaceLocal[f];
    double nodes[3 * MaxLagrangeTetNodes], normals[3 * MaxLagrangeTetNodes], du[3], dv[3];
    GatherCell(this->Points.data(), this->Connectivity.data(), this->NodesPerCell, c, nodes);
    GatherCell(
      this->NodalNormals.data(), this->Connectivity.data(), this->NodesPerCell, c, normals);
    FaceFrame(lf, du, dv);
    auto residual = [&](const double t[2], double dd, double F[3], double A[3][3]) {
      double pc[3], x[3], J[3][3], s[3], Js[3][3];
      TetFaceToTetParametric(lf, t, pc);
      EvaluateLagrangeTet(b, nodes, pc, x, J);
      EvaluateLagrangeTet(b, normals, pc, s, Js);
      const double sl = std::sqrt(Dot(s, s));
      if (!(sl > 1e-12))
        return false;
      double sh[3], xu[3], xv[3], su[3], sv[3];
      for (int k = 0; k < 3; ++k)
      {
        sh[k] = s[k] / sl;
        xu[k] = J[0][k] * du[0] + J[1][k] * du[1] + J[2][k] * du[2];
        xv[k] = J[0][k] * dv[0] + J[1][k] * dv[1] + J[2][k] * dv[2];
        su[k] = Js[0][k] * du[0] + Js[1][k] * du[1] + Js[2][k] * du[2];
        sv[k] = Js[0][k] * dv[0] + Js[1][k] * dv[1] + Js[2][k] * dv[2];
      }
      const double shu = Dot(sh, su), shv = Dot(sh, sv);
      for (int k = 0; k < 3; ++k)
      {
        F[k] = x[k] + dd * sh[k] - p[k];
        if (A)
        {
          A[k][0] = xu[k] + dd * (su[k] - sh[k] * shu) / sl;
          A[k][1] = xv[k] + dd * (sv[k] - sh[k] * shv) / sl;
          A[k][2] = sh[k];
        }
      }
      return true;
    };
    int exitEdge = -1;
    double lastNorm = HUGE_VAL;
    for (int it = 0; it < 40; ++it)
    {
      ++iterations;
      double F[3], A[3][3], step[3];
      if (!residual(uv, d, F, A))
        return -1;
      const double nF = std::sqrt(Dot(F, F));
      const bool inside = uv[0] >= -1e-12 && uv[1] >= -1e-12 && uv[0] + uv[1] <= 1 + 1e-12;
      if (inside && nF <= tolF)
        return 0;
      const double rhs[3] = { -F[0], -F[1], -F[2] };
      if (!Solve3(A, rhs, step))
        return -1;
      if (inside && nF <= 100 * tolF && std::abs(step[0]) + std::abs(step[1]) < 1e-13)
        return 0; // stagnation at round-off
      if (it > 0 && !(nF < lastNorm) && nF > 100 * tolF)
        return -1;
      lastNorm = nF;
      double t[2] = { uv[0] + step[0], uv[1] + step[1] };
      // leaving the triangle: stop at the side crossed first, then go across it
      double a = 1.0;
      int side = -1;
      if (t[1] < 0 && step[1] < 0)
      {
        const double s = -uv[1] / step[1];
        if (s < a)
          a = s, side = 0; // v = 0: edge ab
      }
      if (t[0] + t[1] > 1 && step[0] + step[1] > 0)
      {
        const double s = (1 - uv[0] - uv[1]) / (step[0] + step[1]);
        if (s < a)
          a = s, side = 1; // edge bc
      }
      if (t[0] < 0 && step[0] < 0)
      {
        const double s = -uv[0] / step[0];
        if (s < a)
          a = s, side = 2; // u = 0: edge ca
      }
      a = std::max(0.0, a);
      uv[0] += a * step[0];
      uv[1] += a * step[1];
      d += a * step[2];
      if (side >= 0)
      {
        ProjectTriangle(uv);
        exitEdge = side;
        break;
      }
    }
    if (exitEdge < 0)
      return -1;
    // across edge exitEdge to the neighbouring boundary face
    const Id g = this->Corners.BoundaryFaceNeighbor[3 * f + exitEdge];
    if (g < 0 || (exitEdge == lastEdge && hop > 8))
      return -1;
    const std::int64_t* cc = &this->Connectivity[this->NodesPerCell * c];
    const Id A0 = cc[TetFaceNodes[lf][exitEdge]], B0 = cc[TetFaceNodes[lf][(exitEdge + 1) % 3]];
    const double t = exitEdge == 0 ? uv[0] : (exitEdge == 1 ? uv[1] : 1 - uv[1]);
    const Id gc = this->Corners.BoundaryFaceCell[g];
    const int glf = this->Corners.BoundaryFaceLocal[g];
    const std::int64_t* gcc = &this->Connectivity[this->NodesPerCell * gc];
    int ge = -1;
    double gt = 0;
    for (int e = 0; e < 3; ++e)
    {
      const Id a0 = gcc[TetFaceNodes[glf][e]], b0 = gcc[TetFaceNodes[glf][(e + 1) % 3]];
      if (a0 == A0 && b0 == B0)
        ge = e, gt = t;
      else if (a0 == B0 && b0 == A0)
        ge = e, gt = 1 - t;
    }
    if (ge < 0)
      return -1;
    f = g;
    lastEdge = ge;
    if (ge == 0)
      uv[0] = gt, uv[1] = 0;
    else if (ge == 1)
      uv[0] = 1 - gt, uv[1] = gt;
    else
      uv[0] = 0, uv[1] = 1 - gt;
  }
  return -1;
}

void LagrangeEmbeddingMesh::Embed(const double v[3], int method, VertexEmbedding& r) const
{
  r = VertexEmbedding();
  Id cell = -1;
  double pc[3];
  if (this->Locate(v, cell, pc))
  {
    // inside: clamp round-off into the reference tet
    double lsum = 0;
    for (int i = 0; i < 3; ++i)
    {
      pc[i] = std::max(0.0, pc[i]);
      lsum += pc[i];
    }
    if (lsum > 1)
      for (int i = 0; i < 3; ++i)
        pc[i] /= lsum;
    double x[3];
    this->CellPoint(cell, pc, x);
    r.Cell = cell;
    std::copy(pc, pc + 3, r.PC);
    r.Inside = true;
    r.Residual = std::sqrt((x[0] - v[0]) * (x[0] - v[0]) + (x[1] - v[1]) * (x[1] - v[1]) +
      (x[2] - v[2]) * (x[2] - v[2]));
    return;
  }
  Id f = -1;
  double uv[2] = { 1.0 / 3, 1.0 / 3 };
  bool certified = true;
  const double d2 = this->ClosestBoundaryPoint(v, f, uv, certified, &r.Visited);
  r.Uncertified = !certified;
  r.ClosestDistance = std::sqrt(d2);
  r.BoundaryFace = f;
  r.UV[0] = uv[0];
  r.UV[1] = uv[1];
  double x[3];
  this->FacePoint(f, uv, x);
  const Id closestCell = this->Corners.BoundaryFaceCell[f];
  const int closestLocal = this->Corners.BoundaryFaceLocal[f];
  double closestPC[3];
  TetFaceToTetParametric(closestLocal, uv, closestPC);
  if (method == EMBED_BARYCENTRIC)
  {
    // the closest cell's map extrapolated: its inverse from the closest point
    double nodes[3 * MaxLagrangeTetNodes];
    GatherCell(
      this->Points.data(), this->Connectivity.data(), this->NodesPerCell, closestCell, nodes);
    double q[3] = { closestPC[0], closestPC[1], closestPC[2] };
    double y[3], J[3][3];
    for (int it = 0; it < 40; ++it)
    {
      ++r.Iterations;
      EvaluateLagrangeTet(*this->Basis, nodes, q, y, J);
      double A[3][3], rhs[3], step[3];
      for (int d = 0; d < 3; ++d)
      {
        for (int i = 0; i < 3; ++i)
          A[d][i] = J[i][d];
        rhs[d] = v[d] - y[d];
      }
      if (!Solve3(A, rhs, step) || Dot(rhs, rhs) <= 1e-30 * this->Diagonal * this->Diagonal)
        break;
      for (int i = 0; i < 3; ++i)
        q[i] += step[i];
    }
    EvaluateLagrangeTet(*this->Basis, nodes, q, y, J);
    r.Cell = closestCell;
    std::copy(q, q + 3, r.PC);
    r.Residual = std::sqrt((y[0] - v[0]) * (y[0] - v[0]) + (y[1] - v[1]) * (y[1] - v[1]) +
      (y[2] - v[2]) * (y[2] - v[2]));
    return;
  }
  // normal offset from the closest point; d starts at the signed distance along n
  double s[3];
  {
    double nodes[3 * MaxLagrangeTetNodes], J[3][3];
    GatherCell(
      this->NodalNormals.data(), this->Connectivity.data(), this->NodesPerCell, closestCell, nodes);
    EvaluateLagrangeTet(*this->Basis, nodes, closestPC, s, J);
  }
  const double e[3] = { v[0] - x[0], v[1] - x[1], v[2] - x[2] };
  double d = (Dot(e, s) >= 0 ? 1.0 : -1.0) * r.ClosestDistance;
  // As on tet10 (hoembedEmbeddingSearch.cxx): only a foot within 8 x the closest distance
  // counts (beyond the normal field's focal distance a walk can reach a far foot, and the
  // transfer would swing v on a long lever); retried from the faces around the closest
  // face's corners, then the fallback.
  const double reach = 8.0 * r.ClosestDistance + 1e-6 * this->Diagonal;
  const double d0 = d;
  Id nf = f;
  double nuv[2] = { uv[0], uv[1] };
  int its = 0;
  int status = this->NormalOffset(v, nf, nuv, d, its);
  if (status == 0 && std::abs(d) > reach)
    status = -1;
  for (int a = 0; a < 3 && status != 0; ++a)
  {
    const Id node = this->Corners.BoundaryFaceNodes[3 * f + a];
    for (Id i = this->Corners.NodeFaceOffsets[node];
         i < this->Corners.NodeFaceOffsets[node + 1] && status != 0; ++i)
    {
      nf = this->Corners.NodeFaces[i];
      nuv[0] = nuv[1] = 1.0 / 3.0;
      d = d0;
      status = this->NormalOffset(v, nf, nuv, d, its);
      if (status == 0 && std::abs(d) > reach)
        status = -1;
    }
  }
  r.Iterations = its;
  if (status == 0)
  {
    const Id c = this->Corners.BoundaryFaceCell[nf];
    const int lf = this->Corners.BoundaryFaceLocal[nf];
    ProjectTriangle(nuv);
    TetFaceToTetParametric(lf, nuv, r.PC);
    r.Cell = c;
    r.Face = static_cast<signed char>(lf);
    r.Distance = d;
    r.BoundaryFace = nf;
    // the residual of the reconstruction p + d n from the stored values
    double nodes[3 * MaxLagrangeTetNodes], normals[3 * MaxLagrangeTetNodes], y[3], n[3], J[3][3];
    GatherCell(this->Points.data(), this->Connectivity.data(), this->NodesPerCell, c, nodes);
    GatherCell(
      this->NodalNormals.data(), this->Connectivity.data(), this->NodesPerCell, c, normals);
    EvaluateLagrangeTet(*this->Basis, nodes, r.PC, y, J);
    EvaluateLagrangeTet(*this->Basis, normals, r.PC, n, J);
    const double nl = std::sqrt(Dot(n, n));
    double res2 = 0;
    for (int k = 0; k < 3; ++k)
    {
      const double w = y[k] + d * n[k] / nl - v[k];
      res2 += w * w;
    }
    r.Residual = std::sqrt(res2);
    return;
  }
  // fallback: the closest point and v = p + J(pc) q
  r.Fallback = true;
  r.Cell = closestCell;
  std::copy(closestPC, closestPC + 3, r.PC);
  r.Face = -1;
  r.Distance = 0.0;
  double q[3], y[3], J[3][3], nodes[3 * MaxLagrangeTetNodes];
  this->Offset(closestCell, closestPC, v, q);
  GatherCell(
    this->Points.data(), this->Connectivity.data(), this->NodesPerCell, closestCell, nodes);
  EvaluateLagrangeTet(*this->Basis, nodes, closestPC, y, J);
  double res2 = 0;
  for (int k = 0; k < 3; ++k)
  {
    const double w = y[k] + J[0][k] * q[0] + J[1][k] * q[1] + J[2][k] * q[2] - v[k];
    res2 += w * w;
  }
  r.Residual = std::sqrt(res2);
}
} // namespace hoembed
