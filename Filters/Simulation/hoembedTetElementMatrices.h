/**
 * @file hoembedTetElementMatrices.h
 * @brief Element matrices of isotropic linear elasticity on tet4 / tet10 elements.
 *
 * Plain C++ kernels (no VTK pipeline code). Node coordinates are 3 doubles per node in
 * VTK's node order (see hoembedShapeFunctions.h); `n` is 4 (VTK_TETRA) or 10
 * (VTK_QUADRATIC_TETRA). Element vectors and matrices use the node-major DOF layout
 * (node a, component i) -> 3 a + i; matrices are dense, row-major, (3n) x (3n).
 *
 * Quadrature: collapsed (Duffy / Stroud conical product) Gauss-Legendre rules on the
 * reference tet with 4^3 = 64 points, exact for polynomial integrands of degree 5: the
 * stiffness (degree 2) and mass (degree 4) of a straight tet10 are exact; on a curved
 * (quadratic-map) tet10 the stiffness integrand is rational and the mass integrand
 * N_i N_j det J has degree 7, so they are accurate, not exact (a 27-point rule gave a
 * 7e-6 relative displacement difference to a converged P2 solve on a curved beam, this
 * one 4e-8).
 *
 * The lumped mass is HRZ (diagonal of the consistent mass scaled so that each direction
 * keeps the element mass); plain row-sum lumping would give negative tet10 corner masses.
 */
#ifndef hoembedTetElementMatrices_h
#define hoembedTetElementMatrices_h

#include "hoembedFiltersSimulationModule.h"

namespace hoembed
{
/// Lame parameters from Young's modulus and Poisson's ratio.
HOEMBEDFILTERSSIMULATION_EXPORT void LameParameters(
  double young, double poisson, double& lambda, double& mu);

/**
 * Quadrature rule on the VTK reference tet (corners (0,0,0),(1,0,0),(0,1,0),(0,0,1),
 * volume 1/6) with m^3 points, m in [1, 6]; exact for polynomials of degree 2m - 3.
 * pc gets 3 m^3 doubles, w gets m^3 weights that sum to 1/6. Returns the point count.
 */
HOEMBEDFILTERSSIMULATION_EXPORT int TetQuadrature(int m, double* pc, double* w);

/// Element stiffness K (3n x 3n) of isotropic linear elasticity. Returns the element
/// volume (integral of det J with the same rule); <= 0 flags an invalid element.
HOEMBEDFILTERSSIMULATION_EXPORT double ElementStiffness(
  int n, const double* x, double young, double poisson, double* K);

/// Consistent element mass M (3n x 3n; the same n x n block on each component).
HOEMBEDFILTERSSIMULATION_EXPORT void ElementConsistentMass(
  int n, const double* x, double density, double* M);

/// HRZ-lumped element mass: n positive nodal masses summing to density * volume.
HOEMBEDFILTERSSIMULATION_EXPORT void ElementLumpedMassHRZ(
  int n, const double* x, double density, double* m);

/// Consistent body-force vector f_a = integral of N_a * density * g over the element
/// (3n doubles). For tet10 the corner entries point against g (they are negative).
HOEMBEDFILTERSSIMULATION_EXPORT void ElementBodyForce(
  int n, const double* x, double density, const double g[3], double* f);

/// Gradients dN_a/dX (n x 3, row-major) at parametric point pc; returns det J.
HOEMBEDFILTERSSIMULATION_EXPORT double ShapeGradients(
  int n, const double* x, const double pc[3], double* gradN);

/**
 * Rotation of the polar decomposition F = R S, row-major 3x3. For det F > 1e-6 |F|^3
 * by the scaled Newton iteration X <- (g X + X^-T / g) / 2 (converged to round-off,
 * ~10x cheaper than an SVD); otherwise (and should it not converge) via SVD
 * F = U S V^T, R = U V^T; when det F <= 0 (an inverted or flat element) the sign of the
 * singular vector of the smallest singular value is flipped so that R stays a proper
 * rotation (det R = +1) that varies continuously through inversion.
 */
HOEMBEDFILTERSSIMULATION_EXPORT void PolarRotation(const double F[9], double R[9]);

/// von Mises stress of the small-strain stress of the (co-rotated) displacement u
/// (3n doubles) at parametric point pc.
HOEMBEDFILTERSSIMULATION_EXPORT double VonMisesStress(
  int n, const double* x, const double* u, const double pc[3], double young, double poisson);
} // namespace hoembed

#endif
