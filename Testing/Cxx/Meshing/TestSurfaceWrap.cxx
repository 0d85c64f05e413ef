// The envelope path of the mesher: hoembed::WrapSurface on triangle soups (checked by
// hoembed::SurfaceCheck and, independently, by VTK's vtkSelectEnclosedPoints), and
// vtkTet10Mesher on each input class
// (open, sheet, several parts, non-manifold, duplicated, flipped), checked with VTK's
// own vtkCellValidator and vtkQuadraticTetra (a point search in the curved cells).
#include "hoembedSurfaceCheck.h"
#include "hoembedSurfaceWrap.h"
#include "hoembedTestUtilities.h"

#include "vtkTet10Mesher.h"

#include "vtkAppendPolyData.h"
#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCellValidator.h"
#include "vtkCleanPolyData.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkDataSetSurfaceFilter.h"
#include "vtkExecutive.h"
#include "vtkFieldData.h"
#include "vtkGenericCell.h"
#include "vtkNew.h"
#include "vtkPlaneSource.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSelectEnclosedPoints.h"
#include "vtkSphereSource.h"
#include "vtkStaticCellLocator.h"
#include "vtkTriangleFilter.h"
#include "vtkUnstructuredGrid.h"

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace
{
using Id = std::int64_t;

struct ErrorCatcher : public vtkCommand
{
  static ErrorCatcher* New()
  {
    return new ErrorCatcher;
  }
  void Execute(vtkObject*, unsigned long, void* data) override
  {
    this->Text += static_cast<const char*>(data);
  }
  std::string Text;
};

vtkSmartPointer<vtkPolyData> Triangulated(vtkAlgorithm* source)
{
  vtkNew<vtkTriangleFilter> tri;
  tri->SetInputConnection(source->GetOutputPort());
  tri->Update();
  return tri->GetOutput();
}

vtkSmartPointer<vtkPolyData> Sphere(double r, double cx, int res = 24)
{
  vtkNew<vtkSphereSource> s;
  s->SetRadius(r);
  s->SetCenter(cx, 0, 0);
  s->SetThetaResolution(res);
  s->SetPhiResolution(res);
  return Triangulated(s);
}

vtkSmartPointer<vtkPolyData> Append(vtkPolyData* a, vtkPolyData* b)
{
  vtkNew<vtkAppendPolyData> app;
  app->AddInputData(a);
  app->AddInputData(b);
  app->Update();
  return app->GetOutput();
}

// Drop every triangle whose centroid has z above `zcut`.
vtkSmartPointer<vtkPolyData> Cut(vtkPolyData* in, double zcut)
{
  vtkNew<vtkCellArray> polys;
  for (vtkIdType c = 0; c < in->GetNumberOfCells(); ++c)
  {
    double z = 0.0, x[3];
    vtkIdList* ids = in->GetCell(c)->GetPointIds();
    for (vtkIdType k = 0; k < 3; ++k)
    {
      in->GetPoint(ids->GetId(k), x);
      z += x[2] / 3.0;
    }
    if (z <= zcut)
      polys->InsertNextCell(ids);
  }
  vtkNew<vtkPolyData> cut;
  cut->SetPoints(in->GetPoints());
  cut->SetPolys(polys);
  vtkNew<vtkCleanPolyData> clean; // drop the points of the removed triangles
  clean->SetInputData(cut);
  clean->Update();
  return clean->GetOutput();
}

void ToArrays(vtkPolyData* pd, std::vector<double>& pts, std::vector<Id>& tris)
{
  pts.resize(3 * pd->GetNumberOfPoints());
  for (vtkIdType i = 0; i < pd->GetNumberOfPoints(); ++i)
    pd->GetPoint(i, &pts[3 * i]);
  tris.clear();
  for (vtkIdType c = 0; c < pd->GetNumberOfCells(); ++c)
  {
    vtkIdList* ids = pd->GetCell(c)->GetPointIds();
    for (vtkIdType k = 0; k < 3; ++k)
      tris.push_back(ids->GetId(k));
  }
}

vtkSmartPointer<vtkPolyData> FromArrays(const std::vector<double>& pts, const std::vector<Id>& tris)
{
  vtkNew<vtkPoints> p;
  for (size_t i = 0; i < pts.size() / 3; ++i)
    p->InsertNextPoint(&pts[3 * i]);
  vtkNew<vtkCellArray> c;
  for (size_t t = 0; t < tris.size() / 3; ++t)
  {
    const vtkIdType ids[3] = { tris[3 * t], tris[3 * t + 1], tris[3 * t + 2] };
    c->InsertNextCell(3, ids);
  }
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  pd->SetPoints(p);
  pd->SetPolys(c);
  return pd;
}

// The kernel: a watertight, manifold, intersection-free envelope that holds every input
// vertex (vtkSelectEnclosedPoints, VTK's ray-parity test, is the independent judge).
void CheckWrapKernel(const char* name, vtkPolyData* soup, double alpha, double offset)
{
  std::vector<double> pts;
  std::vector<Id> tris;
  ToArrays(soup, pts, tris);
  hoembed::SurfaceWrapResult w = hoembed::WrapSurface(pts, tris, alpha, offset);
  HOEMBED_CHECK(w.Error.empty(), "%s: wrap failed: %s", name, w.Error.c_str());
  if (!w.Error.empty())
    return;
  hoembed::SurfaceCheck check;
  const Id np = static_cast<Id>(w.Points.size() / 3), nt = static_cast<Id>(w.Tris.size() / 3);
  check.Run(w.Points.data(), np, w.Tris.data(), nt);
  HOEMBED_CHECK(check.IsClosedManifold() && check.DegenerateTriangles == 0,
    "%s: envelope not a closed manifold (%lld boundary, %lld non-manifold, %lld flipped edges)",
    name, (long long)check.BoundaryEdges, (long long)check.NonManifoldEdges,
    (long long)check.InconsistentEdges);
  HOEMBED_CHECK(check.SignedVolume > 0.0, "%s: envelope volume %g", name, check.SignedVolume);
  const Id crossings = hoembed::SurfaceCheck::CountSelfIntersections(
    w.Points.data(), np, w.Tris.data(), nt, 1e-12, 10);
  HOEMBED_CHECK(
    crossings == 0, "%s: envelope self-intersects (%lld pairs)", name, (long long)crossings);
  vtkSmartPointer<vtkPolyData> env = FromArrays(w.Points, w.Tris);
  vtkNew<vtkSelectEnclosedPoints> inside;
  inside->SetInputData(soup);
  inside->SetSurfaceData(env);
  inside->Update();
  Id outside = 0;
  for (vtkIdType i = 0; i < soup->GetNumberOfPoints(); ++i)
    outside += inside->IsInside(i) ? 0 : 1;
  HOEMBED_CHECK(
    outside == 0, "%s: %lld input vertices outside the envelope", name, (long long)outside);
  std::printf(
    "%s: envelope of %lld triangles, volume %.4g\n", name, (long long)nt, check.SignedVolume);
}

// The filter: completes, every element valid by VTK's validator and its own bound, and
// every input vertex inside or next to the curved mesh (VTK's vtkQuadraticTetra point
// search in every cell of a locator's candidates).
void CheckMesher(
  const char* name, vtkPolyData* surface, bool expectEnvelopeNodes = false, bool expectWrap = true)
{
  vtkNew<vtkTet10Mesher> mesher;
  vtkNew<ErrorCatcher> catcher;
  mesher->AddObserver(vtkCommand::ErrorEvent, catcher);
  mesher->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, catcher);
  mesher->SetInputData(surface);
  mesher->SetTargetNumberOfElements(400);
  mesher->Update();
  vtkUnstructuredGrid* mesh = mesher->GetOutput();
  HOEMBED_CHECK(
    catcher->Text.empty() && mesh->GetNumberOfCells() > 0, "%s: %s", name, catcher->Text.c_str());
  if (mesh->GetNumberOfCells() == 0)
    return;
  vtkDataArray* q = mesh->GetCellData()->GetArray("MinScaledJacobian");
  double qmin = q->GetRange()[0];
  HOEMBED_CHECK(qmin > 0.0, "%s: min scaled Jacobian %g", name, qmin);
  vtkNew<vtkCellValidator> validator;
  validator->SetInputData(mesh);
  validator->Update();
  vtkDataArray* states = vtkUnstructuredGrid::SafeDownCast(validator->GetOutput())
                           ->GetCellData()
                           ->GetArray("ValidityState");
  const short bad = static_cast<short>(vtkCellValidator::State::IntersectingEdges) |
    static_cast<short>(vtkCellValidator::State::IntersectingFaces) |
    static_cast<short>(vtkCellValidator::State::FacesAreOrientedIncorrectly);
  Id invalid = 0;
  for (vtkIdType c = 0; c < states->GetNumberOfTuples(); ++c)
    invalid += (static_cast<short>(states->GetTuple1(c)) & bad) ? 1 : 0;
  HOEMBED_CHECK(invalid == 0, "%s: %lld cells fail vtkCellValidator", name, (long long)invalid);
  HOEMBED_CHECK(!expectWrap || mesh->GetFieldData()->GetArray("EnvelopeOffset")->GetTuple1(0) > 0.0,
    "%s: not meshed through the envelope", name);
  const double envNodes = mesh->GetFieldData()->GetArray("EnvelopeNodeCount")->GetTuple1(0);
  if (expectEnvelopeNodes)
    HOEMBED_CHECK(envNodes > 0, "%s: no node left on the envelope over the hole", name);
  // Containment: distance of every input vertex to the curved mesh (0 inside a cell).
  double b[6];
  surface->GetBounds(b);
  const double diag = std::sqrt(
    (b[1] - b[0]) * (b[1] - b[0]) + (b[3] - b[2]) * (b[3] - b[2]) + (b[5] - b[4]) * (b[5] - b[4]));
  // The curved boundary, subdivided (VTK's own tri6 subdivision): inside test by ray
  // parity, and the distance of the vertices outside to it.
  vtkNew<vtkDataSetSurfaceFilter> boundary;
  boundary->SetInputData(mesh);
  boundary->SetNonlinearSubdivisionLevel(3);
  boundary->Update();
  vtkNew<vtkSelectEnclosedPoints> inside;
  inside->SetInputData(surface);
  inside->SetSurfaceData(boundary->GetOutput());
  inside->Update();
  vtkNew<vtkStaticCellLocator> loc;
  loc->SetDataSet(boundary->GetOutput());
  loc->BuildLocator();
  double worst = 0.0;
  for (vtkIdType i = 0; i < surface->GetNumberOfPoints(); ++i)
  {
    if (inside->IsInside(i))
      continue;
    double x[3], cp[3], d2;
    int sub;
    vtkIdType cid;
    surface->GetPoint(i, x);
    loc->FindClosestPoint(x, cp, cid, sub, d2);
    worst = std::max(worst, std::sqrt(d2) / diag);
  }
  // The curved boundary follows the surface between its nodes only to the element size's
  // sagitta (a percent or two of the diagonal here); a part left out would be tens of
  // percent away.
  HOEMBED_CHECK(
    worst < 0.03, "%s: an input vertex is %g of the diagonal outside the mesh", name, worst);
  std::printf("%s: %lld cells, min scaled Jacobian %.3g, %g envelope nodes, worst outside %.2e\n",
    name, (long long)mesh->GetNumberOfCells(), qmin, envNodes, worst);
}
} // namespace

int main(int, char*[])
{
  vtkSmartPointer<vtkPolyData> sphere = Sphere(1.0, 0.0);
  vtkSmartPointer<vtkPolyData> open = Cut(sphere, 0.6);
  vtkNew<vtkPlaneSource> planeSource;
  planeSource->SetResolution(20, 20);
  vtkSmartPointer<vtkPolyData> sheet = Triangulated(planeSource);
  vtkSmartPointer<vtkPolyData> overlapping = Append(sphere, Sphere(1.0, 0.8));
  vtkSmartPointer<vtkPolyData> farApart = Append(sphere, Sphere(0.3, 4.0));
  vtkSmartPointer<vtkPolyData> nested = Append(sphere, Sphere(0.4, 0.0));
  vtkSmartPointer<vtkPolyData> duplicated = Append(sphere, sphere);
  vtkSmartPointer<vtkPolyData> finned =
    Append(sphere, Triangulated(planeSource)); // a sheet through it
  vtkSmartPointer<vtkPolyData> flipped = Sphere(1.0, 0.0);
  for (vtkIdType c = 0; c < flipped->GetNumberOfCells(); c += 3)
    flipped->ReverseCell(c);

  CheckWrapKernel("kernel open sphere", open, 0.2, 0.02);
  CheckWrapKernel("kernel sheet", sheet, 0.1, 0.02);
  CheckWrapKernel("kernel overlapping", overlapping, 0.3, 0.02);
  {
    // Degenerate triangles only: nothing to wrap, a clear error.
    std::vector<double> pts = { 0, 0, 0, 1, 0, 0, 2, 0, 0 };
    std::vector<Id> tris = { 0, 1, 2, 0, 0, 1 };
    hoembed::SurfaceWrapResult w = hoembed::WrapSurface(pts, tris, 0.1, 0.01);
    HOEMBED_CHECK(
      w.Error.find("non-zero area") != std::string::npos, "degenerate: '%s'", w.Error.c_str());
  }

  CheckMesher("open sphere", open, true);
  CheckMesher("sheet", sheet);
  CheckMesher("overlapping spheres", overlapping);
  // Two clean closed parts: today's coarsening path (no envelope needed).
  CheckMesher("far-apart spheres", farApart, false, false);
  CheckMesher("nested spheres", nested);
  CheckMesher("duplicated shell", duplicated);
  CheckMesher("sphere with a fin sheet", finned);
  CheckMesher("flipped triangles", flipped);
  {
    // Two closed tets glued along an edge: closed but not manifold.
    vtkNew<vtkPoints> pts;
    const double P[6][3] = { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 }, { 0, -1, 0 },
      { 0, 0, -1 } };
    for (auto& p : P)
      pts->InsertNextPoint(p);
    vtkNew<vtkCellArray> tris;
    const vtkIdType T[8][3] = { { 0, 2, 1 }, { 0, 1, 3 }, { 1, 2, 3 }, { 0, 3, 2 }, { 0, 1, 4 },
      { 0, 5, 1 }, { 1, 5, 4 }, { 0, 4, 5 } };
    for (auto& t : T)
      tris->InsertNextCell(3, t);
    vtkNew<vtkPolyData> bowtie;
    bowtie->SetPoints(pts);
    bowtie->SetPolys(tris);
    CheckMesher("two tets glued along an edge", bowtie);
  }
  return hoembed_test::Report("TestSurfaceWrap");
}
