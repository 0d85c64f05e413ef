#include "hoembedCorotationalSolver.h"
#include "hoembedCorotationalSolverImpl.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace hoembed
{

CorotationalSolver::CorotationalSolver() : P(new Impl) {}

CorotationalSolver::~CorotationalSolver() = default;

namespace
{
// The steps of CorotationalSolver::Initialize.

// Per cell (in parallel): rest stiffness Ke (made exactly symmetric), centroid shape
// gradients G, the per-component mass block Me (consistent or HRZ-lumped) and the
// integral of each shape function times density fg; bad[e] = 1 for a cell of zero or
// negative volume.
void ComputeElementMatrices(CorotationalSolver::Impl& I, double young, double poisson,
  double density, bool lumpedMass, std::vector<double>& Me, std::vector<double>& fg,
  std::vector<char>& bad)
{
  const int N = I.N, D = I.D;
  const long long NC = I.NC;
  ParallelFor(NC, 64, // heavy per cell: worth threads early
    [&](vtkIdType begin, vtkIdType end) {
      std::vector<double> xe(3 * N), Mfull(D * D);
      const double c[3] = { 0.25, 0.25, 0.25 };
      for (vtkIdType e = begin; e < end; ++e)
      {
        for (int a = 0; a < N; ++a)
        {
          for (int i = 0; i < 3; ++i)
          {
            xe[3 * a + i] = I.X[3 * I.Conn[e * N + a] + i];
          }
        }
        const double vol = ElementStiffness(N, xe.data(), young, poisson, &I.Ke[e * D * D]);
        if (!(vol > 0.0) || !std::isfinite(vol))
        {
          bad[e] = 1;
          continue;
        }
        double* K = &I.Ke[e * D * D];
        for (int r = 0; r < D; ++r) // exactly symmetric (the products read it either way)
        {
          for (int q = r + 1; q < D; ++q)
          {
            const double m = 0.5 * (K[r * D + q] + K[q * D + r]);
            K[r * D + q] = K[q * D + r] = m;
          }
        }
        ShapeGradients(N, xe.data(), c, &I.G[e * N * 3]);
        if (lumpedMass)
        {
          std::vector<double> m(N);
          ElementLumpedMassHRZ(N, xe.data(), density, m.data());
          for (int a = 0; a < N; ++a)
          {
            Me[e * N * N + a * N + a] = m[a];
          }
        }
        else
        {
          ElementConsistentMass(N, xe.data(), density, Mfull.data());
          for (int a = 0; a < N; ++a)
          {
            for (int b = 0; b < N; ++b)
            {
              Me[e * N * N + a * N + b] = Mfull[(3 * a) * D + 3 * b];
            }
          }
        }
        const double gunit[3] = { 1.0, 0.0, 0.0 };
        std::vector<double> f(D);
        ElementBodyForce(N, xe.data(), density, gunit, f.data());
        for (int a = 0; a < N; ++a)
        {
          fg[e * N + a] = f[3 * a];
        }
      }
    });
}

// The sparsity pattern of the 3x3 node blocks (node adjacency) into I.A.
void BuildBlockPattern(CorotationalSolver::Impl& I)
{
  const int N = I.N;
  const long long NC = I.NC;
  // Sparsity pattern: node adjacency -> 3x3 blocks.
  std::vector<std::vector<int>> adj(I.NP);
  for (long long e = 0; e < NC; ++e)
  {
    for (int a = 0; a < N; ++a)
    {
      for (int b = 0; b < N; ++b)
      {
        adj[I.Conn[e * N + a]].push_back(I.Conn[e * N + b]);
      }
    }
  }
  std::vector<Eigen::Triplet<double, int>> trip;
  for (long long p = 0; p < I.NP; ++p)
  {
    auto& l = adj[p];
    std::sort(l.begin(), l.end());
    l.erase(std::unique(l.begin(), l.end()), l.end());
    if (l.empty())
    {
      l.push_back(static_cast<int>(p)); // isolated point: keep a diagonal entry
    }
    for (int q : l)
    {
      for (int i = 0; i < 3; ++i)
      {
        for (int j = 0; j < 3; ++j)
        {
          trip.emplace_back(static_cast<int>(3 * p + i), 3 * q + j, 0.0);
        }
      }
    }
  }
  I.A.resize(3 * I.NP, 3 * I.NP);
  I.A.setFromTriplets(trip.begin(), trip.end());
  I.A.makeCompressed();
}

// The global stiffness and mass values on I.A's pattern, the nodal body force, the node
// cell counts, the mass matrix M and its per-component form MN.
void AssembleGlobalMatrices(
  CorotationalSolver::Impl& I, const std::vector<double>& Me, const std::vector<double>& fg)
{
  const int N = I.N, D = I.D;
  const long long NC = I.NC;
  const int* outer = I.A.outerIndexPtr();
  const int* inner = I.A.innerIndexPtr();
  auto position = [&](int row, int col) {
    const int* b = inner + outer[row];
    const int* e = inner + outer[row + 1];
    return static_cast<int>(std::lower_bound(b, e, col) - inner);
  };
  I.MassValues.assign(I.A.nonZeros(), 0.0);
  I.StiffValues.assign(I.A.nonZeros(), 0.0);
  I.Gravity0.assign(3 * I.NP, 0.0);
  I.NodeCellCount.assign(I.NP, 0);
  for (long long e = 0; e < NC; ++e)
  {
    for (int a = 0; a < N; ++a)
    {
      const int pa = I.Conn[e * N + a];
      I.NodeCellCount[pa]++;
      I.Gravity0[3 * pa] += fg[e * N + a];
      for (int i = 0; i < 3; ++i)
      {
        for (int b = 0; b < N; ++b)
        {
          const int pb = I.Conn[e * N + b];
          const int row = 3 * pa + i;
          const int base = position(row, 3 * pb);
          for (int j = 0; j < 3; ++j)
          {
            const int idx = base + j;
            I.StiffValues[idx] += I.Ke[(e * D + 3 * a + i) * D + 3 * b + j];
            if (i == j)
            {
              I.MassValues[idx] += Me[e * N * N + a * N + b];
            }
          }
        }
      }
    }
  }
  I.M = I.A;
  std::copy(I.MassValues.begin(), I.MassValues.end(), I.M.valuePtr());
  {
    std::vector<Eigen::Triplet<double, int>> mt;
    mt.reserve(NC * N * N);
    for (long long e = 0; e < NC; ++e)
    {
      for (int a = 0; a < N; ++a)
      {
        for (int b = 0; b < N; ++b)
        {
          mt.emplace_back(I.Conn[e * N + a], I.Conn[e * N + b], Me[e * N * N + a * N + b]);
        }
      }
    }
    I.MN.resize(I.NP, I.NP);
    I.MN.setFromTriplets(mt.begin(), mt.end());
    I.MN.makeCompressed();
  }
}
} // namespace

bool CorotationalSolver::Initialize(int nodesPerCell, long long numberOfCells,
  const long long* connectivity, long long numberOfPoints, const double* restPoints, double young,
  double poisson, double density, bool lumpedMass, std::string& error, long long& badCell)
{
  Impl& I = *this->P;
  badCell = -1;
  // A new mesh: the ordering, the symbolic analyses and every factor are of the old
  // pattern (kept, a mesh of another size was read through the old maps out of bounds).
  if (I.Worker.joinable())
  {
    I.Worker.join();
  }
  I.Job.reset();
  I.Cur.reset();
  I.Base.reset();
  I.Spare.clear();
  I.Analyzed = false;
  I.HaveFactor = false;
  ++I.Generation;
  if (nodesPerCell != 4 && nodesPerCell != 10)
  {
    error = "only 4- or 10-node tetrahedra are supported";
    return false;
  }
  I.N = nodesPerCell;
  I.D = 3 * nodesPerCell;
  I.NC = numberOfCells;
  I.NP = numberOfPoints;
  I.Young = young;
  I.Poisson = poisson;
  I.Density = density;
  I.Conn.assign(connectivity, connectivity + numberOfCells * nodesPerCell);
  for (long long k = 0; k < numberOfCells * nodesPerCell; ++k)
  {
    if (connectivity[k] < 0 || connectivity[k] >= numberOfPoints)
    {
      badCell = k / nodesPerCell;
      error = "a cell references a point id out of range";
      return false;
    }
  }
  I.X.assign(restPoints, restPoints + 3 * numberOfPoints);
  const int N = I.N, D = I.D;
  const long long NC = I.NC;
  I.Ke.assign(NC * D * D, 0.0);
  I.G.assign(NC * N * 3, 0.0);
  I.Rot.assign(NC * 9, 0.0);
  std::vector<double> Me(NC * N * N, 0.0); // per-component mass block
  std::vector<double> fg(NC * N, 0.0);     // integral of N_a (times density)
  std::vector<char> bad(NC, 0);

  ComputeElementMatrices(I, young, poisson, density, lumpedMass, Me, fg, bad);
  for (long long e = 0; e < NC; ++e)
  {
    if (bad[e])
    {
      badCell = e;
      error = "a cell has zero or negative volume (det J <= 0 at a quadrature point)";
      return false;
    }
  }

  BuildBlockPattern(I);
  AssembleGlobalMatrices(I, Me, fg);
  I.BuildBlocks();
  I.Free.assign(3 * I.NP, 1);
  I.PrescribedMask.assign(I.NP, 0);
  I.Target.assign(3 * I.NP, 0.0);
  I.NumberPrescribed = 0;
  this->SetFixed(nullptr);
  I.FExt.assign(3 * I.NP, 0.0);
  I.NodeRot.assign(9 * I.NP, 0.0);
  I.HaveFactor = false;
  I.Mat = Material::Corotated;
  this->ResetState();
  this->ResetTimings();
  return true;
}

bool CorotationalSolver::Impl::UpdateFree()
{
  bool changed = false;
  for (long long p = 0; p < NP; ++p)
  {
    // points in no cell have no mass and no stiffness: keep them where they are
    const char f = (FixedMask[p] || PrescribedMask[p] || NodeCellCount[p] == 0) ? 0 : 1;
    changed = changed || Free[3 * p] != f;
    Free[3 * p] = Free[3 * p + 1] = Free[3 * p + 2] = f;
  }
  return changed;
}

void CorotationalSolver::SetFixed(const unsigned char* fixed)
{
  Impl& I = *this->P;
  I.FixedMask.assign(I.NP, 0);
  if (fixed)
  {
    for (long long p = 0; p < I.NP; ++p)
    {
      I.FixedMask[p] = fixed[p] ? 1 : 0;
    }
  }
  I.PrescribedMask.resize(I.NP, 0);
  I.UpdateFree();
  I.HaveFactor = false;
  I.Base.reset(); // made for other clamps
  ++I.Generation;
}

void CorotationalSolver::SetPrescribedMotion(const unsigned char* mask, const double* targets)
{
  Impl& I = *this->P;
  I.PrescribedMask.assign(I.NP, 0);
  I.Target.assign(3 * I.NP, 0.0);
  I.NumberPrescribed = 0;
  for (long long p = 0; mask && p < I.NP; ++p)
  {
    // a clamped point stays clamped; a point in no cell has nothing to move
    if (mask[p] && !I.FixedMask[p] && I.NodeCellCount[p] > 0)
    {
      I.PrescribedMask[p] = 1;
      I.NumberPrescribed++;
      for (int i = 0; i < 3; ++i)
      {
        I.Target[3 * p + i] = targets ? targets[3 * p + i] : 0.0;
      }
    }
  }
  if (I.UpdateFree() && !I.Background)
  {
    // Other DOFs leave (or join) the system: the factor no longer matches. The targets
    // alone do not change the matrix, so moving them keeps the factor. (With background
    // factorisation, the step compares the factor's free set with the system's.)
    I.HaveFactor = false;
  }
}

void CorotationalSolver::SetBackgroundFactorization(bool on, int lag)
{
  Impl& I = *this->P;
  I.Lag = std::max(0, lag);
  if (on == I.Background)
  {
    return;
  }
  I.Background = on;
  if (!on)
  {
    // back to the synchronous rules: a factor of another free set is not reused
    if (I.Worker.joinable())
    {
      I.Worker.join();
    }
    I.Recycle(std::move(I.Job));
    I.Job.reset();
    I.Base.reset();
    if (I.Cur && I.Cur->Free != I.Free)
    {
      I.HaveFactor = false;
    }
  }
}

void CorotationalSolver::SetPrescribedSpeedLimit(double speed)
{
  this->P->PrescribedSpeed = std::isfinite(speed) ? speed : 0.0;
}

long long CorotationalSolver::GetNumberOfPrescribedPoints() const
{
  return this->P->NumberPrescribed;
}

void CorotationalSolver::SetExternalForces(const double gravity[3], const double* nodalForces)
{
  Impl& I = *this->P;
  for (long long p = 0; p < I.NP; ++p)
  {
    for (int i = 0; i < 3; ++i)
    {
      // Gravity0 holds integral(N_a) * density in its x slot.
      I.FExt[3 * p + i] =
        I.Gravity0[3 * p] * gravity[i] + (nodalForces ? nodalForces[3 * p + i] : 0.0);
    }
  }
}

void CorotationalSolver::SetTimeStep(double dt)
{
  this->P->Dt = dt;
}

void CorotationalSolver::SetRayleighDamping(double alpha, double beta)
{
  this->P->Alpha = alpha;
  this->P->Beta = beta;
}

void CorotationalSolver::SetSolverControls(double tol, int maxIterations)
{
  this->P->Tol = tol;
  this->P->MaxIt = std::max(1, maxIterations);
}

void CorotationalSolver::ResetState()
{
  Impl& I = *this->P;
  I.x = I.X;
  I.RotationsValid = false;
  I.RestartPreconditioner();
  I.v.assign(3 * I.NP, 0.0);
  I.dv.assign(3 * I.NP, 0.0);
}

void CorotationalSolver::SetState(const double* positions, const double* velocities)
{
  Impl& I = *this->P;
  if (positions)
  {
    I.x.assign(positions, positions + 3 * I.NP);
  }
  I.RotationsValid = false;
  I.RestartPreconditioner();
  if (velocities)
  {
    I.v.assign(velocities, velocities + 3 * I.NP);
  }
  I.dv.assign(3 * I.NP, 0.0);
}

bool CorotationalSolver::Step()
{
  Impl& I = *this->P;
  if (I.Mat != Material::Corotated)
  {
    return I.HyperStep();
  }
  const double dt = I.Dt;
  const double cM = I.StaticMode ? 0.0 : 1.0 + dt * I.Alpha;
  const double cK = dt * I.Beta + dt * dt;
  const double vScale = dt + I.Beta;

  // Prescribed DOFs (see the header): they are put on their targets first, so that the
  // rotations and forces are evaluated (the step linearised) at x* = (x_free, targets),
  // not at a configuration the prescribed motion has not reached yet: a large drag in one
  // step then distorts only what it really distorts. Their velocity over the step is
  // w = (target - x) / dt. In the forces, evaluated at x* + (dt + beta) v, they carry
  // u = beta w / (dt + beta) (their displacement is already in x*, only the stiffness
  // damping beta K w is left); delta = M-weighted terms the forces do not carry (inertia
  // w - v_old, mass damping dt alpha (w - u)), moved to the right-hand side below.
  const bool prescribed = I.NumberPrescribed > 0 && !I.StaticMode;
  std::vector<double> delta, w;
  if (prescribed)
  {
    delta.assign(3 * I.NP, 0.0);
    w.assign(3 * I.NP, 0.0);
  }
  std::vector<double> reach; // where the prescribed points get in this step
  if (prescribed)
  {
    reach.assign(3 * I.NP, 0.0);
    const double limit = I.PrescribedSpeed * dt;
    for (long long p = 0; p < I.NP; ++p)
    {
      if (I.PrescribedMask[p])
      {
        double d[3], n = 0.0;
        for (int i = 0; i < 3; ++i)
        {
          d[i] = I.X[3 * p + i] + I.Target[3 * p + i] - I.x[3 * p + i];
          n += d[i] * d[i];
        }
        n = std::sqrt(n);
        const bool capped = I.PrescribedSpeed > 0.0 && n > limit;
        for (int i = 0; i < 3; ++i)
        {
          reach[3 * p + i] =
            capped ? I.x[3 * p + i] + d[i] * (limit / n) : I.X[3 * p + i] + I.Target[3 * p + i];
        }
      }
    }
  }
  for (long long k = 0; k < 3 * I.NP; ++k)
  {
    if (!I.Free[k])
    {
      if (prescribed && I.PrescribedMask[k / 3])
      {
        const double target = reach[k];
        w[k] = (target - I.x[k]) / dt;
        const double u = I.Beta / (dt + I.Beta) * w[k];
        delta[k] = (w[k] - I.v[k]) + dt * I.Alpha * (w[k] - u);
        I.x[k] = target;
        I.v[k] = u;
      }
      else
      {
        I.v[k] = 0.0; // clamped nodes do not move (static increments: held nodes too)
      }
    }
  }
  auto t0 = Clock::now();
  I.ComputeRotations();
  auto t1 = Clock::now();

  I.CM = cM;
  I.CK = cK;
  // S = sum_e R_e K_e R_e^T and the elastic forces -R_e K_e (R_e^T (x + (dt+beta) v) - X)
  I.VScale = vScale;
  if (I.Assembled())
  {
    I.AssembleS(vScale);
  }
  else
  {
    I.ElementForces(vScale);
  }

  Eigen::VectorXd rhs = Eigen::Map<const Eigen::VectorXd>(I.FExt.data(), 3 * I.NP);
  if (I.Alpha != 0.0)
  {
    I.MassApply(I.v.data(), -I.Alpha, rhs.data());
  }
  rhs += Eigen::Map<const Eigen::VectorXd>(I.FInt.data(), 3 * I.NP);
  rhs *= dt;
  if (prescribed)
  {
    I.MassApply(delta.data(), -1.0, rhs.data()); // rows of the free DOFs: -M_fc delta
  }
  I.Mask(rhs);
  auto t2 = Clock::now();

  // Preconditioner: the unrotated factor (first step, new dt / damping / clamps), then
  // the factor of a recent system matrix, refreshed when the CG iterations since the
  // last factorisation exceed an estimate of its cost (RefactorBudget) and the
  // iterations per step have grown by half (so that it pays for itself).
  if (I.Background && !I.StaticMode)
  {
    I.BackgroundPreconditioner(cM, cK);
  }
  else if (!I.HaveFactor || cM != I.Cur->CM || cK != I.Cur->CK)
  {
    I.Factor(cM, cK);
  }
  else if (I.LastIt > std::max(2, (3 * I.ItAfterFactor) / 2) &&
    I.IterationsSinceFactor > I.RefactorBudget())
  {
    auto ta = Clock::now();
    I.AssembleA(cM, cK);
    const double assembly = Seconds(ta, Clock::now());
    I.T.Assembly += assembly;
    I.T.Solve -= assembly; // counted in the solve phase below; keep it in assembly
    I.FactorMatrix(I.A, false, cM, cK);
  }
  I.UpdateRelativeRotations();
  double load = 0.0;
  for (long long k = 0; k < 3 * I.NP; ++k)
  {
    load += I.Free[k] ? I.FExt[k] * I.FExt[k] : 0.0;
  }
  I.LoadFloor = dt * std::sqrt(load);
  auto ts = Clock::now();
  Eigen::Map<Eigen::VectorXd> dv(I.dv.data(), 3 * I.NP);
  Eigen::VectorXd sol = dv, r0;
  const bool guessed = I.InitialGuess(rhs, sol, r0);
  I.LastIt = I.PCG(rhs, sol, I.Tol, guessed ? &r0 : nullptr);
  if (I.JustFactored)
  {
    I.ItAfterFactor = I.LastIt;
    I.JustFactored = false;
  }
  dv = sol;
  if (!I.StaticMode && I.GuessDepth() > 0)
  {
    I.History.insert(I.History.begin(), sol);
    if (static_cast<int>(I.History.size()) > I.GuessDepth())
    {
      I.History.pop_back();
    }
  }
  I.StepCount++;
  I.SolveSinceFactor += Seconds(ts, Clock::now());
  I.IterationsSinceFactor += I.LastIt;
  bool finite = true;
  I.RotationsValid = false;
  for (long long k = 0; k < 3 * I.NP; ++k)
  {
    I.v[k] += I.dv[k];
    I.x[k] += dt * I.v[k];
    if (prescribed && I.PrescribedMask[k / 3])
    {
      I.v[k] = w[k];
      I.x[k] = reach[k]; // on the target exactly (unless the speed limit holds it back)
    }
    if (!std::isfinite(I.x[k]) || !std::isfinite(I.v[k]))
    {
      finite = false;
    }
  }
  auto t3 = Clock::now();
  I.T.Rotation += Seconds(t0, t1);
  I.T.Assembly += Seconds(t1, t2);
  I.T.Solve += Seconds(t2, t3);
  I.T.Steps++;
  I.T.Iterations += I.LastIt;
  return finite;
}

bool CorotationalSolver::SolveStatic(int maxIterations, double tolerance, std::string& error)
{
  Impl& I = *this->P;
  bool anyFixed = false;
  for (char f : I.Free)
  {
    anyFixed = anyFixed || !f;
  }
  if (!anyFixed)
  {
    error = "the static solve needs clamped nodes (a free body has no equilibrium)";
    return false;
  }
  if (I.Mat != Material::Corotated)
  {
    return I.HyperStatic(I.NewtonMaxIt, I.NewtonTol, error);
  }
  for (long long k = 0; k < 3 * I.NP && I.NumberPrescribed > 0; ++k)
  {
    if (I.PrescribedMask[k / 3])
    {
      I.x[k] = I.X[k] + I.Target[k]; // held on their targets
    }
  }
  if (!I.Factor(0.0, 1.0))
  {
    error = "the clamped stiffness matrix is singular (clamp more nodes)";
    return false;
  }
  // No load on the free nodes and the held nodes at rest: the equilibrium is the rest
  // state itself. Iterating would only chase round-off (x - X has no digits for the
  // relative convergence test), so it is returned as it is.
  bool loaded = false;
  for (long long k = 0; k < 3 * I.NP && !loaded; ++k)
  {
    loaded = I.Free[k] ? I.FExt[k] != 0.0 : I.x[k] != I.X[k];
  }
  if (!loaded)
  {
    std::copy(I.X.begin(), I.X.end(), I.x.begin());
    std::fill(I.v.begin(), I.v.end(), 0.0);
    std::fill(I.dv.begin(), I.dv.end(), 0.0);
    I.HaveFactor = false;
    return true;
  }
  const double saveDt = I.Dt, saveA = I.Alpha, saveB = I.Beta;
  // A static increment is an implicit step with dt = 1, no mass, from zero velocity:
  // K~ dx = f_ext - f_int(x) (Step with a zero mass coefficient; the factor of K just
  // computed is the one for cM = 0, cK = 1).
  I.StaticMode = true;
  I.Dt = 1.0;
  I.Alpha = 0.0;
  I.Beta = 0.0;
  const double saveTol = I.Tol;
  I.Tol = std::min(I.Tol, 1e-13);
  bool ok = false;
  double previous = -1.0;
  for (int it = 0; it < maxIterations; ++it)
  {
    std::fill(I.v.begin(), I.v.end(), 0.0);
    std::fill(I.dv.begin(), I.dv.end(), 0.0);
    if (!this->Step())
    {
      error = "the static solve produced a non-finite state";
      break;
    }
    // increment (exact: dv of the step) against the displacement so far
    double dn = 0.0, un = 0.0, xn = 0.0;
    for (long long k = 0; k < 3 * I.NP; ++k)
    {
      dn += I.dv[k] * I.dv[k];
      un += (I.x[k] - I.X[k]) * (I.x[k] - I.X[k]);
      xn += I.x[k] * I.x[k];
    }
    dn = std::sqrt(dn);
    un = std::sqrt(un);
    xn = std::sqrt(xn);
    if (dn <= tolerance * un || un == 0.0)
    {
      ok = true;
      break;
    }
    // Stagnation at round-off level: the state is stored as positions x, so x - X carries
    // an absolute error of a few ulps of |x|, and for a stiff body whose displacement is
    // 1e-9 of its size that alone is 1e-7 of the displacement (a bar at E = 1e15 under
    // gravity stalled there and was reported as "load too large").
    if (it >= 3 && previous >= 0.0 && dn >= 0.5 * previous &&
      dn <= 1e-7 * un + 64 * std::numeric_limits<double>::epsilon() * xn)
    {
      ok = true;
      break;
    }
    previous = dn;
  }
  if (!ok && error.empty())
  {
    error = "the static solve did not converge (load too large for the co-rotated iteration)";
  }
  I.StaticMode = false;
  I.Dt = saveDt;
  I.Alpha = saveA;
  I.Beta = saveB;
  I.Tol = saveTol;
  I.HaveFactor = false;
  std::fill(I.v.begin(), I.v.end(), 0.0);
  std::fill(I.dv.begin(), I.dv.end(), 0.0);
  return ok;
}

long long CorotationalSolver::GetNumberOfPoints() const
{
  return this->P->NP;
}

long long CorotationalSolver::GetNumberOfCells() const
{
  return this->P->NC;
}

const double* CorotationalSolver::GetPositions() const
{
  return this->P->x.data();
}

const double* CorotationalSolver::GetVelocities() const
{
  return this->P->v.data();
}

const double* CorotationalSolver::GetRestPositions() const
{
  return this->P->X.data();
}

void CorotationalSolver::ComputeNodalRotations(double* rotations) const
{
  Impl& I = *this->P;
  I.EnsureRotations();
  for (long long p = 0; p < I.NP; ++p)
  {
    PolarRotation(&I.NodeRot[9 * p], rotations + 9 * p);
  }
}

void CorotationalSolver::ComputeVonMises(double* stress) const
{
  Impl& I = *this->P;
  if (I.Mat != Material::Corotated)
  {
    I.HyperVonMises(stress);
    return;
  }
  I.EnsureRotations();
  const int N = I.N;
  ParallelFor(I.NC, ParallelCells, [&](vtkIdType begin, vtkIdType end) {
    double Xe[30], ue[30];
    const double c[3] = { 0.25, 0.25, 0.25 };
    for (vtkIdType e = begin; e < end; ++e)
    {
      const Mat3 R = Eigen::Map<const Mat3>(&I.Rot[e * 9]);
      for (int a = 0; a < N; ++a)
      {
        const int pa = I.Conn[e * N + a];
        const Eigen::Vector3d y(I.x[3 * pa], I.x[3 * pa + 1], I.x[3 * pa + 2]);
        const Eigen::Vector3d l = R.transpose() * y;
        for (int i = 0; i < 3; ++i)
        {
          Xe[3 * a + i] = I.X[3 * pa + i];
          ue[3 * a + i] = l[i] - Xe[3 * a + i];
        }
      }
      // the co-rotated displacement carries an arbitrary translation: harmless, the
      // stress only sees its gradient.
      stress[e] = VonMisesStress(N, Xe, ue, c, I.Young, I.Poisson);
    }
  });
}

double CorotationalSolver::KineticEnergy() const
{
  const Impl& I = *this->P;
  Eigen::Map<const Eigen::VectorXd> vv(I.v.data(), 3 * I.NP);
  return 0.5 * vv.dot(I.M * vv);
}

double CorotationalSolver::StrainEnergy() const
{
  Impl& I = *this->P;
  if (I.Mat != Material::Corotated)
  {
    return I.HyperEnergy(I.x.data());
  }
  I.EnsureRotations();
  const int N = I.N, D = I.D;
  double energy = 0.0;
  std::vector<double> ue(D);
  for (long long e = 0; e < I.NC; ++e)
  {
    const Mat3 R = Eigen::Map<const Mat3>(&I.Rot[e * 9]);
    for (int a = 0; a < N; ++a)
    {
      const int pa = I.Conn[e * N + a];
      const Eigen::Vector3d l =
        R.transpose() * Eigen::Vector3d(I.x[3 * pa], I.x[3 * pa + 1], I.x[3 * pa + 2]);
      for (int i = 0; i < 3; ++i)
      {
        ue[3 * a + i] = l[i] - I.X[3 * pa + i];
      }
    }
    const double* K = &I.Ke[e * D * D];
    for (int r = 0; r < D; ++r)
    {
      double s = 0.0;
      for (int c = 0; c < D; ++c)
      {
        s += K[r * D + c] * ue[c];
      }
      energy += 0.5 * ue[r] * s;
    }
  }
  return energy;
}

double CorotationalSolver::TotalMass() const
{
  const Impl& I = *this->P;
  double m = 0.0;
  for (long long p = 0; p < I.NP; ++p)
  {
    m += I.Gravity0[3 * p];
  }
  return m;
}

const CorotationalSolver::Timings& CorotationalSolver::GetTimings() const
{
  return this->P->T;
}

CorotationalSolver::Traffic CorotationalSolver::GetTraffic() const
{
  const Impl& I = *this->P;
  Traffic t;
  const long long ke = static_cast<long long>(I.Ke.size()) * 8;
  const long long mass = static_cast<long long>(I.MN.nonZeros()) * (8 + 4) + (I.NP + 1) * 4;
  if (I.Assembled())
  {
    const long long blocks = static_cast<long long>(I.S.size()) * 8;
    t.ProductBytes = blocks + mass;
    t.AssemblyBytes = ke + blocks;
  }
  else
  {
    t.ProductBytes = ke + mass;
  }
  if (I.Cur)
  {
    const auto factor = [](const auto& f) {
      // Val and Row read by the forward and the backward solve; the diagonal once each
      return 2 *
        (static_cast<long long>(f.Val.size()) * sizeof(f.Val[0]) +
          static_cast<long long>(f.Row.size()) * 4) +
        2 * static_cast<long long>(f.DiagInv.size()) * 8;
    };
    t.PreconditionerBytes = !I.Large() ? factor(I.Cur->SmallBlocks)
      : I.Cur->UseLargeBlocks          ? factor(I.Cur->LargeBlocks)
                                       : 0; // CHOLMOD's own solve: not estimated
  }
  t.GuessProducts = I.GuessDepth();
  return t;
}

void CorotationalSolver::ResetTimings()
{
  this->P->T = Timings();
}

int CorotationalSolver::GetLastIterations() const
{
  return this->P->LastIt;
}

double CorotationalSolver::GetLastRelativeResidual() const
{
  return this->P->LastRes;
}
} // namespace hoembed
