/**
 * @file hoembedCeresReference.h
 * @brief The paper's way of finding closest points, with solvers nobody here wrote: a
 * bound-constrained Levenberg–Marquardt (Ceres) on every candidate boundary face, the
 * face maps evaluated by VTK's own cells.
 *
 * Suwelack et al. solve their closest-point problems with levmar's box-constrained LM.
 * This is that method as an independent reference for vtkEmbeddingCoordinatesFilter: no
 * HOEmbed kernel, shape function, face table or bound is used. Any 3D cell type VTK
 * evaluates works (tetrahedra and hexahedra: linear, quadratic, triquadratic, Lagrange of
 * any order), because the boundary faces are VTK's (vtkCell::GetFace) and their maps and
 * derivatives VTK's (vtkCell::InterpolateFunctions / InterpolateDerivs).
 *
 * - Boundary faces: the faces of the cells whose sorted corner ids occur once.
 * - Distance to a face: LM on the residual x(u, v) - q over the face's parameters with
 *   bounds; a triangle is reached through the collapsed square u = s, v = (1 - s) t,
 *   (s, t) in [0, 1]^2, so that its constraints are bounds. A start at the middle, then,
 *   unless that answer lies a fifth of the face's size beyond the best distance so far, a
 *   grid of StartsPerDirection^2 starts; the smallest distance kept.
 * - Which faces: in increasing order of the distance to their node box grown by
 *   BoxMargin of its diagonal, until that distance exceeds the best found. Node boxes
 *   of curved faces are not guaranteed hulls (as the paper's candidate search is not):
 *   the margin makes a miss unlikely on the test shapes, not impossible.
 * - Inside: for each cell whose grown node box holds q, LM on x(xi) - q over the cell's
 *   parametric domain (a tetrahedron through the collapsed cube, a hexahedron's unit
 *   cube as is), from the middle and then CellStartsPerDirection^3 starts; q is inside
 *   when a residual falls to InsideTolerance of the diagonal.
 *   The distance is then 0, as vtkEmbeddingCoordinatesFilter's EmbeddingClosestDistance.
 *
 * Single threaded: VTK cells keep scratch state in their evaluation calls.
 */
#ifndef hoembedCeresReference_h
#define hoembedCeresReference_h

#include "vtkCell.h"
#include "vtkSmartPointer.h"
#include "vtkUnstructuredGrid.h"

#include <string>
#include <vector>

namespace hoembed_ceres
{
struct CeresOptions
{
  int StartsPerDirection = 3;     ///< starts per face: this squared
  int CellStartsPerDirection = 2; ///< starts per cell of the inside test: this cubed
  double BoxMargin = 0.25;        ///< node boxes grown by this much of their diagonal
  double InsideTolerance = 1e-13; ///< of the mesh diagonal
  int MaxIterations = 100;
};

/// One face or cell: VTK's cell (a copy) and its nodes' coordinates.
struct CeresPiece
{
  vtkSmartPointer<vtkCell> Cell;
  std::vector<double> Nodes;            ///< 3 per node
  double Box[6] = { 0, 0, 0, 0, 0, 0 }; ///< grown node box
  bool Simplex = false;                 ///< triangle face / tetrahedral cell
  bool InterleavedDerivatives = false;  ///< VTK's InterpolateDerivs layout for this cell
  double Size = 0.0;                    ///< node box diagonal
  vtkIdType Source = -1;                ///< the grid's cell id
  int LocalFace = -1;                   ///< the face's number in that cell
};

struct CeresMesh
{
  std::vector<CeresPiece> Faces; ///< boundary faces
  std::vector<CeresPiece> Cells;
  double Diagonal = 0.0;

  /// Returns "" or the problem (no cells, a cell that is not 3D, ...).
  std::string Build(vtkUnstructuredGrid* grid, const CeresOptions& options);
};

struct CeresResult
{
  double Distance = 0.0; ///< 0 inside
  bool Inside = false;
  vtkIdType Cell = -1;           ///< the cell holding q, or the cell of the closest face
  int LocalFace = -1;            ///< -1 inside
  double Point[3] = { 0, 0, 0 }; ///< the closest point (q inside)
  int FacesSolved = 0;
  int CellsSolved = 0;
  int Iterations = 0; ///< LM iterations, all solves
};

/// The distance from q to the mesh (see the file comment).
void CeresDistance(
  const CeresMesh& mesh, const double q[3], const CeresOptions& options, CeresResult& result);
} // namespace hoembed_ceres

#endif
