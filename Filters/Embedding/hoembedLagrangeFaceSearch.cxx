// The certified closest point on the curved boundary of a Lagrange tet mesh: the local
// solve on one face and the branch and bound over its sub-triangles (the search of
// hoembed::LagrangeEmbeddingMesh; see hoembedLagrangeEmbedding.h).
#include "hoembedLagrangeEmbedding.h"

#include "hoembedLagrangeEmbeddingInternal.h"

#include <algorithm>
#include <cmath>

namespace hoembed
{
using lagrange_detail::Dot;
using lagrange_detail::Interval;
using lagrange_detail::LocalFaceSolve;
using lagrange_detail::ProjectTriangle;
namespace
{
using Id = LagrangeEmbeddingMesh::Id;

struct SubTriangle
{
  double Q[3][2];
  int Depth;
};
} // namespace

void LagrangeEmbeddingMesh::SearchFace(
  Id f, const double v[3], double& best2, Id& bestFace, double bestUV[2], bool& certified) const
{
  const LagrangeTetBasis& b = *this->Basis;
  const int p = b.Order;
  const int nt = static_cast<int>(this->TriLattice.size() / 3);
  auto eval = [&](const double uv[2], double x[3], double xu[3], double xv[3], double H[3][3]) {
    this->FacePoint(f, uv, x, xu, xv, H);
  };
  const double tol = this->SearchTolerance * this->Diagonal;
  auto threshold = [&]() {
    const double r = std::max(0.0, std::sqrt(best2) - tol);
    return r * r;
  };
  // this face's own local solution (a KKT point of the face: the tight place to bound
  // from, also when another face holds the same point as the best one)
  double ownUV[2] = { 0, 0 }, ownD2 = HUGE_VAL;
  auto tryStart = [&](double uv[2]) {
    int its = 0;
    const double d2 = LocalFaceSolve<lagrange_detail::TriangleDomain>(eval, v, uv, its);
    if (d2 < ownD2)
    {
      ownD2 = d2;
      ownUV[0] = uv[0];
      ownUV[1] = uv[1];
    }
    if (d2 < best2)
    {
      best2 = d2;
      bestFace = f;
      bestUV[0] = uv[0];
      bestUV[1] = uv[1];
    }
  };
  // no solve up front: the root's bounds drop most faces a search visits, and where they
  // do not, a local solve starts from the first sub-triangle holding a nearer point
  SubTriangle stack[256];
  int top = 0;
  stack[top++] = { { { 0, 0 }, { 1, 0 }, { 0, 1 } }, 0 };
  int budget = 4000;
  double vals[3 * 15], net[3 * 15]; // nt <= 15 (order 4)
  while (top > 0)
  {
    const SubTriangle s = stack[--top];
    if (--budget < 0)
    {
      certified = false;
      return;
    }
    // the sub-patch's Bernstein net: its values at the lattice, collocated
    for (int i = 0; i < nt; ++i)
    {
      const int* l = &this->TriLattice[3 * i];
      double uv[2];
      for (int k = 0; k < 2; ++k)
        uv[k] = (l[0] * s.Q[0][k] + l[1] * s.Q[1][k] + l[2] * s.Q[2][k]) / p;
      this->FacePoint(f, uv, &vals[3 * i]);
    }
    for (int i = 0; i < nt; ++i)
    {
      double acc[3] = { 0, 0, 0 };
      for (int k = 0; k < nt; ++k)
        for (int d = 0; d < 3; ++d)
          acc[d] += this->TriToBernstein[i * nt + k] * vals[3 * k + d];
      for (int d = 0; d < 3; ++d)
        net[3 * i + d] = acc[d];
    }
    // the box lower bound (convex hull of the net)
    Interval box[3];
    for (int i = 0; i < nt; ++i)
      for (int d = 0; d < 3; ++d)
        box[d].Add(net[3 * i + d]);
    double lb = 0.0;
    for (int d = 0; d < 3; ++d)
    {
      const double gap = std::max(0.0, std::max(box[d].Lo - v[d], v[d] - box[d].Hi));
      lb += gap * gap;
    }
    if (lb >= threshold())
      continue;
    // interval Hessian of f = |x - v|^2 in the sub-triangle's own coordinates (s, t)
    // (p = 1: J constant, no second derivatives: the same bound with zero nets)
    double lambda = 0.0; // lower bound of the smallest eigenvalue of the Hessian of f
    {
      auto pos = [&](int i1, int i2) {
        // position of (n - i1 - i2, i1, i2) in TriLattice (i1 outer, i2 inner)
        int k = 0;
        for (int a = 0; a < i1; ++a)
          k += p - a + 1;
        return k + i2;
      };
      Interval xs[3], xt[3], xss[3], xst[3], xtt[3];
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
      Interval hss, htt, hst;
      hss.Lo = hss.Hi = htt.Lo = htt.Hi = hst.Lo = hst.Hi = 0.0;
      for (int d = 0; d < 3; ++d)
      {
        Interval e;
        e.Lo = box[d].Lo - v[d];
        e.Hi = box[d].Hi - v[d];
        hss = Sum(hss, Sum(Square(xs[d]), Mul(e, xss[d])));
        htt = Sum(htt, Sum(Square(xt[d]), Mul(e, xtt[d])));
        hst = Sum(hst, Sum(Mul(xs[d], xt[d]), Mul(e, xst[d])));
      }
      const double off = std::max(std::abs(hst.Lo), std::abs(hst.Hi));
      // the smallest eigenvalue of any matrix with diagonal >= (hss.Lo, htt.Lo) and
      // off-diagonal within +-off is at least that of [[hss.Lo, off], [off, htt.Lo]]
      const double mean = 0.5 * (hss.Lo + htt.Lo), half = 0.5 * (hss.Lo - htt.Lo);
      lambda = 2.0 * (mean - std::sqrt(half * half + off * off)); // f's Hessian is 2 h
    }
    // Second-order bound at a point c of the sub-triangle: for every u in it, with d the
    // local coordinates of u - c, f(u) >= f(c) + grad f(c) . d + lambda / 2 |d|^2; with
    // lambda < 0 that is concave in d, so its minimum is at a corner; with lambda >= 0 the
    // linear part alone (at a corner too) is a bound. c: the best point when it lies in
    // the sub-triangle (then grad f . d >= 0 there and the bound is tight), else the
    // centroid.
    const double cen[2] = { (s.Q[0][0] + s.Q[1][0] + s.Q[2][0]) / 3,
      (s.Q[0][1] + s.Q[1][1] + s.Q[2][1]) / 3 };
    auto local = [&](const double u[2], double l[2]) {
      const double a0[2] = { s.Q[1][0] - s.Q[0][0], s.Q[1][1] - s.Q[0][1] };
      const double b0[2] = { s.Q[2][0] - s.Q[0][0], s.Q[2][1] - s.Q[0][1] };
      const double r[2] = { u[0] - s.Q[0][0], u[1] - s.Q[0][1] };
      const double det = a0[0] * b0[1] - a0[1] * b0[0];
      l[0] = (r[0] * b0[1] - r[1] * b0[0]) / det;
      l[1] = (a0[0] * r[1] - a0[1] * r[0]) / det;
      const double m = -1e-12;
      return l[0] >= m && l[1] >= m && 1 - l[0] - l[1] >= m;
    };
    auto secondOrder = [&](const double c[2], double& fc) {
      double x[3], xu[3], xv[3], cl[2];
      this->FacePoint(f, c, x, xu, xv);
      local(c, cl);
      const double e[3] = { x[0] - v[0], x[1] - v[1], x[2] - v[2] };
      fc = Dot(e, e);
      const double g[2] = { 2 * Dot(xu, e), 2 * Dot(xv, e) };
      const double corners[3][2] = { { 0, 0 }, { 1, 0 }, { 0, 1 } };
      double low = HUGE_VAL;
      for (int k = 0; k < 3; ++k)
      {
        const double dl[2] = { corners[k][0] - cl[0], corners[k][1] - cl[1] };
        const double lin = g[0] * (s.Q[k][0] - c[0]) + g[1] * (s.Q[k][1] - c[1]);
        low = std::min(low, lin + 0.5 * std::min(0.0, lambda) * (dl[0] * dl[0] + dl[1] * dl[1]));
      }
      return fc + low;
    };
    double c[2] = { cen[0], cen[1] }, cl[2];
    if (ownD2 < HUGE_VAL && local(ownUV, cl))
      c[0] = ownUV[0], c[1] = ownUV[1];
    double fc = 0.0;
    if (secondOrder(c, fc) >= threshold())
      continue;
    // a nearer point may lie here (or, at the root, the face was never solved): solve from
    // c, then bound again from the face's solution when it lies in this sub-triangle
    double fcen = fc;
    if (c[0] != cen[0] || c[1] != cen[1])
    {
      double x[3];
      this->FacePoint(f, cen, x);
      fcen = (x[0] - v[0]) * (x[0] - v[0]) + (x[1] - v[1]) * (x[1] - v[1]) +
        (x[2] - v[2]) * (x[2] - v[2]);
    }
    if (s.Depth == 0 || fcen < best2 || fc < best2)
    {
      double uv[2] = { c[0], c[1] };
      tryStart(uv);
      if (local(ownUV, cl))
      {
        c[0] = ownUV[0], c[1] = ownUV[1];
        if (secondOrder(c, fc) >= threshold())
          continue;
      }
    }
    if (s.Depth >= 24 || top + 4 > 256)
    {
      certified = false;
      continue;
    }
    // split at the edge midpoints
    double m[3][2];
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 2; ++d)
        m[k][d] = 0.5 * (s.Q[k][d] + s.Q[(k + 1) % 3][d]);
    const int dp = s.Depth + 1;
    stack[top++] = { { { s.Q[0][0], s.Q[0][1] }, { m[0][0], m[0][1] }, { m[2][0], m[2][1] } }, dp };
    stack[top++] = { { { m[0][0], m[0][1] }, { s.Q[1][0], s.Q[1][1] }, { m[1][0], m[1][1] } }, dp };
    stack[top++] = { { { m[2][0], m[2][1] }, { m[1][0], m[1][1] }, { s.Q[2][0], s.Q[2][1] } }, dp };
    stack[top++] = { { { m[0][0], m[0][1] }, { m[1][0], m[1][1] }, { m[2][0], m[2][1] } }, dp };
  }
}

double LagrangeEmbeddingMesh::ClosestBoundaryPoint(
  const double v[3], Id& face, double uv[2], bool& certified, int* facesSearched) const
{
  double best2 = HUGE_VAL;
  face = -1;
  certified = true;
  int searched = 0;
  this->FaceTree.VisitNearer(v, best2, [&](Id f) {
    ++searched;
    this->SearchFace(f, v, best2, face, uv, certified);
  });
  if (facesSearched)
    *facesSearched = searched;
  return best2;
}

} // namespace hoembed
