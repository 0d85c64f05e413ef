#include "hoembedHyperelasticMaterial.h"

#include "hoembedTetElementMatrices.h"

#include <Eigen/Dense>

#include <cmath>
#include <limits>

namespace hoembed
{
namespace
{
// A forward-mode dual number (value, derivative along one direction): the tangent is the
// derivative of the same stress code that gives P, so the two can never disagree.
struct Dual
{
  double v = 0.0, d = 0.0;
  Dual() = default;
  Dual(double value, double derivative = 0.0) : v(value), d(derivative) {}
};
inline Dual operator+(Dual a, Dual b)
{
  return { a.v + b.v, a.d + b.d };
}
inline Dual operator-(Dual a, Dual b)
{
  return { a.v - b.v, a.d - b.d };
}
inline Dual operator-(Dual a)
{
  return { -a.v, -a.d };
}
inline Dual operator*(Dual a, Dual b)
{
  return { a.v * b.v, a.d * b.v + a.v * b.d };
}
inline Dual operator/(Dual a, Dual b)
{
  return { a.v / b.v, (a.d * b.v - a.v * b.d) / (b.v * b.v) };
}
inline Dual log(Dual a)
{
  return { std::log(a.v), a.d / a.v };
}
inline Dual pow(Dual a, double p)
{
  const double f = std::pow(a.v, p);
  return { f, p * f / a.v * a.d };
}
inline double Value(double a)
{
  return a;
}
inline double Value(Dual a)
{
  return a.v;
}
using std::log;
using std::pow;

// cof(F) = det(F) F^-T (row-major) and J = det F
template <typename T>
T Cofactor(const T* F, T* c)
{
  c[0] = F[4] * F[8] - F[5] * F[7];
  c[1] = F[5] * F[6] - F[3] * F[8];
  c[2] = F[3] * F[7] - F[4] * F[6];
  c[3] = F[2] * F[7] - F[1] * F[8];
  c[4] = F[0] * F[8] - F[2] * F[6];
  c[5] = F[1] * F[6] - F[0] * F[7];
  c[6] = F[1] * F[5] - F[2] * F[4];
  c[7] = F[2] * F[3] - F[0] * F[5];
  c[8] = F[0] * F[4] - F[1] * F[3];
  return F[0] * c[0] + F[1] * c[1] + F[2] * c[2];
}

// C = F^T F
template <typename T>
void RightCauchyGreen(const T* F, T* C)
{
  for (int i = 0; i < 3; ++i)
  {
    for (int j = 0; j < 3; ++j)
    {
      C[3 * i + j] = F[i] * F[j] + F[3 + i] * F[3 + j] + F[6 + i] * F[6 + j];
    }
  }
}

// P(F) of the law (P may be nullptr); returns Psi. One code for double and Dual.
template <typename T>
T StressT(const HyperelasticLaw& law, const T* F, T* P)
{
  const double inf = std::numeric_limits<double>::infinity();
  switch (law.Kind)
  {
    case Material::StVK:
    {
      T C[9], E[9];
      RightCauchyGreen(F, C);
      for (int k = 0; k < 9; ++k)
      {
        E[k] = 0.5 * (C[k] - ((k % 4 == 0) ? 1.0 : 0.0));
      }
      const T trE = E[0] + E[4] + E[8];
      T EE = 0.0;
      for (int k = 0; k < 9; ++k)
      {
        EE = EE + E[k] * E[k];
      }
      if (P)
      {
        T S[9];
        for (int k = 0; k < 9; ++k)
        {
          S[k] = 2.0 * law.Mu * E[k] + ((k % 4 == 0) ? law.Lambda * trE : T(0.0));
        }
        for (int i = 0; i < 3; ++i)
        {
          for (int j = 0; j < 3; ++j)
          {
            P[3 * i + j] = F[3 * i] * S[j] + F[3 * i + 1] * S[3 + j] + F[3 * i + 2] * S[6 + j];
          }
        }
      }
      return law.Mu * EE + 0.5 * law.Lambda * trE * trE;
    }
    case Material::NeoHookean:
    {
      T c[9];
      const T J = Cofactor(F, c);
      T Ic = 0.0;
      for (int k = 0; k < 9; ++k)
      {
        Ic = Ic + F[k] * F[k];
      }
      const T Ja = J - law.Alpha;
      if (P)
      {
        const T s = law.Mu * (1.0 - 1.0 / (Ic + 1.0));
        for (int k = 0; k < 9; ++k)
        {
          P[k] = s * F[k] + law.Lambda * Ja * c[k];
        }
      }
      // minus its value at rest (a constant: zero energy at rest, like the other laws)
      return 0.5 * law.Mu * (Ic - 3.0) + 0.5 * law.Lambda * Ja * Ja - 0.5 * law.Mu * log(Ic + 1.0) -
        law.Rest;
    }
    case Material::MooneyRivlin:
    {
      T c[9], C[9];
      const T J = Cofactor(F, c);
      if (!(Value(J) > 0.0))
      {
        if (P)
        {
          for (int k = 0; k < 9; ++k)
          {
            P[k] = 0.0;
          }
        }
        return T(inf);
      }
      RightCauchyGreen(F, C);
      T I1 = 0.0, CC = 0.0;
      for (int k = 0; k < 9; ++k)
      {
        I1 = I1 + F[k] * F[k];
        CC = CC + C[k] * C[k];
      }
      const T I2 = 0.5 * (I1 * I1 - CC);
      const T j23 = pow(J, -2.0 / 3.0), j43 = pow(J, -4.0 / 3.0);
      if (P)
      {
        for (int i = 0; i < 3; ++i)
        {
          for (int j = 0; j < 3; ++j)
          {
            const int k = 3 * i + j;
            const T FC = F[3 * i] * C[j] + F[3 * i + 1] * C[3 + j] + F[3 * i + 2] * C[6 + j];
            const T finvT = c[k] / J;
            P[k] = law.C10 * j23 * (2.0 * F[k] - (2.0 / 3.0) * I1 * finvT) +
              law.C01 * j43 * (2.0 * (I1 * F[k] - FC) - (4.0 / 3.0) * I2 * finvT) +
              law.Kappa * (J - 1.0) * c[k];
          }
        }
      }
      return law.C10 * (j23 * I1 - 3.0) + law.C01 * (j43 * I2 - 3.0) +
        0.5 * law.Kappa * (J - 1.0) * (J - 1.0);
    }
    case Material::Corotated:
      break;
  }
  return T(inf);
}
} // namespace

HyperelasticLaw HyperelasticLaw::Make(
  Material kind, double young, double poisson, double c10, double c01)
{
  HyperelasticLaw law;
  law.Kind = kind;
  double lambda = 0.0, mu = 0.0;
  LameParameters(young, poisson, lambda, mu);
  switch (kind)
  {
    case Material::NeoHookean:
      law.Mu = 4.0 / 3.0 * mu;
      law.Lambda = lambda + 5.0 / 6.0 * mu;
      law.Alpha = 1.0 + 3.0 * law.Mu / (4.0 * law.Lambda);
      law.Rest =
        0.5 * law.Lambda * (1.0 - law.Alpha) * (1.0 - law.Alpha) - 0.5 * law.Mu * std::log(4.0);
      break;
    case Material::MooneyRivlin:
      law.Kappa = young / (3.0 * (1.0 - 2.0 * poisson));
      law.C10 = (c10 == 0.0 && c01 == 0.0) ? 0.25 * mu : c10;
      law.C01 = (c10 == 0.0 && c01 == 0.0) ? 0.25 * mu : c01;
      break;
    default:
      law.Mu = mu;
      law.Lambda = lambda;
      break;
  }
  return law;
}

double HyperelasticLaw::Energy(const double F[9]) const
{
  return StressT<double>(*this, F, nullptr);
}

double HyperelasticLaw::Stress(const double F[9], double P[9]) const
{
  return StressT<double>(*this, F, P);
}

double HyperelasticLaw::Tangent(const double F[9], double P[9], double A[81], bool project) const
{
  const double psi = StressT<double>(*this, F, P);
  Eigen::Matrix<double, 9, 9, Eigen::RowMajor> T;
  if (Kind == Material::NeoHookean)
  {
    // closed form (the derivative of StressT's P, checked against central differences
    // in TestHyperelasticMaterial): dP/dF = s I + 2 mu' / (Ic + 1)^2 F (x) F + lambda' c (x) c
    // + lambda' (J - a) dc/dF, with s = mu' (1 - 1 / (Ic + 1)), c = cof F and
    // dc_ij / dF_kl = eps_ikn eps_jlq F_nq; 9 dual passes cost ~3x more
    double c[9];
    const double J = Cofactor(F, c);
    double Ic = 0.0;
    for (int k = 0; k < 9; ++k)
    {
      Ic += F[k] * F[k];
    }
    const double s = Mu * (1.0 - 1.0 / (Ic + 1.0));
    const double f2 = 2.0 * Mu / ((Ic + 1.0) * (Ic + 1.0));
    const double h = Lambda * (J - Alpha);
    for (int ij = 0; ij < 9; ++ij)
    {
      for (int kl = 0; kl < 9; ++kl)
      {
        T(ij, kl) = f2 * F[ij] * F[kl] + Lambda * c[ij] * c[kl] + (ij == kl ? s : 0.0);
      }
    }
    // eps_ikn eps_jlq = +-1 for i != k, j != l (n, q the third indices)
    for (int i = 0; i < 3; ++i)
    {
      for (int k = 0; k < 3; ++k)
      {
        if (i == k)
        {
          continue;
        }
        const int n = 3 - i - k;
        const double si = ((k - i + 3) % 3 == 1) ? 1.0 : -1.0; // eps_ikn
        for (int j = 0; j < 3; ++j)
        {
          for (int l = 0; l < 3; ++l)
          {
            if (j == l)
            {
              continue;
            }
            const int q = 3 - j - l;
            const double sj = ((l - j + 3) % 3 == 1) ? 1.0 : -1.0;
            T(3 * i + j, 3 * k + l) += h * si * sj * F[3 * n + q];
          }
        }
      }
    }
  }
  Dual Fd[9], Pd[9];
  for (int kl = 0; kl < 9 && Kind != Material::NeoHookean; ++kl)
  {
    for (int k = 0; k < 9; ++k)
    {
      Fd[k] = Dual(F[k], k == kl ? 1.0 : 0.0);
    }
    StressT<Dual>(*this, Fd, Pd);
    for (int ij = 0; ij < 9; ++ij)
    {
      T(ij, kl) = Pd[ij].d;
    }
  }
  // a Hessian: symmetric up to round-off, made exactly so (the eigen-solver and the
  // Cholesky factor read one triangle)
  T = (0.5 * (T + T.transpose())).eval();
  // Positive definite after a shift by 1e-10 of its largest diagonal entry (a 9x9
  // Cholesky, far cheaper than the eigensystem): kept, shifted (its rotation directions
  // are singular at rest and round-off makes them slightly negative). Else the
  // eigenvalue clamp.
  bool definite = false;
  if (project)
  {
    const double shift = 1e-10 * T.diagonal().cwiseAbs().maxCoeff();
    const Eigen::Matrix<double, 9, 9> Ts = T + shift * Eigen::Matrix<double, 9, 9>::Identity();
    definite = Eigen::LLT<Eigen::Matrix<double, 9, 9>>(Ts).info() == Eigen::Success;
    if (definite)
    {
      T = Ts;
    }
  }
  if (project && !definite)
  {
    // The eigenvalue clamp through the principal frame: every law here is isotropic, so
    // with F = U diag(s) V^T (U, V rotations; s_3 < 0 when inverted) the tangent is
    // K T^ K^T, K = the rotation dF^ -> U dF^ V^T of R^9, and T^, the tangent at diag(s),
    // decouples into the 3 x 3 block of the stretches (0, 4, 8) and three 2 x 2 blocks
    // of the pairs (1, 3), (2, 6), (5, 7). Clamping those blocks' eigenvalues is the 9 x
    // 9 clamp (TestHyperelasticMaterial compares the two) at a 3 x 3 SVD and small
    // eigenproblems, instead of a 9 x 9 eigensolver (~10x the whole tangent).
    const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> Fm(F);
    Eigen::JacobiSVD<Eigen::Matrix3d> svd(Fm, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d U = svd.matrixU(), V = svd.matrixV();
    Eigen::Vector3d sv = svd.singularValues();
    if (U.determinant() < 0.0)
    {
      U.col(2) *= -1.0;
      sv(2) *= -1.0;
    }
    if (V.determinant() < 0.0)
    {
      V.col(2) *= -1.0;
      sv(2) *= -1.0;
    }
    const double Fs[9] = { sv(0), 0, 0, 0, sv(1), 0, 0, 0, sv(2) };
    double Ps[9], As[81];
    Tangent(Fs, Ps, As, false);
    Eigen::Map<Eigen::Matrix<double, 9, 9, Eigen::RowMajor>> Th(As);
    Eigen::Matrix<double, 9, 9> Tp = Eigen::Matrix<double, 9, 9>::Zero();
    {
      const int id[3] = { 0, 4, 8 };
      Eigen::Matrix3d B;
      for (int a = 0; a < 3; ++a)
      {
        for (int b = 0; b < 3; ++b)
        {
          B(a, b) = 0.5 * (Th(id[a], id[b]) + Th(id[b], id[a]));
        }
      }
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(B);
      const Eigen::Matrix3d Bp = es.eigenvectors() * es.eigenvalues().cwiseMax(0.0).asDiagonal() *
        es.eigenvectors().transpose();
      for (int a = 0; a < 3; ++a)
      {
        for (int b = 0; b < 3; ++b)
        {
          Tp(id[a], id[b]) = Bp(a, b);
        }
      }
    }
    const int pairs[3][2] = { { 1, 3 }, { 2, 6 }, { 5, 7 } };
    for (const auto& pr : pairs)
    {
      const int i = pr[0], j = pr[1];
      // [[p, r], [r, q]]: eigenvalues m +- w, eigenvectors (c, s), (-s, c)
      const double p = Th(i, i), q = Th(j, j), r = 0.5 * (Th(i, j) + Th(j, i));
      const double m = 0.5 * (p + q), w = std::hypot(0.5 * (p - q), r);
      const double l1 = std::max(m + w, 0.0), l2 = std::max(m - w, 0.0);
      const double th = 0.5 * std::atan2(2.0 * r, p - q), c = std::cos(th), s = std::sin(th);
      Tp(i, i) = l1 * c * c + l2 * s * s;
      Tp(j, j) = l1 * s * s + l2 * c * c;
      Tp(i, j) = Tp(j, i) = (l1 - l2) * c * s;
    }
    Eigen::Matrix<double, 9, 9> K;
    for (int i = 0; i < 3; ++i)
    {
      for (int j = 0; j < 3; ++j)
      {
        for (int a = 0; a < 3; ++a)
        {
          for (int b = 0; b < 3; ++b)
          {
            K(3 * i + j, 3 * a + b) = U(i, a) * V(j, b);
          }
        }
      }
    }
    T = K * Tp * K.transpose();
  }
  Eigen::Map<Eigen::Matrix<double, 9, 9, Eigen::RowMajor>> out(A);
  out = T;
  return psi;
}
} // namespace hoembed
