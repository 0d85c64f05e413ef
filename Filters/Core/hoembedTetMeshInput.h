/**
 * @file hoembedTetMeshInput.h
 * @brief The one reader of an FE mesh (tet10 or tet4) that every stage uses.
 *
 * Reads plain arrays (points, VTK cell types, offsets and connectivity in VTK's
 * vtkCellArray layout) and checks them in one order with one set of messages:
 *  1. there are points and cells;
 *  2. every cell is VTK_QUADRATIC_TETRA (24) or every cell is VTK_TETRA (10), each with
 *     10 or 4 node ids;
 *  3. every node id is in [0, number of points);
 *  4. every coordinate is finite (when points are given);
 *  5. no cell is a ghost (CellGhosts, when given): the FE mesh must be whole on every
 *     process. A ghost cell is a copy of another process's cell, so a mesh with ghosts is
 *     a distributed one (a filter such as D3 or GhostCellsGenerator on the Mesh input):
 *     its ghosts would be elements counted twice, and what is missing from the local part
 *     would silently be missing from every closest-point search and solve.
 * It keeps the connectivity (64-bit ids, npc per cell, back to back), optionally the
 * points as doubles, and the topology fingerprint (hoembed::MeshFingerprint). Element
 * validity (det J > 0) is not checked here: the stages differ in when they need it.
 *
 * VTK-free: a binding fills TetMeshArrays from its own data (see
 * hoembedTetMeshInputVTK.h for vtkUnstructuredGrid).
 */
#ifndef hoembedTetMeshInput_h
#define hoembedTetMeshInput_h

#include "hoembedCoreModule.h"

#include <cstdint>
#include <string>
#include <vector>

namespace hoembed
{
/// Views of a mesh's arrays (nothing owned). Points: exactly one of PointsDouble and
/// PointsFloat (3 values per point), or neither when only the topology is read. Cells:
/// either the 64-bit or the 32-bit pair of offsets (NumberOfCells + 1 values) and
/// connectivity.
struct TetMeshArrays
{
  std::int64_t NumberOfPoints = 0;
  const double* PointsDouble = nullptr;
  const float* PointsFloat = nullptr;
  std::int64_t NumberOfCells = 0;
  const unsigned char* CellTypes = nullptr;
  const std::int64_t* Offsets64 = nullptr;
  const std::int64_t* Connectivity64 = nullptr;
  const std::int32_t* Offsets32 = nullptr;
  const std::int32_t* Connectivity32 = nullptr;
  /// Optional, one per cell: VTK's ghost flags (vtkGhostType); a cell with the
  /// GhostDuplicateCell bit is another process's cell.
  const unsigned char* CellGhosts = nullptr;
  /// Optional, 3 per cell: VTK's HigherOrderDegrees cell data; a VTK_LAGRANGE_HEXAHEDRON
  /// whose degrees are not (p, p, p) for the order its node count gives is refused.
  const double* HigherOrderDegrees = nullptr;
};

/// VTK's vtkDataSetAttributes::DUPLICATECELL (checked where VTK is at hand).
constexpr unsigned char GhostDuplicateCell = 1;

class HOEMBEDCORE_EXPORT TetMeshInput
{
public:
  /// What Read keeps besides the connectivity.
  enum Keep
  {
    KeepTopology = 0,
    KeepPoints = 1,      ///< the points as doubles (Points)
    KeepFingerprint = 2, ///< the fingerprint (Fingerprint)
    /// also accept VTK_LAGRANGE_TETRAHEDRON (71) of order 1-4 (4, 10, 20 or 35 nodes in
    /// VTK's order, one order per mesh): the embedding and the transfer, which handle them
    KeepLagrange = 4,
    /// also accept hexahedra (one type per mesh): VTK_LAGRANGE_HEXAHEDRON (72) of uniform
    /// order 1-3 (8, 27 or 64 nodes: the order is read from the node count),
    /// VTK_TRIQUADRATIC_HEXAHEDRON (29, 27 nodes), VTK_QUADRATIC_HEXAHEDRON (25, 20 nodes)
    KeepHexahedra = 8
  };

  /// Read and check; the empty string on success, else one sentence naming the problem
  /// (the caller prefixes its own name, e.g. through vtkErrorMacro). `keep` is a sum of
  /// Keep values. On failure the members are unspecified.
  std::string Read(const TetMeshArrays& in, int keep);

  /// 24 (VTK_QUADRATIC_TETRA), 10 (VTK_TETRA), 71 (KeepLagrange), 72, 29, 25 (KeepHexahedra)
  int CellType = 0;
  int NodesPerCell = 0; ///< 10 or 4 (Lagrange: 4, 10, 20 or 35; hexahedra: 8, 27, 64, 20)
  std::int64_t NumberOfPoints = 0;
  std::int64_t NumberOfCells = 0;
  std::vector<std::int64_t> Connectivity; ///< NodesPerCell ids per cell
  std::vector<double> Points;             ///< 3 per point (KeepPoints)
  std::string Fingerprint;                ///< 16 hex digits (KeepFingerprint)

  static constexpr int QuadraticTetra = 24;         // VTK_QUADRATIC_TETRA
  static constexpr int LinearTetra = 10;            // VTK_TETRA
  static constexpr int LagrangeTetra = 71;          // VTK_LAGRANGE_TETRAHEDRON
  static constexpr int LagrangeHexahedron = 72;     // VTK_LAGRANGE_HEXAHEDRON
  static constexpr int TriQuadraticHexahedron = 29; // VTK_TRIQUADRATIC_HEXAHEDRON
  static constexpr int QuadraticHexahedron = 25;    // VTK_QUADRATIC_HEXAHEDRON
  /// one of the three hexahedron types
  static bool IsHexahedron(int type)
  {
    return type == LagrangeHexahedron || type == TriQuadraticHexahedron ||
      type == QuadraticHexahedron;
  }
};

/// The first point (index) with a non-finite coordinate, or -1; `xyz` holds 3 per point.
HOEMBEDCORE_EXPORT std::int64_t FirstNonFinitePoint(const double* xyz, std::int64_t n);
HOEMBEDCORE_EXPORT std::int64_t FirstNonFinitePoint(const float* xyz, std::int64_t n);
} // namespace hoembed

#endif
