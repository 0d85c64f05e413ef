#include "hoembedClosestPoint.h"
#include "hoembedClosestPointInternal.h"
#include "hoembedElementGeometry.h"
#include "hoembedShapeFunctions.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hoembed
{
using detail::Eval;

namespace
{
// Constraint k of the N-simplex in the form a_k . xi >= b_k: k < N: xi_k >= 0; k = N:
// -sum xi >= -1.
template <int N>
inline double Slack(int k, const double* xi)
{
  if (k < N)
  {
    return xi[k];
  }
  double s = 1.0;
  for (int i = 0; i < N; ++i)
  {
    s -= xi[i];
  }
  return s;
}

template <int N>
inline double NormalDot(int k, const double* p)
{
  if (k < N)
  {
    return p[k];
  }
  double s = 0.0;
  for (int i = 0; i < N; ++i)
  {
    s -= p[i];
  }
  return s;
}

// Per active set: an orthonormal basis Z of the free directions and the least-squares
// multiplier operator P (mu = P g), precomputed once.
template <int N>
struct ActiveSetTables
{
  static constexpr int NC = N + 1;
  int M[1 << NC];           // number of free directions
  double Z[1 << NC][N][N];  // Z[mask][col][component]
  int NA[1 << NC];          // number of active constraints
  int Which[1 << NC][NC];   // active constraint indices
  double P[1 << NC][NC][N]; // multipliers: mu_a = sum_i P[a][i] g_i
  bool Valid[1 << NC];

  ActiveSetTables()
  {
    for (int mask = 0; mask < (1 << NC); ++mask)
    {
      double A[NC][N];
      int na = 0;
      for (int k = 0; k < NC; ++k)
      {
        if (mask & (1 << k))
        {
          for (int i = 0; i < N; ++i)
          {
            A[na][i] = (k < N) ? (i == k ? 1.0 : 0.0) : -1.0;
          }
          this->Which[mask][na++] = k;
        }
      }
      this->NA[mask] = na;
      this->Valid[mask] = na <= N;
      this->M[mask] = 0;
      if (!this->Valid[mask])
      {
        continue;
      }
      // orthonormal basis U of the active normals, then Z completing it
      double U[N][N];
      int nu = 0;
      auto orth = [&](double w[N], double(*B)[N], int nb) {
        for (int b = 0; b < nb; ++b)
        {
          double c = 0.0;
          for (int i = 0; i < N; ++i)
            c += w[i] * B[b][i];
          for (int i = 0; i < N; ++i)
            w[i] -= c * B[b][i];
        }
      };
      double basis[2 * N][N];
      int nbasis = 0;
      for (int a = 0; a < na; ++a)
      {
        double w[N];
        for (int i = 0; i < N; ++i)
          w[i] = A[a][i];
        orth(w, U, nu);
        double l = 0.0;
        for (int i = 0; i < N; ++i)
          l += w[i] * w[i];
        l = std::sqrt(l);
        for (int i = 0; i < N; ++i)
          U[nu][i] = w[i] / l;
        ++nu;
      }
      for (int a = 0; a < nu; ++a)
        for (int i = 0; i < N; ++i)
          basis[a][i] = U[a][i];
      nbasis = nu;
      int m = 0;
      for (int e = 0; e < N && nbasis < N; ++e)
      {
        double w[N];
        for (int i = 0; i < N; ++i)
          w[i] = (i == e) ? 1.0 : 0.0;
        orth(w, basis, nbasis);
        double l = 0.0;
        for (int i = 0; i < N; ++i)
          l += w[i] * w[i];
        l = std::sqrt(l);
        if (l < 1e-8)
          continue;
        for (int i = 0; i < N; ++i)
        {
          basis[nbasis][i] = w[i] / l;
          this->Z[mask][m][i] = w[i] / l;
        }
        ++nbasis;
        ++m;
      }
      this->M[mask] = m;
      // P = (A A^T)^-1 A by Gauss-Jordan on the na x na system
      double G[NC][NC + N];
      for (int a = 0; a < na; ++a)
      {
        for (int b = 0; b < na; ++b)
        {
          double s = 0.0;
          for (int i = 0; i < N; ++i)
            s += A[a][i] * A[b][i];
          G[a][b] = s;
        }
        for (int i = 0; i < N; ++i)
          G[a][na + i] = A[a][i];
      }
      for (int c = 0; c < na; ++c)
      {
        int piv = c;
        for (int r = c + 1; r < na; ++r)
          if (std::fabs(G[r][c]) > std::fabs(G[piv][c]))
            piv = r;
        for (int j = 0; j < na + N; ++j)
          std::swap(G[c][j], G[piv][j]);
        const double inv = 1.0 / G[c][c];
        for (int j = 0; j < na + N; ++j)
          G[c][j] *= inv;
        for (int r = 0; r < na; ++r)
        {
          if (r == c)
            continue;
          const double f = G[r][c];
          for (int j = 0; j < na + N; ++j)
            G[r][j] -= f * G[c][j];
        }
      }
      for (int a = 0; a < na; ++a)
        for (int i = 0; i < N; ++i)
          this->P[mask][a][i] = G[a][na + i];
    }
  }
};

template <int N>
const ActiveSetTables<N>& Tables()
{
  static const ActiveSetTables<N> tables;
  return tables;
}

// Solve (H + lambda I) y = b for a small SPD matrix by Cholesky; false if not SPD.
template <int M>
bool CholeskySolve(const double H[3][3], double lambda, const double* b, double* y)
{
  double Lm[3][3] = {};
  for (int i = 0; i < M; ++i)
  {
    for (int j = 0; j <= i; ++j)
    {
      double s = H[i][j] + (i == j ? lambda : 0.0);
      for (int k = 0; k < j; ++k)
        s -= Lm[i][k] * Lm[j][k];
      if (i == j)
      {
        if (!(s > 0.0))
          return false;
        Lm[i][i] = std::sqrt(s);
      }
      else
      {
        Lm[i][j] = s / Lm[j][j];
      }
    }
  }
  double z[3];
  for (int i = 0; i < M; ++i)
  {
    double s = b[i];
    for (int k = 0; k < i; ++k)
      s -= Lm[i][k] * z[k];
    z[i] = s / Lm[i][i];
  }
  for (int i = M - 1; i >= 0; --i)
  {
    double s = z[i];
    for (int k = i + 1; k < M; ++k)
      s -= Lm[k][i] * y[k];
    y[i] = s / Lm[i][i];
  }
  return true;
}

// Levenberg-Marquardt damping until H + lambda I is positive definite (H itself, lambda
// = 0, was tried by SolveReduced).
bool SolveReducedDamped(int m, const double H[3][3], const double* b, double* y)
{
  double tr = 0.0;
  for (int i = 0; i < m; ++i)
    tr += std::fabs(H[i][i]);
  double lambda = 1e-10 * tr + 1e-300;
  for (int attempt = 1; attempt < 40; ++attempt)
  {
    bool ok = false;
    switch (m)
    {
      case 1:
        ok = CholeskySolve<1>(H, lambda, b, y);
        break;
      case 2:
        ok = CholeskySolve<2>(H, lambda, b, y);
        break;
      default:
        ok = CholeskySolve<3>(H, lambda, b, y);
        break;
    }
    if (ok)
      return true;
    lambda = lambda == 0.0 ? 1e-10 * tr + 1e-300 : lambda * 10.0;
  }
  return false;
}

inline bool SolveReduced(int m, const double H[3][3], const double* b, double* y)
{
  // the common case first: H positive definite, no damping (inlined)
  switch (m)
  {
    case 1:
      if (CholeskySolve<1>(H, 0.0, b, y))
        return true;
      break;
    case 2:
      if (CholeskySolve<2>(H, 0.0, b, y))
        return true;
      break;
    default:
      if (CholeskySolve<3>(H, 0.0, b, y))
        return true;
      break;
  }
  return SolveReducedDamped(m, H, b, y);
}

// The active-set solve, one function on purpose (~260 lines): its steps (start, Newton
// step on the free directions, ratio test against the inactive constraints, release of
// constraints with a wrong-signed multiplier, convergence) are the branches of one loop
// that carries xi, the active set, g and H between them; as separate functions they
// would pass that state through memory in the innermost loop of the embedding (every
// outside vertex runs it), and the loop's control flow would be spread over them.
template <int N>
void Solve(const QuadraticMap& m, const double v[3], const double* start, ClosestPointResult& res,
  int maxIterations)
{
  constexpr int NC = N + 1;
  const ActiveSetTables<N>& T = Tables<N>();
  double xi[N];
  double sum = 0.0;
  for (int i = 0; i < N; ++i)
  {
    xi[i] = start ? start[i] : 1.0 / (N + 1);
    if (!(xi[i] > 0.0)) // also catches NaN
      xi[i] = 0.0;
    sum += xi[i];
  }
  if (sum > 1.0)
    for (int i = 0; i < N; ++i)
      xi[i] /= sum;
  int W = 0;
  for (int k = 0; k < NC; ++k)
    if (Slack<N>(k, xi) <= 0.0)
      W |= 1 << k;
  if (!T.Valid[W])
    W = 0;

  double x[3], J[N][3], r[3];
  Eval<N>(m, xi, x, J);
  for (int d = 0; d < 3; ++d)
    r[d] = x[d] - v[d];
  double f = 0.5 * Dot(r, r);
  bool converged = false;
  int drops = 0;
  int justDropped = -1;
  bool stalled = false; // the last step did not decrease f: stationary at round-off level
  int it = 0;
  for (; it < maxIterations; ++it)
  {
    double g[N], H[N][N];
    for (int i = 0; i < N; ++i)
    {
      g[i] = Dot(J[i], r);
      for (int j = 0; j <= i; ++j)
      {
        H[i][j] = H[j][i] = Dot(J[i], J[j]) + Dot(r, m.Q[i][j]);
      }
    }
    const int mf = T.M[W];
    double p[N] = {};
    if (mf > 0)
    {
      double gr[3], Hr[3][3], y[3];
      for (int a = 0; a < mf; ++a)
      {
        gr[a] = 0.0;
        for (int i = 0; i < N; ++i)
          gr[a] -= T.Z[W][a][i] * g[i];
      }
      for (int a = 0; a < mf; ++a)
        for (int b = 0; b < mf; ++b)
        {
          double s = 0.0;
          for (int i = 0; i < N; ++i)
            for (int j = 0; j < N; ++j)
              s += T.Z[W][a][i] * H[i][j] * T.Z[W][b][j];
          Hr[a][b] = s;
        }
      if (!SolveReduced(mf, Hr, gr, y))
      {
        for (int a = 0; a < mf; ++a)
          y[a] = gr[a];
      }
      for (int i = 0; i < N; ++i)
        for (int a = 0; a < mf; ++a)
          p[i] += T.Z[W][a][i] * y[a];
      double gp = 0.0;
      for (int i = 0; i < N; ++i)
        gp += g[i] * p[i];
      if (gp > 0.0 || (justDropped >= 0 && NormalDot<N>(justDropped, p) < 0.0))
      {
        // projected steepest descent with the Cauchy step: it leaves a constraint whose
        // multiplier was negative towards the inside
        double gg = 0.0, gHg = 0.0;
        for (int a = 0; a < mf; ++a)
        {
          gg += gr[a] * gr[a];
          for (int b = 0; b < mf; ++b)
            gHg += gr[a] * Hr[a][b] * gr[b];
        }
        const double t = gHg > 0.0 ? gg / gHg : 1.0;
        for (int i = 0; i < N; ++i)
        {
          p[i] = 0.0;
          for (int a = 0; a < mf; ++a)
            p[i] += t * T.Z[W][a][i] * gr[a];
        }
      }
    }
    double pmax = 0.0;
    for (int i = 0; i < N; ++i)
      pmax = std::max(pmax, std::fabs(p[i]));

    // ratio test against the inactive constraints
    double amax = 1.0;
    int block = -1;
    for (int k = 0; k < NC; ++k)
    {
      if (W & (1 << k))
        continue;
      const double ap = NormalDot<N>(k, p);
      if (ap < 0.0)
      {
        const double a = std::max(0.0, Slack<N>(k, xi)) / -ap;
        if (a < amax)
        {
          amax = a;
          block = k;
        }
      }
    }

    if (pmax <= 1e-12 || (stalled && pmax <= 1e-6))
    {
      stalled = false;
      // stationary on the current face of the simplex: take the tiny step, check multipliers
      if (pmax > 0.0)
      {
        for (int i = 0; i < N; ++i)
          xi[i] += amax * p[i];
        if (block >= 0)
        {
          W |= 1 << block;
          if (block < N)
            xi[block] = 0.0;
        }
        Eval<N>(m, xi, x, J);
        for (int d = 0; d < 3; ++d)
          r[d] = x[d] - v[d];
        f = 0.5 * Dot(r, r);
        for (int i = 0; i < N; ++i)
          g[i] = Dot(J[i], r);
      }
      const int na = T.NA[W];
      int worst = -1;
      double gmax = 0.0;
      for (int i = 0; i < N; ++i)
        gmax = std::max(gmax, std::fabs(g[i]));
      double worstMu = -1e-10 * gmax;
      for (int a = 0; a < na; ++a)
      {
        double mu = 0.0;
        for (int i = 0; i < N; ++i)
          mu += T.P[W][a][i] * g[i];
        if (mu < worstMu)
        {
          worstMu = mu;
          worst = T.Which[W][a];
        }
      }
      if (worst < 0 || drops >= 2 * NC)
      {
        converged = true;
        ++it;
        break;
      }
      W &= ~(1 << worst);
      justDropped = worst;
      ++drops;
      continue;
    }

    justDropped = -1;
    double descent = 0.0;
    for (int i = 0; i < N; ++i)
      descent += g[i] * p[i];
    double alpha = amax;
    double xt[N], xnew[3], Jnew[N][3], rnew[3], fnew = f;
    bool accepted = false;
    for (int ls = 0; ls < 40; ++ls)
    {
      for (int i = 0; i < N; ++i)
        xt[i] = xi[i] + alpha * p[i];
      if (alpha == amax && block >= 0)
      {
        if (block < N)
          xt[block] = 0.0;
      }
      for (int i = 0; i < N; ++i)
        if (xt[i] < 0.0)
          xt[i] = 0.0;
      Eval<N>(m, xt, xnew, Jnew);
      for (int d = 0; d < 3; ++d)
        rnew[d] = xnew[d] - v[d];
      fnew = 0.5 * Dot(rnew, rnew);
      // Armijo, or a full step that does not increase f beyond round-off (near the
      // solution the decrease is below the resolution of f)
      if (fnew <= f + 1e-4 * alpha * descent || (ls == 0 && fnew <= f * (1.0 + 1e-13)))
      {
        accepted = true;
        break;
      }
      alpha *= 0.5;
    }
    if (!accepted)
    {
      // no decrease possible at round-off level: the current point is a minimum
      converged = fnew >= f - 1e-15 * f;
      ++it;
      break;
    }
    if (alpha == amax && block >= 0)
      W |= 1 << block;
    for (int i = 0; i < N; ++i)
      xi[i] = xt[i];
    // keep sum <= 1 exactly
    double s = 0.0;
    for (int i = 0; i < N; ++i)
      s += xi[i];
    if (s > 1.0)
      for (int i = 0; i < N; ++i)
        xi[i] /= s;
    for (int d = 0; d < 3; ++d)
    {
      x[d] = xnew[d];
      r[d] = rnew[d];
      for (int i = 0; i < N; ++i)
        J[i][d] = Jnew[i][d];
    }
    stalled = !(fnew < f * (1.0 - 1e-14));
    f = fnew;
  }
  // exact feasibility: no negative coordinate, sum <= 1
  {
    double s = 0.0;
    for (int i = 0; i < N; ++i)
    {
      xi[i] = std::max(0.0, xi[i]);
      s += xi[i];
    }
    if (s > 1.0)
    {
      double rest = 1.0;
      for (int i = 0; i < N - 1; ++i)
      {
        xi[i] = std::min(xi[i] / s, rest);
        rest -= xi[i];
      }
      xi[N - 1] = std::max(0.0, rest);
    }
  }
  // active bits as found at the solution (exact bound activity)
  int active = 0;
  for (int k = 0; k < NC; ++k)
  {
    if (Slack<N>(k, xi) <= 1e-13)
      active |= 1 << k;
  }
  for (int i = 0; i < 3; ++i)
    res.Param[i] = i < N ? xi[i] : 0.0;
  for (int d = 0; d < 3; ++d)
    res.Point[d] = x[d];
  res.Distance2 = 2.0 * f;
  res.Active = active;
  res.Iterations = it;
  res.Converged = converged;
}

} // namespace

namespace
{
// A converged answer of the patch fast paths: parameters xi, point x, squared distance f.
void SetPatchResult(const double xi[2], const double x[3], double f, int active, int iterations,
  ClosestPointResult& res)
{
  res.Param[0] = xi[0];
  res.Param[1] = xi[1];
  res.Param[2] = 0.0;
  for (int d = 0; d < 3; ++d)
    res.Point[d] = x[d];
  res.Distance2 = f;
  res.Active = active;
  res.Iterations = iterations;
  res.Converged = true;
}

// Where plain Newton leaves the triangle: the constraint (0 u = 0, 1 v = 0, 2 u + v = 1)
// the step from xi to xi + p crosses first, and the edge parameter t of the crossing
// (EdgeNewton2's parametrisation). -1 when the crossing is not clear cut.
int Crossing(const double xi[2], const double p[2], double& t)
{
  double amin = 2.0;
  int k = -1;
  const double slack[3] = { xi[0], xi[1], 1.0 - xi[0] - xi[1] };
  const double rate[3] = { p[0], p[1], -p[0] - p[1] };
  for (int c = 0; c < 3; ++c)
    if (rate[c] < 0.0)
    {
      const double a = slack[c] / -rate[c];
      if (a < amin)
      {
        amin = a;
        k = c;
      }
    }
  if (k < 0 || !(amin >= 0.0 && amin <= 1.0))
    return -1;
  const double y[2] = { xi[0] + amin * p[0], xi[1] + amin * p[1] };
  t = k == 1 ? y[0] : y[1];
  return t > 0.0 && t < 1.0 ? k : -1;
}

// Fast path for a patch: plain Newton from an interior start. Accepted only when every
// iterate stays strictly inside, the Hessian stays positive definite, the step becomes
// negligible and f did not grow: then the result is an interior local minimum (KKT with
// no active constraint). Otherwise the caller runs the active-set solver; when a step
// left the triangle, `edge` and `t` say where (Crossing), else edge = -1.
bool InteriorNewton2(const QuadraticMap& m, const double v[3], const double* start,
  ClosestPointResult& res, int& edge, double& t)
{
  edge = -1;
  double xi[2] = { start[0], start[1] };
  if (!(xi[0] > 0.0 && xi[1] > 0.0 && xi[0] + xi[1] < 1.0))
    return false;
  double x[3], J[2][3], r[3];
  double f0 = -1.0;
  for (int it = 0; it < 8; ++it)
  {
    Eval<2>(m, xi, x, J);
    for (int d = 0; d < 3; ++d)
      r[d] = x[d] - v[d];
    if (f0 < 0.0)
      f0 = Dot(r, r);
    const double g0 = Dot(J[0], r), g1 = Dot(J[1], r);
    const double h00 = Dot(J[0], J[0]) + Dot(r, m.Q[0][0]);
    const double h01 = Dot(J[0], J[1]) + Dot(r, m.Q[0][1]);
    const double h11 = Dot(J[1], J[1]) + Dot(r, m.Q[1][1]);
    const double det = h00 * h11 - h01 * h01;
    if (!(h00 > 0.0) || !(det > 1e-14 * h00 * h11))
      return false;
    const double p[2] = { -(h11 * g0 - h01 * g1) / det, -(h00 * g1 - h01 * g0) / det };
    if (!(xi[0] + p[0] > 0.0 && xi[1] + p[1] > 0.0 && xi[0] + p[0] + xi[1] + p[1] < 1.0))
    {
      edge = Crossing(xi, p, t);
      return false;
    }
    xi[0] += p[0];
    xi[1] += p[1];
    // quadratic convergence: after a step below 1e-6 the new iterate is within ~1e-12 of
    // the minimum (parametric; the distance is then off by ~1e-24 of the patch's size
    // squared), so no further step is taken
    if (std::fabs(p[0]) + std::fabs(p[1]) <= 1e-6)
    {
      Eval<2>(m, xi, x, J);
      for (int d = 0; d < 3; ++d)
        r[d] = x[d] - v[d];
      const double f = Dot(r, r);
      if (f > f0)
        return false;
      SetPatchResult(xi, x, f, 0, it + 1, res);
      return true;
    }
  }
  return false;
}

// Fast path on one edge of a patch (constraint k: 0 u = 0, xi = (0, t); 1 v = 0,
// xi = (t, 0); 2 u + v = 1, xi = (1 - t, t)): plain Newton on t from t0. Accepted only
// when every iterate stays strictly inside the edge, the second derivative stays
// positive, the step becomes negligible, f did not grow, and the multiplier of the
// constraint is not negative (as in the active-set solver: >= -1e-10 of the gradient):
// then the result is a KKT point with that one constraint active. Otherwise the caller
// runs the active-set solver.
bool EdgeNewton2(
  const QuadraticMap& m, const double v[3], int k, double t0, ClosestPointResult& res)
{
  static const double Dir[3][2] = { { 0, 1 }, { 1, 0 }, { -1, 1 } };
  const double* dir = Dir[k];
  // d2x/dt2 = sum_ij dir_i dir_j Q_ij (constant)
  double q[3];
  for (int d = 0; d < 3; ++d)
    q[d] = dir[0] * dir[0] * m.Q[0][0][d] + 2.0 * dir[0] * dir[1] * m.Q[0][1][d] +
      dir[1] * dir[1] * m.Q[1][1][d];
  auto point = [k](double t, double xi[2]) {
    xi[0] = k == 0 ? 0.0 : (k == 1 ? t : 1.0 - t);
    xi[1] = k == 1 ? 0.0 : t;
  };
  double t = t0, xi[2], x[3], J[2][3], r[3], f0 = -1.0;
  for (int it = 0; it < 8; ++it)
  {
    point(t, xi);
    Eval<2>(m, xi, x, J);
    for (int d = 0; d < 3; ++d)
      r[d] = x[d] - v[d];
    if (f0 < 0.0)
      f0 = Dot(r, r);
    double xt[3];
    for (int d = 0; d < 3; ++d)
      xt[d] = dir[0] * J[0][d] + dir[1] * J[1][d];
    const double g = Dot(xt, r);
    const double h = Dot(xt, xt) + Dot(r, q);
    if (!(h > 0.0))
      return false;
    const double step = -g / h;
    t += step;
    if (!(t > 0.0 && t < 1.0))
      return false;
    if (std::fabs(step) <= 1e-6)
    {
      point(t, xi);
      Eval<2>(m, xi, x, J);
      for (int d = 0; d < 3; ++d)
        r[d] = x[d] - v[d];
      const double f = Dot(r, r);
      if (f > f0)
        return false;
      // multiplier of the active constraint (gradient = mu * its normal + a tangential
      // part that vanishes at the solution)
      const double gu = Dot(J[0], r), gv = Dot(J[1], r);
      const double mu = k == 0 ? gu : (k == 1 ? gv : -0.5 * (gu + gv));
      if (mu < -1e-10 * std::max(std::fabs(gu), std::fabs(gv)))
        return false;
      int active = 0;
      const double slack[3] = { xi[0], xi[1], 1.0 - xi[0] - xi[1] };
      for (int c = 0; c < 3; ++c)
        if (c == k || slack[c] <= 1e-13)
          active |= 1 << c;
      SetPatchResult(xi, x, f, active, it + 1, res);
      return true;
    }
  }
  return false;
}
} // namespace

void ClosestPointOnMap(const QuadraticMap& m, const double v[3], const double* start,
  ClosestPointResult& res, int maxIterations)
{
  if (m.Dim == 2)
  {
    if (start)
    {
      // interior Newton; where it leaves the triangle, or from a start on one edge,
      // Newton along that edge; the active-set solver for the rest
      int edge = -1;
      double t = 0.0;
      if (InteriorNewton2(m, v, start, res, edge, t))
        return;
      if (edge < 0)
      {
        const double slack[3] = { start[0], start[1], 1.0 - start[0] - start[1] };
        const int zero = (slack[0] == 0.0) + (slack[1] == 0.0) + (slack[2] == 0.0);
        if (zero == 1 && slack[0] >= 0.0 && slack[1] >= 0.0 && slack[2] >= 0.0)
        {
          edge = slack[0] == 0.0 ? 0 : (slack[1] == 0.0 ? 1 : 2);
          t = edge == 1 ? start[0] : start[1];
        }
      }
      if (edge >= 0 && EdgeNewton2(m, v, edge, t, res))
        return;
    }
    Solve<2>(m, v, start, res, maxIterations);
  }
  else
    Solve<3>(m, v, start, res, maxIterations);
}

} // namespace hoembed
