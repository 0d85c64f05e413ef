#include "hoembedLagrangeHexEmbedding.h"

#include "hoembedEmbeddingFlood.h" // EMBED_* values
#include "hoembedLagrangeEmbeddingInternal.h"
#include "hoembedParallel.h"

#include <algorithm>
#include <cmath>
#include <array>
#include <map>
#include <string>
#include <utility>

namespace hoembed
{
using lagrange_detail::Interval;
namespace
{
using Id = LagrangeHexEmbeddingMesh::Id;

const int (&FaceU)[6] = HexFaceU;
const int (&FaceV)[6] = HexFaceV;

// Bernstein polynomials of degree p (<= 3) at u: values, first and second derivatives.
void Bernstein1D(int p, double u, double* B, double* dB, double* ddB)
{
  auto basis = [&](int n, double* out) {
    // out[0..n]
    for (int a = 0; a <= n; ++a)
    {
      double c = 1.0;
      for (int i = 1; i <= a; ++i)
        c = c * (n - a + i) / i;
      out[a] = c * std::pow(u, a) * std::pow(1.0 - u, n - a);
    }
  };
  basis(p, B);
  double b1[4] = { 0, 0, 0, 0 }, b2[4] = { 0, 0, 0, 0 };
  if (p >= 1)
    basis(p - 1, b1);
  if (p >= 2)
    basis(p - 2, b2);
  for (int a = 0; a <= p; ++a)
  {
    const double lo1 = a >= 1 ? b1[a - 1] : 0.0, hi1 = a <= p - 1 ? b1[a] : 0.0;
    dB[a] = p * (lo1 - hi1);
    double s = 0.0;
    if (p >= 2)
    {
      if (a >= 2)
        s += b2[a - 2];
      if (a >= 1 && a - 1 <= p - 2)
        s -= 2 * b2[a - 1];
      if (a <= p - 2)
        s += b2[a];
    }
    ddB[a] = p * (p - 1) * s;
  }
}

} // namespace

std::string LagrangeHexEmbeddingMesh::Build(std::vector<double> points, std::vector<Id> conn,
  int cellType, int nodesPerCell, Id* firstInvalidCell)
{
  this->Basis = GetLagrangeHexBasis(cellType, nodesPerCell);
  if (!this->Basis)
    return "unsupported hexahedron (cell type " + std::to_string(cellType) + ", " +
      std::to_string(nodesPerCell) + " nodes)";
  const LagrangeHexBasis& b = *this->Basis;
  this->NodesPerCell = nodesPerCell;
  this->Points = std::move(points);
  this->Connectivity = std::move(conn);
  const Id npts = static_cast<Id>(this->Points.size() / 3);
  const Id ncells = static_cast<Id>(this->Connectivity.size() / nodesPerCell);
  if (ncells == 0)
    return "the mesh has no cells";
  for (Id id : this->Connectivity)
    if (id < 0 || id >= npts)
      return "a cell refers to a point that does not exist";
  // boundary quads: the faces (by their corners) of one cell only
  const std::string problem = FindHexBoundaryFaces(this->Connectivity.data(), ncells, nodesPerCell,
    this->FaceCell, this->FaceLocal, this->CellFace);
  if (!problem.empty())
    return problem;
  this->FaceCorners.clear();
  for (std::size_t f = 0; f < this->FaceCell.size(); ++f)
    for (int k = 0; k < 4; ++k)
      this->FaceCorners.push_back(
        this
          ->Connectivity[nodesPerCell * this->FaceCell[f] + HexFaceCorners[this->FaceLocal[f]][k]]);
  const Id nfaces = static_cast<Id>(this->FaceCell.size());
  if (nfaces == 0)
    return "the mesh has no boundary faces";
  // neighbours across the edges, corner node -> faces
  std::map<std::pair<Id, Id>, std::vector<Id>> edges;
  for (Id f = 0; f < nfaces; ++f)
    for (int e = 0; e < 4; ++e)
    {
      const Id a = this->FaceCorners[4 * f + e], c = this->FaceCorners[4 * f + (e + 1) % 4];
      edges[{ std::min(a, c), std::max(a, c) }].push_back(f);
    }
  this->FaceNeighbor.assign(4 * nfaces, -1);
  for (Id f = 0; f < nfaces; ++f)
    for (int e = 0; e < 4; ++e)
    {
      const Id a = this->FaceCorners[4 * f + e], c = this->FaceCorners[4 * f + (e + 1) % 4];
      const auto& list = edges[{ std::min(a, c), std::max(a, c) }];
      if (list.size() == 2)
        this->FaceNeighbor[4 * f + e] = list[0] == f ? list[1] : list[0];
    }
  this->NodeFaceOffsets.assign(npts + 1, 0);
  for (Id f = 0; f < nfaces; ++f)
    for (int k = 0; k < 4; ++k)
      ++this->NodeFaceOffsets[this->FaceCorners[4 * f + k] + 1];
  for (Id i = 0; i < npts; ++i)
    this->NodeFaceOffsets[i + 1] += this->NodeFaceOffsets[i];
  this->NodeFaces.assign(this->NodeFaceOffsets[npts], 0);
  {
    std::vector<Id> fill(this->NodeFaceOffsets.begin(), this->NodeFaceOffsets.end() - 1);
    for (Id f = 0; f < nfaces; ++f)
      for (int k = 0; k < 4; ++k)
        this->NodeFaces[fill[this->FaceCorners[4 * f + k]]++] = f;
  }
  double lo[3] = { HUGE_VAL, HUGE_VAL, HUGE_VAL }, hi[3] = { -HUGE_VAL, -HUGE_VAL, -HUGE_VAL };
  for (Id i = 0; i < npts; ++i)
    for (int d = 0; d < 3; ++d)
    {
      lo[d] = std::min(lo[d], this->Points[3 * i + d]);
      hi[d] = std::max(hi[d], this->Points[3 * i + d]);
    }
  this->Diagonal = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
    (hi[2] - lo[2]) * (hi[2] - lo[2]));
  // tensor forms, control-point boxes, validity
  const int nt = b.TensorNodes, p = b.Order, q = p + 1;
  this->Tensors.assign(static_cast<std::size_t>(3 * nt) * ncells, 0.0);
  std::vector<double> cellBoxes(6 * ncells);
  std::vector<unsigned char> invalid(ncells, 0);
  ParallelLoop(Id(0), ncells, [&](Id cb, Id ce) {
    double x[3 * MaxLagrangeHexNodes], ctrl[3 * MaxLagrangeHexNodes];
    for (Id c = cb; c < ce; ++c)
    {
      for (int k = 0; k < nodesPerCell; ++k)
        for (int d = 0; d < 3; ++d)
          x[3 * k + d] = this->Points[3 * this->Connectivity[nodesPerCell * c + k] + d];
      double* t = &this->Tensors[static_cast<std::size_t>(3 * nt) * c];
      LagrangeHexToTensor(b, x, t);
      TensorHexToBernstein(b, t, ctrl);
      lagrange_detail::ControlPointBox(ctrl, nt, &cellBoxes[6 * c]);
      if (firstInvalidCell)
        invalid[c] = LagrangeHexIsValid(b, t) ? 0 : 1;
    }
  });
  if (firstInvalidCell)
    *firstInvalidCell = lagrange_detail::FirstFlagged(invalid, ncells);
  this->CellTree.Build(cellBoxes);
  // the smooth normal field: angle-weighted nodal normals (paper eq. 6-7)
  this->NodalNormals.assign(3 * npts, 0.0);
  ComputeHexBoundaryNormals(b, this->FaceCell, this->FaceLocal, this->Points.data(), npts,
    this->Connectivity.data(), this->NodalNormals.data());
  this->NormalTensors.assign(this->Tensors.size(), 0.0);
  ParallelLoop(Id(0), ncells, [&](Id cb, Id ce) {
    double x[3 * MaxLagrangeHexNodes];
    for (Id c = cb; c < ce; ++c)
    {
      for (int k = 0; k < nodesPerCell; ++k)
        for (int d = 0; d < 3; ++d)
          x[3 * k + d] = this->NodalNormals[3 * this->Connectivity[nodesPerCell * c + k] + d];
      LagrangeHexToTensor(b, x, &this->NormalTensors[static_cast<std::size_t>(3 * nt) * c]);
    }
  });
  // face nets: the cell's control points on the face, (a, b) = (u, v) indices, a fastest
  const int nq = q * q;
  std::vector<double> faceBoxes(6 * nfaces);
  this->FaceNets.assign(static_cast<std::size_t>(3 * nq) * nfaces, 0.0);
  ParallelLoop(Id(0), nfaces, [&](Id fb, Id fe) {
    double ctrl[3 * MaxLagrangeHexNodes];
    for (Id f = fb; f < fe; ++f)
    {
      const int lf = this->FaceLocal[f];
      TensorHexToBernstein(
        b, &this->Tensors[static_cast<std::size_t>(3 * nt) * this->FaceCell[f]], ctrl);
      double* box = &faceBoxes[6 * f];
      for (int d = 0; d < 3; ++d)
        box[d] = HUGE_VAL, box[d + 3] = -HUGE_VAL;
      double* net = &this->FaceNets[static_cast<std::size_t>(3 * nq) * f];
      for (int bb = 0; bb < q; ++bb)
        for (int a = 0; a < q; ++a)
        {
          int ijk[3];
          const int fixed = 3 - FaceU[lf] - FaceV[lf];
          ijk[0] = ijk[1] = ijk[2] = 0;
          ijk[fixed] = lf & 1 ? p : 0;
          ijk[FaceU[lf]] += a;
          ijk[FaceV[lf]] += bb;
          const int k = (ijk[2] * q + ijk[1]) * q + ijk[0];
          for (int d = 0; d < 3; ++d)
          {
            net[3 * (bb * q + a) + d] = ctrl[3 * k + d];
            box[d] = std::min(box[d], ctrl[3 * k + d]);
            box[d + 3] = std::max(box[d + 3], ctrl[3 * k + d]);
          }
        }
    }
  });
  this->FaceTree.Build(faceBoxes);
  return std::string();
}

void LagrangeHexEmbeddingMesh::CellPoint(
  Id c, const double pc[3], double x[3], double J[3][3]) const
{
  double Jl[3][3];
  const std::size_t n = static_cast<std::size_t>(3 * this->Basis->TensorNodes);
  EvaluateTensorHex(this->Basis->Order, &this->Tensors[n * c], pc, x, J ? J : Jl);
}

void LagrangeHexEmbeddingMesh::CellNormal(
  Id c, const double pc[3], double s[3], double J[3][3]) const
{
  const std::size_t n = static_cast<std::size_t>(3 * this->Basis->TensorNodes);
  EvaluateTensorHex(this->Basis->Order, &this->NormalTensors[n * c], pc, s, J);
}

void LagrangeHexEmbeddingMesh::FacePoint(
  Id f, const double uv[2], double x[3], double xu[3], double xv[3], double (*H)[3]) const
{
  const int p = this->Basis->Order, q = p + 1;
  const double* net = &this->FaceNets[static_cast<std::size_t>(3 * q * q) * f];
  double Bu[4], dBu[4], ddBu[4], Bv[4], dBv[4], ddBv[4];
  Bernstein1D(p, uv[0], Bu, dBu, ddBu);
  Bernstein1D(p, uv[1], Bv, dBv, ddBv);
  for (int d = 0; d < 3; ++d)
  {
    x[d] = 0;
    if (xu)
      xu[d] = 0;
    if (xv)
      xv[d] = 0;
    if (H)
      H[0][d] = H[1][d] = H[2][d] = 0;
  }
  for (int bb = 0; bb < q; ++bb)
    for (int a = 0; a < q; ++a)
    {
      const double* P = net + 3 * (bb * q + a);
      for (int d = 0; d < 3; ++d)
      {
        x[d] += Bu[a] * Bv[bb] * P[d];
        if (xu)
          xu[d] += dBu[a] * Bv[bb] * P[d];
        if (xv)
          xv[d] += Bu[a] * dBv[bb] * P[d];
        if (H)
        {
          H[0][d] += ddBu[a] * Bv[bb] * P[d];
          H[1][d] += dBu[a] * dBv[bb] * P[d];
          H[2][d] += Bu[a] * ddBv[bb] * P[d];
        }
      }
    }
}

namespace
{
// The sub-squares of a quadrilateral face's parameter domain (SearchFacePatches' policy).
struct SquarePatches
{
  using Domain = lagrange_detail::SquareDomain;
  struct Sub
  {
    double U0, V0, H;
    int Depth;
  };
  static constexpr int Budget = 6000, MaxDepth = 30;
  const LagrangeHexEmbeddingMesh& M;
  Id F;
  int Order;
  const std::vector<double>& B; // 1D values at the lattice -> Bernstein (q x q)

  static Sub Root()
  {
    return { 0.0, 0.0, 1.0, 0 };
  }
  // the sub-patch's Bernstein net: values at its lattice, collocated in u then v
  int Net(const Sub& s, double* net) const
  {
    const int p = this->Order, q = p + 1;
    double vals[3 * 16];
    for (int bb = 0; bb < q; ++bb)
      for (int a = 0; a < q; ++a)
      {
        const double uv[2] = { s.U0 + s.H * a / p, s.V0 + s.H * bb / p };
        this->M.FacePoint(this->F, uv, &vals[3 * (bb * q + a)]);
      }
    for (int bb = 0; bb < q; ++bb)
      for (int a = 0; a < q; ++a)
        for (int d = 0; d < 3; ++d)
        {
          double acc = 0.0;
          for (int k = 0; k < q; ++k)
            for (int l = 0; l < q; ++l)
              acc += this->B[a * q + k] * this->B[bb * q + l] * vals[3 * (l * q + k) + d];
          net[3 * (bb * q + a) + d] = acc;
        }
    return q * q;
  }
  void Derivatives(const double* net, Interval xs[3], Interval xt[3], Interval xss[3],
    Interval xst[3], Interval xtt[3]) const
  {
    const int p = this->Order, q = p + 1;
    auto P = [&](int a, int bb, int d) { return net[3 * (bb * q + a) + d]; };
    for (int d = 0; d < 3; ++d)
    {
      xss[d].Lo = xss[d].Hi = xtt[d].Lo = xtt[d].Hi = xst[d].Lo = xst[d].Hi = 0.0;
      for (int bb = 0; bb < q; ++bb)
        for (int a = 0; a < p; ++a)
        {
          xs[d].Add(p * (P(a + 1, bb, d) - P(a, bb, d)));
          xt[d].Add(p * (P(bb, a + 1, d) - P(bb, a, d)));
        }
      bool first = true;
      auto add = [&](Interval& iv, double val, bool& fst) {
        if (fst)
          iv.Lo = iv.Hi = val;
        else
          iv.Add(val);
      };
      for (int bb = 0; bb < q; ++bb)
        for (int a = 0; a + 2 <= p; ++a)
        {
          add(xss[d], p * (p - 1) * (P(a + 2, bb, d) - 2 * P(a + 1, bb, d) + P(a, bb, d)), first);
          first = false;
        }
      first = true;
      for (int bb = 0; bb < q; ++bb)
        for (int a = 0; a + 2 <= p; ++a)
        {
          add(xtt[d], p * (p - 1) * (P(bb, a + 2, d) - 2 * P(bb, a + 1, d) + P(bb, a, d)), first);
          first = false;
        }
      first = true;
      for (int bb = 0; bb < p; ++bb)
        for (int a = 0; a < p; ++a)
        {
          add(xst[d],
            p * p * (P(a + 1, bb + 1, d) - P(a + 1, bb, d) - P(a, bb + 1, d) + P(a, bb, d)), first);
          first = false;
        }
    }
  }
  static void Centre(const Sub& s, double c[2])
  {
    c[0] = s.U0 + 0.5 * s.H;
    c[1] = s.V0 + 0.5 * s.H;
  }
  static bool Inside(const Sub& s, const double u[2])
  {
    const double m = 1e-12 * s.H;
    return u[0] >= s.U0 - m && u[0] <= s.U0 + s.H + m && u[1] >= s.V0 - m && u[1] <= s.V0 + s.H + m;
  }
  // d = (u - c) / H
  static double CornerBound(const Sub& s, const double c[2], const double g[2], double lambda)
  {
    double low = HUGE_VAL;
    for (int k = 0; k < 4; ++k)
    {
      const double corner[2] = { s.U0 + s.H * (k & 1), s.V0 + s.H * (k >> 1) };
      const double du = corner[0] - c[0], dv = corner[1] - c[1];
      const double dl2 = (du * du + dv * dv) / (s.H * s.H);
      low = std::min(low, g[0] * du + g[1] * dv + 0.5 * std::min(0.0, lambda) * dl2);
    }
    return low;
  }
  static int Split(const Sub& s, Sub* stack, int top)
  {
    const double h = 0.5 * s.H;
    for (int k = 0; k < 4; ++k)
      stack[top++] = { s.U0 + h * (k & 1), s.V0 + h * (k >> 1), h, s.Depth + 1 };
    return top;
  }
};
} // namespace

void LagrangeHexEmbeddingMesh::SearchFace(
  Id f, const double v[3], double& best2, Id& bestFace, double bestUV[2], bool& certified) const
{
  const SquarePatches patches{ *this, f, this->Basis->Order, this->Basis->ToBernstein1D };
  lagrange_detail::SearchFacePatches(patches, *this, f, v, best2, bestFace, bestUV, certified);
}

double LagrangeHexEmbeddingMesh::ClosestBoundaryPoint(
  const double v[3], Id& face, double uv[2], bool& certified, int* facesSearched) const
{
  return lagrange_detail::NearestOverFaces(this->FaceTree, v, face, uv, certified, facesSearched,
    [&](Id f, double& best2, Id& bestFace, double bestUV[2], bool& ok) {
      this->SearchFace(f, v, best2, bestFace, bestUV, ok);
    });
}

namespace
{
// The hexahedra for the per-vertex embedding (lagrange_detail::EmbedVertex).
struct HexCells : lagrange_detail::MeshCells<LagrangeHexEmbeddingMesh>
{
  using Face = lagrange_detail::SquareDomain;
  static constexpr double CellCentre = 0.5;
  static constexpr int StartCorners[4] = { 0, 1, 3, 4 };
  static bool InsideCell(const double q[3], double m)
  {
    return q[0] >= -m && q[1] >= -m && q[2] >= -m && q[0] <= 1 + m && q[1] <= 1 + m &&
      q[2] <= 1 + m;
  }
  static bool FarOutside(const double q[3])
  {
    return q[0] < -1 || q[1] < -1 || q[2] < -1 || q[0] > 2 || q[1] > 2 || q[2] > 2;
  }
  static void ClampIntoCell(double pc[3])
  {
    for (int i = 0; i < 3; ++i)
      pc[i] = std::min(1.0, std::max(0.0, pc[i]));
  }

  // the cell's tensor forms (held by the mesh: nothing to gather)
  struct Bound
  {
    const LagrangeHexEmbeddingMesh* M;
    Id C;
    void Point(const double pc[3], double x[3], double J[3][3]) const
    {
      M->CellPoint(C, pc, x, J);
    }
    void Normal(const double pc[3], double s[3], double J[3][3]) const
    {
      M->CellNormal(C, pc, s, J);
    }
  };
  Bound Bind(Id c, bool) const
  {
    return Bound{ &M, c };
  }

  Id FaceCell(Id f) const
  {
    return M.FaceCell[f];
  }
  int FaceLocal(Id f) const
  {
    return M.FaceLocal[f];
  }
  static void FaceToParametric(int lf, const double uv[2], double pc[3])
  {
    HexFaceToParametric(lf, uv, pc);
  }
  static void FaceTangents(int lf, const double J[3][3], double xu[3], double xv[3])
  {
    std::copy(J[FaceU[lf]], J[FaceU[lf]] + 3, xu);
    std::copy(J[FaceV[lf]], J[FaceV[lf]] + 3, xv);
  }
  Id Neighbor(Id f, int e) const
  {
    return M.FaceNeighbor[4 * f + e];
  }
  Id Corner(Id f, int e) const
  {
    return M.FaceCorners[4 * f + e];
  }
  Id NodeFacesBegin(Id n) const
  {
    return M.NodeFaceOffsets[n];
  }
  Id NodeFacesEnd(Id n) const
  {
    return M.NodeFaceOffsets[n + 1];
  }
  Id NodeFace(Id i) const
  {
    return M.NodeFaces[i];
  }
};
} // namespace

bool LagrangeHexEmbeddingMesh::Offset(
  Id c, const double pc[3], const double v[3], double q[3]) const
{
  return lagrange_detail::OffsetInCell(HexCells{ { *this, this->CellTree } }, c, pc, v, q);
}

void LagrangeHexEmbeddingMesh::Embed(const double v[3], int method, VertexEmbedding& r) const
{
  lagrange_detail::EmbedVertex(HexCells{ { *this, this->CellTree } }, v, method, r);
}
} // namespace hoembed
