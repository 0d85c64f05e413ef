/**
 * @file hoembedClosestPointCertify.h
 * @brief Global closest point on one curved patch: certify a local solution of
 * ClosestPointOnMap, or find the nearer point it missed.
 *
 * The squared distance over a strongly curved tri6 patch is not convex: a solve from one
 * start (even several) can stop in a local minimum, on the patch border or inside (see
 * Testing/Cxx/Embedding/TestEmbeddingNonConvexFace.cxx).
 *
 * The certificate is an exact expansion at a parametric point r (the local solution):
 * the map is quadratic and its Jacobian affine, so with D = u - r, p = x(r) - v,
 * g = 2 J(r)^T p and P_ij = p . Q_ij, for every u
 *   |x(u) - v|^2 = |p|^2 + g . D + D^T P D + |J((u + r) / 2) D|^2
 * (x(u) - x(r) = J((u + r) / 2) D). Over a parametric sub-triangle q, J^T J on
 * S = (q + r) / 2 is at every point a convex combination of its six Bernstein
 * coefficients E_k (2 x 2 matrices from J at S's corners), so
 *   |x(u) - v|^2 - |p|^2 >= min_k min_{u in q} g . D + D^T (P + E_k) D,
 * each minimum exact (corners, edges, interior). A cheaper first try uses one matrix
 * below all E_k (entry ranges). Near a local solution g . D >= 0, so on a patch that is
 * not too curved for its distance to v the bound over the whole triangle already proves
 * r global (SolutionCertified: a few hundred flops, enough for most faces; the share is
 * in Benchmarks/RESULTS.md).
 *
 * Where it is not, CertifyClosestPointOnPatch runs a best-first branch and bound over
 * parametric sub-triangles: a sub-triangle is dropped when the distance to the flat
 * triangle of its corners, less the largest deviation of the patch from it
 * ((2/3) max_e |2 m_e - a_e - b_e|: the patch minus the flat triangle is
 * sum_{i<j} 2 mu_i mu_j (2 m_ij - x_i - x_j), sum 2 mu_i mu_j <= 2/3), or the expansion
 * at r, is within `tol` of the best distance known (on this patch or elsewhere:
 * `incumbent2`); otherwise it is split in four. Its corners are points of the patch:
 * when one is nearer than r, it is polished by a local solve and the search expands
 * there too.
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

/**
 * True when no point of the patch `m` (Dim 2) is nearer to `v` than
 * min(|x(r) - v|^2, incumbent2) by more than `tol` (a distance), proven by the expansion
 * at r over the whole triangle (see the file comment); r need not be converged, but
 * only a local solution makes the bound tight. False: not proven (then
 * CertifyClosestPointOnPatch decides).
 */
HOEMBEDFILTERSEMBEDDING_EXPORT bool SolutionCertified(const QuadraticMap& m, const double v[3],
  double incumbent2, double tol, const ClosestPointResult& r);
/**
 * True when no point of the patch `m` (Dim 2) is nearer to `v` than sqrt(incumbent2) - tol,
 * proven by the expansion at the parametric point `uv` (any point, e.g. the closest
 * point of the flat triangle) without solving: lets a search skip faces that cannot
 * improve its best distance. False: not proven.
 */
HOEMBEDFILTERSEMBEDDING_EXPORT bool PatchFartherThan(
  const QuadraticMap& m, const double v[3], const double uv[2], double incumbent2, double tol);

} // namespace hoembed

#endif
