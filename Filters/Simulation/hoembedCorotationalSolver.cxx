#include "hoembedCorotationalSolver.h"

#include "hoembedTetElementMatrices.h"

#include "vtkSMPTools.h"

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#ifdef HOEMBED_HAVE_CHOLMOD
#include <Eigen/CholmodSupport>
#endif

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <vector>

namespace hoembed
{
namespace
{
using Clock = std::chrono::steady_clock;
using RowMat = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;
using ColMat = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
using Mat3 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;
// Small systems: Eigen's simplicial factor (low per-solve overhead). Large systems:
// CHOLMOD's supernodal factor when available (much less time to factorise).
using SmallFactorization = Eigen::SimplicialLLT<ColMat, Eigen::Lower, Eigen::AMDOrdering<int>>;
#ifdef HOEMBED_HAVE_CHOLMOD
using LargeFactorization = Eigen::CholmodSupernodalLLT<ColMat, Eigen::Lower>;
#else
using LargeFactorization = SmallFactorization;
#endif
constexpr long long LargeSystem = 6000; // DOF from which the large factorisation is used

double Seconds(Clock::time_point a, Clock::time_point b)
{
  return std::chrono::duration<double>(b - a).count();
}

// Loops shorter than `minParallel` run on the calling thread: for meshes of a few hundred
// cells the thread hand-off costs more than it saves (measured 2x slower steps on the
// shared 2-core machine for a 168-cell mesh).
template <typename F>
void ParallelFor(vtkIdType n, vtkIdType minParallel, F&& f)
{
  if (n < minParallel)
  {
    f(0, n);
  }
  else
  {
    vtkSMPTools::For(0, n, f);
  }
}
constexpr vtkIdType ParallelCells = 1000;
constexpr vtkIdType ParallelValues = 1000000;
} // namespace

struct CorotationalSolver::Impl
{
  int N = 0;  // nodes per cell
  int D = 0;  // 3 N
  long long NC = 0, NP = 0;
  std::vector<int> Conn;
  std::vector<double> X, x, v, dv;
  std::vector<double> Ke;     // NC * D * D rest stiffness
  std::vector<double> G;      // NC * N * 3 centroid shape gradients
  std::vector<double> Rot;    // NC * 9 element rotations
  std::vector<double> NodeRot; // NP * 9 (averaged, not projected) for the preconditioner
  std::vector<double> EB;     // NC * D * D rotated element matrices
  std::vector<double> EF;     // NC * D element right-hand sides
  std::vector<int> Scatter;   // NC * D * D value index in the CSR pattern
  std::vector<int> GatherOffsets, GatherIndex; // per CSR value: element entries summed into it
  std::vector<double> MassValues, StiffValues; // rest M and K on the pattern
  std::vector<double> Gravity0; // consistent body force for unit density * g / density
  std::vector<double> FExt;
  std::vector<char> Free; // 3 NP
  std::vector<int> NodeCellCount;
  double Young = 1, Poisson = 0.3, Density = 1;
  double Dt = 0.01, Alpha = 0, Beta = 0;
  double Tol = 1e-8;
  int MaxIt = 500;
  RowMat A, M;
  // preconditioner
  SmallFactorization SmallLLT;
  LargeFactorization LargeLLT;
  bool Large() const { return 3 * NP >= LargeSystem; }
  bool FactorOK() const
  {
    return (Large() ? LargeLLT.info() : SmallLLT.info()) == Eigen::Success;
  }
  bool HaveFactor = false;
  bool Analyzed = false;
  int ItAfterFactor = 0;
  bool JustFactored = false;
  double FactorCM = -1, FactorCK = -1;
  double FactorSeconds = 0.0;   // cost of the last factorisation
  double SolveSinceFactor = 0.0; // CG seconds spent with it since (reported only)
  long long IterationsSinceFactor = 0;
  // Deterministic estimate of a factorisation's cost in preconditioned CG iterations
  // (3D meshes: factor ~ n^2, solve ~ n^4/3 flops; calibrated on this machine: ~30 at
  // 1.1k DOF, ~150 at 15k DOF). Time-based rules made results depend on machine load.
  double RefactorBudget() const
  {
    const double b = 0.25 * std::pow(static_cast<double>(3 * NP), 2.0 / 3.0);
    return std::min(500.0, std::max(10.0, b));
  }
  std::vector<double> FactorQ;  // NP * 9 nodal rotations baked into the factor
  std::vector<double> RelRot;   // NP * 9: NodeRot * FactorQ^T (preconditioner rotation)
  double LoadFloor = 0.0;       // |dt f_ext|: residual scale when the system is at rest
  Timings T;
  int LastIt = 0;
  double LastRes = 0;

  void ComputeRotations();
  bool RotationsValid = false; // Rot / NodeRot match x
  // A restart from a new state starts from the unrotated factor again, so that the same
  // state and settings always give bitwise the same trajectory.
  void RestartPreconditioner()
  {
    HaveFactor = false;
    LastIt = 0;
    ItAfterFactor = 0;
    IterationsSinceFactor = 0;
  }
  void EnsureRotations()
  {
    if (!RotationsValid)
    {
      ComputeRotations();
    }
  }
  void ApplyPrec(const Eigen::VectorXd& r, Eigen::VectorXd& z) const;
  bool Factor(double cM, double cK);
  bool FactorMatrix(const RowMat& source, bool rest, double cM, double cK);
  void UpdateRelativeRotations();
  int PCG(const Eigen::VectorXd& b, Eigen::VectorXd& xs, double tol);
  // y = CM M p + CK sum_e R_e K_e R_e^T p_e (matrix-free: element by element)
  void MatVec(const Eigen::VectorXd& p, Eigen::VectorXd& y);
  // y += s * M p with the node-level (scalar) mass matrix
  void MassApply(const double* p, double s, double* y) const;
  // assemble A = cM M + cK sum R K R^T (only needed to refresh the factorisation)
  void AssembleA(double cM, double cK);
  double CM = 1.0, CK = 0.0;
  bool StaticMode = false; // steps without mass (static increments)
  RowMat MN;              // NP x NP scalar mass matrix
  std::vector<double> EW; // NC * D element matvec results
  void Mask(Eigen::VectorXd& r) const
  {
    for (long long k = 0; k < 3 * NP; ++k)
    {
      if (!Free[k])
      {
        r[k] = 0.0;
      }
    }
  }
};

CorotationalSolver::CorotationalSolver()
  : P(new Impl)
{
}

CorotationalSolver::~CorotationalSolver() = default;

bool CorotationalSolver::Initialize(int nodesPerCell, long long numberOfCells,
  const long long* connectivity, long long numberOfPoints, const double* restPoints,
  double young, double poisson, double density, bool lumpedMass, std::string& error,
  long long& badCell)
{
  Impl& I = *this->P;
  badCell = -1;
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
  I.EB.assign(NC * D * D, 0.0);
  I.EF.assign(NC * D, 0.0);
  std::vector<double> Me(NC * N * N, 0.0); // per-component mass block
  std::vector<double> fg(NC * N, 0.0);    // integral of N_a (times density)
  std::vector<char> bad(NC, 0);

  ParallelFor(NC, 64, // heavy per cell: worth threads early
    [&](vtkIdType begin, vtkIdType end)
    {
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
  for (long long e = 0; e < NC; ++e)
  {
    if (bad[e])
    {
      badCell = e;
      error = "a cell has zero or negative volume (det J <= 0 at a quadrature point)";
      return false;
    }
  }

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
  const int* outer = I.A.outerIndexPtr();
  const int* inner = I.A.innerIndexPtr();
  auto position = [&](int row, int col)
  {
    const int* b = inner + outer[row];
    const int* e = inner + outer[row + 1];
    return static_cast<int>(std::lower_bound(b, e, col) - inner);
  };
  I.Scatter.assign(NC * D * D, 0);
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
            I.Scatter[(e * D + 3 * a + i) * D + 3 * b + j] = idx;
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
  I.EW.assign(NC * D, 0.0);
  // Transpose of the scatter map, so that the assembly runs in parallel over CSR values.
  const long long nnz = I.A.nonZeros();
  I.GatherOffsets.assign(nnz + 1, 0);
  for (int idx : I.Scatter)
  {
    I.GatherOffsets[idx + 1]++;
  }
  for (long long k = 0; k < nnz; ++k)
  {
    I.GatherOffsets[k + 1] += I.GatherOffsets[k];
  }
  I.GatherIndex.assign(I.Scatter.size(), 0);
  {
    std::vector<int> fill(I.GatherOffsets.begin(), I.GatherOffsets.end() - 1);
    for (size_t j = 0; j < I.Scatter.size(); ++j)
    {
      I.GatherIndex[fill[I.Scatter[j]]++] = static_cast<int>(j);
    }
  }
  I.Free.assign(3 * I.NP, 1);
  this->SetFixed(nullptr);
  I.FExt.assign(3 * I.NP, 0.0);
  I.NodeRot.assign(9 * I.NP, 0.0);
  I.HaveFactor = false;
  this->ResetState();
  this->ResetTimings();
  return true;
}

void CorotationalSolver::SetFixed(const unsigned char* fixed)
{
  Impl& I = *this->P;
  for (long long p = 0; p < I.NP; ++p)
  {
    // points in no cell have no mass and no stiffness: keep them where they are
    const char f = ((fixed && fixed[p]) || I.NodeCellCount[p] == 0) ? 0 : 1;
    I.Free[3 * p] = I.Free[3 * p + 1] = I.Free[3 * p + 2] = f;
  }
  I.HaveFactor = false;
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

void CorotationalSolver::Impl::ComputeRotations()
{
  RotationsValid = true;
  ParallelFor(NC, ParallelCells,
    [&](vtkIdType begin, vtkIdType end)
    {
      for (vtkIdType e = begin; e < end; ++e)
      {
        double F[9] = { 0, 0, 0, 0, 0, 0, 0, 0, 0 };
        const double* g = &G[e * N * 3];
        for (int a = 0; a < N; ++a)
        {
          const double* xa = &x[3 * Conn[e * N + a]];
          for (int i = 0; i < 3; ++i)
          {
            for (int j = 0; j < 3; ++j)
            {
              F[3 * i + j] += xa[i] * g[3 * a + j];
            }
          }
        }
        PolarRotation(F, &Rot[e * 9]);
      }
    });
  std::fill(NodeRot.begin(), NodeRot.end(), 0.0);
  for (long long e = 0; e < NC; ++e)
  {
    const double* R = &Rot[e * 9];
    for (int a = 0; a < N; ++a)
    {
      double* Q = &NodeRot[9 * Conn[e * N + a]];
      for (int k = 0; k < 9; ++k)
      {
        Q[k] += R[k];
      }
    }
  }
  for (long long p = 0; p < NP; ++p)
  {
    double* Q = &NodeRot[9 * p];
    if (NodeCellCount[p] == 0)
    {
      Q[0] = Q[4] = Q[8] = 1.0;
      continue;
    }
    const double s = 1.0 / NodeCellCount[p];
    for (int k = 0; k < 9; ++k)
    {
      Q[k] *= s;
    }
  }
}

bool CorotationalSolver::Impl::Factor(double cM, double cK)
{
  if (HaveFactor && cM == FactorCM && cK == FactorCK)
  {
    return FactorOK();
  }
  return FactorMatrix(A, true, cM, cK);
}

// Factorise either the unrotated system cM M + cK K (rest = true) or the current
// assembled A (rest = false), with clamped rows and columns replaced by the identity.
// The symbolic analysis is done once (the pattern never changes).
bool CorotationalSolver::Impl::FactorMatrix(const RowMat& source, bool rest, double cM, double cK)
{
  auto t0 = Clock::now();
  RowMat A0 = source;
  double* val = A0.valuePtr();
  const double* cur = source.valuePtr();
  const int* outer = A0.outerIndexPtr();
  const int* inner = A0.innerIndexPtr();
  for (long long r = 0; r < 3 * NP; ++r)
  {
    for (int k = outer[r]; k < outer[r + 1]; ++k)
    {
      const int c = inner[k];
      if (!Free[r] || !Free[c])
      {
        val[k] = (r == c) ? 1.0 : 0.0;
      }
      else
      {
        val[k] = rest ? cM * MassValues[k] + cK * StiffValues[k] : cur[k];
      }
    }
  }
  ColMat A0c = A0;
  if (!Analyzed)
  {
    if (Large())
    {
      LargeLLT.analyzePattern(A0c);
    }
    else
    {
      SmallLLT.analyzePattern(A0c);
    }
    Analyzed = true;
  }
  if (Large())
  {
    LargeLLT.factorize(A0c);
  }
  else
  {
    SmallLLT.factorize(A0c);
  }
  JustFactored = true;
  HaveFactor = true;
  FactorCM = cM;
  FactorCK = cK;
  FactorQ.assign(9 * NP, 0.0);
  if (rest)
  {
    for (long long p = 0; p < NP; ++p)
    {
      FactorQ[9 * p] = FactorQ[9 * p + 4] = FactorQ[9 * p + 8] = 1.0;
    }
  }
  else
  {
    FactorQ = NodeRot;
  }
  FactorSeconds = Seconds(t0, Clock::now());
  SolveSinceFactor = 0.0;
  IterationsSinceFactor = 0;
  return FactorOK();
}

void CorotationalSolver::Impl::UpdateRelativeRotations()
{
  RelRot.resize(9 * NP);
  for (long long p = 0; p < NP; ++p)
  {
    const double* Q = &NodeRot[9 * p];
    const double* F = &FactorQ[9 * p];
    double* R = &RelRot[9 * p];
    for (int i = 0; i < 3; ++i)
    {
      for (int j = 0; j < 3; ++j)
      {
        R[3 * i + j] = Q[3 * i] * F[3 * j] + Q[3 * i + 1] * F[3 * j + 1] + Q[3 * i + 2] * F[3 * j + 2];
      }
    }
  }
}

void CorotationalSolver::Impl::ApplyPrec(const Eigen::VectorXd& r, Eigen::VectorXd& z) const
{
  Eigen::VectorXd t(3 * NP);
  for (long long p = 0; p < NP; ++p)
  {
    const double* Q = &RelRot[9 * p];
    const double* rp = r.data() + 3 * p;
    for (int i = 0; i < 3; ++i)
    {
      t[3 * p + i] = Q[i] * rp[0] + Q[3 + i] * rp[1] + Q[6 + i] * rp[2]; // Q^T r
    }
  }
  Eigen::VectorXd s = Large() ? Eigen::VectorXd(LargeLLT.solve(t)) : Eigen::VectorXd(SmallLLT.solve(t));
  for (long long p = 0; p < NP; ++p)
  {
    const double* Q = &RelRot[9 * p];
    const double* sp = s.data() + 3 * p;
    for (int i = 0; i < 3; ++i)
    {
      z[3 * p + i] = Q[3 * i] * sp[0] + Q[3 * i + 1] * sp[1] + Q[3 * i + 2] * sp[2];
    }
  }
  Mask(z);
}

int CorotationalSolver::Impl::PCG(const Eigen::VectorXd& b, Eigen::VectorXd& xs, double tol)
{
  const double bnorm = b.norm();
  LastRes = 0.0;
  if (!std::isfinite(bnorm))
  {
    xs.setConstant(std::numeric_limits<double>::quiet_NaN()); // reported by Step
    return 0;
  }
  if (bnorm == 0.0)
  {
    xs.setZero();
    return 0;
  }
  Mask(xs);
  Eigen::VectorXd r(3 * NP);
  MatVec(xs, r);
  r = b - r;
  Mask(r);
  Eigen::VectorXd z(3 * NP), p(3 * NP), Ap(3 * NP);
  double rn = r.norm();
  const double goal = tol * std::max(bnorm, LoadFloor);
  if (rn <= goal)
  {
    LastRes = rn / bnorm;
    return 0;
  }
  ApplyPrec(r, z);
  p = z;
  double rz = r.dot(z);
  int it = 0;
  while (it < MaxIt)
  {
    ++it;
    MatVec(p, Ap);
    Mask(Ap);
    const double pAp = p.dot(Ap);
    if (!(pAp > 0.0))
    {
      break;
    }
    const double a = rz / pAp;
    xs += a * p;
    r -= a * Ap;
    rn = r.norm();
    if (rn <= goal || !std::isfinite(rn))
    {
      break;
    }
    ApplyPrec(r, z);
    const double rzNew = r.dot(z);
    p = z + (rzNew / rz) * p;
    rz = rzNew;
  }
  LastRes = rn / bnorm;
  return it;
}

void CorotationalSolver::Impl::MassApply(const double* p, double s, double* y) const
{
  const int* outer = MN.outerIndexPtr();
  const int* inner = MN.innerIndexPtr();
  const double* val = MN.valuePtr();
  for (long long r = 0; r < NP; ++r)
  {
    double a0 = 0.0, a1 = 0.0, a2 = 0.0;
    for (int k = outer[r]; k < outer[r + 1]; ++k)
    {
      const double m = val[k];
      const double* q = p + 3 * inner[k];
      a0 += m * q[0];
      a1 += m * q[1];
      a2 += m * q[2];
    }
    y[3 * r] += s * a0;
    y[3 * r + 1] += s * a1;
    y[3 * r + 2] += s * a2;
  }
}

void CorotationalSolver::Impl::MatVec(const Eigen::VectorXd& p, Eigen::VectorXd& y)
{
  ParallelFor(NC, ParallelCells,
    [&](vtkIdType begin, vtkIdType end)
    {
      double l[30], w[30];
      for (vtkIdType e = begin; e < end; ++e)
      {
        const double* R = &Rot[e * 9];
        for (int a = 0; a < N; ++a)
        {
          const double* q = p.data() + 3 * Conn[e * N + a];
          for (int i = 0; i < 3; ++i)
          {
            l[3 * a + i] = R[i] * q[0] + R[3 + i] * q[1] + R[6 + i] * q[2]; // R^T q
          }
        }
        const double* K = &Ke[e * D * D];
        for (int r = 0; r < D; ++r)
        {
          double s = 0.0;
          const double* Kr = K + r * D;
          for (int c = 0; c < D; ++c)
          {
            s += Kr[c] * l[c];
          }
          w[r] = s;
        }
        double* out = &EW[e * D];
        for (int a = 0; a < N; ++a)
        {
          for (int i = 0; i < 3; ++i)
          {
            out[3 * a + i] =
              R[3 * i] * w[3 * a] + R[3 * i + 1] * w[3 * a + 1] + R[3 * i + 2] * w[3 * a + 2];
          }
        }
      }
    });
  y.setZero();
  MassApply(p.data(), CM, y.data());
  for (long long e = 0; e < NC; ++e)
  {
    const double* out = &EW[e * D];
    for (int a = 0; a < N; ++a)
    {
      double* ya = y.data() + 3 * Conn[e * N + a];
      ya[0] += CK * out[3 * a];
      ya[1] += CK * out[3 * a + 1];
      ya[2] += CK * out[3 * a + 2];
    }
  }
}

void CorotationalSolver::Impl::AssembleA(double cM, double cK)
{
  ParallelFor(NC, ParallelCells,
    [&](vtkIdType begin, vtkIdType end)
    {
      for (vtkIdType e = begin; e < end; ++e)
      {
        const Mat3 R = Eigen::Map<const Mat3>(&Rot[e * 9]);
        const double* K = &Ke[e * D * D];
        double* B = &EB[e * D * D];
        for (int a = 0; a < N; ++a)
        {
          for (int b = a; b < N; ++b)
          {
            Mat3 Kab;
            for (int i = 0; i < 3; ++i)
            {
              for (int j = 0; j < 3; ++j)
              {
                Kab(i, j) = K[(3 * a + i) * D + 3 * b + j];
              }
            }
            const Mat3 Bab = R * Kab * R.transpose();
            for (int i = 0; i < 3; ++i)
            {
              for (int j = 0; j < 3; ++j)
              {
                B[(3 * a + i) * D + 3 * b + j] = Bab(i, j);
                B[(3 * b + j) * D + 3 * a + i] = Bab(i, j);
              }
            }
          }
        }
      }
    });
  double* val = A.valuePtr();
  const long long nnz = A.nonZeros();
  {
    const int* off = GatherOffsets.data();
    const int* gi = GatherIndex.data();
    const double* eb = EB.data();
    const double* mv = MassValues.data();
    ParallelFor(nnz, ParallelValues,
      [&](vtkIdType begin, vtkIdType end)
      {
        for (vtkIdType k = begin; k < end; ++k)
        {
          double sum = 0.0;
          for (int j = off[k]; j < off[k + 1]; ++j)
          {
            sum += eb[gi[j]];
          }
          val[k] = cM * mv[k] + cK * sum;
        }
      });
  }
}

bool CorotationalSolver::Step()
{
  Impl& I = *this->P;
  const int N = I.N, D = I.D;
  const long long NC = I.NC;
  const double dt = I.Dt;
  const double cM = I.StaticMode ? 0.0 : 1.0 + dt * I.Alpha;
  const double cK = dt * I.Beta + dt * dt;
  const double vScale = dt + I.Beta;

  for (long long k = 0; k < 3 * I.NP; ++k)
  {
    if (!I.Free[k])
    {
      I.v[k] = 0.0; // clamped nodes do not move
    }
  }
  auto t0 = Clock::now();
  I.ComputeRotations();
  auto t1 = Clock::now();

  I.CM = cM;
  I.CK = cK;
  // Element forces -R K (R^T (x + (dt+beta) v) - X).
  ParallelFor(NC, ParallelCells,
    [&](vtkIdType begin, vtkIdType end)
    {
      double ue[30], w[30];
      for (vtkIdType e = begin; e < end; ++e)
      {
        const Mat3 R = Eigen::Map<const Mat3>(&I.Rot[e * 9]);
        const double* K = &I.Ke[e * D * D];
        for (int a = 0; a < N; ++a)
        {
          const int pa = I.Conn[e * N + a];
          Eigen::Vector3d y(I.x[3 * pa] + vScale * I.v[3 * pa],
            I.x[3 * pa + 1] + vScale * I.v[3 * pa + 1], I.x[3 * pa + 2] + vScale * I.v[3 * pa + 2]);
          const Eigen::Vector3d l = R.transpose() * y;
          for (int i = 0; i < 3; ++i)
          {
            ue[3 * a + i] = l[i] - I.X[3 * pa + i];
          }
        }
        for (int r = 0; r < D; ++r)
        {
          double s = 0.0;
          const double* Kr = K + r * D;
          for (int c = 0; c < D; ++c)
          {
            s += Kr[c] * ue[c];
          }
          w[r] = s;
        }
        double* f = &I.EF[e * D];
        for (int a = 0; a < N; ++a)
        {
          const Eigen::Vector3d l(w[3 * a], w[3 * a + 1], w[3 * a + 2]);
          const Eigen::Vector3d g = R * l;
          f[3 * a] = -g[0];
          f[3 * a + 1] = -g[1];
          f[3 * a + 2] = -g[2];
        }
      }
    });

  Eigen::VectorXd rhs = Eigen::Map<const Eigen::VectorXd>(I.FExt.data(), 3 * I.NP);
  if (I.Alpha != 0.0)
  {
    I.MassApply(I.v.data(), -I.Alpha, rhs.data());
  }
  for (long long e = 0; e < NC; ++e)
  {
    const double* f = &I.EF[e * D];
    for (int a = 0; a < N; ++a)
    {
      const int pa = I.Conn[e * N + a];
      rhs[3 * pa] += f[3 * a];
      rhs[3 * pa + 1] += f[3 * a + 1];
      rhs[3 * pa + 2] += f[3 * a + 2];
    }
  }
  rhs *= dt;
  I.Mask(rhs);
  auto t2 = Clock::now();

  // Preconditioner: the unrotated factor (first step, new dt / damping / clamps), then
  // the factor of a recent system matrix, refreshed when the CG time spent since the
  // last factorisation exceeds what the factorisation cost (so it pays for itself).
  if (!I.HaveFactor || cM != I.FactorCM || cK != I.FactorCK)
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
  Eigen::VectorXd sol = dv;
  I.LastIt = I.PCG(rhs, sol, I.Tol);
  if (I.JustFactored)
  {
    I.ItAfterFactor = I.LastIt;
    I.JustFactored = false;
  }
  dv = sol;
  I.SolveSinceFactor += Seconds(ts, Clock::now());
  I.IterationsSinceFactor += I.LastIt;
  bool finite = true;
  I.RotationsValid = false;
  for (long long k = 0; k < 3 * I.NP; ++k)
  {
    I.v[k] += I.dv[k];
    I.x[k] += dt * I.v[k];
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
  if (!I.Factor(0.0, 1.0))
  {
    error = "the clamped stiffness matrix is singular (clamp more nodes)";
    return false;
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
    double dn = 0.0, un = 0.0;
    for (long long k = 0; k < 3 * I.NP; ++k)
    {
      dn += I.dv[k] * I.dv[k];
      un += (I.x[k] - I.X[k]) * (I.x[k] - I.X[k]);
    }
    dn = std::sqrt(dn);
    un = std::sqrt(un);
    if (dn <= tolerance * un || un == 0.0)
    {
      ok = true;
      break;
    }
    // stagnation at round-off level (x - X loses digits for tiny displacements)
    if (it >= 3 && previous >= 0.0 && dn >= 0.5 * previous && dn <= 1e-7 * un)
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
  I.EnsureRotations();
  const int N = I.N;
  ParallelFor(I.NC, ParallelCells,
    [&](vtkIdType begin, vtkIdType end)
    {
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
