// hoembed::CorotationalSolver's background factorisation (SetBackgroundFactorization): a
// grab or release of prescribed nodes is stepped with a stand-in preconditioner while a
// worker thread factorises the new system. Every step must still be the solution of the
// step's own constrained system: checked against the same sequence solved with the
// synchronous refactorisation (each step's CG converged to 1e-10, so the two runs differ
// only by the CG's tolerance), for several lags (the new factor taken 1 or 3 steps after
// it was asked for, never, or whenever the thread is done), through a grab-release-grab
// in quick succession (before any new factor is ready), with the option switched off
// half-way, and with the solver destroyed while its worker runs (leaks and races: this
// test runs under ASan + UBSan in `make test-sanitize`). The mesh has more than 6000 DOF,
// so the large (CHOLMOD, when built with it) factor is the one computed by the worker.
#include "hoembedCorotationalSolver.h"
#include "hoembedTestUtilities.h"

#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

namespace
{
using hoembed::CorotationalSolver;

struct Beam
{
  std::vector<long long> Conn;
  std::vector<double> Rest;
  long long NC = 0, NP = 0;
  std::vector<unsigned char> Clamp, Tip, Mid;
};

Beam MakeBeam()
{
  // 4 x 1 x 0.75, 20 x 4 x 3 cubes: 1440 tet10, 2583 nodes (7749 DOF)
  auto mesh = hoembed_test::MakeBoxTetMesh(20, 4, 3, 4.0, 1.0, 0.75, 2);
  Beam b;
  int npc = 0;
  for (std::int64_t id : hoembed_test::MeshConnectivity(mesh, npc))
  {
    b.Conn.push_back(id);
  }
  b.Rest = hoembed_test::PointsOf(mesh);
  b.NC = mesh->GetNumberOfCells();
  b.NP = mesh->GetNumberOfPoints();
  b.Clamp.assign(b.NP, 0);
  b.Tip.assign(b.NP, 0);
  b.Mid.assign(b.NP, 0);
  for (long long p = 0; p < b.NP; ++p)
  {
    const double* x = &b.Rest[3 * p];
    b.Clamp[p] = x[0] <= 1e-9;
    b.Tip[p] = x[0] >= 4.0 - 1e-9;
    b.Mid[p] = std::abs(x[0] - 2.0) < 0.15 && x[2] >= 0.75 - 1e-9;
  }
  return b;
}

// The grab schedule: step k -> 0 none, 1 tip, 2 mid. A grab of the tip, a release, then
// tip, none, mid on three consecutive steps (each changes the prescribed set before any
// new factor can be ready with a lag of 3), then a release.
int Grabbed(int k)
{
  if (k >= 5 && k < 15)
  {
    return 1;
  }
  if (k == 20)
  {
    return 1;
  }
  if (k >= 22 && k < 30)
  {
    return 2;
  }
  return 0;
}

struct Record
{
  std::vector<std::vector<double>> X; // positions after each step
  std::vector<int> Iterations;
  long long Factorizations = 0; // synchronous
  long long Background = 0;     // taken from the worker
};

// mode: -1 synchronous; else background with that lag. switchOffAt: the step from which
// the background is switched off again (-1: never).
Record Run(const Beam& b, int mode, int switchOffAt = -1, int steps = 32)
{
  CorotationalSolver s;
  std::string error;
  long long badCell = -1;
  Record r;
  if (!s.Initialize(
        10, b.NC, b.Conn.data(), b.NP, b.Rest.data(), 2e5, 0.45, 1000.0, false, error, badCell))
  {
    HOEMBED_CHECK(false, "Initialize: %s", error.c_str());
    return r;
  }
  s.SetFixed(b.Clamp.data());
  const double g[3] = { 0.0, 0.0, -9.81 };
  s.SetExternalForces(g, nullptr);
  s.SetTimeStep(0.01);
  s.SetRayleighDamping(1.0, 0.005);
  s.SetSolverControls(1e-10, 2000);
  s.ResetState();
  s.SetBackgroundFactorization(mode >= 0, std::max(0, mode));
  std::vector<double> target(3 * b.NP, 0.0);
  for (int k = 0; k < steps; ++k)
  {
    if (k == switchOffAt)
    {
      s.SetBackgroundFactorization(false);
    }
    const int which = Grabbed(k);
    const std::vector<unsigned char>& mask = which == 1 ? b.Tip : b.Mid;
    // targets: a fixed function of the step (not of the state), lifting and twisting
    for (long long p = 0; p < b.NP; ++p)
    {
      const double* x = &b.Rest[3 * p];
      target[3 * p] = 0.0;
      target[3 * p + 1] = 0.002 * k * (x[2] - 0.375);
      target[3 * p + 2] = 0.004 * k;
    }
    s.SetPrescribedMotion(which ? mask.data() : nullptr, target.data());
    s.ResetTimings();
    HOEMBED_CHECK(s.Step(), "mode %d: non-finite state at step %d", mode, k);
    const auto& t = s.GetTimings();
    r.Factorizations += t.Factorizations;
    r.Background += t.BackgroundFactorizations;
    r.Iterations.push_back(s.GetLastIterations());
    // converged to the tolerance, not stopped by the iteration cap
    HOEMBED_CHECK(s.GetLastIterations() < 2000, "mode %d step %d: CG at its cap", mode, k);
    r.X.emplace_back(s.GetPositions(), s.GetPositions() + 3 * b.NP);
  }
  return r;
}

double RelativeDifference(
  const Beam& b, const std::vector<double>& x, const std::vector<double>& ref)
{
  double d = 0.0, u = 0.0;
  for (size_t k = 0; k < x.size(); ++k)
  {
    d += (x[k] - ref[k]) * (x[k] - ref[k]);
    u += (ref[k] - b.Rest[k]) * (ref[k] - b.Rest[k]);
  }
  return std::sqrt(d / std::max(u, 1e-300));
}

void CompareWithSynchronous(const Beam& b, const Record& sync, const Record& r, const char* what)
{
  HOEMBED_CHECK(r.X.size() == sync.X.size(), "%s: %zu steps", what, r.X.size());
  double worst = 0.0;
  for (size_t k = 0; k < std::min(r.X.size(), sync.X.size()); ++k)
  {
    const double d = RelativeDifference(b, r.X[k], sync.X[k]);
    worst = std::max(worst, d);
    HOEMBED_CHECK(d < 1e-6, "%s: step %zu differs from the synchronous run by %g", what, k, d);
  }
  std::printf("%s: largest relative difference from the synchronous run %.2e, %lld "
              "synchronous and %lld background factorisations\n",
    what, worst, r.Factorizations, r.Background);
}

void TestBackgroundFactorization()
{
  const Beam b = MakeBeam();
  HOEMBED_CHECK(3 * b.NP >= 6000, "the beam should use the large factor (%lld DOF)", 3 * b.NP);
  const Record sync = Run(b, -1);
  // the synchronous run refactorises at the first step and at each change of the set
  // (6 changes), plus whatever its refresh rule adds
  HOEMBED_CHECK(sync.Factorizations >= 7, "synchronous: %lld factorisations", sync.Factorizations);
  HOEMBED_CHECK(sync.Background == 0, "synchronous: background factors taken");
  double lifted = 0.0;
  for (long long p = 0; p < b.NP; ++p)
  {
    lifted = std::max(lifted, sync.X[14][3 * p + 2] - b.Rest[3 * p + 2]);
  }
  HOEMBED_CHECK(lifted > 0.05, "the grab did not lift the tip (%g)", lifted);

  Record lag3;
  for (int lag : { 1, 3, 1000 })
  {
    const std::string what = "lag " + std::to_string(lag);
    const Record r = Run(b, lag);
    if (lag == 3)
    {
      lag3 = r;
    }
    CompareWithSynchronous(b, sync, r, what.c_str());
    // only the first step factorises on the calling thread: every grab and release is
    // stepped with a stand-in while the worker runs
    HOEMBED_CHECK(
      r.Factorizations == 1, "%s: %lld synchronous factorisations", what.c_str(), r.Factorizations);
    if (lag < 1000)
    {
      HOEMBED_CHECK(
        r.Background >= 2, "%s: %lld background factors taken", what.c_str(), r.Background);
    }
    else
    {
      HOEMBED_CHECK(
        r.Background == 0, "%s: %lld background factors taken", what.c_str(), r.Background);
    }
  }
  // with a lag the run does not depend on timing: bitwise the same twice
  const Record& a = lag3;
  const Record c = Run(b, 3);
  bool same = a.X.size() == c.X.size();
  for (size_t k = 0; same && k < a.X.size(); ++k)
  {
    same = std::memcmp(a.X[k].data(), c.X[k].data(), a.X[k].size() * sizeof(double)) == 0;
  }
  HOEMBED_CHECK(same, "two runs with lag 3 differ");
  HOEMBED_CHECK(a.Iterations == c.Iterations, "two runs with lag 3 took other iterations");

  // whenever the worker is done (timing-dependent): the same solutions to tolerance
  CompareWithSynchronous(b, sync, Run(b, 0), "lag 0");
  // switched off while a stand-in serves (step 23: mid grabbed, its factor not ready)
  const Record off = Run(b, 3, 23);
  CompareWithSynchronous(b, sync, off, "switched off at step 23");
  HOEMBED_CHECK(
    off.Factorizations >= 2, "switched off: %lld synchronous factorisations", off.Factorizations);

  // destroyed (and switched off) with the worker running: joined, nothing leaks
  Run(b, 0, -1, 6);     // the grab's job just started
  Run(b, 0, -1, 23);    // a stale job may still run
  Run(b, 1000, 23, 24); // switched off while the mid grab's job runs
}
} // namespace

int main(int, char*[])
{
  TestBackgroundFactorization();
  return hoembed_test::Report("TestCorotationalSolver");
}
