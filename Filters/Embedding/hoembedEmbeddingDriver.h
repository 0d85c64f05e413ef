/**
 * @file hoembedEmbeddingDriver.h
 * @brief The embedding as one VTK-free driver: plain arrays in, plain arrays out.
 *
 * What vtkEmbeddingCoordinatesFilter does between reading its inputs and writing its
 * output, so that any binding (VTK's, or the pip module over numpy arrays) runs the same
 * code:
 *  1. SetSurface: the surface's points (copied as doubles, finite check) and triangles
 *     (polygons fanned, strips split: hoembed::AppendSurfaceTriangles, then checked).
 *  2. PrepareAndOrder: the FE mesh (hoembed::TetMeshInput, then EmbeddingMesh::Prepare
 *     with the validity check) unless the binding keeps the prepared one, and the
 *     surface's order for the flood, as two parallel tasks.
 *  3. Embed: the flood (hoembed::FloodSurface, paper Algorithm 2); on Lagrange tets of
 *     order 3-4 (VTK_LAGRANGE_TETRAHEDRON of 20 or 35 nodes) and on hexahedra
 *     (hoembed::LagrangeHexEmbeddingMesh) one certified search per
 *     vertex instead (hoembed::LagrangeEmbeddingMesh; EmbeddingElementsVisited then
 *     counts the boundary faces searched). Orders 1-2 are tet4 / tet10 node for node.
 *  4. WriteArrays / WriteFallbackOffsets: the per-vertex results in surface point order
 *     into the binding's arrays, with the counts the binding reports.
 * Errors come back as one sentence (empty: success); the binding adds its name.
 *
 * Threading: hoembedParallel.h (vtkSMPTools in the VTK build); results do not depend on
 * the number of threads (the flood's partitions are fixed by the surface).
 */
#ifndef hoembedEmbeddingDriver_h
#define hoembedEmbeddingDriver_h

#include "hoembedEmbeddingFlood.h"
#include "hoembedFiltersEmbeddingModule.h"
#include "hoembedLagrangeEmbedding.h"
#include "hoembedLagrangeHexEmbedding.h"
#include "hoembedPropertyRange.h"
#include "hoembedSurfaceTriangles.h"
#include "hoembedTetMeshInput.h"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace hoembed
{
/// Where WriteArrays puts the results: one value (or 3) per surface point, in its order.
struct EmbeddingOutputArrays
{
  std::int64_t* CellId = nullptr;     ///< EmbeddingCellId
  double* ParametricCoords = nullptr; ///< EmbeddingParametricCoords (3 per point)
  double* Distance = nullptr;         ///< EmbeddingDistance
  double* Residual = nullptr;         ///< EmbeddingResidual
  double* ClosestDistance = nullptr;  ///< EmbeddingClosestDistance
  signed char* Face = nullptr;        ///< EmbeddingFace (-1 for barycentric)
  int* Iterations = nullptr;          ///< EmbeddingIterations
  int* Visited = nullptr;             ///< EmbeddingElementsVisited
  unsigned char* Fallback = nullptr;  ///< EmbeddingFallback
};

/// What WriteArrays found (first*: the lowest surface point id, -1 when none).
struct EmbeddingSummary
{
  std::int64_t Uncertified = 0, FirstUncertified = -1;
  std::int64_t Fallbacks = 0, FirstFallback = -1;
  /// points whose embedding does not reproduce them: EmbeddingResidual over
  /// ResidualTolerance of the mesh's diagonal (the barycentric method outside a curved
  /// mesh, where it extrapolates its closest cell's map); the largest residual, relative
  std::int64_t Inexact = 0, FirstInexact = -1;
  double MaxResidual = 0.0;
  int Method = 0;
};

/// The embedding's settings and their defaults, written once: vtkEmbeddingCoordinatesFilter
/// initialises its properties from a default-constructed EmbeddingOptions, the package's
/// embed() its keyword defaults (through the compiled module), and a test checks the
/// ParaView XML's default_values against the filter.
struct EmbeddingOptions
{
  /// EMBED_NORMAL_OFFSET (the paper's v = p + d n) or EMBED_BARYCENTRIC (the baseline)
  int Method = EMBED_NORMAL_OFFSET;
  /// surface patches flooded in parallel; 0: about one per 1000 triangles, at most 256
  int NumberOfPartitions = 0;
  /// refuse meshes with inverted or degenerate elements (PrepareAndOrder's check)
  bool ValidateElements = true;
  /// keep the prepared mesh while the binding knows it is the same (PrepareAndOrder with
  /// no mesh)
  bool ReuseMeshPreparation = true;
};

/// The valid range of the embedding's numeric property, written once: PrepareAndOrder
/// refuses a value outside it with its sentence; the package (RANGES, check_range) and the
/// ParaView XML's range domain (kept inside by a test) read it from here.
constexpr PropertyRange EmbeddingRanges[] = {
  { "NumberOfPartitions", 0, 1 << 20, false, false, true },
};

/// Relative to the mesh's bounding-box diagonal: a residual above it is reported (an exact
/// embedding's is round-off, under 1e-12 of the diagonal).
constexpr double ResidualTolerance = 1e-6;

/// The warnings of a summary, one sentence each (none when every point is certified and
/// has its normal offset): what the filter and the package's embed() report.
HOEMBEDFILTERSEMBEDDING_EXPORT std::vector<std::string> EmbeddingWarnings(
  const EmbeddingSummary& summary);

class HOEMBEDFILTERSEMBEDDING_EXPORT EmbeddingDriver
{
public:
  /// Step 1. `points`: 3 doubles or floats per point (exactly one given).
  std::string SetSurface(const double* pointsDouble, const float* pointsFloat,
    std::int64_t numberOfPoints, const CellArrayView& polygons, const CellArrayView& strips);
  /// Step 2. `mesh` null: keep the prepared mesh (the binding knows it is the same).
  /// A mesh error is reported before a surface (triangle) error.
  std::string PrepareAndOrder(const TetMeshArrays* mesh, bool validateElements, int partitions);
  /// Forget the prepared mesh (after a failure, or to force a new preparation).
  void ForgetMesh()
  {
    this->Fingerprint.clear();
  }
  const std::string& GetFingerprint() const
  {
    return this->Fingerprint;
  }
  /// Step 3. `method`: EMBED_NORMAL_OFFSET or EMBED_BARYCENTRIC.
  void Embed(int method, const std::function<void(double)>& progress);
  std::int64_t GetNumberOfPoints() const
  {
    return this->NumberOfPoints;
  }
  /// Step 4: the results into `out` (every array given); an error names the first point
  /// with a non-finite result.
  std::string WriteArrays(const EmbeddingOutputArrays& out, EmbeddingSummary& summary) const;
  /// EmbeddingFallbackOffset (3 per point: q of v = p + J q, zero where not a fallback).
  void WriteFallbackOffsets(double* out) const;
  /// Give back surface-sized memory beyond about 64 MiB (kept below that between calls:
  /// the larger the surface, the smaller the share of its page faults in the time).
  void ReleaseLargeSurfaceMemory();

private:
  std::string PrepareMesh(const TetMeshArrays& mesh, bool validateElements);

  double MeshDiagonal() const
  {
    return this->Hexahedra ? this->HexMesh.Diagonal
                           : (this->Lagrange ? this->LagrangeMesh.Diagonal : this->Mesh.Diagonal);
  }

  // mesh-sized: kept
  EmbeddingMesh Mesh;
  /// Lagrange tets of order 3 and 4 (orders 1 and 2 are tet4 and tet10 node for node and
  /// take the EmbeddingMesh path): per-vertex certified search, no flood
  LagrangeEmbeddingMesh LagrangeMesh;
  bool Lagrange = false;
  /// hexahedra (VTK_LAGRANGE_HEXAHEDRON 1-3, hex27, hex20): the same per-vertex search
  LagrangeHexEmbeddingMesh HexMesh;
  bool Hexahedra = false;
  std::string Fingerprint; // of the prepared mesh; empty: none prepared
  // surface-sized
  EmbedWorkspace Flood;
  std::int64_t NumberOfPoints = 0;
  int Method = 0;
  std::vector<double> SurfacePoints;
  std::vector<std::int64_t> Triangles, Order;
  std::vector<VertexEmbedding> Results;
  std::string SurfaceError;
};
} // namespace hoembed

#endif
