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
  int M[1 << NC];             // number of free directions
  double Z[1 << NC][N][N];    // Z[mask][col][component]
  int NA[1 << NC];            // number of active constraints
  int Which[1 << NC][NC];     // active constraint indices
  double P[1 << NC][NC][N];   // multipliers: mu_a = sum_i P[a][i] g_i
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
      auto orth = [&](double w[N], double (*B)[N], int nb) {
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
void Solve(const QuadraticMap& m, const double v[3], const double* start,
  ClosestPointResult& res, int maxIterations)
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

void MakeTriangleMap(const double* x, int n, QuadraticMap& m)
{
  // Monomial coefficients of x(u, v) = sum_a N_a(u, v) x_a, read off the expanded shape
  // functions (VTK order: corners 0, 1, 2; mid-edge nodes 3 (01), 4 (12), 5 (20)):
  //   tri6: L_u = 4 x3 - 3 x0 - x1, L_v = 4 x5 - 3 x0 - x2, Q_uu = 4 (x0 + x1) - 8 x3,
  //         Q_vv = 4 (x0 + x2) - 8 x5, Q_uv = 4 (x0 - x3 + x4 - x5);
  //   tri3: L_u = x1 - x0, L_v = x2 - x0, Q = 0.
  m = QuadraticMap();
  m.Dim = 2;
  const double* x0 = x;
  const double* x1 = x + 3;
  const double* x2 = x + 6;
  for (int d = 0; d < 3; ++d)
  {
    m.C[d] = x0[d];
    if (n == 6)
    {
      const double* x3 = x + 9;
      const double* x4 = x + 12;
      const double* x5 = x + 15;
      m.L[0][d] = 4.0 * x3[d] - 3.0 * x0[d] - x1[d];
      m.L[1][d] = 4.0 * x5[d] - 3.0 * x0[d] - x2[d];
      m.Q[0][0][d] = 4.0 * (x0[d] + x1[d]) - 8.0 * x3[d];
      m.Q[1][1][d] = 4.0 * (x0[d] + x2[d]) - 8.0 * x5[d];
      m.Q[0][1][d] = m.Q[1][0][d] = 4.0 * ((x0[d] - x3[d]) + (x4[d] - x5[d]));
    }
    else
    {
      m.L[0][d] = x1[d] - x0[d];
      m.L[1][d] = x2[d] - x0[d];
    }
  }
}


namespace
{
// b / F^2 for the Jacobians G at the 4 corners of a tet over which J is affine: b the
// smallest Bernstein coefficient of det J, F^2 the largest squared Frobenius norm (|J|_F^2
// is convex, so it peaks at a corner). Every singular value of J there is >= 2 b / F^2:
// det = s1 s2 s3 and s1 s2 <= (s1^2 + s2^2) / 2 <= F^2 / 2. 0 when b is not clear of
// round-off (1e-6 of the largest coefficient).
double SingularValueBound(const double G[4][3][3])
{
  double F2 = 0.0;
  for (int k = 0; k < 4; ++k)
  {
    double f2 = 0.0;
    for (int i = 0; i < 3; ++i)
      f2 += Dot(G[k][i], G[k][i]);
    F2 = std::max(F2, f2);
  }
  double hi = 0.0;
  const double b = DetBernsteinMin(G, &hi);
  if (!(b > 1e-6 * hi) || !(F2 > 0.0))
    return 0.0;
  return 2.0 * b / F2;
}

// Jacobians of the map at the corners centre + scale (e_k - centre) of the reference tet
// T scaled about its centroid, or of (T + eta) / 2 when eta is given.
void CornerJacobians(const QuadraticMap& m, const double* eta, double scale, double G[4][3][3])
{
  // J is affine in xi, so at the corner a + s (e_k - a) (anchor a: the centroid, or eta
  // with s = 1/2) it is (1 - s) J(a) + s J(e_k), where J(e_0) = L and J(e_j) = L + Q_j
  static const double Centre[3] = { 0.25, 0.25, 0.25 };
  const double* a = eta ? eta : Centre;
  const double s = eta ? 0.5 : scale;
  double A[3][3];
  for (int i = 0; i < 3; ++i)
    for (int d = 0; d < 3; ++d)
      A[i][d] = m.L[i][d] + m.Q[i][0][d] * a[0] + m.Q[i][1][d] * a[1] + m.Q[i][2][d] * a[2];
  for (int i = 0; i < 3; ++i)
    for (int d = 0; d < 3; ++d)
    {
      const double anchor = (1.0 - s) * A[i][d];
      G[0][i][d] = anchor + s * m.L[i][d];
      for (int k = 1; k < 4; ++k)
        G[k][i][d] = anchor + s * (m.L[i][d] + m.Q[i][k - 1][d]);
    }
}

// dist(eta, T) from below: the largest violated face inequality (normals of the faces
// u = 0, v = 0, w = 0 and u + v + w = 1 have lengths 1, 1, 1, sqrt(3))
double DistanceToReferenceTet(const double eta[3])
{
  return std::max({ -eta[0], -eta[1], -eta[2], (eta[0] + eta[1] + eta[2] - 1.0) / std::sqrt(3.0) });
}
} // namespace

bool Tet10JacobianProvablyPositive(const QuadraticMap& m)
{
  // J is affine in xi: the corner Jacobians are J(0) = L and J(e_j) = L + Q_j
  double G[4][3][3], hi = 0.0;
  CornerJacobians(m, nullptr, 1.0, G);
  const double lo = DetBernsteinMin(G, &hi);
  return lo > 1e-12 * hi;
}

bool Tet10JacobianProvablyPositive(const double* x)
{
  QuadraticMap m;
  MakeTetMap(x, 10, m);
  return Tet10JacobianProvablyPositive(m);
}

double TetMapExclusionRate(const QuadraticMap& m)
{
  double G[4][3][3];
  CornerJacobians(m, nullptr, ExclusionRateScale, G);
  return SingularValueBound(G);
}

double TetMapExclusionRadius(const QuadraticMap& m, const double eta[3], double rate)
{
  const double dT = DistanceToReferenceTet(eta);
  if (!(dT > 0.0))
    return 0.0;
  // eta in the reference tet scaled by s about its centroid, s = 1 - 4 min lambda: then
  // S = (T + eta) / 2 lies in T scaled by (1 + s) / 2, where `rate` holds
  const double lmin = std::min({ eta[0], eta[1], eta[2], 1.0 - eta[0] - eta[1] - eta[2] });
  if (rate > 0.0 && 0.5 * (2.0 - 4.0 * lmin) <= ExclusionRateScale)
    return rate * dT / (1.0 + 1e-6);
  double G[4][3][3];
  CornerJacobians(m, eta, 0.0, G);
  return SingularValueBound(G) * dT / (1.0 + 1e-6);
}

bool TetMapExcludes(const QuadraticMap& m, const double eta[3], double reach)
{
  return TetMapExclusionRadius(m, eta) > reach;
}

void MakeTetMap(const double* x, int n, QuadraticMap& m)
{
  // Monomial coefficients of x(xi) = sum_a N_a(xi) x_a in xi = (lambda_1, lambda_2,
  // lambda_3), read off the expanded shape functions. Corner k = i + 1 of xi_i, M0[i] its
  // mid-edge node with corner 0, Mid[i][j] the mid-edge node of corners i + 1, j + 1
  // (VTK order: 4 (01), 5 (12), 6 (02), 7 (03), 8 (13), 9 (23)):
  //   tet10: L_i = 4 x_M0[i] - 3 x0 - x_k, Q_ii = 4 (x0 + x_k) - 8 x_M0[i],
  //          Q_ij = 4 (x0 - x_M0[i] - x_M0[j] + x_Mid[i][j]);
  //   tet4:  L_i = x_k - x0, Q = 0.
  static const int M0[3] = { 4, 6, 7 };
  static const int Mid[3][3] = { { -1, 5, 8 }, { 5, -1, 9 }, { 8, 9, -1 } };
  m = QuadraticMap();
  m.Dim = 3;
  const double* x0 = x;
  for (int d = 0; d < 3; ++d)
  {
    m.C[d] = x0[d];
    for (int i = 0; i < 3; ++i)
    {
      const double xk = x[3 * (i + 1) + d];
      if (n != 10)
      {
        m.L[i][d] = xk - x0[d];
        continue;
      }
      const double mi = x[3 * M0[i] + d];
      m.L[i][d] = 4.0 * mi - 3.0 * x0[d] - xk;
      m.Q[i][i][d] = 4.0 * (x0[d] + xk) - 8.0 * mi;
      for (int j = 0; j < i; ++j)
        m.Q[i][j][d] = m.Q[j][i][d] =
          4.0 * ((x0[d] - mi) + (x[3 * Mid[i][j] + d] - x[3 * M0[j] + d]));
    }
  }
}

void EvaluateMap(const QuadraticMap& m, const double* xi, double x[3], double (*J)[3])
{
  double Jl[3][3];
  if (m.Dim == 2)
    Eval<2>(m, xi, x, Jl);
  else
    Eval<3>(m, xi, x, Jl);
  if (J)
    for (int i = 0; i < m.Dim; ++i)
      for (int d = 0; d < 3; ++d)
        J[i][d] = Jl[i][d];
}

namespace
{
// A converged answer of the patch fast paths: parameters xi, point x, squared distance f.
void SetPatchResult(const double xi[2], const double x[3], double f, int active,
  int iterations, ClosestPointResult& res)
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
bool EdgeNewton2(const QuadraticMap& m, const double v[3], int k, double t0,
  ClosestPointResult& res)
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
