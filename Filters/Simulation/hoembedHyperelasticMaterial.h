/**
 * @file hoembedHyperelasticMaterial.h
 * @brief Hyperelastic energy densities of the FE stepper: St. Venant-Kirchhoff, the stable
 * Neo-Hookean of Smith, de Goes and Kim (2018) and compressible Mooney-Rivlin; per point
 * the energy Psi(F), the first Piola-Kirchhoff stress P = dPsi/dF and the tangent
 * dP/dF (9 x 9), exact or made positive semi-definite.
 *
 * Plain C++ kernel (no VTK, Eigen only in the .cxx). F, P are 3x3 row-major; the tangent
 * A is 9 x 9 row-major with A[3 i + j][3 k + l] = dP_ij / dF_kl.
 *
 * Parameters from Young's modulus E and Poisson's ratio nu (mu, lambda: Lame, kappa =
 * E / (3 (1 - 2 nu)) the bulk modulus), each chosen so that the material's small-strain
 * limit is linear elasticity with E and nu (the co-rotated material's):
 * - StVK: Psi = mu E:E + lambda / 2 tr(E)^2, E = (F^T F - I) / 2.
 * - Stable Neo-Hookean (Smith et al. 2018, eq. 14 with its log term):
 *   Psi = mu'/2 (I_C - 3) + lambda'/2 (J - a)^2 - mu'/2 log(I_C + 1),
 *   a = 1 + 3 mu' / (4 lambda'), with the paper's re-parametrisation mu' = 4/3 mu and
 *   lambda' = lambda + 5/6 mu (its linearisation at F = I is then mu, lambda), minus
 *   its (constant) value at F = I so that the energy at rest is 0. Defined
 *   and smooth for every F, inverted ones included (J < 0 costs energy, no pole).
 * - Mooney-Rivlin (compressible, deviatoric invariants):
 *   Psi = C10 (J^-2/3 I_1 - 3) + C01 (J^-4/3 I_2 - 3) + kappa/2 (J - 1)^2; its shear
 *   modulus is 2 (C10 + C01). From E, nu: C10 = C01 = mu / 4 (unless both are given);
 *   kappa from E, nu always. Undefined for J <= 0: the energy is +infinity there (a
 *   line search then backs away from inversion; it cannot recover an inverted element).
 * The tangent is exact: in closed form for Neo-Hookean (the law of live frames), else
 * forward-mode differentiation of the hand-written P (the derivative of exactly the P in
 * use); the projected tangent clamps the negative eigenvalues of the symmetric 9 x 9
 * tangent to zero (computed in the principal frame of F, where the tangent of an
 * isotropic law splits into a 3 x 3 and three 2 x 2 blocks), which makes an element
 * Hessian (a positive combination of B^T A B over its quadrature points) positive
 * semi-definite.
 */
#ifndef hoembedHyperelasticMaterial_h
#define hoembedHyperelasticMaterial_h

#include "hoembedFiltersSimulationModule.h"

namespace hoembed
{
/// The stepper's materials (StepperParameters::Material); Corotated is co-rotated linear
/// elasticity (hoembedCorotationalSolver.h), the others are hyperelastic.
enum class Material
{
  Corotated = 0,
  StVK = 1,
  NeoHookean = 2,
  MooneyRivlin = 3
};

struct HOEMBEDFILTERSSIMULATION_EXPORT HyperelasticLaw
{
  Material Kind = Material::NeoHookean;
  double Mu = 0.0, Lambda = 0.0; ///< StVK: Lame; Neo-Hookean: mu', lambda' above
  double Alpha = 1.0;            ///< Neo-Hookean rest-stability shift a
  double Rest = 0.0;             ///< Neo-Hookean: the formula's value at F = I, subtracted
  double C10 = 0.0, C01 = 0.0, Kappa = 0.0; ///< Mooney-Rivlin

  /// The law's constants from E, nu (and c10, c01 for Mooney-Rivlin: both 0 = from E,
  /// nu) with the conversions of the file's doc.
  static HyperelasticLaw Make(Material kind, double young, double poisson, double c10, double c01);

  /// Energy density (+infinity where undefined: Mooney-Rivlin at J <= 0).
  double Energy(const double F[9]) const;
  /// First Piola-Kirchhoff stress; returns the energy density.
  double Stress(const double F[9], double P[9]) const;
  /// Stress and tangent dP/dF (exact; `project`: negative eigenvalues clamped to 0).
  double Tangent(const double F[9], double P[9], double A[81], bool project) const;
};
} // namespace hoembed

#endif
