#include "vtkTet10Mesher.h"

#include "hoembedCurvedMeshBuilder.h"
#include "hoembedElementGeometry.h"
#include "hoembedSpatialOrder.h"
#include "hoembedSurfaceCheck.h"
#include "hoembedTetGenBridge.h"

#include "vtkAppendPolyData.h"
#include "vtkCellArray.h"
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
#include "vtkTriangleFilter.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"
#include "vtkWindowedSincPolyDataFilter.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
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

//------------------------------------------------------------------------------
int vtkTet10Mesher::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0]);
  vtkUnstructuredGrid* output = vtkUnstructuredGrid::GetData(outputVector);
  this->RelaxedNodeCount = 0;
  this->CurvedNodeCount = 0;
  this->MaxSurfaceDeviation = 0.0;
  if (!input || !output)
  {
    vtkErrorMacro("missing input surface or output grid");
    return 0;
  }
  output->Initialize();

  // Distributed pipelines: gather every process's piece (in rank order, so every process
  // appends the same surface) before any check, so that all processes take part in the
  // collective call and then mesh the same surface. TetGen and the curving are
  // deterministic: every process produces the same mesh. The coincident points of the
  // pieces' seams are merged below with every other coincident point.
  vtkNew<vtkAppendPolyData> gathered;
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  if (controller && controller->GetNumberOfProcesses() > 1)
  {
    vtkNew<vtkPolyData> mine;
    mine->ShallowCopy(input);
    std::vector<vtkSmartPointer<vtkDataObject>> pieces;
    if (!controller->AllGather(mine, pieces) ||
      static_cast<int>(pieces.size()) != controller->GetNumberOfProcesses())
    {
      vtkErrorMacro("could not gather the surface's pieces from the "
        << controller->GetNumberOfProcesses() << " processes");
      return 0;
    }
    for (const auto& piece : pieces)
    {
      auto* poly = vtkPolyData::SafeDownCast(piece);
      if (poly && poly->GetNumberOfPoints() > 0)
      {
        gathered->AddInputData(poly);
      }
    }
    if (gathered->GetNumberOfInputConnections(0) > 0)
    {
      gathered->Update();
      input = gathered->GetOutput();
    }
  }

  // ---- 1. checks ----------------------------------------------------------------------
  if (input->GetNumberOfPoints() == 0 || input->GetNumberOfCells() == 0)
  {
    vtkErrorMacro("the input surface is empty (" << input->GetNumberOfPoints() << " points, "
                                                 << input->GetNumberOfCells() << " cells)");
    return 0;
  }
  for (vtkIdType i = 0; i < input->GetNumberOfPoints(); ++i)
  {
    double x[3];
    input->GetPoint(i, x);
    if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2]))
    {
      vtkErrorMacro("the input surface has a non-finite coordinate (NaN or Inf) at point " << i);
      return 0;
    }
  }
  if (input->GetNumberOfPolys() + input->GetNumberOfStrips() == 0)
  {
    vtkErrorMacro("the input has no polygons: a closed triangle surface is needed");
    return 0;
  }
  // Triangulate polygons and strips, drop vertices and lines, merge coincident points.
  vtkNew<vtkTriangleFilter> triangulate;
  triangulate->SetInputData(input);
  triangulate->PassVertsOff();
  triangulate->PassLinesOff();
  vtkNew<vtkCleanPolyData> clean;
  clean->SetInputConnection(triangulate->GetOutputPort());
  clean->PointMergingOn();
  clean->SetAbsoluteTolerance(0.0);
  clean->ToleranceIsAbsoluteOn();
  clean->ConvertLinesToPointsOff();
  clean->ConvertPolysToLinesOff();
  clean->ConvertStripsToPolysOff();
  clean->Update();
  vtkSmartPointer<vtkPolyData> fine = clean->GetOutput();
  TriSurface fineArrays;
  if (!ToArrays(fine, fineArrays) || fineArrays.Tris.empty())
  {
    vtkErrorMacro("the input has no usable triangles after triangulation");
    return 0;
  }
  hoembed::SurfaceCheck check;
  check.Run(fineArrays.Points.data(), static_cast<Id>(fineArrays.Points.size() / 3),
    fineArrays.Tris.data(), static_cast<Id>(fineArrays.Tris.size() / 3));
  if (check.BoundaryEdges > 0)
  {
    vtkErrorMacro("the input surface is open: " << check.BoundaryEdges
                    << " boundary edges (e.g. between points " << check.ExampleEdge[0] << " and "
                    << check.ExampleEdge[1] << "); close its holes first");
    return 0;
  }
  if (check.NonManifoldEdges > 0)
  {
    vtkErrorMacro("the input surface is not manifold: "
      << check.NonManifoldEdges << " edges are shared by more than two triangles (e.g. "
      << check.ExampleEdge[0] << "-" << check.ExampleEdge[1] << ")");
    return 0;
  }
  if (check.InconsistentEdges > 0)
  {
    vtkErrorMacro("the input surface is not consistently oriented: "
      << check.InconsistentEdges << " edges are used twice in the same direction");
    return 0;
  }
  const double volume = std::fabs(check.SignedVolume);
  double bounds[6];
  fine->GetBounds(bounds);
  const double diag = std::sqrt((bounds[1] - bounds[0]) * (bounds[1] - bounds[0]) +
    (bounds[3] - bounds[2]) * (bounds[3] - bounds[2]) +
    (bounds[5] - bounds[4]) * (bounds[5] - bounds[4]));
  if (!(volume > 1e-12 * diag * diag * diag))
  {
    vtkErrorMacro("the input surface encloses no volume");
    return 0;
  }
  this->UpdateProgress(0.1);

  // ---- 2. coarsening --------------------------------------------------------------------
  // A regular tet of edge h has volume h^3 / (6 sqrt 2); quality meshes average about
  // that, so N elements of a volume V have h = (6 sqrt(2) V / N)^(1/3).
  double h = this->TargetEdgeLength > 0.0
    ? this->TargetEdgeLength
    : std::cbrt(6.0 * std::sqrt(2.0) * volume / this->TargetNumberOfElements);
  const double nFine = static_cast<double>(fineArrays.Tris.size() / 3);

  // Decimate to the boundary of edge length h, mesh with TetGen; when a target number of
  // elements is asked for, correct h from the count obtained and keep the closest result.
  // A decimation that folds (not a closed manifold, or self-intersecting: TetGen can crash
  // on such input) or a TetGen failure is retried with a slightly different target.
  hoembed::TetGenResult tg;
  hoembed::TetGenParameters params;
  params.RadiusEdgeRatio = this->RadiusEdgeRatio;
  params.MinDihedralAngle = this->MinDihedralAngle;
  double bestMismatch = VTK_DOUBLE_MAX;
  std::string lastError;
  double triFactor = 1.0;
  // Fine detail (thorns, noise) can make the decimated surface fold onto itself; after a
  // failed attempt the surface is low-pass filtered (windowed sinc, which keeps the
  // volume) before decimation. Only the coarse boundary comes from the filtered surface:
  // curved nodes still go onto the original one.
  vtkSmartPointer<vtkPolyData> toDecimate = fine;
  for (int attempt = 0; attempt < 10; ++attempt)
  {
    if (attempt == 2)
    {
      vtkNew<vtkWindowedSincPolyDataFilter> smooth;
      smooth->SetInputData(fine);
      smooth->SetNumberOfIterations(30);
      smooth->SetPassBand(0.01);
      smooth->NormalizeCoordinatesOn();
      smooth->BoundarySmoothingOff();
      smooth->FeatureEdgeSmoothingOff();
      smooth->NonManifoldSmoothingOff();
      smooth->Update();
      toDecimate = smooth->GetOutput();
      triFactor = 1.0;
    }
    this->UpdateProgress(0.1 + 0.05 * attempt);
    // Boundary triangles of edge h: equilateral area sqrt(3)/4 h^2.
    const double nTri = std::max(8.0, triFactor * check.Area / (std::sqrt(3.0) / 4.0 * h * h));
    TriSurface coarse;
    if (nTri < 0.9 * nFine)
    {
      vtkNew<vtkQuadricDecimation> decimate;
      decimate->SetInputData(toDecimate);
      decimate->SetTargetReduction(1.0 - nTri / nFine);
      decimate->VolumePreservationOff();
      decimate->AttributeErrorMetricOff();
      decimate->Update();
      if (!ToArrays(decimate->GetOutput(), coarse))
      {
        vtkErrorMacro("decimation produced non-triangle cells");
        return 0;
      }
    }
    else
    {
      coarse = fineArrays;
    }
    hoembed::SurfaceCheck coarseCheck;
    coarseCheck.Run(coarse.Points.data(), static_cast<Id>(coarse.Points.size() / 3),
      coarse.Tris.data(), static_cast<Id>(coarse.Tris.size() / 3));
    if (!coarseCheck.IsClosedManifold() || coarseCheck.DegenerateTriangles > 0 ||
      hoembed::SurfaceCheck::CountSelfIntersections(coarse.Points.data(),
        static_cast<Id>(coarse.Points.size() / 3), coarse.Tris.data(),
        static_cast<Id>(coarse.Tris.size() / 3), 1e-9, 1) > 0)
    {
      lastError = "the coarsened surface is not a closed manifold free of self-intersections";
      triFactor *= 1.15;
      continue;
    }
    params.MaxVolume = h * h * h / (6.0 * std::sqrt(2.0));
    params.PreserveBoundary = this->PreserveBoundary;
    hoembed::TetGenResult run = hoembed::RunTetGen(coarse.Points, coarse.Tris, params);
    if (!run.Error.empty() && params.PreserveBoundary)
    {
      params.PreserveBoundary = false; // TetGen may need boundary points to succeed
      run = hoembed::RunTetGen(coarse.Points, coarse.Tris, params);
    }
    if (!run.Error.empty())
    {
      lastError = run.Error;
      triFactor *= 1.15;
      continue;
    }
    const double ratio = static_cast<double>(run.Tets.size() / 4) / this->TargetNumberOfElements;
    const double mismatch = std::fabs(std::log(ratio));
    if (mismatch < bestMismatch)
    {
      bestMismatch = mismatch;
      tg = std::move(run);
    }
    if (this->TargetEdgeLength > 0.0 || (ratio > 0.8 && ratio < 1.25))
    {
      break;
    }
    h *= std::cbrt(ratio);
  }
  if (tg.Tets.empty())
  {
    tg.Error = lastError;
  }
  if (!tg.Error.empty())
  {
    vtkErrorMacro("TetGen could not mesh the surface: " << tg.Error
                    << (check.DegenerateTriangles ? " (the input has degenerate triangles)" : "")
                    << ". Check the input for self-intersections, or ask for more elements.");
    return 0;
  }
  this->UpdateProgress(0.5);

  // ---- 3. curved mesh on the fine surface ----------------------------------------------
  SurfaceProjector projector(fine);
  hoembed::SurfaceQueries queries;
  queries.Closest = [&](const double x[3], double cp[3]) { projector.Project(x, cp); };
  vtkNew<vtkStaticPointLocator> vertexLocator;
  vertexLocator->SetDataSet(fine);
  vertexLocator->BuildLocator();
  vtkNew<vtkIdList> nearIds;
  queries.VerticesWithin = [&](const double x[3], double r, std::vector<double>& out) {
    vertexLocator->FindPointsWithinRadius(r, x, nearIds);
    out.resize(3 * nearIds->GetNumberOfIds());
    for (vtkIdType k = 0; k < nearIds->GetNumberOfIds(); ++k)
      fine->GetPoint(nearIds->GetId(k), &out[3 * k]);
  };
  queries.Ray = [&](const double a[3], const double b[3], double hit[3]) {
    return projector.Ray(a, b, hit);
  };
  hoembed::CurvedMeshOptions options;
  options.Order = this->ElementOrder;
  options.CurveBoundary = this->CurveBoundary;
  options.ProjectCorners = this->ProjectCorners;
  options.QualityRatio = this->CurvedQualityRatio;
  // Beyond det J > 0, curved elements must pass VTK's own cell validator (its linearised
  // faces must not intersect or flip), so that VTK tools accept every element.
  vtkNew<vtkQuadraticTetra> checkCell;
  checkCell->GetPoints()->SetNumberOfPoints(10);
  for (vtkIdType i = 0; i < 10; ++i)
    checkCell->GetPointIds()->SetId(i, i);
  options.ExtraCheck = [&checkCell](const double* x) {
    double longest = 0.0;
    for (vtkIdType i = 0; i < 10; ++i)
    {
      checkCell->GetPoints()->SetPoint(i, x + 3 * i);
      longest = std::max(longest, vtkMath::Distance2BetweenPoints(x, x + 3 * i));
    }
    // Curved faces are legitimately not convex: only intersections and flips count.
    const auto state = static_cast<short>(vtkCellValidator::Check(checkCell, 1e-6 * std::sqrt(longest)));
    const short bad = static_cast<short>(vtkCellValidator::State::IntersectingEdges) |
      static_cast<short>(vtkCellValidator::State::IntersectingFaces) |
      static_cast<short>(vtkCellValidator::State::FacesAreOrientedIncorrectly) |
      static_cast<short>(vtkCellValidator::State::WrongNumberOfPoints);
    return (state & bad) == 0;
  };
  hoembed::CurvedMesh mesh = hoembed::BuildCurvedMesh(tg.Points, tg.Tets, queries, options,
    [this](double f) { this->UpdateProgress(0.5 + 0.4 * f); });
  if (!mesh.Error.empty())
  {
    vtkErrorMacro("could not build the curved mesh: " << mesh.Error);
    return 0;
  }
  this->CurvedNodeCount = mesh.CurvedNodes;
  this->RelaxedNodeCount = mesh.RelaxedNodes;

  // Thin parts: how far is the fine surface from the coarse straight boundary?
  {
    TriSurface boundary;
    boundary.Points = mesh.LinearPoints;
    boundary.Tris = mesh.LinearBoundary;
    vtkSmartPointer<vtkPolyData> bpd = FromArrays(boundary);
    SurfaceProjector toCoarse(bpd);
    const Id nFinePts = static_cast<Id>(fineArrays.Points.size() / 3);
    const Id stride = std::max<Id>(1, nFinePts / 20000);
    double worst = 0.0;
    for (Id i = 0; i < nFinePts; i += stride)
    {
      double cp[3];
      worst = std::max(worst, toCoarse.Project(&fineArrays.Points[3 * i], cp));
    }
    this->MaxSurfaceDeviation = diag > 0.0 ? worst / diag : 0.0;
    if (this->MaxSurfaceDeviation > this->SurfaceDeviationWarning)
    {
      vtkWarningMacro("the coarse mesh does not resolve parts of the surface: a surface point is "
        << this->MaxSurfaceDeviation * 100.0
        << "% of the bounding-box diagonal away from it (thin parts are smaller than the element "
           "size; ask for more elements or a smaller TargetEdgeLength)");
    }
  }
  this->UpdateProgress(0.95);
  const int npc = this->ElementOrder == 2 ? 10 : 4;
  // memory order: cells along a Morton curve, nodes by first use (neighbouring elements
  // are neighbours in the arrays; the embedding's searches read less scattered memory)
  std::vector<Id> cellOrder, pointOrder;
  hoembed::SpatialOrder(mesh.Points, mesh.Conn, npc, cellOrder, pointOrder);
  const Id nTets = static_cast<Id>(cellOrder.size());
  const Id nPts = static_cast<Id>(pointOrder.size());
  std::vector<double> pts(3 * nPts);
  std::vector<unsigned char> boundaryNode(nPts);
  std::vector<Id> newId(nPts);
  for (Id k = 0; k < nPts; ++k)
  {
    const Id i = pointOrder[k];
    newId[i] = k;
    boundaryNode[k] = mesh.BoundaryNode[i];
    for (int d = 0; d < 3; ++d)
      pts[3 * k + d] = mesh.Points[3 * i + d];
  }
  std::vector<Id> conn(npc * nTets);
  for (Id t = 0; t < nTets; ++t)
    for (int a = 0; a < npc; ++a)
      conn[npc * t + a] = newId[mesh.Conn[npc * cellOrder[t] + a]];

  // ---- 5. output ----------------------------------------------------------------------
  vtkNew<vtkPoints> outPts;
  outPts->SetDataTypeToDouble();
  outPts->SetNumberOfPoints(nPts);
  for (Id i = 0; i < nPts; ++i)
    outPts->SetPoint(i, &pts[3 * i]);
  vtkNew<vtkCellArray> cells;
  cells->AllocateExact(nTets, npc * nTets);
  vtkNew<vtkDoubleArray> quality;
  quality->SetName("MinScaledJacobian");
  quality->SetNumberOfTuples(nTets);
  Id invalid = 0;
  for (Id t = 0; t < nTets; ++t)
  {
    vtkIdType ids[10];
    double x[30];
    for (int a = 0; a < npc; ++a)
    {
      ids[a] = conn[npc * t + a];
      for (int d = 0; d < 3; ++d)
        x[3 * a + d] = pts[3 * ids[a] + d];
    }
    cells->InsertNextCell(npc, ids);
    const double q = npc == 10 ? hoembed::Tet10MinScaledJacobian(x) : hoembed::Tet4ScaledJacobian(x);
    quality->SetValue(t, q);
    invalid += q > 0.0 ? 0 : 1;
  }
  if (invalid > 0)
  {
    vtkErrorMacro(<< invalid << " elements are not valid after meshing (internal error)");
    return 0;
  }
  vtkNew<vtkUnsignedCharArray> bnd;
  bnd->SetName("BoundaryNode");
  bnd->SetNumberOfTuples(nPts);
  for (Id i = 0; i < nPts; ++i)
    bnd->SetValue(i, boundaryNode[i]);

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
  addId("RelaxedNodeCount", this->RelaxedNodeCount);
  addId("CurvedNodeCount", this->CurvedNodeCount);
  vtkNew<vtkDoubleArray> dev;
  dev->SetName("MaxSurfaceDeviation");
  dev->InsertNextValue(this->MaxSurfaceDeviation);
  output->GetFieldData()->AddArray(dev);
  this->UpdateProgress(1.0);
  return 1;
}

void vtkTet10Mesher::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "TargetNumberOfElements: " << this->TargetNumberOfElements << "\n";
  os << indent << "TargetEdgeLength: " << this->TargetEdgeLength << "\n";
  os << indent << "ElementOrder: " << this->ElementOrder << "\n";
  os << indent << "CurveBoundary: " << (this->CurveBoundary ? "On" : "Off") << "\n";
  os << indent << "ProjectCorners: " << (this->ProjectCorners ? "On" : "Off") << "\n";
  os << indent << "PreserveBoundary: " << (this->PreserveBoundary ? "On" : "Off") << "\n";
  os << indent << "RadiusEdgeRatio: " << this->RadiusEdgeRatio << "\n";
  os << indent << "MinDihedralAngle: " << this->MinDihedralAngle << "\n";
  os << indent << "CurvedQualityRatio: " << this->CurvedQualityRatio << "\n";
  os << indent << "SurfaceDeviationWarning: " << this->SurfaceDeviationWarning << "\n";
  os << indent << "RelaxedNodeCount: " << this->RelaxedNodeCount << "\n";
  os << indent << "CurvedNodeCount: " << this->CurvedNodeCount << "\n";
  os << indent << "MaxSurfaceDeviation: " << this->MaxSurfaceDeviation << "\n";
}
