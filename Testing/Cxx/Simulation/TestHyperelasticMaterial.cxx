// hoembed::HyperelasticLaw (StVK, stable Neo-Hookean, Mooney-Rivlin): the stress is the
// derivative of the energy and the tangent the derivative of the stress (central
// differences), no stress at rest, the small-strain tangent is the isotropic elasticity
// tensor of E and nu written out here (lambda d_ij d_kl + mu (d_ik d_jl + d_il d_jk): the
// documented conversions), the projected tangent is positive semi-definite and equal to
// the exact one where that is, and the stable Neo-Hookean stays finite through
// inversion while Mooney-Rivlin's energy is +infinity there.
#include "hoembedHyperelasticMaterial.h"
#include "hoembedTestUtilities.h"

#include <Eigen/Dense>

#include <cmath>
#include <limits>

namespace
{
using hoembed::HyperelasticLaw;
using hoembed::Material;

double MaxAbs(const double* a, int n)
{
  double m = 0.0;
  for (int k = 0; k < n; ++k)
  {
    m = std::max(m, std::abs(a[k]));
  }
  return m;
}

void CheckDerivatives(const HyperelasticLaw& law, const double F[9], const char* what)
{
  double P[9], A[81];
  law.Tangent(F, P, A, false);
  const double h = 1e-6;
  for (int kl = 0; kl < 9; ++kl)
  {
    double Fp[9], Fm[9], Pp[9], Pm[9];
    for (int k = 0; k < 9; ++k)
    {
      Fp[k] = Fm[k] = F[k];
    }
    Fp[kl] += h;
    Fm[kl] -= h;
    const double dpsi = (law.Stress(Fp, Pp) - law.Stress(Fm, Pm)) / (2 * h);
    HOEMBED_CHECK(std::abs(dpsi - P[kl]) <= 1e-6 * (1.0 + MaxAbs(P, 9)),
      "%s: dPsi/dF[%d] = %.12g, P = %.12g", what, kl, dpsi, P[kl]);
    for (int ij = 0; ij < 9; ++ij)
    {
      const double dP = (Pp[ij] - Pm[ij]) / (2 * h);
      HOEMBED_CHECK(std::abs(dP - A[9 * ij + kl]) <= 1e-6 * (1.0 + MaxAbs(A, 81)),
        "%s: dP[%d]/dF[%d] = %.12g, tangent %.12g", what, ij, kl, dP, A[9 * ij + kl]);
    }
  }
}
} // namespace

int main(int, char*[])
{
  const double E = 3.0e5, nu = 0.4;
  const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
  const Material kinds[3] = { Material::StVK, Material::NeoHookean, Material::MooneyRivlin };
  const char* names[3] = { "stvk", "neo-hookean", "mooney-rivlin" };
  // a large, rotated, sheared deformation with det F ~ 0.6
  const double F1[9] = { 0.9, 0.35, -0.2, -0.3, 0.8, 0.25, 0.15, -0.1, 0.85 };
  const double I[9] = { 1, 0, 0, 0, 1, 0, 0, 0, 1 };
  for (int m = 0; m < 3; ++m)
  {
    const HyperelasticLaw law = HyperelasticLaw::Make(kinds[m], E, nu, 0.0, 0.0);
    CheckDerivatives(law, F1, names[m]);
    double P[9], A[81];
    const double psi0 = law.Tangent(I, P, A, false);
    HOEMBED_CHECK(std::abs(psi0) <= 1e-9 * E && MaxAbs(P, 9) <= 1e-9 * E,
      "%s: energy %g, stress %g at rest", names[m], psi0, MaxAbs(P, 9));
    for (int i = 0; i < 3; ++i)
    {
      for (int j = 0; j < 3; ++j)
      {
        for (int k = 0; k < 3; ++k)
        {
          for (int l = 0; l < 3; ++l)
          {
            const double c =
              lambda * (i == j) * (k == l) + mu * ((i == k) * (j == l) + (i == l) * (j == k));
            const double a = A[9 * (3 * i + j) + 3 * k + l];
            HOEMBED_CHECK(std::abs(a - c) <= 1e-9 * E, "%s: C_%d%d%d%d = %.10g, expected %.10g",
              names[m], i, j, k, l, a, c);
          }
        }
      }
    }
    // projection: PSD; unchanged where the exact tangent is already PSD (at rest)
    double Ap[81];
    law.Tangent(I, P, Ap, true);
    HOEMBED_CHECK(
      (Eigen::Map<Eigen::Matrix<double, 81, 1>>(Ap) - Eigen::Map<Eigen::Matrix<double, 81, 1>>(A))
          .cwiseAbs()
          .maxCoeff() <= 1e-9 * E,
      "%s: the projection changed a positive definite tangent", names[m]);
    // the projection (through the principal frame) is the eigenvalue clamp of the 9 x 9
    // tangent, computed here by brute force: a compressed, a sheared and (Neo-Hookean,
    // StVK) an inverted point
    const double Fs[3][9] = { { 0.3, 0.05, 0.0, 0.02, 1.1, 0.1, 0.0, -0.1, 1.2 },
      { 0.9, 0.35, -0.2, -0.3, 0.8, 0.25, 0.15, -0.1, 0.85 },
      { -0.4, 0.2, 0.1, 0.1, 0.9, -0.3, 0.05, 0.2, 1.1 } };
    for (int t = 0; t < (kinds[m] == Material::MooneyRivlin ? 2 : 3); ++t)
    {
      double Ae[81];
      law.Tangent(Fs[t], P, Ae, false);
      law.Tangent(Fs[t], P, Ap, true);
      Eigen::Map<Eigen::Matrix<double, 9, 9, Eigen::RowMajor>> Aem(Ae), Apm(Ap);
      const Eigen::Matrix<double, 9, 9> sym = 0.5 * (Aem + Aem.transpose());
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 9, 9>> es(sym);
      const Eigen::Matrix<double, 9, 9> clamp = es.eigenvectors() *
        es.eigenvalues().cwiseMax(0.0).asDiagonal() * es.eigenvectors().transpose();
      const double diff = (clamp - Apm).cwiseAbs().maxCoeff();
      HOEMBED_CHECK(es.eigenvalues().minCoeff() < 0.0 || t == 1,
        "%s: point %d was meant to be indefinite", names[m], t);
      HOEMBED_CHECK(diff <= 1e-9 * E,
        "%s: projected tangent at point %d differs from the 9 x 9 "
        "clamp by %g",
        names[m], t, diff);
    }
    const double Fc[9] = { 0.3, 0.05, 0.0, 0.02, 1.1, 0.1, 0.0, -0.1, 1.2 }; // compressed
    law.Tangent(Fc, P, Ap, true);
    Eigen::Map<Eigen::Matrix<double, 9, 9, Eigen::RowMajor>> Am(Ap);
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 9, 9>> es(Am.transpose());
    HOEMBED_CHECK(es.eigenvalues().minCoeff() >= -1e-9 * E, "%s: projected tangent eigenvalue %g",
      names[m], es.eigenvalues().minCoeff());
  }
  // the compressed point above does have a negative eigenvalue for StVK (the projection
  // did something)
  {
    const HyperelasticLaw law = HyperelasticLaw::Make(Material::StVK, E, nu, 0.0, 0.0);
    const double Fc[9] = { 0.3, 0.05, 0.0, 0.02, 1.1, 0.1, 0.0, -0.1, 1.2 };
    double P[9], A[81];
    law.Tangent(Fc, P, A, false);
    Eigen::Map<Eigen::Matrix<double, 9, 9, Eigen::RowMajor>> Am(A);
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 9, 9>> es(Am.transpose());
    HOEMBED_CHECK(es.eigenvalues().minCoeff() < 0.0, "stvk: compressed tangent is definite");
  }
  // inversion: F = diag(1, 1, -0.5)
  const double Finv[9] = { 1, 0, 0, 0, 1, 0, 0, 0, -0.5 };
  {
    const HyperelasticLaw nh = HyperelasticLaw::Make(Material::NeoHookean, E, nu, 0.0, 0.0);
    CheckDerivatives(nh, Finv, "neo-hookean inverted");
    const HyperelasticLaw mr = HyperelasticLaw::Make(Material::MooneyRivlin, E, nu, 0.0, 0.0);
    HOEMBED_CHECK(std::isinf(mr.Energy(Finv)), "mooney-rivlin: finite energy when inverted");
    // given C10, C01: the shear modulus is 2 (C10 + C01)
    const HyperelasticLaw mg = HyperelasticLaw::Make(Material::MooneyRivlin, E, nu, 1e4, 3e4);
    double P[9], A[81];
    mg.Tangent(I, P, A, false);
    HOEMBED_CHECK(
      std::abs(A[9 * 1 + 1] - 2 * (1e4 + 3e4)) <= 1e-6, "mooney-rivlin: shear %g", A[9 * 1 + 1]);
    CheckDerivatives(mg, F1, "mooney-rivlin given");
  }
  return hoembed_test::Report("TestHyperelasticMaterial");
}
