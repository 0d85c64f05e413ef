#include "vtkTet10Mesher.h"

#include "hoembedMesherDriver.h"
#include "hoembedSurfaceCheck.h"
#include "hoembedTetGenBridge.h"

#include "vtkAppendPolyData.h"
#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCellData.h"
#include "vtkCellValidator.h"
#include "vtkQuadraticTetra.h"
#include "vtkCleanPolyData.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkGenericCell.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMath.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkQuadricDecimation.h"
#include "vtkSmartPointer.h"
#include "vtkStaticCellLocator.h"
#include "vtkStaticPointLocator.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkIdList.h"
#include "vtkPolygon.h"
#include "vtkTriangleStrip.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"
#include "vtkWindowedSincPolyDataFilter.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

vtkStandardNewMacro(vtkTet10Mesher);

namespace
{
using Id = std::int64_t;

// A triangle surface as plain arrays.
struct TriSurface
{
  std::vector<double> Points;
  std::vector<Id> Tris;
};

bool ToArrays(vtkPolyData* pd, TriSurface& s)
{
  const vtkIdType np = pd->GetNumberOfPoints();
  s.Points.resize(3 * np);
  for (vtkIdType i = 0; i < np; ++i)
  {
    pd->GetPoint(i, &s.Points[3 * i]);
  }
  s.Tris.clear();
  vtkCellArray* polys = pd->GetPolys();
  vtkIdType n;
  const vtkIdType* ids;
  for (polys->InitTraversal(); polys->GetNextCell(n, ids);)
  {
    if (n != 3)
    {
      return false;
    }
    s.Tris.insert(s.Tris.end(), ids, ids + 3);
  }
  return true;
}

vtkSmartPointer<vtkPolyData> FromArrays(const TriSurface& s)
{
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToDouble();
  pts->SetNumberOfPoints(static_cast<vtkIdType>(s.Points.size() / 3));
  for (vtkIdType i = 0; i < pts->GetNumberOfPoints(); ++i)
  {
    pts->SetPoint(i, &s.Points[3 * i]);
  }
  vtkNew<vtkCellArray> polys;
  for (size_t t = 0; t < s.Tris.size() / 3; ++t)
  {
    const vtkIdType ids[3] = { s.Tris[3 * t], s.Tris[3 * t + 1], s.Tris[3 * t + 2] };
    polys->InsertNextCell(3, ids);
  }
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  pd->SetPoints(pts);
  pd->SetPolys(polys);
  return pd;
}

// Closest points on the fine surface.
class SurfaceProjector
{
public:
  explicit SurfaceProjector(vtkPolyData* surface)
  {
    this->Locator->SetDataSet(surface);
    this->Locator->BuildLocator();
  }
  double Project(const double x[3], double out[3])
  {
    vtkIdType cellId;
    int subId;
    double d2;
    this->Locator->FindClosestPoint(x, out, this->Cell, cellId, subId, d2);
    return std::sqrt(d2);
  }

  // Unit normal of the surface triangle closest to x.
  void Normal(const double x[3], double n[3])
  {
    vtkIdType cellId;
    int subId;
    double d2, cp[3];
    this->Locator->FindClosestPoint(x, cp, this->Cell, cellId, subId, d2);
    n[0] = n[1] = n[2] = 0.0;
    if (cellId >= 0 && this->Cell->GetNumberOfPoints() >= 3)
      vtkPolygon::ComputeNormal(this->Cell->GetPoints(), n);
  }

  // First crossing of the segment a-b with the surface.
  bool Ray(const double a[3], const double b[3], double hit[3])
  {
    double t, pc[3];
    int subId;
    vtkIdType cellId;
    return this->Locator->IntersectWithLine(a, b, 0.0, t, hit, pc, subId, cellId, this->Cell) != 0;
  }

private:
  vtkNew<vtkStaticCellLocator> Locator;
  vtkNew<vtkGenericCell> Cell;
};

} // namespace

vtkTet10Mesher::vtkTet10Mesher() = default;
vtkTet10Mesher::~vtkTet10Mesher() = default;

int vtkTet10Mesher::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  return 1;
}

namespace
{
// Triangles of every polygon and strip (vertices and lines dropped). vtkTriangleFilter
// drops polygons its ear cut cannot split (non-planar or degenerate quads of artist
// meshes, opening false holes): a quad is split along its shorter diagonal, a larger
// polygon by vtkPolygon's ear cut, else as a fan from its first vertex.
vtkSmartPointer<vtkPolyData> Triangulate(vtkPolyData* input)
{
  vtkNew<vtkCellArray> tris;
  vtkNew<vtkPolygon> polygon;
  vtkNew<vtkIdList> local;
  vtkIdType n;
  const vtkIdType* ids;
  vtkCellArray* polys = input->GetPolys();
  for (polys->InitTraversal(); polys->GetNextCell(n, ids);)
  {
    if (n == 3)
    {
      tris->InsertNextCell(3, ids);
      continue;
    }
    if (n == 4)
    {
      double x[4][3];
      for (int k = 0; k < 4; ++k)
        input->GetPoint(ids[k], x[k]);
      const bool d02 =
        vtkMath::Distance2BetweenPoints(x[0], x[2]) <= vtkMath::Distance2BetweenPoints(x[1], x[3]);
      const vtkIdType t1[3] = { ids[0], ids[1], ids[d02 ? 2 : 3] };
      const vtkIdType t2[3] = { d02 ? ids[0] : ids[1], ids[2], ids[3] };
      tris->InsertNextCell(3, t1);
      tris->InsertNextCell(3, t2);
      continue;
    }
    if (n < 3)
      continue;
    polygon->GetPointIds()->SetNumberOfIds(n);
    polygon->GetPoints()->SetNumberOfPoints(n);
    for (vtkIdType k = 0; k < n; ++k)
    {
      polygon->GetPointIds()->SetId(k, ids[k]);
      polygon->GetPoints()->SetPoint(k, input->GetPoint(ids[k]));
    }
    if (polygon->Triangulate(local) && local->GetNumberOfIds() == 3 * (n - 2))
    {
      for (vtkIdType t = 0; t < n - 2; ++t)
      {
        const vtkIdType tri[3] = { ids[local->GetId(3 * t)], ids[local->GetId(3 * t + 1)],
          ids[local->GetId(3 * t + 2)] };
        tris->InsertNextCell(3, tri);
      }
    }
    else
      for (vtkIdType k = 1; k + 1 < n; ++k)
      {
        const vtkIdType tri[3] = { ids[0], ids[k], ids[k + 1] };
        tris->InsertNextCell(3, tri);
      }
  }
  vtkCellArray* strips = input->GetStrips();
  for (strips->InitTraversal(); strips->GetNextCell(n, ids);)
    vtkTriangleStrip::DecomposeStrip(static_cast<int>(n), ids, tris);
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->SetPoints(input->GetPoints());
  out->SetPolys(tris);
  return out;
}

// Point ids of every cell kind in range. vtkCleanPolyData (and the triangulation below)
// read them unchecked: an id out of range crashes them.
std::string CheckPointIds(vtkPolyData* input)
{
  const vtkIdType np = input->GetNumberOfPoints();
  const std::pair<const char*, vtkCellArray*> kinds[] = { { "vertex", input->GetVerts() },
    { "line", input->GetLines() }, { "polygon", input->GetPolys() },
    { "triangle strip", input->GetStrips() } };
  for (const auto& kind : kinds)
  {
    vtkIdType n, k = 0;
    const vtkIdType* ids;
    auto it = vtk::TakeSmartPointer(kind.second->NewIterator());
    for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell(), ++k)
    {
      it->GetCurrentCell(n, ids);
      for (vtkIdType j = 0; j < n; ++j)
      {
        if (ids[j] < 0 || ids[j] >= np)
        {
          std::ostringstream msg;
          msg << kind.first << " " << k << " of the input names point id " << ids[j]
              << ", but the surface has " << np << " points (ids 0.." << np - 1 << ")";
          return msg.str();
        }
      }
    }
  }
  return std::string();
}

// The element count a request asks for: TargetNumberOfElements, or the volume to mesh
// (below) over the volume of a regular tet of edge TargetEdgeLength.
double EstimatedElements(vtkPolyData* input, double edge, int target)
{
  if (!(edge > 0.0))
    return static_cast<double>(target);
  // The volume to mesh: what the surface encloses (signed volume, taken about the
  // bounding-box centre so that an open surface's value does not depend on where the
  // origin is), or, when larger, the envelope of a sheet: its area times the envelope's
  // thickness (twice the default offset of a quarter of the element size). An open
  // surface encloses nothing meaningful; its signed volume can be 0 for a sheet through
  // the origin, which let any request through.
  double bounds[6];
  input->GetBounds(bounds);
  const double o[3] = { 0.5 * (bounds[0] + bounds[1]), 0.5 * (bounds[2] + bounds[3]),
    0.5 * (bounds[4] + bounds[5]) };
  double volume = 0.0, area = 0.0;
  vtkIdType n;
  const vtkIdType* ids;
  auto it = vtk::TakeSmartPointer(input->GetPolys()->NewIterator());
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
  {
    it->GetCurrentCell(n, ids);
    double a[3], b[3], c[3];
    for (vtkIdType j = 1; j + 1 < n; ++j)
    {
      input->GetPoint(ids[0], a);
      input->GetPoint(ids[j], b);
      input->GetPoint(ids[j + 1], c);
      for (int d = 0; d < 3; ++d)
      {
        a[d] -= o[d];
        b[d] -= o[d];
        c[d] -= o[d];
      }
      double ab[3], ac[3], cross[3];
      for (int d = 0; d < 3; ++d)
      {
        ab[d] = b[d] - a[d];
        ac[d] = c[d] - a[d];
      }
      vtkMath::Cross(ab, ac, cross);
      area += 0.5 * vtkMath::Norm(cross);
      volume += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                  a[2] * (b[0] * c[1] - b[1] * c[0])) / 6.0;
    }
  }
  const double sheet = area * 0.5 * edge;
  return std::max(std::fabs(volume), sheet) * 6.0 * std::sqrt(2.0) / (edge * edge * edge);
}

// Distributed pipelines: every process's piece of the surface, gathered in rank order (so
// every process appends the same surface) before any check, so that all processes take
// part in the collective call and then mesh the same surface. The pieces' seams are
// merged by the read step with every other coincident point. Returns an error message.
std::string GatherPieces(vtkPolyData*& input, vtkAppendPolyData* gathered)
{
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  if (!controller || controller->GetNumberOfProcesses() <= 1)
    return std::string();
  vtkNew<vtkPolyData> mine;
  mine->ShallowCopy(input);
  std::vector<vtkSmartPointer<vtkDataObject>> pieces;
  if (!controller->AllGather(mine, pieces) ||
    static_cast<int>(pieces.size()) != controller->GetNumberOfProcesses())
  {
    std::ostringstream msg;
    msg << "could not gather the surface's pieces from the "
        << controller->GetNumberOfProcesses() << " processes";
    return msg.str();
  }
  for (const auto& piece : pieces)
  {
    auto* poly = vtkPolyData::SafeDownCast(piece);
    if (poly && poly->GetNumberOfPoints() > 0)
      gathered->AddInputData(poly);
  }
  if (gathered->GetNumberOfInputConnections(0) > 0)
  {
    gathered->Update();
    input = gathered->GetOutput();
  }
  return std::string();
}

// Read step: triangulate polygons and strips, drop vertices and lines, merge coincident
// points. Returns an error message, empty on success.
std::string CleanInput(vtkPolyData* input, double mergeTolerance, vtkSmartPointer<vtkPolyData>& fine,
  TriSurface& arrays)
{
  if (input->GetNumberOfPoints() == 0 || input->GetNumberOfCells() == 0)
  {
    std::ostringstream msg;
    msg << "the input surface is empty (" << input->GetNumberOfPoints() << " points, "
        << input->GetNumberOfCells() << " cells)";
    return msg.str();
  }
  for (vtkIdType i = 0; i < input->GetNumberOfPoints(); ++i)
  {
    double x[3];
    input->GetPoint(i, x);
    if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2]))
    {
      std::ostringstream msg;
      msg << "the input surface has a non-finite coordinate (NaN or Inf) at point " << i;
      return msg.str();
    }
  }
  if (input->GetNumberOfPolys() + input->GetNumberOfStrips() == 0)
    return "the input has no polygons (only points or lines), so nothing to enclose in a "
           "volume: give a triangle surface (reconstruct one from a point cloud first, e.g. "
           "with vtkSurfaceReconstructionFilter)";
  vtkSmartPointer<vtkPolyData> triangles = Triangulate(input);
  vtkNew<vtkCleanPolyData> clean;
  clean->SetInputData(triangles);
  clean->PointMergingOn();
  // Shared vertices stored with rounding (STL exports: ~1e-6 apart) must meet: the merge
  // tolerance is relative to the bounding-box diagonal.
  if (mergeTolerance > 0.0)
  {
    clean->ToleranceIsAbsoluteOff();
    clean->SetTolerance(mergeTolerance);
  }
  else
  {
    clean->SetAbsoluteTolerance(0.0);
    clean->ToleranceIsAbsoluteOn();
  }
  clean->ConvertLinesToPointsOff();
  clean->ConvertPolysToLinesOff();
  clean->ConvertStripsToPolysOff();
  clean->Update();
  fine = clean->GetOutput();
  if (!ToArrays(fine, arrays) || arrays.Tris.empty())
    return "the input has no usable triangles after triangulation";
  return std::string();
}

// The VTK side of the driver's services: decimation and smoothing of the fine surface,
// queries on it, distances to a triangle set, VTK's cell validator. Holds what the
// closures use, so it must outlive the driver call.
class VTKServices
{
public:
  explicit VTKServices(vtkPolyData* fine)
    : Fine(fine)
    , Projector(fine)
  {
    this->VertexLocator->SetDataSet(fine);
    this->VertexLocator->BuildLocator();
    this->CheckCell->GetPoints()->SetNumberOfPoints(10);
    for (vtkIdType i = 0; i < 10; ++i)
      this->CheckCell->GetPointIds()->SetId(i, i);
    this->Diagonal = fine->GetLength();
  }

  hoembed::MesherServices Make()
  {
    hoembed::MesherServices s;
    s.Decimate = [this](double reduction, bool smoothed, std::vector<double>& points,
                   std::vector<hoembed::SurfaceCheck::Id>& tris) {
      vtkNew<vtkQuadricDecimation> decimate;
      decimate->SetInputData(smoothed ? this->Smoothed() : this->Fine.Get());
      decimate->SetTargetReduction(reduction);
      decimate->VolumePreservationOff();
      decimate->AttributeErrorMetricOff();
      decimate->Update();
      TriSurface coarse;
      if (!ToArrays(decimate->GetOutput(), coarse))
        return false;
      points.swap(coarse.Points);
      tris.swap(coarse.Tris);
      return true;
    };
    s.Fine.Closest = [this](const double x[3], double cp[3]) { this->Projector.Project(x, cp); };
    s.Fine.VerticesWithin = [this](const double x[3], double r, std::vector<double>& out) {
      this->VertexLocator->FindPointsWithinRadius(r, x, this->NearIds);
      out.resize(3 * this->NearIds->GetNumberOfIds());
      for (vtkIdType k = 0; k < this->NearIds->GetNumberOfIds(); ++k)
        this->Fine->GetPoint(this->NearIds->GetId(k), &out[3 * k]);
    };
    s.NormalAt = [this](const double x[3], double n[3]) { this->Projector.Normal(x, n); };
    s.Fine.Ray = [this](const double a[3], const double b[3], double hit[3]) {
      return this->Projector.Ray(a, b, hit);
    };
    s.MaxDistanceToTriangles = [](const std::vector<double>& points,
                                 const std::vector<hoembed::SurfaceCheck::Id>& tris,
                                 const std::vector<double>& query, hoembed::SurfaceCheck::Id stride) {
      TriSurface target;
      target.Points = points;
      target.Tris = tris;
      vtkSmartPointer<vtkPolyData> pd = FromArrays(target);
      SurfaceProjector toTarget(pd);
      double worst = 0.0;
      for (size_t i = 0; i < query.size() / 3; i += static_cast<size_t>(stride))
      {
        double cp[3];
        worst = std::max(worst, toTarget.Project(&query[3 * i], cp));
      }
      return worst;
    };
    // Beyond det J > 0, curved elements must pass VTK's own cell validator (its
    // linearised faces must not intersect or flip), so that VTK tools accept every element.
    s.ExtraCheck = [this](const double* x) {
      // VTK's validator is not scale-invariant (its tolerance and some of its internal
      // ones are absolute; seen: a cell of a surface of diagonal 5e-6 passed at its own
      // scale and failed at unit scale). The cell is checked as it is in the surface
      // scaled to a unit diagonal, with a tolerance of 1e-6 there: as a user checking the
      // mesh so finds it.
      const double scale = this->Diagonal > 0.0 ? 1.0 / this->Diagonal : 1.0;
      for (vtkIdType i = 0; i < 10; ++i)
      {
        const double p[3] = { (x[3 * i] - x[0]) * scale, (x[3 * i + 1] - x[1]) * scale,
          (x[3 * i + 2] - x[2]) * scale };
        this->CheckCell->GetPoints()->SetPoint(i, p);
      }
      // Curved faces are legitimately not convex: only intersections and flips count.
      const auto state = static_cast<short>(vtkCellValidator::Check(this->CheckCell, 1e-6));
      const short bad = static_cast<short>(vtkCellValidator::State::IntersectingEdges) |
        static_cast<short>(vtkCellValidator::State::IntersectingFaces) |
        static_cast<short>(vtkCellValidator::State::FacesAreOrientedIncorrectly) |
        static_cast<short>(vtkCellValidator::State::WrongNumberOfPoints);
      return (state & bad) == 0;
    };
    return s;
  }

private:
  // The low-pass filtered fine surface (windowed sinc keeps the volume), made once.
  vtkPolyData* Smoothed()
  {
    if (!this->SmoothedSurface)
    {
      vtkNew<vtkWindowedSincPolyDataFilter> smooth;
      smooth->SetInputData(this->Fine);
      smooth->SetNumberOfIterations(30);
      smooth->SetPassBand(0.01);
      smooth->NormalizeCoordinatesOn();
      smooth->BoundarySmoothingOff();
      smooth->FeatureEdgeSmoothingOff();
      smooth->NonManifoldSmoothingOff();
      smooth->Update();
      this->SmoothedSurface = smooth->GetOutput();
    }
    return this->SmoothedSurface;
  }

  vtkSmartPointer<vtkPolyData> Fine;
  vtkSmartPointer<vtkPolyData> SmoothedSurface;
  SurfaceProjector Projector;
  vtkNew<vtkStaticPointLocator> VertexLocator;
  vtkNew<vtkIdList> NearIds;
  vtkNew<vtkQuadraticTetra> CheckCell;
  double Diagonal = 0.0;
};

// Write step: the driver's arrays into the output grid.
void WriteOutput(const hoembed::MesherResult& r, vtkUnstructuredGrid* output)
{
  const int npc = r.NodesPerCell;
  const vtkIdType nPts = static_cast<vtkIdType>(r.Points.size() / 3);
  const vtkIdType nTets = static_cast<vtkIdType>(r.MinScaledJacobian.size());
  vtkNew<vtkPoints> outPts;
  outPts->SetDataTypeToDouble();
  outPts->SetNumberOfPoints(nPts);
  for (vtkIdType i = 0; i < nPts; ++i)
    outPts->SetPoint(i, &r.Points[3 * i]);
  vtkNew<vtkCellArray> cells;
  cells->AllocateExact(nTets, npc * nTets);
  vtkNew<vtkDoubleArray> quality;
  quality->SetName("MinScaledJacobian");
  quality->SetNumberOfTuples(nTets);
  for (vtkIdType t = 0; t < nTets; ++t)
  {
    vtkIdType ids[10];
    for (int a = 0; a < npc; ++a)
      ids[a] = r.Conn[npc * t + a];
    cells->InsertNextCell(npc, ids);
    quality->SetValue(t, r.MinScaledJacobian[t]);
  }
  vtkNew<vtkUnsignedCharArray> bnd;
  bnd->SetName("BoundaryNode");
  bnd->SetNumberOfTuples(nPts);
  for (vtkIdType i = 0; i < nPts; ++i)
    bnd->SetValue(i, r.BoundaryNode[i]);
  output->SetPoints(outPts);
  output->SetCells(npc == 10 ? VTK_QUADRATIC_TETRA : VTK_TETRA, cells);
  output->GetCellData()->AddArray(quality);
  output->GetPointData()->AddArray(bnd);
  auto addId = [&](const char* name, vtkIdType v) {
    vtkNew<vtkIdTypeArray> a;
    a->SetName(name);
    a->InsertNextValue(v);
    output->GetFieldData()->AddArray(a);
  };
  addId("RelaxedNodeCount", r.RelaxedNodeCount);
  addId("CurvedNodeCount", r.CurvedNodeCount);
  addId("EnvelopeNodeCount", r.EnvelopeNodeCount);
  addId("BoundaryCrossingsFound", r.BoundaryCrossingsFound);
  addId("BoundaryCrossingsLeft", r.BoundaryCrossingsLeft);
  addId("PoorElementCount", r.PoorElementCount);
  vtkNew<vtkDoubleArray> quantiles;
  quantiles->SetName("MinScaledJacobianQuantiles");
  quantiles->SetNumberOfComponents(3);
  quantiles->InsertNextTuple(r.QualityQuantiles);
  output->GetFieldData()->AddArray(quantiles);
  vtkNew<vtkDoubleArray> dev;
  dev->SetName("MaxSurfaceDeviation");
  dev->InsertNextValue(r.MaxSurfaceDeviation);
  output->GetFieldData()->AddArray(dev);
  vtkNew<vtkDoubleArray> offset;
  offset->SetName("EnvelopeOffset");
  offset->InsertNextValue(r.Wrapped ? r.EnvelopeOffset : 0.0);
  output->GetFieldData()->AddArray(offset);
}
} // namespace

int vtkTet10Mesher::RequestUpdateExtent(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector*)
{
  // Distributed pipelines (a global controller of N > 1 processes, as in pvbatch/pvserver
  // under MPI): every process asks its upstream for the piece it holds (rank of N), the
  // same request the pipeline's other consumers of that surface make, and RequestData
  // gathers the pieces. Asking for the whole surface instead would not work: consumers of
  // one output port share one update request, so the mesher's request for the whole
  // would override the embedding's request for a piece on the same surface. Whatever
  // piece is asked of the mesher, it produces the whole mesh (the embedding and transfer
  // need all of it on every process).
  // In one process (a piece asked of a serial pipeline) the whole surface is requested.
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  const bool distributed = controller && controller->GetNumberOfProcesses() > 1;
  using SDDP = vtkStreamingDemandDrivenPipeline;
  if (vtkInformation* inInfo = inputVector[0]->GetInformationObject(0))
  {
    inInfo->Set(SDDP::UPDATE_PIECE_NUMBER(), distributed ? controller->GetLocalProcessId() : 0);
    inInfo->Set(SDDP::UPDATE_NUMBER_OF_PIECES(), distributed ? controller->GetNumberOfProcesses() : 1);
    inInfo->Set(SDDP::UPDATE_NUMBER_OF_GHOST_LEVELS(), 0);
  }
  return 1;
}

// Before any VTK filter sees the input: properties finite (the clamp macros let NaN
// through), point ids in range, and a size TetGen can mesh in reasonable time and memory.
bool vtkTet10Mesher::CheckRequest(vtkPolyData* input)
{
  const std::pair<const char*, double> props[] = { { "TargetEdgeLength", this->TargetEdgeLength },
    { "RadiusEdgeRatio", this->RadiusEdgeRatio }, { "MinDihedralAngle", this->MinDihedralAngle },
    { "CurvedQualityRatio", this->CurvedQualityRatio },
    { "MinimumQuality", this->MinimumQuality },
    { "SurfaceDeviationWarning", this->SurfaceDeviationWarning },
    { "EnvelopeTolerance", this->EnvelopeTolerance }, { "MergeTolerance", this->MergeTolerance } };
  for (const auto& p : props)
  {
    if (!std::isfinite(p.second))
    {
      vtkErrorMacro(<< p.first << " is " << p.second << ": a finite value is needed");
      return false;
    }
  }
  const std::string idError = CheckPointIds(input);
  if (!idError.empty())
  {
    vtkErrorMacro(<< idError);
    return false;
  }
  const double estimate =
    EstimatedElements(input, this->TargetEdgeLength, this->TargetNumberOfElements);
  if (estimate > static_cast<double>(this->MaximumNumberOfElements))
  {
    // Peak memory of the mesher per element, rounded up from a measurement
    // (Benchmarks/RESULTS.md, Reliability).
    const double bytesPerElement = 1.0e3;
    vtkErrorMacro("the mesh would have about "
      << static_cast<long long>(estimate) << " elements (about "
      << std::ceil(estimate * bytesPerElement / 1e9)
      << " GB of memory to mesh), more than MaximumNumberOfElements = "
      << this->MaximumNumberOfElements
      << ": ask for fewer elements (or a longer TargetEdgeLength), or raise "
         "MaximumNumberOfElements");
    return false;
  }
  return true;
}

int vtkTet10Mesher::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0]);
  vtkUnstructuredGrid* output = vtkUnstructuredGrid::GetData(outputVector);
  this->RelaxedNodeCount = 0;
  this->CurvedNodeCount = 0;
  this->MaxSurfaceDeviation = 0.0;
  this->EnvelopeNodeCount = 0;
  if (!input || !output)
  {
    vtkErrorMacro("missing input surface or output grid");
    return 0;
  }
  output->Initialize();
  vtkNew<vtkAppendPolyData> gathered; // holds the gathered surface while it is read
  const std::string gatherError = GatherPieces(input, gathered);
  if (!gatherError.empty())
  {
    vtkErrorMacro(<< gatherError);
    return 0;
  }
  if (!this->CheckRequest(input))
  {
    return 0;
  }
  // AbortExecute stops TetGen too (polled through progress events while it meshes).
  hoembed::ScopedTetGenAbort tetgenAbort([this]() {
    this->UpdateProgress(std::min(1.0, this->GetProgress() + 1e-6));
    return this->AbortExecute != 0;
  });

  vtkSmartPointer<vtkPolyData> fine;
  TriSurface fineArrays;
  const std::string readError = CleanInput(input, this->MergeTolerance, fine, fineArrays);
  if (!readError.empty())
  {
    vtkErrorMacro(<< readError);
    return 0;
  }

  hoembed::MesherOptions options;
  options.TargetNumberOfElements = this->TargetNumberOfElements;
  options.TargetEdgeLength = this->TargetEdgeLength;
  options.ElementOrder = this->ElementOrder;
  options.CurveBoundary = this->CurveBoundary;
  options.ProjectCorners = this->ProjectCorners;
  options.PreserveBoundary = this->PreserveBoundary;
  options.RadiusEdgeRatio = this->RadiusEdgeRatio;
  options.MinDihedralAngle = this->MinDihedralAngle;
  options.SurfaceDeviationWarning = this->SurfaceDeviationWarning;
  options.CurvedQualityRatio = this->CurvedQualityRatio;
  options.MinimumQuality = this->MinimumQuality;
  options.EnvelopeTolerance = this->EnvelopeTolerance;
  VTKServices services(fine);
  const hoembed::MesherResult result = hoembed::RunMesher(fineArrays.Points, fineArrays.Tris,
    options, services.Make(), [this](double f) { this->UpdateProgress(f); });
  for (const std::string& w : result.Warnings)
    vtkWarningMacro(<< w);
  if (!result.Error.empty())
  {
    vtkErrorMacro(<< result.Error);
    return 0;
  }
  this->CurvedNodeCount = result.CurvedNodeCount;
  this->RelaxedNodeCount = result.RelaxedNodeCount;
  this->MaxSurfaceDeviation = result.MaxSurfaceDeviation;
  this->EnvelopeNodeCount = result.EnvelopeNodeCount;
  WriteOutput(result, output);
  this->UpdateProgress(1.0);
  return 1;
}

void vtkTet10Mesher::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "TargetNumberOfElements: " << this->TargetNumberOfElements << "\n";
  os << indent << "MaximumNumberOfElements: " << this->MaximumNumberOfElements << "\n";
  os << indent << "TargetEdgeLength: " << this->TargetEdgeLength << "\n";
  os << indent << "ElementOrder: " << this->ElementOrder << "\n";
  os << indent << "CurveBoundary: " << (this->CurveBoundary ? "On" : "Off") << "\n";
  os << indent << "ProjectCorners: " << (this->ProjectCorners ? "On" : "Off") << "\n";
  os << indent << "PreserveBoundary: " << (this->PreserveBoundary ? "On" : "Off") << "\n";
  os << indent << "RadiusEdgeRatio: " << this->RadiusEdgeRatio << "\n";
  os << indent << "MinDihedralAngle: " << this->MinDihedralAngle << "\n";
  os << indent << "CurvedQualityRatio: " << this->CurvedQualityRatio << "\n";
  os << indent << "MinimumQuality: " << this->MinimumQuality << "\n";
  os << indent << "EnvelopeTolerance: " << this->EnvelopeTolerance << "\n";
  os << indent << "MergeTolerance: " << this->MergeTolerance << "\n";
  os << indent << "SurfaceDeviationWarning: " << this->SurfaceDeviationWarning << "\n";
  os << indent << "RelaxedNodeCount: " << this->RelaxedNodeCount << "\n";
  os << indent << "CurvedNodeCount: " << this->CurvedNodeCount << "\n";
  os << indent << "MaxSurfaceDeviation: " << this->MaxSurfaceDeviation << "\n";
  os << indent << "EnvelopeNodeCount: " << this->EnvelopeNodeCount << "\n";
}
