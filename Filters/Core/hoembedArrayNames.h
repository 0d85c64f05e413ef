/**
 * @file hoembedArrayNames.h
 * @brief The array-name contract between the stages, and the embedding methods.
 *
 * Array names are part of the API (tests, examples and users rely on them): every stage
 * reads and writes them through these constants, so a name is spelled once.
 *
 * FE mesh (mesher output, stepper input/output):
 *  - cells: MinScaledJacobian (double); points: BoundaryNode (uchar)
 *  - stepper input points: Fixed (nonzero = clamped)
 *  - stepper output points: Displacement, Velocity (3 doubles), NodalRotation (9 doubles,
 *    row-major); cells: VonMisesStress
 * Embedded surface (embedding output, transfer input), point data:
 *  - EmbeddingCellId (vtkIdType), EmbeddingParametricCoords (3 doubles, VTK r s t),
 *    EmbeddingDistance (double), EmbeddingResidual (double), EmbeddingFace (signed char)
 *  - field data: EmbeddingMethod (string, see EmbeddingMethodName),
 *    EmbeddingMeshFingerprint (string, hoembed::MeshFingerprint of the rest mesh)
 */
#ifndef hoembedArrayNames_h
#define hoembedArrayNames_h

#include <cstring>

namespace hoembed
{
namespace ArrayNames
{
// FE mesh
constexpr const char* MinScaledJacobian = "MinScaledJacobian";
constexpr const char* BoundaryNode = "BoundaryNode";
// mesher output, field data (the run's statistics)
constexpr const char* RelaxedNodeCount = "RelaxedNodeCount";
constexpr const char* CurvedNodeCount = "CurvedNodeCount";
constexpr const char* EnvelopeNodeCount = "EnvelopeNodeCount";
constexpr const char* BoundaryCrossingsFound = "BoundaryCrossingsFound";
constexpr const char* BoundaryCrossingsLeft = "BoundaryCrossingsLeft";
constexpr const char* PoorElementCount = "PoorElementCount";
constexpr const char* MinScaledJacobianQuantiles = "MinScaledJacobianQuantiles";
constexpr const char* MaxSurfaceDeviation = "MaxSurfaceDeviation";
constexpr const char* EnvelopeOffset = "EnvelopeOffset";
constexpr const char* Fixed = "Fixed";
constexpr const char* Displacement = "Displacement";
constexpr const char* Velocity = "Velocity";
constexpr const char* NodalRotation = "NodalRotation";
constexpr const char* VonMisesStress = "VonMisesStress";
// stepper output, field data
constexpr const char* KineticEnergy = "KineticEnergy";
constexpr const char* StrainEnergy = "StrainEnergy";
constexpr const char* SolverIterations = "SolverIterations";
// a frame's time in field data (the package's simulate() frames; write_series reads it):
// the name VTK's XML readers and pyvista give a dataset's time
constexpr const char* TimeValue = "TimeValue";
// embedded surface, point data
constexpr const char* EmbeddingCellId = "EmbeddingCellId";
constexpr const char* EmbeddingParametricCoords = "EmbeddingParametricCoords";
constexpr const char* EmbeddingDistance = "EmbeddingDistance";
constexpr const char* EmbeddingResidual = "EmbeddingResidual";
constexpr const char* EmbeddingFace = "EmbeddingFace";
/// transfer output: area-weighted point normals for shading (VTK's usual name)
constexpr const char* Normals = "Normals";
/// diagnostics: the closest distance to the boundary, Newton iterations, elements visited
constexpr const char* EmbeddingClosestDistance = "EmbeddingClosestDistance";
constexpr const char* EmbeddingIterations = "EmbeddingIterations";
constexpr const char* EmbeddingElementsVisited = "EmbeddingElementsVisited";
/// 1 where v = p + d n has no solution and v = p + J(p) q is used instead
constexpr const char* EmbeddingFallback = "EmbeddingFallback";
/// q of those vertices (3 doubles; written only when some vertex falls back)
constexpr const char* EmbeddingFallbackOffset = "EmbeddingFallbackOffset";
/// Every array of the embedding (and its diagnostics) starts with this: a transfer drops
/// them from its output, since they describe the rest state.
constexpr const char* EmbeddingPrefix = "Embedding";
// embedded surface, field data
constexpr const char* EmbeddingMethod = "EmbeddingMethod";
constexpr const char* EmbeddingMeshFingerprint = "EmbeddingMeshFingerprint";
constexpr const char* NumberOfFallbackPoints = "NumberOfFallbackPoints";
} // namespace ArrayNames

/// The two embeddings (values equal vtkEmbeddingCoordinatesFilter's NORMAL_OFFSET and
/// BARYCENTRIC, and the kernels' method argument).
enum class EmbeddingMethod : int
{
  NormalOffset = 0,
  Barycentric = 1
};

/// The value written to / read from the EmbeddingMethod field array.
inline const char* EmbeddingMethodName(EmbeddingMethod m)
{
  return m == EmbeddingMethod::Barycentric ? "barycentric" : "normal-offset";
}

/// False for a name that is neither method.
inline bool ParseEmbeddingMethod(const char* name, EmbeddingMethod& m)
{
  if (name && std::strcmp(name, "normal-offset") == 0)
  {
    m = EmbeddingMethod::NormalOffset;
    return true;
  }
  if (name && std::strcmp(name, "barycentric") == 0)
  {
    m = EmbeddingMethod::Barycentric;
    return true;
  }
  return false;
}
} // namespace hoembed

#endif
