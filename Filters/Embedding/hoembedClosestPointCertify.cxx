#include "hoembedClosestPointCertify.h"
#include "hoembedVector3.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace hoembed
{
namespace
{
inline double Dist(const double a[3], const double b[3])
{
  const double d[3] = { a[0] - b[0], a[1] - b[1], a[2] - b[2] };
  return std::sqrt(Dot(d, d));
}

double SegmentDistance(const double p[3], const double a[3], const double b[3])
{
  const double ab[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] };
  const double ap[3] = { p[0] - a[0], p[1] - a[1], p[2] - a[2] };
  const double l2 = Dot(ab, ab);
  const double t = l2 > 0.0 ? std::min(1.0, std::max(0.0, Dot(ap, ab) / l2)) : 0.0;
  const double q[3] = { a[0] + t * ab[0], a[1] + t * ab[1], a[2] + t * ab[2] };
  return Dist(p, q);
}

// Distance from p to the flat triangle (a, b, c) (hoembed::ClosestPointOnTriangle);
// degenerate triangles fall back to the three edges.
double TriangleDistance(const double p[3], const double a[3], const double b[3], const double c[3])
{
  const double ab[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] };
  const double ac[3] = { c[0] - a[0], c[1] - a[1], c[2] - a[2] };
  const double ap[3] = { p[0] - a[0], p[1] - a[1], p[2] - a[2] };
  double st[2];
  if (!ClosestPointOnTriangle(ap, ab, ac, st))
    return std::min(
      { SegmentDistance(p, a, b), SegmentDistance(p, b, c), SegmentDistance(p, c, a) });
  const double q[3] = { a[0] + st[0] * ab[0] + st[1] * ac[0], a[1] + st[0] * ab[1] + st[1] * ac[1],
    a[2] + st[0] * ab[2] + st[1] * ac[2] };
  return Dist(p, q);
}

struct Node
{
  double Lower;
  double Q[3][2]; // parametric corners
  double X[3][3]; // their points
  double Dev;     // bound of |patch - flat triangle of X|
  int Depth;
};

// Bound of the deviation of the patch over the sub-triangle q from the flat triangle of
// its corners, (2/3) max_e |e_e| with e_ij = 2 m_ij - x_i - x_j = -(1/4) d^T Q d along the
// edge direction d. Halving the sub-triangle halves d: its children deviate by a quarter.
double Deviation(const QuadraticMap& m, const double q[3][2])
{
  double dev = 0.0;
  for (int k = 0; k < 3; ++k)
  {
    const double d[2] = { q[(k + 1) % 3][0] - q[k][0], q[(k + 1) % 3][1] - q[k][1] };
    double e[3];
    for (int c = 0; c < 3; ++c)
      e[c] = -0.25 *
        (d[0] * (m.Q[0][0][c] * d[0] + m.Q[0][1][c] * d[1]) +
          d[1] * (m.Q[1][0][c] * d[0] + m.Q[1][1][c] * d[1]));
    dev = std::max(dev, std::sqrt(Dot(e, e)));
  }
  return 2.0 / 3.0 * dev;
}

// Minimum over the reference triangle of q(y) = g . (y - y0) + (y - y0)^T A (y - y0)
// (A symmetric: a00, a01, a11): corners, the critical point of each edge, the interior
// critical point when A is positive definite.
double MinQuadraticOnTriangle(const double g[2], const double A[3], const double y0[2])
{
  auto q = [&](double s, double t) {
    const double ds = s - y0[0], dt = t - y0[1];
    return g[0] * ds + g[1] * dt + A[0] * ds * ds + 2.0 * A[1] * ds * dt + A[2] * dt * dt;
  };
  const double P[3][2] = { { 0, 0 }, { 1, 0 }, { 0, 1 } };
  double m = std::min({ q(0, 0), q(1, 0), q(0, 1) });
  for (int e = 0; e < 3; ++e)
  {
    const double* a = P[e];
    const double* b = P[(e + 1) % 3];
    const double d[2] = { b[0] - a[0], b[1] - a[1] };
    const double da[2] = { a[0] - y0[0], a[1] - y0[1] };
    // q(a + tau d) = q(a) + beta tau + gamma tau^2
    const double gamma = A[0] * d[0] * d[0] + 2.0 * A[1] * d[0] * d[1] + A[2] * d[1] * d[1];
    const double beta = g[0] * d[0] + g[1] * d[1] +
      2.0 * (A[0] * da[0] * d[0] + A[1] * (da[0] * d[1] + da[1] * d[0]) + A[2] * da[1] * d[1]);
    if (gamma > 0.0)
    {
      const double tau = -beta / (2.0 * gamma);
      if (tau > 0.0 && tau < 1.0)
        m = std::min(m, q(a[0] + tau * d[0], a[1] + tau * d[1]));
    }
  }
  const double det = A[0] * A[2] - A[1] * A[1];
  if (A[0] > 0.0 && det > 0.0)
  {
    // grad q = g + 2 A (y - y0) = 0
    const double ys = y0[0] - 0.5 * (A[2] * g[0] - A[1] * g[1]) / det;
    const double yt = y0[1] - 0.5 * (A[0] * g[1] - A[1] * g[0]) / det;
    if (ys >= 0.0 && yt >= 0.0 && ys + yt <= 1.0)
      m = std::min(m, q(ys, yt));
  }
  return m;
}

// The exact expansion of f(u) = |x(u) - v|^2 at a parametric point r and its lower
// bound over a parametric sub-triangle (see the header's file comment).
const double RootTriangle[3][2] = { { 0, 0 }, { 1, 0 }, { 0, 1 } };

struct Expansion
{
  double R[2];
  double F;
  double G[2];
  double P[3];
  double J[2][3];

  Expansion() = default;
  Expansion(const QuadraticMap& m, const double v[3], const double r[2])
  {
    double x[3];
    this->R[0] = r[0];
    this->R[1] = r[1];
    EvaluateMap(m, r, x, this->J);
    const double p[3] = { x[0] - v[0], x[1] - v[1], x[2] - v[2] };
    this->F = Dot(p, p);
    this->G[0] = 2.0 * Dot(this->J[0], p);
    this->G[1] = 2.0 * Dot(this->J[1], p);
    this->P[0] = Dot(p, m.Q[0][0]);
    this->P[1] = Dot(p, m.Q[0][1]);
    this->P[2] = Dot(p, m.Q[1][1]);
  }

  // Lower bound of f over the parametric triangle q (>= 0) when that is at least `target`
  // (a squared distance); otherwise some value below `target` (the cheap bound is
  // refined only while it stays below it, and given up once it cannot reach it).
  double LowerBound2(const QuadraticMap& m, const double q[3][2], double target) const
  {
    // Jacobians at the corners of S: J(s_k) = J(r) + Q (q_k - r) / 2
    double JS[3][2][3];
    for (int k = 0; k < 3; ++k)
    {
      const double h0 = 0.5 * (q[k][0] - this->R[0]), h1 = 0.5 * (q[k][1] - this->R[1]);
      for (int i = 0; i < 2; ++i)
        for (int d = 0; d < 3; ++d)
          JS[k][i][d] = this->J[i][d] + m.Q[i][0][d] * h0 + m.Q[i][1][d] * h1;
    }
    // Bernstein coefficients (2 x 2 symmetric: 00, 01, 11) of J^T J over S: J_a^T J_a at
    // the corners, (J_a^T J_b + J_b^T J_a) / 2 at the edges. J^T J is their convex
    // combination (the Bernstein basis is >= 0 and sums to 1) at every point of S.
    double E[6][3];
    double lo[3] = { 1e300, 1e300, 1e300 }, hi[3] = { -1e300, -1e300, -1e300 };
    int n = 0;
    for (int a = 0; a < 3; ++a)
      for (int b = a; b < 3; ++b, ++n)
      {
        E[n][0] = Dot(JS[a][0], JS[b][0]);
        E[n][1] = 0.5 * (Dot(JS[a][0], JS[b][1]) + Dot(JS[b][0], JS[a][1]));
        E[n][2] = Dot(JS[a][1], JS[b][1]);
        for (int k = 0; k < 3; ++k)
        {
          lo[k] = std::min(lo[k], E[n][k]);
          hi[k] = std::max(hi[k], E[n][k]);
        }
      }
    // in the coordinates y of q (u = q0 + B y): g' = B^T g, A' = B^T A B, y0 = B^-1 (r - q0)
    const double B[2][2] = { { q[1][0] - q[0][0], q[2][0] - q[0][0] },
      { q[1][1] - q[0][1], q[2][1] - q[0][1] } };
    const double det = B[0][0] * B[1][1] - B[0][1] * B[1][0];
    const double dr[2] = { this->R[0] - q[0][0], this->R[1] - q[0][1] };
    const double y0[2] = { (B[1][1] * dr[0] - B[0][1] * dr[1]) / det,
      (B[0][0] * dr[1] - B[1][0] * dr[0]) / det };
    const double g2[2] = { B[0][0] * this->G[0] + B[1][0] * this->G[1],
      B[0][1] * this->G[0] + B[1][1] * this->G[1] };
    // min over q of g . D + D^T (P + E) D
    auto minOver = [&](const double* e) {
      const double A[3] = { this->P[0] + e[0], this->P[1] + e[1], this->P[2] + e[2] };
      const double AB[2][2] = { { A[0] * B[0][0] + A[1] * B[1][0],
                                  A[0] * B[0][1] + A[1] * B[1][1] },
        { A[1] * B[0][0] + A[2] * B[1][0], A[1] * B[0][1] + A[2] * B[1][1] } };
      const double A2[3] = { B[0][0] * AB[0][0] + B[1][0] * AB[1][0],
        B[0][0] * AB[0][1] + B[1][0] * AB[1][1], B[0][1] * AB[0][1] + B[1][1] * AB[1][1] };
      return MinQuadraticOnTriangle(g2, A2, y0);
    };
    // cheap: one matrix below every E (entry ranges, the off-diagonal spread moved to
    // the diagonal: the difference is diagonally dominant)
    const double rad = 0.5 * (hi[1] - lo[1]);
    const double Elow[3] = { lo[0] - rad, 0.5 * (lo[1] + hi[1]), lo[2] - rad };
    double bound = this->F + minOver(Elow);
    if (bound >= target)
      return bound;
    // tighter: the smallest of the six minima, one per Bernstein coefficient (the first
    // one below the target settles it: the bound stays below)
    double m6 = minOver(E[0]);
    for (int k = 1; k < 6 && this->F + m6 >= target; ++k)
      m6 = std::min(m6, minOver(E[k]));
    return std::max({ 0.0, bound, this->F + m6 });
  }

  // True when f >= limit^2 over the parametric triangle q (limit: a distance).
  bool Resolves(const QuadraticMap& m, const double q[3][2], double limit) const
  {
    return std::sqrt(this->LowerBound2(m, q, limit > 0.0 ? limit * limit : 0.0)) >= limit;
  }
};
} // namespace

bool CertifyClosestPointOnPatch(const QuadraticMap& m, const double v[3], double incumbent2,
  double tol, ClosestPointResult& r, bool* certified, int maxNodes)
{
  constexpr int Capacity = 64;
  constexpr int MaxDepth = 30;
  Node heap[Capacity];
  int n = 0;
  bool complete = true;
  double best2 = r.Distance2; // nearest point found on this patch
  double bestUV[2] = { r.Param[0], r.Param[1] };
  bool improved = false;
  auto limit = [&]() { return std::sqrt(std::min(best2, incumbent2)) - tol; };
  // queue a sub-triangle: its corners are points of the patch (upper bounds)
  auto push = [&](const double q[3][2], const double X[3][3], double dev, int depth) {
    for (int k = 0; k < 3; ++k)
    {
      const double d[3] = { X[k][0] - v[0], X[k][1] - v[1], X[k][2] - v[2] };
      if (Dot(d, d) < best2)
      {
        best2 = Dot(d, d);
        bestUV[0] = q[k][0];
        bestUV[1] = q[k][1];
        improved = true;
      }
    }
    const double lb = std::max(0.0, TriangleDistance(v, X[0], X[1], X[2]) - dev);
    if (lb >= limit())
      return;
    if (n == Capacity)
    {
      complete = false;
      return;
    }
    Node& nd = heap[n++];
    nd.Lower = lb;
    nd.Depth = depth;
    nd.Dev = dev;
    for (int k = 0; k < 3; ++k)
    {
      for (int j = 0; j < 2; ++j)
        nd.Q[k][j] = q[k][j];
      for (int j = 0; j < 3; ++j)
        nd.X[k][j] = X[k][j];
    }
  };
  {
    double X[3][3];
    for (int k = 0; k < 3; ++k)
      EvaluateMap(m, RootTriangle[k], X[k]);
    push(RootTriangle, X, Deviation(m, RootTriangle), 0);
  }
  const Expansion atR(m, v, r.Param);
  Expansion atBest;
  bool haveBest = false;
  double centre2 = r.Distance2;
  int nodes = 0;
  while (n > 0)
  {
    int k = 0;
    for (int i = 1; i < n; ++i)
      if (heap[i].Lower < heap[k].Lower)
        k = i;
    const Node nd = heap[k];
    heap[k] = heap[--n];
    if (nd.Lower >= limit())
      break; // the smallest bound left: nothing nearer remains
    if (++nodes > maxNodes)
    {
      complete = false;
      break;
    }
    // the exact expansion at the local solution r: resolves the sub-triangles near r
    if (atR.Resolves(m, nd.Q, limit()))
      continue;
    // a point nearer than the last centre by more than round-off was found (a corner
    // of a sub-triangle): polish it to a local solution and expand there too
    if (std::sqrt(best2) < std::sqrt(centre2) - 1e-3 * tol)
    {
      ClosestPointResult p;
      ClosestPointOnMap(m, v, bestUV, p);
      if (p.Distance2 < best2)
      {
        best2 = p.Distance2;
        bestUV[0] = p.Param[0];
        bestUV[1] = p.Param[1];
      }
      atBest = Expansion(m, v, bestUV);
      centre2 = best2;
      haveBest = true;
    }
    if (haveBest && atBest.Resolves(m, nd.Q, limit()))
      continue;
    if (nd.Depth >= MaxDepth)
    {
      complete = false;
      continue;
    }
    double mid[3][2], M[3][3];
    for (int e = 0; e < 3; ++e)
    {
      for (int j = 0; j < 2; ++j)
        mid[e][j] = 0.5 * (nd.Q[e][j] + nd.Q[(e + 1) % 3][j]);
      EvaluateMap(m, mid[e], M[e]);
    }
    const double dev = 0.25 * nd.Dev;
    auto kid = [&](const double* qa, const double* qb, const double* qc, const double* xa,
                 const double* xb, const double* xc) {
      const double q[3][2] = { { qa[0], qa[1] }, { qb[0], qb[1] }, { qc[0], qc[1] } };
      const double X[3][3] = { { xa[0], xa[1], xa[2] }, { xb[0], xb[1], xb[2] },
        { xc[0], xc[1], xc[2] } };
      push(q, X, dev, nd.Depth + 1);
    };
    kid(nd.Q[0], mid[0], mid[2], nd.X[0], M[0], M[2]);
    kid(mid[0], nd.Q[1], mid[1], M[0], nd.X[1], M[1]);
    kid(mid[2], mid[1], nd.Q[2], M[2], M[1], nd.X[2]);
    kid(mid[1], mid[2], mid[0], M[1], M[2], M[0]);
  }
  if (certified)
    *certified = complete;
  // improvements far below the tolerance (round-off of the same point) are ignored
  if (!improved || !(std::sqrt(best2) < std::sqrt(r.Distance2) - 1e-3 * tol))
    return false;
  // polish from the nearer point (the full solver sets the constraint bits)
  ClosestPointResult p;
  ClosestPointOnMap(m, v, bestUV, p);
  if (p.Distance2 <= best2 * (1.0 + 1e-14))
    r = p;
  else
  {
    r = ClosestPointResult();
    r.Param[0] = bestUV[0];
    r.Param[1] = bestUV[1];
    EvaluateMap(m, r.Param, r.Point);
    r.Distance2 = best2;
    r.Active = (bestUV[0] <= 0.0 ? 1 : 0) | (bestUV[1] <= 0.0 ? 2 : 0) |
      (bestUV[0] + bestUV[1] >= 1.0 ? 4 : 0);
    r.Converged = true;
  }
  return true;
}

bool SolutionCertified(const QuadraticMap& m, const double v[3], double incumbent2, double tol,
  const ClosestPointResult& r)
{
  const Expansion e(m, v, r.Param);
  return e.Resolves(m, RootTriangle, std::sqrt(std::min(e.F, incumbent2)) - tol);
}

bool PatchFartherThan(
  const QuadraticMap& m, const double v[3], const double uv[2], double incumbent2, double tol)
{
  const Expansion e(m, v, uv);
  return e.F >= incumbent2 && e.Resolves(m, RootTriangle, std::sqrt(incumbent2) - tol);
}
} // namespace hoembed
