/**
 * @file hoembedTransferDriver.h
 * @brief The deformation transfer as one VTK-free driver: plain arrays in, plain arrays out.
 *
 * What vtkDeformationTransferFilter does between reading its inputs and writing its
 * output, so that any binding (VTK's, or a Python module over plain arrays) runs the same
 * code. Four steps, each cached across frames by the driver:
 *  1. SetMeshTopology: the FE mesh's cells (hoembed::TetMeshInput: types, connectivity,
 *     node ranges, fingerprint) and the boundary topology; rebuilt only when the
 *     fingerprint, the cell order or the number of points changes.
 *  2. BuildPlan: one TransferEntry per surface vertex from the embedding arrays, checked
 *     (cell ids whole and in range, finite values, parametric coordinates and distances
 *     in range, a boundary face for every offset vertex).
 *  3. EvaluateFrame: per frame, from the deformed points: finite check, inverted cells
 *     (counted, a warning), the cell maps, the nodal normals (recompute, rotate or
 *     deform, paper eq. 6-7 and §5.1), the face normal fields, then v' = p' + d n'.
 *  4. SetPolygons / ComputeVertexNormals: optional area-weighted vertex normals of the
 *     transferred surface (polygon incidence cached).
 * The checks of what the binding read, before the steps that use it (so that every
 * binding refuses the same inputs with the same sentences; a binding only reads its
 * objects and passes shapes and arrays): CheckMeshSize before step 1, CheckSurface
 * (field data and embedding arrays) before step 2, FrameArraysUsed (which deformed-mesh
 * arrays a normal mode reads) before step 3.
 * Errors come back as one sentence (empty: success); the binding adds its name.
 *
 * Threading: every loop runs through the ParallelFor given to the constructor (serial by
 * default); the results do not depend on how the ranges are split.
 */
#ifndef hoembedTransferDriver_h
#define hoembedTransferDriver_h

#include "hoembedArrayNames.h"
#include "hoembedFiltersTransferModule.h"
#include "hoembedLagrangeHex.h"
#include "hoembedLagrangeTet.h"
#include "hoembedPropertyRange.h"
#include "hoembedTetMeshInput.h"
#include "hoembedTetMeshTopology.h"
#include "hoembedTransferKernel.h"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace hoembed
{
/// Runs body(begin, end) over subranges of [0, n), ranges of about `grain` items.
using ParallelFor = std::function<void(
  std::int64_t n, std::int64_t grain, const std::function<void(std::int64_t, std::int64_t)>& body)>;

/// The embedding arrays of the surface, one value (or 3) per vertex, as doubles.
struct TransferEmbedding
{
  std::int64_t NumberOfVertices = 0;
  EmbeddingMethod Method = EmbeddingMethod::NormalOffset;
  const double* CellIds = nullptr;          ///< EmbeddingCellId
  const double* ParametricCoords = nullptr; ///< EmbeddingParametricCoords (3 per vertex)
  const double* Distances = nullptr;        ///< EmbeddingDistance (normal-offset only)
  const double* Faces = nullptr;            ///< EmbeddingFace, or null: deduced from pcoords
  /// EmbeddingFallbackOffset (3 per vertex), or null: vertices with a nonzero offset q
  /// move as p' + J'(p) q (the embedding's fallback where v = p + d n has no solution)
  const double* FallbackOffsets = nullptr;
};

/// The shape of a point array as a binding found it (Present false: no array of that name).
struct TransferArrayShape
{
  bool Present = false;
  int Components = 0;
  std::int64_t Tuples = 0;
};

/// What the embedded surface holds, as a binding reads it before copying any value: its
/// field data strings (null: absent, empty or not a string array) and its point arrays'
/// shapes. CheckSurface judges it.
struct TransferSurfaceInfo
{
  std::int64_t NumberOfVertices = 0;
  const char* Method = nullptr;      ///< field data EmbeddingMethod (first value)
  const char* Fingerprint = nullptr; ///< field data EmbeddingMeshFingerprint (first value)
  TransferArrayShape CellIds, ParametricCoords, Distances, Faces, FallbackOffsets;
};

/// Which of the optional embedding arrays the plan reads (CheckSurface's answer; the
/// binding passes those to BuildPlan, as doubles, and null for the others).
struct TransferArraysUsed
{
  bool Distances = false;
  bool Faces = false;
  bool FallbackOffsets = false;
};

/// How the deformed normals n' are obtained (values of vtkDeformationTransferFilter's
/// NormalMode).
enum class TransferNormals : int
{
  Recompute = 0, ///< smooth normals of the deformed boundary (paper eq. 6-7)
  Rotate = 1,    ///< rest normals rotated by the nodal rotations (paper §5.1)
  Deform = 2     ///< rest normals pushed forward by the nodal deformation gradient
};

/// How the unit point normals of the transferred surface (for shading) are obtained
/// (values of vtkDeformationTransferFilter's PointNormalsMode).
enum class TransferPointNormals : int
{
  /// area-weighted normals of the deformed polygons (Newell), recomputed every frame
  Recompute = 0,
  /// the rest surface's area-weighted normals carried by the deformation: cof(F) n0 at
  /// each vertex's p (hoembed::ComputeNormalCovectors), in the same pass as the positions;
  /// needs the surface's rest points (SetRestSurfacePoints) and the mesh's Displacement
  Transform = 1
};

/// One frame of the deformed mesh (3 doubles per node unless said otherwise).
struct TransferFrame
{
  const double* Points = nullptr;
  TransferNormals Normals = TransferNormals::Recompute;
  const double* Displacements = nullptr; ///< x - X, or null
  const double* Rotations = nullptr;     ///< 9 per node (row-major), or null
  bool CountInverted = true;
  /// When set, EvaluateFrame also writes unit point normals (3 floats per vertex) of the
  /// transferred surface, as PointNormalsMode says (both need SetPolygons first).
  float* PointNormals = nullptr;
  TransferPointNormals PointNormalsMode = TransferPointNormals::Recompute;
};

/// The transfer's settings and their defaults, written once: vtkDeformationTransferFilter
/// initialises its properties from a default-constructed TransferOptions, the package's
/// transfer() its keyword defaults (through the compiled module), and a test checks the
/// ParaView XML's default_values against the filter.
struct TransferOptions
{
  TransferNormals NormalMode = TransferNormals::Recompute;
  /// write unit point normals of the transferred surface, and how
  bool ComputePointNormals = false;
  TransferPointNormals PointNormalsMode = TransferPointNormals::Recompute;
  /// count inverted or degenerate deformed cells (TransferFrame::CountInverted)
  bool CheckInvertedElements = true;
  /// BuildPlan's face tolerance: how close to 0 a parametric coordinate of a point on a
  /// boundary face may be
  double FaceTolerance = 1e-6;
};

/// The valid range of the transfer's numeric property, written once: BuildPlan refuses a
/// value outside it with its sentence; the package (RANGES) and the ParaView XML's range
/// domain (kept inside by a test) read it from here.
constexpr PropertyRange TransferRanges[] = {
  { "FaceTolerance", 0, 1, false, false, false },
};

class HOEMBEDFILTERSTRANSFER_EXPORT TransferDriver
{
public:
  explicit TransferDriver(ParallelFor parallelFor = ParallelFor());

  /// Before step 1: the deformed mesh is not empty (at least 4 points and a cell, a
  /// cell array) and its cells fit the plan's 32-bit cell ids.
  static std::string CheckMeshSize(
    std::int64_t numberOfPoints, std::int64_t numberOfCells, bool hasCells);

  /// Step 1. `cells` needs no points. Sets `rebuilt` when the topology was built anew.
  std::string SetMeshTopology(const TetMeshArrays& cells, bool& rebuilt);
  /// Drop the topology (and so the plan): the next SetMeshTopology rebuilds.
  void ForgetMesh();
  const std::string& GetFingerprint() const
  {
    return this->Fingerprint;
  }
  int GetNodesPerCell() const
  {
    return this->NodesPerCell;
  }
  std::int64_t GetNumberOfCells() const
  {
    return this->NumberOfCells;
  }
  std::int64_t GetNumberOfPoints() const
  {
    return this->NumberOfMeshPoints;
  }

  /// Before step 2 (after step 1), every frame: the surface's field data (an embedding
  /// method, the fingerprint of this mesh) and point arrays (EmbeddingCellId,
  /// EmbeddingParametricCoords, EmbeddingDistance for normal-offset; EmbeddingFace and
  /// EmbeddingFallbackOffset when present: one tuple per vertex, the right number of
  /// components). Sets `method` and which optional arrays the plan reads.
  std::string CheckSurface(
    const TransferSurfaceInfo& surface, EmbeddingMethod& method, TransferArraysUsed& used) const;
  /// Which point arrays of the deformed mesh a frame reads in `normals` mode, given their
  /// shapes (one tuple per node; Displacement 3 components, NodalRotation 9): the others
  /// are passed as null.
  static void FrameArraysUsed(TransferNormals normals, std::int64_t numberOfPoints,
    const TransferArrayShape& displacements, const TransferArrayShape& rotations,
    bool& useDisplacements, bool& useRotations);
  /// The same when the frame also writes point normals in `pointNormals` mode (Transform
  /// reads the displacements for the rest mesh).
  static void FrameArraysUsed(TransferNormals normals, TransferPointNormals pointNormals,
    std::int64_t numberOfPoints, const TransferArrayShape& displacements,
    const TransferArrayShape& rotations, bool& useDisplacements, bool& useRotations);

  /// Step 2 (after step 1). `faceTolerance`: see DeduceBoundaryFace; `meshLength`: the
  /// mesh's bounding-box diagonal (scale of the distance check; <= 0 or not finite: no
  /// distance bound).
  std::string BuildPlan(
    const TransferEmbedding& embedding, double faceTolerance, double meshLength);
  /// False until a plan is built for the current topology.
  bool HasPlan() const
  {
    return this->PlanVersion == this->TopologyVersion;
  }
  std::int64_t GetNumberOfVertices() const
  {
    return static_cast<std::int64_t>(this->Plan.size());
  }

  /// Step 3 (after step 2): deformed vertices into `outDouble` or `outFloat` (3 per
  /// vertex; exactly one given), and point normals when frame.PointNormals is set (after
  /// step 4; Transform falls back to Recompute, with a warning, without the rest surface
  /// points or the Displacement array). `warnings` receives what the binding should
  /// report (inverted cells, a normal mode that falls back to recompute).
  std::string EvaluateFrame(const TransferFrame& frame, double* outDouble, float* outFloat,
    std::vector<std::string>& warnings);
  /// Inverted or degenerate cells of the last frame (0 unless counted).
  std::int64_t GetNumberOfInvertedCells() const
  {
    return this->InvertedCells;
  }

  /// Step 4: the surface's polygons (VTK offsets/connectivity layout) for vertex normals.
  void SetPolygons(const std::int64_t* offsets, const std::int64_t* connectivity,
    std::int64_t numberOfPolygons, std::int64_t numberOfVertices);
  /// Unit area-weighted vertex normals (3 floats per vertex) of the transferred points.
  void ComputeVertexNormals(const double* points, float* normals);
  void ComputeVertexNormals(const float* points, float* normals);
  /// Step 4b (after step 4), for TransferPointNormals::Transform: the surface's rest
  /// points (those its embedding was made from; 3 per vertex). Their area-weighted normals
  /// are kept until the next call, SetPolygons or BuildPlan.
  void SetRestSurfacePoints(const double* points);
  void SetRestSurfacePoints(const float* points);
  bool HasRestSurfaceNormals() const
  {
    return this->RestSurfaceValid;
  }
  /// Transform mode: the vertices of the last frame whose normal was recomputed from the
  /// polygons because the map folds there (det F <= 0 at p, or p in an inverted cell).
  std::int64_t GetNumberOfFoldedNormals() const
  {
    return this->FoldedNormals;
  }

private:
  void For(std::int64_t n, std::int64_t grain,
    const std::function<void(std::int64_t, std::int64_t)>& body) const;
  std::string ComputeNodalNormals(const TransferFrame& frame, std::vector<std::string>& warnings);
  std::string UpdateRestPoints(const TransferFrame& frame);
  template <typename T>
  void VertexNormals(const T* points, float* normals);
  template <typename T>
  void RestSurfacePoints(const T* points);
  template <typename T>
  std::string EvaluatePoints(
    const TransferFrame& frame, T* out, std::vector<std::string>& warnings);

  ParallelFor Parallel;
  // step 1
  std::string Fingerprint;
  int NodesPerCell = 0;
  std::int64_t NumberOfCells = 0;
  std::vector<std::int64_t> Conn;
  TetMeshTopology Topology; // of the corner tets for Lagrange cells of order 3-4
  /// Lagrange tets of order 3-4 (hoembedLagrangeTransfer.h); null for tet4 / tet10
  const LagrangeTetBasis* Lagrange = nullptr;
  std::string EvaluateLagrangeFrame(const TransferFrame& frame, double* outDouble, float* outFloat,
    std::vector<std::string>& warnings);
  /// hexahedra (hoembedLagrangeHex.h); null otherwise. Topology is then empty: the
  /// boundary faces are HexFaceCell / HexFaceLocal, CellFace 6 per cell.
  const LagrangeHexBasis* Hex = nullptr;
  std::vector<std::int64_t> HexFaceCell, HexCellFace;
  std::vector<int> HexFaceLocal;
  std::int64_t NumberOfMeshPoints = 0;
  int TopologyVersion = 0;
  // step 2
  std::vector<TransferEntry> Plan;
  bool PlanHasOffsets = false;
  std::vector<std::int64_t> FallbackVertices; // fallback vertices and their q, 3 each
  std::vector<double> FallbackOffsets;
  EmbeddingMethod PlanMethod = EmbeddingMethod::NormalOffset;
  int PlanVersion = -1;
  // step 3 (per-frame tables, reused)
  std::vector<double> NodalNormals, CellCoeffs, FaceCoeffs;
  std::vector<double> RestPoints, RestNormals;
  bool RestValid = false;
  // rest points (x - u) of the mesh: updated once per frame, RestVersion counts changes
  std::int64_t FrameCount = 0, RestFrame = -1, RestVersion = 0, RestNormalsVersion = -1;
  // step 4b: rest surface normals and the per-vertex covectors (rebuilt when the rest
  // mesh, the plan or the rest surface changed: the versions they were built from)
  std::vector<float> RestSurfaceNormals, Covectors;
  std::vector<double> RestCellCoeffs;
  bool RestSurfaceValid = false;
  std::int64_t PlanStamp = 0, RestSurfaceStamp = 0;
  std::int64_t CovRest = -1, CovPlan = -1, CovSurface = -1;
  std::int64_t FoldedNormals = 0;
  std::vector<unsigned char> FoldedCells; // per cell: inverted this frame (transform mode)
  std::int64_t InvertedCells = 0;
  // step 4
  std::vector<std::int64_t> PolyOffsets, PolyConn, IncOffsets, IncPolys;
  std::vector<std::int32_t> IncPolys32; // used instead of IncPolys when the ids fit
  std::vector<double> PolyNormals;
};
} // namespace hoembed

#endif
