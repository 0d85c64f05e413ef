/**
 * @file hoembedClosestPoint.h
 * @brief Constrained closest point on a quadratic (or linear) triangle patch (2 variables)
 * and in a quadratic (or linear) tetrahedron (3 variables), paper eq. 3.
 *
 * The maps are polynomials of degree <= 2 over the reference simplex, stored in monomial
 * form (QuadraticMap): x(xi) = C + sum_i L_i xi_i + 1/2 sum_ij Q_ij xi_i xi_j. Their
 * Jacobian and (constant) second derivatives are exact, so the solver is a full Newton
 * method with Levenberg-Marquardt damping where the Hessian is not positive definite, an
 * active set over the simplex constraints (faces, edges, corners; multipliers checked
 * before a constraint is kept) and a backtracking line search with a ratio test, so
 * every iterate stays inside the simplex exactly (no constraint is ever violated) and the
 * objective decreases monotonically. This converges where plain Newton does not (points
 * far from a strongly curved element). For patches a plain Newton iteration from an
 * interior start is tried first and kept only when it stays inside with a positive
 * definite Hessian and converges (an interior local minimum).
 *
 * Constraint bits (ClosestPointResult::Active):
 * - 2 variables (u, v): bit 0: u = 0 (edge ca), bit 1: v = 0 (edge ab), bit 2: u + v = 1
 *   (edge bc). Two bits set: a corner.
 * - 3 variables (r, s, t): bit 0: r = 0 (tet face 2), bit 1: s = 0 (face 0), bit 2: t = 0
 *   (face 3), bit 3: r + s + t = 1 (face 1); faces in hoembed::TetFaceNodes order.
 *
 * Plain C++ kernels; the solver keeps everything on the stack (thread safe).
 */
#ifndef hoembedClosestPoint_h
#define hoembedClosestPoint_h

#include "hoembedFiltersEmbeddingModule.h"
#include "hoembedQuadraticMap.h" // QuadraticMap, the maps and their bounds (Core)

namespace hoembed
{
struct ClosestPointResult
{
  double Param[3] = { 0, 0, 0 }; ///< (u, v) or (r, s, t), inside the simplex
  double Point[3] = { 0, 0, 0 };
  double Distance2 = 0.0; ///< squared distance |x(Param) - v|^2
  int Active = 0;         ///< constraint bits, see the file comment
  int Iterations = 0;
  bool Converged = false;
};

/**
 * Closest point of `v` on the patch / in the element `m` (m.Dim = 2 or 3), starting
 * from `start` (projected into the simplex; null: the centroid). At most `maxIterations`
 * Newton iterations.
 */
HOEMBEDFILTERSEMBEDDING_EXPORT void ClosestPointOnMap(const QuadraticMap& m, const double v[3],
  const double* start, ClosestPointResult& res, int maxIterations = 60);

/**
 * Closest point of a flat triangle to a point p, by Voronoi regions (Ericson, Real-Time
 * Collision Detection 5.1.5). The triangle is a, a + ab, a + ac and `ap` = p - a; the
 * answer is a + st[0] ab + st[1] ac. Returns false (st at the centroid) for a degenerate
 * triangle, or when round-off puts the interior answer outside the triangle.
 */
HOEMBEDFILTERSEMBEDDING_EXPORT bool ClosestPointOnTriangle(
  const double ap[3], const double ab[3], const double ac[3], double st[2]);

/**
 * A start for ClosestPointOnMap from the straight simplex through the map's corners:
 * Dim 2, the closest point of v on the flat triangle; Dim 3, the linear tet's
 * barycentric coordinates of v, clamped into the simplex.
 */
HOEMBEDFILTERSEMBEDDING_EXPORT void LinearStart(
  const QuadraticMap& m, const double v[3], double* start);

/**
 * Unconstrained inverse of a tet map: find pc with x(pc) = v (pc may leave the element:
 * extrapolated coordinates), damped Newton from `pc` (in/out). Returns |x(pc) - v|.
 * With `outsideStop` > 0 the iteration stops as soon as |x(pc) - v| <= outsideStop with
 * pc more than 1e-3 outside the reference tet: enough for a caller that only needs to
 * know that v is not in the element (TetMapExcludes with reach tol + |x(pc) - v|).
 * Such a search also gives up (returning the residual reached) on a Newton step longer
 * than 2 in parametric units (a nearly singular Jacobian where the map folds outside the
 * element) or after 10 backtracking steps without decrease (30 otherwise).
 */
HOEMBEDFILTERSEMBEDDING_EXPORT double InvertTetMap(const QuadraticMap& m, const double v[3],
  double pc[3], int& iterations, int maxIterations = 60, double outsideStop = 0.0);

/**
 * Normal-offset solve in one boundary face (paper eq. 8-9 with the normalised normal of
 * eq. 7): find (u, v, d) with x(u, v) + d * s(u, v) / |s(u, v)| = p, where `x` is the
 * face map and `s` the interpolated nodal-normal field (both QuadraticMap, Dim 2).
 * Newton from (uv, d). Returns 0 when converged inside the face (|F| <= tol, or the
 * Newton step is below 1e-13 in (u, v) and tol in d with |F| <= 100 tol: on an edge,
 * where the normal field has a kink), 1 + e when
 * the iteration left the face through edge e (0: ab, 1: bc, 2: ca); uv then lies on that
 * edge), -1 when it failed (singular or no progress). `iterations` is incremented.
 */
HOEMBEDFILTERSEMBEDDING_EXPORT int SolveNormalOffset(const QuadraticMap& x, const QuadraticMap& s,
  const double p[3], double uv[2], double& d, double tol, int& iterations, int maxIterations = 40);
/**
 * The offset of v from the point x(pc) of a tet map in parametric units: q with
 * J(pc) q = v - x(pc), J = dx/dpc. x(pc) + J(pc) q rebuilds v to round-off, and a
 * deformed map gives x'(pc) + J'(pc) q = p' + F (v - p), F = J' J^-1 the deformation
 * gradient at p. False (q = 0) when J(pc) is singular.
 */
HOEMBEDFILTERSEMBEDDING_EXPORT bool TetMapOffset(
  const QuadraticMap& m, const double pc[3], const double v[3], double q[3]);
} // namespace hoembed

#endif
