/**
 * @file hoembedExactDistance.h
 * @brief Certified brute-force distance from a point to a tet4 / tet10 mesh, written
 * independently of the embedding filter (its own shape functions, boundary extraction,
 * solvers and bounds) to check vtkEmbeddingCoordinatesFilter on every vertex.
 *
 * Boundary distance: global best-first branch and bound over every boundary face
 * (tri6, or tri3 for tet4). A (sub-)triangle of a face is the quadratic map of its
 * parametric sub-triangle; its lower bound is the distance to the flat triangle of its
 * three corners minus the largest deviation of the patch from that triangle,
 * (2/3) max_e |2 m_e - a_e - b_e| (exact for quadratic patches: the patch minus the flat
 * triangle is sum_{i<j} 2 mu_i mu_j (2 m_ij - x_i - x_j), and sum 2 mu_i mu_j <= 2/3).
 * Faces enter the queue with the distance to their Bezier control-point box (a tri6 lies
 * in the convex hull of its control points, corners and 2 m - (a + b) / 2, not of its
 * nodes). A sub-triangle on which the squared distance is provably strongly convex (a
 * lower bound of the smallest eigenvalue of J^T J + sum (x - p) . x_ij from the spread of
 * J and the farthest control point) is solved locally (Newton inside, monotone bisection
 * on its three edges) and certified with the convexity inequality
 * f(xi) >= f(xi*) + grad f(xi*) . (xi - xi*) at its corners; otherwise it is split in
 * four. The search stops when the smallest lower bound left is within the tolerance of
 * the best distance found: Lower <= true distance <= Upper, both reported.
 *
 * Inside: every cell whose control-point box holds the point is inverted by recursive
 * subdivision of its reference tet: sub-tets whose Bezier control-point box is farther
 * than 1e-12 of the diagonal from the point are dropped, Newton runs from the centroid of
 * each sub-tet kept, and the point is inside when a run lands in the reference tet
 * (Newton from a few fixed starts alone can stall on a fold of the map's extension
 * outside the reference tet of a strongly curved cell). Outside is proved when every
 * sub-tet is dropped; sub-tets left at the depth limit are counted (InsideUndecided).
 * VTK's vtkQuadraticTetra / vtkTetra EvaluatePosition is a second opinion
 * (disagreements are counted, VTK's own tolerance aside).
 *
 * Plain C++ except for the VTK cells of the second opinion; thread safe per call
 * (each thread passes its own ExactScratch).
 */
#ifndef hoembedExactDistance_h
#define hoembedExactDistance_h

#include "vtkNew.h"
#include "vtkQuadraticTetra.h"
#include "vtkTetra.h"

#include <cstdint>
#include <string>
#include <vector>

namespace hoembed_exact
{
using Id = std::int64_t;

struct ExactMesh
{
  int NodesPerCell = 10;
  Id NumberOfCells = 0;
  std::vector<double> Points; ///< 3 per node
  std::vector<Id> Cells;      ///< NodesPerCell per cell, VTK order
  /// Boundary faces: 6 node ids each (corners a b c, mid-edge nodes ab bc ca; for tet4
  /// the mids are -1 and the face is flat).
  std::vector<Id> Faces;
  std::vector<double> FaceBox; ///< 6 per face: control-point box
  std::vector<double> CellBox; ///< 6 per cell: control-point box
  double Diagonal = 0.0;       ///< bounding-box diagonal of the nodes

  /// Faces used by exactly one cell are boundary faces. Returns "" or the problem.
  std::string Build(
    const double* points, Id numberOfPoints, const Id* cells, Id numberOfCells, int nodesPerCell);
  Id NumberOfFaces() const
  {
    return static_cast<Id>(this->Faces.size() / 6);
  }
};

struct ExactOptions
{
  double CertifyTolerance = 1e-12; ///< of the diagonal: Upper - Lower at most this
  int MaxDepth = 26;               ///< subdivision levels of one face
  long MaxNodes = 200000;          ///< per query; beyond, the queue's bound is reported
  int InsideMaxDepth = 44;         ///< subdivision levels of a cell's reference tet
  long InsideMaxNodes = 200000;    ///< sub-tets per cell; beyond, the rest is undecided
};

struct ExactResult
{
  double Upper = 0.0; ///< boundary distance, attained at (Face, UV)
  double Lower = 0.0; ///< certified lower bound of the boundary distance
  Id Face = -1;
  double UV[2] = { 0, 0 };
  bool Inside = false; ///< a cell contains the point (own Newton inversion)
  Id InsideCell = -1;
  int InsideCellsVtk = 0; ///< cells VTK's EvaluatePosition puts the point in
  int InsideCellsOwn = 0; ///< cells the own inversion puts the point in
  int CandidateCells = 0; ///< cells whose control box holds the point
  int VtkDisagreements = 0;
  bool InsideVtk = false; ///< some cell contains the point according to VTK
  long Nodes = 0;         ///< branch-and-bound nodes processed
  int DepthLimited = 0;   ///< nodes that hit MaxDepth unresolved
  bool NodeLimited = false;
  long InsideNodes = 0;    ///< sub-tets visited by the inside test, all cells
  int InsideUndecided = 0; ///< sub-tets left holding the point at the limits, all cells
  double Distance() const
  {
    return this->Inside ? 0.0 : this->Upper;
  }
};

struct ExactScratch
{
  struct Item
  {
    double Key;
    Id Face;
    double Q[3][2];
    int Depth; // -1: a face not yet evaluated (Key is its box bound)
    bool operator<(const Item& o) const
    {
      return this->Key > o.Key;
    } // min-heap
  };
  std::vector<Item> Heap;
  vtkNew<vtkQuadraticTetra> Tet10;
  vtkNew<vtkTetra> Tet4;
};

/// Certified boundary distance and inside test of v (see the file comment).
void ExactDistance(const ExactMesh& mesh, const double v[3], const ExactOptions& opt,
  ExactScratch& scratch, ExactResult& res);

/// Print the inside test of v cell by cell (own inversion and VTK) to stderr.
void ExplainInside(const ExactMesh& mesh, const double v[3]);

/// Boundary distance only (used by ExactDistance).
void ExactBoundaryDistance(const ExactMesh& mesh, const double v[3], const ExactOptions& opt,
  ExactScratch& scratch, ExactResult& res);

/// Tet map of cell c (own VTK-order shape functions).
void ExactCellPoint(const ExactMesh& mesh, Id c, const double pc[3], double x[3]);
} // namespace hoembed_exact

#endif
