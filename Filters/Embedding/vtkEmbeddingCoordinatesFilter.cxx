#include "vtkEmbeddingCoordinatesFilter.h"

#include "hoembedClosestPoint.h"
#include "hoembedEmbeddingFlood.h"
#include "hoembedSurfaceTriangles.h"
#include "hoembedArrayNames.h"
#include "hoembedTetMeshInputVTK.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCellData.h"
#include "vtkCellType.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
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
#include "vtkSMPTools.h"
#include "vtkSignedCharArray.h"
#include "vtkUnsignedCharArray.h"
#include "vtkStringArray.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <sstream>
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

// Copy the surface's points as 3 doubles each (float and double arrays read directly);
// false with `bad` the first point with a non-finite coordinate.
bool CopyFinitePoints(vtkPoints* pts, std::vector<double>& out, vtkIdType& bad)
{
  const vtkIdType n = pts->GetNumberOfPoints();
  const double* d = nullptr;
  const float* f = nullptr;
  hoembed::ViewPoints(pts, d, f, out);
  if (d && d != out.data())
    out.assign(d, d + 3 * n);
  else if (f)
    out.assign(f, f + 3 * n);
  bad = hoembed::FirstNonFinitePoint(out.data(), n);
  return bad < 0;
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

struct vtkEmbeddingCoordinatesFilter::vtkInternals
{
  // mesh-sized: kept
  hoembed::EmbeddingMesh Mesh;
  // the input the prepared mesh belongs to (no grid: none, or the last preparation failed)
  MeshState PreparedState;
  bool PreparedValidated = false;
  std::string PreparedFingerprint;
  // surface-sized: kept up to MaxKeptBytes (~350 bytes per vertex, so about 190k
  // vertices): the larger the surface, the smaller the share of its page faults in the
  // time, so past that size the memory is not worth holding between Updates)
  hoembed::EmbedWorkspace Flood;
  std::vector<double> SurfacePoints;
  std::vector<Id> Triangles, Order;
  std::vector<hoembed::VertexEmbedding> Results;
  static constexpr std::size_t MaxKeptBytes = std::size_t(64) << 20;

  void ReleaseLargeSurfaceMemory()
  {
    const std::size_t bytes = this->Flood.GetCapacityInBytes() +
      sizeof(double) * this->SurfacePoints.capacity() +
      sizeof(Id) * (this->Triangles.capacity() + this->Order.capacity()) +
      sizeof(hoembed::VertexEmbedding) * this->Results.capacity();
    if (bytes <= MaxKeptBytes)
      return;
    this->Flood.Release();
    std::vector<double>().swap(this->SurfacePoints);
    std::vector<Id>().swap(this->Triangles);
    std::vector<Id>().swap(this->Order);
    std::vector<hoembed::VertexEmbedding>().swap(this->Results);
  }
};

vtkEmbeddingCoordinatesFilter::vtkEmbeddingCoordinatesFilter()
  : Internals(new vtkInternals)
{
  this->SetNumberOfInputPorts(2);
}

vtkEmbeddingCoordinatesFilter::~vtkEmbeddingCoordinatesFilter() = default;

const char* vtkEmbeddingCoordinatesFilter::GetMethodAsString()
{
  return hoembed::EmbeddingMethodName(this->Method == BARYCENTRIC ? hoembed::EmbeddingMethod::Barycentric : hoembed::EmbeddingMethod::NormalOffset);
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

std::string vtkEmbeddingCoordinatesFilter::PrepareMesh(vtkUnstructuredGrid* mesh)
{
  std::ostringstream msg;
  hoembed::EmbeddingMesh& em = this->Internals->Mesh;
  // types, connectivity, node ranges, finite points and the fingerprint: the one reader
  hoembed::TetMeshInput input;
  std::vector<double> scratch;
  const std::string readError = input.Read(hoembed::ViewTetMesh(mesh, true, scratch),
    hoembed::TetMeshInput::KeepPoints | hoembed::TetMeshInput::KeepFingerprint);
  if (!readError.empty())
  {
    return readError + ".";
  }
  em.Points.swap(input.Points);
  em.Connectivity.swap(input.Connectivity);
  const int npc = input.NodesPerCell;
  const vtkIdType ncells = input.NumberOfCells;
  // element validity is checked in the pass that builds the cell maps
  Id firstInvalid = ncells;
  const std::string err = em.Prepare(npc, this->ValidateElements ? &firstInvalid : nullptr);
  if (firstInvalid < ncells)
  {
    msg << "The FE mesh has an inverted or degenerate element: cell "
      << firstInvalid << " has a non-positive Jacobian determinant"
      << (npc == 10 ? " somewhere inside it." : ".");
    return msg.str();
  }
  if (!err.empty())
  {
    msg << "The FE mesh topology is not usable: " << err;
    return msg.str();
  }
  this->Internals->PreparedFingerprint = input.Fingerprint;
  return std::string();
}

int vtkEmbeddingCoordinatesFilter::RequestData(vtkInformation*,
  vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* surface = vtkPolyData::GetData(inputVector[0], 0);
  vtkUnstructuredGrid* mesh = vtkUnstructuredGrid::GetData(inputVector[1], 0);
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  vtkInternals& internals = *this->Internals;
  this->NumberOfUncertifiedPoints = 0;
  this->NumberOfFallbackPoints = 0;
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
  vtkIdType bad = -1;
  if (!CopyFinitePoints(surface->GetPoints(), internals.SurfacePoints, bad))
  {
    vtkErrorMacro("The surface has a non-finite (NaN or infinite) coordinate at point " << bad << ".");
    return 0;
  }
  // the surface's triangles (polygons fanned, strips split); their problems are reported
  // after the mesh's
  std::vector<Id>& tris = internals.Triangles;
  tris.clear();
  hoembed::AppendSurfaceTriangles(ViewCells(surface->GetPolys()), ViewCells(surface->GetStrips()), tris);
  const std::string surfaceError = hoembed::CheckSurfaceTriangles(tris, surface->GetNumberOfPoints());
  if (!this->PrepareMeshAndOrder(mesh, surface->GetNumberOfPoints(), surfaceError))
  {
    return 0;
  }
  this->UpdateProgress(0.1);

  const int method =
    this->Method == BARYCENTRIC ? hoembed::EMBED_BARYCENTRIC : hoembed::EMBED_NORMAL_OFFSET;
  hoembed::FloodSurface(internals.Mesh, method, internals.Results,
    [this](double x) { this->UpdateProgress(0.1 + 0.9 * x); }, nullptr, internals.Flood);
  // surface-sized memory beyond the cap is given back however this Update ends
  struct Trim
  {
    vtkInternals* Internals;
    ~Trim() { this->Internals->ReleaseLargeSurfaceMemory(); }
  } trim{ this->Internals.get() };
  if (!this->WriteOutput(surface, method, output))
  {
    return 0;
  }
  this->UpdateProgress(1.0);
  return 1;
}

// Prepare the FE mesh (unless the prepared one serves) and order the surface for the
// flood; report the mesh's problem, else `surfaceError`, else none.
bool vtkEmbeddingCoordinatesFilter::PrepareMeshAndOrder(
  vtkUnstructuredGrid* mesh, vtkIdType ns, const std::string& surfaceError)
{
  vtkInternals& internals = *this->Internals;
  const std::vector<double>& sp = internals.SurfacePoints;
  const std::vector<Id>& tris = internals.Triangles;
  // The FE mesh is prepared anew unless the prepared one belongs to this very input
  // (ReuseMeshPreparation) and was validated when validation is asked for. The surface's
  // order for the flood depends on the surface only: it is built meanwhile (two tasks;
  // on two threads the preparation's serial parts and the ordering overlap). Both tasks
  // only record problems; messages and progress come from this thread.
  const MeshState meshState = MeshState::Of(mesh);
  const bool prepare = !(this->ReuseMeshPreparation && internals.PreparedState == meshState &&
    (internals.PreparedValidated || !this->ValidateElements));
  std::vector<Id>& order = internals.Order; // res[k] belongs to surface point order[k]
  std::string meshError;
  if (prepare)
    internals.PreparedState = MeshState();
  vtkSMPTools::For(0, 2, 1, [&](vtkIdType b, vtkIdType e) {
    for (vtkIdType task = b; task < e; ++task)
    {
      if (task == 0 && prepare)
        meshError = this->PrepareMesh(mesh);
      else if (task == 1 && surfaceError.empty())
        hoembed::OrderSurface(
          sp.data(), ns, tris, this->NumberOfPartitions, &order, internals.Flood);
    }
  });
  if (!meshError.empty())
  {
    vtkErrorMacro(<< meshError);
    return false;
  }
  if (prepare)
  {
    internals.PreparedState = meshState;
    internals.PreparedValidated = this->ValidateElements;
    ++this->NumberOfMeshPreparations;
  }
  if (!surfaceError.empty())
  {
    vtkErrorMacro(<< surfaceError);
    return false;
  }
  return true;
}

// The embedding arrays (in surface point order) and field data on a shallow copy of the
// surface; false with an error when a point has no finite result.
bool vtkEmbeddingCoordinatesFilter::WriteOutput(vtkPolyData* surface, int method, vtkPolyData* output)
{
  vtkInternals& internals = *this->Internals;
  const vtkIdType ns = surface->GetNumberOfPoints();
  const std::vector<hoembed::VertexEmbedding>& res = internals.Results;
  const std::vector<Id>& order = internals.Order; // res[k] belongs to surface point order[k]
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
  closest->SetName("EmbeddingClosestDistance");
  closest->SetNumberOfTuples(ns);
  vtkNew<vtkSignedCharArray> face;
  face->SetName(hoembed::ArrayNames::EmbeddingFace);
  face->SetNumberOfTuples(ns);
  vtkNew<vtkIntArray> iters;
  iters->SetName("EmbeddingIterations");
  iters->SetNumberOfTuples(ns);
  vtkNew<vtkIntArray> visited;
  visited->SetName("EmbeddingElementsVisited");
  visited->SetNumberOfTuples(ns);
  std::atomic<vtkIdType> firstFailed(ns);
  std::atomic<vtkIdType> uncertified(0), firstUncertified(ns);
  vtkNew<vtkUnsignedCharArray> fallback;
  fallback->SetName(hoembed::ArrayNames::EmbeddingFallback);
  fallback->SetNumberOfTuples(ns);
  std::atomic<vtkIdType> fallbacks(0), firstFallback(ns);
  auto lowest = [](std::atomic<vtkIdType>& first, vtkIdType i) {
    vtkIdType cur = first.load();
    while (i < cur && !first.compare_exchange_weak(cur, i))
    {
    }
  };
  vtkSMPTools::For(0, ns, [&](vtkIdType b, vtkIdType e) {
    vtkIdType localUncertified = 0, localFallbacks = 0;
    for (vtkIdType k = b; k < e; ++k)
    {
      const hoembed::VertexEmbedding& r = res[k];
      const vtkIdType i = order[k];
      if (r.Uncertified)
      {
        ++localUncertified;
        lowest(firstUncertified, i);
      }
      if (!std::isfinite(r.PC[0]) || !std::isfinite(r.PC[1]) || !std::isfinite(r.PC[2]) ||
        !std::isfinite(r.Distance) || !std::isfinite(r.Residual) || r.Cell < 0)
      {
        lowest(firstFailed, i);
        continue;
      }
      cellId->SetValue(i, r.Cell);
      pcoords->SetTypedTuple(i, r.PC);
      dist->SetValue(i, r.Distance);
      residual->SetValue(i, r.Residual);
      closest->SetValue(i, r.ClosestDistance);
      face->SetValue(i, method == hoembed::EMBED_BARYCENTRIC ? -1 : r.Face);
      iters->SetValue(i, r.Iterations);
      visited->SetValue(i, r.Visited);
      fallback->SetValue(i, r.Fallback ? 1 : 0);
      if (r.Fallback)
      {
        ++localFallbacks;
        lowest(firstFallback, i);
      }
    }
    uncertified += localUncertified;
    fallbacks += localFallbacks;
  });
  if (firstFailed.load() < ns)
  {
    vtkErrorMacro("Surface point " << firstFailed.load()
                                   << " could not be embedded (non-finite result).");
    return false;
  }
  this->NumberOfUncertifiedPoints = uncertified.load();
  if (this->NumberOfUncertifiedPoints > 0)
  {
    vtkWarningMacro(<< this->NumberOfUncertifiedPoints
                    << " surface point(s) (e.g. point " << firstUncertified.load()
                    << "): the closest-point search on a curved boundary face ran out of its "
                       "budget; their distance may be a local minimum only.");
  }

  this->NumberOfFallbackPoints = fallbacks.load();
  vtkNew<vtkDoubleArray> fallbackOffset;
  if (this->NumberOfFallbackPoints > 0)
  {
    vtkWarningMacro(<< this->NumberOfFallbackPoints << " surface point(s) (e.g. point "
                    << firstFallback.load()
                    << ") have no normal offset v = p + d n: they use their closest point p "
                       "and the offset v - p instead (EmbeddingFallback = 1).");
    // the offsets in parametric units, only where some point needs them
    fallbackOffset->SetName(hoembed::ArrayNames::EmbeddingFallbackOffset);
    fallbackOffset->SetNumberOfComponents(3);
    fallbackOffset->SetNumberOfTuples(ns);
    vtkSMPTools::For(0, ns, [&](vtkIdType b, vtkIdType e) {
      for (vtkIdType k = b; k < e; ++k)
      {
        double q[3] = { 0, 0, 0 };
        if (res[k].Fallback) // the q of its residual (EmbedVertex), computed again
          hoembed::TetMapOffset(internals.Mesh.CellMaps[res[k].Cell], res[k].PC,
            &internals.SurfacePoints[3 * order[k]], q);
        fallbackOffset->SetTypedTuple(order[k], q);
      }
    });
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
  fp->InsertNextValue(internals.PreparedFingerprint);
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


