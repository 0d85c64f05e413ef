#include "vtkTet10Mesher.h"

#include "hoembedArrayNames.h"
#include "hoembedMesherDriver.h"
#include "hoembedSurfaceCheck.h"
#include "hoembedSurfaceRead.h"
#include "hoembedTetGenBridge.h"

#include "vtkAppendPolyData.h"
#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCellValidator.h"
#include "vtkQuadraticTetra.h"
#include "vtkCleanPolyData.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkGenericCell.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
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
#include "vtkTypeInt64Array.h"
#include "vtkIdList.h"
#include "vtkPolygon.h"
#include "vtkSMPTools.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"
#include "vtkWindowedSincPolyDataFilter.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
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

// The static locators sort their bin map with vtkSMPTools::Sort. Under TBB the order of
// the cells of one bin then depends on the scheduling, and with it which of two
// equidistant triangles FindClosestPoint returns for a point whose closest point is on
// their common edge (tens of 3000 such queries changed from one build of the locator to
// the next): the same surface gave another mesh. Built by the sequential backend, the
// order is std::sort's, the same at every run and thread count.
void BuildLocatorDeterministically(vtkLocator* l)
{
  vtkSMPTools::LocalScope(
    vtkSMPTools::Config{ 1, "Sequential", false }, [l]() { l->BuildLocator(); });
}

// Closest points on the fine surface.
class SurfaceProjector
{
public:
  explicit SurfaceProjector(vtkPolyData* surface)
  {
    this->Locator->SetDataSet(surface);
    BuildLocatorDeterministically(this->Locator);
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

vtkTet10Mesher::vtkTet10Mesher()
{
  // the defaults are the driver's
  const hoembed::MesherOptions o;
  this->TargetNumberOfElements = o.TargetNumberOfElements;
  this->TargetEdgeLength = o.TargetEdgeLength;
  this->ElementOrder = o.ElementOrder;
  this->CurveBoundary = o.CurveBoundary;
  this->ProjectCorners = o.ProjectCorners;
  this->PreserveBoundary = o.PreserveBoundary;
  this->RadiusEdgeRatio = o.RadiusEdgeRatio;
  this->MinDihedralAngle = o.MinDihedralAngle;
  this->SurfaceDeviationWarning = o.SurfaceDeviationWarning;
  this->CurvedQualityRatio = o.CurvedQualityRatio;
  this->MinimumQuality = o.MinimumQuality;
  this->CurvedQualityTarget = o.CurvedQualityTarget;
  this->EnvelopeTolerance = o.EnvelopeTolerance;
  this->MergeTolerance = hoembed::MesherServiceSettings::MergeTolerance;
  this->MaximumNumberOfElements = hoembed::MesherServiceSettings::MaximumNumberOfElements;
}

vtkTet10Mesher::~vtkTet10Mesher() = default;

int vtkTet10Mesher::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  return 1;
}

namespace
{
// The input surface as the read step's plain arrays (points as doubles, cells as 64-bit
// ids: copies where VTK stores something else). Holds the copies.
struct InputArrays
{
  std::vector<double> Points;
  std::vector<Id> Copies[8];
  hoembed::SurfaceInput View;

  explicit InputArrays(vtkPolyData* input)
  {
    const vtkIdType np = input->GetNumberOfPoints();
    this->Points.resize(3 * static_cast<size_t>(np));
    for (vtkIdType i = 0; i < np; ++i)
      input->GetPoint(i, &this->Points[3 * i]);
    this->View.NumberOfPoints = np;
    this->View.Points = this->Points.data();
    this->View.Verts = this->Cells(input->GetVerts(), 0);
    this->View.Lines = this->Cells(input->GetLines(), 2);
    this->View.Polys = this->Cells(input->GetPolys(), 4);
    this->View.Strips = this->Cells(input->GetStrips(), 6);
  }

private:
  hoembed::SurfaceCells Cells(vtkCellArray* ca, int slot)
  {
    hoembed::SurfaceCells c;
    if (!ca || ca->GetNumberOfCells() == 0)
      return c;
    c.NumberOfCells = ca->GetNumberOfCells();
    if (ca->IsStorage64Bit())
    {
      c.Offsets = reinterpret_cast<const Id*>(ca->GetOffsetsArray64()->GetPointer(0));
      c.Connectivity = reinterpret_cast<const Id*>(ca->GetConnectivityArray64()->GetPointer(0));
      return c;
    }
    auto copy = [](vtkDataArray* a, std::vector<Id>& out) {
      out.resize(static_cast<size_t>(a->GetNumberOfValues()));
      for (vtkIdType i = 0; i < a->GetNumberOfValues(); ++i)
        out[i] = static_cast<Id>(a->GetComponent(i, 0));
    };
    copy(ca->GetOffsetsArray(), this->Copies[slot]);
    copy(ca->GetConnectivityArray(), this->Copies[slot + 1]);
    c.Offsets = this->Copies[slot].data();
    c.Connectivity = this->Copies[slot + 1].data();
    return c;
  }
};
static_assert(sizeof(vtkIdType) == sizeof(Id), "64-bit vtkIdType expected");
// the refused verdicts are spelled as bits in the driver's settings (the package reads
// them there): they must be this VTK's
static_assert(hoembed::MesherServiceSettings::RefusedCellStates ==
    (static_cast<short>(vtkCellValidator::State::IntersectingEdges) |
      static_cast<short>(vtkCellValidator::State::IntersectingFaces) |
      static_cast<short>(vtkCellValidator::State::FacesAreOrientedIncorrectly) |
      static_cast<short>(vtkCellValidator::State::WrongNumberOfPoints)),
  "the cell validator's State bits");

// Distributed pipelines: every process's piece of the surface, gathered in rank order (so
// every process appends the same surface) before any check, so that all processes take
// part in the collective call and then mesh the same surface. The pieces' seams are
// merged by the read step with every other coincident point. Ghost cells (a distributing
// filter such as D3 adds a layer of the neighbours' cells, marked in vtkGhostType) are
// left out: each is some other process's own cell, and gathered twice it would make the
// surface non-manifold. Returns an error message.
std::string GatherPieces(vtkPolyData*& input, vtkAppendPolyData* gathered)
{
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  if (!controller || controller->GetNumberOfProcesses() <= 1)
    return std::string();
  vtkNew<vtkPolyData> mine;
  if (input->GetCellGhostArray())
  {
    mine->DeepCopy(input);
    mine->RemoveGhostCells();
  }
  else
  {
    mine->ShallowCopy(input);
  }
  std::vector<vtkSmartPointer<vtkDataObject>> pieces;
  if (!controller->AllGather(mine, pieces) ||
    static_cast<int>(pieces.size()) != controller->GetNumberOfProcesses())
  {
    std::ostringstream msg;
    msg << "could not gather the surface's pieces from the " << controller->GetNumberOfProcesses()
        << " processes";
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

// Read step (hoembed::ReadSurface) with its VTK services: vtkPolygon's ear cut, and
// vtkCleanPolyData to merge coincident points (on the input's own vtkPoints). `fine`
// receives the merged surface, which the mesher's services query. Returns an error
// message, empty on success.
std::string ReadInput(vtkPolyData* input, const InputArrays& arrays, double mergeTolerance,
  vtkSmartPointer<vtkPolyData>& fine, TriSurface& merged)
{
  hoembed::SurfaceReadServices services;
  vtkNew<vtkPolygon> polygon;
  vtkNew<vtkIdList> local;
  services.EarCut = [&](const Id* ids, Id n, const double* xyz, std::vector<Id>& out) {
    polygon->GetPointIds()->SetNumberOfIds(n);
    polygon->GetPoints()->SetNumberOfPoints(n);
    for (vtkIdType k = 0; k < n; ++k)
    {
      polygon->GetPointIds()->SetId(k, ids[k]);
      polygon->GetPoints()->SetPoint(k, xyz + 3 * k);
    }
    if (!polygon->Triangulate(local))
      return false;
    out.resize(static_cast<size_t>(local->GetNumberOfIds()));
    for (vtkIdType k = 0; k < local->GetNumberOfIds(); ++k)
      out[k] = local->GetId(k);
    return true;
  };
  services.Merge = [&](const std::vector<Id>& tris, std::vector<double>& points,
                     std::vector<Id>& mergedTris) {
    vtkNew<vtkCellArray> cells;
    cells->AllocateExact(
      static_cast<vtkIdType>(tris.size() / 3), static_cast<vtkIdType>(tris.size()));
    for (size_t t = 0; t < tris.size() / 3; ++t)
    {
      const vtkIdType ids[3] = { tris[3 * t], tris[3 * t + 1], tris[3 * t + 2] };
      cells->InsertNextCell(3, ids);
    }
    vtkNew<vtkPolyData> triangles;
    triangles->SetPoints(input->GetPoints());
    triangles->SetPolys(cells);
    vtkNew<vtkCleanPolyData> clean;
    clean->SetInputData(triangles);
    clean->PointMergingOn();
    // Shared vertices stored with rounding (STL exports: ~1e-6 apart) must meet: the
    // merge tolerance is relative to the bounding-box diagonal.
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
    TriSurface out;
    if (!ToArrays(fine, out))
      return false;
    points.swap(out.Points);
    mergedTris.swap(out.Tris);
    return true;
  };
  return hoembed::ReadSurface(arrays.View, services, merged.Points, merged.Tris);
}

// The VTK side of the driver's services: decimation and smoothing of the fine surface,
// queries on it, distances to a triangle set, VTK's cell validator. Holds what the
// closures use, so it must outlive the driver call.
class VTKServices
{
public:
  explicit VTKServices(vtkPolyData* fine) : Fine(fine), Diagonal(fine->GetLength())
  {
    // The queries run on the surface scaled by a power of two to a unit diagonal (see
    // Unit()): the locators' bins and tolerances then do not depend on the surface's size,
    // so a closest point on an edge shared by two triangles is computed from the same
    // triangle at every scale (at 2^10 a corner came out one ulp apart).
    this->Projector.reset(new SurfaceProjector(this->Unit()));
    this->VertexLocator->SetDataSet(this->Unit());
    BuildLocatorDeterministically(this->VertexLocator);
    this->CheckCell->GetPoints()->SetNumberOfPoints(10);
    for (vtkIdType i = 0; i < 10; ++i)
      this->CheckCell->GetPointIds()->SetId(i, i);
  }

  hoembed::MesherServices Make()
  {
    hoembed::MesherServices s;
    s.Decimate = [this](double reduction, bool smoothed, std::vector<double>& points,
                   std::vector<hoembed::SurfaceCheck::Id>& tris) {
      vtkNew<vtkQuadricDecimation> decimate;
      decimate->SetInputData(smoothed ? this->Smoothed() : this->Unit());
      decimate->SetTargetReduction(reduction);
      decimate->VolumePreservationOff();
      decimate->AttributeErrorMetricOff();
      decimate->Update();
      TriSurface coarse;
      if (!ToArrays(decimate->GetOutput(), coarse))
        return false;
      for (double& x : coarse.Points)
        x = std::ldexp(x, this->Exponent);
      points.swap(coarse.Points);
      tris.swap(coarse.Tris);
      return true;
    };
    s.Fine.Closest = [this](const double x[3], double cp[3]) {
      double u[3];
      this->ToUnit(x, u);
      this->Projector->Project(u, cp);
      this->FromUnit(cp);
    };
    s.Fine.VerticesWithin = [this](const double x[3], double r, std::vector<double>& out) {
      double u[3];
      this->ToUnit(x, u);
      this->VertexLocator->FindPointsWithinRadius(std::ldexp(r, -this->Exponent), u, this->NearIds);
      out.resize(3 * this->NearIds->GetNumberOfIds());
      for (vtkIdType k = 0; k < this->NearIds->GetNumberOfIds(); ++k)
        this->Fine->GetPoint(this->NearIds->GetId(k), &out[3 * k]);
    };
    s.NormalAt = [this](const double x[3], double n[3]) {
      double u[3];
      this->ToUnit(x, u);
      this->Projector->Normal(u, n);
    };
    s.Fine.Ray = [this](const double a[3], const double b[3], double hit[3]) {
      double ua[3], ub[3];
      this->ToUnit(a, ua);
      this->ToUnit(b, ub);
      const bool found = this->Projector->Ray(ua, ub, hit);
      this->FromUnit(hit);
      return found;
    };
    s.MaxDistanceToTriangles =
      [](const std::vector<double>& points, const std::vector<hoembed::SurfaceCheck::Id>& tris,
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
      using Settings = hoembed::MesherServiceSettings;
      const auto state =
        static_cast<short>(vtkCellValidator::Check(this->CheckCell, Settings::CellCheckTolerance));
      return (state & Settings::RefusedCellStates) == 0;
    };
    return s;
  }

private:
  void ToUnit(const double x[3], double u[3]) const
  {
    for (int d = 0; d < 3; ++d)
      u[d] = std::ldexp(x[d], -this->Exponent);
  }
  void FromUnit(double x[3]) const
  {
    for (int d = 0; d < 3; ++d)
      x[d] = std::ldexp(x[d], this->Exponent);
  }

  // The fine surface scaled by a power of two to a diagonal in [0.5, 1), made once:
  // vtkQuadricDecimation has absolute thresholds (the same bunny decimated differently at
  // 2^-10 of its size), and a power of two scales exactly, so a surface scaled by 2^k
  // is decimated into the same coarse surface, scaled.
  vtkPolyData* Unit()
  {
    if (!this->UnitSurface)
    {
      std::frexp(this->Diagonal, &this->Exponent);
      this->UnitSurface = vtkSmartPointer<vtkPolyData>::New();
      this->UnitSurface->ShallowCopy(this->Fine);
      vtkNew<vtkPoints> scaled;
      scaled->SetDataTypeToDouble();
      const vtkIdType n = this->Fine->GetNumberOfPoints();
      scaled->SetNumberOfPoints(n);
      for (vtkIdType i = 0; i < n; ++i)
      {
        double x[3];
        this->Fine->GetPoint(i, x);
        for (double& c : x)
          c = std::ldexp(c, -this->Exponent);
        scaled->SetPoint(i, x);
      }
      this->UnitSurface->SetPoints(scaled);
    }
    return this->UnitSurface;
  }

  // The low-pass filtered fine surface (windowed sinc keeps the volume), made once, at
  // the scale of Unit().
  vtkPolyData* Smoothed()
  {
    if (!this->SmoothedSurface)
    {
      vtkNew<vtkWindowedSincPolyDataFilter> smooth;
      smooth->SetInputData(this->Unit());
      smooth->SetNumberOfIterations(hoembed::MesherServiceSettings::SmoothingIterations);
      smooth->SetPassBand(hoembed::MesherServiceSettings::SmoothingPassBand);
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
  vtkSmartPointer<vtkPolyData> UnitSurface;
  int Exponent = 0; ///< Unit() = Fine x 2^-Exponent
  vtkSmartPointer<vtkPolyData> SmoothedSurface;
  std::unique_ptr<SurfaceProjector> Projector;
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
  quality->SetName(hoembed::ArrayNames::MinScaledJacobian);
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
  bnd->SetName(hoembed::ArrayNames::BoundaryNode);
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
  namespace N = hoembed::ArrayNames;
  addId(N::RelaxedNodeCount, r.RelaxedNodeCount);
  addId(N::CurvedNodeCount, r.CurvedNodeCount);
  addId(N::EnvelopeNodeCount, r.EnvelopeNodeCount);
  addId(N::BoundaryCrossingsFound, r.BoundaryCrossingsFound);
  addId(N::BoundaryCrossingsLeft, r.BoundaryCrossingsLeft);
  addId(N::PoorElementCount, r.PoorElementCount);
  vtkNew<vtkDoubleArray> quantiles;
  quantiles->SetName(hoembed::ArrayNames::MinScaledJacobianQuantiles);
  quantiles->SetNumberOfComponents(3);
  quantiles->InsertNextTuple(r.QualityQuantiles);
  output->GetFieldData()->AddArray(quantiles);
  vtkNew<vtkDoubleArray> dev;
  dev->SetName(hoembed::ArrayNames::MaxSurfaceDeviation);
  dev->InsertNextValue(r.MaxSurfaceDeviation);
  output->GetFieldData()->AddArray(dev);
  vtkNew<vtkDoubleArray> offset;
  offset->SetName(hoembed::ArrayNames::EnvelopeOffset);
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
    inInfo->Set(
      SDDP::UPDATE_NUMBER_OF_PIECES(), distributed ? controller->GetNumberOfProcesses() : 1);
    inInfo->Set(SDDP::UPDATE_NUMBER_OF_GHOST_LEVELS(), 0);
  }
  return 1;
}

// Before any work: every property in the driver's range (hoembed::MesherRanges; the set
// macros do not clamp, so that a bad value is refused with its sentence, not changed).
bool vtkTet10Mesher::CheckRequest(vtkPolyData*)
{
  const std::pair<const char*, double> props[] = { { "TargetEdgeLength", this->TargetEdgeLength },
    { "RadiusEdgeRatio", this->RadiusEdgeRatio }, { "MinDihedralAngle", this->MinDihedralAngle },
    { "CurvedQualityRatio", this->CurvedQualityRatio }, { "MinimumQuality", this->MinimumQuality },
    { "CurvedQualityTarget", this->CurvedQualityTarget },
    { "SurfaceDeviationWarning", this->SurfaceDeviationWarning },
    { "EnvelopeTolerance", this->EnvelopeTolerance }, { "MergeTolerance", this->MergeTolerance },
    { "TargetNumberOfElements", this->TargetNumberOfElements },
    { "MaximumNumberOfElements", static_cast<double>(this->MaximumNumberOfElements) },
    { "ElementOrder", this->ElementOrder } };
  for (const auto& p : props)
  {
    const std::string error = hoembed::CheckMesherProperty(p.first, p.second);
    if (!error.empty())
    {
      vtkErrorMacro(<< error);
      return false;
    }
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
  // point ids in range (the read step's VTK services read them unchecked: an id out of
  // range crashes them) and a size TetGen can mesh in reasonable time and memory
  const InputArrays arrays(input);
  const std::string idError = hoembed::CheckSurfacePointIds(arrays.View);
  if (!idError.empty())
  {
    vtkErrorMacro(<< idError);
    return 0;
  }
  const std::string sizeError = hoembed::CheckEstimatedSize(arrays.View, this->TargetEdgeLength,
    this->TargetNumberOfElements, this->MaximumNumberOfElements, "MaximumNumberOfElements");
  if (!sizeError.empty())
  {
    vtkErrorMacro(<< sizeError);
    return 0;
  }

  // AbortExecute stops TetGen too (polled through progress events while it meshes).
  hoembed::ScopedTetGenAbort tetgenAbort([this]() {
    this->UpdateProgress(std::min(1.0, this->GetProgress() + 1e-6));
    return this->AbortExecute != 0;
  });

  vtkSmartPointer<vtkPolyData> fine;
  TriSurface fineArrays;
  const std::string readError = ReadInput(input, arrays, this->MergeTolerance, fine, fineArrays);
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
  options.CurvedQualityTarget = this->CurvedQualityTarget;
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
  os << indent << "CurvedQualityTarget: " << this->CurvedQualityTarget << "\n";
  os << indent << "MinimumQuality: " << this->MinimumQuality << "\n";
  os << indent << "EnvelopeTolerance: " << this->EnvelopeTolerance << "\n";
  os << indent << "MergeTolerance: " << this->MergeTolerance << "\n";
  os << indent << "SurfaceDeviationWarning: " << this->SurfaceDeviationWarning << "\n";
  os << indent << "RelaxedNodeCount: " << this->RelaxedNodeCount << "\n";
  os << indent << "CurvedNodeCount: " << this->CurvedNodeCount << "\n";
  os << indent << "MaxSurfaceDeviation: " << this->MaxSurfaceDeviation << "\n";
  os << indent << "EnvelopeNodeCount: " << this->EnvelopeNodeCount << "\n";
}
