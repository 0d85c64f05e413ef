#include "vtkDeformationTransferFilter.h"

#include "hoembedArrayNames.h"
#include "hoembedTetMeshInputVTK.h"
#include "hoembedTransferDriver.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkStringArray.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkDeformationTransferFilter);

namespace
{
using hoembed::ArrayNames::EmbeddingCellId;
using hoembed::ArrayNames::EmbeddingDistance;
using hoembed::ArrayNames::EmbeddingFace;
using hoembed::ArrayNames::EmbeddingFallbackOffset;
using hoembed::ArrayNames::EmbeddingParametricCoords;

// The first value of a string array in field data, or null (no per-frame copy).
const vtkStdString* FieldString(vtkFieldData* fd, const char* name)
{
  auto* a = fd ? vtkStringArray::SafeDownCast(fd->GetAbstractArray(name)) : nullptr;
  return a && a->GetNumberOfValues() > 0 ? &a->GetValue(0) : nullptr;
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

// What the driver's checks need to know of a point array (null: absent).
hoembed::TransferArrayShape Shape(vtkDataArray* a)
{
  hoembed::TransferArrayShape shape;
  if (a)
  {
    shape.Present = true;
    shape.Components = a->GetNumberOfComponents();
    shape.Tuples = static_cast<std::int64_t>(a->GetNumberOfTuples());
  }
  return shape;
}

// The driver's loops on VTK's SMP backend.
void SMPFor(
  std::int64_t n, std::int64_t grain, const std::function<void(std::int64_t, std::int64_t)>& body)
{
  vtkSMPTools::For(0, static_cast<vtkIdType>(n), static_cast<vtkIdType>(grain),
    [&](vtkIdType b, vtkIdType e) { body(b, e); });
}
} // namespace

// The algorithm and its caches live in hoembed::TransferDriver; this keeps what only the
// VTK binding knows: which input objects (and modification times) the driver's mesh
// topology, plan and polygons were built from, and buffers for non-double arrays.
struct vtkDeformationTransferFilter::Internals
{
  hoembed::TransferDriver Driver{ SMPFor };
  // mesh topology key: the cell array and cell types objects and their MTimes
  vtkCellArray* CellsKey = nullptr;
  vtkMTimeType CellsMTime = 0;
  vtkUnsignedCharArray* TypesKey = nullptr;
  vtkMTimeType TypesMTime = 0;
  vtkIdType NumberOfPointsKey = -1;
  // plan key: surface object, its MTime, method
  vtkPolyData* SurfaceKey = nullptr;
  vtkMTimeType SurfaceMTime = 0;
  std::string PlanMethod;
  // polygon key: the surface's polygon cell array and its MTime
  vtkCellArray* PolysKey = nullptr;
  vtkMTimeType PolysMTime = 0;
  // rest surface normals key (TRANSFORM_POINT_NORMALS): the points object and its MTime
  vtkPoints* RestKey = nullptr;
  vtkMTimeType RestMTime = 0;
  // buffers for arrays that are not vtkDoubleArray
  std::vector<double> RestPoints, Points, Displacements, Rotations, CellIds, PCoords, Distances,
    Faces, Fallback;
};

// the wrapped enumerators are the driver's values (the properties hold them as ints)
static_assert(vtkDeformationTransferFilter::RECOMPUTE_NORMALS ==
      static_cast<int>(hoembed::TransferNormals::Recompute) &&
    vtkDeformationTransferFilter::ROTATE_NORMALS ==
      static_cast<int>(hoembed::TransferNormals::Rotate) &&
    vtkDeformationTransferFilter::DEFORM_NORMALS ==
      static_cast<int>(hoembed::TransferNormals::Deform) &&
    vtkDeformationTransferFilter::RECOMPUTE_POINT_NORMALS ==
      static_cast<int>(hoembed::TransferPointNormals::Recompute) &&
    vtkDeformationTransferFilter::TRANSFORM_POINT_NORMALS ==
      static_cast<int>(hoembed::TransferPointNormals::Transform),
  "vtkDeformationTransferFilter's modes are hoembed::TransferNormals and TransferPointNormals");

//------------------------------------------------------------------------------
vtkDeformationTransferFilter::vtkDeformationTransferFilter() : Internal(new Internals)
{
  // the defaults are the driver's
  const hoembed::TransferOptions o;
  this->NormalMode = static_cast<int>(o.NormalMode);
  this->ComputePointNormals = o.ComputePointNormals;
  this->PointNormalsMode = static_cast<int>(o.PointNormalsMode);
  this->CheckInvertedElements = o.CheckInvertedElements;
  this->FaceTolerance = o.FaceTolerance;
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
  if (surface->GetNumberOfPoints() == 0 &&
    vtkStreamingDemandDrivenPipeline::GetUpdateNumberOfPieces(
      outputVector->GetInformationObject(0)) > 1)
  {
    // An empty piece of a distributed surface moves to an empty result on this process,
    // not an error: a failure on some processes only would leave the collective calls
    // downstream (ParaView's delivery to the client) waiting for them.
    output->Initialize();
    return 1;
  }
  if (!this->PrepareMesh(mesh))
  {
    return 0;
  }
  this->UpdateProgress(0.1);
  if (!this->PreparePlan(surface, mesh))
  {
    return 0;
  }
  this->UpdateProgress(0.3);
  vtkNew<vtkPoints> newPoints;
  vtkSmartPointer<vtkFloatArray> normals;
  if (this->ComputePointNormals)
  {
    this->PreparePolygons(surface);
    normals = vtkSmartPointer<vtkFloatArray>::New();
    normals->SetName(hoembed::ArrayNames::Normals);
    normals->SetNumberOfComponents(3);
    normals->SetNumberOfTuples(surface->GetNumberOfPoints());
  }
  if (!this->TransferPoints(surface, mesh, newPoints, normals))
  {
    return 0;
  }
  this->UpdateProgress(0.8);
  this->WriteOutput(surface, newPoints, normals, output);
  this->UpdateProgress(1.0);
  return 1;
}

//------------------------------------------------------------------------------
bool vtkDeformationTransferFilter::PrepareMesh(vtkUnstructuredGrid* mesh)
{
  Internals& I = *this->Internal;
  const vtkIdType numMeshPoints = mesh->GetNumberOfPoints();
  const std::string sizeError = hoembed::TransferDriver::CheckMeshSize(
    numMeshPoints, mesh->GetNumberOfCells(), mesh->GetCells() != nullptr);
  if (!sizeError.empty())
  {
    vtkErrorMacro(<< sizeError);
    return false;
  }
  vtkCellArray* cells = mesh->GetCells();
  vtkUnsignedCharArray* types = mesh->GetCellTypesArray();
  if (cells == I.CellsKey && cells->GetMTime() == I.CellsMTime && types == I.TypesKey &&
    (!types || types->GetMTime() == I.TypesMTime) && numMeshPoints == I.NumberOfPointsKey)
  {
    return true;
  }
  std::vector<double> unused, degrees;
  bool rebuilt = false;
  const std::string error =
    I.Driver.SetMeshTopology(hoembed::ViewTetMesh(mesh, false, unused, &degrees), rebuilt);
  if (!error.empty())
  {
    vtkErrorMacro(<< error);
    I.CellsKey = nullptr;
    return false;
  }
  if (rebuilt)
  {
    ++this->TopologyBuildCount;
  }
  I.CellsKey = cells;
  I.CellsMTime = cells->GetMTime();
  I.TypesKey = types;
  I.TypesMTime = types ? types->GetMTime() : 0;
  I.NumberOfPointsKey = numMeshPoints;
  return true;
}

//------------------------------------------------------------------------------
bool vtkDeformationTransferFilter::PreparePlan(vtkPolyData* surface, vtkUnstructuredGrid* mesh)
{
  Internals& I = *this->Internal;
  hoembed::TransferDriver& driver = I.Driver;
  // the driver judges what the surface holds (CheckSurface); this only reads it
  vtkFieldData* fd = surface->GetFieldData();
  const vtkStdString* methodValue = FieldString(fd, hoembed::ArrayNames::EmbeddingMethod);
  const vtkStdString* fpValue = FieldString(fd, hoembed::ArrayNames::EmbeddingMeshFingerprint);
  const vtkIdType numVerts = surface->GetNumberOfPoints();
  vtkPointData* pd = surface->GetPointData();
  vtkDataArray* cellIds = pd->GetArray(EmbeddingCellId);
  vtkDataArray* pcoords = pd->GetArray(EmbeddingParametricCoords);
  vtkDataArray* dist = pd->GetArray(EmbeddingDistance);
  vtkDataArray* faces = pd->GetArray(EmbeddingFace);
  vtkDataArray* fallback = pd->GetArray(EmbeddingFallbackOffset);
  hoembed::TransferSurfaceInfo info;
  info.NumberOfVertices = numVerts;
  info.Method = methodValue ? methodValue->c_str() : nullptr;
  info.Fingerprint = fpValue ? fpValue->c_str() : nullptr;
  info.CellIds = Shape(cellIds);
  info.ParametricCoords = Shape(pcoords);
  info.Distances = Shape(dist);
  info.Faces = Shape(faces);
  info.FallbackOffsets = Shape(fallback);
  hoembed::EmbeddingMethod m;
  hoembed::TransferArraysUsed used;
  const std::string checkError = driver.CheckSurface(info, m, used);
  if (!checkError.empty())
  {
    vtkErrorMacro(<< checkError);
    return false;
  }
  const std::string method = *methodValue;
  if (surface == I.SurfaceKey && surface->GetMTime() == I.SurfaceMTime && driver.HasPlan() &&
    method == I.PlanMethod)
  {
    return true;
  }
  I.SurfaceKey = nullptr;
  hoembed::TransferEmbedding em;
  em.NumberOfVertices = numVerts;
  em.Method = m;
  em.CellIds = ContiguousDoubles(cellIds, numVerts, I.CellIds);
  em.ParametricCoords = ContiguousDoubles(pcoords, numVerts, I.PCoords);
  em.Distances = used.Distances ? ContiguousDoubles(dist, numVerts, I.Distances) : nullptr;
  em.Faces = used.Faces ? ContiguousDoubles(faces, numVerts, I.Faces) : nullptr;
  em.FallbackOffsets =
    used.FallbackOffsets ? ContiguousDoubles(fallback, numVerts, I.Fallback) : nullptr;
  const std::string error = driver.BuildPlan(em, this->FaceTolerance, mesh->GetLength());
  // the copies are needed only while the plan is built
  std::vector<double>().swap(I.CellIds);
  std::vector<double>().swap(I.PCoords);
  std::vector<double>().swap(I.Distances);
  std::vector<double>().swap(I.Faces);
  std::vector<double>().swap(I.Fallback);
  if (!error.empty())
  {
    vtkErrorMacro(<< error);
    return false;
  }
  I.SurfaceKey = surface;
  I.SurfaceMTime = surface->GetMTime();
  I.PlanMethod = method;
  ++this->PlanBuildCount;
  return true;
}

//------------------------------------------------------------------------------
bool vtkDeformationTransferFilter::TransferPoints(
  vtkPolyData* surface, vtkUnstructuredGrid* mesh, vtkPoints* newPoints, vtkFloatArray* normals)
{
  Internals& I = *this->Internal;
  const vtkIdType numMeshPoints = mesh->GetNumberOfPoints();
  hoembed::TransferFrame frame;
  frame.Points = ContiguousDoubles(mesh->GetPoints()->GetData(), numMeshPoints, I.Points);
  frame.Normals = static_cast<hoembed::TransferNormals>(this->NormalMode);
  frame.CountInverted = this->CheckInvertedElements;
  if (normals)
  {
    frame.PointNormals = normals->GetPointer(0);
    frame.PointNormalsMode = static_cast<hoembed::TransferPointNormals>(this->PointNormalsMode);
    vtkPoints* rest = surface->GetPoints();
    if (frame.PointNormalsMode == hoembed::TransferPointNormals::Transform && rest &&
      (!I.Driver.HasRestSurfaceNormals() || rest != I.RestKey || rest->GetMTime() != I.RestMTime))
    {
      if (rest->GetDataType() == VTK_FLOAT)
      {
        I.Driver.SetRestSurfacePoints(static_cast<const float*>(rest->GetVoidPointer(0)));
      }
      else
      {
        I.Driver.SetRestSurfacePoints(
          ContiguousDoubles(rest->GetData(), rest->GetNumberOfPoints(), I.RestPoints));
      }
      I.RestKey = rest;
      I.RestMTime = rest->GetMTime();
    }
  }
  vtkPointData* pd = mesh->GetPointData();
  vtkDataArray* disp = pd->GetArray(hoembed::ArrayNames::Displacement);
  vtkDataArray* rot = pd->GetArray(hoembed::ArrayNames::NodalRotation);
  bool useDisp = false, useRot = false;
  hoembed::TransferDriver::FrameArraysUsed(
    frame.Normals, frame.PointNormalsMode, numMeshPoints, Shape(disp), Shape(rot), useDisp, useRot);
  frame.Displacements = useDisp ? ContiguousDoubles(disp, numMeshPoints, I.Displacements) : nullptr;
  frame.Rotations = useRot ? ContiguousDoubles(rot, numMeshPoints, I.Rotations) : nullptr;
  int precision = VTK_DOUBLE;
  if (this->OutputPointsPrecision == SINGLE_PRECISION ||
    (this->OutputPointsPrecision == DEFAULT_PRECISION && surface->GetPoints() &&
      surface->GetPoints()->GetDataType() == VTK_FLOAT))
  {
    precision = VTK_FLOAT;
  }
  newPoints->SetDataType(precision);
  newPoints->SetNumberOfPoints(surface->GetNumberOfPoints());
  void* out = newPoints->GetVoidPointer(0);
  std::vector<std::string> warnings;
  const std::string error =
    I.Driver.EvaluateFrame(frame, precision == VTK_DOUBLE ? static_cast<double*>(out) : nullptr,
      precision == VTK_FLOAT ? static_cast<float*>(out) : nullptr, warnings);
  this->NumberOfInvertedElements = static_cast<vtkIdType>(I.Driver.GetNumberOfInvertedCells());
  this->NumberOfFoldedPointNormals = static_cast<vtkIdType>(I.Driver.GetNumberOfFoldedNormals());
  for (const std::string& w : warnings)
  {
    vtkWarningMacro(<< w);
  }
  if (!error.empty())
  {
    vtkErrorMacro(<< error);
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
void vtkDeformationTransferFilter::WriteOutput(
  vtkPolyData* surface, vtkPoints* newPoints, vtkFloatArray* normals, vtkPolyData* output)
{
  output->CopyStructure(surface);
  output->SetPoints(newPoints);
  output->GetPointData()->ShallowCopy(surface->GetPointData());
  output->GetCellData()->ShallowCopy(surface->GetCellData());
  output->GetFieldData()->ShallowCopy(surface->GetFieldData());
  // Every Embedding* point array (the embedding's own, and its diagnostics) describes the
  // rest state, not this frame.
  const char* prefix = hoembed::ArrayNames::EmbeddingPrefix;
  for (int a = output->GetPointData()->GetNumberOfArrays() - 1; a >= 0; --a)
  {
    const char* name = output->GetPointData()->GetArrayName(a);
    if (name && std::strncmp(name, prefix, std::strlen(prefix)) == 0)
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
  if (normals)
  {
    output->GetPointData()->SetNormals(normals);
  }
}

// The driver's polygons (for the point normals), rebuilt when the surface's polygon
// array changed.
void vtkDeformationTransferFilter::PreparePolygons(vtkPolyData* surface)
{
  Internals& I = *this->Internal;
  const vtkIdType numVerts = surface->GetNumberOfPoints();
  vtkCellArray* polys = surface->GetPolys();
  if (polys != I.PolysKey || (polys && polys->GetMTime() != I.PolysMTime))
  {
    const vtkIdType numPolys = polys ? polys->GetNumberOfCells() : 0;
    std::vector<std::int64_t> offsets(numPolys + 1, 0), conn;
    vtkDataArray* offs = polys ? polys->GetOffsetsArray() : nullptr;
    vtkDataArray* ids = polys ? polys->GetConnectivityArray() : nullptr;
    for (vtkIdType p = 0; offs && p <= numPolys; ++p)
    {
      offsets[p] = static_cast<std::int64_t>(offs->GetComponent(p, 0));
    }
    conn.resize(polys ? polys->GetNumberOfConnectivityIds() : 0);
    for (size_t k = 0; ids && k < conn.size(); ++k)
    {
      conn[k] = static_cast<std::int64_t>(ids->GetComponent(static_cast<vtkIdType>(k), 0));
    }
    I.Driver.SetPolygons(offsets.data(), conn.data(), numPolys, numVerts);
    I.PolysKey = polys;
    I.PolysMTime = polys ? polys->GetMTime() : 0;
  }
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
  os << indent << "PointNormalsMode: "
     << (this->PointNormalsMode == TRANSFORM_POINT_NORMALS ? "TRANSFORM_POINT_NORMALS"
                                                           : "RECOMPUTE_POINT_NORMALS")
     << "\n";
  os << indent << "CheckInvertedElements: " << (this->CheckInvertedElements ? "On" : "Off") << "\n";
  os << indent << "FaceTolerance: " << this->FaceTolerance << "\n";
  os << indent << "OutputPointsPrecision: " << this->OutputPointsPrecision << "\n";
  os << indent << "NumberOfInvertedElements: " << this->NumberOfInvertedElements << "\n";
  os << indent << "TopologyBuildCount: " << this->TopologyBuildCount << "\n";
  os << indent << "PlanBuildCount: " << this->PlanBuildCount << "\n";
}
