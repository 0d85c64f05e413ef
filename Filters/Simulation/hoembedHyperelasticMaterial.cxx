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
  Dual Fd[9], Pd[9];
  for (int kl = 0; kl < 9; ++kl)
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
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 9, 9>> es(T);
    const auto& lam = es.eigenvalues();
    if (lam.minCoeff() < 0.0)
    {
      const Eigen::Matrix<double, 9, 1> clamped = lam.cwiseMax(0.0);
      T = es.eigenvectors() * clamped.asDiagonal() * es.eigenvectors().transpose();
    }
  }
  Eigen::Map<Eigen::Matrix<double, 9, 9, Eigen::RowMajor>> out(A);
  out = T;
  return psi;
}
} // namespace hoembed
