#include "vtkDeformationTransferFilter.h"

#include "hoembedBoundaryNormals.h"
#include "hoembedMeshFingerprint.h"
#include "hoembedTetMeshTopology.h"
#include "hoembedTransferKernel.h"
#include "hoembedTransferNormals.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCellType.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPTools.h"
#include "vtkSignedCharArray.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkStringArray.h"
#include "vtkTypeInt64Array.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkDeformationTransferFilter);

namespace
{
// The first value of a string array in field data, or null (no per-frame copy).
const vtkStdString* FieldString(vtkFieldData* fd, const char* name)
{
  auto* a = fd ? vtkStringArray::SafeDownCast(fd->GetAbstractArray(name)) : nullptr;
  return a && a->GetNumberOfValues() > 0 ? &a->GetValue(0) : nullptr;
}

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

// The values of `a` (n tuples) as contiguous doubles: its own storage when it is a
// vtkDoubleArray, else copied into `buffer` (reused between frames).
const double* ContiguousDoubles(vtkDataArray* a, vtkIdType n, std::vector<double>& buffer)
{
  if (auto* d = vtkDoubleArray::SafeDownCast(a))
  {
    return d->GetPointer(0);
  }
  const int nc = a->GetNumberOfComponents();
  buffer.resize(static_cast<size_t>(nc) * n);
  for (vtkIdType i = 0; i < n; ++i)
  {
    a->GetTuple(i, &buffer[static_cast<size_t>(nc) * i]);
  }
  return buffer.data();
}
} // namespace

struct vtkDeformationTransferFilter::Internals
{
  // Mesh topology cache (key: the cell array and cell types objects and their MTimes).
  vtkCellArray* CellsKey = nullptr;
  vtkMTimeType CellsMTime = 0;
  vtkUnsignedCharArray* TypesKey = nullptr;
  vtkMTimeType TypesMTime = 0;
  vtkIdType NumberOfPointsKey = -1;
  std::string Fingerprint;
  int NodesPerCell = 0;
  std::vector<std::int64_t> Conn;
  hoembed::TetMeshTopology Topology;
  int TopologyVersion = 0;

  // Per-vertex plan cache (key: surface object, its MTime, topology version, method).
  vtkPolyData* SurfaceKey = nullptr;
  vtkMTimeType SurfaceMTime = 0;
  int PlanTopologyVersion = -1;
  std::string PlanMethod;
  std::vector<hoembed::TransferEntry> Plan;
  bool PlanHasOffsets = false;

  // Output normals cache (key: the surface's polygon cell array and its MTime).
  vtkCellArray* PolysKey = nullptr;
  vtkMTimeType PolysMTime = 0;
  std::vector<std::int64_t> PolyOffsets, PolyConn, IncOffsets, IncPolys;
  std::vector<double> PolyNormals;

  // Per-frame tables, reused.
  std::vector<double> Points, NodalNormals, CellCoeffs, FaceCoeffs;
  std::vector<double> RestPoints, RestNormals, Rotations;
  bool RestValid = false;

  void ResetPlan()
  {
    this->SurfaceKey = nullptr;
    this->PlanTopologyVersion = -1;
  }
};

//------------------------------------------------------------------------------
vtkDeformationTransferFilter::vtkDeformationTransferFilter()
  : Internal(new Internals)
{
  this->SetNumberOfInputPorts(2);
  this->SetNumberOfOutputPorts(1);
}

vtkDeformationTransferFilter::~vtkDeformationTransferFilter() = default;

//------------------------------------------------------------------------------
int vtkDeformationTransferFilter::FillInputPortInformation(int port, vtkInformation* info)
{
  if (port == 0)
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  }
  else
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkUnstructuredGrid");
  }
  return 1;
}

//------------------------------------------------------------------------------
int vtkDeformationTransferFilter::RequestInformation(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkInformation* meshInfo = inputVector[1]->GetInformationObject(0);
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  using SDDP = vtkStreamingDemandDrivenPipeline;
  // The surface is static: the output's time is the mesh's.
  outInfo->Remove(SDDP::TIME_STEPS());
  outInfo->Remove(SDDP::TIME_RANGE());
  if (meshInfo && meshInfo->Has(SDDP::TIME_STEPS()))
  {
    outInfo->CopyEntry(meshInfo, SDDP::TIME_STEPS());
  }
  if (meshInfo && meshInfo->Has(SDDP::TIME_RANGE()))
  {
    outInfo->CopyEntry(meshInfo, SDDP::TIME_RANGE());
  }
  return 1;
}

//------------------------------------------------------------------------------
int vtkDeformationTransferFilter::RequestUpdateExtent(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  using SDDP = vtkStreamingDemandDrivenPipeline;
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  vtkInformation* meshInfo = inputVector[1]->GetInformationObject(0);
  vtkInformation* surfInfo = inputVector[0]->GetInformationObject(0);
  if (meshInfo)
  {
    if (outInfo->Has(SDDP::UPDATE_TIME_STEP()))
    {
      meshInfo->Set(SDDP::UPDATE_TIME_STEP(), outInfo->Get(SDDP::UPDATE_TIME_STEP()));
    }
    else
    {
      meshInfo->Remove(SDDP::UPDATE_TIME_STEP());
    }
  }
  if (surfInfo)
  {
    // The embedded surface does not vary in time.
    surfInfo->Remove(SDDP::UPDATE_TIME_STEP());
  }
  if (meshInfo)
  {
    // Distributed pipelines: each process moves its piece of the surface (port 0 keeps
    // the requested piece) with the whole deformed mesh.
    meshInfo->Set(SDDP::UPDATE_PIECE_NUMBER(), 0);
    meshInfo->Set(SDDP::UPDATE_NUMBER_OF_PIECES(), 1);
    meshInfo->Set(SDDP::UPDATE_NUMBER_OF_GHOST_LEVELS(), 0);
  }
  return 1;
}

//------------------------------------------------------------------------------
int vtkDeformationTransferFilter::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* surface = vtkPolyData::GetData(inputVector[0], 0);
  vtkUnstructuredGrid* mesh = vtkUnstructuredGrid::GetData(inputVector[1], 0);
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  Internals& I = *this->Internal;
  this->NumberOfInvertedElements = 0;
  if (!surface || !mesh || !output)
  {
    vtkErrorMacro("needs the embedded surface on port 0 and the deformed FE mesh on port 1");
    return 0;
  }
  if (mesh->GetInformation()->Has(vtkDataObject::DATA_TIME_STEP()))
  {
    output->GetInformation()->Set(vtkDataObject::DATA_TIME_STEP(),
      mesh->GetInformation()->Get(vtkDataObject::DATA_TIME_STEP()));
  }
  else
  {
    output->GetInformation()->Remove(vtkDataObject::DATA_TIME_STEP());
  }

  // --- The deformed mesh: cell types, topology (cached) and fingerprint.
  const vtkIdType numMeshPoints = mesh->GetNumberOfPoints();
  const vtkIdType numCells = mesh->GetNumberOfCells();
  if (numMeshPoints < 4 || numCells < 1 || !mesh->GetCells())
  {
    vtkErrorMacro("the deformed FE mesh (port 1) is empty");
    return 0;
  }
  if (numCells > INT32_MAX)
  {
    vtkErrorMacro("the deformed FE mesh has too many cells (" << numCells << ")");
    return 0;
  }
  vtkCellArray* cells = mesh->GetCells();
  vtkUnsignedCharArray* types = mesh->GetCellTypesArray();
  if (cells != I.CellsKey || cells->GetMTime() != I.CellsMTime || types != I.TypesKey ||
    (types && types->GetMTime() != I.TypesMTime) || numMeshPoints != I.NumberOfPointsKey)
  {
    const int type0 = mesh->GetCellType(0);
    if (type0 != VTK_QUADRATIC_TETRA && type0 != VTK_TETRA)
    {
      vtkErrorMacro("the FE mesh must consist of VTK_QUADRATIC_TETRA or VTK_TETRA cells; cell 0 "
                    "has type "
        << type0);
      I.CellsKey = nullptr;
      return 0;
    }
    const int npc = type0 == VTK_QUADRATIC_TETRA ? 10 : 4;
    std::vector<std::int64_t> conn(static_cast<size_t>(npc) * numCells);
    hoembed::MeshFingerprint fp(numMeshPoints, numCells);
    for (vtkIdType c = 0; c < numCells; ++c)
    {
      vtkIdType n = 0;
      const vtkIdType* ids = nullptr;
      cells->GetCellAtId(c, n, ids);
      if (mesh->GetCellType(c) != type0 || n != npc)
      {
        vtkErrorMacro("the FE mesh mixes cell types or node counts (cell "
          << c << " has type " << mesh->GetCellType(c) << " with " << n
          << " nodes); all cells must be VTK_QUADRATIC_TETRA or all VTK_TETRA");
        I.CellsKey = nullptr;
        return 0;
      }
      std::int64_t* dst = &conn[static_cast<size_t>(npc) * c];
      for (int a = 0; a < npc; ++a)
      {
        dst[a] = static_cast<std::int64_t>(ids[a]);
      }
      fp.AddCell(type0, dst, npc);
    }
    const std::string hex = fp.Hex();
    if (hex != I.Fingerprint || npc != I.NodesPerCell || I.Topology.NumberOfPoints != numMeshPoints)
    {
      const std::string problem = I.Topology.Build(conn.data(), numCells, npc, numMeshPoints);
      if (!problem.empty())
      {
        vtkErrorMacro("invalid FE mesh topology: " << problem);
        I.CellsKey = nullptr;
        I.Fingerprint.clear();
        return 0;
      }
      I.Conn.swap(conn);
      I.Fingerprint = hex;
      I.NodesPerCell = npc;
      ++I.TopologyVersion;
      ++this->TopologyBuildCount;
      const int csize = hoembed::CellCoefficientSize(npc);
      const int fsize = hoembed::FaceCoefficientSize(npc);
      I.CellCoeffs.assign(static_cast<size_t>(csize) * numCells, 0.0);
      I.FaceCoeffs.assign(static_cast<size_t>(fsize) * I.Topology.GetNumberOfBoundaryFaces(), 0.0);
      I.NodalNormals.assign(3 * static_cast<size_t>(numMeshPoints), 0.0);
      I.RestValid = false;
    }
    I.CellsKey = cells;
    I.CellsMTime = cells->GetMTime();
    I.TypesKey = types;
    I.TypesMTime = types ? types->GetMTime() : 0;
    I.NumberOfPointsKey = numMeshPoints;
  }
  const int npc = I.NodesPerCell;
  this->UpdateProgress(0.1);

  // --- The embedding: field data, then the per-vertex plan (cached).
  const vtkStdString* methodValue = FieldString(surface->GetFieldData(), "EmbeddingMethod");
  if (!methodValue)
  {
    vtkErrorMacro("the surface (port 0) has no field data EmbeddingMethod: is it the output of "
                  "vtkEmbeddingCoordinatesFilter?");
    return 0;
  }
  const std::string& method = *methodValue;
  if (method != "normal-offset" && method != "barycentric")
  {
    vtkErrorMacro("unknown EmbeddingMethod '" << method
                                              << "' (expected normal-offset or barycentric)");
    return 0;
  }
  const vtkStdString* fpValue = FieldString(surface->GetFieldData(), "EmbeddingMeshFingerprint");
  if (!fpValue)
  {
    vtkErrorMacro("the surface (port 0) has no field data EmbeddingMeshFingerprint");
    return 0;
  }
  const std::string& surfaceFp = *fpValue;
  if (surfaceFp != I.Fingerprint)
  {
    vtkErrorMacro("the FE mesh (port 1) is not the mesh the surface was embedded in: mesh "
                  "fingerprint "
      << I.Fingerprint << " (" << numMeshPoints << " points, " << numCells
      << " cells), embedding fingerprint " << surfaceFp);
    return 0;
  }
  const vtkIdType numVerts = surface->GetNumberOfPoints();
  if (surface != I.SurfaceKey || surface->GetMTime() != I.SurfaceMTime ||
    I.PlanTopologyVersion != I.TopologyVersion || method != I.PlanMethod)
  {
    I.ResetPlan();
    vtkPointData* pd = surface->GetPointData();
    const bool offset = method == "normal-offset";
    vtkDataArray* cellIds = pd->GetArray("EmbeddingCellId");
    vtkDataArray* pcoords = pd->GetArray("EmbeddingParametricCoords");
    vtkDataArray* dist = pd->GetArray("EmbeddingDistance");
    vtkDataArray* faces = pd->GetArray("EmbeddingFace");
    std::string missing;
    if (!cellIds || cellIds->GetNumberOfComponents() != 1 ||
      cellIds->GetNumberOfTuples() != numVerts)
    {
      missing += " EmbeddingCellId (1 component)";
    }
    if (!pcoords || pcoords->GetNumberOfComponents() != 3 ||
      pcoords->GetNumberOfTuples() != numVerts)
    {
      missing += " EmbeddingParametricCoords (3 components)";
    }
    if (offset &&
      (!dist || dist->GetNumberOfComponents() != 1 || dist->GetNumberOfTuples() != numVerts))
    {
      missing += " EmbeddingDistance (1 component)";
    }
    if (faces && (faces->GetNumberOfComponents() != 1 || faces->GetNumberOfTuples() != numVerts))
    {
      missing += " EmbeddingFace (1 component)";
    }
    if (!missing.empty())
    {
      vtkErrorMacro("the surface (port 0) lacks point data arrays, or they do not have one tuple "
                    "per point:"
        << missing);
      return 0;
    }
    auto* idsFast = vtkIdTypeArray::SafeDownCast(cellIds);
    auto* pcFast = vtkDoubleArray::SafeDownCast(pcoords);
    auto* dFast = vtkDoubleArray::SafeDownCast(dist);
    auto* fFast = vtkSignedCharArray::SafeDownCast(faces);
    I.Plan.resize(static_cast<size_t>(numVerts));
    vtkIdType badCell = 0, badValue = 0, badFace = 0, firstBad = -1;
    bool hasOffsets = false;
    const hoembed::TetMeshTopology& topo = I.Topology;
    for (vtkIdType i = 0; i < numVerts; ++i)
    {
      hoembed::TransferEntry& e = I.Plan[i];
      const double cid = idsFast ? static_cast<double>(idsFast->GetValue(i)) : cellIds->GetComponent(i, 0);
      if (!(cid >= 0 && cid < numCells))
      {
        ++badCell;
        firstBad = firstBad < 0 ? i : firstBad;
        e = hoembed::TransferEntry{ { 0, 0, 0 }, 0.0, 0, -1 };
        continue;
      }
      e.Cell = static_cast<std::int32_t>(cid);
      for (int k = 0; k < 3; ++k)
      {
        e.PC[k] = pcFast ? pcFast->GetTypedComponent(i, k) : pcoords->GetComponent(i, k);
      }
      e.Distance = 0.0;
      e.Face = -1;
      if (offset)
      {
        e.Distance = dFast ? dFast->GetValue(i) : dist->GetComponent(i, 0);
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
      if (e.Distance == 0.0)
      {
        continue;
      }
      int local = -1;
      if (faces)
      {
        local = static_cast<int>(fFast ? fFast->GetValue(i) : faces->GetComponent(i, 0));
      }
      if (local >= 0 && local < 4 && topo.CellBoundaryFace[4 * e.Cell + local] >= 0)
      {
        e.Face = static_cast<std::int32_t>(4 * topo.CellBoundaryFace[4 * e.Cell + local] + local);
      }
      else if (local < 0)
      {
        e.Face = hoembed::DeduceBoundaryFace(topo, e.Cell, e.PC, this->FaceTolerance);
      }
      if (e.Face < 0)
      {
        ++badFace;
        firstBad = firstBad < 0 ? i : firstBad;
        continue;
      }
      hasOffsets = true;
    }
    if (badCell || badValue || badFace)
    {
      vtkErrorMacro("invalid embedding for this mesh: "
        << badCell << " vertices with a cell id outside [0, " << numCells << "), " << badValue
        << " with non-finite coordinates or distance, " << badFace
        << " with a distance but no boundary face of their cell (first bad vertex " << firstBad
        << ")");
      return 0;
    }
    I.PlanHasOffsets = hasOffsets;
    I.SurfaceKey = surface;
    I.SurfaceMTime = surface->GetMTime();
    I.PlanTopologyVersion = I.TopologyVersion;
    I.PlanMethod = method;
    ++this->PlanBuildCount;
  }
  this->UpdateProgress(0.3);

  // --- Deformed points: contiguous doubles, finite.
  const double* pts = ContiguousDoubles(mesh->GetPoints()->GetData(), numMeshPoints, I.Points);
  if (!AllFinite(pts, 3 * static_cast<std::int64_t>(numMeshPoints)))
  {
    vtkErrorMacro("the deformed FE mesh has non-finite (NaN or infinite) point coordinates");
    return 0;
  }

  // --- Inverted elements: warn, still map.
  if (this->CheckInvertedElements)
  {
    std::atomic<std::int64_t> inverted(0);
    const std::int64_t* conn = I.Conn.data();
    vtkSMPTools::For(0, numCells, 256, [&](vtkIdType b, vtkIdType e) {
      inverted += hoembed::CountInvertedCells(conn, npc, pts, b, e);
    });
    const std::int64_t total = inverted.load();
    this->NumberOfInvertedElements = static_cast<vtkIdType>(total);
    if (total > 0)
    {
      vtkWarningMacro(<< total << " of " << numCells
                      << " deformed FE elements are inverted or degenerate (det J <= 0 at a "
                         "corner or the centroid); the surface is still mapped through them");
    }
  }
  this->UpdateProgress(0.4);

  // --- Nodal normals and the per-frame coefficient tables.
  {
    const std::int64_t* conn = I.Conn.data();
    double* cc = I.CellCoeffs.data();
    vtkSMPTools::For(0, numCells, 1024, [&](vtkIdType b, vtkIdType e) {
      hoembed::ComputeCellMapCoefficients(conn, npc, pts, b, e, cc);
    });
  }
  const bool offsets = I.PlanHasOffsets && I.PlanMethod == "normal-offset";
  if (offsets)
  {
    // ROTATE_NORMALS and DEFORM_NORMALS start from the rest normals (rest points x - u).
    const bool rotate = this->NormalMode == ROTATE_NORMALS;
    bool fromRest = this->NormalMode != RECOMPUTE_NORMALS;
    vtkDataArray* rot = mesh->GetPointData()->GetArray("NodalRotation");
    vtkDataArray* disp = mesh->GetPointData()->GetArray("Displacement");
    const bool haveDisp =
      disp && disp->GetNumberOfComponents() == 3 && disp->GetNumberOfTuples() == numMeshPoints;
    const bool haveRot =
      rot && rot->GetNumberOfComponents() == 9 && rot->GetNumberOfTuples() == numMeshPoints;
    if (rotate && !(haveRot && haveDisp))
    {
      vtkWarningMacro("NormalMode is ROTATE_NORMALS but the FE mesh lacks point data NodalRotation "
                      "(9 components) or Displacement (3 components): recomputing the normals "
                      "from the deformed boundary");
      fromRest = false;
    }
    else if (fromRest && !haveDisp)
    {
      vtkWarningMacro("NormalMode is DEFORM_NORMALS but the FE mesh lacks point data "
                      "Displacement (3 components): recomputing the normals from the deformed "
                      "boundary");
      fromRest = false;
    }
    if (!fromRest)
    {
      hoembed::ComputeBoundaryNodeNormals(I.Topology, pts, I.NodalNormals.data());
    }
    else
    {
      // Rest points x - u; the rest normals are recomputed only when these change.
      I.RestPoints.resize(3 * static_cast<size_t>(numMeshPoints));
      if (I.RestNormals.size() != I.RestPoints.size())
      {
        I.RestNormals.assign(I.RestPoints.size(), 0.0);
        I.RestValid = false;
      }
      double lo[3] = { VTK_DOUBLE_MAX, VTK_DOUBLE_MAX, VTK_DOUBLE_MAX };
      double hi[3] = { -VTK_DOUBLE_MAX, -VTK_DOUBLE_MAX, -VTK_DOUBLE_MAX };
      double change = I.RestValid ? 0.0 : VTK_DOUBLE_MAX;
      for (vtkIdType i = 0; i < numMeshPoints; ++i)
      {
        double u[3];
        disp->GetTuple(i, u);
        for (int d = 0; d < 3; ++d)
        {
          const double x = pts[3 * i + d] - u[d];
          if (!std::isfinite(x))
          {
            change = -1.0;
          }
          if (I.RestValid)
          {
            change = std::max(change, std::fabs(x - I.RestPoints[3 * i + d]));
          }
          I.RestPoints[3 * i + d] = x;
          lo[d] = std::min(lo[d], x);
          hi[d] = std::max(hi[d], x);
        }
      }
      if (change < 0.0)
      {
        vtkErrorMacro("the FE mesh's Displacement array has non-finite values");
        return 0;
      }
      const double diag = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) +
        (hi[1] - lo[1]) * (hi[1] - lo[1]) + (hi[2] - lo[2]) * (hi[2] - lo[2]));
      if (change > 1e-9 * diag)
      {
        hoembed::ComputeBoundaryNodeNormals(I.Topology, I.RestPoints.data(), I.RestNormals.data());
        I.RestValid = true;
      }
      if (!rotate) // DEFORM_NORMALS
      {
        const double* rest = I.RestNormals.data();
        const double* restPts = I.RestPoints.data();
        const std::int64_t* conn = I.Conn.data();
        double* nn = I.NodalNormals.data();
        vtkSMPTools::For(0, numMeshPoints, 1024, [&](vtkIdType b, vtkIdType e) {
          hoembed::DeformNodalNormals(I.Topology, conn, npc, restPts, pts, rest, b, e, nn);
        });
      }
    }
    if (fromRest && rotate)
    {
      const double* rotations = ContiguousDoubles(rot, numMeshPoints, I.Rotations);
      if (!AllFinite(rotations, 9 * static_cast<std::int64_t>(numMeshPoints)))
      {
        vtkErrorMacro("the FE mesh's NodalRotation array has non-finite values");
        return 0;
      }
      const double* rest = I.RestNormals.data();
      double* nn = I.NodalNormals.data();
      vtkSMPTools::For(0, numMeshPoints, 4096, [&](vtkIdType b, vtkIdType e) {
        hoembed::RotateNodalNormals(rest, rotations, b, e, nn);
      });
    }
    const double* nn = I.NodalNormals.data();
    double* fc = I.FaceCoeffs.data();
    vtkSMPTools::For(0, I.Topology.GetNumberOfBoundaryFaces(), 1024,
      [&](vtkIdType b, vtkIdType e) {
        hoembed::ComputeFaceNormalCoefficients(I.Topology, nn, b, e, fc);
      });
  }
  this->UpdateProgress(0.5);

  // --- The per-vertex evaluation into the new output points.
  int precision = VTK_DOUBLE;
  if (this->OutputPointsPrecision == SINGLE_PRECISION ||
    (this->OutputPointsPrecision == DEFAULT_PRECISION && surface->GetPoints() &&
      surface->GetPoints()->GetDataType() == VTK_FLOAT))
  {
    precision = VTK_FLOAT;
  }
  vtkNew<vtkPoints> newPoints;
  newPoints->SetDataType(precision);
  newPoints->SetNumberOfPoints(numVerts);
  {
    const hoembed::TransferEntry* plan = I.Plan.data();
    const double* cc = I.CellCoeffs.data();
    const double* fc = offsets ? I.FaceCoeffs.data() : nullptr;
    if (precision == VTK_DOUBLE)
    {
      double* out = static_cast<double*>(newPoints->GetVoidPointer(0));
      vtkSMPTools::For(0, numVerts, 8192, [&](vtkIdType b, vtkIdType e) {
        hoembed::EvaluateTransfer(plan, npc, cc, fc, b, e, out);
      });
    }
    else
    {
      float* out = static_cast<float*>(newPoints->GetVoidPointer(0));
      vtkSMPTools::For(0, numVerts, 8192, [&](vtkIdType b, vtkIdType e) {
        hoembed::EvaluateTransfer(plan, npc, cc, fc, b, e, out);
      });
    }
  }
  this->UpdateProgress(0.8);

  // --- Output: the surface's structure and data, new points, optional normals.
  output->CopyStructure(surface);
  output->SetPoints(newPoints);
  output->GetPointData()->ShallowCopy(surface->GetPointData());
  output->GetCellData()->ShallowCopy(surface->GetCellData());
  output->GetFieldData()->ShallowCopy(surface->GetFieldData());
  // Every Embedding* point array (the embedding's own, and its diagnostics) describes the
  // rest state, not this frame.
  for (int a = output->GetPointData()->GetNumberOfArrays() - 1; a >= 0; --a)
  {
    const char* name = output->GetPointData()->GetArrayName(a);
    if (name && std::strncmp(name, "Embedding", 9) == 0)
    {
      output->GetPointData()->RemoveArray(a);
    }
  }
  if (vtkDataArray* stale = output->GetPointData()->GetNormals())
  {
    output->GetPointData()->RemoveArray(stale->GetName());
    output->GetPointData()->SetNormals(nullptr);
  }
  if (vtkDataArray* stale = output->GetCellData()->GetNormals())
  {
    output->GetCellData()->RemoveArray(stale->GetName());
    output->GetCellData()->SetNormals(nullptr);
  }
  if (this->ComputePointNormals)
  {
    vtkCellArray* polys = surface->GetPolys();
    const vtkIdType numPolys = polys ? polys->GetNumberOfCells() : 0;
    if (polys != I.PolysKey || (polys && polys->GetMTime() != I.PolysMTime))
    {
      I.PolyOffsets.resize(numPolys + 1);
      I.PolyConn.resize(polys ? polys->GetNumberOfConnectivityIds() : 0);
      vtkDataArray* offs = polys ? polys->GetOffsetsArray() : nullptr;
      vtkDataArray* conn = polys ? polys->GetConnectivityArray() : nullptr;
      I.PolyOffsets[0] = 0;
      for (vtkIdType p = 0; offs && p <= numPolys; ++p)
      {
        I.PolyOffsets[p] = static_cast<std::int64_t>(offs->GetComponent(p, 0));
      }
      for (size_t k = 0; conn && k < I.PolyConn.size(); ++k)
      {
        I.PolyConn[k] = static_cast<std::int64_t>(conn->GetComponent(static_cast<vtkIdType>(k), 0));
      }
      hoembed::BuildVertexPolygonIncidence(
        I.PolyOffsets.data(), I.PolyConn.data(), numPolys, numVerts, I.IncOffsets, I.IncPolys);
      I.PolyNormals.resize(3 * static_cast<size_t>(numPolys));
      I.PolysKey = polys;
      I.PolysMTime = polys ? polys->GetMTime() : 0;
    }
    const std::int64_t* po = I.PolyOffsets.data();
    const std::int64_t* pc = I.PolyConn.data();
    double* pn = I.PolyNormals.data();
    void* raw = newPoints->GetVoidPointer(0);
    vtkSMPTools::For(0, numPolys, 8192, [&](vtkIdType b, vtkIdType e) {
      if (precision == VTK_DOUBLE)
      {
        hoembed::ComputePolygonNormals(po, pc, static_cast<const double*>(raw), b, e, pn);
      }
      else
      {
        hoembed::ComputePolygonNormals(po, pc, static_cast<const float*>(raw), b, e, pn);
      }
    });
    vtkNew<vtkFloatArray> normals;
    normals->SetName("Normals");
    normals->SetNumberOfComponents(3);
    normals->SetNumberOfTuples(numVerts);
    float* nout = normals->GetPointer(0);
    const std::int64_t* io = I.IncOffsets.data();
    const std::int64_t* ip = I.IncPolys.data();
    vtkSMPTools::For(0, numVerts, 8192, [&](vtkIdType b, vtkIdType e) {
      hoembed::ComputeVertexNormals(io, ip, pn, b, e, nout);
    });
    output->GetPointData()->SetNormals(normals);
  }
  this->UpdateProgress(1.0);
  return 1;
}

//------------------------------------------------------------------------------
void vtkDeformationTransferFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "NormalMode: "
     << (this->NormalMode == ROTATE_NORMALS
            ? "ROTATE_NORMALS"
            : (this->NormalMode == DEFORM_NORMALS ? "DEFORM_NORMALS" : "RECOMPUTE_NORMALS"))
     << "\n";
  os << indent << "ComputePointNormals: " << (this->ComputePointNormals ? "On" : "Off") << "\n";
  os << indent << "CheckInvertedElements: " << (this->CheckInvertedElements ? "On" : "Off")
     << "\n";
  os << indent << "FaceTolerance: " << this->FaceTolerance << "\n";
  os << indent << "OutputPointsPrecision: " << this->OutputPointsPrecision << "\n";
  os << indent << "NumberOfInvertedElements: " << this->NumberOfInvertedElements << "\n";
  os << indent << "TopologyBuildCount: " << this->TopologyBuildCount << "\n";
  os << indent << "PlanBuildCount: " << this->PlanBuildCount << "\n";
}
