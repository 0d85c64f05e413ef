/**
 * @file hoembedEmbeddingMesh.h
 * @brief The rest FE mesh prepared for embedding: topology, smooth nodal normals, the
 * monomial maps of every cell and boundary face (and of the interpolated normal field on
 * each boundary face), a box grid (and, when first needed, a box tree) over the boundary
 * faces, a box grid
 * over the cells, and each cell's straight tet with its edge bumps.
 *
 * Plain C++ kernel; read-only after Build (but for the face tree's one-time build, which
 * is synchronised), so any number of threads may query it.
 */
#ifndef hoembedEmbeddingMesh_h
#define hoembedEmbeddingMesh_h

#include "hoembedClosestPoint.h"
#include "hoembedBoxGrid.h"
#include "hoembedAabbTree.h"
#include "hoembedFiltersEmbeddingModule.h"
#include "hoembedTetBarycentric.h"
#include "hoembedTetMeshTopology.h"

#include <atomic>
#include <mutex>
#include <string>
#include <vector>

namespace hoembed
{
class HOEMBEDFILTERSEMBEDDING_EXPORT EmbeddingMesh
{
public:
  using Id = TetMeshTopology::Id;

  /**
   * Prepare a tet4 (nodesPerCell 4) or tet10 (10) mesh: `points` 3 doubles per node,
   * `conn` nodesPerCell ids per cell in VTK order. Returns "" or a description of the
   * problem (topology errors of TetMeshTopology::Build, no boundary). Threading: the cell
   * data (maps, boxes, barycentric forms, cell grid) and the boundary data (topology, normals, face
   * maps, face grid) are built as two parallel tasks (hoembedParallel.h), each parallel per item;
   * the result does not depend on the number of threads.
   */
  std::string Build(
    const double* points, Id numberOfPoints, const Id* conn, Id numberOfCells, int nodesPerCell);
  /// The same, taking over the node coordinates (3 per node) and the connectivity
  /// (nodesPerCell per cell) without copying them (pass rvalues).
  std::string Build(std::vector<double> points, std::vector<Id> conn, int nodesPerCell);
  /// The same from the node coordinates and connectivity already in Points and
  /// Connectivity. A mesh prepared again reuses the memory of its previous preparation
  /// (vectors keep their capacity), so repeated preparations touch no fresh pages.
  /// With `firstInvalidCell`, every cell is also checked for det J > 0 throughout (tet10:
  /// Bernstein coefficients of det J, then hoembed::Tet10IsValid; tet4: det J clear of
  /// round-off) in the same pass that builds its map, and the lowest failing cell is
  /// stored there (the number of cells when all pass). The mesh is prepared either way;
  /// the caller decides what an invalid cell means.
  std::string Prepare(int nodesPerCell, Id* firstInvalidCell = nullptr);

  TetMeshTopology Topology;
  std::vector<double> Points;       ///< 3 per node
  std::vector<Id> Connectivity;     ///< nodesPerCell per cell
  std::vector<double> NodalNormals; ///< 3 per node (ComputeBoundaryNodeNormals)
  std::vector<QuadraticMap> CellMaps;
  std::vector<QuadraticMap> FaceMaps;   ///< per boundary face, Dim 2
  std::vector<QuadraticMap> NormalMaps; ///< per boundary face: sum_I N_I(u, v) nbar_I
  /// Per boundary face: unit normal n of the corner plane, offset c = n . x_a, and the
  /// range [lo, hi] of n . x - c over the face's Bezier control points (the face lies in
  /// that slab): 6 doubles n, c, lo, hi.
  std::vector<double> FaceSlabs;
  /// Per boundary face: the corners a, b, c of its straight triangle and the largest
  /// in-plane (tangential) length t of the curved face's deviation from it (the
  /// deviation x(u, v) - flat(u, v) is a quadratic with Bezier control points 0 at the
  /// corners and 2 (m - (p + q) / 2) at the edges, so its tangential part is at most t):
  /// 10 doubles. t = +inf for a degenerate corner plane (no tangential bound).
  std::vector<double> FaceFlat;
  /// Per cell: its straight tet plus edge bumps (hoembedTetBarycentric.h): the slabs of
  /// the straight faces pushed out by the control points (CellExitFace) and the sweeps
  /// that prove a point away from the cell (TetBarycentricExcludes).
  std::vector<TetBarycentricForm> CellForms;
  /// A box tree over the boundary faces (long-range queries: points far from the mesh),
  /// built at its first use, by one thread, the others waiting (thread safe).
  const AabbTree& GetFaceTree() const;
  BoxGrid FaceGrid;      ///< the face boxes (32 bins per face): short-range queries
  BoxGrid CellGrid;      ///< over the cells' control-point boxes
  double Diagonal = 0.0; ///< bounding-box diagonal of the mesh nodes
  /// Working memory of Prepare (the boxes the grids and the tree are built from), kept
  /// for the next preparation.
  struct BuildScratch
  {
    std::vector<double> CellBoxes, FaceBoxes;
  } Scratch;

private:
  mutable AabbTree FaceTree; // over Scratch.FaceBoxes
  mutable std::mutex FaceTreeMutex;
  mutable std::atomic<bool> FaceTreeBuilt{ false };

public:
  int NodesPerCell() const
  {
    return this->Topology.NodesPerCell;
  }

  /// Lower bound of the squared distance from v to boundary face f: the face lies within
  /// [lo, hi] of its corner plane (FaceSlabs) and within t of the straight triangle in
  /// the plane (FaceFlat), so |v - y|^2 >= (dist_plane(proj v, triangle) - t)_+^2 +
  /// dist(height of v, [lo, hi])^2 for every point y of the face.
  double FaceLowerBound2(Id f, const double v[3]) const;

  /// False when v (with slack tol) is certainly outside cell c (the slabs of CellForms); cheap.
  bool CellMayContain(Id c, const double v[3], double tol) const;

  /// The local face (TetFaceNodes order) of cell c whose slab v (with slack tol) lies
  /// farthest beyond, -1 when v is within all four (CellMayContain).
  int CellExitFace(Id c, const double v[3], double tol) const;

  /// Tet map of cell c at pc (tet4/tet10 shape functions over the cell's nodes).
  void CellPoint(Id c, const double pc[3], double x[3]) const;
};
} // namespace hoembed

#endif
