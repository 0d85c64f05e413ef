/**
 * @file hoembedTetMeshTopology.h
 * @brief Adjacency of a tet4 / tet10 mesh: face neighbours, boundary faces (tri3 / tri6
 * patches), boundary-edge neighbours and the boundary faces around each node.
 *
 * Plain C++ kernel. Built in time linear in the mesh size for bounded node valence
 * (faces and edges are bucketed by their smallest node id, each bucket sorted: a node
 * shared by k cells costs O(k log k), no global sort and no hashing).
 */
#ifndef hoembedTetMeshTopology_h
#define hoembedTetMeshTopology_h

#include "hoembedCoreModule.h"

#include <cstdint>
#include <string>
#include <vector>

namespace hoembed
{
class HOEMBEDCORE_EXPORT TetMeshTopology
{
public:
  using Id = std::int64_t;

  /**
   * Build the adjacency of `numberOfCells` cells of `nodesPerCell` (4 or 10) nodes each,
   * connectivity flattened in `conn` (VTK node order), node ids in [0, numberOfPoints).
   * Returns an empty string on success, otherwise a description of the problem (node id
   * out of range, a face shared by more than two cells, repeated nodes in a cell,
   * negative counts, tet10 neighbours sharing a face's corners but not its mid-edge
   * nodes). On failure the topology is left empty. Cells are expected positively
   * oriented: boundary faces then point outward.
   */
  std::string Build(const Id* conn, Id numberOfCells, int nodesPerCell, Id numberOfPoints);

  int NodesPerCell = 10;
  Id NumberOfCells = 0;
  Id NumberOfPoints = 0;

  /// 4 per cell: the cell across local face f (hoembed::TetFaceNodes order), -1 on the boundary.
  std::vector<Id> FaceNeighbor;
  /// 4 per cell: index of the boundary face that local face f is, or -1 for interior faces.
  std::vector<Id> CellBoundaryFace;

  /// Boundary faces: owning cell, its local face, and the face's nodes (3 for tet4, 6 for
  /// tet10, tri6 order: corners a b c, mids ab bc ca), oriented outward.
  std::vector<Id> BoundaryFaceCell;
  std::vector<int> BoundaryFaceLocal;
  std::vector<Id> BoundaryFaceNodes;
  Id GetNumberOfBoundaryFaces() const
  {
    return static_cast<Id>(BoundaryFaceCell.size());
  }
  int GetNodesPerFace() const
  {
    return NodesPerCell == 10 ? 6 : 3;
  }

  /// 3 per boundary face: the boundary face across edge ab, bc, ca; -1 when the edge has
  /// no other boundary face or more than one (non-manifold boundary edge).
  std::vector<Id> BoundaryFaceNeighbor;
  /// Number of boundary edges shared by more than two boundary faces.
  Id NumberOfNonManifoldBoundaryEdges = 0;

  /// Unique boundary edges: 2 corner ids each (+ the mid node for tet10, else -1).
  std::vector<Id> BoundaryEdgeNodes; // 3 per edge: a, b, mid
  Id GetNumberOfBoundaryEdges() const
  {
    return static_cast<Id>(BoundaryEdgeNodes.size() / 3);
  }

  /// Boundary faces around each node (CSR): faces of node i are
  /// NodeFaces[NodeFaceOffsets[i] .. NodeFaceOffsets[i+1]).
  std::vector<Id> NodeFaceOffsets;
  std::vector<Id> NodeFaces;
  bool IsBoundaryNode(Id i) const
  {
    return NodeFaceOffsets[i + 1] > NodeFaceOffsets[i];
  }

private:
  std::string BuildImpl(const Id* conn, Id numberOfCells, int nodesPerCell, Id numberOfPoints);

  /// Working memory of Build (faces and boundary edges bucketed by their smallest node,
  /// the per-node stamps of the repeated-node check), kept so that building again reuses
  /// it.
  template <int K>
  struct Keyed
  {
    Id Key[K]; ///< node ids, ascending
    Id Item;
  };
  std::vector<Keyed<3>> SortedFaces;
  std::vector<Keyed<2>> SortedEdges;
  std::vector<Id> BucketOffsets;
  std::vector<Id> NodeStamp;
};
} // namespace hoembed

#endif
