#include "hoembedTransferDriver.h"

#include "hoembedLagrangeTransfer.h"

#include "hoembedBoundaryNormals.h"
#include "hoembedTransferNormals.h"

#include <algorithm>
#include <atomic>
#include <cfloat>
#include <cmath>
#include <limits>
#include <mutex>
#include <sstream>
#include <utility>

namespace hoembed
{
namespace
{
bool AllFinite(const double* x, std::int64_t n)
{
  for (std::int64_t i = 0; i < n; ++i)
  {
    if (!std::isfinite(x[i]))
    {
      return false;
    }
  }
  return true;
}

// What the plan can check of an embedding read back from a file. p lies in its cell for
// a normal-offset embedding and a few cell sizes outside it at most for a barycentric one
// (extrapolated), but hand-made embeddings (a face plane's projection with a distance)
// extrapolate too, and that maps nothing wrong: parametric coordinates are refused only
// beyond MaxExtrapolation cell sizes, which no surface the mesh approximates comes near.
// A surface may lie far outside a small mesh (the embedding gives such vertices large
// distances, or its flagged fallback; a sphere a million diagonals around a beam is
// carried exactly, Testing/Python/test_embedding_numerics.py), so |d| is refused only
// beyond MaxDistance mesh diagonals: the unit normal n' is known to a few units in the
// last place, so beyond that the round-off of d n' alone exceeds 1e-7 of the diagonal and
// the mesh's deformation no longer reaches the vertex faithfully (a hand-edited 1e12 put
// points 5.8e11 diagonals away under the former bound of 1e13; 1e300 would overflow).
constexpr double MaxExtrapolation = 1e3;
constexpr double MaxDistance = 1e9;
} // namespace

TransferDriver::TransferDriver(ParallelFor parallelFor) : Parallel(std::move(parallelFor)) {}

void TransferDriver::For(std::int64_t n, std::int64_t grain,
  const std::function<void(std::int64_t, std::int64_t)>& body) const
{
  if (n <= 0)
  {
    return;
  }
  if (this->Parallel)
  {
    this->Parallel(n, grain, body);
  }
  else
  {
    body(0, n);
  }
}

//------------------------------------------------------------------------------
std::string TransferDriver::CheckMeshSize(
  std::int64_t numberOfPoints, std::int64_t numberOfCells, bool hasCells)
{
  if (numberOfPoints < 4 || numberOfCells < 1 || !hasCells)
  {
    return "the deformed FE mesh (port 1) is empty";
  }
  if (numberOfCells > INT32_MAX)
  {
    return "the deformed FE mesh has too many cells (" + std::to_string(numberOfCells) + ")";
  }
  return std::string();
}

//------------------------------------------------------------------------------
std::string TransferDriver::SetMeshTopology(const TetMeshArrays& cells, bool& rebuilt)
{
  rebuilt = false;
  TetMeshInput input;
  const std::string readError = input.Read(cells,
    TetMeshInput::KeepFingerprint | TetMeshInput::KeepLagrange | TetMeshInput::KeepHexahedra);
  if (!readError.empty())
  {
    return readError;
  }
  const int npc = input.NodesPerCell;
  if (input.Fingerprint == this->Fingerprint && npc == this->NodesPerCell &&
    this->NumberOfMeshPoints == input.NumberOfPoints)
  {
    return std::string();
  }
  this->Hex =
    TetMeshInput::IsHexahedron(input.CellType) ? GetLagrangeHexBasis(input.CellType, npc) : nullptr;
  if (this->Hex)
  {
    // hexahedra: their boundary quads; the tet tables and topology stay empty
    const std::string problem = FindHexBoundaryFaces(input.Connectivity.data(), input.NumberOfCells,
      npc, this->HexFaceCell, this->HexFaceLocal, this->HexCellFace);
    if (!problem.empty())
    {
      this->ForgetMesh();
      return "invalid FE mesh topology: " + problem;
    }
    this->Lagrange = nullptr;
    this->Topology = TetMeshTopology();
    this->Conn.swap(input.Connectivity);
    this->Fingerprint = input.Fingerprint;
    this->NodesPerCell = npc;
    this->NumberOfCells = input.NumberOfCells;
    this->NumberOfMeshPoints = input.NumberOfPoints;
    ++this->TopologyVersion;
    this->CellCoeffs.clear();
    this->FaceCoeffs.clear();
    this->NodalNormals.assign(3 * static_cast<size_t>(input.NumberOfPoints), 0.0);
    this->RestValid = false;
    this->RestFrame = -1;
    this->RestPoints.clear();
    rebuilt = true;
    return std::string();
  }
  // Lagrange cells of order 3-4: the topology of their corner tets (orders 1-2 are tet4
  // and tet10 node for node)
  this->Lagrange = npc > 10 ? GetLagrangeTetBasis(LagrangeTetOrder(npc)) : nullptr;
  std::vector<std::int64_t> corners;
  if (this->Lagrange)
  {
    corners.resize(4 * static_cast<std::size_t>(input.NumberOfCells));
    for (std::int64_t c = 0; c < input.NumberOfCells; ++c)
      for (int k = 0; k < 4; ++k)
        corners[4 * c + k] = input.Connectivity[npc * c + k];
  }
  const std::string problem = this->Lagrange
    ? this->Topology.Build(corners.data(), input.NumberOfCells, 4, input.NumberOfPoints)
    : this->Topology.Build(
        input.Connectivity.data(), input.NumberOfCells, npc, input.NumberOfPoints);
  if (!problem.empty())
  {
    this->ForgetMesh();
    return "invalid FE mesh topology: " + problem;
  }
  this->Conn.swap(input.Connectivity);
  this->Fingerprint = input.Fingerprint;
  this->NodesPerCell = npc;
  this->NumberOfCells = input.NumberOfCells;
  this->NumberOfMeshPoints = input.NumberOfPoints;
  ++this->TopologyVersion;
  const int tableNodes = this->Lagrange ? 4 : npc; // the tet tables are not used then
  this->CellCoeffs.assign(static_cast<size_t>(CellCoefficientSize(tableNodes)) *
      (this->Lagrange ? 0 : input.NumberOfCells),
    0.0);
  this->FaceCoeffs.assign(static_cast<size_t>(FaceCoefficientSize(tableNodes)) *
      (this->Lagrange ? 0 : this->Topology.GetNumberOfBoundaryFaces()),
    0.0);
  this->NodalNormals.assign(3 * static_cast<size_t>(input.NumberOfPoints), 0.0);
  this->RestValid = false;
  this->RestFrame = -1;
  this->RestPoints.clear();
  rebuilt = true;
  return std::string();
}

void TransferDriver::ForgetMesh()
{
  this->Fingerprint.clear();
  this->NodesPerCell = 0;
  this->PlanVersion = -1;
}

//------------------------------------------------------------------------------
namespace
{
bool Fits(const TransferArrayShape& a, int components, std::int64_t tuples)
{
  return a.Present && a.Components == components && a.Tuples == tuples;
}
} // namespace

std::string TransferDriver::CheckSurface(
  const TransferSurfaceInfo& s, EmbeddingMethod& method, TransferArraysUsed& used) const
{
  used = TransferArraysUsed();
  if (!s.Method)
  {
    return "the surface (port 0) has no field data EmbeddingMethod: is it the output of "
           "vtkEmbeddingCoordinatesFilter?";
  }
  if (!ParseEmbeddingMethod(s.Method, method))
  {
    return std::string("unknown EmbeddingMethod '") + s.Method +
      "' (expected normal-offset or barycentric)";
  }
  if (!s.Fingerprint)
  {
    return "the surface (port 0) has no field data EmbeddingMeshFingerprint";
  }
  if (this->Fingerprint != s.Fingerprint)
  {
    std::ostringstream msg;
    msg << "the FE mesh (port 1) is not the mesh the surface was embedded in: mesh "
           "fingerprint "
        << this->Fingerprint << " (" << this->NumberOfMeshPoints << " points, "
        << this->NumberOfCells << " cells), embedding fingerprint " << s.Fingerprint;
    return msg.str();
  }
  const std::int64_t n = s.NumberOfVertices;
  const bool offset = method == EmbeddingMethod::NormalOffset;
  std::string missing;
  if (!Fits(s.CellIds, 1, n))
  {
    missing += " EmbeddingCellId (1 component)";
  }
  if (!Fits(s.ParametricCoords, 3, n))
  {
    missing += " EmbeddingParametricCoords (3 components)";
  }
  if (offset && !Fits(s.Distances, 1, n))
  {
    missing += " EmbeddingDistance (1 component)";
  }
  if (s.Faces.Present && !Fits(s.Faces, 1, n))
  {
    missing += " EmbeddingFace (1 component)";
  }
  // the fallback offsets belong to the normal-offset embedding only
  if (offset && s.FallbackOffsets.Present && !Fits(s.FallbackOffsets, 3, n))
  {
    missing += " EmbeddingFallbackOffset (3 components)";
  }
  if (!missing.empty())
  {
    return "the surface (port 0) lacks point data arrays, or they do not have one tuple per "
           "point:" +
      missing;
  }
  used.Distances = offset;
  used.Faces = s.Faces.Present;
  used.FallbackOffsets = offset && s.FallbackOffsets.Present;
  return std::string();
}

void TransferDriver::FrameArraysUsed(TransferNormals normals, std::int64_t numberOfPoints,
  const TransferArrayShape& displacements, const TransferArrayShape& rotations,
  bool& useDisplacements, bool& useRotations)
{
  // recompute needs neither; deform the displacements; rotate both (the displacements
  // for its fallback where rotations are missing). A wrong shape counts as missing.
  useDisplacements =
    normals != TransferNormals::Recompute && Fits(displacements, 3, numberOfPoints);
  useRotations = normals == TransferNormals::Rotate && Fits(rotations, 9, numberOfPoints);
}

void TransferDriver::FrameArraysUsed(TransferNormals normals, TransferPointNormals pointNormals,
  std::int64_t numberOfPoints, const TransferArrayShape& displacements,
  const TransferArrayShape& rotations, bool& useDisplacements, bool& useRotations)
{
  FrameArraysUsed(
    normals, numberOfPoints, displacements, rotations, useDisplacements, useRotations);
  useDisplacements = useDisplacements ||
    (pointNormals == TransferPointNormals::Transform && Fits(displacements, 3, numberOfPoints));
}

//------------------------------------------------------------------------------
std::string TransferDriver::BuildPlan(
  const TransferEmbedding& em, double faceTolerance, double meshLength)
{
  this->PlanVersion = -1;
  const std::string rangeError = CheckPropertyRange(TransferRanges[0], faceTolerance);
  if (!rangeError.empty())
  {
    return rangeError;
  }
  const std::int64_t numVerts = em.NumberOfVertices;
  const std::int64_t numCells = this->NumberOfCells;
  const bool offset = em.Method == EmbeddingMethod::NormalOffset;
  this->Plan.resize(static_cast<size_t>(numVerts));
  this->FallbackVertices.clear();
  this->FallbackOffsets.clear();
  std::int64_t badCell = 0, badValue = 0, badRange = 0, badFace = 0, firstBad = -1;
  bool hasOffsets = false;
  const double maxDistance =
    std::isfinite(meshLength) && meshLength > 0.0 ? MaxDistance * meshLength : DBL_MAX;
  const TetMeshTopology& topo = this->Topology;
  for (std::int64_t i = 0; i < numVerts; ++i)
  {
    TransferEntry& e = this->Plan[i];
    const double cid = em.CellIds[i];
    if (!(cid >= 0 && cid < numCells && cid == std::floor(cid)))
    {
      ++badCell;
      firstBad = firstBad < 0 ? i : firstBad;
      e = TransferEntry{ { 0, 0, 0 }, 0.0, 0, -1 };
      continue;
    }
    e.Cell = static_cast<std::int32_t>(cid);
    for (int k = 0; k < 3; ++k)
    {
      e.PC[k] = em.ParametricCoords[3 * i + k];
    }
    e.Distance = 0.0;
    e.Face = -1;
    if (offset)
    {
      e.Distance = em.Distances[i];
    }
    if (!std::isfinite(e.PC[0]) || !std::isfinite(e.PC[1]) || !std::isfinite(e.PC[2]) ||
      !std::isfinite(e.Distance))
    {
      ++badValue;
      firstBad = firstBad < 0 ? i : firstBad;
      e.Distance = 0.0;
      e.PC[0] = e.PC[1] = e.PC[2] = 0.0;
      continue;
    }
    const bool pcNear = std::fabs(e.PC[0]) <= MaxExtrapolation &&
      std::fabs(e.PC[1]) <= MaxExtrapolation && std::fabs(e.PC[2]) <= MaxExtrapolation;
    if (!pcNear || std::fabs(e.Distance) > maxDistance)
    {
      ++badRange;
      firstBad = firstBad < 0 ? i : firstBad;
      e.Distance = 0.0;
      e.PC[0] = e.PC[1] = e.PC[2] = 0.0;
      continue;
    }
    const double* q = em.FallbackOffsets ? em.FallbackOffsets + 3 * i : nullptr;
    if (q && (q[0] != 0.0 || q[1] != 0.0 || q[2] != 0.0))
    {
      if (!std::isfinite(q[0]) || !std::isfinite(q[1]) || !std::isfinite(q[2]))
      {
        ++badValue;
        firstBad = firstBad < 0 ? i : firstBad;
        continue;
      }
      // a fallback vertex: p' (no normal offset), then p' + J' q after the main loop
      e.Distance = 0.0;
      this->FallbackVertices.push_back(i);
      this->FallbackOffsets.insert(this->FallbackOffsets.end(), q, q + 3);
      continue;
    }
    if (e.Distance == 0.0)
    {
      continue;
    }
    int local = -1;
    if (em.Faces)
    {
      local = static_cast<int>(em.Faces[i]);
    }
    if (this->Hex)
    {
      // hexahedra: the face is the local face (0-5); the evaluation needs only the cell
      if (local >= 0 && local < 6 && this->HexCellFace[6 * e.Cell + local] >= 0)
        e.Face = local;
    }
    else if (local >= 0 && local < 4 && topo.CellBoundaryFace[4 * e.Cell + local] >= 0)
    {
      e.Face = static_cast<std::int32_t>(4 * topo.CellBoundaryFace[4 * e.Cell + local] + local);
    }
    else if (local < 0)
    {
      e.Face = DeduceBoundaryFace(topo, e.Cell, e.PC, faceTolerance);
    }
    if (e.Face < 0)
    {
      ++badFace;
      firstBad = firstBad < 0 ? i : firstBad;
      continue;
    }
    hasOffsets = true;
  }
  if (badCell || badValue || badRange || badFace)
  {
    std::ostringstream msg;
    msg << "invalid embedding for this mesh: " << badCell << " vertices with a cell id outside [0, "
        << numCells << ") or not a whole number (" << ArrayNames::EmbeddingCellId << "), "
        << badValue << " with non-finite " << ArrayNames::EmbeddingParametricCoords << ", "
        << ArrayNames::EmbeddingDistance << " or " << ArrayNames::EmbeddingFallbackOffset << ", "
        << badRange << " with " << ArrayNames::EmbeddingParametricCoords << " over "
        << MaxExtrapolation << " (far outside their cell) or an |" << ArrayNames::EmbeddingDistance
        << "| over " << MaxDistance << " mesh diagonals, " << badFace
        << " with a distance but no boundary face of their cell (" << ArrayNames::EmbeddingFace
        << ") (first bad vertex " << firstBad << ")";
    return msg.str();
  }
  this->PlanHasOffsets = hasOffsets;
  this->PlanMethod = em.Method;
  this->PlanVersion = this->TopologyVersion;
  ++this->PlanStamp;
  return std::string();
}

//------------------------------------------------------------------------------
std::string TransferDriver::EvaluateFrame(const TransferFrame& frame, double* outDouble,
  float* outFloat, std::vector<std::string>& warnings)
{
  this->InvertedCells = 0;
  ++this->FrameCount;
  if (!this->HasPlan())
  {
    return "no transfer plan for this mesh (BuildPlan first)";
  }
  const std::int64_t numMeshPoints = this->NumberOfMeshPoints;
  const std::int64_t numCells = this->NumberOfCells;
  const int npc = this->NodesPerCell;
  const double* pts = frame.Points;
  if (!AllFinite(pts, 3 * numMeshPoints))
  {
    return "the deformed FE mesh has non-finite (NaN or infinite) point coordinates";
  }
  if (this->Lagrange || this->Hex)
  {
    return this->EvaluateLagrangeFrame(frame, outDouble, outFloat, warnings);
  }

  // Inverted elements: a warning, still mapped. The transformed point normals need them
  // cell by cell (recomputed from the polygons in those cells).
  const bool flagCells =
    frame.PointNormals && frame.PointNormalsMode == TransferPointNormals::Transform;
  if (frame.CountInverted || flagCells)
  {
    std::atomic<std::int64_t> inverted(0);
    const std::int64_t* conn = this->Conn.data();
    this->FoldedCells.resize(flagCells ? static_cast<size_t>(numCells) : 0);
    unsigned char* flags = flagCells ? this->FoldedCells.data() : nullptr;
    this->For(numCells, 256, [&](std::int64_t b, std::int64_t e) {
      inverted += MarkInvertedCells(conn, npc, pts, b, e, flags);
    });
    this->InvertedCells = frame.CountInverted ? inverted.load() : 0;
    if (this->InvertedCells > 0)
    {
      std::ostringstream msg;
      msg << this->InvertedCells << " of " << numCells
          << " deformed FE elements are inverted or degenerate (det J <= 0 at a corner or the "
             "centroid); the surface is still mapped through them";
      warnings.push_back(msg.str());
    }
  }

  // The per-frame coefficient tables: cell maps, then (offset vertices only) normals.
  {
    const std::int64_t* conn = this->Conn.data();
    double* cc = this->CellCoeffs.data();
    this->For(numCells, 1024, [&](std::int64_t b, std::int64_t e) {
      ComputeCellMapCoefficients(conn, npc, pts, b, e, cc);
    });
  }
  const bool offsets = this->PlanHasOffsets && this->PlanMethod == EmbeddingMethod::NormalOffset;
  if (offsets)
  {
    const std::string error = this->ComputeNodalNormals(frame, warnings);
    if (!error.empty())
    {
      return error;
    }
    const double* nn = this->NodalNormals.data();
    double* fc = this->FaceCoeffs.data();
    this->For(this->Topology.GetNumberOfBoundaryFaces(), 1024, [&](std::int64_t b, std::int64_t e) {
      ComputeFaceNormalCoefficients(this->Topology, nn, b, e, fc);
    });
  }

  if (outDouble)
  {
    return this->EvaluatePoints(frame, outDouble, warnings);
  }
  return this->EvaluatePoints(frame, outFloat, warnings);
}

template <typename T>
std::string TransferDriver::EvaluatePoints(
  const TransferFrame& frame, T* out, std::vector<std::string>& warnings)
{
  const int npc = this->NodesPerCell;
  const bool offsets = this->PlanHasOffsets && this->PlanMethod == EmbeddingMethod::NormalOffset;
  const TransferEntry* plan = this->Plan.data();
  const double* cc = this->CellCoeffs.data();
  const double* fc = offsets ? this->FaceCoeffs.data() : nullptr;
  const std::int64_t numVerts = this->GetNumberOfVertices();
  float* normals = frame.PointNormals;
  bool transform = normals && frame.PointNormalsMode == TransferPointNormals::Transform;
  std::vector<std::pair<std::int64_t, std::int64_t>> foldedVertices; // ranges holding some
  this->FoldedNormals = 0;
  if (transform && !(this->RestSurfaceValid && frame.Displacements))
  {
    warnings.push_back(std::string("PointNormalsMode is TRANSFORM but ") +
      (frame.Displacements ? "the rest surface points were not given"
                           : std::string("the FE mesh lacks point data ") +
            ArrayNames::Displacement + " (3 components)") +
      ": recomputing the point normals from the deformed polygons");
    transform = false;
  }
  if (transform)
  {
    // The covectors m = J0^T n0 / det J0 depend on the rest mesh, the plan and the rest
    // surface: rebuilt when one of them changed (rest points: beyond 1e-9 of the mesh).
    const std::string error = this->UpdateRestPoints(frame);
    if (!error.empty())
    {
      return error;
    }
    if (this->CovRest != this->RestVersion || this->CovPlan != this->PlanStamp ||
      this->CovSurface != this->RestSurfaceStamp)
    {
      const std::int64_t* conn = this->Conn.data();
      this->RestCellCoeffs.resize(this->CellCoeffs.size());
      double* rc = this->RestCellCoeffs.data();
      const double* rp = this->RestPoints.data();
      this->For(this->NumberOfCells, 1024, [&](std::int64_t b, std::int64_t e) {
        ComputeCellMapCoefficients(conn, npc, rp, b, e, rc);
      });
      this->Covectors.resize(3 * static_cast<size_t>(numVerts));
      float* cov = this->Covectors.data();
      const float* rn = this->RestSurfaceNormals.data();
      this->For(numVerts, 8192, [&](std::int64_t b, std::int64_t e) {
        ComputeNormalCovectors(plan, npc, rc, rn, b, e, cov);
      });
      this->CovRest = this->RestVersion;
      this->CovPlan = this->PlanStamp;
      this->CovSurface = this->RestSurfaceStamp;
    }
    const float* cov = this->Covectors.data();
    std::mutex mutex;
    std::vector<std::pair<std::int64_t, std::int64_t>> foldedRanges;
    const unsigned char* foldedCells =
      this->FoldedCells.empty() ? nullptr : this->FoldedCells.data();
    this->For(numVerts, 8192, [&](std::int64_t b, std::int64_t e) {
      if (EvaluateTransfer(plan, npc, cc, fc, cov, foldedCells, b, e, out, normals) > 0)
      {
        std::lock_guard<std::mutex> lock(mutex);
        foldedRanges.emplace_back(b, e);
      }
    });
    foldedVertices = std::move(foldedRanges);
  }
  else
  {
    this->For(numVerts, 8192,
      [&](std::int64_t b, std::int64_t e) { EvaluateTransfer(plan, npc, cc, fc, b, e, out); });
  }
  EvaluateFallbackTransfer(plan, npc, cc, this->FallbackVertices.data(),
    this->FallbackOffsets.data(), 0, static_cast<std::int64_t>(this->FallbackVertices.size()), out);
  if (normals && !transform)
  {
    this->VertexNormals(static_cast<const T*>(out), normals);
  }
  // Transformed normals the kernel left (NaN: the map folds there) are recomputed from the
  // polygons around the vertex, as RECOMPUTE does (same terms, same order, same bits).
  const std::int64_t* po = this->PolyOffsets.data();
  const std::int64_t* pc = this->PolyConn.data();
  const std::int64_t* io = this->IncOffsets.data();
  const bool narrow = this->IncPolys.empty();
  for (const auto& range : foldedVertices)
  {
    for (std::int64_t i = range.first; i < range.second; ++i)
    {
      if (!std::isnan(normals[3 * i]))
      {
        continue;
      }
      ++this->FoldedNormals;
      if (narrow)
      {
        ComputeVertexNormal(
          po, pc, static_cast<const T*>(out), io, this->IncPolys32.data(), i, normals);
      }
      else
      {
        ComputeVertexNormal(
          po, pc, static_cast<const T*>(out), io, this->IncPolys.data(), i, normals);
      }
    }
  }
  return std::string();
}

//------------------------------------------------------------------------------
std::string TransferDriver::EvaluateLagrangeFrame(const TransferFrame& frame, double* outDouble,
  float* outFloat, std::vector<std::string>& warnings)
{
  // Lagrange tets of order 3-4 and the hexahedra: the kernels of hoembedLagrangeTransfer.h
  const LagrangeTetBasis* tet = this->Lagrange;
  const LagrangeHexBasis* hex = this->Hex;
  const char* family = hex ? "hexahedra" : "VTK_LAGRANGE_TETRAHEDRON cells of order 3-4";
  const double* pts = frame.Points;
  const std::int64_t* conn = this->Conn.data();
  if (frame.CountInverted)
  {
    std::atomic<std::int64_t> inverted(0);
    this->For(this->NumberOfCells, 256, [&](std::int64_t cb, std::int64_t ce) {
      inverted += hex ? CountInvertedHexCells(*hex, conn, pts, cb, ce)
                      : CountInvertedLagrangeCells(*tet, conn, pts, cb, ce);
    });
    this->InvertedCells = inverted.load();
    if (this->InvertedCells > 0)
    {
      std::ostringstream msg;
      msg << this->InvertedCells << " of " << this->NumberOfCells
          << " deformed FE elements are inverted or degenerate (det J <= 0 at a corner or the "
             "centroid); the surface is still mapped through them";
      warnings.push_back(msg.str());
    }
  }
  const bool offsets = this->PlanHasOffsets && this->PlanMethod == EmbeddingMethod::NormalOffset;
  if (offsets)
  {
    if (frame.Normals != TransferNormals::Recompute)
      warnings.push_back(std::string("NormalMode ROTATE and DEFORM are not implemented for ") +
        family + ": the normals of the deformed boundary are recomputed (RECOMPUTE)");
    this->NodalNormals.assign(3 * static_cast<std::size_t>(this->NumberOfMeshPoints), 0.0);
    if (hex)
      ComputeHexBoundaryNormals(*hex, this->HexFaceCell, this->HexFaceLocal, pts,
        this->NumberOfMeshPoints, conn, this->NodalNormals.data());
    else
      ComputeLagrangeBoundaryNormals(*tet, this->Topology, pts, conn, this->NodalNormals.data());
  }
  const double* nn = this->NodalNormals.data();
  const TransferEntry* plan = this->Plan.data();
  const std::int64_t nv = this->GetNumberOfVertices();
  const std::int64_t nfb = static_cast<std::int64_t>(this->FallbackVertices.size());
  auto run = [&](auto* out) {
    this->For(nv, 4096, [&](std::int64_t vb, std::int64_t ve) {
      if (hex)
        EvaluateHexTransfer(*hex, conn, pts, nn, plan, vb, ve, out);
      else
        EvaluateLagrangeTransfer(*tet, conn, pts, nn, plan, vb, ve, out);
    });
    if (hex)
      EvaluateHexFallback(*hex, conn, pts, plan, this->FallbackVertices.data(),
        this->FallbackOffsets.data(), 0, nfb, out);
    else
      EvaluateLagrangeFallback(*tet, conn, pts, plan, this->FallbackVertices.data(),
        this->FallbackOffsets.data(), 0, nfb, out);
  };
  if (outDouble)
    run(outDouble);
  else
    run(outFloat);
  this->FoldedNormals = 0;
  if (frame.PointNormals)
  {
    if (frame.PointNormalsMode == TransferPointNormals::Transform)
      warnings.push_back(std::string("PointNormalsMode TRANSFORM is not implemented for ") +
        family + ": recomputing the point normals from the deformed polygons");
    if (outDouble)
      this->VertexNormals(static_cast<const double*>(outDouble), frame.PointNormals);
    else
      this->VertexNormals(static_cast<const float*>(outFloat), frame.PointNormals);
  }
  return std::string();
}

//------------------------------------------------------------------------------
std::string TransferDriver::UpdateRestPoints(const TransferFrame& frame)
{
  // once per frame: the nodal normals and the point normals may both ask
  if (this->RestFrame == this->FrameCount)
  {
    return std::string();
  }
  const std::int64_t numMeshPoints = this->NumberOfMeshPoints;
  const double* pts = frame.Points;
  const double* disp = frame.Displacements;
  const bool had = this->RestPoints.size() == 3 * static_cast<size_t>(numMeshPoints);
  this->RestPoints.resize(3 * static_cast<size_t>(numMeshPoints));
  double lo[3] = { DBL_MAX, DBL_MAX, DBL_MAX };
  double hi[3] = { -DBL_MAX, -DBL_MAX, -DBL_MAX };
  double change = had ? 0.0 : DBL_MAX;
  for (std::int64_t i = 0; i < numMeshPoints; ++i)
  {
    for (int d = 0; d < 3; ++d)
    {
      const double x = pts[3 * i + d] - disp[3 * i + d];
      if (!std::isfinite(x))
      {
        change = -1.0;
      }
      if (had && change >= 0.0)
      {
        change = std::max(change, std::fabs(x - this->RestPoints[3 * i + d]));
      }
      this->RestPoints[3 * i + d] = x;
      lo[d] = std::min(lo[d], x);
      hi[d] = std::max(hi[d], x);
    }
  }
  if (change < 0.0)
  {
    this->RestPoints.clear();
    return std::string("the FE mesh's ") + ArrayNames::Displacement +
      " array has non-finite values";
  }
  const double diag = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) +
    (hi[1] - lo[1]) * (hi[1] - lo[1]) + (hi[2] - lo[2]) * (hi[2] - lo[2]));
  if (change > 1e-9 * diag)
  {
    ++this->RestVersion;
  }
  this->RestFrame = this->FrameCount;
  return std::string();
}

//------------------------------------------------------------------------------
std::string TransferDriver::ComputeNodalNormals(
  const TransferFrame& frame, std::vector<std::string>& warnings)
{
  const std::int64_t numMeshPoints = this->NumberOfMeshPoints;
  const double* pts = frame.Points;
  // ROTATE and DEFORM start from the rest normals (rest points x - u).
  const bool rotate = frame.Normals == TransferNormals::Rotate;
  bool fromRest = frame.Normals != TransferNormals::Recompute;
  const bool haveDisp = frame.Displacements != nullptr;
  const bool haveRot = frame.Rotations != nullptr;
  if (rotate && !(haveRot && haveDisp))
  {
    warnings.push_back(
      std::string("NormalMode is ROTATE_NORMALS but the FE mesh lacks point data ") +
      ArrayNames::NodalRotation + " (9 components) or " + ArrayNames::Displacement +
      " (3 components): recomputing the normals from the deformed boundary");
    fromRest = false;
  }
  else if (fromRest && !haveDisp)
  {
    warnings.push_back(
      std::string("NormalMode is DEFORM_NORMALS but the FE mesh lacks point data ") +
      ArrayNames::Displacement +
      " (3 components): recomputing the normals from the deformed boundary");
    fromRest = false;
  }
  if (!fromRest)
  {
    ComputeBoundaryNodeNormals(this->Topology, pts, this->NodalNormals.data());
    return std::string();
  }
  // Rest points x - u; the rest normals are recomputed only when these change.
  const std::string restError = this->UpdateRestPoints(frame);
  if (!restError.empty())
  {
    return restError;
  }
  if (this->RestNormals.size() != this->RestPoints.size())
  {
    this->RestNormals.assign(this->RestPoints.size(), 0.0);
    this->RestValid = false;
  }
  if (!this->RestValid || this->RestNormalsVersion != this->RestVersion)
  {
    ComputeBoundaryNodeNormals(this->Topology, this->RestPoints.data(), this->RestNormals.data());
    this->RestValid = true;
    this->RestNormalsVersion = this->RestVersion;
  }
  const double* rest = this->RestNormals.data();
  double* nn = this->NodalNormals.data();
  if (!rotate) // DEFORM
  {
    const double* restPts = this->RestPoints.data();
    const std::int64_t* conn = this->Conn.data();
    const int npc = this->NodesPerCell;
    this->For(numMeshPoints, 1024, [&](std::int64_t b, std::int64_t e) {
      DeformNodalNormals(this->Topology, conn, npc, restPts, pts, rest, b, e, nn);
    });
    return std::string();
  }
  const double* rotations = frame.Rotations;
  if (!AllFinite(rotations, 9 * numMeshPoints))
  {
    return std::string("the FE mesh's ") + ArrayNames::NodalRotation +
      " array has non-finite values";
  }
  this->For(numMeshPoints, 4096,
    [&](std::int64_t b, std::int64_t e) { RotateNodalNormals(rest, rotations, b, e, nn); });
  return std::string();
}

//------------------------------------------------------------------------------
void TransferDriver::SetPolygons(const std::int64_t* offsets, const std::int64_t* connectivity,
  std::int64_t numberOfPolygons, std::int64_t numberOfVertices)
{
  this->PolyOffsets.assign(1, 0);
  this->PolyConn.clear();
  if (offsets && numberOfPolygons > 0)
  {
    this->PolyOffsets.assign(offsets, offsets + numberOfPolygons + 1);
    this->PolyConn.assign(connectivity, connectivity + offsets[numberOfPolygons]);
  }
  else
  {
    numberOfPolygons = 0;
  }
  this->IncPolys.clear();
  this->IncPolys32.clear();
  if (numberOfPolygons <= std::numeric_limits<std::int32_t>::max())
  {
    BuildVertexPolygonIncidence(this->PolyOffsets.data(), this->PolyConn.data(), numberOfPolygons,
      numberOfVertices, this->IncOffsets, this->IncPolys32);
  }
  else
  {
    BuildVertexPolygonIncidence(this->PolyOffsets.data(), this->PolyConn.data(), numberOfPolygons,
      numberOfVertices, this->IncOffsets, this->IncPolys);
  }
  this->PolyNormals.resize(3 * static_cast<size_t>(numberOfPolygons));
  this->RestSurfaceValid = false;
}

template <typename T>
void TransferDriver::VertexNormals(const T* points, float* normals)
{
  const std::int64_t numPolys = static_cast<std::int64_t>(this->PolyOffsets.size()) - 1;
  const std::int64_t numVerts = static_cast<std::int64_t>(this->IncOffsets.size()) - 1;
  const std::int64_t* po = this->PolyOffsets.data();
  const std::int64_t* pc = this->PolyConn.data();
  double* pn = this->PolyNormals.data();
  this->For(numPolys, 8192,
    [&](std::int64_t b, std::int64_t e) { ComputePolygonNormals(po, pc, points, b, e, pn); });
  const std::int64_t* io = this->IncOffsets.data();
  const std::int64_t* ip = this->IncPolys.data();
  const std::int32_t* ip32 = this->IncPolys32.data();
  const bool narrow = this->IncPolys.empty();
  this->For(numVerts, 8192, [&](std::int64_t b, std::int64_t e) {
    if (narrow)
      hoembed::ComputeVertexNormals(io, ip32, pn, b, e, normals);
    else
      hoembed::ComputeVertexNormals(io, ip, pn, b, e, normals);
  });
}

template <typename T>
void TransferDriver::RestSurfacePoints(const T* points)
{
  const std::int64_t numVerts = static_cast<std::int64_t>(this->IncOffsets.size()) - 1;
  this->RestSurfaceNormals.resize(3 * static_cast<size_t>(numVerts > 0 ? numVerts : 0));
  if (numVerts > 0)
  {
    this->VertexNormals(points, this->RestSurfaceNormals.data());
  }
  this->RestSurfaceValid = numVerts == this->GetNumberOfVertices();
  ++this->RestSurfaceStamp;
}

void TransferDriver::SetRestSurfacePoints(const double* points)
{
  this->RestSurfacePoints(points);
}

void TransferDriver::SetRestSurfacePoints(const float* points)
{
  this->RestSurfacePoints(points);
}

void TransferDriver::ComputeVertexNormals(const double* points, float* normals)
{
  this->VertexNormals(points, normals);
}

void TransferDriver::ComputeVertexNormals(const float* points, float* normals)
{
  this->VertexNormals(points, normals);
}
} // namespace hoembed
