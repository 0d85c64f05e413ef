#include "vtkEmbeddingCoordinatesFilter.h"

#include "hoembedClosestPoint.h"
#include "hoembedEmbeddingFlood.h"
#include "hoembedMeshFingerprint.h"

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

namespace
{
using Id = hoembed::EmbeddingMesh::Id;

// Copy the points as 3 doubles each (float and double arrays read directly); false with
// `bad` the first point with a non-finite coordinate.
bool CopyFinitePoints(vtkPoints* pts, std::vector<double>& out, vtkIdType& bad)
{
  const vtkIdType n = pts->GetNumberOfPoints();
  vtkDataArray* data = pts->GetData();
  if (auto* d = vtkDoubleArray::FastDownCast(data))
    out.assign(d->GetPointer(0), d->GetPointer(0) + 3 * n);
  else if (auto* f = vtkFloatArray::FastDownCast(data))
    out.assign(f->GetPointer(0), f->GetPointer(0) + 3 * n);
  else
  {
    out.resize(3 * static_cast<size_t>(n));
    for (vtkIdType i = 0; i < n; ++i)
      pts->GetPoint(i, &out[3 * i]);
  }
  for (vtkIdType i = 0; i < n; ++i)
  {
    const double* x = &out[3 * i];
    if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2]))
    {
      bad = i;
      return false;
    }
  }
  return true;
}

// The first cell (in order) whose type differs from cell 0's or whose size is not npc;
// Cell -1 when there is none.
struct CellScan
{
  vtkIdType Cell = -1;
  int Type = 0;
  vtkIdType Size = 0;
};

template <typename T>
CellScan ScanCells(const T* offsets, const T* ids, const unsigned char* types, vtkIdType ncells,
  int npc, std::vector<Id>& conn, hoembed::MeshFingerprint& fingerprint)
{
  CellScan bad;
  const int type0 = types[0];
  for (vtkIdType c = 0; c < ncells; ++c)
  {
    const vtkIdType size = static_cast<vtkIdType>(offsets[c + 1] - offsets[c]);
    if (types[c] != type0 || size != npc)
    {
      bad.Cell = c;
      bad.Type = types[c];
      bad.Size = size;
      return bad;
    }
  }
  // every cell has npc ids: they lie back to back
  conn.assign(ids + offsets[0], ids + offsets[ncells]);
  for (vtkIdType c = 0; c < ncells; ++c)
    fingerprint.AddCell(type0, conn.data() + npc * c, npc);
  return bad;
}

CellScan ReadCells(vtkUnstructuredGrid* mesh, int npc, std::vector<Id>& conn,
  hoembed::MeshFingerprint& fingerprint)
{
  vtkCellArray* cells = mesh->GetCells();
  const unsigned char* types = mesh->GetCellTypesArray()->GetPointer(0);
  const vtkIdType ncells = mesh->GetNumberOfCells();
  if (cells->IsStorage64Bit())
    return ScanCells(cells->GetOffsetsArray64()->GetPointer(0),
      cells->GetConnectivityArray64()->GetPointer(0), types, ncells, npc, conn, fingerprint);
  return ScanCells(cells->GetOffsetsArray32()->GetPointer(0),
    cells->GetConnectivityArray32()->GetPointer(0), types, ncells, npc, conn, fingerprint);
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
  // vertices; the larger the surface, the smaller the share of its page faults: 6% of
  // the time on dragon's 50k vertices, not worth holding hundreds of MB between Updates)
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
  return this->Method == BARYCENTRIC ? "barycentric" : "normal-offset";
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
  vtkIdType bad = -1;
  std::vector<double>& meshPts = em.Points;
  if (!CopyFinitePoints(mesh->GetPoints(), meshPts, bad))
  {
    msg << "The FE mesh has a non-finite (NaN or infinite) coordinate at node " << bad << ".";
    return msg.str();
  }

  // cells: all tet10 or all tet4
  const vtkIdType ncells = mesh->GetNumberOfCells();
  const int type0 = mesh->GetCellType(0);
  if (type0 != VTK_QUADRATIC_TETRA && type0 != VTK_TETRA)
  {
    msg << "The FE mesh has a cell of type " << type0 << " (cell 0): only VTK_TETRA (10) "
           "and VTK_QUADRATIC_TETRA (24) cells are supported.";
    return msg.str();
  }
  const int npc = type0 == VTK_QUADRATIC_TETRA ? 10 : 4;
  const vtkIdType npts = mesh->GetNumberOfPoints();
  std::vector<Id>& conn = em.Connectivity;
  // cell types and connectivity read straight from the arrays (no vtkIdList per cell),
  // the fingerprint in the same pass
  hoembed::MeshFingerprint fingerprint(npts, ncells);
  const CellScan scan = ReadCells(mesh, npc, conn, fingerprint);
  if (scan.Cell >= 0)
  {
    if (scan.Type != type0)
    {
      msg << "The FE mesh mixes cell types: cell " << scan.Cell << " has type " << scan.Type
          << ", cell 0 has type " << type0 << "; use only tet4 or only tet10 cells.";
    }
    else
    {
      msg << "Cell " << scan.Cell << " has " << scan.Size << " points, expected " << npc << ".";
    }
    return msg.str();
  }
  for (vtkIdType i = 0; i < npc * ncells; ++i)
  {
    if (conn[i] < 0 || conn[i] >= npts)
    {
      msg << "Cell " << i / npc << " refers to node " << conn[i] << ", out of range [0, " << npts
          << ").";
      return msg.str();
    }
  }
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
  this->Internals->PreparedFingerprint = fingerprint.Hex();
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
  std::vector<double>& sp = internals.SurfacePoints; // 3 doubles each
  if (!CopyFinitePoints(surface->GetPoints(), sp, bad))
  {
    vtkErrorMacro("The surface has a non-finite (NaN or infinite) coordinate at point " << bad << ".");
    return 0;
  }
  // surface points and triangles
  const vtkIdType ns = surface->GetNumberOfPoints();
  std::vector<Id>& tris = internals.Triangles;
  tris.clear();
  {
    // a polygon or strip of k points gives k - 2 triangles
    vtkIdType ntri = 0;
    for (vtkCellArray* ca : { surface->GetPolys(), surface->GetStrips() })
      ntri += std::max<vtkIdType>(0, ca->GetNumberOfConnectivityIds() - 2 * ca->GetNumberOfCells());
    tris.reserve(3 * static_cast<size_t>(ntri));
    auto it = vtk::TakeSmartPointer(surface->GetPolys()->NewIterator());
    for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
    {
      vtkIdType n;
      const vtkIdType* p;
      it->GetCurrentCell(n, p);
      for (vtkIdType k = 1; k + 1 < n; ++k)
      {
        tris.push_back(p[0]);
        tris.push_back(p[k]);
        tris.push_back(p[k + 1]);
      }
    }
    auto st = vtk::TakeSmartPointer(surface->GetStrips()->NewIterator());
    for (st->GoToFirstCell(); !st->IsDoneWithTraversal(); st->GoToNextCell())
    {
      vtkIdType n;
      const vtkIdType* p;
      st->GetCurrentCell(n, p);
      for (vtkIdType k = 0; k + 2 < n; ++k)
      {
        tris.push_back(p[k]);
        tris.push_back(p[k + 1]);
        tris.push_back(p[k + 2]);
      }
    }
  }
  // the surface's problems are reported after the mesh's
  std::string surfaceError;
  if (tris.size() / 3 > static_cast<size_t>(VTK_INT_MAX))
    surfaceError = "The surface has more than 2^31 triangles, which is not supported.";
  for (Id id : tris)
  {
    if (surfaceError.empty() && (id < 0 || id >= ns))
    {
      std::ostringstream os;
      os << "A surface polygon refers to point " << id << ", out of range [0, " << ns << ").";
      surfaceError = os.str();
    }
  }

  // The FE mesh is prepared anew unless the prepared one belongs to this very input
  // (ReuseMeshPreparation) and was validated when validation is asked for. The surface's
  // order for the flood depends on the surface only: it is built meanwhile (two tasks;
  // on two threads the preparation's serial parts and the ordering overlap). Both tasks
  // only record problems; messages and progress come from this thread.
  hoembed::EmbeddingMesh& em = internals.Mesh;
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
    return 0;
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
    return 0;
  }
  this->UpdateProgress(0.1);

  std::vector<hoembed::VertexEmbedding>& res = internals.Results;
  const int method =
    this->Method == BARYCENTRIC ? hoembed::EMBED_BARYCENTRIC : hoembed::EMBED_NORMAL_OFFSET;
  hoembed::FloodSurface(em, method, res, [this](double x) { this->UpdateProgress(0.1 + 0.9 * x); },
    nullptr, internals.Flood);
  // surface-sized memory beyond the cap is given back however this Update ends
  struct Trim
  {
    vtkInternals* Internals;
    ~Trim() { this->Internals->ReleaseLargeSurfaceMemory(); }
  } trim{ this->Internals.get() };

  vtkNew<vtkIdTypeArray> cellId;
  cellId->SetName("EmbeddingCellId");
  cellId->SetNumberOfTuples(ns);
  vtkNew<vtkDoubleArray> pcoords;
  pcoords->SetName("EmbeddingParametricCoords");
  pcoords->SetNumberOfComponents(3);
  pcoords->SetNumberOfTuples(ns);
  vtkNew<vtkDoubleArray> dist;
  dist->SetName("EmbeddingDistance");
  dist->SetNumberOfTuples(ns);
  vtkNew<vtkDoubleArray> residual;
  residual->SetName("EmbeddingResidual");
  residual->SetNumberOfTuples(ns);
  vtkNew<vtkDoubleArray> closest;
  closest->SetName("EmbeddingClosestDistance");
  closest->SetNumberOfTuples(ns);
  vtkNew<vtkSignedCharArray> face;
  face->SetName("EmbeddingFace");
  face->SetNumberOfTuples(ns);
  vtkNew<vtkIntArray> iters;
  iters->SetName("EmbeddingIterations");
  iters->SetNumberOfTuples(ns);
  vtkNew<vtkIntArray> visited;
  visited->SetName("EmbeddingElementsVisited");
  visited->SetNumberOfTuples(ns);
  std::atomic<vtkIdType> firstFailed(ns);
  std::atomic<vtkIdType> uncertified(0), firstUncertified(ns);
  auto lowest = [](std::atomic<vtkIdType>& first, vtkIdType i) {
    vtkIdType cur = first.load();
    while (i < cur && !first.compare_exchange_weak(cur, i))
    {
    }
  };
  vtkSMPTools::For(0, ns, [&](vtkIdType b, vtkIdType e) {
    vtkIdType localUncertified = 0;
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
    }
    uncertified += localUncertified;
  });
  if (firstFailed.load() < ns)
  {
    vtkErrorMacro("Surface point " << firstFailed.load()
                                   << " could not be embedded (non-finite result).");
    return 0;
  }
  this->NumberOfUncertifiedPoints = uncertified.load();
  if (this->NumberOfUncertifiedPoints > 0)
  {
    vtkWarningMacro(<< this->NumberOfUncertifiedPoints
                    << " surface point(s) (e.g. point " << firstUncertified.load()
                    << "): the closest-point search on a curved boundary face ran out of its "
                       "budget; their distance may be a local minimum only.");
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

  vtkNew<vtkFieldData> fd;
  if (surface->GetFieldData())
    fd->DeepCopy(surface->GetFieldData());
  vtkNew<vtkStringArray> methodName;
  methodName->SetName("EmbeddingMethod");
  methodName->InsertNextValue(this->GetMethodAsString());
  vtkNew<vtkStringArray> fp;
  fp->SetName("EmbeddingMeshFingerprint");
  fp->InsertNextValue(internals.PreparedFingerprint);
  fd->AddArray(methodName);
  fd->AddArray(fp);
  output->SetFieldData(fd);
  this->UpdateProgress(1.0);
  return 1;
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
}//------------------------------------------------------------------------------
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


