// The mesher's bounds (issue 27): the envelope (CGAL's alpha wrap, hoembed::WrapSurface)
// stops at its work bound and on an abort, and vtkTet10Mesher's AbortExecute reaches it.
// Input: a generated thin multi-part shell (3 x 3 thin-walled cups, each a capped
// cylinder and an open tube inside it that pokes through its top: an open,
// self-intersecting soup of 18 parts), where a small ball makes the wrap follow every
// wall on both sides.
#include "hoembedMesherDriver.h"
#include "hoembedSurfaceCheck.h"
#include "hoembedSurfaceWrap.h"
#include "hoembedTestUtilities.h"
#include "hoembedTetGenBridge.h"

#include "vtkTet10Mesher.h"

#include "vtkAppendPolyData.h"
#include "vtkCellData.h"
#include "vtkCellValidator.h"
#include "vtkDataArray.h"
#include "vtkCommand.h"
#include "vtkCellLocator.h"
#include "vtkCylinderSource.h"
#include "vtkQuadricDecimation.h"
#include "vtkSphereSource.h"
#include "vtkExecutive.h"
#include "vtkNew.h"
#include "vtkPolyData.h"
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

vtkSmartPointer<vtkPolyData> Cylinder(
  double r, double h, double cx, double cy, double cz, bool capped)
{
  vtkNew<vtkCylinderSource> c;
  c->SetRadius(r);
  c->SetHeight(h);
  c->SetCenter(cx, cy, cz);
  c->SetResolution(48);
  c->SetCapping(capped);
  vtkNew<vtkTriangleFilter> tri;
  tri->SetInputConnection(c->GetOutputPort());
  tri->Update();
  return tri->GetOutput();
}

// k x k cups of radius r, wall thickness t, height 0.5 (along y), 0.02 apart: size ~1.
vtkSmartPointer<vtkPolyData> ThinCups(int k, double t)
{
  const double gap = 0.02, r = (1.0 - (k - 1) * gap) / (2 * k);
  vtkNew<vtkAppendPolyData> app;
  for (int i = 0; i < k; ++i)
    for (int j = 0; j < k; ++j)
    {
      const double x = (2 * i + 1) * r + i * gap, z = (2 * j + 1) * r + j * gap;
      app->AddInputData(Cylinder(r, 0.5, x, 0.25, z, true));
      app->AddInputData(Cylinder(r - t, 0.5, x, 0.25 + t, z, false));
    }
  app->Update();
  return app->GetOutput();
}

void ToArrays(vtkPolyData* pd, std::vector<double>& pts, std::vector<Id>& tris)
{
  pts.resize(3 * pd->GetNumberOfPoints());
  for (vtkIdType i = 0; i < pd->GetNumberOfPoints(); ++i)
    pd->GetPoint(i, &pts[3 * i]);
  tris.clear();
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < pd->GetNumberOfCells(); ++c)
  {
    pd->GetCellPoints(c, ids);
    for (vtkIdType k = 0; k < 3; ++k)
      tris.push_back(ids->GetId(k));
  }
}

void CheckWrapBounds(vtkPolyData* shell)
{
  std::vector<double> pts;
  std::vector<Id> tris;
  ToArrays(shell, pts, tris);

  // Unbounded at a coarse ball: a closed manifold envelope, and the work it took is known.
  hoembed::SurfaceWrapResult coarse = hoembed::WrapSurface(pts, tris, 0.1, 0.025);
  HOEMBED_CHECK(coarse.Error.empty() && !coarse.Stopped, "coarse wrap: '%s'", coarse.Error.c_str());
  hoembed::SurfaceCheck check;
  check.Run(coarse.Points.data(), static_cast<Id>(coarse.Points.size() / 3), coarse.Tris.data(),
    static_cast<Id>(coarse.Tris.size() / 3));
  HOEMBED_CHECK(check.IsClosedManifold(), "coarse envelope not a closed manifold");
  HOEMBED_CHECK(coarse.Gates > 0 && coarse.SteinerPoints > 0, "no work counted (%llu, %llu)",
    (unsigned long long)coarse.Gates, (unsigned long long)coarse.SteinerPoints);
  std::printf("coarse wrap: %llu gates, %llu Steiner points, %zu envelope points\n",
    (unsigned long long)coarse.Gates, (unsigned long long)coarse.SteinerPoints,
    coarse.Points.size() / 3);

  // A ball 10x smaller follows both sides of every wall: far more work than the coarse
  // one. The gate bound stops it right after the bound, with nothing returned.
  hoembed::SurfaceWrapLimits limits;
  limits.MaxGates = 20000;
  hoembed::SurfaceWrapResult fine = hoembed::WrapSurface(pts, tris, 0.01, 0.0025, limits);
  HOEMBED_CHECK(fine.Stopped && !fine.Aborted, "fine wrap not stopped by its bound");
  HOEMBED_CHECK(
    fine.Gates == limits.MaxGates + 1, "stopped after %llu gates", (unsigned long long)fine.Gates);
  HOEMBED_CHECK(
    fine.Error.find("work bound") != std::string::npos, "error: '%s'", fine.Error.c_str());
  HOEMBED_CHECK(fine.Points.empty() && fine.Tris.empty(), "a stopped wrap returned an envelope");

  limits = hoembed::SurfaceWrapLimits();
  limits.MaxSteinerPoints = 100;
  fine = hoembed::WrapSurface(pts, tris, 0.01, 0.0025, limits);
  HOEMBED_CHECK(fine.Stopped && fine.SteinerPoints == 101, "Steiner bound: %llu points",
    (unsigned long long)fine.SteinerPoints);

  // The abort is polled every 256 gates: an abort at the 4th poll stops it at gate 1024.
  int polls = 0;
  limits = hoembed::SurfaceWrapLimits();
  limits.Abort = [&polls]() { return ++polls == 4; };
  fine = hoembed::WrapSurface(pts, tris, 0.01, 0.0025, limits);
  HOEMBED_CHECK(fine.Stopped && fine.Aborted && fine.Gates == 1024 && polls == 4,
    "abort: stopped %d aborted %d after %llu gates, %d polls", fine.Stopped, fine.Aborted,
    (unsigned long long)fine.Gates, polls);
  HOEMBED_CHECK(
    fine.Error.find("aborted") != std::string::npos, "abort error: '%s'", fine.Error.c_str());

  // Without a callback of its own the wrap polls the thread's abort scope (how
  // vtkTet10Mesher's AbortExecute reaches it).
  polls = 0;
  {
    hoembed::ScopedTetGenAbort scope([&polls]() { return ++polls == 2; });
    fine = hoembed::WrapSurface(pts, tris, 0.01, 0.0025);
  }
  HOEMBED_CHECK(fine.Aborted && fine.Gates == 512, "scoped abort: aborted %d after %llu gates",
    fine.Aborted, (unsigned long long)fine.Gates);
}

// vtkTet10Mesher on the shell: completes at the default settings (valid cells by VTK's own
// validator), and AbortExecute set from a progress observer while the envelope is being
// built stops it there with an error and an empty output.
void CheckMesherAbort(vtkPolyData* shell)
{
  {
    vtkNew<vtkTet10Mesher> mesher;
    mesher->SetInputData(shell);
    mesher->SetTargetNumberOfElements(500);
    mesher->Update();
    vtkUnstructuredGrid* out = mesher->GetOutput();
    HOEMBED_CHECK(out->GetNumberOfCells() > 0, "the shell was not meshed");
    vtkNew<vtkCellValidator> validator;
    validator->SetInputData(out);
    validator->Update();
    vtkDataArray* states = validator->GetOutput()->GetCellData()->GetArray("ValidityState");
    vtkIdType bad = 0;
    for (vtkIdType c = 0; states && c < states->GetNumberOfTuples(); ++c)
      bad += states->GetTuple1(c) != 0 ? 1 : 0;
    HOEMBED_CHECK(states && bad == 0, "%lld cells fail vtkCellValidator", (long long)bad);
    std::printf("shell at 500: %lld cells\n", (long long)out->GetNumberOfCells());
  }
  // Progress 0.1 is the surface check's end, 0.2 the first envelope's: the polls in
  // between (each raises the progress by 1e-6) come from the driver's check after the
  // surface check (the first) and from the wrap (the others).
  struct Aborter : public vtkCommand
  {
    static Aborter* New()
    {
      return new Aborter;
    }
    void Execute(vtkObject* caller, unsigned long, void*) override
    {
      auto* alg = static_cast<vtkAlgorithm*>(caller);
      const double p = alg->GetProgress();
      if (p > 0.1 && p < 0.2 && ++this->Seen == 3)
        alg->SetAbortExecute(1);
    }
    int Seen = 0;
  };
  vtkNew<vtkTet10Mesher> mesher;
  vtkNew<ErrorCatcher> catcher;
  vtkNew<Aborter> aborter;
  mesher->AddObserver(vtkCommand::ErrorEvent, catcher);
  mesher->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, catcher);
  mesher->AddObserver(vtkCommand::ProgressEvent, aborter);
  mesher->SetInputData(shell);
  mesher->SetTargetNumberOfElements(500);
  mesher->Update();
  HOEMBED_CHECK(aborter->Seen >= 3, "only %d polls seen in the envelope", aborter->Seen);
  HOEMBED_CHECK(catcher->Text.find("aborted") != std::string::npos &&
      catcher->Text.find("envelope") != std::string::npos,
    "abort error: '%s'", catcher->Text.c_str());
  HOEMBED_CHECK(mesher->GetOutput()->GetNumberOfCells() == 0, "output not empty after an abort");
}
// hoembed::RunMesher on a clean closed sphere with services made of VTK's classes here:
// TetGen's work bound reached on the coarsened surface falls back to the envelope (a
// warning says so) instead of an error.
void CheckTetGenBoundFallsBack()
{
  vtkNew<vtkSphereSource> src;
  src->SetThetaResolution(40);
  src->SetPhiResolution(40);
  vtkNew<vtkTriangleFilter> tri;
  tri->SetInputConnection(src->GetOutputPort());
  tri->Update();
  vtkPolyData* fine = tri->GetOutput();
  std::vector<double> pts;
  std::vector<Id> tris;
  ToArrays(fine, pts, tris);
  vtkNew<vtkCellLocator> locator;
  locator->SetDataSet(fine);
  locator->BuildLocator();
  hoembed::MesherServices services;
  services.Decimate = [fine](double reduction, bool, std::vector<double>& p, std::vector<Id>& t) {
    vtkNew<vtkQuadricDecimation> decimate;
    decimate->SetInputData(fine);
    decimate->SetTargetReduction(reduction);
    decimate->VolumePreservationOff();
    decimate->Update();
    ToArrays(decimate->GetOutput(), p, t);
    return true;
  };
  vtkCellLocator* loc = locator;
  services.Fine.Closest = [loc](const double x[3], double cp[3]) {
    vtkIdType cell;
    int sub;
    double d2;
    loc->FindClosestPoint(x, cp, cell, sub, d2);
  };
  services.Fine.Ray = [loc](const double a[3], const double b[3], double hit[3]) {
    double t, pc[3];
    int sub;
    return loc->IntersectWithLine(a, b, 0.0, t, hit, pc, sub) != 0;
  };
  services.MaxDistanceToTriangles = [](const std::vector<double>&, const std::vector<Id>&,
                                      const std::vector<double>&, Id) { return 0.0; };
  hoembed::MesherOptions options;
  // an option outside its range (hoembed::MesherRanges) is refused before any work, with
  // the value (no clamping anywhere: 0 elements is not turned into 4)
  options.TargetNumberOfElements = 0;
  hoembed::MesherResult refused = hoembed::RunMesher(pts, tris, options, services);
  HOEMBED_CHECK(refused.Error ==
      "TargetNumberOfElements must be an integer in [4, 10000000] "
      "(got 0).",
    "got '%s'", refused.Error.c_str());
  options.TargetNumberOfElements = 500;
  options.MinimumQuality = 1.5;
  HOEMBED_CHECK(
    hoembed::CheckMesherOptions(options) == "MinimumQuality must be in [0, 1] (got 1.5).",
    "got '%s'", hoembed::CheckMesherOptions(options).c_str());
  options.MinimumQuality = hoembed::MesherOptions().MinimumQuality;
  hoembed::MesherResult plain = hoembed::RunMesher(pts, tris, options, services);
  HOEMBED_CHECK(plain.Error.empty() && !plain.Wrapped, "sphere: '%s', wrapped %d",
    plain.Error.c_str(), plain.Wrapped);
  options.CoarseTetGenMaxCreated = 100; // far below the ~8 per element TetGen creates
  hoembed::MesherResult bounded = hoembed::RunMesher(pts, tris, options, services);
  HOEMBED_CHECK(bounded.Error.empty(), "bounded: '%s'", bounded.Error.c_str());
  HOEMBED_CHECK(bounded.Wrapped && bounded.EnvelopeOffset > 0.0, "not meshed through the envelope");
  HOEMBED_CHECK(!bounded.Conn.empty() && bounded.BoundaryCrossingsLeft == 0, "no mesh");
  bool said = false;
  for (const std::string& w : bounded.Warnings)
    said = said ||
      (w.find("work bound") != std::string::npos && w.find("envelope") != std::string::npos);
  HOEMBED_CHECK(said, "no warning naming the work bound and the envelope");
  std::printf("TetGen bound: %zu cells through the envelope (%zu coarsened)\n",
    bounded.MinScaledJacobian.size(), plain.MinScaledJacobian.size());
}

// A clean closed sphere with a spherical cavity (the inner shell's triangles face into
// it), meshed through its envelope (Wrap = 1, what a fallback does): the cavity stays
// empty. The envelope flood-fills from outside and never reaches the cavity; it used to
// be filled.
void CheckEnvelopeKeepsCavity()
{
  auto sphere = [](double r) {
    vtkNew<vtkSphereSource> src;
    src->SetRadius(r);
    src->SetThetaResolution(48);
    src->SetPhiResolution(48);
    vtkNew<vtkTriangleFilter> tri;
    tri->SetInputConnection(src->GetOutputPort());
    tri->Update();
    vtkSmartPointer<vtkPolyData> pd = tri->GetOutput();
    return pd;
  };
  std::vector<double> pts, inner;
  std::vector<Id> tris, innerTris;
  ToArrays(sphere(1.0), pts, tris);
  ToArrays(sphere(0.5), inner, innerTris);
  const Id base = static_cast<Id>(pts.size() / 3);
  pts.insert(pts.end(), inner.begin(), inner.end());
  for (size_t t = 0; t < innerTris.size() / 3; ++t)
  {
    tris.push_back(base + innerTris[3 * t]);
    tris.push_back(base + innerTris[3 * t + 2]);
    tris.push_back(base + innerTris[3 * t + 1]);
  }
  hoembed::MesherServices services;
  services.Fine.Closest = [](const double x[3], double cp[3]) {
    // the nearer of the two spheres
    const double r = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    const double onto = std::fabs(r - 1.0) < std::fabs(r - 0.5) ? 1.0 : 0.5;
    for (int d = 0; d < 3; ++d)
      cp[d] = r > 0.0 ? x[d] * onto / r : (d == 0 ? onto : 0.0);
  };
  services.Fine.Ray = [](const double*, const double*, double*) { return false; };
  services.MaxDistanceToTriangles = [](const std::vector<double>&, const std::vector<Id>&,
                                      const std::vector<double>&, Id) { return 0.0; };
  hoembed::MesherOptions options;
  options.TargetNumberOfElements = 1500;
  options.Wrap = 1;
  const hoembed::MesherResult r = hoembed::RunMesher(pts, tris, options, services);
  HOEMBED_CHECK(
    r.Error.empty() && r.Wrapped, "cavity: '%s', wrapped %d", r.Error.c_str(), r.Wrapped);
  // straight volume of the corner tets, and no tet around the centre
  double volume = 0.0;
  Id aroundCentre = 0;
  const int npc = r.NodesPerCell;
  for (size_t c = 0; c < r.Conn.size() / npc; ++c)
  {
    const double* x[4];
    for (int a = 0; a < 4; ++a)
      x[a] = &r.Points[3 * r.Conn[npc * c + a]];
    double e[3][3];
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 3; ++d)
        e[k][d] = x[k + 1][d] - x[0][d];
    volume += (e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
                e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
                e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0])) /
      6.0;
    for (int a = 0; a < 4; ++a)
      aroundCentre += std::sqrt(x[a][0] * x[a][0] + x[a][1] * x[a][1] + x[a][2] * x[a][2]) < 0.4;
  }
  const double expected = 4.0 / 3.0 * 3.141592653589793 * (1.0 - 0.125);
  HOEMBED_CHECK(aroundCentre == 0, "cavity: %lld tet corners inside the cavity",
    static_cast<long long>(aroundCentre));
  HOEMBED_CHECK(std::fabs(volume - expected) < 0.1 * expected,
    "cavity: straight volume %g, the solid's %g (filled: %g)", volume, expected,
    4.0 / 3.0 * 3.141592653589793);
  std::printf("cavity through the envelope: %zu cells, straight volume %g (solid %g)\n",
    r.MinScaledJacobian.size(), volume, expected);
}
} // namespace

int main(int, char*[])
{
  CheckTetGenBoundFallsBack();
  CheckEnvelopeKeepsCavity();
  vtkSmartPointer<vtkPolyData> shell = ThinCups(3, 0.004);
  CheckWrapBounds(shell);
  CheckMesherAbort(shell);
  return hoembed_test::Report("TestMesherDriver");
}
