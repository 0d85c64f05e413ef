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
 * deviation of the patch from it, (2/3) max_e |2 m_e - a_e - b_e| (the patch minus the flat
 * triangle is sum_{i<j} 2 mu_i mu_j (2 m_ij - x_i - x_j) with sum 2 mu_i mu_j <= 2/3). On a
 * sub-triangle where the squared distance is provably convex (a lower bound of the
 * smallest Hessian eigenvalue from the spread of the Jacobian and the farthest control
 * point) it is solved with ClosestPointOnMap and certified by the convexity inequality
 * f(xi) >= f(xi*) + grad f(xi*) . (xi - xi*) at the sub-triangle's corners; otherwise it
 * is split in four. Sub-triangles whose bound is within `tol` of the best distance known
 * (on this patch or elsewhere: `incumbent2`) are dropped.
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
