/**
 * @file hoembedQuadraticMap.h
 * @brief The quadratic (or linear) map of a tet or triangle in monomial form, its
 *        bounds, and the one tet validity proof every stage uses.
 *
 * x(xi) = C + sum_i L_i xi_i + 1/2 sum_ij Q_ij xi_i xi_j over the reference simplex of
 * dimension 2 (tri3/tri6) or 3 (tet4/tet10), read off the expanded VTK shape functions
 * (MakeTriangleMap, MakeTetMap); its Jacobian is affine, so bounds over a simplex come
 * from the Jacobians at its corners (Bernstein coefficients of det J): the validity proof
 * (TetIsValid) and the exclusion bounds of the embedding's cell search.
 *
 * Plain C++ (no VTK).
 */
#ifndef hoembedQuadraticMap_h
#define hoembedQuadraticMap_h

#include "hoembedCoreModule.h"
#include "hoembedLanes.h"

namespace hoembed
{
/// A polynomial map of degree <= 2 from the reference simplex of dimension Dim (2 or 3)
/// to R^3, in monomial form.
struct alignas(64) QuadraticMap
{
  int Dim = 3;
  double C[3] = { 0, 0, 0 };
  double L[3][3] = {};    ///< L[i] = dx/dxi_i at xi = 0
  double Q[3][3][3] = {}; ///< Q[i][j] = d2x / dxi_i dxi_j (symmetric)
};

/// Monomial form of a tri6 (n = 6) or tri3 (n = 3) patch, nodes in VTK order (3 doubles each).
HOEMBEDCORE_EXPORT void MakeTriangleMap(const double* x, int n, QuadraticMap& m);
/// Monomial form of a tet10 (n = 10) or tet4 (n = 4), nodes in VTK order.
HOEMBEDCORE_EXPORT void MakeTetMap(const double* x, int n, QuadraticMap& m);

/**
 * True when det J > 0 is proven over the whole tet10 (nodes in VTK order) by the cubic's
 * Bernstein coefficients, all above 1e-12 of their largest magnitude (they come from the
 * corner Jacobians: det(sum_k lambda_k G_k) expanded multilinearly). False means "not
 * proven": the caller falls back to a finer test (hoembed::Tet10IsValid).
 */
HOEMBEDCORE_EXPORT bool Tet10JacobianProvablyPositive(const double* x);
/// The same from the element's monomial map (MakeTetMap of its nodes).
HOEMBEDCORE_EXPORT bool Tet10JacobianProvablyPositive(const QuadraticMap& m);

/**
 * True when no point of the element of the tet map `m` (Dim 3, quadratic or linear) lies
 * within `reach` of x(eta), for a parametric point eta outside the reference tet T.
 * Proof used: for quadratic maps x(xi) - x(eta) = J((xi + eta) / 2) (xi - eta) exactly
 * (J is affine), and over S = (T + eta) / 2, det J >= b (smallest Bernstein coefficient,
 * from the Jacobians at S's corners) and |J|_F <= F (largest Frobenius norm there), so
 * the smallest singular value of J is >= 2 b / F^2 (s1 s2 <= F^2 / 2) and
 * |x(xi) - x(eta)| >= 2 b / F^2 * dist(eta, T) for every xi in T. False: not proven.
 */
HOEMBEDCORE_EXPORT bool TetMapExcludes(const QuadraticMap& m, const double eta[3], double reach);

/// The reference tet scaled by this factor about its centroid is where
/// TetMapExclusionRate bounds the Jacobian.
constexpr double ExclusionRateScale = 1.2;

/**
 * A lower bound of every singular value of J over the reference tet scaled by
 * ExclusionRateScale about its centroid (2 b / F^2 as in TetMapExcludes); 0 when det J is
 * not proven positive there. Computed once per element, it serves TetMapExclusionRadius
 * for every eta within twice the reference tet (scaled about the centroid).
 */
HOEMBEDCORE_EXPORT double TetMapExclusionRate(const QuadraticMap& m);

/**
 * The radius of a ball around x(eta) proven to hold no point of the element (eta
 * outside the reference tet T): 2 b / F^2 * dist(eta, T) as in TetMapExcludes, less a
 * relative 1e-6 for round-off; 0 when nothing is proven. `rate` (> 0) is the element's
 * TetMapExclusionRate: used when it covers (T + eta) / 2, which saves the bound over it.
 */
HOEMBEDCORE_EXPORT double TetMapExclusionRadius(
  const QuadraticMap& m, const double eta[3], double rate = 0.0);

/// x(xi) and, when J is not null, J[i] = dx/dxi_i (m.Dim vectors of 3).
HOEMBEDCORE_EXPORT void EvaluateMap(
  const QuadraticMap& m, const double* xi, double x[3], double (*J)[3] = nullptr);

/**
 * The one validity proof of a tet cell (nodes in VTK order, 3 doubles each): true when
 * det J > 0 is proven throughout. tet10: the Bernstein coefficients of det J from the
 * corner Jacobians of `m` settle nearly every element (Tet10JacobianProvablyPositive),
 * the subdividing bound (hoembed::Tet10IsValid) the others; tet4: det J clear of
 * round-off against the edge lengths (1e-12 l^3). `m` is MakeTetMap of x.
 */
HOEMBEDCORE_EXPORT bool TetIsValid(const double* x, int nodesPerCell, const QuadraticMap& m);
/// The same, computing the map.
HOEMBEDCORE_EXPORT bool TetIsValid(const double* x, int nodesPerCell);

namespace detail
{
/// x(xi) and J[i] = dx/dxi_i of a map of dimension N (monomial form): coordinates x and
/// y in the two lanes of a vector register, z apart (Q[i][j] and L[i] hold x, y, z
/// contiguously), half the arithmetic instructions of a scalar loop.
template <int N>
inline void Eval(const QuadraticMap& m, const double* xi, double x[3], double J[][3])
{
  using lanes::Load;
  using lanes::Pair;
  Pair acc = Load(m.C);
  double accz = m.C[2];
  for (int i = 0; i < N; ++i)
  {
    const Pair l = Load(m.L[i]);
    Pair ji = l;
    double jz = m.L[i][2];
    for (int j = 0; j < N; ++j)
    {
      ji += Load(m.Q[i][j]) * xi[j];
      jz += m.Q[i][j][2] * xi[j];
    }
    lanes::Store(J[i], ji);
    J[i][2] = jz;
    const double h = 0.5 * xi[i];
    acc += h * (l + ji);
    accz += h * (m.L[i][2] + jz);
  }
  lanes::Store(x, acc);
  x[2] = accz;
}

} // namespace detail
} // namespace hoembed

#endif
