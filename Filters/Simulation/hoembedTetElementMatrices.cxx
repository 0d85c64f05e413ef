#include "hoembedTetElementMatrices.h"

#include "hoembedShapeFunctions.h"

#include <Eigen/Dense>

#include <cmath>
#include <vector>

namespace hoembed
{
namespace
{
// Gauss-Legendre nodes/weights on [0, 1] (Newton on the Legendre polynomial).
void GaussLegendre01(int m, double* xi, double* wi)
{
  const double pi = 3.14159265358979323846;
  for (int k = 0; k < m; ++k)
  {
    double x = std::cos(pi * (k + 0.75) / (m + 0.5));
    double dp = 1.0;
    for (int it = 0; it < 100; ++it)
    {
      double p0 = 1.0, p1 = x;
      for (int j = 2; j <= m; ++j)
      {
        const double p2 = ((2.0 * j - 1.0) * x * p1 - (j - 1.0) * p0) / j;
        p0 = p1;
        p1 = p2;
      }
      if (m == 1)
      {
        p1 = x;
        p0 = 1.0;
      }
      dp = m * (x * p1 - p0) / (x * x - 1.0);
      const double dx = p1 / dp;
      x -= dx;
      if (std::abs(dx) < 1e-16)
      {
        break;
      }
    }
    xi[k] = 0.5 * (1.0 - x);
    wi[k] = 1.0 / ((1.0 - x * x) * dp * dp); // 2/((1-x^2)P'^2) scaled by 1/2
  }
}

void Shape(int n, const double pc[3], double* N)
{
  if (n == 10)
  {
    Tet10Shape(pc, N);
  }
  else
  {
    Tet4Shape(pc, N);
  }
}

void Derivs(int n, const double pc[3], double* dN)
{
  if (n == 10)
  {
    Tet10Derivs(pc, dN);
  }
  else
  {
    Tet4Derivs(pc, dN);
  }
}

struct Rule
{
  int count = 0;
  double pc[3 * 216];
  double w[216];
  explicit Rule(int m)
  {
    this->count = TetQuadrature(m, this->pc, this->w);
  }
};

const Rule& StiffnessRule()
{
  static const Rule rule(4); // see the header: 3^3 points are not enough on curved tet10
  return rule;
}

const Rule& MassRule()
{
  static const Rule rule(4);
  return rule;
}
} // namespace

void LameParameters(double young, double poisson, double& lambda, double& mu)
{
  lambda = young * poisson / ((1.0 + poisson) * (1.0 - 2.0 * poisson));
  mu = young / (2.0 * (1.0 + poisson));
}

int TetQuadrature(int m, double* pc, double* w)
{
  m = m < 1 ? 1 : (m > 6 ? 6 : m);
  double xi[6], wi[6];
  GaussLegendre01(m, xi, wi);
  int q = 0;
  for (int i = 0; i < m; ++i)
  {
    for (int j = 0; j < m; ++j)
    {
      for (int k = 0; k < m; ++k)
      {
        const double u = xi[i], v = xi[j], s = xi[k];
        pc[3 * q] = u;
        pc[3 * q + 1] = v * (1.0 - u);
        pc[3 * q + 2] = s * (1.0 - u) * (1.0 - v);
        w[q] = wi[i] * wi[j] * wi[k] * (1.0 - u) * (1.0 - u) * (1.0 - v);
        ++q;
      }
    }
  }
  return q;
}

double ShapeGradients(int n, const double* x, const double pc[3], double* gradN)
{
  double dN[30];
  Derivs(n, pc, dN);
  Eigen::Matrix3d J = Eigen::Matrix3d::Zero(); // J(i, j) = d x_i / d pc_j
  for (int a = 0; a < n; ++a)
  {
    for (int i = 0; i < 3; ++i)
    {
      for (int j = 0; j < 3; ++j)
      {
        J(i, j) += x[3 * a + i] * dN[j * n + a];
      }
    }
  }
  const double det = J.determinant();
  if (det == 0.0)
  {
    for (int k = 0; k < 3 * n; ++k)
    {
      gradN[k] = 0.0;
    }
    return 0.0;
  }
  const Eigen::Matrix3d Jinv = J.inverse();
  for (int a = 0; a < n; ++a)
  {
    // dN/dX_i = sum_j dN/dpc_j dpc_j/dX_i
    for (int i = 0; i < 3; ++i)
    {
      gradN[3 * a + i] = dN[a] * Jinv(0, i) + dN[n + a] * Jinv(1, i) + dN[2 * n + a] * Jinv(2, i);
    }
  }
  return det;
}

double ElementStiffness(int n, const double* x, double young, double poisson, double* K)
{
  double lambda, mu;
  LameParameters(young, poisson, lambda, mu);
  const int d = 3 * n;
  for (int k = 0; k < d * d; ++k)
  {
    K[k] = 0.0;
  }
  const Rule& rule = StiffnessRule();
  double volume = 0.0;
  double g[30];
  for (int q = 0; q < rule.count; ++q)
  {
    const double det = ShapeGradients(n, x, rule.pc + 3 * q, g);
    if (!(det > 0.0))
    {
      return det;
    }
    const double w = rule.w[q] * det;
    volume += w;
    for (int a = 0; a < n; ++a)
    {
      const double* ga = g + 3 * a;
      for (int b = 0; b < n; ++b)
      {
        const double* gb = g + 3 * b;
        const double dot = ga[0] * gb[0] + ga[1] * gb[1] + ga[2] * gb[2];
        for (int i = 0; i < 3; ++i)
        {
          double* row = K + (3 * a + i) * d + 3 * b;
          for (int j = 0; j < 3; ++j)
          {
            row[j] += w * (lambda * ga[i] * gb[j] + mu * ga[j] * gb[i] + (i == j ? mu * dot : 0.0));
          }
        }
      }
    }
  }
  return volume;
}

void ElementConsistentMass(int n, const double* x, double density, double* M)
{
  const int d = 3 * n;
  for (int k = 0; k < d * d; ++k)
  {
    M[k] = 0.0;
  }
  const Rule& rule = MassRule();
  double N[10], g[30];
  for (int q = 0; q < rule.count; ++q)
  {
    const double det = ShapeGradients(n, x, rule.pc + 3 * q, g);
    Shape(n, rule.pc + 3 * q, N);
    const double w = rule.w[q] * det * density;
    for (int a = 0; a < n; ++a)
    {
      for (int b = 0; b < n; ++b)
      {
        const double v = w * N[a] * N[b];
        for (int i = 0; i < 3; ++i)
        {
          M[(3 * a + i) * d + 3 * b + i] += v;
        }
      }
    }
  }
}

void ElementLumpedMassHRZ(int n, const double* x, double density, double* m)
{
  const Rule& rule = MassRule();
  double N[10], g[30];
  double total = 0.0, diag = 0.0;
  for (int a = 0; a < n; ++a)
  {
    m[a] = 0.0;
  }
  for (int q = 0; q < rule.count; ++q)
  {
    const double det = ShapeGradients(n, x, rule.pc + 3 * q, g);
    Shape(n, rule.pc + 3 * q, N);
    const double w = rule.w[q] * det * density;
    total += w;
    for (int a = 0; a < n; ++a)
    {
      m[a] += w * N[a] * N[a];
    }
  }
  for (int a = 0; a < n; ++a)
  {
    diag += m[a];
  }
  const double scale = diag > 0.0 ? total / diag : 0.0;
  for (int a = 0; a < n; ++a)
  {
    m[a] *= scale;
  }
}

void ElementBodyForce(int n, const double* x, double density, const double gvec[3], double* f)
{
  const Rule& rule = MassRule();
  double N[10], g[30];
  for (int k = 0; k < 3 * n; ++k)
  {
    f[k] = 0.0;
  }
  for (int q = 0; q < rule.count; ++q)
  {
    const double det = ShapeGradients(n, x, rule.pc + 3 * q, g);
    Shape(n, rule.pc + 3 * q, N);
    const double w = rule.w[q] * det * density;
    for (int a = 0; a < n; ++a)
    {
      for (int i = 0; i < 3; ++i)
      {
        f[3 * a + i] += w * N[a] * gvec[i];
      }
    }
  }
}

namespace
{
void PolarRotationSVD(const double F[9], double R[9])
{
  const Eigen::Matrix3d Fm = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(F);
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(Fm, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d U = svd.matrixU();
  const Eigen::Matrix3d V = svd.matrixV();
  if ((U * V.transpose()).determinant() < 0.0)
  {
    U.col(2) = -U.col(2); // singular values are sorted: column 2 is the smallest
  }
  const Eigen::Matrix3d Rm = U * V.transpose();
  Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> out(R);
  out = Rm;
}
} // namespace

// Scaled Newton iteration for the orthogonal polar factor (Higham 1986):
// X <- (g X + X^-T / g) / 2 with g = |det X|^(-1/3); quadratic convergence, ~4-7
// iterations from a deformation gradient, about 10x cheaper than a 3x3 JacobiSVD. Used
// when F is safely non-inverted (det F > 1e-6 |F|^3); otherwise (inverted, nearly
// degenerate) and if it does not converge, the SVD with the sign fix.
void PolarRotation(const double F[9], double R[9])
{
  double X[9];
  double n2 = 0.0;
  for (int k = 0; k < 9; ++k)
  {
    X[k] = F[k];
    n2 += F[k] * F[k];
  }
  const double nF = std::sqrt(n2);
  const double det0 = F[0] * (F[4] * F[8] - F[5] * F[7]) - F[1] * (F[3] * F[8] - F[5] * F[6]) +
    F[2] * (F[3] * F[7] - F[4] * F[6]);
  if (!(nF > 0.0) || !std::isfinite(nF) || !(det0 > 1e-6 * nF * nF * nF))
  {
    PolarRotationSVD(F, R);
    return;
  }
  for (int it = 0; it < 30; ++it)
  {
    double C[9]; // cofactor matrix: X^-T = C / det X
    C[0] = X[4] * X[8] - X[5] * X[7];
    C[1] = X[5] * X[6] - X[3] * X[8];
    C[2] = X[3] * X[7] - X[4] * X[6];
    C[3] = X[2] * X[7] - X[1] * X[8];
    C[4] = X[0] * X[8] - X[2] * X[6];
    C[5] = X[1] * X[6] - X[0] * X[7];
    C[6] = X[1] * X[5] - X[2] * X[4];
    C[7] = X[2] * X[3] - X[0] * X[5];
    C[8] = X[0] * X[4] - X[1] * X[3];
    const double det = X[0] * C[0] + X[1] * C[1] + X[2] * C[2];
    if (!(det > 0.0))
    {
      break;
    }
    const double g = it < 6 ? 1.0 / std::cbrt(det) : 1.0; // no scaling near convergence
    const double a = 0.5 * g, b = 0.5 / (g * det);
    double change = 0.0, size = 0.0;
    for (int k = 0; k < 9; ++k)
    {
      const double y = a * X[k] + b * C[k];
      change += (y - X[k]) * (y - X[k]);
      size += y * y;
      X[k] = y;
    }
    if (change <= 1e-26 * size) // |dX| <= 1e-13 |X|: the next step is below round-off
    {
      for (int k = 0; k < 9; ++k)
      {
        R[k] = X[k];
      }
      return;
    }
  }
  PolarRotationSVD(F, R);
}

double VonMisesStress(
  int n, const double* x, const double* u, const double pc[3], double young, double poisson)
{
  double lambda, mu;
  LameParameters(young, poisson, lambda, mu);
  double g[30];
  ShapeGradients(n, x, pc, g);
  double H[3][3] = { { 0, 0, 0 }, { 0, 0, 0 }, { 0, 0, 0 } };
  for (int a = 0; a < n; ++a)
  {
    for (int i = 0; i < 3; ++i)
    {
      for (int j = 0; j < 3; ++j)
      {
        H[i][j] += u[3 * a + i] * g[3 * a + j];
      }
    }
  }
  double e[3][3];
  for (int i = 0; i < 3; ++i)
  {
    for (int j = 0; j < 3; ++j)
    {
      e[i][j] = 0.5 * (H[i][j] + H[j][i]);
    }
  }
  const double tr = e[0][0] + e[1][1] + e[2][2];
  double s[3][3];
  for (int i = 0; i < 3; ++i)
  {
    for (int j = 0; j < 3; ++j)
    {
      s[i][j] = 2.0 * mu * e[i][j] + (i == j ? lambda * tr : 0.0);
    }
  }
  const double a = s[0][0] - s[1][1], b = s[1][1] - s[2][2], c = s[2][2] - s[0][0];
  const double v = 0.5 * (a * a + b * b + c * c) +
    3.0 * (s[0][1] * s[0][1] + s[1][2] * s[1][2] + s[0][2] * s[0][2]);
  return std::sqrt(v > 0.0 ? v : 0.0);
}
} // namespace hoembed
