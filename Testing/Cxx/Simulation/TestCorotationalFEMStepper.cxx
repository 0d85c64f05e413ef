// Tests of vtkCorotationalFEMStepper and its kernels against independent references:
// analytic integrals, rigid-body null spaces, Euler-Bernoulli beam theory, invariance
// under rigid motions, volume conservation, energy under huge time steps, error paths.
// (The P2 comparison with scikit-fem lives in Testing/Python/test_simulation.py.)
#include "hoembedCorotationalSolver.h"
#include "hoembedElementGeometry.h"
#include "hoembedShapeFunctions.h"
#include "hoembedTestUtilities.h"
#include "hoembedTetElementMatrices.h"

#include "vtkCallbackCommand.h"
#include "vtkCellData.h"
#include "vtkCommand.h"
#include "vtkDoubleArray.h"
#include "vtkExecutive.h"
#include "vtkFieldData.h"
#include "vtkIdList.h"
#include "vtkInformation.h"
#include "vtkIntArray.h"
#include "vtkMath.h"
#include "vtkPointData.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include "vtkCorotationalFEMStepper.h"

#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

namespace
{
using hoembed_test::MakeBoxTetMesh;

class ErrorCatcher : public vtkCommand
{
public:
  static ErrorCatcher* New()
  {
    return new ErrorCatcher;
  }
  void Execute(vtkObject*, unsigned long, void* data) override
  {
    if (data)
    {
      this->Messages += static_cast<const char*>(data);
      this->Messages += "\n";
    }
  }
  std::string Messages;
};

double Factorial(int n)
{
  return n <= 1 ? 1.0 : n * Factorial(n - 1);
}

void TestQuadrature()
{
  double pc[3 * 216], w[216];
  for (int m = 2; m <= 4; ++m)
  {
    const int n = hoembed::TetQuadrature(m, pc, w);
    const int degree = 2 * m - 3;
    for (int a = 0; a <= degree; ++a)
      for (int b = 0; a + b <= degree; ++b)
        for (int c = 0; a + b + c <= degree; ++c)
        {
          double s = 0.0;
          for (int q = 0; q < n; ++q)
            s += w[q] * std::pow(pc[3 * q], a) * std::pow(pc[3 * q + 1], b) *
              std::pow(pc[3 * q + 2], c);
          const double exact =
            Factorial(a) * Factorial(b) * Factorial(c) / Factorial(a + b + c + 3);
          HOEMBED_CHECK(std::abs(s - exact) < 1e-14, "m=%d monomial r^%d s^%d t^%d: %g vs %g", m, a,
            b, c, s, exact);
        }
  }
}

// A distorted, curved tet10 (positive).
void CurvedTet10(double x[30])
{
  const double corners[4][3] = { { 0.1, -0.2, 0.0 }, { 1.3, 0.1, 0.2 }, { 0.2, 1.1, -0.1 },
    { 0.3, 0.2, 0.9 } };
  for (int a = 0; a < 4; ++a)
    for (int i = 0; i < 3; ++i)
      x[3 * a + i] = corners[a][i];
  for (int e = 0; e < 6; ++e)
    for (int i = 0; i < 3; ++i)
      x[3 * (4 + e) + i] = 0.5 *
          (corners[hoembed::TetEdgeCorners[e][0]][i] + corners[hoembed::TetEdgeCorners[e][1]][i]) +
        0.03 * std::sin(3.0 * e + i);
}

void TestElementMatrices()
{
  double x[30];
  CurvedTet10(x);
  HOEMBED_CHECK(hoembed::Tet10IsValid(x), "curved test tet must be valid");
  std::vector<double> K(900), M(900), f(30);
  const double vol = hoembed::ElementStiffness(10, x, 1000.0, 0.3, K.data());
  const double volRef = hoembed::Tet10Volume(x);
  HOEMBED_CHECK(std::abs(vol - volRef) < 1e-12 * volRef, "stiffness volume %g vs %g", vol, volRef);
  // Rigid motions (3 translations + 3 infinitesimal rotations) are in the null space.
  for (int mode = 0; mode < 6; ++mode)
  {
    double u[30];
    for (int a = 0; a < 10; ++a)
    {
      const double* p = x + 3 * a;
      double v[3] = { 0, 0, 0 };
      if (mode < 3)
        v[mode] = 1.0;
      else
      {
        double w[3] = { 0, 0, 0 };
        w[mode - 3] = 1.0;
        vtkMath::Cross(w, p, v);
      }
      for (int i = 0; i < 3; ++i)
        u[3 * a + i] = v[i];
    }
    double maxf = 0.0, maxK = 0.0;
    for (int r = 0; r < 30; ++r)
    {
      double s = 0.0;
      for (int c = 0; c < 30; ++c)
      {
        s += K[r * 30 + c] * u[c];
        maxK = std::max(maxK, std::abs(K[r * 30 + c]));
      }
      maxf = std::max(maxf, std::abs(s));
    }
    HOEMBED_CHECK(maxf < 1e-11 * maxK, "rigid mode %d not in null space of K: %g", mode, maxf);
  }
  // Symmetry.
  double asym = 0.0;
  for (int r = 0; r < 30; ++r)
    for (int c = 0; c < 30; ++c)
      asym = std::max(asym, std::abs(K[r * 30 + c] - K[c * 30 + r]));
  HOEMBED_CHECK(asym < 1e-12 * std::abs(K[0]), "K not symmetric: %g", asym);

  // Mass and body force of a straight tet10: analytic integrals of N_a.
  double s[30];
  const double corners[4][3] = { { 0, 0, 0 }, { 2, 0, 0 }, { 0, 1, 0 }, { 0, 0, 3 } };
  for (int a = 0; a < 4; ++a)
    for (int i = 0; i < 3; ++i)
      s[3 * a + i] = corners[a][i];
  for (int e = 0; e < 6; ++e)
    for (int i = 0; i < 3; ++i)
      s[3 * (4 + e) + i] = 0.5 *
        (corners[hoembed::TetEdgeCorners[e][0]][i] + corners[hoembed::TetEdgeCorners[e][1]][i]);
  const double V = 1.0; // 2*1*3/6
  const double rho = 7.0, g[3] = { 0.0, 0.0, -2.0 };
  hoembed::ElementBodyForce(10, s, rho, g, f.data());
  for (int a = 0; a < 10; ++a)
  {
    const double expect = (a < 4 ? -V / 20.0 : V / 5.0) * rho * g[2];
    HOEMBED_CHECK(std::abs(f[3 * a + 2] - expect) < 1e-12, "body force node %d: %g vs %g", a,
      f[3 * a + 2], expect);
  }
  hoembed::ElementConsistentMass(10, s, rho, M.data());
  double total = 0.0;
  for (int a = 0; a < 10; ++a)
    for (int b = 0; b < 10; ++b)
      total += M[(3 * a) * 30 + 3 * b];
  HOEMBED_CHECK(std::abs(total - rho * V) < 1e-12, "consistent mass %g vs %g", total, rho * V);
  // analytic corner-corner entry: int N0 N0 = V * 6/420 = V/70 for tet10
  HOEMBED_CHECK(std::abs(M[0] - rho * V / 70.0) < 1e-12, "M00 %g vs %g", M[0], rho * V / 70.0);
  double m[10];
  hoembed::ElementLumpedMassHRZ(10, s, rho, m);
  double ms = 0.0;
  for (int a = 0; a < 10; ++a)
  {
    HOEMBED_CHECK(m[a] > 0.0, "HRZ mass %d not positive: %g", a, m[a]);
    ms += m[a];
  }
  HOEMBED_CHECK(std::abs(ms - rho * V) < 1e-12, "HRZ mass sum %g", ms);
}

void TestPolar()
{
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  for (int trial = 0; trial < 50; ++trial)
  {
    double axis[3] = { U(rng), U(rng), U(rng) };
    vtkMath::Normalize(axis);
    const double ang = 3.0 * U(rng);
    double q[4] = { std::cos(ang / 2), std::sin(ang / 2) * axis[0], std::sin(ang / 2) * axis[1],
      std::sin(ang / 2) * axis[2] };
    double Q[3][3];
    vtkMath::QuaternionToMatrix3x3(q, Q);
    double S[3][3] = { { 1.5, 0.2, 0.1 }, { 0.2, 0.8, -0.1 }, { 0.1, -0.1, 1.1 } };
    const bool invert = trial % 2 == 1;
    if (invert)
    {
      // inverted element: F = Q diag(1, 1, -0.3)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          S[i][j] = (i == j) ? (i == 2 ? -0.3 : 1.0) : 0.0;
    }
    double F[3][3], R[9];
    vtkMath::Multiply3x3(Q, S, F);
    hoembed::PolarRotation(&F[0][0], R);
    double err = 0.0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        err = std::max(err, std::abs(R[3 * i + j] - Q[i][j]));
    double Rm[3][3] = { { R[0], R[1], R[2] }, { R[3], R[4], R[5] }, { R[6], R[7], R[8] } };
    HOEMBED_CHECK(std::abs(vtkMath::Determinant3x3(Rm) - 1.0) < 1e-12, "det R != 1");
    HOEMBED_CHECK(err < 1e-10, "polar rotation off by %g (inverted %d)", err, invert);
  }
}

vtkSmartPointer<vtkCorotationalFEMStepper> MakeStepper(vtkUnstructuredGrid* mesh)
{
  auto s = vtkSmartPointer<vtkCorotationalFEMStepper>::New();
  s->SetInputData(mesh);
  return s;
}

vtkUnstructuredGrid* RunAt(vtkCorotationalFEMStepper* s, double t)
{
  s->UpdateTimeStep(t);
  return s->GetOutput();
}

double MeshVolume(vtkUnstructuredGrid* g)
{
  double v = 0.0;
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < g->GetNumberOfCells(); ++c)
  {
    g->GetCellPoints(c, ids);
    double x[30];
    for (vtkIdType a = 0; a < ids->GetNumberOfIds(); ++a)
      g->GetPoint(ids->GetId(a), x + 3 * a);
    v += ids->GetNumberOfIds() == 10 ? hoembed::Tet10Volume(x) : hoembed::Tet4Volume(x);
  }
  return v;
}

double MaxAbs(vtkDataArray* a)
{
  double m = 0.0;
  for (vtkIdType i = 0; i < a->GetNumberOfTuples(); ++i)
    for (int c = 0; c < a->GetNumberOfComponents(); ++c)
      m = std::max(m, std::abs(a->GetComponent(i, c)));
  return m;
}

double MinComponent(vtkDataArray* a, int comp)
{
  double m = 0.0;
  for (vtkIdType i = 0; i < a->GetNumberOfTuples(); ++i)
    m = std::min(m, a->GetComponent(i, comp));
  return m;
}

// Static cantilever (clamped at x = 0) under gravity vs Euler-Bernoulli + Timoshenko shear.
void TestStaticBeam()
{
  const double L = 10.0, h = 1.0, E = 1e11, rho = 1000.0, g = 9.81;
  auto mesh = MakeBoxTetMesh(20, 2, 2, L, h, h, 2);
  auto s = MakeStepper(mesh);
  s->SetYoungModulus(E);
  s->SetPoissonRatio(0.0);
  s->SetDensity(rho);
  s->SetGravity(0, 0, -g);
  s->UseClampPlaneOn();
  s->SetClampPlaneOrigin(0, 0, 0);
  s->SetClampPlaneNormal(1, 0, 0);
  s->StaticSolveOn();
  s->Update();
  vtkDataArray* d = s->GetOutput()->GetPointData()->GetArray("Displacement");
  HOEMBED_CHECK(d != nullptr, "static solve has no Displacement");
  if (!d)
    return;
  const double I = h * h * h * h / 12.0, q = rho * g * h * h;
  const double bending = q * L * L * L * L / (8.0 * E * I);
  const double shear = q * L * L / (2.0 * (5.0 / 6.0) * (E / 2.0) * h * h);
  const double tip = -MinComponent(d, 2);
  HOEMBED_CHECK(std::abs(tip - (bending + shear)) < 0.03 * bending,
    "static tip deflection %g vs beam theory %g", tip, bending + shear);
  std::printf("static beam: tip %.6e, Euler-Bernoulli+shear %.6e (rel %.2e)\n", tip,
    bending + shear, tip / (bending + shear) - 1.0);
}

// Free body displaced by a large rigid rotation stays there, stress-free.
void TestRigidRotation(int order)
{
  auto mesh = MakeBoxTetMesh(3, 2, 2, 3.0, 1.0, 1.0, order);
  const vtkIdType np = mesh->GetNumberOfPoints();
  double q[4] = { std::cos(1.2), std::sin(1.2) / std::sqrt(3.0), std::sin(1.2) / std::sqrt(3.0),
    std::sin(1.2) / std::sqrt(3.0) }; // 137 degrees about (1,1,1)
  double Q[3][3];
  vtkMath::QuaternionToMatrix3x3(q, Q);
  vtkNew<vtkDoubleArray> u0;
  u0->SetName("U0");
  u0->SetNumberOfComponents(3);
  u0->SetNumberOfTuples(np);
  vtkNew<vtkDoubleArray> v0;
  v0->SetName("V0");
  v0->SetNumberOfComponents(3);
  v0->SetNumberOfTuples(np);
  for (vtkIdType p = 0; p < np; ++p)
  {
    double X[3], y[3];
    mesh->GetPoint(p, X);
    vtkMath::Multiply3x3(Q, X, y);
    for (int i = 0; i < 3; ++i)
    {
      u0->SetComponent(p, i, y[i] - X[i] + 5.0);  // rotate and translate
      v0->SetComponent(p, i, i == 0 ? 0.7 : 0.0); // uniform drift velocity (pure translation)
    }
  }
  mesh->GetPointData()->AddArray(u0);
  mesh->GetPointData()->AddArray(v0);
  auto s = MakeStepper(mesh);
  s->SetInitialDisplacementArrayName("U0");
  s->SetInitialVelocityArrayName("V0");
  s->SetGravity(0, 0, 0);
  s->SetRayleighMass(0.0);
  s->SetRayleighStiffness(0.05);
  s->SetYoungModulus(1e6);
  s->SetNumberOfTimeSteps(40);
  s->SetTimeStep(0.01);
  vtkUnstructuredGrid* out = RunAt(s, 0.4);
  vtkDataArray* d = out->GetPointData()->GetArray("Displacement");
  vtkDataArray* vm = out->GetCellData()->GetArray("VonMisesStress");
  vtkDataArray* rot = out->GetPointData()->GetArray("NodalRotation");
  double errU = 0.0, errR = 0.0;
  for (vtkIdType p = 0; p < np; ++p)
  {
    for (int i = 0; i < 3; ++i)
    {
      const double expect = u0->GetComponent(p, i) + (i == 0 ? 0.7 * 0.4 : 0.0);
      errU = std::max(errU, std::abs(d->GetComponent(p, i) - expect));
    }
    for (int k = 0; k < 9; ++k)
      errR = std::max(errR, std::abs(rot->GetComponent(p, k) - Q[k / 3][k % 3]));
  }
  HOEMBED_CHECK(errU < 1e-9, "order %d: rigid rotation drifted by %g", order, errU);
  HOEMBED_CHECK(
    MaxAbs(vm) < 1e-6, "order %d: rigid rotation has stress %g (E = 1e6)", order, MaxAbs(vm));
  HOEMBED_CHECK(
    errR < 1e-9, "order %d: NodalRotation differs from the rigid rotation by %g", order, errR);
  std::printf("rigid rotation (order %d): drift %.2e, max von Mises %.2e, rotation err %.2e\n",
    order, errU, MaxAbs(vm), errR);
}

// Clamped beam, nearly incompressible, large deflection: volume kept; released, it
// returns to its rest shape (no ghost forces).
void TestLargeDeflection()
{
  auto mesh = MakeBoxTetMesh(8, 2, 2, 4.0, 0.5, 0.5, 2);
  const double V0 = MeshVolume(mesh);
  auto s = MakeStepper(mesh);
  s->SetYoungModulus(1e7);
  s->SetPoissonRatio(0.49);
  s->SetDensity(1000.0);
  s->UseClampPlaneOn();
  s->SetClampPlaneNormal(1, 0, 0);
  s->SetRayleighMass(2.0);
  s->SetRayleighStiffness(0.02);
  s->SetTimeStep(0.02);
  s->SetNumberOfTimeSteps(150);
  vtkUnstructuredGrid* out = RunAt(s, 3.0);
  vtkDataArray* d = out->GetPointData()->GetArray("Displacement");
  const double tip = -MinComponent(d, 2);
  const double V = MeshVolume(out);
  HOEMBED_CHECK(tip > 1.0, "beam should deflect a lot (tip %g of length 4)", tip);
  HOEMBED_CHECK(std::abs(V / V0 - 1.0) < 0.02, "volume changed by %g %% under large deflection",
    100.0 * (V / V0 - 1.0));
  std::printf(
    "large deflection: tip %.3f (L = 4), volume change %.3f %%\n", tip, 100.0 * (V / V0 - 1.0));

  // Release: start from the deflected state, no gravity.
  vtkNew<vtkDoubleArray> u0;
  u0->DeepCopy(d);
  u0->SetName("U0");
  mesh->GetPointData()->AddArray(u0);
  auto r = MakeStepper(mesh);
  r->SetYoungModulus(1e7);
  r->SetPoissonRatio(0.49);
  r->SetDensity(1000.0);
  r->UseClampPlaneOn();
  r->SetClampPlaneNormal(1, 0, 0);
  r->SetGravity(0, 0, 0);
  r->SetInitialDisplacementArrayName("U0");
  r->SetRayleighMass(2.0);
  r->SetRayleighStiffness(0.02);
  r->SetTimeStep(0.05);
  r->SetNumberOfTimeSteps(400);
  vtkUnstructuredGrid* back = RunAt(r, 20.0);
  const double rest = MaxAbs(back->GetPointData()->GetArray("Displacement"));
  HOEMBED_CHECK(rest < 1e-3 * tip, "released beam did not return to rest: |u| %g", rest);
  std::printf("released beam: max |u| after 20 s = %.2e (from tip %.3f)\n", rest, tip);
  mesh->GetPointData()->RemoveArray("U0");
}

// Huge time steps without damping: the energy never grows (backward Euler dissipates).
// The clamped beam starts straight with a large swinging velocity, no gravity.
void TestLargeTimeSteps()
{
  auto mesh = MakeBoxTetMesh(6, 2, 2, 3.0, 0.5, 0.5, 2);
  const vtkIdType np = mesh->GetNumberOfPoints();
  vtkNew<vtkDoubleArray> v0;
  v0->SetName("V0");
  v0->SetNumberOfComponents(3);
  v0->SetNumberOfTuples(np);
  for (vtkIdType p = 0; p < np; ++p)
  {
    double X[3];
    mesh->GetPoint(p, X);
    v0->SetTuple3(p, 0.0, 0.0, 3.0 * X[0]); // tip speed 9 m/s
  }
  mesh->GetPointData()->AddArray(v0);
  auto s = MakeStepper(mesh);
  s->SetYoungModulus(1e7);
  s->SetPoissonRatio(0.49);
  s->UseClampPlaneOn();
  s->SetClampPlaneNormal(1, 0, 0);
  s->SetRayleighMass(0.0);
  s->SetRayleighStiffness(0.0);
  s->SetGravity(0, 0, 0);
  s->SetInitialVelocityArrayName("V0");
  for (double dt : { 0.01, 0.5, 5.0 })
  {
    s->SetTimeStep(dt);
    s->SetNumberOfTimeSteps(60);
    s->UpdateInformation();
    double e0 = 0.0, prev = 0.0, maxRise = 0.0, maxE = 0.0;
    bool finite = true;
    for (int k = 0; k <= 60; ++k)
    {
      vtkUnstructuredGrid* out = RunAt(s, k * dt);
      vtkFieldData* fd = out->GetFieldData();
      if (!fd->GetArray("KineticEnergy"))
      {
        finite = false;
        break;
      }
      const double e = fd->GetArray("KineticEnergy")->GetComponent(0, 0) +
        fd->GetArray("StrainEnergy")->GetComponent(0, 0);
      finite = finite && std::isfinite(e);
      if (k == 0)
        e0 = prev = e;
      maxRise = std::max(maxRise, (e - prev) / e0);
      maxE = std::max(maxE, e);
      prev = e;
      finite = finite && MaxAbs(out->GetPointData()->GetArray("Displacement")) < 3.0;
    }
    HOEMBED_CHECK(finite, "dt = %g: non-finite or exploding state", dt);
    // One linearised solve per step: a step that swings the beam through a large angle
    // (dt = 0.5 here: ~50 degrees in the first step) overshoots its strain energy once,
    // then dissipates; it never grows without bound.
    HOEMBED_CHECK(
      e0 > 0.0 && maxE <= 10.0 * e0, "dt = %g: energy grew from %g to %g", dt, e0, maxE);
    HOEMBED_CHECK(prev <= (dt > 0.1 ? 1e-2 : 1.0) * e0, "dt = %g: energy not dissipated: %g of %g",
      dt, prev, e0);
    if (dt != 0.5)
    {
      HOEMBED_CHECK(maxRise < 1e-9, "dt = %g: energy rose by %g of E0 in one step", dt, maxRise);
    }
    std::printf(
      "dt = %g: E0 = %.4g, max E / E0 = %.6f, largest one-step rise %.2e E0, final E/E0 %.3g\n", dt,
      e0, maxE / e0, maxRise, prev / e0);
  }
  mesh->GetPointData()->RemoveArray("V0");
}

void TestTimeProtocol()
{
  auto mesh = MakeBoxTetMesh(4, 1, 1, 4.0, 1.0, 1.0, 2);
  auto s = MakeStepper(mesh);
  s->UseClampPlaneOn();
  s->SetTimeStep(0.01);
  s->SetNumberOfTimeSteps(20);
  s->UpdateInformation();
  vtkInformation* info = s->GetOutputInformation(0);
  const int n = info->Length(vtkStreamingDemandDrivenPipeline::TIME_STEPS());
  const double* ts = info->Get(vtkStreamingDemandDrivenPipeline::TIME_STEPS());
  HOEMBED_CHECK(n == 21, "TIME_STEPS has %d values, expected 21", n);
  HOEMBED_CHECK(n == 21 && std::abs(ts[7] - 0.07) < 1e-15, "t_7 = %g", n == 21 ? ts[7] : -1.0);
  const double* range = info->Get(vtkStreamingDemandDrivenPipeline::TIME_RANGE());
  HOEMBED_CHECK(range && std::abs(range[1] - 0.2) < 1e-15, "TIME_RANGE wrong");
  RunAt(s, 0.03);
  HOEMBED_CHECK(
    s->GetLastNumberOfSteps() == 3, "first request took %d steps", s->GetLastNumberOfSteps());
  vtkNew<vtkDoubleArray> first;
  first->DeepCopy(s->GetOutput()->GetPointData()->GetArray("Displacement"));
  RunAt(s, 0.04);
  HOEMBED_CHECK(
    s->GetLastNumberOfSteps() == 1, "sequential frame took %d steps", s->GetLastNumberOfSteps());
  const double dataTime = s->GetOutput()->GetInformation()->Get(vtkDataObject::DATA_TIME_STEP());
  HOEMBED_CHECK(std::abs(dataTime - 0.04) < 1e-15, "DATA_TIME_STEP %g", dataTime);
  int progressEvents = 0;
  vtkNew<vtkCallbackCommand> counter;
  counter->SetClientData(&progressEvents);
  counter->SetCallback(
    [](vtkObject*, unsigned long, void* cd, void*) { ++*static_cast<int*>(cd); });
  s->AddObserver(vtkCommand::ProgressEvent, counter);
  RunAt(s, 0.10);
  s->RemoveObservers(vtkCommand::ProgressEvent);
  HOEMBED_CHECK(progressEvents >= 2, "only %d progress events for 6 steps", progressEvents);
  HOEMBED_CHECK(
    s->GetLastNumberOfSteps() == 6, "jump forward took %d steps", s->GetLastNumberOfSteps());
  RunAt(s, 0.03);
  HOEMBED_CHECK(s->GetLastNumberOfSteps() == 3, "jump back took %d steps (restart expected)",
    s->GetLastNumberOfSteps());
  vtkDataArray* again = s->GetOutput()->GetPointData()->GetArray("Displacement");
  double diff = 0.0;
  for (vtkIdType i = 0; i < again->GetNumberOfValues(); ++i)
    diff = std::max(
      diff, std::abs(again->GetComponent(i / 3, i % 3) - first->GetComponent(i / 3, i % 3)));
  HOEMBED_CHECK(diff == 0.0, "restart is not bitwise reproducible: %g", diff);
  HOEMBED_CHECK(s->GetOutput()->GetNumberOfPoints() == mesh->GetNumberOfPoints() &&
      s->GetOutput()->GetNumberOfCells() == mesh->GetNumberOfCells(),
    "output topology differs from the input");
}

// Tet10 resists locking: at nu = 0.49 a coarse tet10 beam deflects far more than tet4.
void TestTet4VsTet10()
{
  double tips[2];
  for (int order = 1; order <= 2; ++order)
  {
    auto mesh = MakeBoxTetMesh(8, 2, 2, 8.0, 1.0, 1.0, order);
    auto s = MakeStepper(mesh);
    s->SetYoungModulus(1e9);
    s->SetPoissonRatio(0.49);
    s->UseClampPlaneOn();
    s->StaticSolveOn();
    s->Update();
    vtkDataArray* d = s->GetOutput()->GetPointData()->GetArray("Displacement");
    tips[order - 1] = d ? -MinComponent(d, 2) : 0.0;
  }
  HOEMBED_CHECK(tips[0] > 0.0 && tips[1] > 1.5 * tips[0],
    "tet4 locking not visible: tet4 tip %g, tet10 tip %g", tips[0], tips[1]);
  std::printf("locking: tet4 tip %.4e, tet10 tip %.4e\n", tips[0], tips[1]);
}

bool ExpectError(vtkCorotationalFEMStepper* s, const char* needle, double t = 0.0)
{
  vtkNew<ErrorCatcher> catcher;
  s->AddObserver(vtkCommand::ErrorEvent, catcher);
  s->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, catcher);
  s->UpdateTimeStep(t);
  s->RemoveObservers(vtkCommand::ErrorEvent);
  s->GetExecutive()->RemoveObservers(vtkCommand::ErrorEvent);
  const bool found = catcher->Messages.find(needle) != std::string::npos;
  const bool empty = s->GetOutput()->GetNumberOfPoints() == 0;
  HOEMBED_CHECK(
    found, "expected an error containing '%s', got: %s", needle, catcher->Messages.c_str());
  HOEMBED_CHECK(empty, "output not empty after error '%s'", needle);
  return found && empty;
}

void TestErrors()
{
  auto mesh = MakeBoxTetMesh(2, 1, 1, 2.0, 1.0, 1.0, 2);
  {
    auto s = MakeStepper(mesh);
    s->SetPoissonRatio(0.5);
    ExpectError(s, "PoissonRatio");
    s->SetPoissonRatio(-1.0);
    ExpectError(s, "PoissonRatio");
    s->SetPoissonRatio(0.3);
    s->SetYoungModulus(0.0);
    ExpectError(s, "YoungModulus");
    s->SetYoungModulus(1e5);
    s->SetDensity(-1.0);
    ExpectError(s, "Density");
    s->SetDensity(1000.0);
    s->SetTimeStep(0.0);
    ExpectError(s, "TimeStep");
    s->SetTimeStep(0.01);
    s->Update();
    HOEMBED_CHECK(s->GetOutput()->GetNumberOfPoints() == mesh->GetNumberOfPoints(),
      "stepper does not recover after errors");
  }
  {
    // inverted rest element: swap two corners of cell 1
    auto bad = MakeBoxTetMesh(2, 1, 1, 2.0, 1.0, 1.0, 2);
    vtkNew<vtkIdList> ids;
    bad->GetCellPoints(1, ids);
    vtkIdType pts[10];
    for (int a = 0; a < 10; ++a)
      pts[a] = ids->GetId(a);
    std::swap(pts[1], pts[2]);
    std::swap(pts[4], pts[6]); // mids 01 <-> 20 follow the swap
    std::swap(pts[8], pts[9]); // 13 <-> 23
    bad->GetCells()->ReplaceCellAtId(1, 10, pts);
    auto s = MakeStepper(bad);
    ExpectError(s, "cell 1");
  }
  {
    // zero-volume tet4
    auto flat = MakeBoxTetMesh(1, 1, 1, 1.0, 1.0, 1.0, 1);
    flat->GetPoints()->SetPoint(7, 0.5, 0.5, 0.0);
    flat->GetPoints()->SetPoint(4, 0.5, 0.5, 0.0);
    flat->GetPoints()->SetPoint(5, 0.5, 0.5, 0.0);
    flat->GetPoints()->SetPoint(6, 0.5, 0.5, 0.0);
    auto s = MakeStepper(flat);
    ExpectError(s, "zero volume");
  }
  {
    // unsupported cells
    auto hex = hoembed_test::MakeUnitHexahedron();
    auto s = MakeStepper(hex);
    ExpectError(s, "Unsupported cell");
  }
  {
    // non-finite state during integration
    auto m2 = MakeBoxTetMesh(2, 1, 1, 2.0, 1.0, 1.0, 2);
    vtkNew<vtkDoubleArray> f;
    f->SetName("F");
    f->SetNumberOfComponents(3);
    f->SetNumberOfTuples(m2->GetNumberOfPoints());
    f->Fill(1e300);
    m2->GetPointData()->AddArray(f);
    auto s = MakeStepper(m2);
    s->SetExternalForceArrayName("F");
    s->UseClampPlaneOn();
    ExpectError(s, "time step 1", 0.05);
  }
  {
    auto s = MakeStepper(mesh);
    s->SetExternalForceArrayName("NoSuchArray");
    ExpectError(s, "ExternalForceArrayName");
    auto f = MakeStepper(mesh);
    f->SetFixedArrayName("NoSuchClamps");
    ExpectError(f, "FixedArrayName");
    auto t = MakeStepper(mesh);
    t->StaticSolveOn(); // free body
    ExpectError(t, "clamped");
  }
}
// LiveMode: both end faces of a beam prescribed on a rigid rotation about z, changed every
// step; every prescribed node is on its target after each step, and once held, the damped
// stepper settles on the rigid motion of the whole beam (a co-rotated body is strain-free
// there: an analytic reference). Loads change without a restart; ResetState restarts;
// Step is refused offline.
void TestLiveMode()
{
  const double L = 3.0;
  auto mesh = MakeBoxTetMesh(6, 1, 1, L, 1.0, 1.0, 2);
  const vtkIdType np = mesh->GetNumberOfPoints();
  auto s = MakeStepper(mesh);
  s->SetGravity(0, 0, 0);
  s->SetYoungModulus(1e5);
  s->SetRayleighMass(5.0);
  s->SetTimeStep(0.05);
  s->SetSolverTolerance(1e-12);
  s->LiveModeOn();
  vtkNew<vtkDoubleArray> mask, target;
  mask->SetNumberOfTuples(np);
  target->SetNumberOfComponents(3);
  target->SetNumberOfTuples(np);
  const double c[3] = { 0.5 * L, 0.5, 0.5 };
  auto rigid = [&](double angle, vtkIdType p, double u[3]) {
    double X[3];
    mesh->GetPoint(p, X);
    const double ca = std::cos(angle), sa = std::sin(angle);
    const double dx = X[0] - c[0], dy = X[1] - c[1];
    u[0] = c[0] + ca * dx - sa * dy + 0.2 * angle - X[0];
    u[1] = c[1] + sa * dx + ca * dy - X[1];
    u[2] = 0.1 * angle;
  };
  for (vtkIdType p = 0; p < np; ++p)
  {
    double X[3];
    mesh->GetPoint(p, X);
    mask->SetValue(p, (X[0] < 1e-9 || X[0] > L - 1e-9) ? 1.0 : 0.0);
  }
  double angle = 0.0;
  for (int k = 1; k <= 20; ++k)
  {
    angle = 0.5 * k / 20.0;
    for (vtkIdType p = 0; p < np; ++p)
    {
      double u[3];
      rigid(angle, p, u);
      target->SetTuple(p, u);
    }
    HOEMBED_CHECK(s->SetPrescribedMotion(mask, target), "SetPrescribedMotion refused");
    HOEMBED_CHECK(s->Step(1), "live step %d failed", k);
    vtkDataArray* d = s->GetOutput()->GetPointData()->GetArray("Displacement");
    double off = 0.0;
    for (vtkIdType p = 0; d && p < np; ++p)
    {
      if (mask->GetValue(p) != 0.0)
      {
        double X[3], u[3];
        mesh->GetPoint(p, X);
        rigid(angle, p, u);
        for (int i = 0; i < 3; ++i)
        {
          off = std::max(off, std::abs(d->GetComponent(p, i) - ((X[i] + u[i]) - X[i])));
        }
      }
    }
    HOEMBED_CHECK(d && off == 0.0, "step %d: prescribed nodes %g off their targets", k, off);
  }
  HOEMBED_CHECK(s->Step(300), "holding failed");
  HOEMBED_CHECK(std::abs(s->GetSimulationTime() - 320 * 0.05) < 1e-9, "time %g after 320 steps",
    s->GetSimulationTime());
  vtkDataArray* d = s->GetOutput()->GetPointData()->GetArray("Displacement");
  double err = 0.0;
  for (vtkIdType p = 0; d && p < np; ++p)
  {
    double u[3];
    rigid(angle, p, u);
    for (int i = 0; i < 3; ++i)
    {
      err = std::max(err, std::abs(d->GetComponent(p, i) - u[i]));
    }
  }
  HOEMBED_CHECK(d && err < 1e-8, "held beam is %g from the rigid motion", err);
  vtkDataArray* vm = s->GetOutput()->GetCellData()->GetArray("VonMisesStress");
  HOEMBED_CHECK(
    vm && MaxAbs(vm) < 1e-6 * 1e5, "stress in a rigid motion: %g", vm ? MaxAbs(vm) : -1.0);
  // a load change continues from the state
  vtkNew<vtkDoubleArray> forces;
  forces->SetNumberOfComponents(3);
  forces->SetNumberOfTuples(np);
  forces->Fill(0.0);
  forces->SetComponent(np / 2, 2, 10.0);
  HOEMBED_CHECK(s->SetNodalForces(forces), "SetNodalForces refused");
  HOEMBED_CHECK(s->Step(1), "step after a load change failed");
  HOEMBED_CHECK(std::abs(s->GetSimulationTime() - 321 * 0.05) < 1e-9,
    "a load change restarted the clock: %g", s->GetSimulationTime());
  s->ResetState();
  HOEMBED_CHECK(s->Step(0) && s->GetSimulationTime() == 0.0, "ResetState did not restart");
  vtkDataArray* u0 = s->GetOutput()->GetPointData()->GetArray("Displacement");
  HOEMBED_CHECK(u0 && MaxAbs(u0) == 0.0, "state after ResetState is not the rest state");
  s->LiveModeOff();
  vtkNew<ErrorCatcher> catcher;
  s->AddObserver(vtkCommand::ErrorEvent, catcher);
  HOEMBED_CHECK(!s->Step(1), "Step accepted with LiveMode off");
  s->RemoveObservers(vtkCommand::ErrorEvent);
  HOEMBED_CHECK(catcher->Messages.find("LiveMode") != std::string::npos, "no LiveMode error: %s",
    catcher->Messages.c_str());
}
} // namespace

// ComputeDiagnostics off: the stress and energy arrays are left out and nothing else
// changes (points and point arrays bitwise equal to a stepper with it on, offline and in
// LiveMode, where switching it does not restart).
void TestDiagnosticsOff()
{
  auto mesh = MakeBoxTetMesh(4, 1, 1, 2.0, 1.0, 1.0, 2);
  auto on = MakeStepper(mesh);
  auto off = MakeStepper(mesh);
  off->ComputeDiagnosticsOff();
  auto same = [&](const char* what) {
    vtkUnstructuredGrid* a = on->GetOutput();
    vtkUnstructuredGrid* b = off->GetOutput();
    bool equal = a->GetNumberOfPoints() == b->GetNumberOfPoints();
    for (vtkIdType p = 0; equal && p < a->GetNumberOfPoints(); ++p)
    {
      double x[3], y[3];
      a->GetPoint(p, x);
      b->GetPoint(p, y);
      equal = std::memcmp(x, y, sizeof(x)) == 0;
    }
    for (const char* name : { "Displacement", "Velocity", "NodalRotation" })
    {
      vtkDataArray* u = a->GetPointData()->GetArray(name);
      vtkDataArray* v = b->GetPointData()->GetArray(name);
      equal = equal && u && v && u->GetNumberOfValues() == v->GetNumberOfValues();
      for (vtkIdType k = 0; equal && k < u->GetNumberOfValues(); ++k)
      {
        equal = u->GetComponent(k / u->GetNumberOfComponents(), k % u->GetNumberOfComponents()) ==
          v->GetComponent(k / v->GetNumberOfComponents(), k % v->GetNumberOfComponents());
      }
    }
    HOEMBED_CHECK(equal, "%s: outputs differ with ComputeDiagnostics off", what);
    HOEMBED_CHECK(a->GetCellData()->GetArray("VonMisesStress") &&
        a->GetFieldData()->GetArray("KineticEnergy") && a->GetFieldData()->GetArray("StrainEnergy"),
      "%s: diagnostics missing with ComputeDiagnostics on", what);
    HOEMBED_CHECK(!b->GetCellData()->GetArray("VonMisesStress") &&
        !b->GetFieldData()->GetArray("KineticEnergy") &&
        !b->GetFieldData()->GetArray("StrainEnergy") &&
        b->GetFieldData()->GetArray("SolverIterations"),
      "%s: wrong field/cell arrays with ComputeDiagnostics off", what);
  };
  const double t = 5 * on->GetTimeStep();
  on->UpdateTimeStep(t);
  off->UpdateTimeStep(t);
  same("offline");
  on->LiveModeOn();
  off->LiveModeOn();
  HOEMBED_CHECK(on->Step(3) && off->Step(3), "live steps failed");
  same("live");
  off->ComputeDiagnosticsOn();
  HOEMBED_CHECK(off->Step(0) && off->GetSimulationTime() == on->GetSimulationTime(),
    "switching ComputeDiagnostics restarted the live state");
}

int main(int, char*[])
{
  TestQuadrature();
  TestElementMatrices();
  TestPolar();
  TestStaticBeam();
  TestRigidRotation(2);
  TestRigidRotation(1);
  TestLargeDeflection();
  TestLargeTimeSteps();
  TestTimeProtocol();
  TestTet4VsTet10();
  TestErrors();
  TestLiveMode();
  TestDiagnosticsOff();
  return hoembed_test::Report("TestCorotationalFEMStepper");
}
