// The certified closest point on the curved boundary of a Lagrange tet mesh: the
// sub-triangles of a face for the branch and bound (lagrange_detail::SearchFacePatches,
// shared with the hexahedra's sub-squares) and the search over the faces near a point
// (hoembed::LagrangeEmbeddingMesh; see hoembedLagrangeEmbedding.h).
#include "hoembedLagrangeEmbedding.h"

#include "hoembedLagrangeEmbeddingInternal.h"

#include <algorithm>
#include <cmath>

namespace hoembed
{
using lagrange_detail::Interval;
namespace
{
using Id = LagrangeEmbeddingMesh::Id;

// The sub-triangles of a triangular face's parameter domain (SearchFacePatches' policy).
struct TrianglePatches
{
  using Domain = lagrange_detail::TriangleDomain;
  struct Sub
  {
    double Q[3][2];
    int Depth;
  };
  static constexpr int Budget = 4000, MaxDepth = 24;
  const LagrangeEmbeddingMesh& M;
  Id F;
  int Order;
  const std::vector<int>& Lattice;   // 3 per control point
  const std::vector<double>& ToBern; // values at the lattice -> Bernstein net

  static Sub Root()
  {
    return { { { 0, 0 }, { 1, 0 }, { 0, 1 } }, 0 };
  }
  // the sub-patch's Bernstein net: its values at the lattice, collocated
  int Net(const Sub& s, double* net) const
  {
    const int nt = static_cast<int>(this->Lattice.size() / 3);
    double vals[3 * 15]; // nt <= 15 (order 4)
    for (int i = 0; i < nt; ++i)
    {
      const int* l = &this->Lattice[3 * i];
      double uv[2];
      for (int k = 0; k < 2; ++k)
        uv[k] = (l[0] * s.Q[0][k] + l[1] * s.Q[1][k] + l[2] * s.Q[2][k]) / this->Order;
      this->M.FacePoint(this->F, uv, &vals[3 * i]);
    }
    for (int i = 0; i < nt; ++i)
    {
      double acc[3] = { 0, 0, 0 };
      for (int k = 0; k < nt; ++k)
        for (int d = 0; d < 3; ++d)
          acc[d] += this->ToBern[i * nt + k] * vals[3 * k + d];
      for (int d = 0; d < 3; ++d)
        net[3 * i + d] = acc[d];
    }
    return nt;
  }
  // (p = 1: J constant, no second derivatives: the same bound with zero nets)
  void Derivatives(const double* net, Interval xs[3], Interval xt[3], Interval xss[3],
    Interval xst[3], Interval xtt[3]) const
  {
    const int p = this->Order;
    auto pos = [&](int i1, int i2) {
      // position of (n - i1 - i2, i1, i2) in the lattice (i1 outer, i2 inner)
      int k = 0;
      for (int a = 0; a < i1; ++a)
        k += p - a + 1;
      return k + i2;
    };
    for (int i1 = 0; i1 < p; ++i1)
      for (int i2 = 0; i1 + i2 < p; ++i2)
        for (int d = 0; d < 3; ++d)
        {
          const double b0 = net[3 * pos(i1, i2) + d];
          xs[d].Add(p * (net[3 * pos(i1 + 1, i2) + d] - b0));
          xt[d].Add(p * (net[3 * pos(i1, i2 + 1) + d] - b0));
        }
    const double pp = double(p) * (p - 1);
    for (int i1 = 0; i1 <= p - 2; ++i1)
      for (int i2 = 0; i1 + i2 <= p - 2; ++i2)
        for (int d = 0; d < 3; ++d)
        {
          const double b00 = net[3 * pos(i1, i2) + d];
          const double b10 = net[3 * pos(i1 + 1, i2) + d];
          const double b01 = net[3 * pos(i1, i2 + 1) + d];
          xss[d].Add(pp * (net[3 * pos(i1 + 2, i2) + d] - 2 * b10 + b00));
          xtt[d].Add(pp * (net[3 * pos(i1, i2 + 2) + d] - 2 * b01 + b00));
          xst[d].Add(pp * (net[3 * pos(i1 + 1, i2 + 1) + d] - b10 - b01 + b00));
        }
    if (p < 2)
      for (int d = 0; d < 3; ++d)
        xss[d].Lo = xss[d].Hi = xtt[d].Lo = xtt[d].Hi = xst[d].Lo = xst[d].Hi = 0.0;
  }
  static void Centre(const Sub& s, double c[2])
  {
    c[0] = (s.Q[0][0] + s.Q[1][0] + s.Q[2][0]) / 3;
    c[1] = (s.Q[0][1] + s.Q[1][1] + s.Q[2][1]) / 3;
  }
  // u's coordinates l in the sub-triangle (its corners 0, (1, 0), (0, 1)); inside it?
  static bool Local(const Sub& s, const double u[2], double l[2])
  {
    const double a0[2] = { s.Q[1][0] - s.Q[0][0], s.Q[1][1] - s.Q[0][1] };
    const double b0[2] = { s.Q[2][0] - s.Q[0][0], s.Q[2][1] - s.Q[0][1] };
    const double r[2] = { u[0] - s.Q[0][0], u[1] - s.Q[0][1] };
    const double det = a0[0] * b0[1] - a0[1] * b0[0];
    l[0] = (r[0] * b0[1] - r[1] * b0[0]) / det;
    l[1] = (a0[0] * r[1] - a0[1] * r[0]) / det;
    const double m = -1e-12;
    return l[0] >= m && l[1] >= m && 1 - l[0] - l[1] >= m;
  }
  static bool Inside(const Sub& s, const double u[2])
  {
    double l[2];
    return Local(s, u, l);
  }
  static double CornerBound(const Sub& s, const double c[2], const double g[2], double lambda)
  {
    double cl[2];
    Local(s, c, cl);
    const double corners[3][2] = { { 0, 0 }, { 1, 0 }, { 0, 1 } };
    double low = HUGE_VAL;
    for (int k = 0; k < 3; ++k)
    {
      const double dl[2] = { corners[k][0] - cl[0], corners[k][1] - cl[1] };
      const double lin = g[0] * (s.Q[k][0] - c[0]) + g[1] * (s.Q[k][1] - c[1]);
      low = std::min(low, lin + 0.5 * std::min(0.0, lambda) * (dl[0] * dl[0] + dl[1] * dl[1]));
    }
    return low;
  }
  // split at the edge midpoints
  static int Split(const Sub& s, Sub* stack, int top)
  {
    double m[3][2];
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 2; ++d)
        m[k][d] = 0.5 * (s.Q[k][d] + s.Q[(k + 1) % 3][d]);
    const int dp = s.Depth + 1;
    stack[top++] = { { { s.Q[0][0], s.Q[0][1] }, { m[0][0], m[0][1] }, { m[2][0], m[2][1] } }, dp };
    stack[top++] = { { { m[0][0], m[0][1] }, { s.Q[1][0], s.Q[1][1] }, { m[1][0], m[1][1] } }, dp };
    stack[top++] = { { { m[2][0], m[2][1] }, { m[1][0], m[1][1] }, { s.Q[2][0], s.Q[2][1] } }, dp };
    stack[top++] = { { { m[0][0], m[0][1] }, { m[1][0], m[1][1] }, { m[2][0], m[2][1] } }, dp };
    return top;
  }
};
} // namespace

void LagrangeEmbeddingMesh::SearchFace(
  Id f, const double v[3], double& best2, Id& bestFace, double bestUV[2], bool& certified) const
{
  const TrianglePatches patches{ *this, f, this->Basis->Order, this->TriLattice,
    this->TriToBernstein };
  lagrange_detail::SearchFacePatches(patches, *this, f, v, best2, bestFace, bestUV, certified);
}

double LagrangeEmbeddingMesh::ClosestBoundaryPoint(
  const double v[3], Id& face, double uv[2], bool& certified, int* facesSearched) const
{
  return lagrange_detail::NearestOverFaces(this->FaceTree, v, face, uv, certified, facesSearched,
    [&](Id f, double& best2, Id& bestFace, double bestUV[2], bool& ok) {
      this->SearchFace(f, v, best2, bestFace, bestUV, ok);
    });
}

} // namespace hoembed
