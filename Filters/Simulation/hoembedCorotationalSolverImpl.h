// Private to HOEmbed::FiltersSimulation (not installed): the state of
// hoembed::CorotationalSolver, shared by its two implementation files
// (hoembedCorotationalSolver.cxx: set-up, stepping, outputs;
// hoembedCorotationalSolverLinear.cxx: rotations, products, preconditioner, CG).
#ifndef hoembedCorotationalSolverImpl_h
#define hoembedCorotationalSolverImpl_h

#include "hoembedCorotationalSolver.h"

#include "hoembedHyperelasticMaterial.h"
#include "hoembedTetElementMatrices.h"

#include "hoembedParallel.h"
#ifdef HOEMBED_NO_VTK
// The pip wheel has no VTK headers: VTK's 64-bit id type (VTK_USE_64BIT_IDS, Debian's and
// the VTK wheels' setting), for the loops' index type.
using vtkIdType = long long;
#endif

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#ifdef HOEMBED_HAVE_CHOLMOD
#include <Eigen/CholmodSupport>
#endif

#include <algorithm>
#include <atomic>
#include <chrono>
#include <functional>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <thread>
#include <vector>

namespace hoembed
{
namespace corotational_detail
{
using Clock = std::chrono::steady_clock;
using RowMat = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;
using ColMat = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
using Mat3 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;
// Small systems: Eigen's simplicial factor (low per-solve overhead). Large systems:
// CHOLMOD's supernodal factor when available (much less time to factorise).
// Both factors are computed on the matrix permuted by a node-level fill-reducing ordering
// (the three DOFs of a node stay together, so L is made of 3x3 blocks), then copied into
// BlockFactor for the solves: AMD for the small one, CHOLMOD's choice (AMD / METIS /
// NESDIS) for the large one.
using SmallFactorization = Eigen::SimplicialLLT<ColMat, Eigen::Lower, Eigen::NaturalOrdering<int>>;
#ifdef HOEMBED_HAVE_CHOLMOD
// CHOLMOD's supernodal factor, with access to the factor (copied into node blocks).
class LargeFactorization : public Eigen::CholmodSupernodalLLT<ColMat, Eigen::Lower>
{
public:
  cholmod_factor* Factor()
  {
    return this->m_cholmodFactor;
  }
};
#else
using LargeFactorization = Eigen::SimplicialLLT<ColMat, Eigen::Lower, Eigen::AMDOrdering<int>>;
#endif

// A sparse Cholesky factor L (node-permuted DOF order) stored as 3x3 node blocks, rows
// scaled to a unit diagonal of L L^T (D L, entries in [-1, 1]; Solve applies D before and
// after): per node column J the inverse of its lower-triangular diagonal block and the
// blocks L(I, J), I > J, each as 3 columns padded to 4 values (one AVX2 load per column),
// values stored as T: double for small systems; for large ones, where the solves are
// memory-bound, half precision (LargeValue, CPUs with F16C) or float. Arithmetic stays
// double, so the preconditioner is still the exact inverse of a fixed SPD matrix.
// Triangular solves then run on 4-vectors with one index per block, which beats a scalar
// simplicial solve (Benchmarks/RESULTS.md, stepper).
//
// Two-thread solves (hoembedCorotationalBlockFactor.cxx): the elimination tree of the
// node blocks is cut below its top (the chain of ancestors shared by most of the work,
// for a nested-dissection ordering the top separator) into two groups of independent
// subtrees of about equal work. The forward solve runs the two groups in parallel (their
// updates of the top rows go to one private buffer per group, added before the top is
// solved), the top serially; the backward solve the other way round. Same arithmetic per
// entry as the serial solve up to the order of the additions into the top rows.
template <typename T>
struct BlockFactor
{
  int NB = 0;
  std::vector<double> DiagInv; // 9 per node
  std::vector<int> Ptr, Row;   // blocks of column J: Ptr[J] .. Ptr[J+1]
  std::vector<T> Val;          // 12 per block: 3 columns of 4 (row 4 = 0, for SIMD)
  // CSC lower factor (n = 3 NB columns, any row order within a column)
  void Build(int n, const int* colPtr, const int* rowIdx, const double* val);
  // the same from any column layout: columns(c, rows, values, count) gives the entries of
  // scalar column c (e.g. straight from a supernodal factor)
  using ColumnSource = std::function<void(int, const int*&, const double*&, int&)>;
  void Build(int n, const ColumnSource& columns);
  void Solve(double* t) const; // in place: t <- L^-T L^-1 t
  // Plan the two-group split (Build calls it when NB >= SplitNodes); Split tells whether
  // Solve uses it (also needs vtkSMPTools to run on 2 or more threads).
  void PlanSplit();
  bool Split = false;
  std::vector<int> All, Group[2], Top; // columns, ascending
  std::vector<int> TopSlot;            // column -> index in Top, or -1
  mutable std::vector<double> Buffer[2];
  mutable std::vector<double> Work; // 4 doubles per node
  std::vector<double> Scale;        // per row: 1 / sqrt(diagonal of L L^T)
  static constexpr int SplitNodes = 2000;

private:
  void SolveWork(double* t) const;
  void Forward(const int* cols, std::size_t n, double* t, double* buffer) const;
  void Backward(const int* cols, std::size_t n, double* t) const;
};
#if defined(__F16C__) && defined(__AVX2__) && defined(__FMA__) && defined(__FLT16_MAX__)
#define HOEMBED_HALF_FACTOR 1
using HalfValue = _Float16;
#endif
#if defined(HOEMBED_HALF_FACTOR) && !defined(HOEMBED_FLOAT_FACTOR)
using LargeValue = HalfValue;
#else
using LargeValue = float;
#endif
constexpr long long LargeSystem = 6000; // DOF from which the large factorisation is used

inline double Seconds(Clock::time_point a, Clock::time_point b)
{
  return std::chrono::duration<double>(b - a).count();
}

// Loops shorter than `minParallel` run on the calling thread: for meshes of a few hundred
// cells the thread hand-off costs more than it saves (Benchmarks/RESULTS.md, stepper).
template <typename F>
void ParallelFor(vtkIdType n, vtkIdType minParallel, F&& f)
{
  if (n < minParallel)
  {
    f(0, n);
  }
  else
  {
    ParallelLoop<vtkIdType>(0, n, f);
  }
}
constexpr vtkIdType ParallelCells = 1000;
constexpr vtkIdType ParallelNodes = 2000;
constexpr vtkIdType AssembledCells = 1000;

// w = K l for a symmetric element matrix K (D x D, stored either way): fixed-size Eigen
// products (vectorised, unrolled) for tet10 (D = 30) and tet4 (D = 12).
template <int DD>
inline void SymmetricTimes(const double* K, const double* l, double* w)
{
  Eigen::Map<const Eigen::Matrix<double, DD, DD>> Km(K);
  Eigen::Map<const Eigen::Matrix<double, DD, 1>> lm(l);
  Eigen::Map<Eigen::Matrix<double, DD, 1>> wm(w);
  wm.noalias() = Km * lm;
}
inline void SymmetricTimes(int D, const double* K, const double* l, double* w)
{
  if (D == 30)
  {
    SymmetricTimes<30>(K, l, w);
  }
  else
  {
    SymmetricTimes<12>(K, l, w);
  }
}
constexpr vtkIdType ParallelValues = 1000000;

// One factorised preconditioner (hoembedCorotationalSolverLinear.cxx): the factor of a step
// matrix whose rows and columns of the DOFs that were not free are replaced by the
// identity, the nodal rotations baked into it and the free-DOF mask it was made for. Its
// symbolic analysis is kept (a slot is reused). Heap-held: the solver serves with one and,
// with background factorisation, a worker thread fills another that nothing else reads
// until the worker is joined.
struct PreconditionerFactor
{
  SmallFactorization SmallLLT;
  BlockFactor<double> SmallBlocks;
  LargeFactorization LargeLLT;
  BlockFactor<LargeValue> LargeBlocks;
  bool UseLargeBlocks = false;
  bool Analyzed = false;     // symbolic analysis of Permuted's pattern done
  ColMat Permuted;           // permuted lower part of the matrix (pattern fixed)
  std::vector<double> Q;     // NP * 9 nodal rotations baked into the factor
  std::vector<char> Free;    // 3 NP: the free DOFs of its matrix
  double CM = -1, CK = -1;   // its mass and stiffness coefficients
  bool NoPrescribed = false; // made without prescribed nodes (Free = not clamped)
  bool OK = false;
  double Seconds = 0.0; // of the last Compute
  // symbolic analysis (first time), numeric factorisation and the node blocks; touches
  // nothing outside this object (the worker thread runs it)
  void Compute(bool large, long long np);
  void BuildLargeBlocks(long long np);
};
} // namespace corotational_detail
using namespace corotational_detail;

struct CorotationalSolver::Impl
{
  int N = 0; // nodes per cell
  int D = 0; // 3 N
  long long NC = 0, NP = 0;
  std::vector<int> Conn;
  std::vector<double> X, x, v, dv;
  std::vector<double> Ke;      // NC * D * D rest stiffness
  std::vector<double> G;       // NC * N * 3 centroid shape gradients
  std::vector<double> Rot;     // NC * 9 element rotations
  std::vector<double> NodeRot; // NP * 9 (averaged, not projected) for the preconditioner
  // the step matrix in 3x3 node blocks (hoembedCorotationalSolverAssembly.cxx)
  std::vector<double> S;                      // 9 per block of MN's pattern: sum_e R_e K_e R_e^T
  std::vector<int> BlockOf;                   // NC * N * N: block of each element node pair
  std::vector<int> HalfCells[2], SharedCells; // cells for two threads (no common node)
  std::vector<int> AFromS;                    // per value of A: its value in S (-1: none)
  std::vector<double> FInt;                   // 3 NP elastic forces of the step
  void BuildBlocks();
  void AssembleS(double vScale);
  // Small meshes (NC < AssembledCells: element matrices in cache) skip S: products and
  // forces element by element (cheaper than assembling S every step there).
  bool Assembled() const
  {
    return NC >= AssembledCells;
  }
  void ElementForces(double vScale);
  void MatVecElements(const Eigen::VectorXd& p, Eigen::VectorXd& y);
  /// EW_e = R_e K_e l_e for every element, l_e (D values) filled by local(e, R_e, l_e).
  template <typename Local>
  void ElementProducts(Local&& local);
  /// out += scale * EW scattered to the nodes.
  void ScatterElements(double scale, double* out) const;
  std::vector<double> EW;                      // NC * D element results (small meshes)
  double VScale = 0.0;                         // of the current step
  std::vector<double> MassValues, StiffValues; // rest M and K on the pattern
  std::vector<double> Gravity0; // consistent body force for unit density * g / density
  std::vector<double> FExt;
  std::vector<char> Free; // 3 NP
  // Free = not clamped, not prescribed, in some cell (UpdateFree)
  std::vector<unsigned char> FixedMask, PrescribedMask; // NP each
  std::vector<double> Target; // 3 NP target displacements (prescribed points)
  long long NumberPrescribed = 0;
  double PrescribedSpeed = 0.0; // <= 0: no limit
  bool UpdateFree();            // true when Free changed
  std::vector<int> NodeCellCount;
  double Young = 1, Poisson = 0.3, Density = 1;
  double Dt = 0.01, Alpha = 0, Beta = 0;
  double Tol = 1e-4;
  int MaxIt = 500;
  RowMat A, M;
  // preconditioner: the factor it serves with (Cur)
  std::shared_ptr<PreconditionerFactor> Cur;
  std::vector<int> NodeNew;   // old node -> position in the factor's order
  std::vector<int> PermValue; // A value index -> value index of the permuted lower part
  ColMat PermutedPattern;     // permuted lower part (pattern fixed after the analysis)
  Eigen::VectorXd PrecT;      // work vector of ApplyPrec
  bool Large() const
  {
    return 3 * NP >= LargeSystem;
  }
  bool FactorOK() const
  {
    return Cur && Cur->OK;
  }
  bool HaveFactor = false;
  bool Analyzed = false;
  int ItAfterFactor = 0;
  bool JustFactored = false;
  // Background factorisation (SetBackgroundFactorization; not in static solves): a new
  // factor for a changed prescribed set, or the refresh of a drifted one, is computed by
  // a worker thread (Job) while the CG keeps the current factor (or Base) as its
  // preconditioner, and is taken at the start of a step: the first after it is done
  // (Lag 0), or exactly Lag steps after it was asked for (then waited for: deterministic).
  // Base: the last factor made without prescribed nodes; its free DOFs contain those of
  // any prescribed set, so it serves any of them (see BackgroundPreconditioner).
  bool Background = false;
  int Lag = 0;
  std::shared_ptr<PreconditionerFactor> Base, Job;
  std::vector<std::shared_ptr<PreconditionerFactor>> Spare; // analysed slots to reuse
  std::thread Worker;
  std::atomic<bool> WorkerDone{ false };
  long long StepCount = 0, JobStep = 0;       // steps taken; the step that asked for Job
  unsigned Generation = 0, JobGeneration = 0; // a restart makes older jobs stale
  std::shared_ptr<PreconditionerFactor> NewFactor();
  void Recycle(std::shared_ptr<PreconditionerFactor> f);
  // copy source (rest: cM M + cK K instead) into f with the current Free mask
  void FillFactor(PreconditionerFactor& f, const RowMat& source, bool rest, double cM, double cK);
  // f's set, coefficients and NoPrescribed (what the step reads of a running job)
  void DescribeFactor(PreconditionerFactor& f, double cM, double cK) const;
  // f's values only, for f's Free, CM and CK (rest: no source values read)
  void FillValues(PreconditionerFactor& f, const RowMat& source, bool rest) const;
  void BackgroundPreconditioner(double cM, double cK);
  void PollJob(double cM, double cK);
  void StartJob(double cM, double cK, bool rest);
  bool Covers(const PreconditionerFactor& f) const; // f's free DOFs contain Free
  ~Impl()
  {
    if (Worker.joinable())
    {
      Worker.join();
    }
  }
  double FactorSeconds = 0.0;    // cost of the last factorisation
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
  std::vector<double> RelRot; // NP * 9: NodeRot * Cur->Q^T (preconditioner rotation)
  double LoadFloor = 0.0;     // |dt f_ext|: residual scale when the system is at rest
  Timings T;
  int LastIt = 0;
  double LastRes = 0;

  void ComputeRotations();
  bool RotationsValid = false; // Rot / NodeRot match x
  // A restart from a new state starts from the unrotated factor again, so that the same
  // state and settings always give bitwise the same trajectory.
  // Initial guess of the CG: the Galerkin projection of the step system onto the span of
  // the last GuessDepth() solutions (A-norm-best combination: it contains the previous dv
  // and its polynomial extrapolations). Sets x and its residual r = b - A x; false when
  // there is no history (then x stays as given: the previous dv). Large meshes only: on
  // small ones a preconditioner application costs about a product, the projection's
  // products do not pay.
  int GuessDepth() const
  {
    return Assembled() ? 4 : 0;
  }
  std::vector<Eigen::VectorXd> History; // previous steps' dv, most recent first
  bool InitialGuess(const Eigen::VectorXd& b, Eigen::VectorXd& x, Eigen::VectorXd& r);
  void RestartPreconditioner()
  {
    History.clear();
    HaveFactor = false;
    ++Generation; // a factor being computed in the background is of the old state
    RestartNewton();
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
  void ApplyPrec(const Eigen::VectorXd& r, Eigen::VectorXd& z);
  void Analyze();
  bool Factor(double cM, double cK);
  bool FactorMatrix(const RowMat& source, bool rest, double cM, double cK);
  void UpdateRelativeRotations();
  // r0: the residual b - A xs when known (else computed)
  int PCG(const Eigen::VectorXd& b, Eigen::VectorXd& xs, double tol, const Eigen::VectorXd* r0);
  // y = CM M p + CK S p (S assembled at the start of the step)
  void MatVec(const Eigen::VectorXd& p, Eigen::VectorXd& y);
  // y = cM M p + cK B p on MN's pattern, B one 3x3 block (row-major) per entry of MN in
  // MN's order; with `free`, the rows of held DOFs are 0. MatVec's product (B = S) and the
  // hyperelastic Newton system's (B = its Hessian and damping blocks).
  void MassBlockProduct(const double* blocks, double cM, double cK, const char* free,
    const Eigen::VectorXd& p, Eigen::VectorXd& y) const;
  // y += s * M p with the node-level (scalar) mass matrix
  void MassApply(const double* p, double s, double* y) const;
  // A = cM M + cK S (only needed to refresh the factorisation)
  void AssembleA(double cM, double cK);
  double CM = 1.0, CK = 0.0;
  bool StaticMode = false; // steps without mass (static increments)
  RowMat MN;               // NP x NP scalar mass matrix
  // Hyperelastic materials (hoembedHyperelasticSolver.cxx): Newton on the incremental
  // potential instead of the co-rotated linearised step (Mat != Corotated).
  Material Mat = Material::Corotated;
  HyperelasticLaw Law;
  int HQ = 0;             // quadrature points per cell
  std::vector<double> HG; // NC * HQ * N * 3: dN/dX at the quadrature points
  std::vector<double> HW; // NC * HQ: weight * det J
  double NewtonTol = 1e-8;
  int NewtonMaxIt = 50;
  int LastNewtonIt = 0;
  struct NewtonState; // the factor and work arrays (defined in the .cxx)
  std::shared_ptr<NewtonState> Newton;
  void InitializeHyper();
  void RestartNewton(); // forget the factor kept as CG preconditioner
  /// elastic energy at positions y (+infinity where the law is undefined)
  double HyperEnergy(const double* y) const;
  /// elastic forces' negative (gradient, 3 NP) and, when `blocks`, the Hessian in 3x3
  /// node blocks on MN's pattern (per-point tangent projected when `project`)
  void HyperGradient(const double* y, double* grad, double* blocks, bool project) const;
  bool HyperStep();
  bool HyperStatic(int maxIterations, double tolerance, std::string& error);
  void HyperVonMises(double* stress) const;
  bool HyperInverted(vtkIdType e, const double* y) const;
  long long HyperInvertedCells(const double* y, std::vector<char>& flags) const;
  bool HyperInvertsMore(const double* y, const std::vector<char>& was) const;
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
} // namespace hoembed

#endif
