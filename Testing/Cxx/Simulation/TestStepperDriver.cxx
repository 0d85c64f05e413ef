// hoembedStepperDriver alone, on plain arrays (what the pip wheel's binding gives it),
// against vtkCorotationalFEMStepper on the same mesh: the same frames bit for bit (the
// filter calls this driver; this checks that nothing of the set-up stayed behind in the
// filter), a restart when asked for an earlier step, the static solve, and the driver's
// errors as sentences.
#include "hoembedDriverTestUtilities.h"
#include "hoembedStepperDriver.h"
#include "hoembedTestUtilities.h"
#include "hoembedTetMeshInput.h"

#include "vtkCellArray.h"
#include "vtkCorotationalFEMStepper.h"
#include "vtkDataArray.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace
{
using hoembed_test::MakeBoxTetMesh;

// the mesh as the wheel's binding hands it over (plain arrays)
using PlainMesh = hoembed_test::PlainTetMesh;
PlainMesh Plain(vtkUnstructuredGrid* g)
{
  return PlainMesh(g);
}

bool SamePositions(const hoembed::StepperDriver& d, vtkUnstructuredGrid* out)
{
  const vtkIdType n = out->GetNumberOfPoints();
  std::vector<double> x(3 * n);
  for (vtkIdType p = 0; p < n; ++p)
    out->GetPoint(p, &x[3 * p]);
  return n > 0 && std::memcmp(x.data(), d.Solver.GetPositions(), x.size() * sizeof(double)) == 0;
}

std::string Build(hoembed::StepperDriver& d, const PlainMesh& m,
  const hoembed::StepperParameters& p, const double gravity[3])
{
  hoembed::TetMeshInput mesh;
  std::string error = mesh.Read(m.View(), hoembed::TetMeshInput::KeepPoints);
  if (error.empty())
  {
    hoembed::StepperInputs in;
    std::copy(gravity, gravity + 3, in.Gravity);
    error = d.Build(mesh, p, in);
  }
  return error;
}

void TestFramesEqualTheFilter(int order)
{
  auto grid = MakeBoxTetMesh(8, 2, 2, 4.0, 0.5, 0.5, order);
  const double gravity[3] = { 0.0, -2.0, -9.81 };
  hoembed::StepperParameters p;
  p.YoungModulus = 3e4;
  p.TimeStep = 0.02;
  p.UseClampPlane = true; // the end x <= 0
  p.ClampPlaneNormal[0] = 1.0;
  vtkNew<vtkCorotationalFEMStepper> filter;
  filter->SetInputData(grid);
  filter->SetYoungModulus(p.YoungModulus);
  filter->SetTimeStep(p.TimeStep);
  filter->SetNumberOfTimeSteps(10);
  filter->SetUseClampPlane(true);
  filter->SetClampPlaneNormal(1.0, 0.0, 0.0);
  filter->SetGravity(gravity[0], gravity[1], gravity[2]);

  hoembed::StepperDriver d;
  const PlainMesh m = Plain(grid);
  HOEMBED_CHECK(Build(d, m, p, gravity).empty(), "driver set-up failed");
  // forward, then back (a restart from the initial state), then forward again
  for (long long k : { 1, 4, 7, 2, 10 })
  {
    filter->UpdateTimeStep(k * p.TimeStep);
    HOEMBED_CHECK(d.Advance(k, false, p.TimeStep, {}).empty(), "driver step failed");
    HOEMBED_CHECK(d.CurrentStep == k, "driver at step %d, asked %lld", d.CurrentStep, k);
    HOEMBED_CHECK(SamePositions(d, filter->GetOutput()),
      "order %d step %lld: driver positions differ from the filter's", order, k);
  }
  // not trivially equal: the beam moved down, and the clamped end stayed
  double sag = 0.0;
  for (std::size_t i = 0; i < m.Points.size() / 3; ++i)
  {
    const double dz = d.Solver.GetPositions()[3 * i + 2] - m.Points[3 * i + 2];
    sag = std::min(sag, dz);
    if (m.Points[3 * i] <= 0.0)
      HOEMBED_CHECK(dz == 0.0, "clamped node %zu moved", i);
  }
  HOEMBED_CHECK(sag < -1e-3, "the beam did not sag (%g)", sag);

  // the static solve (a stiffer beam: the soft one's sag is beyond the static iteration)
  p.YoungModulus = 1e9;
  filter->SetYoungModulus(p.YoungModulus);
  filter->SetStaticSolve(true);
  filter->UpdateTimeStep(0.0);
  hoembed::StepperDriver s;
  HOEMBED_CHECK(Build(s, m, p, gravity).empty(), "driver set-up failed");
  HOEMBED_CHECK(s.Advance(0, true, p.TimeStep, {}).empty(), "driver static solve failed");
  HOEMBED_CHECK(SamePositions(s, filter->GetOutput()), "order %d: static solves differ", order);
}

void TestErrors()
{
  auto grid = MakeBoxTetMesh(2, 1, 1, 2.0, 1.0, 1.0, 2);
  PlainMesh m = Plain(grid);
  const double g[3] = { 0.0, 0.0, -9.81 };
  hoembed::StepperParameters p;
  p.UseClampPlane = true;
  p.ClampPlaneNormal[0] = 0.0;
  hoembed::StepperDriver d;
  std::string e = Build(d, m, p, g);
  HOEMBED_CHECK(e == "ClampPlaneNormal must be a nonzero vector.", "got '%s'", e.c_str());
  // a property outside its range (hoembed::StepperRanges) is refused first, with its value
  p.PoissonRatio = 0.5;
  hoembed::StepperDriver d0;
  e = Build(d0, m, p, g);
  HOEMBED_CHECK(e == "PoissonRatio must be in (-1, 0.5) (got 0.5).", "got '%s'", e.c_str());
  p.PoissonRatio = hoembed::StepperParameters().PoissonRatio;
  p.TimeStep = std::nan("");
  e = hoembed::StepperDriver::CheckParameters(p);
  HOEMBED_CHECK(e == "TimeStep must be > 0 (got nan).", "got '%s'", e.c_str());
  p.TimeStep = hoembed::StepperParameters().TimeStep;
  hoembed::StepperOptions o;
  o.NumberOfTimeSteps = -1;
  e = hoembed::StepperDriver::CheckOptions(o);
  HOEMBED_CHECK(e == "NumberOfTimeSteps must be an integer >= 0 (got -1).", "got '%s'", e.c_str());
  // cell 0 inverted: its first two corners swapped
  std::swap(m.Connectivity[0], m.Connectivity[1]);
  p.ClampPlaneNormal[0] = 1.0;
  hoembed::StepperDriver d2;
  e = Build(d2, m, p, g);
  HOEMBED_CHECK(
    e == "Rest cell 0 is inverted or has zero volume (det J <= 0).", "got '%s'", e.c_str());
  // a free body has no static equilibrium
  std::swap(m.Connectivity[0], m.Connectivity[1]);
  p.UseClampPlane = false;
  hoembed::StepperDriver d3;
  HOEMBED_CHECK(Build(d3, m, p, g).empty(), "free body set-up failed");
  e = d3.Advance(0, true, p.TimeStep, {});
  HOEMBED_CHECK(e.rfind("StaticSolve failed: ", 0) == 0 && e.back() == '.', "got '%s'", e.c_str());
  // loads of the wrong size
  d3.NodalForces.assign(6, 1.0);
  e = d3.ApplyLoads(g, 0.0, static_cast<long long>(m.Points.size() / 3));
  HOEMBED_CHECK(e.find("SetNodalForces: the array has 2 tuples") == 0, "got '%s'", e.c_str());
}

// SetPrescribedMotion (the filter's and the wheel's way in): the prescribed nodes reach
// rest + target in the first step (no speed limit), an unread target row of an
// unprescribed node may hold anything, and a non-finite prescribed target is refused
// leaving the previous motion in place.
void TestPrescribedMotion()
{
  auto grid = MakeBoxTetMesh(4, 1, 1, 2.0, 0.5, 0.5, 2);
  const PlainMesh m = Plain(grid);
  const long long n = static_cast<long long>(m.Points.size() / 3);
  const double g[3] = { 0.0, 0.0, 0.0 };
  hoembed::StepperParameters p;
  p.UseClampPlane = true; // the end x <= 0
  hoembed::StepperDriver d;
  HOEMBED_CHECK(Build(d, m, p, g).empty(), "driver set-up failed");
  std::vector<double> mask(n, 0.0), t(3 * n, 0.0);
  long long held = 0;
  for (long long q = 0; q < n; ++q)
  {
    if (m.Points[3 * q] >= 2.0 - 1e-9)
    {
      mask[q] = 2.0; // any nonzero value
      t[3 * q + 2] = 0.1;
      ++held;
    }
    else
    {
      t[3 * q] = std::numeric_limits<double>::quiet_NaN(); // not read
    }
  }
  HOEMBED_CHECK(held > 0, "no node at the free end");
  std::string e = d.SetPrescribedMotion(n, mask.data(), t.data());
  HOEMBED_CHECK(e.empty(), "got '%s'", e.c_str());
  HOEMBED_CHECK(d.ApplyLoads(g, 0.0, n).empty(), "ApplyLoads failed");
  HOEMBED_CHECK(d.Solver.GetNumberOfPrescribedPoints() == held, "%lld prescribed, expected %lld",
    d.Solver.GetNumberOfPrescribedPoints(), held);
  d.Start(p);
  HOEMBED_CHECK(d.Advance(1, false, p.TimeStep, {}).empty(), "driver step failed");
  double worst = 0.0, moved = 0.0;
  for (long long q = 0; q < n; ++q)
  {
    const double dz = d.Solver.GetPositions()[3 * q + 2] - m.Points[3 * q + 2];
    if (mask[q] != 0.0)
      worst = std::max(worst, std::abs(dz - 0.1));
    else if (m.Points[3 * q] > 0.0)
      moved = std::max(moved, std::abs(dz));
  }
  HOEMBED_CHECK(worst < 1e-12, "prescribed nodes %g from their targets", worst);
  HOEMBED_CHECK(moved > 1e-4, "the free nodes did not follow (%g)", moved);
  // a non-finite target of a prescribed node: refused, the old motion kept
  const std::vector<unsigned char> before = d.Mask;
  std::vector<double> bad = t;
  for (long long q = 0; q < n; ++q)
    if (mask[q] != 0.0)
    {
      bad[3 * q + 1] = std::numeric_limits<double>::infinity();
      e = d.SetPrescribedMotion(n, mask.data(), bad.data());
      HOEMBED_CHECK(e.find("the target displacement of point ") == 0 &&
          e.find(" is not finite.") != std::string::npos,
        "got '%s'", e.c_str());
      break;
    }
  HOEMBED_CHECK(d.Mask == before && d.Targets.size() == 3 * static_cast<std::size_t>(n),
    "a refused motion changed the driver's");
  HOEMBED_CHECK(
    d.SetPrescribedMotion(n, nullptr, nullptr).empty() && d.Mask.empty() && d.Targets.empty(),
    "clearing the motion failed");
}
// The clamps' array rule (CheckFixedArray): every kind of array and its sentence.
void TestFixedArrayRule()
{
  using K = hoembed::StepperDriver::FixedArrayKind;
  auto check = [](const char* name, K kind, long long tuples, const char* expected) {
    const std::string e = hoembed::StepperDriver::CheckFixedArray(name, kind, tuples, 10);
    HOEMBED_CHECK(
      e == expected, "'%s': got '%s', expected '%s'", name ? name : "(null)", e.c_str(), expected);
  };
  check(nullptr, K::Absent, 0, "");
  check("", K::Absent, 0, "");
  check("Fixed", K::Absent, 0, ""); // the default, absent: no clamps from an array
  check("Fixed", K::Numeric, 10, "");
  check("Clamp", K::Numeric, 10, "");
  check("Clamp", K::Absent, 0, "FixedArrayName 'Clamp' is not a point-data array of the input.");
  check("Fixed", K::NotNumeric, 10,
    "FixedArrayName 'Fixed' is a point-data array that is not numeric (e.g. strings): the "
    "clamps need numbers (nonzero = clamped).");
  check("Fixed", K::CellOrField, 3,
    "FixedArrayName 'Fixed' is cell or field data, not point data: the clamps are per node "
    "(nonzero = clamped).");
  check(
    "Clamp", K::Numeric, 9, "FixedArrayName 'Clamp' has 9 tuples, expected 10 (one per point).");
}

// The live clock against vtkCorotationalFEMStepper in LiveMode (which runs it): steps
// asked for, a time behind the current one (never backwards), a reset; the frames'
// arrays (WriteFrame) equal the filter's output bit for bit.
void TestLiveClock()
{
  auto grid = MakeBoxTetMesh(4, 1, 1, 2.0, 0.5, 0.5, 2);
  const PlainMesh m = Plain(grid);
  const long long n = static_cast<long long>(m.Points.size() / 3);
  const double g[3] = { 0.0, 0.0, -9.81 };
  hoembed::StepperParameters p;
  p.UseClampPlane = true;
  p.YoungModulus = 3e4;
  vtkNew<vtkCorotationalFEMStepper> filter;
  filter->SetInputData(grid);
  filter->SetYoungModulus(p.YoungModulus);
  filter->SetUseClampPlane(true);
  filter->SetGravity(g[0], g[1], g[2]);
  filter->LiveModeOn();
  hoembed::StepperDriver d;
  HOEMBED_CHECK(Build(d, m, p, g).empty(), "driver set-up failed");
  auto advance = [&](const char* what) {
    long long target = -1;
    std::string e = d.PrepareLiveStep(g, 0.0, n, false, 0, target);
    HOEMBED_CHECK(e.empty(), "%s: %s", what, e.c_str());
    e = d.Advance(target, false, p.TimeStep, {});
    HOEMBED_CHECK(e.empty(), "%s: %s", what, e.c_str());
    return target;
  };
  auto same = [&](const char* what) {
    vtkUnstructuredGrid* out = filter->GetOutput();
    HOEMBED_CHECK(SamePositions(d, out), "%s: positions differ from the filter's", what);
    std::vector<double> x(3 * n), u(3 * n), v(3 * n), r(9 * n);
    d.WriteFrame(x.data(), u.data(), v.data(), r.data(), nullptr);
    const char* names[3] = { "Displacement", "Velocity", "NodalRotation" };
    const std::vector<double>* ours[3] = { &u, &v, &r };
    for (int k = 0; k < 3; ++k)
    {
      vtkDataArray* a = out->GetPointData()->GetArray(names[k]);
      HOEMBED_CHECK(a &&
          std::memcmp(a->GetVoidPointer(0), ours[k]->data(), ours[k]->size() * sizeof(double)) == 0,
        "%s: %s differs from the filter's", what, names[k]);
    }
    HOEMBED_CHECK(filter->GetSimulationTime() == d.ClockStep() * p.TimeStep,
      "%s: time %g, the driver's clock at step %lld", what, filter->GetSimulationTime(),
      d.ClockStep());
  };
  HOEMBED_CHECK(filter->Step(0), "filter Step(0) failed");
  same("start");
  d.RequestSteps(3);
  HOEMBED_CHECK(advance("three steps") == 3 && d.ClockStep() == 3, "not at step 3");
  HOEMBED_CHECK(filter->Step(3), "filter Step(3) failed");
  same("three steps");
  d.RequestStep(1, true); // behind: stays
  HOEMBED_CHECK(advance("behind") == 3, "went backwards");
  HOEMBED_CHECK(filter->AdvanceTo(1 * p.TimeStep), "filter AdvanceTo failed");
  same("behind");
  d.RequestStep(5, true);
  HOEMBED_CHECK(advance("to 5") == 5, "not at step 5");
  HOEMBED_CHECK(filter->AdvanceTo(5 * p.TimeStep), "filter AdvanceTo failed");
  same("to 5");
  d.RequestReset();
  HOEMBED_CHECK(d.ClockStep() == 0, "a pending reset shows step %lld", d.ClockStep());
  HOEMBED_CHECK(advance("reset") == 0, "reset not at step 0");
  filter->ResetState();
  HOEMBED_CHECK(filter->Step(0), "filter Step(0) failed");
  same("reset");
  for (long long q = 0; q < 3 * n; ++q)
    HOEMBED_CHECK(d.Solver.GetPositions()[q] == m.Points[q], "reset: not at rest");
}
// The hyperelastic materials through the driver and the filter: the same frames bit for
// bit (the filter's Material, set by name, reaches the driver); a rigid rotation of the
// whole free body (initial displacement R X - X, no load) has no strain energy and stays
// rigid over steps (a law that is not frame-invariant, or a wrong stress, would move it);
// the material rules' sentences.
void TestHyperelastic(int order)
{
  auto grid = MakeBoxTetMesh(4, 1, 1, 2.0, 0.5, 0.5, order);
  const PlainMesh m = Plain(grid);
  const long long n = static_cast<long long>(m.Points.size() / 3);
  const double gravity[3] = { 0.0, -2.0, -9.81 };
  const char* names[3] = { "stvk", "neo-hookean", "mooney-rivlin" };
  for (int k = 1; k <= 3; ++k)
  {
    hoembed::StepperParameters p;
    p.YoungModulus = 3e4;
    p.TimeStep = 0.02;
    p.UseClampPlane = true;
    p.ClampPlaneNormal[0] = 1.0;
    p.Material = k;
    vtkNew<vtkCorotationalFEMStepper> filter;
    filter->SetInputData(grid);
    filter->SetYoungModulus(p.YoungModulus);
    filter->SetTimeStep(p.TimeStep);
    filter->SetNumberOfTimeSteps(10);
    filter->SetUseClampPlane(true);
    filter->SetClampPlaneNormal(1.0, 0.0, 0.0);
    filter->SetGravity(gravity[0], gravity[1], gravity[2]);
    filter->SetMaterial(names[k - 1]);
    HOEMBED_CHECK(
      filter->GetMaterial() == k, "SetMaterial(%s) gave %d", names[k - 1], filter->GetMaterial());
    hoembed::StepperDriver d;
    HOEMBED_CHECK(Build(d, m, p, gravity).empty(), "%s: driver set-up failed", names[k - 1]);
    for (long long step : { 3, 6 })
    {
      filter->UpdateTimeStep(step * p.TimeStep);
      HOEMBED_CHECK(d.Advance(step, false, p.TimeStep, {}).empty(), "driver step failed");
      HOEMBED_CHECK(SamePositions(d, filter->GetOutput()),
        "%s order %d step %lld: driver positions differ from the filter's", names[k - 1], order,
        step);
    }
    double sag = 0.0;
    for (long long q = 0; q < n; ++q)
      sag = std::min(sag, d.Solver.GetPositions()[3 * q + 2] - m.Points[3 * q + 2]);
    HOEMBED_CHECK(sag < -1e-3, "%s: the beam did not sag (%g)", names[k - 1], sag);

    // rigid rotation by 60 degrees about (1, 1, 1) / sqrt(3), free body, no load
    const double c = 0.5, s3 = std::sqrt(3.0) / 2.0, a = (1.0 - c) / 3.0, b = s3 / std::sqrt(3.0);
    const double R[9] = { c + a, a - b, a + b, a + b, c + a, a - b, a - b, a + b, c + a };
    std::vector<double> u0(3 * n), target(3 * n);
    for (long long q = 0; q < n; ++q)
      for (int i = 0; i < 3; ++i)
      {
        const double* X = &m.Points[3 * q];
        target[3 * q + i] = R[3 * i] * X[0] + R[3 * i + 1] * X[1] + R[3 * i + 2] * X[2];
        u0[3 * q + i] = target[3 * q + i] - X[i];
      }
    hoembed::StepperParameters rp = p;
    rp.UseClampPlane = false;
    hoembed::TetMeshInput mesh;
    HOEMBED_CHECK(mesh.Read(m.View(), hoembed::TetMeshInput::KeepPoints).empty(), "read");
    hoembed::StepperInputs in;
    in.InitialDisplacement = u0.data();
    hoembed::StepperDriver r;
    HOEMBED_CHECK(r.Build(mesh, rp, in).empty(), "rigid set-up failed");
    HOEMBED_CHECK(std::abs(r.Solver.StrainEnergy()) <= 1e-9 * p.YoungModulus,
      "%s: strain energy %g of a rigid rotation", names[k - 1], r.Solver.StrainEnergy());
    HOEMBED_CHECK(r.Advance(4, false, p.TimeStep, {}).empty(), "rigid steps failed");
    double dev = 0.0;
    for (long long q = 0; q < 3 * n; ++q)
      dev = std::max(dev, std::abs(r.Solver.GetPositions()[q] - target[q]));
    HOEMBED_CHECK(
      dev <= 1e-10, "%s order %d: the rigidly rotated body moved by %g", names[k - 1], order, dev);
  }
  // the rules
  hoembed::StepperParameters p;
  int index = 0;
  HOEMBED_CHECK(hoembed::StepperDriver::ParseMaterial("rubber", index) ==
        "Material 'rubber' is not one of corotated, stvk, neo-hookean, mooney-rivlin." &&
      index == -1,
    "ParseMaterial");
  HOEMBED_CHECK(hoembed::StepperDriver::ParseMaterial("mooney-rivlin", index).empty() && index == 3,
    "ParseMaterial(mooney-rivlin) = %d", index);
  p.Material = 4;
  HOEMBED_CHECK(hoembed::StepperDriver::CheckMaterial(p).find("Material must be one of 0 "
                                                              "(corotated)") == 0,
    "%s", hoembed::StepperDriver::CheckMaterial(p).c_str());
  p.Material = 3;
  p.MooneyRivlinC01 = std::nan("");
  HOEMBED_CHECK(
    hoembed::StepperDriver::CheckParameters(p).find("MooneyRivlinC01") == 0, "NaN C01 accepted");
  hoembed::StepperDriver d;
  HOEMBED_CHECK(
    Build(d, m, p, gravity).find("MooneyRivlinC01 must be") == 0, "Build took a NaN C01");
}
} // namespace

int main(int, char*[])
{
  TestHyperelastic(2);
  TestHyperelastic(1);
  TestFramesEqualTheFilter(2);
  TestFramesEqualTheFilter(1);
  TestErrors();
  TestPrescribedMotion();
  TestFixedArrayRule();
  TestLiveClock();
  return hoembed_test::Report("TestStepperDriver");
}
