/**
 * @file hoembedLagrangeEmbedding.h
 * @brief The embedding on VTK's Lagrange tetrahedra of any supported order (1-4): exact
 * closest point on the curved boundary, inside points located exactly, the smooth normal
 * field and the normal offset v = p + d n (or the flagged fallback).
 *
 * The tet4 / tet10 path (EmbeddingMesh, the flood) works on monomial quadratic maps; this
 * one works on any order through the cell's shape functions (hoembedLagrangeTet.h):
 *  - inside: cells whose Bernstein control-point box holds v (a box tree), the map
 *    inverted by damped Newton from the straight tet's barycentric coordinates and from
 *    the centroid; v is inside when the parameters are in the reference tet.
 *  - outside: boundary faces nearest box first (a box tree over the faces' control-point
 *    boxes: the convex hull property). On each face a certified branch and bound over
 *    parametric sub-triangles: each sub-patch's Bernstein net (collocation at its
 *    lattice) gives a box (a lower bound of the distance) and interval bounds of the
 *    Hessian of |x - v|^2; where that Hessian is proven positive definite the function is
 *    convex there, so it lies above its tangent plane at any point c:
 *    f >= f(c) + grad f(c) . (u - c), minimised at a corner. A sub-patch is dropped when
 *    a bound is within `tol` (1e-10 of the diagonal) of the best distance, otherwise it is
 *    split in four; a local projected Newton solve polishes the best candidates. The
 *    result is within tol of the global minimum unless the node budget runs out
 *    (Uncertified).
 *  - normal offset: Newton on x(u, v) + d s / |s| = v, walking to the neighbouring face
 *    across an edge, from the closest point; the fallback v = p + J(pc) q otherwise.
 * One vertex at a time, any number of threads (read-only after Build).
 */
#ifndef hoembedLagrangeEmbedding_h
#define hoembedLagrangeEmbedding_h

#include "hoembedAabbTree.h"
#include "hoembedEmbeddingSearch.h" // VertexEmbedding
#include "hoembedFiltersEmbeddingModule.h"
#include "hoembedLagrangeTet.h"
#include "hoembedTetMeshTopology.h"

#include <string>
#include <vector>

namespace hoembed
{
class HOEMBEDFILTERSEMBEDDING_EXPORT LagrangeEmbeddingMesh
{
public:
  using Id = std::int64_t;

  /**
   * Prepare a Lagrange tet mesh (`nodesPerCell` 4, 10, 20 or 35; nodes in VTK order).
   * Returns "" or the topology problem. With `firstInvalidCell`, every cell's det J is
   * checked by its Bernstein coefficients and the lowest failing cell stored there (the
   * number of cells when all pass).
   */
  std::string Build(std::vector<double> points, std::vector<Id> conn, int nodesPerCell,
    Id* firstInvalidCell = nullptr);

  /// Embed one point (method: EMBED_NORMAL_OFFSET or EMBED_BARYCENTRIC).
  void Embed(const double v[3], int method, VertexEmbedding& out) const;

  /// Closest point of v on the boundary (sqrt of the returned value is the distance):
  /// boundary face, its (u, v), and whether the bound proved it global.
  double ClosestBoundaryPoint(
    const double v[3], Id& face, double uv[2], bool& certified, int* facesSearched = nullptr) const;

  /// q with J(pc) q = v - x(pc) in cell c (the fallback offset); false when J is singular.
  bool Offset(Id c, const double pc[3], const double v[3], double q[3]) const;

  /// x(pc) of cell c.
  void CellPoint(Id c, const double pc[3], double x[3]) const;

  /// Point, tangents and (H: x_uu, x_uv, x_vv) second derivatives of boundary face f at
  /// (u, v) (face corners a, b, c of TetFaceNodes at (0, 0), (1, 0), (0, 1)), from the
  /// face's Bernstein net.
  void FacePoint(Id f, const double uv[2], double x[3], double xu[3] = nullptr,
    double xv[3] = nullptr, double (*H)[3] = nullptr) const;

  const LagrangeTetBasis* Basis = nullptr;
  int NodesPerCell = 0;
  std::vector<double> Points;       ///< 3 per node
  std::vector<Id> Connectivity;     ///< NodesPerCell per cell
  TetMeshTopology Corners;          ///< topology of the corner tets (boundary faces, neighbours)
  std::vector<double> NodalNormals; ///< 3 per node (ComputeLagrangeBoundaryNormals)
  double Diagonal = 0.0;
  /// tolerance of the certified search, relative to Diagonal
  double SearchTolerance = 1e-10;

private:
  void SearchFace(
    Id f, const double v[3], double& best2, Id& bestFace, double bestUV[2], bool& certified) const;

  AabbTree FaceTree, CellTree;
  std::vector<double> TriToBernstein; // (p+1)(p+2)/2 squared
  std::vector<int> TriLattice;        // 3 per control point
  std::vector<double> FaceNets;       // per boundary face: its Bernstein net (3 per point)
};
} // namespace hoembed

#endif
