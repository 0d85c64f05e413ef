#include "hoembedClosestPointCertify.h"

#include <algorithm>
#include <cmath>

namespace hoembed
{
namespace
{
inline double Dot(const double a[3], const double b[3])
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
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
    return std::min({ SegmentDistance(p, a, b), SegmentDistance(p, b, c), SegmentDistance(p, c, a) });
  const double q[3] = { a[0] + st[0] * ab[0] + st[1] * ac[0], a[1] + st[0] * ab[1] + st[1] * ac[1],
    a[2] + st[0] * ab[2] + st[1] * ac[2] };
  return Dist(p, q);
}

// The patch over the parametric sub-triangle q0 q1 q2 as a map of the reference (s, t).
void SubMap(const QuadraticMap& m, const double q[3][2], QuadraticMap& s)
{
  double J[2][3];
  s.Dim = 2;
  EvaluateMap(m, q[0], s.C, J);
  const double a[2] = { q[1][0] - q[0][0], q[1][1] - q[0][1] };
  const double b[2] = { q[2][0] - q[0][0], q[2][1] - q[0][1] };
  for (int d = 0; d < 3; ++d)
  {
    s.L[0][d] = a[0] * J[0][d] + a[1] * J[1][d];
    s.L[1][d] = b[0] * J[0][d] + b[1] * J[1][d];
    auto qf = [&](const double* x, const double* y) {
      return x[0] * (m.Q[0][0][d] * y[0] + m.Q[0][1][d] * y[1]) +
        x[1] * (m.Q[1][0][d] * y[0] + m.Q[1][1][d] * y[1]);
    };
    s.Q[0][0][d] = qf(a, a);
    s.Q[0][1][d] = s.Q[1][0][d] = qf(a, b);
    s.Q[1][1][d] = qf(b, b);
  }
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

// Range over the reference triangle of p = a + b s + c t + d s^2 + e s t + f t^2 from
// its Bernstein coefficients (p lies between their min and max).
void QuadraticRange(double a, double b, double c, double d, double e, double f, double& lo, double& hi)
{
  const double B[6] = { a, a + b + d, a + c + f, a + 0.5 * b, a + 0.5 * c, a + 0.5 * (b + c + e) };
  lo = *std::min_element(B, B + 6);
  hi = *std::max_element(B, B + 6);
}

// A matrix A (a00, a01, a11) with D^T Hs D >= D^T A D for every (s, t) of the reference
// triangle, Hs = (1/2) Hess |x - v|^2 = J^T J + (x - v) . Q; each entry of Hs is a
// quadratic polynomial in (s, t), bounded by its Bernstein coefficients; the spread r of
// the off-diagonal entry costs r (|ds|^2 + |dt|^2). Returns lambda_min(A): positive, the
// squared distance is strictly convex on the sub-patch.
double HessianBound(const QuadraticMap& s, const double v[3], double A[3])
{
  const double* L0 = s.L[0];
  const double* L1 = s.L[1];
  const double* Q00 = s.Q[0][0];
  const double* Q01 = s.Q[0][1];
  const double* Q11 = s.Q[1][1];
  const double w[3] = { s.C[0] - v[0], s.C[1] - v[1], s.C[2] - v[2] };
  const double* Qs[3] = { Q00, Q01, Q11 };
  double lo[3], hi[3];
  for (int k = 0; k < 3; ++k)
  {
    const double* Q = Qs[k];
    // (x - v) . Q_k
    double a = Dot(w, Q), b = Dot(L0, Q), c = Dot(L1, Q), d = 0.5 * Dot(Q00, Q), e = Dot(Q01, Q),
           f = 0.5 * Dot(Q11, Q);
    // + J_i . J_j
    if (k == 0)
    {
      a += Dot(L0, L0);
      b += 2.0 * Dot(L0, Q00);
      c += 2.0 * Dot(L0, Q01);
      d += Dot(Q00, Q00);
      e += 2.0 * Dot(Q00, Q01);
      f += Dot(Q01, Q01);
    }
    else if (k == 1)
    {
      a += Dot(L0, L1);
      b += Dot(L0, Q01) + Dot(Q00, L1);
      c += Dot(L0, Q11) + Dot(Q01, L1);
      d += Dot(Q00, Q01);
      e += Dot(Q00, Q11) + Dot(Q01, Q01);
      f += Dot(Q01, Q11);
    }
    else
    {
      a += Dot(L1, L1);
      b += 2.0 * Dot(L1, Q01);
      c += 2.0 * Dot(L1, Q11);
      d += Dot(Q01, Q01);
      e += 2.0 * Dot(Q01, Q11);
      f += Dot(Q11, Q11);
    }
    QuadraticRange(a, b, c, d, e, f, lo[k], hi[k]);
  }
  const double mid = 0.5 * (lo[1] + hi[1]), rad = 0.5 * (hi[1] - lo[1]);
  A[0] = lo[0] - rad;
  A[1] = mid;
  A[2] = lo[2] - rad;
  return 0.5 * (A[0] + A[2]) - std::sqrt(0.25 * (A[0] - A[2]) * (A[0] - A[2]) + A[1] * A[1]);
}

// The point of the reference triangle nearest to (s, t).
void ProjectToTriangle(double s, double t, double out[2])
{
  if (s >= 0.0 && t >= 0.0 && s + t <= 1.0)
  {
    out[0] = s;
    out[1] = t;
    return;
  }
  const double P[3][2] = { { 0, 0 }, { 1, 0 }, { 0, 1 } };
  double best = 1e300;
  for (int e = 0; e < 3; ++e)
  {
    const double* a = P[e];
    const double* b = P[(e + 1) % 3];
    const double d[2] = { b[0] - a[0], b[1] - a[1] };
    double tau = ((s - a[0]) * d[0] + (t - a[1]) * d[1]) / (d[0] * d[0] + d[1] * d[1]);
    tau = std::min(1.0, std::max(0.0, tau));
    const double q[2] = { a[0] + tau * d[0], a[1] + tau * d[1] };
    const double dist = (q[0] - s) * (q[0] - s) + (q[1] - t) * (q[1] - t);
    if (dist < best)
    {
      best = dist;
      out[0] = std::max(0.0, q[0]);
      out[1] = std::max(0.0, q[1]);
    }
  }
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
    const double root[3][2] = { { 0, 0 }, { 1, 0 }, { 0, 1 } };
    double X[3][3];
    for (int k = 0; k < 3; ++k)
      EvaluateMap(m, root[k], X[k]);
    push(root, X, Deviation(m, root), 0);
  }
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
    QuadraticMap s;
    SubMap(m, nd.Q, s);
    // A point xi* of the sub-triangle and the second-order bound
    // f(xi* + D) >= f(xi*) + grad f . D + D^T A D, minimised exactly over the
    // sub-triangle. xi*: the point of the sub-triangle nearest (in parameters) to the
    // local solution r (r itself when it lies inside: no solve); when that bound fails
    // and the distance is convex on the sub-triangle, a solve there.
    double A[3];
    const double mu = HessianBound(s, v, A);
    double star[2];
    bool resolved = false;
    {
      const double a0 = nd.Q[1][0] - nd.Q[0][0], a1 = nd.Q[1][1] - nd.Q[0][1];
      const double b0 = nd.Q[2][0] - nd.Q[0][0], b1 = nd.Q[2][1] - nd.Q[0][1];
      const double det = a0 * b1 - a1 * b0;
      const double du = r.Param[0] - nd.Q[0][0], dv = r.Param[1] - nd.Q[0][1];
      ProjectToTriangle((du * b1 - dv * b0) / det, (a0 * dv - a1 * du) / det, star);
    }
    for (int pass = 0; pass < 2 && !resolved; ++pass)
    {
      if (pass == 1)
      {
        if (!(mu > 0.0))
          break;
        const double c[2] = { 1.0 / 3.0, 1.0 / 3.0 };
        ClosestPointResult rs;
        ClosestPointOnMap(s, v, c, rs);
        star[0] = rs.Param[0];
        star[1] = rs.Param[1];
      }
      double x[3], J[2][3];
      EvaluateMap(s, star, x, J);
      const double w[3] = { x[0] - v[0], x[1] - v[1], x[2] - v[2] };
      const double f = Dot(w, w);
      if (f < best2)
      {
        best2 = f;
        for (int j = 0; j < 2; ++j)
          bestUV[j] = nd.Q[0][j] + star[0] * (nd.Q[1][j] - nd.Q[0][j]) +
            star[1] * (nd.Q[2][j] - nd.Q[0][j]);
        improved = true;
      }
      const double g[2] = { 2.0 * Dot(J[0], w), 2.0 * Dot(J[1], w) };
      const double lower2 = f + std::min(0.0, MinQuadraticOnTriangle(g, A, star));
      if (std::sqrt(std::max(0.0, lower2)) >= limit())
        resolved = true;
    }
    if (resolved)
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
} // namespace hoembed
