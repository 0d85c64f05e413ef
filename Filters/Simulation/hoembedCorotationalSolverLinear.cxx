#include "hoembedCorotationalSolver.h"
#include "hoembedCorotationalSolverImpl.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <thread>
#include <utility>
#include <vector>

#ifdef __linux__
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>
#endif

namespace hoembed
{
namespace
{
// The background factorisation is a job with no deadline beside frames that have one: on
// two cores at the normal priority it took half of the frame's threads' time, and the
// frames around a grab ran at twice their time. At the lowest priority (Linux: a thread's
// own nice value) it takes the cycles the frames leave (Benchmarks/RESULTS.md, live loop).
void LowerThisThreadsPriority()
{
#ifdef __linux__
  setpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)), 19);
#endif
}
} // namespace

void CorotationalSolver::Impl::ComputeRotations()
{
  RotationsValid = true;
  ParallelFor(NC, ParallelCells, [&](vtkIdType begin, vtkIdType end) {
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
  if (HaveFactor && Cur && cM == Cur->CM && cK == Cur->CK)
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
  if (!Analyzed)
  {
    Analyze();
    Analyzed = true;
  }
  if (!Cur || Cur == Base)
  {
    Cur = NewFactor(); // Base is kept for the prescribed sets to come
  }
  FillFactor(*Cur, source, rest, cM, cK);
  Cur->Compute(Large(), NP);
  if (Background && Cur->NoPrescribed)
  {
    Base = Cur;
  }
  JustFactored = true;
  HaveFactor = true;
  FactorSeconds = Seconds(t0, Clock::now());
  T.Factorizations++;
  T.Factorization += FactorSeconds;
  SolveSinceFactor = 0.0;
  IterationsSinceFactor = 0;
  return FactorOK();
}

void CorotationalSolver::Impl::DescribeFactor(PreconditionerFactor& f, double cM, double cK) const
{
  f.Free = Free;
  f.CM = cM;
  f.CK = cK;
  f.NoPrescribed = NumberPrescribed == 0;
}

void CorotationalSolver::Impl::FillFactor(
  PreconditionerFactor& f, const RowMat& source, bool rest, double cM, double cK)
{
  DescribeFactor(f, cM, cK);
  FillValues(f, source, rest);
  if (!rest)
  {
    f.Q = NodeRot;
  }
}

// Reads only what stays fixed until the worker is joined (the pattern, the rest mass and
// stiffness values, the permutation; Initialize joins it first) and f's own mask and
// coefficients, so the worker can run it for a rest-matrix job.
void CorotationalSolver::Impl::FillValues(
  PreconditionerFactor& f, const RowMat& source, bool rest) const
{
  double* pv = f.Permuted.valuePtr();
  const double* cur = source.valuePtr();
  const int* outer = source.outerIndexPtr();
  const int* inner = source.innerIndexPtr();
  const std::vector<char>& free = f.Free;
  const double cM = f.CM, cK = f.CK;
  for (long long r = 0; r < 3 * NP; ++r)
  {
    for (int k = outer[r]; k < outer[r + 1]; ++k)
    {
      if (PermValue[k] < 0)
      {
        continue; // upper part
      }
      const int c = inner[k];
      double v;
      if (!free[r] || !free[c])
      {
        v = (r == c) ? 1.0 : 0.0;
      }
      else
      {
        v = rest ? cM * MassValues[k] + cK * StiffValues[k] : cur[k];
      }
      pv[PermValue[k]] = v;
    }
  }
  if (rest)
  {
    f.Q.assign(9 * NP, 0.0);
    for (long long p = 0; p < NP; ++p)
    {
      f.Q[9 * p] = f.Q[9 * p + 4] = f.Q[9 * p + 8] = 1.0;
    }
  }
}

void PreconditionerFactor::Compute(bool large, long long np)
{
  auto t0 = Clock::now();
  if (!Analyzed)
  {
    if (large)
    {
#ifdef HOEMBED_HAVE_CHOLMOD
      cholmod_common& c = LargeLLT.cholmod();
      c.nmethods = 1;
      c.method[0].ordering = CHOLMOD_NATURAL; // the matrix comes permuted
      c.postorder = 0;                        // keep it so (node blocks stay in order)
#endif
      LargeLLT.analyzePattern(Permuted);
    }
    else
    {
      SmallLLT.analyzePattern(Permuted);
    }
    Analyzed = true;
  }
  if (large)
  {
    LargeLLT.factorize(Permuted);
    BuildLargeBlocks(np);
    OK = LargeLLT.info() == Eigen::Success;
  }
  else
  {
    SmallLLT.factorize(Permuted);
    OK = SmallLLT.info() == Eigen::Success;
    if (OK)
    {
      const ColMat& L = SmallLLT.matrixL().nestedExpression();
      SmallBlocks.Build(
        static_cast<int>(L.cols()), L.outerIndexPtr(), L.innerIndexPtr(), L.valuePtr());
    }
  }
  Seconds = std::chrono::duration<double>(Clock::now() - t0).count();
}

std::shared_ptr<PreconditionerFactor> CorotationalSolver::Impl::NewFactor()
{
  if (!Spare.empty())
  {
    std::shared_ptr<PreconditionerFactor> f = std::move(Spare.back());
    Spare.pop_back();
    return f;
  }
  auto f = std::make_shared<PreconditionerFactor>();
  f->Permuted = PermutedPattern;
  return f;
}

void CorotationalSolver::Impl::Recycle(std::shared_ptr<PreconditionerFactor> f)
{
  // two spares at most: the factor memory stays bounded whatever the user clicks
  if (f && f != Cur && f != Base && f != Job && Spare.size() < 2)
  {
    Spare.push_back(std::move(f));
  }
}

bool CorotationalSolver::Impl::Covers(const PreconditionerFactor& f) const
{
  for (long long k = 0; k < 3 * NP; ++k)
  {
    if (Free[k] && !f.Free[k])
    {
      return false;
    }
  }
  return true;
}

// Why a factor of another free set serves: the CG runs on the free DOFs F of the current
// system, and ApplyPrec applies P = Q B^-1 Q^T restricted to F (r and z are masked), where
// B is the factor's matrix. When the factor's free DOFs contain F, P restricted to F is a
// principal submatrix of the SPD B^-1, so it is SPD (the CG converges), and it differs
// from the inverse of B's own F block by a term of rank at most the number of DOFs that
// left (B_FF^-1 vs (B^-1)_FF: a Schur complement), so a grab of k nodes costs about 3k
// extra iterations at worst, fewer in practice. A factor that lacks some of F (its
// rows there are identity rows: a release seen from the grabbed factor) has no such
// bound: the CG reached its iteration cap (Benchmarks/RESULTS.md, live loop). Hence Base,
// made without prescribed nodes: its free DOFs contain every prescribed set's.
void CorotationalSolver::Impl::BackgroundPreconditioner(double cM, double cK)
{
  PollJob(cM, cK);
  if (!HaveFactor || !Cur || cM != Cur->CM || cK != Cur->CK)
  {
    FactorMatrix(A, true, cM, cK); // first step, new dt / damping / clamps, a restart
    return;
  }
  if (Cur->Free != Free)
  {
    if (!Covers(*Cur))
    {
      if (Base && Base->CM == cM && Base->CK == cK && Covers(*Base))
      {
        Recycle(std::exchange(Cur, Base));
        JustFactored = true; // its iterations from now on are the reference
        IterationsSinceFactor = 0;
      }
      else
      {
        FactorMatrix(A, true, cM, cK); // nothing serves: as without the background
        return;
      }
    }
    // the factor the synchronous rule makes at a change of the set (of the rest matrix),
    // unless the stand-in is of this set (a release onto Base)
    if (Cur->Free != Free &&
      (!Job || Job->Free != Free || Job->CM != cM || Job->CK != cK || JobGeneration != Generation))
    {
      StartJob(cM, cK, true);
    }
    return;
  }
  // the factor is of this system: refreshed from the current matrix when it has drifted,
  // by the synchronous rule's test, but by the worker
  if (!Job && LastIt > std::max(2, (3 * ItAfterFactor) / 2) &&
    IterationsSinceFactor > RefactorBudget())
  {
    StartJob(cM, cK, false);
  }
}

// Start the worker on the current free set, with the matrix the synchronous rule would
// factorise (rest: cM M + cK K; else A at this step's rotations). With a worker still
// busy on a stale job: waited for with a lag (so that the outcome does not depend on
// timing), else tried again at the next step.
void CorotationalSolver::Impl::StartJob(double cM, double cK, bool rest)
{
  if (Worker.joinable())
  {
    if (Lag == 0 && !WorkerDone.load(std::memory_order_acquire))
    {
      return;
    }
    Worker.join();
    T.BackgroundFactorization += Job->Seconds;
    Recycle(std::move(Job));
    Job.reset();
  }
  if (!rest)
  {
    auto ta = Clock::now();
    AssembleA(cM, cK);
    const double assembly = Seconds(ta, Clock::now());
    T.Assembly += assembly;
    T.Solve -= assembly; // counted in the solve phase of Step; keep it in assembly
  }
  std::shared_ptr<PreconditionerFactor> job = NewFactor();
  if (rest)
  {
    // what the step reads of a running job (its set and coefficients) is set here; its
    // values are filled by the worker (a few ms of the frame that asked for it)
    DescribeFactor(*job, cM, cK);
  }
  else
  {
    FillFactor(*job, A, false, cM, cK); // of this step's A, which later steps overwrite
  }
  Job = job;
  JobStep = StepCount;
  JobGeneration = Generation;
  WorkerDone.store(false, std::memory_order_relaxed);
  Worker = std::thread([this, job, rest]() {
    LowerThisThreadsPriority();
    try
    {
      if (rest)
      {
        FillValues(*job, A, true);
      }
      job->Compute(Large(), NP);
    }
    catch (...) // out of memory: the job is dropped, the stand-in keeps serving
    {
      job->OK = false;
    }
    WorkerDone.store(true, std::memory_order_release);
  });
}

// At the start of a step: a finished job (Lag 0), or the job asked for Lag steps ago
// (waited for), is taken when it is of the current system. One of another free set
// (the user grabbed or released meanwhile) is dropped (at once with a lag, when it
// finishes without), unless it was made without prescribed nodes: then it is the newer
// Base, and the stand-in when Base was.
void CorotationalSolver::Impl::PollJob(double cM, double cK)
{
  if (!Job)
  {
    return;
  }
  const bool current = JobGeneration == Generation && Job->CM == cM && Job->CK == cK;
  const bool stale = !current || Job->Free != Free;
  const bool due =
    Lag > 0 ? (stale || StepCount - JobStep >= Lag) : WorkerDone.load(std::memory_order_acquire);
  if (!due)
  {
    return;
  }
  Worker.join();
  std::shared_ptr<PreconditionerFactor> job = std::move(Job);
  Job.reset();
  T.BackgroundFactorization += job->Seconds;
  if (stale && current && job->OK && job->NoPrescribed)
  {
    std::shared_ptr<PreconditionerFactor> old = std::move(Base);
    Base = std::move(job);
    if (Cur == old)
    {
      Cur = Base;
      JustFactored = true;
      IterationsSinceFactor = 0;
    }
    Recycle(std::move(old));
    return;
  }
  if (stale || !job->OK)
  {
    Recycle(std::move(job));
    return;
  }
  std::shared_ptr<PreconditionerFactor> old = std::move(Cur);
  Cur = std::move(job);
  Recycle(std::move(old));
  if (Cur->NoPrescribed)
  {
    Base = Cur;
  }
  HaveFactor = true;
  JustFactored = true;
  SolveSinceFactor = 0.0;
  IterationsSinceFactor = 0;
  T.BackgroundFactorizations++;
}

// Node-level AMD ordering of the pattern, the permuted lower part of the DOF matrix (three
// consecutive DOFs per node) and the map from A's values to it; symbolic analysis.
void CorotationalSolver::Impl::Analyze()
{
  ColMat nodePattern = MN;
  NodeNew.assign(NP, 0);
  if (Large())
  {
#ifdef HOEMBED_HAVE_CHOLMOD
    // CHOLMOD's own choice (AMD / METIS / its nested dissection, postordered) on the
    // node graph
    LargeFactorization nodeAnalysis;
    nodeAnalysis.cholmod().nmethods = 3; // all, the one with the least fill wins
    nodeAnalysis.cholmod().method[0].ordering = CHOLMOD_AMD;
    nodeAnalysis.cholmod().method[1].ordering = CHOLMOD_METIS;
    nodeAnalysis.cholmod().method[2].ordering = CHOLMOD_NESDIS;
    nodeAnalysis.analyzePattern(nodePattern);
    const int* perm =
      nodeAnalysis.Factor() ? static_cast<const int*>(nodeAnalysis.Factor()->Perm) : nullptr;
    for (long long k = 0; k < NP; ++k)
    {
      NodeNew[perm ? perm[k] : k] = static_cast<int>(k);
    }
#else
    std::iota(NodeNew.begin(), NodeNew.end(), 0); // the simplicial factor orders itself
#endif
  }
  else
  {
    Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> newToOld;
    Eigen::AMDOrdering<int> amd;
    amd(nodePattern, newToOld);
    for (long long k = 0; k < NP; ++k)
    {
      NodeNew[newToOld.indices()[k]] = static_cast<int>(k);
    }
  }
  std::vector<Eigen::Triplet<double, int>> trip;
  trip.reserve(A.nonZeros() / 2 + 3 * NP);
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  for (long long r = 0; r < 3 * NP; ++r)
  {
    const int nr = 3 * NodeNew[r / 3] + static_cast<int>(r % 3);
    for (int k = outer[r]; k < outer[r + 1]; ++k)
    {
      const int c = inner[k];
      const int nc = 3 * NodeNew[c / 3] + c % 3;
      if (nr >= nc)
      {
        trip.emplace_back(nr, nc, static_cast<double>(k));
      }
    }
  }
  PermutedPattern.resize(3 * NP, 3 * NP);
  PermutedPattern.setFromTriplets(trip.begin(), trip.end());
  PermutedPattern.makeCompressed();
  PermValue.assign(A.nonZeros(), -1);
  for (long long j = 0; j < PermutedPattern.nonZeros(); ++j)
  {
    PermValue[static_cast<long long>(PermutedPattern.valuePtr()[j])] = static_cast<int>(j);
  }
}

#ifdef HOEMBED_HAVE_CHOLMOD
namespace
{
// Is the factor in the order of the matrix given to CHOLMOD (the node-permuted one)?
bool InPermutedOrder(const cholmod_factor* F)
{
  const int* perm = static_cast<const int*>(F->Perm);
  for (long long k = 0; perm && k < static_cast<long long>(F->n); ++k)
  {
    if (perm[k] != k)
    {
      return false;
    }
  }
  return true;
}
} // namespace
#endif

// Copy CHOLMOD's supernodal factor (of the node-permuted matrix, natural order) into
// float node blocks; should CHOLMOD have reordered it anyway, the solves stay with it.
void PreconditionerFactor::BuildLargeBlocks(long long NP)
{
  (void)NP; // without CHOLMOD
  UseLargeBlocks = false;
#ifdef HOEMBED_HAVE_CHOLMOD
  if (LargeLLT.info() != Eigen::Success || !LargeLLT.Factor())
  {
    return;
  }
  cholmod_common& c = LargeLLT.cholmod();
  const cholmod_factor* S0 = LargeLLT.Factor();
  if (S0->is_super && S0->is_ll && S0->itype == CHOLMOD_INT && S0->xtype == CHOLMOD_REAL &&
    static_cast<long long>(S0->n) == 3 * NP)
  {
    // read the supernodes directly: column j of supernode s holds rows s[pi[s] + i],
    // values x[px[s] + (j - super[s]) nsrow + i] (i >= j - super[s]: the lower part)
    if (InPermutedOrder(S0))
    {
      const int* super = static_cast<const int*>(S0->super);
      const int* pi = static_cast<const int*>(S0->pi);
      const int* px = static_cast<const int*>(S0->px);
      const int* srow = static_cast<const int*>(S0->s);
      const double* sx = static_cast<const double*>(S0->x);
      std::vector<int> superOf(3 * NP, 0);
      for (int s = 0; s < static_cast<int>(S0->nsuper); ++s)
      {
        for (int j = super[s]; j < super[s + 1]; ++j)
        {
          superOf[j] = s;
        }
      }
      LargeBlocks.Build(static_cast<int>(3 * NP),
        [&](int col, const int*& rows, const double*& values, int& count) {
          const int s = superOf[col];
          const int j = col - super[s];
          const int nsrow = pi[s + 1] - pi[s];
          rows = srow + pi[s] + j;
          values = sx + px[s] + static_cast<long long>(j) * nsrow + j;
          count = nsrow - j;
        });
      UseLargeBlocks = true;
      return;
    }
  }
  cholmod_factor* F = cholmod_copy_factor(LargeLLT.Factor(), &c);
  if (!F)
  {
    return;
  }
  if (cholmod_change_factor(CHOLMOD_REAL, 1, 0, 1, 1, F, &c) && F->is_ll && !F->is_super &&
    static_cast<long long>(F->n) == 3 * NP)
  {
    if (InPermutedOrder(F))
    {
      LargeBlocks.Build(static_cast<int>(3 * NP), static_cast<const int*>(F->p),
        static_cast<const int*>(F->i), static_cast<const double*>(F->x));
      UseLargeBlocks = true;
    }
  }
  cholmod_free_factor(&F, &c);
#endif
}

void CorotationalSolver::Impl::UpdateRelativeRotations()
{
  RelRot.resize(9 * NP);
  for (long long p = 0; p < NP; ++p)
  {
    const double* Q = &NodeRot[9 * p];
    const double* F = &Cur->Q[9 * p];
    double* R = &RelRot[9 * p];
    for (int i = 0; i < 3; ++i)
    {
      for (int j = 0; j < 3; ++j)
      {
        R[3 * i + j] =
          Q[3 * i] * F[3 * j] + Q[3 * i + 1] * F[3 * j + 1] + Q[3 * i + 2] * F[3 * j + 2];
      }
    }
  }
}

void CorotationalSolver::Impl::ApplyPrec(const Eigen::VectorXd& r, Eigen::VectorXd& z)
{
  // t = Q^T r in the factor's node order, solved in place, z = Q t back in mesh order
  Eigen::VectorXd& t = PrecT;
  t.resize(3 * NP);
  for (long long p = 0; p < NP; ++p)
  {
    const double* Q = &RelRot[9 * p];
    const double* rp = r.data() + 3 * p;
    double* tp = t.data() + 3 * NodeNew[p];
    for (int i = 0; i < 3; ++i)
    {
      tp[i] = Q[i] * rp[0] + Q[3 + i] * rp[1] + Q[6 + i] * rp[2];
    }
  }
  if (!Large())
  {
    Cur->SmallBlocks.Solve(t.data());
  }
  else if (Cur->UseLargeBlocks)
  {
    Cur->LargeBlocks.Solve(t.data());
  }
  else
  {
    t = Cur->LargeLLT.solve(t).eval();
  }
  for (long long p = 0; p < NP; ++p)
  {
    const double* Q = &RelRot[9 * p];
    const double* sp = t.data() + 3 * NodeNew[p];
    for (int i = 0; i < 3; ++i)
    {
      z[3 * p + i] = Q[3 * i] * sp[0] + Q[3 * i + 1] * sp[1] + Q[3 * i + 2] * sp[2];
    }
  }
  Mask(z);
}

bool CorotationalSolver::Impl::InitialGuess(
  const Eigen::VectorXd& b, Eigen::VectorXd& x, Eigen::VectorXd& r)
{
  if (StaticMode || History.empty())
  {
    return false;
  }
  // orthonormal basis V of the history (Gram-Schmidt, twice; drops dependent vectors)
  std::vector<Eigen::VectorXd> V;
  for (const Eigen::VectorXd& h : History)
  {
    Eigen::VectorXd q = h;
    for (int pass = 0; pass < 2; ++pass)
    {
      for (const Eigen::VectorXd& w : V)
      {
        q -= w.dot(q) * w;
      }
    }
    const double n = q.norm();
    if (n > 1e-10 * h.norm() && n > 0.0)
    {
      V.push_back(q / n);
    }
  }
  const int m = static_cast<int>(V.size());
  if (m == 0)
  {
    return false;
  }
  std::vector<Eigen::VectorXd> W(m, Eigen::VectorXd(3 * NP));
  Eigen::MatrixXd G(m, m);
  Eigen::VectorXd g(m);
  for (int i = 0; i < m; ++i)
  {
    MatVec(V[i], W[i]);
    Mask(W[i]);
    g[i] = V[i].dot(b);
    for (int j = 0; j <= i; ++j)
    {
      G(i, j) = G(j, i) = V[j].dot(W[i]);
    }
  }
  const Eigen::VectorXd c = G.ldlt().solve(g);
  if (!c.allFinite())
  {
    return false;
  }
  x.setZero();
  r = b;
  for (int i = 0; i < m; ++i)
  {
    x += c[i] * V[i];
    r -= c[i] * W[i];
  }
  return true;
}

int CorotationalSolver::Impl::PCG(
  const Eigen::VectorXd& b, Eigen::VectorXd& xs, double tol, const Eigen::VectorXd* r0)
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
  if (r0)
  {
    r = *r0;
  }
  else
  {
    MatVec(xs, r);
    r = b - r;
  }
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

} // namespace hoembed
