/**
 * @file hoembedLagrangeHexEmbedding.h
 * @brief The embedding on VTK's hexahedra (hoembedLagrangeHex.h: Lagrange order 1-3,
 * triquadratic, serendipity), the tensor-product twin of hoembedLagrangeEmbedding.h:
 *  - inside: cells whose Bernstein control-point box holds v (a box tree), the map
 *    inverted by damped Newton from the cell's centre and from the parallelepiped of its
 *    corner 0 and edges; v is inside when the parameters are in [0, 1]^3.
 *  - outside: boundary quads (faces of one cell only) nearest box first; on each a
 *    certified branch and bound over parametric sub-squares: the sub-patch's Bernstein
 *    net gives a box (a lower bound) and interval bounds of the Hessian of |x - v|^2;
 *    with the smallest eigenvalue bound lambda, f >= f(c) + grad f(c) . (u - c) +
 *    min(0, lambda) / 2 |u - c|^2, minimised at a corner of the square. A sub-square is
 *    dropped when a bound is within 1e-10 of the diagonal of the best distance, otherwise
 *    split in four; projected Newton polishes. Uncertified when the budget runs out.
 *  - normal offset: Newton on x(u, v) + d s / |s| = v across the quads' edges, from the
 *    closest point; the fallback v = p + J(pc) q otherwise.
 * Every cell is held as its tensor form (exact for every type), so one code serves all.
 * Face f's (u, v) map to the cell's parameters as hoembed::HexFaceToParametric says.
 */
#ifndef hoembedLagrangeHexEmbedding_h
#define hoembedLagrangeHexEmbedding_h

#include "hoembedAabbTree.h"
#include "hoembedEmbeddingSearch.h" // VertexEmbedding
#include "hoembedFiltersEmbeddingModule.h"
#include "hoembedLagrangeHex.h"

#include <string>
#include <vector>

namespace hoembed
{
class HOEMBEDFILTERSEMBEDDING_EXPORT LagrangeHexEmbeddingMesh
{
public:
  using Id = std::int64_t;

  /// Prepare a hexahedral mesh of one type (cellType 12, 25, 29 or 72 and its node
  /// count). Returns "" or the problem; with `firstInvalidCell`, the lowest cell whose
  /// det J is not proven positive (the number of cells when all pass).
  std::string Build(std::vector<double> points, std::vector<Id> conn, int cellType,
    int nodesPerCell, Id* firstInvalidCell = nullptr);

  void Embed(const double v[3], int method, VertexEmbedding& out) const;
  double ClosestBoundaryPoint(
    const double v[3], Id& face, double uv[2], bool& certified, int* facesSearched = nullptr) const;
  bool Offset(Id c, const double pc[3], const double v[3], double q[3]) const;
  void CellPoint(Id c, const double pc[3], double x[3], double J[3][3] = nullptr) const;
  /// The smooth normal field (not normalised) and its derivatives in cell c at pc.
  void CellNormal(Id c, const double pc[3], double s[3], double J[3][3]) const;
  void FacePoint(Id f, const double uv[2], double x[3], double xu[3] = nullptr,
    double xv[3] = nullptr, double (*H)[3] = nullptr) const;

  const LagrangeHexBasis* Basis = nullptr;
  int NodesPerCell = 0;
  std::vector<double> Points;       ///< 3 per node
  std::vector<Id> Connectivity;     ///< NodesPerCell per cell
  std::vector<double> NodalNormals; ///< 3 per node: angle-weighted, unit, 0 inside
  std::vector<Id> FaceCell;         ///< per boundary face
  std::vector<int> FaceLocal;       ///< per boundary face: 0-5
  std::vector<Id> CellFace;         ///< 6 per cell: boundary face or -1
  std::vector<Id> FaceNeighbor;     ///< 4 per face, across edges v=0, u=1, v=1, u=0
  std::vector<Id> FaceCorners;      ///< 4 mesh nodes per face at (0,0), (1,0), (1,1), (0,1)
  std::vector<Id> NodeFaceOffsets, NodeFaces; ///< corner node -> boundary faces
  double Diagonal = 0.0;
  double SearchTolerance = 1e-10;

private:
  void SearchFace(
    Id f, const double v[3], double& best2, Id& bestFace, double bestUV[2], bool& certified) const;

  AabbTree FaceTree, CellTree;
  std::vector<double> Tensors, NormalTensors; ///< per cell: the tensor forms
  std::vector<double> FaceNets;               ///< per face: (p + 1)^2 control points
};
} // namespace hoembed

#endif
