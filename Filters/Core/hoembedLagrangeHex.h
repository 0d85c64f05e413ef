/**
 * @file hoembedLagrangeHex.h
 * @brief VTK's hexahedra of the tensor-product family: VTK_LAGRANGE_HEXAHEDRON of uniform
 * order 1-3 ((p + 1)^3 nodes), VTK_TRIQUADRATIC_HEXAHEDRON (27 nodes) and
 * VTK_QUADRATIC_HEXAHEDRON (20 nodes, serendipity). Node order, shape functions, the
 * exact tensor-product (Q_p) form of every cell's map, its Bernstein (Bezier) control
 * points, and the validity proof of det J by its Bernstein coefficients.
 *
 * Every supported cell's map lies in Q_p (degree p in each of r, s, t in [0, 1]): the
 * Lagrange and triquadratic cells are Q_p node for node (a permutation), and the
 * serendipity space of the 20-node cell is a subspace of Q_2, so its map evaluated at the
 * 27 points of the Q_2 lattice is that same map, exactly. The geometry code therefore
 * works on one form, the tensor nodal values t[(k (p + 1) + j) (p + 1) + i] at
 * (i, j, k) / p (LagrangeHexToTensor); only the node order and the 20-node shape
 * functions are per type.
 *
 * Node order (checked against vtkLagrangeHexahedron, vtkTriQuadraticHexahedron and
 * vtkQuadraticHexahedron in TestLagrangeHex): corners 0-7 ((0,0,0), (1,0,0), (1,1,0),
 * (0,1,0), then the same at t = 1), then the edges' nodes, the faces' and the body's as
 * vtkHigherOrderHexahedron::PointIndexFromIJK numbers them.
 *
 * Validity: det J lies in Q_{3p-1}; its Bernstein coefficients (tensor collocation at
 * the lattice of that degree, exact) bound it below over the cell. When not conclusive
 * the cell is split in 8 sub-boxes, up to 3 levels; proven when the smallest coefficient
 * is above 1e-9 of the largest magnitude; a lattice value <= 0 is a counterexample.
 *
 * Plain C++ (no VTK); read-only tables built once per type (thread safe).
 */
#ifndef hoembedLagrangeHex_h
#define hoembedLagrangeHex_h

#include "hoembedCoreModule.h"

#include <cstdint>
#include <string>
#include <vector>

namespace hoembed
{
constexpr int HexahedronCellType = 12;             ///< VTK_HEXAHEDRON
constexpr int QuadraticHexahedronCellType = 25;    ///< VTK_QUADRATIC_HEXAHEDRON
constexpr int TriQuadraticHexahedronCellType = 29; ///< VTK_TRIQUADRATIC_HEXAHEDRON
constexpr int LagrangeHexahedronCellType = 72;     ///< VTK_LAGRANGE_HEXAHEDRON
/// The largest node count of a supported hexahedron, and of its tensor form (order 3).
constexpr int MaxLagrangeHexNodes = 64;

struct HOEMBEDCORE_EXPORT LagrangeHexBasis
{
  int CellType = 0;
  int Order = 0;         ///< p: the tensor form's degree per direction
  int NumberOfNodes = 0; ///< the VTK cell's
  int TensorNodes = 0;   ///< (p + 1)^3
  /// per VTK node: its lattice index (i, j, k), 3 per node (multiples of 1/p)
  std::vector<int> Lattice;
  /// 20-node cell: tensor values = ToTensor * nodal values (27 x 20, row-major); empty
  /// for the tensor types, whose TensorNode[l] is the VTK node at tensor index l
  std::vector<double> ToTensor;
  std::vector<int> TensorNode;
  /// 1D Lagrange (nodes a / p) to Bernstein values, (p + 1)^2 row-major
  std::vector<double> ToBernstein1D;
  /// det J: degree 3p - 1 per direction, its values at a / (3p - 1) to Bernstein
  int DetDegree = 0;
  std::vector<double> DetToBernstein1D;
};

/// The basis of a cell type and node count (12: 8; 25: 20; 29: 27; 72: 8, 27, 64);
/// null when not supported.
HOEMBEDCORE_EXPORT const LagrangeHexBasis* GetLagrangeHexBasis(int cellType, int nodesPerCell);

/// "VTK_LAGRANGE_HEXAHEDRON of order 2", "VTK_QUADRATIC_HEXAHEDRON", ... for messages.
HOEMBEDCORE_EXPORT std::string HexahedronTypeName(int cellType, int nodesPerCell);

/// Parametric coordinates (r, s, t) in [0, 1]^3 of node k.
HOEMBEDCORE_EXPORT void LagrangeHexNodeParametric(const LagrangeHexBasis& b, int k, double pc[3]);

/// Shape function values N[k] at pc (VTK's node order; the serendipity ones for 20 nodes).
HOEMBEDCORE_EXPORT void LagrangeHexShape(const LagrangeHexBasis& b, const double pc[3], double* N);

/// The tensor form (TensorNodes values, 3 each) of a nodal field y (3 per node, VTK order).
HOEMBEDCORE_EXPORT void LagrangeHexToTensor(const LagrangeHexBasis& b, const double* y, double* t);

/**
 * x and J[i] = dx/dpc_i (and H[i][j] = d2x / dpc_i dpc_j when H is not null) of a tensor
 * form t of degree p (3 doubles per lattice node, i fastest).
 */
HOEMBEDCORE_EXPORT void EvaluateTensorHex(int p, const double* t, const double pc[3], double x[3],
  double J[3][3], double (*H)[3][3] = nullptr);

/// Bernstein control points (3 each, the tensor order) of a tensor form t of degree p.
HOEMBEDCORE_EXPORT void TensorHexToBernstein(
  const LagrangeHexBasis& b, const double* t, double* control);

/// det J > 0 proven over the whole cell; `tensor`: the cell's tensor form.
HOEMBEDCORE_EXPORT bool LagrangeHexIsValid(const LagrangeHexBasis& b, const double* tensor);

/// The hex corners of local face lf (0-5: r = 0, r = 1, s = 0, s = 1, t = 0, t = 1) at
/// its (u, v) = (0,0), (1,0), (1,1), (0,1); the face's u and v run along parameters
/// HexFaceU[lf] and HexFaceV[lf], and du x dv points out of the cell.
HOEMBEDCORE_EXPORT extern const int HexFaceCorners[6][4];
HOEMBEDCORE_EXPORT extern const int HexFaceU[6];
HOEMBEDCORE_EXPORT extern const int HexFaceV[6];

/// Local face lf at (u, v) to the cell's (r, s, t).
HOEMBEDCORE_EXPORT void HexFaceToParametric(int lf, const double uv[2], double pc[3]);

/**
 * The boundary faces (faces of one cell only, by their 4 corners) of a hexahedral mesh,
 * in (cell, local face) order: `faceCell`, `faceLocal`, and `cellFace` (6 per cell: the
 * boundary face index, -1 for an interior face). "" or the problem.
 */
HOEMBEDCORE_EXPORT std::string FindHexBoundaryFaces(const std::int64_t* conn, std::int64_t ncells,
  int nodesPerCell, std::vector<std::int64_t>& faceCell, std::vector<int>& faceLocal,
  std::vector<std::int64_t>& cellFace);

/**
 * Angle-weighted smooth normals at the nodes of the boundary faces (paper eq. 6-7 at any
 * order): at each node of each boundary face, the exact unit normal of the curved face
 * there, weighted by the face's angle at the node (between its two edges at a corner, pi
 * elsewhere); unit, or (0, 0, 0) at interior nodes and where the contributions cancel.
 * `normals`: 3 per mesh node (npts nodes).
 */
HOEMBEDCORE_EXPORT void ComputeHexBoundaryNormals(const LagrangeHexBasis& b,
  const std::vector<std::int64_t>& faceCell, const std::vector<int>& faceLocal,
  const double* points, std::int64_t npts, const std::int64_t* conn, double* normals);
} // namespace hoembed

#endif
