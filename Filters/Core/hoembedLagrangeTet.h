/**
 * @file hoembedLagrangeTet.h
 * @brief VTK's Lagrange tetrahedron (VTK_LAGRANGE_TETRAHEDRON) of order 1-4: node order,
 * shape functions with first and second derivatives, the Bernstein (Bezier) form, the
 * validity proof of det J by its Bernstein coefficients, and the smooth boundary normals.
 *
 * Node order (vtkLagrangeTetra's, checked against VTK in TestLagrangeTet): the 4 corners,
 * then p - 1 nodes per edge on edges 01, 12, 20, 03, 13, 23 (from the first corner to the
 * second), then the face-interior nodes of faces (0 1 3), (1 2 3), (0 2 3), (0 1 2), then
 * the body nodes. Orders 1 and 2 are tet4 and tet10 node for node. The 15-node
 * "order 2 with bubbles" variant is not an order-p tet and is not accepted.
 *
 * A node is a multi-index alpha = (a0, a1, a2, a3), sum p, at barycentric point alpha / p
 * (lambda0 = 1 - r - s - t, lambda1 = r, lambda2 = s, lambda3 = t); its shape function is
 * prod_m l_{a_m}(lambda_m), l_a(x) = prod_{q < a} (p x - q) / (q + 1). The same
 * multi-indices, in the same order, index the Bernstein control points.
 *
 * Validity: det J is a polynomial of degree 3 (p - 1); its Bernstein coefficients, from
 * its values at the lattice of that degree (collocation, exact for that degree), bound it
 * below over the whole cell. Where the bound is not conclusive (at degree 9, order 4, it
 * is loose), the cell is split into 8 sub-tets (red refinement), up to 3 levels, each
 * bounded the same way from its own lattice. A sub-tet is proven when its smallest
 * coefficient is above 1e-9 of the cell's largest magnitude (round-off of the
 * collocation); a lattice value <= 0 is a counterexample. Never an invalid cell; at worst
 * a valid cell within that margin of zero is refused.
 *
 * Plain C++ (no VTK); read-only tables built once per order (thread safe).
 */
#ifndef hoembedLagrangeTet_h
#define hoembedLagrangeTet_h

#include "hoembedCoreModule.h"
#include "hoembedTetMeshTopology.h"

#include <cstdint>
#include <vector>

namespace hoembed
{
/// VTK_LAGRANGE_TETRAHEDRON
constexpr int LagrangeTetraCellType = 71;
/// The largest node count of a supported Lagrange tet (order 4).
constexpr int MaxLagrangeTetNodes = 35;

/// The order of a Lagrange tet of `nodesPerCell` nodes (4, 10, 20, 35 -> 1..4), else -1.
HOEMBEDCORE_EXPORT int LagrangeTetOrder(int nodesPerCell);

struct HOEMBEDCORE_EXPORT LagrangeTetBasis
{
  int Order = 0;
  int NumberOfNodes = 0;
  /// per node, in VTK's order: the barycentric multi-index (a0, a1, a2, a3)
  std::vector<int> Lattice; // 4 per node
  /// node (and control point) index of a multi-index: Index[(a1 * (p + 1) + a2) * (p + 1) + a3]
  std::vector<int> Index;
  /// control points = ToBernstein * nodal values (NumberOfNodes^2, row-major)
  std::vector<double> ToBernstein;
  /// det J: its NumberOfDetNodes values at the lattice of degree 3 (p - 1) (barycentric
  /// points DetLattice / (3 (p - 1)), 3 per point: r, s, t) to its Bernstein coefficients
  int NumberOfDetNodes = 0;
  std::vector<double> DetNodes;       // 3 per point (r, s, t)
  std::vector<double> DetToBernstein; // NumberOfDetNodes^2

  int NodeIndex(int a1, int a2, int a3) const
  {
    const int q = this->Order + 1;
    return this->Index[(a1 * q + a2) * q + a3];
  }
};

/// The basis of order 1..4 (built at first use; thread safe). Null for another order.
HOEMBEDCORE_EXPORT const LagrangeTetBasis* GetLagrangeTetBasis(int order);

/// Parametric coordinates (r, s, t) of node k.
HOEMBEDCORE_EXPORT void LagrangeTetNodeParametric(const LagrangeTetBasis& b, int k, double pc[3]);

/// Shape function values N[k] at pc (VTK's node order).
HOEMBEDCORE_EXPORT void LagrangeTetShape(const LagrangeTetBasis& b, const double pc[3], double* N);

/**
 * x = sum_k N_k(pc) y_k of a nodal field y (3 doubles per node, the cell's nodes in
 * VTK's order), J[i] = dx/dpc_i and, when H is not null, H[i][j] = d2x / dpc_i dpc_j.
 */
HOEMBEDCORE_EXPORT void EvaluateLagrangeTet(const LagrangeTetBasis& b, const double* y,
  const double pc[3], double x[3], double J[3][3], double (*H)[3][3] = nullptr);

/// Bernstein control points (3 per node, same order) of a nodal field y.
HOEMBEDCORE_EXPORT void LagrangeTetToBernstein(
  const LagrangeTetBasis& b, const double* y, double* control);

/**
 * The smallest Bernstein coefficient of det J over the cell (nodes x, 3 per node) and,
 * in `hi`, the largest magnitude: det J >= the smallest everywhere in the cell.
 */
HOEMBEDCORE_EXPORT double LagrangeTetDetBernsteinMin(
  const LagrangeTetBasis& b, const double* x, double* hi = nullptr);

/// det J > 0 proven over the whole cell (the bound above, refined by subdivision).
HOEMBEDCORE_EXPORT bool LagrangeTetIsValid(const LagrangeTetBasis& b, const double* x);

/**
 * Angle-weighted smooth normals at the boundary nodes of a Lagrange tet mesh (paper
 * eq. 6-7 at any order): at each node of each boundary face, the exact unit normal of
 * the curved face there (dx/du x dx/dv), weighted by the face's angle at the node (the
 * angle between its two edge tangents at a corner, pi elsewhere). `corners` is the
 * topology of the mesh's corner tets (TetMeshTopology::Build over the 4 corners of every
 * cell, nodesPerCell 4), whose boundary faces point outward. `normals`: 3 per mesh node,
 * (0, 0, 0) at interior nodes and where the contributions cancel (as
 * hoembed::ComputeBoundaryNodeNormals). The field inside a face is sum_k N_k(pc) n_k
 * over the cell's nodes (the others' shape functions vanish on the face), normalised.
 */
HOEMBEDCORE_EXPORT void ComputeLagrangeBoundaryNormals(const LagrangeTetBasis& b,
  const TetMeshTopology& corners, const double* points, const std::int64_t* conn, double* normals);

/// Gather the nodes of cell c (3 doubles each) from a point array.
inline void GatherCell(
  const double* points, const std::int64_t* conn, int npc, std::int64_t c, double* out)
{
  const std::int64_t* ids = conn + npc * c;
  for (int k = 0; k < npc; ++k)
  {
    const double* p = points + 3 * ids[k];
    out[3 * k] = p[0];
    out[3 * k + 1] = p[1];
    out[3 * k + 2] = p[2];
  }
}
} // namespace hoembed

#endif
