#include "hoembedTetBarycentric.h"
#include "hoembedShapeFunctions.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hoembed
{
void MakeTetBarycentricForm(const double* x, int n, TetBarycentricForm& form)
{
  form.Slack = -1.0; // not usable until complete
  double A[3][3];    // columns: x1 - x0, x2 - x0, x3 - x0
  for (int d = 0; d < 3; ++d)
  {
    form.X0[d] = x[d];
    for (int i = 0; i < 3; ++i)
      A[d][i] = x[3 * (i + 1) + d] - x[d];
  }
  // inverse by cofactors: rows of A^-1 are the gradients of lambda_1..3
  const double C[3][3] = { { A[1][1] * A[2][2] - A[1][2] * A[2][1],
                             A[0][2] * A[2][1] - A[0][1] * A[2][2],
                             A[0][1] * A[1][2] - A[0][2] * A[1][1] },
    { A[1][2] * A[2][0] - A[1][0] * A[2][2], A[0][0] * A[2][2] - A[0][2] * A[2][0],
      A[0][2] * A[1][0] - A[0][0] * A[1][2] },
    { A[1][0] * A[2][1] - A[1][1] * A[2][0], A[0][1] * A[2][0] - A[0][0] * A[2][1],
      A[0][0] * A[1][1] - A[0][1] * A[1][0] } };
  const double det = A[0][0] * C[0][0] + A[0][1] * C[1][0] + A[0][2] * C[2][0];
  const double inv = 1.0 / det;
  if (!std::isfinite(inv) || inv == 0.0)
    return;
  double normA = 0.0;
  for (int d = 0; d < 3; ++d)
  {
    form.G[0][d] = 0.0;
    for (int i = 0; i < 3; ++i)
    {
      form.G[i + 1][d] = C[i][d] * inv;
      form.G[0][d] -= form.G[i + 1][d];
      normA += A[d][i] * A[d][i];
    }
  }
  double normInv = 0.0;
  for (int k = 0; k < 4; ++k)
  {
    const double g2 =
      form.G[k][0] * form.G[k][0] + form.G[k][1] * form.G[k][1] + form.G[k][2] * form.G[k][2];
    form.GNorm[k] = std::sqrt(g2);
    normInv += k > 0 ? g2 : 0.0;
  }
  const double cond = std::sqrt(normA * normInv);
  if (!(cond <= 1e8))
    return;
  for (int k = 0; k < 4; ++k)
    form.Bump[k] = 0.0; // corners: l_k is 0 or 1
  for (int e = 0; e < 6; ++e)
  {
    const int i = TetEdgeCorners[e][0], j = TetEdgeCorners[e][1];
    double delta[3] = { 0, 0, 0 };
    if (n == 10)
      for (int d = 0; d < 3; ++d)
        delta[d] = x[3 * (4 + e) + d] - 0.5 * (x[3 * i + d] + x[3 * j + d]);
    for (int k = 0; k < 4; ++k)
    {
      const double w = form.G[k][0] * delta[0] + form.G[k][1] * delta[1] + form.G[k][2] * delta[2];
      form.W[e][k] = w;
      // the edge's Bezier coefficient of l_k(x(lambda))
      const double b = 0.5 * ((k == i) + (k == j)) + 2.0 * w;
      form.Bump[k] = std::max(form.Bump[k], -b);
    }
  }
  // the gradients carry a relative error of about cond * eps; the sweeps add a few eps
  form.Slack = 1e-12 + 64.0 * std::numeric_limits<double>::epsilon() * cond;
}

namespace
{
// The straight tet's barycentric coordinates l of p and their round-off allowance.
void StraightCoordinates(
  const TetBarycentricForm& form, const double p[3], double l[4], double slack[4])
{
  const double y[3] = { p[0] - form.X0[0], p[1] - form.X0[1], p[2] - form.X0[2] };
  for (int k = 0; k < 4; ++k)
  {
    l[k] = form.G[k][0] * y[0] + form.G[k][1] * y[1] + form.G[k][2] * y[2] + (k == 0 ? 1.0 : 0.0);
    slack[k] = form.Slack * (1.0 + std::fabs(l[k]));
  }
}
} // namespace

int TetBarycentricBeyond(const TetBarycentricForm& form, const double p[3], double reach)
{
  if (form.Slack < 0.0)
    return -1;
  double l[4], slack[4];
  StraightCoordinates(form, p, l, slack);
  int corner = -1;
  double worst = 0.0; // distance beyond the slab, in world units
  for (int k = 0; k < 4; ++k)
  {
    const double beyond = -(l[k] + form.Bump[k] + slack[k]);
    if (beyond > reach * form.GNorm[k] && (corner < 0 || beyond > worst * form.GNorm[k]))
    {
      corner = k;
      worst = beyond / form.GNorm[k];
    }
  }
  return corner;
}

bool TetBarycentricExcludes(
  const TetBarycentricForm& form, const double p[3], double reach, int maxSweeps)
{
  if (form.Slack < 0.0)
    return false;
  double L[4], r[4];
  StraightCoordinates(form, p, L, r);
  for (int k = 0; k < 4; ++k)
    r[k] += form.GNorm[k] * reach;
  double lo[4] = { 0, 0, 0, 0 }, hi[4] = { 1, 1, 1, 1 };
  double width = 4.0;
  for (int sweep = 0; sweep < maxSweeps; ++sweep)
  {
    // 4 lambda_i lambda_j over the current box, per edge
    double qlo[6], qhi[6];
    for (int e = 0; e < 6; ++e)
    {
      const int i = TetEdgeCorners[e][0], j = TetEdgeCorners[e][1];
      const double s = std::min(1.0, hi[i] + hi[j]);
      qlo[e] = 4.0 * lo[i] * lo[j];
      qhi[e] = std::min(4.0 * hi[i] * hi[j], s * s);
    }
    // the range of sum_e q_e w_ke, all four k at once (q_e >= 0)
    double plo[4] = { 0, 0, 0, 0 }, phi[4] = { 0, 0, 0, 0 };
    for (int e = 0; e < 6; ++e)
      for (int k = 0; k < 4; ++k)
      {
        const double a = qlo[e] * form.W[e][k], b = qhi[e] * form.W[e][k];
        plo[k] += std::min(a, b);
        phi[k] += std::max(a, b);
      }
    for (int k = 0; k < 4; ++k)
    {
      lo[k] = std::max(lo[k], L[k] - phi[k] - r[k]);
      hi[k] = std::min(hi[k], L[k] - plo[k] + r[k]);
    }
    // the sum constraint: lambda_m = 1 - sum of the others
    const double sumLo = lo[0] + lo[1] + lo[2] + lo[3];
    const double sumHi = hi[0] + hi[1] + hi[2] + hi[3];
    double w = 0.0;
    bool empty = false;
    for (int m = 0; m < 4; ++m)
    {
      lo[m] = std::max(lo[m], 1.0 - (sumHi - hi[m]));
      hi[m] = std::min(hi[m], 1.0 - (sumLo - lo[m]));
      empty |= lo[m] > hi[m];
      w += hi[m] - lo[m];
    }
    // (a NaN p never gets here: every comparison with it is false, the box stays put)
    if (empty)
      return true;
    // give up when a sweep no longer shrinks the box much
    if (!(w < 0.9 * width))
      return false;
    width = w;
  }
  return false;
}
} // namespace hoembed
