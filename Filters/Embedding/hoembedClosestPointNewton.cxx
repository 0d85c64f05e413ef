// Newton-type solves on the monomial maps: a start from the straight simplex, the
// unconstrained inverse of a tet map, and the normal-offset solve of paper eq. 8-9.
#include "hoembedClosestPoint.h"
#include "hoembedClosestPointInternal.h"

#include <algorithm>
#include <cmath>

namespace hoembed
{
using detail::Eval;
using detail::Solve3;

bool ClosestPointOnTriangle(
  const double ap[3], const double ab[3], const double ac[3], double st[2])
{
  auto answer = [st](double s, double t) {
    st[0] = s;
    st[1] = t;
    return true;
  };
  const double d1 = Dot(ab, ap), d2 = Dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0)
    return answer(0.0, 0.0);
  const double bp[3] = { ap[0] - ab[0], ap[1] - ab[1], ap[2] - ab[2] };
  const double d3 = Dot(ab, bp), d4 = Dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3)
    return answer(1.0, 0.0);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 && d1 - d3 > 0.0)
    return answer(d1 / (d1 - d3), 0.0);
  const double cp[3] = { ap[0] - ac[0], ap[1] - ac[1], ap[2] - ac[2] };
  const double d5 = Dot(ab, cp), d6 = Dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6)
    return answer(0.0, 1.0);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 && d2 - d6 > 0.0)
    return answer(0.0, d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 && (d4 - d3) + (d5 - d6) > 0.0)
  {
    const double t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return answer(1.0 - t, t);
  }
  const double den = va + vb + vc;
  if (!(den > 0.0) || va < 0.0 || vb < 0.0 || vc < 0.0)
  {
    answer(1.0 / 3.0, 1.0 / 3.0);
    return false;
  }
  return answer(vb / den, vc / den);
}

void LinearStart(const QuadraticMap& m, const double v[3], double* start)
{
  // corners x(0), x(e_i) = C + L_i + Q_ii / 2
  double e[3][3], w[3];
  for (int i = 0; i < m.Dim; ++i)
    for (int d = 0; d < 3; ++d)
      e[i][d] = m.L[i][d] + 0.5 * m.Q[i][i][d];
  for (int d = 0; d < 3; ++d)
    w[d] = v[d] - m.C[d];
  if (m.Dim == 3)
  {
    double A[3][3], pc[3];
    for (int d = 0; d < 3; ++d)
      for (int i = 0; i < 3; ++i)
        A[d][i] = e[i][d];
    if (!Solve3(A, w, pc))
    {
      start[0] = start[1] = start[2] = 0.25;
      return;
    }
    double s = 0.0;
    for (int i = 0; i < 3; ++i)
    {
      pc[i] = std::max(0.0, pc[i]);
      s += pc[i];
    }
    for (int i = 0; i < 3; ++i)
      start[i] = s > 1.0 ? pc[i] / s : pc[i];
    return;
  }
  // Dim 2: closest point on the triangle (0, e0, e1)
  ClosestPointOnTriangle(w, e[0], e[1], start);
}

double InvertTetMap(const QuadraticMap& m, const double v[3], double pc[3], int& iterations,
  int maxIterations, double outsideStop)
{
  double x[3], J[3][3], F[3];
  Eval<3>(m, pc, x, J);
  for (int d = 0; d < 3; ++d)
    F[d] = x[d] - v[d];
  double f = Dot(F, F);
  // converged: |x(pc) - v| at the round-off of the map's coordinates (a Newton step
  // from there cannot decrease it, and the line search would halve it 30 times)
  double scale = 0.0;
  for (int i = 0; i < 3; ++i)
    scale += std::fabs(m.C[i]) + std::sqrt(Dot(m.L[i], m.L[i]));
  const double floor2 = (1e-15 * scale) * (1e-15 * scale);
  // a search gives up sooner on a step the line search cannot make decrease f
  const int maxLineSearch = outsideStop > 0.0 ? 10 : 30;
  for (int it = 0; it < maxIterations && f > floor2; ++it)
  {
    ++iterations;
    double A[3][3], b[3], dx[3];
    for (int d = 0; d < 3; ++d)
    {
      for (int i = 0; i < 3; ++i)
        A[d][i] = J[i][d];
      b[d] = -F[d];
    }
    if (!Solve3(A, b, dx))
      break;
    // converged to round-off: a line search would only halve a step that cannot decrease
    // f any more (30 evaluations)
    const double dmax = std::max({ std::fabs(dx[0]), std::fabs(dx[1]), std::fabs(dx[2]) });
    if (dmax <= 1e-14 * (1.0 + std::fabs(pc[0]) + std::fabs(pc[1]) + std::fabs(pc[2])))
      break;
    // a search (outsideStop > 0) that meets a step longer than the reference tet: the
    // Jacobian is nearly singular here (the map folds outside the element), there is no
    // preimage nearby; the caller's constrained solve decides. (An extrapolation for a
    // far point, outsideStop = 0, goes on.)
    if (outsideStop > 0.0 && dmax > 2.0)
      break;
    double alpha = 1.0;
    bool accepted = false;
    double pt[3], xt[3], Jt[3][3], Ft[3], ft = f;
    for (int ls = 0; ls < maxLineSearch; ++ls)
    {
      for (int i = 0; i < 3; ++i)
        pt[i] = pc[i] + alpha * dx[i];
      Eval<3>(m, pt, xt, Jt);
      for (int d = 0; d < 3; ++d)
        Ft[d] = xt[d] - v[d];
      ft = Dot(Ft, Ft);
      if (ft < f)
      {
        accepted = true;
        break;
      }
      // f(alpha) ~ f - 2 f alpha + c alpha^2 along the Newton direction (slope -2 f):
      // the minimiser of the quadratic through f(0), f'(0), f(alpha), kept within
      // [alpha / 10, alpha / 2]
      const double c = (ft - f + 2.0 * f * alpha) / (alpha * alpha);
      const double amin = c > 0.0 ? f / c : 0.5 * alpha;
      alpha = std::max(0.1 * alpha, std::min(0.5 * alpha, amin));
    }
    if (!accepted)
      break;
    const double step =
      std::max({ std::fabs(pc[0] - pt[0]), std::fabs(pc[1] - pt[1]), std::fabs(pc[2] - pt[2]) });
    for (int i = 0; i < 3; ++i)
    {
      pc[i] = pt[i];
      F[i] = Ft[i];
      for (int d = 0; d < 3; ++d)
        J[i][d] = Jt[i][d];
    }
    f = ft;
    if (step <= 1e-15 * (1.0 + std::fabs(pc[0]) + std::fabs(pc[1]) + std::fabs(pc[2])))
      break;
    // clearly outside the element and close enough for the caller's exclusion proof
    if (f <= outsideStop * outsideStop &&
      std::min({ pc[0], pc[1], pc[2], 1.0 - pc[0] - pc[1] - pc[2] }) < -1e-3)
      break;
  }
  return std::sqrt(f);
}

int SolveNormalOffset(const QuadraticMap& xm, const QuadraticMap& sm, const double p[3],
  double uv[2], double& d, double tol, int& iterations, int maxIterations)
{
  auto residual = [&](const double* w, double dd, double F[3], double Jx[2][3], double n[3],
                    double Js[2][3], double& ls) {
    double x[3], s[3];
    Eval<2>(xm, w, x, Jx);
    Eval<2>(sm, w, s, Js);
    ls = std::sqrt(Dot(s, s));
    for (int k = 0; k < 3; ++k)
    {
      n[k] = ls > 0.0 ? s[k] / ls : 0.0;
      F[k] = x[k] + dd * n[k] - p[k];
    }
    return std::sqrt(Dot(F, F));
  };
  double F[3], Jx[2][3], n[3], Js[2][3], ls;
  double fn = residual(uv, d, F, Jx, n, Js, ls);
  for (int it = 0; it < maxIterations; ++it)
  {
    if (!(ls > 0.0) || !std::isfinite(fn))
      return -1;
    if (fn <= tol)
      return 0;
    ++iterations;
    double A[3][3], b[3], delta[3];
    for (int c = 0; c < 2; ++c)
    {
      const double ns = Dot(n, Js[c]);
      for (int k = 0; k < 3; ++k)
        A[k][c] = Jx[c][k] + d * (Js[c][k] - n[k] * ns) / ls;
    }
    for (int k = 0; k < 3; ++k)
    {
      A[k][2] = n[k];
      b[k] = -F[k];
    }
    if (!Solve3(A, b, delta))
      return -1;
    // converged to round-off: the remaining Newton step is below the resolution of the
    // coordinates (happens on an edge, where the normal field has a kink)
    if (std::fabs(delta[0]) + std::fabs(delta[1]) <= 1e-13 && std::fabs(delta[2]) <= tol &&
      fn <= 100.0 * tol)
      return 0;
    // ratio test: where does the step leave the triangle?
    double amax = 1.0;
    int edge = -1;
    if (delta[1] < 0.0 && uv[1] + delta[1] < 0.0)
    {
      const double a = std::max(0.0, uv[1]) / -delta[1];
      if (a < amax)
      {
        amax = a;
        edge = 0; // v = 0: edge ab
      }
    }
    if (delta[0] + delta[1] > 0.0 && uv[0] + uv[1] + delta[0] + delta[1] > 1.0)
    {
      const double a = std::max(0.0, 1.0 - uv[0] - uv[1]) / (delta[0] + delta[1]);
      if (a < amax)
      {
        amax = a;
        edge = 1; // u + v = 1: edge bc
      }
    }
    if (delta[0] < 0.0 && uv[0] + delta[0] < 0.0)
    {
      const double a = std::max(0.0, uv[0]) / -delta[0];
      if (a < amax)
      {
        amax = a;
        edge = 2; // u = 0: edge ca
      }
    }
    if (edge >= 0)
    {
      uv[0] += amax * delta[0];
      uv[1] += amax * delta[1];
      d += amax * delta[2];
      if (edge == 0)
        uv[1] = 0.0;
      else if (edge == 2)
        uv[0] = 0.0;
      else
      {
        const double s = uv[0] + uv[1];
        if (s > 0.0)
        {
          uv[0] /= s;
          uv[1] /= s;
        }
      }
      uv[0] = std::min(1.0, std::max(0.0, uv[0]));
      uv[1] = std::min(1.0 - uv[0], std::max(0.0, uv[1]));
      return 1 + edge;
    }
    double alpha = 1.0;
    bool accepted = false;
    for (int ls2 = 0; ls2 < 30; ++ls2)
    {
      double w[2] = { uv[0] + alpha * delta[0], uv[1] + alpha * delta[1] };
      const double dd = d + alpha * delta[2];
      double Ft[3], Jxt[2][3], nt[3], Jst[2][3], lst;
      const double ft = residual(w, dd, Ft, Jxt, nt, Jst, lst);
      if (ft < fn || ft <= tol)
      {
        uv[0] = w[0];
        uv[1] = w[1];
        d = dd;
        fn = ft;
        ls = lst;
        for (int k = 0; k < 3; ++k)
        {
          F[k] = Ft[k];
          n[k] = nt[k];
          Jx[0][k] = Jxt[0][k];
          Jx[1][k] = Jxt[1][k];
          Js[0][k] = Jst[0][k];
          Js[1][k] = Jst[1][k];
        }
        accepted = true;
        break;
      }
      alpha *= 0.5;
    }
    if (!accepted)
      return fn <= tol ? 0 : -1;
  }
  return fn <= tol ? 0 : -1;
}

bool TetMapOffset(const QuadraticMap& m, const double pc[3], const double v[3], double q[3])
{
  double x[3], J[3][3], A[3][3], b[3];
  Eval<3>(m, pc, x, J);
  for (int d = 0; d < 3; ++d)
  {
    for (int i = 0; i < 3; ++i)
      A[d][i] = J[i][d];
    b[d] = v[d] - x[d];
  }
  if (Solve3(A, b, q))
    return true;
  q[0] = q[1] = q[2] = 0.0;
  return false;
}
} // namespace hoembed
