// Small pieces shared by the certified searches of hoembed::LagrangeEmbeddingMesh
// (hoembedLagrangeEmbedding.cxx, hoembedLagrangeFaceSearch.cxx: triangular faces) and
// hoembed::LagrangeHexEmbeddingMesh (hoembedLagrangeHexEmbedding.cxx: quadrilateral
// faces). Private.
#ifndef hoembedLagrangeEmbeddingInternal_h
#define hoembedLagrangeEmbeddingInternal_h

#include <algorithm>
#include <cmath>

namespace hoembed
{
namespace lagrange_detail
{
inline double Dot(const double a[3], const double b[3])
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

// Solve A x = b (3 x 3, A[r][c]) by Cramer's rule; false when singular.
inline bool Solve3(const double A[3][3], const double b[3], double x[3])
{
  const double det = A[0][0] * (A[1][1] * A[2][2] - A[1][2] * A[2][1]) -
    A[0][1] * (A[1][0] * A[2][2] - A[1][2] * A[2][0]) +
    A[0][2] * (A[1][0] * A[2][1] - A[1][1] * A[2][0]);
  double scale = 0.0;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      scale = std::max(scale, std::abs(A[r][c]));
  if (!(std::abs(det) > 1e-300) || !(std::abs(det) > 1e-14 * scale * scale * scale))
    return false;
  for (int k = 0; k < 3; ++k)
  {
    double M[3][3];
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        M[r][c] = c == k ? b[r] : A[r][c];
    x[k] = (M[0][0] * (M[1][1] * M[2][2] - M[1][2] * M[2][1]) -
             M[0][1] * (M[1][0] * M[2][2] - M[1][2] * M[2][0]) +
             M[0][2] * (M[1][0] * M[2][1] - M[1][1] * M[2][0])) /
      det;
  }
  return true;
}

// Interval arithmetic of the branch and bound's Hessian bounds.
struct Interval
{
  double Lo = HUGE_VAL, Hi = -HUGE_VAL;
  void Add(double x)
  {
    Lo = std::min(Lo, x);
    Hi = std::max(Hi, x);
  }
};
inline Interval Mul(const Interval& a, const Interval& b)
{
  Interval r;
  r.Add(a.Lo * b.Lo);
  r.Add(a.Lo * b.Hi);
  r.Add(a.Hi * b.Lo);
  r.Add(a.Hi * b.Hi);
  return r;
}
inline Interval Square(const Interval& a)
{
  Interval r;
  r.Lo = a.Lo > 0 ? a.Lo * a.Lo : (a.Hi < 0 ? a.Hi * a.Hi : 0.0);
  r.Hi = std::max(a.Lo * a.Lo, a.Hi * a.Hi);
  return r;
}
inline Interval Sum(const Interval& a, const Interval& b)
{
  Interval r;
  r.Lo = a.Lo + b.Lo;
  r.Hi = a.Hi + b.Hi;
  return r;
}

// Euclidean projection of (u, v) onto the reference triangle.
inline void ProjectTriangle(double uv[2])
{
  double u = uv[0], v = uv[1];
  if (u + v > 1.0)
  {
    const double s = 0.5 * (u + v - 1.0);
    u -= s;
    v -= s;
  }
  u = std::max(0.0, u);
  v = std::max(0.0, v);
  if (u > 1.0)
    u = 1.0;
  if (v > 1.0 - u)
    v = 1.0 - u;
  uv[0] = u;
  uv[1] = v;
}

// (u, v) clamped into the unit square.
inline void ClampSquare(double uv[2])
{
  uv[0] = std::min(1.0, std::max(0.0, uv[0]));
  uv[1] = std::min(1.0, std::max(0.0, uv[1]));
}

// The two face domains of LocalFaceSolve: Project puts (u, v) into the domain; Binding
// counts the sides at which the gradient g of the distance pushes (u, v) out, and for one
// such side gives the direction t along it.
struct TriangleDomain
{
  static void Project(double uv[2])
  {
    ProjectTriangle(uv);
  }
  static int Binding(const double uv[2], const double g[2], double t[2])
  {
    const double eps = 1e-15;
    const bool b0 = uv[0] <= eps && g[0] > 0, b1 = uv[1] <= eps && g[1] > 0;
    const bool b2 = uv[0] + uv[1] >= 1 - eps && g[0] + g[1] < 0;
    t[0] = b0 ? 0.0 : 1.0;
    t[1] = b0 ? 1.0 : (b1 ? 0.0 : -1.0);
    return int(b0) + int(b1) + int(b2);
  }
};
struct SquareDomain
{
  static void Project(double uv[2])
  {
    ClampSquare(uv);
  }
  static int Binding(const double uv[2], const double g[2], double t[2])
  {
    const double eps = 1e-15;
    bool bound[2];
    for (int k = 0; k < 2; ++k)
      bound[k] = (uv[k] <= eps && g[k] > 0) || (uv[k] >= 1 - eps && g[k] < 0);
    t[0] = bound[0] ? 0.0 : 1.0;
    t[1] = bound[0] ? 1.0 : 0.0;
    return int(bound[0]) + int(bound[1]);
  }
};

// Local closest point on one face: projected Newton over the face's reference domain
// (Domain: an active set of its sides), monotone in |x - v|^2. eval(uv, x, xu, xv, H)
// gives the point, its derivatives and the second derivatives (H[0] = xuu, H[1] = xuv,
// H[2] = xvv). Returns that squared distance; `iterations` counts the Newton steps.
template <typename Domain, typename Eval>
double LocalFaceSolve(const Eval& eval, const double v[3], double uv[2], int& iterations)
{
  Domain::Project(uv);
  double x[3], xu[3], xv[3], H[3][3];
  eval(uv, x, xu, xv, H);
  double e[3] = { x[0] - v[0], x[1] - v[1], x[2] - v[2] };
  double f = Dot(e, e);
  for (int it = 0; it < 60; ++it)
  {
    ++iterations;
    const double g[2] = { 2 * Dot(xu, e), 2 * Dot(xv, e) };
    double A[2][2] = { { 2 * (Dot(xu, xu) + Dot(e, H[0])), 2 * (Dot(xu, xv) + Dot(e, H[1])) },
      { 0, 2 * (Dot(xv, xv) + Dot(e, H[2])) } };
    A[1][0] = A[0][1];
    double t[2];
    const int nb = Domain::Binding(uv, g, t);
    double step[2] = { 0, 0 };
    if (nb >= 2)
      break; // a corner with both sides binding: a KKT point
    if (nb == 1)
    {
      // Newton along the binding side
      const double gt = g[0] * t[0] + g[1] * t[1];
      const double ht =
        t[0] * (A[0][0] * t[0] + A[0][1] * t[1]) + t[1] * (A[1][0] * t[0] + A[1][1] * t[1]);
      const double a = ht > 0 ? -gt / ht : -gt;
      step[0] = a * t[0];
      step[1] = a * t[1];
    }
    else
    {
      // Newton, shifted to positive definite where the Hessian is not
      const double tr = A[0][0] + A[1][1];
      double mu = 0.0;
      const double det = A[0][0] * A[1][1] - A[0][1] * A[1][0];
      if (!(A[0][0] > 0 && det > 1e-14 * tr * tr))
      {
        const double disc = std::sqrt(std::max(0.0, 0.25 * tr * tr - det));
        const double lmin = 0.5 * tr - disc;
        mu = -lmin + 1e-3 * std::abs(tr) + 1e-300;
      }
      const double a00 = A[0][0] + mu, a11 = A[1][1] + mu;
      const double dd = a00 * a11 - A[0][1] * A[1][0];
      if (!(dd > 0))
      {
        step[0] = -g[0];
        step[1] = -g[1];
      }
      else
      {
        step[0] = -(a11 * g[0] - A[0][1] * g[1]) / dd;
        step[1] = -(a00 * g[1] - A[1][0] * g[0]) / dd;
      }
    }
    double alpha = 1.0;
    bool moved = false;
    for (int ls = 0; ls < 40; ++ls, alpha *= 0.5)
    {
      double s[2] = { uv[0] + alpha * step[0], uv[1] + alpha * step[1] };
      Domain::Project(s);
      double y[3], yu[3], yv[3], yH[3][3];
      eval(s, y, yu, yv, yH);
      const double en[3] = { y[0] - v[0], y[1] - v[1], y[2] - v[2] };
      const double fn = Dot(en, en);
      if (fn <= f)
      {
        const double change = std::abs(s[0] - uv[0]) + std::abs(s[1] - uv[1]);
        uv[0] = s[0];
        uv[1] = s[1];
        std::copy(y, y + 3, x);
        std::copy(yu, yu + 3, xu);
        std::copy(yv, yv + 3, xv);
        for (int k = 0; k < 3; ++k)
          std::copy(yH[k], yH[k] + 3, H[k]);
        std::copy(en, en + 3, e);
        moved = change > 1e-16;
        f = fn;
        break;
      }
    }
    if (!moved)
      break;
  }
  return f;
}

} // namespace lagrange_detail
} // namespace hoembed

#endif
