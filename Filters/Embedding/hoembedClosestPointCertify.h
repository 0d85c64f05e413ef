/**
 * @file hoembedClosestPointCertify.h
 * @brief Global closest point on one curved patch: certify a local solution of
 * ClosestPointOnMap, or find the nearer point it missed.
 *
 * The squared distance over a strongly curved tri6 patch is not convex: a solve from one
 * start (even several) can stop in a local minimum, on the patch border or inside (see
 * Testing/Cxx/TestEmbeddingNonConvexFace.cxx). This is a best-first branch and bound over
 * parametric sub-triangles of the patch. Each sub-triangle is again a quadratic patch;
 * its lower bound is the distance to the flat triangle of its corners minus the largest
 * deviation of the patch from it, (2/3) max_e |2 m_e - a_e - b_e| (the patch minus the
 * flat triangle is sum_{i<j} 2 mu_i mu_j (2 m_ij - x_i - x_j), sum 2 mu_i mu_j <= 2/3).
 * A sub-triangle is resolved by the second-order bound
 * f(xi* + D) >= f(xi*) + grad f(xi*) . D + D^T A D, minimised exactly over it, with xi*
 * its point nearest to the local solution (no solve) or, where the distance is provably
 * convex, a solve there, and A a lower bound of (1/2) Hess |x - v|^2 = J^T J + (x - v) . Q
 * over it (each entry is a quadratic polynomial, bounded by its Bernstein coefficients);
 * otherwise it is split in four. Sub-triangles whose bound is within `tol` of the best
 * distance known (on this patch or elsewhere: `incumbent2`) are dropped.
 *
 * Plain C++ kernel on the stack (fixed-size queue), thread safe.
 */
#ifndef hoembedClosestPointCertify_h
#define hoembedClosestPointCertify_h

#include "hoembedClosestPoint.h"
#include "hoembedFiltersEmbeddingModule.h"

namespace hoembed
{
/**
 * `r` is a solution of ClosestPointOnMap on the patch `m` (Dim 2) for `v`. Searches the
 * patch for a point nearer than min(r.Distance2, incumbent2) by more than `tol`
 * (a distance). When one is found, `r` is replaced by the solve polished from it and
 * the function returns true. `certified`, when not null, is set to false if the node
 * budget ran out before the search ended (the result is then the best found).
 */
HOEMBEDFILTERSEMBEDDING_EXPORT bool CertifyClosestPointOnPatch(const QuadraticMap& m,
  const double v[3], double incumbent2, double tol, ClosestPointResult& r,
  bool* certified = nullptr, int maxNodes = 400);
} // namespace hoembed

#endif
