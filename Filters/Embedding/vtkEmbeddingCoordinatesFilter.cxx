#include "vtkEmbeddingCoordinatesFilter.h"

#include "hoembedEmbeddingDriver.h"
#include "hoembedArrayNames.h"
#include "hoembedTetMeshInputVTK.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCellData.h"
#include "vtkCellType.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSignedCharArray.h"
#include "vtkUnsignedCharArray.h"
#include "vtkStringArray.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

vtkStandardNewMacro(vtkEmbeddingCoordinatesFilter);

static_assert(vtkEmbeddingCoordinatesFilter::NORMAL_OFFSET == hoembed::EMBED_NORMAL_OFFSET &&
    vtkEmbeddingCoordinatesFilter::BARYCENTRIC == hoembed::EMBED_BARYCENTRIC,
  "the filter's Method values are hoembed::EmbeddingMethod's");

namespace
{
using Id = hoembed::EmbeddingMesh::Id;

// Views of a vtkCellArray's offsets and connectivity for the triangle kernel.
hoembed::CellArrayView ViewCells(vtkCellArray* ca)
{
  hoembed::CellArrayView v;
  v.NumberOfCells = ca ? ca->GetNumberOfCells() : 0;
  if (v.NumberOfCells == 0)
    return v;
  if (ca->IsStorage64Bit())
  {
    v.Offsets64 = reinterpret_cast<const std::int64_t*>(ca->GetOffsetsArray64()->GetPointer(0));
    v.Connectivity64 =
      reinterpret_cast<const std::int64_t*>(ca->GetConnectivityArray64()->GetPointer(0));
  }
  else
  {
    v.Offsets32 = reinterpret_cast<const std::int32_t*>(ca->GetOffsetsArray32()->GetPointer(0));
    v.Connectivity32 =
      reinterpret_cast<const std::int32_t*>(ca->GetConnectivityArray32()->GetPointer(0));
  }
  return v;
}

} // namespace

// What identifies a mesh input's state: the grid (its address and modification time,
// which covers its points) and the modification times of its cell array and of the
// arrays behind it (edited in place, those need their own Modified()).
struct MeshState
{
  const void* Grid = nullptr;
  vtkMTimeType Times[5] = { 0, 0, 0, 0, 0 };

  static MeshState Of(vtkUnstructuredGrid* mesh)
  {
    MeshState s;
    s.Grid = mesh;
    vtkCellArray* cells = mesh->GetCells();
    s.Times[0] = mesh->GetMTime();
    s.Times[1] = cells ? cells->GetMTime() : 0;
    s.Times[2] = cells ? cells->GetOffsetsArray()->GetMTime() : 0;
    s.Times[3] = cells ? cells->GetConnectivityArray()->GetMTime() : 0;
    s.Times[4] = mesh->GetCellTypesArray() ? mesh->GetCellTypesArray()->GetMTime() : 0;
    return s;
  }
  bool operator==(const MeshState& o) const
  {
    return this->Grid == o.Grid && std::equal(this->Times, this->Times + 5, o.Times);
  }
};

// The algorithm and its surface- and mesh-sized memory live in hoembed::EmbeddingDriver;
// this keeps what only the VTK binding knows: which input (and modification times) the
// driver's prepared mesh belongs to.
struct vtkEmbeddingCoordinatesFilter::vtkInternals
{
  hoembed::EmbeddingDriver Driver;
  // the input the prepared mesh belongs to (no grid: none, or the last preparation failed)
  MeshState PreparedState;
  bool PreparedValidated = false;
};

vtkEmbeddingCoordinatesFilter::vtkEmbeddingCoordinatesFilter() : Internals(new vtkInternals)
{
  this->SetNumberOfInputPorts(2);
  // the defaults are the driver's
  const hoembed::EmbeddingOptions o;
  this->Method = o.Method;
  this->NumberOfPartitions = o.NumberOfPartitions;
  this->ValidateElements = o.ValidateElements;
  this->ReuseMeshPreparation = o.ReuseMeshPreparation;
}

vtkEmbeddingCoordinatesFilter::~vtkEmbeddingCoordinatesFilter() = default;

const char* vtkEmbeddingCoordinatesFilter::GetMethodAsString()
{
  return hoembed::EmbeddingMethodName(this->Method == BARYCENTRIC
      ? hoembed::EmbeddingMethod::Barycentric
      : hoembed::EmbeddingMethod::NormalOffset);
}

void vtkEmbeddingCoordinatesFilter::SetMeshData(vtkUnstructuredGrid* mesh)
{
  this->SetInputData(1, mesh);
}

void vtkEmbeddingCoordinatesFilter::SetMeshConnection(vtkAlgorithmOutput* output)
{
  this->SetInputConnection(1, output);
}

int vtkEmbeddingCoordinatesFilter::FillInputPortInformation(int port, vtkInformation* info)
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

int vtkEmbeddingCoordinatesFilter::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* surface = vtkPolyData::GetData(inputVector[0], 0);
  vtkUnstructuredGrid* mesh = vtkUnstructuredGrid::GetData(inputVector[1], 0);
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  vtkInternals& internals = *this->Internals;
  hoembed::EmbeddingDriver& driver = internals.Driver;
  this->NumberOfUncertifiedPoints = 0;
  this->NumberOfFallbackPoints = 0;
  if (surface && output && surface->GetNumberOfPoints() == 0 &&
    vtkStreamingDemandDrivenPipeline::GetUpdateNumberOfPieces(
      outputVector->GetInformationObject(0)) > 1)
  {
    // An empty piece of a distributed surface (a serial reader gives every process but
    // the first nothing) is an empty result, not an error: a failure on some processes
    // only stops the pipeline there, and the collective calls downstream (ParaView's
    // delivery gathers every output to the client) then wait forever for them.
    output->Initialize();
    return 1;
  }
  if (!surface || surface->GetNumberOfPoints() == 0)
  {
    vtkErrorMacro("The surface (input port 0) is empty: it has no points.");
    return 0;
  }
  if (!mesh || mesh->GetNumberOfPoints() == 0 || mesh->GetNumberOfCells() == 0)
  {
    vtkErrorMacro("The FE mesh (input port 1) is empty: it needs points and tet4 or tet10 cells.");
    return 0;
  }
  // surface-sized memory beyond the driver's cap is given back however this Update ends
  struct Trim
  {
    hoembed::EmbeddingDriver* Driver;
    ~Trim()
    {
      this->Driver->ReleaseLargeSurfaceMemory();
    }
  } trim{ &driver };
  const double* pd = nullptr;
  const float* pf = nullptr;
  std::vector<double> scratch;
  hoembed::ViewPoints(surface->GetPoints(), pd, pf, scratch);
  const std::string surfaceError = driver.SetSurface(pd, pf, surface->GetNumberOfPoints(),
    ViewCells(surface->GetPolys()), ViewCells(surface->GetStrips()));
  if (!surfaceError.empty())
  {
    vtkErrorMacro(<< surfaceError);
    return 0;
  }
  std::vector<double>().swap(scratch);
  if (!this->PrepareMeshAndOrder(mesh))
  {
    return 0;
  }
  this->UpdateProgress(0.1);

  const int method =
    this->Method == BARYCENTRIC ? hoembed::EMBED_BARYCENTRIC : hoembed::EMBED_NORMAL_OFFSET;
  driver.Embed(method, [this](double x) { this->UpdateProgress(0.1 + 0.9 * x); });
  if (!this->WriteOutput(surface, output))
  {
    return 0;
  }
  this->UpdateProgress(1.0);
  return 1;
}

// Prepare the FE mesh (unless the prepared one serves) and order the surface for the
// flood; report the mesh's problem, else the surface's triangles', else none.
bool vtkEmbeddingCoordinatesFilter::PrepareMeshAndOrder(vtkUnstructuredGrid* mesh)
{
  vtkInternals& internals = *this->Internals;
  // The FE mesh is prepared anew unless the prepared one belongs to this very input
  // (ReuseMeshPreparation) and was validated when validation is asked for.
  const MeshState meshState = MeshState::Of(mesh);
  const bool prepare = !(this->ReuseMeshPreparation && internals.PreparedState == meshState &&
    (internals.PreparedValidated || !this->ValidateElements));
  std::vector<double> scratch, degrees;
  hoembed::TetMeshArrays arrays;
  if (prepare)
  {
    internals.PreparedState = MeshState();
    arrays = hoembed::ViewTetMesh(mesh, true, scratch, &degrees);
  }
  const std::string error = internals.Driver.PrepareAndOrder(
    prepare ? &arrays : nullptr, this->ValidateElements != 0, this->NumberOfPartitions);
  const bool meshOk = internals.Driver.GetFingerprint().size() > 0;
  if (prepare && meshOk)
  {
    internals.PreparedState = meshState;
    internals.PreparedValidated = this->ValidateElements;
    ++this->NumberOfMeshPreparations;
  }
  if (!error.empty())
  {
    vtkErrorMacro(<< error);
    return false;
  }
  return true;
}

// The embedding arrays (in surface point order) and field data on a shallow copy of the
// surface; false with an error when a point has no finite result.
bool vtkEmbeddingCoordinatesFilter::WriteOutput(vtkPolyData* surface, vtkPolyData* output)
{
  const hoembed::EmbeddingDriver& driver = this->Internals->Driver;
  const vtkIdType ns = surface->GetNumberOfPoints();
  vtkNew<vtkIdTypeArray> cellId;
  cellId->SetName(hoembed::ArrayNames::EmbeddingCellId);
  cellId->SetNumberOfTuples(ns);
  vtkNew<vtkDoubleArray> pcoords;
  pcoords->SetName(hoembed::ArrayNames::EmbeddingParametricCoords);
  pcoords->SetNumberOfComponents(3);
  pcoords->SetNumberOfTuples(ns);
  vtkNew<vtkDoubleArray> dist;
  dist->SetName(hoembed::ArrayNames::EmbeddingDistance);
  dist->SetNumberOfTuples(ns);
  vtkNew<vtkDoubleArray> residual;
  residual->SetName(hoembed::ArrayNames::EmbeddingResidual);
  residual->SetNumberOfTuples(ns);
  vtkNew<vtkDoubleArray> closest;
  closest->SetName(hoembed::ArrayNames::EmbeddingClosestDistance);
  closest->SetNumberOfTuples(ns);
  vtkNew<vtkSignedCharArray> face;
  face->SetName(hoembed::ArrayNames::EmbeddingFace);
  face->SetNumberOfTuples(ns);
  vtkNew<vtkIntArray> iters;
  iters->SetName(hoembed::ArrayNames::EmbeddingIterations);
  iters->SetNumberOfTuples(ns);
  vtkNew<vtkIntArray> visited;
  visited->SetName(hoembed::ArrayNames::EmbeddingElementsVisited);
  visited->SetNumberOfTuples(ns);
  vtkNew<vtkUnsignedCharArray> fallback;
  fallback->SetName(hoembed::ArrayNames::EmbeddingFallback);
  fallback->SetNumberOfTuples(ns);
  static_assert(sizeof(vtkIdType) == sizeof(std::int64_t), "64-bit vtkIdType");
  hoembed::EmbeddingOutputArrays arrays;
  arrays.CellId = reinterpret_cast<std::int64_t*>(cellId->GetPointer(0));
  arrays.ParametricCoords = pcoords->GetPointer(0);
  arrays.Distance = dist->GetPointer(0);
  arrays.Residual = residual->GetPointer(0);
  arrays.ClosestDistance = closest->GetPointer(0);
  arrays.Face = face->GetPointer(0);
  arrays.Iterations = iters->GetPointer(0);
  arrays.Visited = visited->GetPointer(0);
  arrays.Fallback = fallback->GetPointer(0);
  hoembed::EmbeddingSummary summary;
  const std::string error = driver.WriteArrays(arrays, summary);
  if (!error.empty())
  {
    vtkErrorMacro(<< error);
    return false;
  }
  this->NumberOfUncertifiedPoints = summary.Uncertified;
  this->NumberOfFallbackPoints = summary.Fallbacks;
  for (const std::string& warning : hoembed::EmbeddingWarnings(summary))
  {
    vtkWarningMacro(<< warning);
  }
  vtkNew<vtkDoubleArray> fallbackOffset;
  if (this->NumberOfFallbackPoints > 0)
  {
    // the offsets in parametric units, only where some point needs them
    fallbackOffset->SetName(hoembed::ArrayNames::EmbeddingFallbackOffset);
    fallbackOffset->SetNumberOfComponents(3);
    fallbackOffset->SetNumberOfTuples(ns);
    driver.WriteFallbackOffsets(fallbackOffset->GetPointer(0));
  }

  output->ShallowCopy(surface);
  vtkPointData* pd = output->GetPointData();
  pd->AddArray(cellId);
  pd->AddArray(pcoords);
  pd->AddArray(dist);
  pd->AddArray(residual);
  pd->AddArray(face);
  pd->AddArray(iters);
  pd->AddArray(visited);
  pd->AddArray(closest);
  pd->AddArray(fallback);
  if (this->NumberOfFallbackPoints > 0)
    pd->AddArray(fallbackOffset);

  vtkNew<vtkFieldData> fd;
  if (surface->GetFieldData())
    fd->DeepCopy(surface->GetFieldData());
  vtkNew<vtkStringArray> methodName;
  methodName->SetName(hoembed::ArrayNames::EmbeddingMethod);
  methodName->InsertNextValue(this->GetMethodAsString());
  vtkNew<vtkStringArray> fp;
  fp->SetName(hoembed::ArrayNames::EmbeddingMeshFingerprint);
  fp->InsertNextValue(driver.GetFingerprint());
  fd->AddArray(methodName);
  fd->AddArray(fp);
  vtkNew<vtkIdTypeArray> numFallback;
  numFallback->SetName(hoembed::ArrayNames::NumberOfFallbackPoints);
  numFallback->InsertNextValue(this->NumberOfFallbackPoints);
  fd->AddArray(numFallback);
  output->SetFieldData(fd);
  this->UpdateProgress(1.0);
  return true;
}

void vtkEmbeddingCoordinatesFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Method: " << this->GetMethodAsString() << "\n";
  os << indent << "NumberOfPartitions: " << this->NumberOfPartitions << "\n";
  os << indent << "ValidateElements: " << (this->ValidateElements ? "On" : "Off") << "\n";
  os << indent << "ReuseMeshPreparation: " << (this->ReuseMeshPreparation ? "On" : "Off") << "\n";
  os << indent << "NumberOfMeshPreparations: " << this->NumberOfMeshPreparations << "\n";
  os << indent << "NumberOfUncertifiedPoints: " << this->NumberOfUncertifiedPoints << "\n";
  os << indent << "NumberOfFallbackPoints: " << this->NumberOfFallbackPoints << "\n";
}

//------------------------------------------------------------------------------
int vtkEmbeddingCoordinatesFilter::RequestUpdateExtent(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector*)
{
  // Port 0 keeps the piece the pipeline asked for: each process embeds its piece of the
  // surface. A vertex's result depends only on its own connected component and the flood
  // partition (to the last bits, through the Newton start), so pieces embedded on several
  // processes equal the same pieces embedded together when NumberOfPartitions is fixed.
  // Port 1: the whole FE mesh on every process (it is small).
  using SDDP = vtkStreamingDemandDrivenPipeline;
  if (vtkInformation* inInfo = inputVector[1]->GetInformationObject(0))
  {
    inInfo->Set(SDDP::UPDATE_PIECE_NUMBER(), 0);
    inInfo->Set(SDDP::UPDATE_NUMBER_OF_PIECES(), 1);
    inInfo->Set(SDDP::UPDATE_NUMBER_OF_GHOST_LEVELS(), 0);
  }
  return 1;
}
