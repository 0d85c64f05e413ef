/**
 * @file hoembedElementGeometry.h
 * @brief Jacobians, a conservative validity test and quality of tet4 / tet10 elements.
 *
 * Plain C++ kernels. Node coordinates are passed as 3 doubles per node in VTK's node
 * order (see hoembedShapeFunctions.h).
 *
 * The Jacobian determinant of a quadratic (tet10) element is a cubic polynomial in the
 * barycentric coordinates. It is represented exactly by its 20 coefficients in the cubic
 * Bernstein basis; their minimum is a lower bound of det J over the whole element
 * (Bernstein polynomials are non-negative and sum to one), and the bound is sharp at the
 * corners (up to a round-off allowance of 1e-12 of the largest coefficient, subtracted so
 * that a positive bound is positive for the exact polynomial too). `Tet10JacobianBounds` computes
 * that bound, refined by de Casteljau subdivision where it is not conclusive, so `Tet10IsValid`
 * never accepts an element whose det J reaches zero anywhere inside it.
 */
#ifndef hoembedElementGeometry_h
#define hoembedElementGeometry_h

#include "hoembedCoreModule.h"

namespace hoembed
{
/// Jacobian J[i][j] = d x_i / d pc_j of a tet10 at parametric point pc.
HOEMBEDCORE_EXPORT void Tet10Jacobian(const double* x, const double pc[3], double J[3][3]);
/// det J of a tet10 at parametric point pc (6 x the volume scale of a straight tet).
HOEMBEDCORE_EXPORT double Tet10JacobianDeterminant(const double* x, const double pc[3]);
/// det J of a tet4 (constant): (x1 - x0) . ((x2 - x0) x (x3 - x0)).
HOEMBEDCORE_EXPORT double Tet4JacobianDeterminant(const double* x);
HOEMBEDCORE_EXPORT double Determinant3(const double J[3][3]);

/**
 * Jacobians of a tet10 (nodes in VTK order) at its 4 corners: G[k][i] = dx/dxi_i at
 * corner k (xi = 0, e_1, e_2, e_3). The Jacobian is affine in xi, so it is
 * sum_k lambda_k G[k] everywhere (lambda: barycentric coordinates).
 */
HOEMBEDCORE_EXPORT void Tet10CornerJacobians(const double* x, double G[4][3][3]);

/**
 * Smallest Bernstein coefficient of det J over a tet on which J is affine, from its
 * corner Jacobians G (as Tet10CornerJacobians gives them; or those of any sub-tet, or
 * of a tet around the element): det(sum_a lambda_a G_a) expanded multilinearly. NaN when
 * a coefficient is NaN. `hi`, when not null, receives the largest coefficient magnitude.
 */
HOEMBEDCORE_EXPORT double DetBernsteinMin(const double G[4][3][3], double* hi = nullptr);

/**
 * The 20 Bernstein coefficients of det(sum_a lambda_a G_a): b[k] belongs to the
 * multi-index (3 - n1 - n2 - n3, n1, n2, n3) (counts of corners 0..3), k running over
 * n1, then n2, then n3 ascending; det(sum_a lambda_a G_a) = sum_k b[k] 3! / (n0! n1! n2!
 * n3!) lambda^n. (The symmetric trilinear form of det at the matrices the multi-index
 * names, from determinants of sums.)
 */
HOEMBEDCORE_EXPORT void DetBernsteinCoefficients(const double G[4][3][3], double b[20]);

/**
 * Bounds of det J over the whole tet10 element.
 * @param x        10 nodes, 3 doubles each
 * @param minBound on return, a lower bound of min det J (exact at the corners)
 * @param maxBound on return, an upper bound of max det J
 * @param depth    de Casteljau subdivision levels used when the plain bound is not
 *                 positive while sampled values are (0 = plain Bernstein bound)
 * The returned lower bound is the best one found; it is positive only if det J > 0
 * everywhere in the element.
 */
HOEMBEDCORE_EXPORT void Tet10JacobianBounds(
  const double* x, double& minBound, double& maxBound, int depth = 3);

/// True when det J > 0 everywhere in the tet10 (conservative: may reject a valid element
/// whose minimum is within round-off of zero, never accepts an invalid one).
HOEMBEDCORE_EXPORT bool Tet10IsValid(const double* x, int depth = 3);

/**
 * Scaled Jacobian of a tet10, Verdict's definition applied pointwise: at a point with
 * Jacobian J, sqrt(2) det J divided by the largest product, over the 4 corners, of the
 * lengths of the 3 reference edges at that corner mapped by J (so the value does not
 * depend on the node numbering, and a regular straight tet scores 1). The minimum is
 * taken over the 20 nodes of the cubic lattice; the result is at most 0 whenever the
 * element is not provably valid (Tet10IsValid), and at most 1.
 * For a straight tet10 this equals vtkMeshQuality's tet scaled Jacobian.
 */
HOEMBEDCORE_EXPORT double Tet10MinScaledJacobian(const double* x);
/// Tet10MinScaledJacobian without the validity proof: the minimum over the 20 lattice
/// nodes alone (at most 1). Cheaper; a search may use it, an acceptance test may not.
HOEMBEDCORE_EXPORT double Tet10SampledScaledJacobian(const double* x);
/// Scaled Jacobian of a straight tet4, as vtkMeshQuality / Verdict computes it (min over
/// the 4 corners, sqrt(2) normalised: 1 for a regular tet; -1 for a zero-length edge).
HOEMBEDCORE_EXPORT double Tet4ScaledJacobian(const double* x);
/// Volume of a tet10 (exact: the mean of the cubic Bernstein coefficients of det J / 6).
HOEMBEDCORE_EXPORT double Tet10Volume(const double* x);
HOEMBEDCORE_EXPORT double Tet4Volume(const double* x);
} // namespace hoembed

#endif
