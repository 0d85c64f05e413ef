/**
 * @file hoembedTetBarycentric.h
 * @brief A curved tet as its straight tet plus edge bumps, and a cheap proof that a point
 * is away from it (no Newton iteration).
 *
 * The tet10 map in barycentric coordinates lambda (VTK node order, edges e = (i, j) with
 * midnode m_e) is
 *     x(lambda) = sum_i lambda_i x_i + sum_e 4 lambda_i lambda_j delta_e,
 *     delta_e = m_e - (x_i + x_j) / 2
 * (the straight tet through the corners plus a bump per curved edge; a tet4 has no bump).
 * With l(y) the straight tet's barycentric coordinates of a point y (affine in y, linear
 * part g_k = grad l_k), x(lambda) = y gives
 *     lambda_k = l_k(y) - sum_e 4 lambda_i lambda_j w_ke,   w_ke = g_k . delta_e.
 * For every y within `reach` of p, l_k(y) lies within |g_k| reach of l_k(p). So every
 * lambda of the element (a box in [0, 1]^4 to start with, sum 1) whose point is within
 * reach of p satisfies these four equations with interval right-hand sides. A sweep
 * evaluates them over the current box (4 lambda_i lambda_j in [4 lo_i lo_j,
 * min(4 hi_i hi_j, min(1, hi_i + hi_j)^2)]), intersects, then intersects with the sum
 * constraint; the sweeps stop when the box's total width no longer falls by 10%. An empty
 * interval proves that no point of the element lies within reach of p. Later sweeps localise the
 * bumps (on the real meshes most of the cells that share an edge with a point's closest boundary
 * face are excluded in a few sweeps, where the straight-face slabs below exclude none: the curved
 * edge's control point bulges across their faces).
 *
 * The cheap test first: l_k(x(lambda)) = lambda_k + sum_e 4 lambda_i lambda_j w_ke is a
 * quadratic whose Bezier coefficients are the corners' 0 or 1 and, at edge e,
 * (l_k(x_i) + l_k(x_j)) / 2 + 2 w_ke; so the element lies where l_k >= -Bump[k], the
 * smallest coefficient's negative part (the slab of the straight face opposite corner
 * k, pushed out by the control points).
 */
#ifndef hoembedTetBarycentric_h
#define hoembedTetBarycentric_h

#include "hoembedFiltersEmbeddingModule.h"

namespace hoembed
{
struct alignas(64) TetBarycentricForm
{
  double X0[3] = { 0, 0, 0 };       ///< corner 0: l_k(y) = G[k] . (y - X0) + (k == 0)
  double G[4][3] = {};              ///< gradients of the straight tet's barycentric coordinates
  double GNorm[4] = { 0, 0, 0, 0 }; ///< |G[k]|
  double Bump[4] = { 0, 0, 0, 0 };  ///< the element lies where l_k >= -Bump[k] (>= 0)
  double Slack = -1.0;              ///< round-off allowance in lambda; < 0: not usable
  // (the fields above are all the slab test TetBarycentricBeyond reads: 3 cache lines)
  double W[6][4] = {}; ///< W[e][k] = w_ke = G[k] . delta_e (edges in VTK midnode order)
};

/**
 * The form of a tet10 (n = 10) or tet4 (n = 4), nodes in VTK order (3 doubles each).
 * An ill-conditioned straight tet (the norm of its edge matrix times that of its inverse
 * above 1e8) gives a form that never excludes anything.
 */
HOEMBEDFILTERSEMBEDDING_EXPORT void MakeTetBarycentricForm(
  const double* x, int n, TetBarycentricForm& form);

/**
 * The corner k opposite the straight face beyond whose slab (l_k < -Bump[k]) p lies
 * farthest, by more than `reach`; -1 when p is within all four slabs (or the form is not
 * usable). Four dot products.
 */
HOEMBEDFILTERSEMBEDDING_EXPORT int TetBarycentricBeyond(
  const TetBarycentricForm& form, const double p[3], double reach);

/**
 * True when no point of the element is within `reach` of p (proven by the interval sweeps
 * of the file comment, at most `maxSweeps`); false: not proven.
 */
HOEMBEDFILTERSEMBEDDING_EXPORT bool TetBarycentricExcludes(
  const TetBarycentricForm& form, const double p[3], double reach, int maxSweeps = 8);
} // namespace hoembed

#endif
