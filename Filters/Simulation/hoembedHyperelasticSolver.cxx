// hoembed::CorotationalSolver with a hyperelastic material (SetMaterial): Newton's method
// on the backward-Euler incremental potential (or, static, on the potential energy), see
// hoembedCorotationalSolver.h. Shares the solver's mesh, mass, loads, clamps and
// prescribed motion; only the step and the static solve differ from the co-rotated ones.
#include "hoembedCorotationalSolver.h"
#include "hoembedCorotationalSolverImpl.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace hoembed
{
namespace
{
// The Newton systems are factorised directly (a fresh numeric factorisation per
// iteration on the fixed pattern, symbolic analysis once): CHOLMOD's supernodal factor
// when the build has it, else Eigen's simplicial one on an AMD ordering.
#ifdef HOEMBED_HAVE_CHOLMOD
using NewtonFactorization = Eigen::CholmodSupernodalLLT<ColMat, Eigen::Lower>;
#else
using NewtonFactorization = Eigen::SimplicialLLT<ColMat, Eigen::Lower, Eigen::AMDOrdering<int>>;
#endif
// Quadrature of the hyperelastic energy. Tet10: the symmetric 4-point rule of degree 2
// (barycentric (a, b, b, b) and permutations, weights 1/24), C3D10's "full" integration:
// exact for the small-strain stiffness of a straight tet10 (its integrand B^T C B is of
// degree 2, so at small load the laws are exactly linear elasticity), positive weights
// (a positive combination of projected point tangents stays positive semi-definite),
// and 27 / 4 times cheaper per Newton iteration than the 27-point conical rule used
// before (the energy, its gradient and Hessian, and the line search all scale with the
// points). Tet4: 1 point (F is constant on a straight tet4).
int HyperQuadrature(int N, double* pc, double* w)
{
  if (N != 10)
  {
    pc[0] = pc[1] = pc[2] = 0.25;
    w[0] = 1.0 / 6.0;
    return 1;
  }
  const double a = 0.58541019662496845446, b = 0.13819660112501051518;
  const double pts[12] = { b, b, b, a, b, b, b, a, b, b, b, a };
  for (int q = 0; q < 4; ++q)
  {
    for (int i = 0; i < 3; ++i)
    {
      pc[3 * q + i] = pts[3 * q + i];
    }
    w[q] = 1.0 / 24.0;
  }
  return 4;
}
} // namespace

struct CorotationalSolver::Impl::NewtonState
{
  NewtonFactorization LLT;
  bool Analyzed = false;
  ColMat H;                            // the free-DOF system (non-free rows and columns: identity)
  std::vector<double> ElementHessians; // HyperGradient's work buffer
  std::vector<long long> IncidenceOffsets, Incidences; // per node: e * N + a, cell order
  std::vector<char> Inverted;           // per cell, at the Newton iterate (line search)
  std::vector<Eigen::VectorXd> History; // the last directions of RotatedFactorCG, newest first
  void Remember(const Eigen::VectorXd& d)
  {
    History.insert(History.begin(), d);
    if (History.size() > 4)
    {
      History.pop_back();
    }
  }
  std::vector<double> DampBlocks, SysBlocks; // beta / dt K_n; Blocks + DampBlocks
  RowMat HR; // its values on A's (symmetric) pattern, row-major: the block factor's source
  std::vector<double> Blocks, DampValues; // Hessian blocks; beta / dt K_n on A's values
  bool HaveFactor = false;                // LLT holds a factor of an earlier system with FactorFree
  bool BlocksReady = false; // Blocks hold the (projected) Hessian at the solve's start
  std::vector<char> FactorFree;
};

void CorotationalSolver::Impl::RestartNewton()
{
  if (Newton)
  {
    Newton->HaveFactor = false; // a restart from a state: the same trajectory every time
    Newton->History.clear();
  }
}

void CorotationalSolver::Impl::InitializeHyper()
{
  std::vector<double> pc(3 * 4), w(4);
  HQ = HyperQuadrature(N, pc.data(), w.data());
  HG.assign(NC * HQ * N * 3, 0.0);
  HW.assign(NC * HQ, 0.0);
  ParallelFor(NC, 64, [&](vtkIdType begin, vtkIdType end) {
    double xe[30];
    for (vtkIdType e = begin; e < end; ++e)
    {
      for (int a = 0; a < N; ++a)
      {
        for (int i = 0; i < 3; ++i)
        {
          xe[3 * a + i] = X[3 * Conn[e * N + a] + i];
        }
      }
      for (int q = 0; q < HQ; ++q)
      {
        const double det = ShapeGradients(N, xe, &pc[3 * q], &HG[(e * HQ + q) * N * 3]);
        HW[e * HQ + q] = w[q] * det;
      }
    }
  });
  if (!Newton)
  {
    Newton = std::make_shared<NewtonState>();
  }
  auto& off = Newton->IncidenceOffsets;
  auto& inc = Newton->Incidences;
  off.assign(NP + 1, 0);
  for (long long k = 0; k < NC * N; ++k)
  {
    off[Conn[k] + 1]++;
  }
  for (long long p = 0; p < NP; ++p)
  {
    off[p + 1] += off[p];
  }
  inc.assign(NC * N, 0);
  std::vector<long long> fill(off.begin(), off.end() - 1);
  for (long long k = 0; k < NC * N; ++k)
  {
    inc[fill[Conn[k]]++] = k;
  }
  Newton->Analyzed = false;
  Newton->HaveFactor = false;
}

namespace
{
// F = sum_a y_a (x) dN_a/dX (row-major)
inline void DeformationGradient(int N, const int* conn, const double* y, const double* g, double* F)
{
  for (int k = 0; k < 9; ++k)
  {
    F[k] = 0.0;
  }
  for (int a = 0; a < N; ++a)
  {
    const double* ya = y + 3 * conn[a];
    const double* ga = g + 3 * a;
    for (int i = 0; i < 3; ++i)
    {
      for (int j = 0; j < 3; ++j)
      {
        F[3 * i + j] += ya[i] * ga[j];
      }
    }
  }
}
} // namespace

namespace
{
inline double Det3(const double* F)
{
  return F[0] * (F[4] * F[8] - F[5] * F[7]) - F[1] * (F[3] * F[8] - F[5] * F[6]) +
    F[2] * (F[3] * F[7] - F[4] * F[6]);
}
} // namespace

// Cell e of positions y is inverted (or flat): det F <= 0 at a quadrature point (where
// the energy sees the cell), or (tet10) the straight tet of its corners has turned over
// (what a viewer draws of it). Not the Jacobian of the curved cell everywhere: at its
// corners it can turn negative without the 4-point energy seeing it, and refusing that
// jammed a one-iteration-per-frame drag at a cell the energy kept pushing there.
bool CorotationalSolver::Impl::HyperInverted(vtkIdType e, const double* y) const
{
  double F[9];
  for (int q = 0; q < HQ; ++q)
  {
    DeformationGradient(N, &Conn[e * N], y, &HG[(e * HQ + q) * N * 3], F);
    if (!(Det3(F) > 0.0))
    {
      return true;
    }
  }
  if (N != 10)
  {
    return false;
  }
  double now[9], rest[9];
  const int* c = &Conn[e * N];
  for (int k = 0; k < 3; ++k)
  {
    for (int i = 0; i < 3; ++i)
    {
      now[3 * k + i] = y[3 * c[k + 1] + i] - y[3 * c[0] + i];
      rest[3 * k + i] = X[3 * c[k + 1] + i] - X[3 * c[0] + i];
    }
  }
  return !(Det3(now) * Det3(rest) > 0.0);
}

// Flags the inverted cells of y (HyperInverted) into `flags`; returns their number
long long CorotationalSolver::Impl::HyperInvertedCells(
  const double* y, std::vector<char>& flags) const
{
  flags.assign(NC, 0);
  ParallelFor(NC, ParallelCells, [&](vtkIdType begin, vtkIdType end) {
    for (vtkIdType e = begin; e < end; ++e)
    {
      flags[e] = HyperInverted(e, y) ? 1 : 0;
    }
  });
  long long n = 0;
  for (char f : flags)
  {
    n += f;
  }
  return n;
}

// True when y inverts a cell not flagged in `was` (the line search's and the held
// move's refusal)
bool CorotationalSolver::Impl::HyperInvertsMore(const double* y, const std::vector<char>& was) const
{
  std::vector<char> now(NC, 0);
  ParallelFor(NC, ParallelCells, [&](vtkIdType begin, vtkIdType end) {
    for (vtkIdType e = begin; e < end; ++e)
    {
      now[e] = (!was[e] && HyperInverted(e, y)) ? 1 : 0;
    }
  });
  for (char f : now)
  {
    if (f)
    {
      return true;
    }
  }
  return false;
}

double CorotationalSolver::Impl::HyperEnergy(const double* y) const
{
  std::vector<double> per(NC, 0.0);
  ParallelFor(NC, ParallelCells, [&](vtkIdType begin, vtkIdType end) {
    double F[9];
    for (vtkIdType e = begin; e < end; ++e)
    {
      double s = 0.0;
      for (int q = 0; q < HQ; ++q)
      {
        DeformationGradient(N, &Conn[e * N], y, &HG[(e * HQ + q) * N * 3], F);
        s += HW[e * HQ + q] * Law.Energy(F);
      }
      per[e] = s;
    }
  });
  double total = 0.0; // summed in cell order: the same bits on any thread count
  for (double s : per)
  {
    total += s;
  }
  return total;
}

void CorotationalSolver::Impl::HyperGradient(
  const double* y, double* grad, double* blocks, bool project) const
{
  // the element Hessians (NC D^2 doubles: 22 MB at 3000 tet10) in a buffer kept between
  // calls (a fresh one cost its page faults every call); only the blocks b >= a are
  // computed, the others are their transposes
  std::vector<double> fe(NC * D, 0.0);
  std::vector<double>& he = Newton->ElementHessians;
  if (blocks)
  {
    he.resize(NC * D * D); // zeroed per element below, on the threads
  }
  ParallelFor(NC, 64, [&](vtkIdType begin, vtkIdType end) {
    double F[9], P[9], A[81], T[27];
    for (vtkIdType e = begin; e < end; ++e)
    {
      double* f = &fe[e * D];
      double* h = blocks ? &he[e * D * D] : nullptr;
      if (h)
      {
        std::fill(h, h + D * D, 0.0);
      }
      for (int q = 0; q < HQ; ++q)
      {
        const double* g = &HG[(e * HQ + q) * N * 3];
        const double w = HW[e * HQ + q];
        DeformationGradient(N, &Conn[e * N], y, g, F);
        if (h)
        {
          Law.Tangent(F, P, A, project);
        }
        else
        {
          Law.Stress(F, P);
        }
        for (int a = 0; a < N; ++a)
        {
          const double* ga = g + 3 * a;
          for (int i = 0; i < 3; ++i)
          {
            f[3 * a + i] += w * (P[3 * i] * ga[0] + P[3 * i + 1] * ga[1] + P[3 * i + 2] * ga[2]);
          }
          if (!h)
          {
            continue;
          }
          // T[i][kl] = w sum_j A[ij][kl] g_aj, then H(ai, bk) += sum_l T[i][kl] g_bl
          for (int i = 0; i < 3; ++i)
          {
            for (int kl = 0; kl < 9; ++kl)
            {
              T[9 * i + kl] = w *
                (A[(3 * i) * 9 + kl] * ga[0] + A[(3 * i + 1) * 9 + kl] * ga[1] +
                  A[(3 * i + 2) * 9 + kl] * ga[2]);
            }
          }
          for (int b = a; b < N; ++b)
          {
            const double* gb = g + 3 * b;
            for (int i = 0; i < 3; ++i)
            {
              for (int k = 0; k < 3; ++k)
              {
                const double* t = &T[9 * i + 3 * k];
                h[(3 * a + i) * D + 3 * b + k] += t[0] * gb[0] + t[1] * gb[1] + t[2] * gb[2];
              }
            }
          }
        }
      }
      if (h)
      {
        for (int a = 0; a < N; ++a)
        {
          for (int b = 0; b < a; ++b)
          {
            for (int i = 0; i < 3; ++i)
            {
              for (int k = 0; k < 3; ++k)
              {
                h[(3 * a + i) * D + 3 * b + k] = h[(3 * b + k) * D + 3 * a + i];
              }
            }
          }
        }
      }
    }
  });
  // scatter by node rows on the threads: a row's blocks and gradient entries take the
  // contributions of its cells in cell order (the node's incidence list is in cell
  // order), so the sums are the same bits as a serial scatter in cell order
  const std::vector<long long>& off = Newton->IncidenceOffsets;
  const std::vector<long long>& inc = Newton->Incidences;
  ParallelFor(NP, ParallelNodes, [&](vtkIdType begin, vtkIdType end) {
    for (vtkIdType p = begin; p < end; ++p)
    {
      double* gp = grad + 3 * p;
      gp[0] = gp[1] = gp[2] = 0.0;
      if (blocks)
      {
        for (int k = MN.outerIndexPtr()[p]; k < MN.outerIndexPtr()[p + 1]; ++k)
        {
          std::fill(blocks + 9 * static_cast<long long>(k),
            blocks + 9 * static_cast<long long>(k) + 9, 0.0);
        }
      }
      for (long long c = off[p]; c < off[p + 1]; ++c)
      {
        const long long ea = inc[c]; // e * N + a
        const long long e = ea / N;
        const int a = static_cast<int>(ea % N);
        for (int i = 0; i < 3; ++i)
        {
          gp[i] += fe[e * D + 3 * a + i];
        }
        if (!blocks)
        {
          continue;
        }
        for (int b = 0; b < N; ++b)
        {
          double* blk = blocks + 9 * static_cast<long long>(BlockOf[ea * N + b]);
          const double* src = &he[(e * D + 3 * a) * D + 3 * b];
          for (int i = 0; i < 3; ++i)
          {
            for (int k = 0; k < 3; ++k)
            {
              blk[3 * i + k] += src[i * D + k];
            }
          }
        }
      }
    }
  });
}

namespace
{
// The Newton loop shared by the step and the static solve. The potential is
//   Phi(x) = cM/2 |x - xhat|_M^2 + a/2 |x - xn|_M^2 + 1/2 (x - xn)^T Kd (x - xn)
//            + Psi(x) - f^T x
// over the free DOFs (the others held where x has them): dynamic, cM = 1/dt^2,
// xhat = xn + dt vn (backward Euler), a = alpha/dt (mass damping) and Kd = beta/dt times the
// Hessian at the step's start (stiffness damping, frozen over the step); static, all 0.
struct Potential
{
  CorotationalSolver::Impl& I;
  double CM = 0.0, CA = 0.0;
  const std::vector<double>* XHat = nullptr; // dynamic only
  const std::vector<double>* XN = nullptr;
  bool Damp = false; // I.Newton->DampValues hold beta/dt K_n (on A's values)

  // Phi and, when g, its gradient (3 NP; zero on the held DOFs)
  double Value(const std::vector<double>& x, double* g) const
  {
    const long long n3 = 3 * I.NP;
    double phi = 0.0;
    std::vector<double> r(n3, 0.0), mr(n3, 0.0);
    if (g)
    {
      I.HyperGradient(x.data(), g, nullptr, false);
      phi = I.HyperEnergy(x.data());
    }
    else
    {
      phi = I.HyperEnergy(x.data());
    }
    if (!std::isfinite(phi))
    {
      return std::numeric_limits<double>::infinity();
    }
    for (long long k = 0; k < n3; ++k)
    {
      phi -= I.FExt[k] * x[k];
      if (g)
      {
        g[k] -= I.FExt[k];
      }
    }
    if (CM > 0.0 || CA > 0.0)
    {
      // cM (x - xhat) + a (x - xn), through M
      for (long long k = 0; k < n3; ++k)
      {
        r[k] = CM * (x[k] - (*XHat)[k]);
      }
      std::vector<double> s(n3, 0.0);
      for (long long k = 0; k < n3; ++k)
      {
        s[k] = x[k] - (*XN)[k];
      }
      I.MassApply(r.data(), 1.0, mr.data());
      std::vector<double> ms(n3, 0.0);
      I.MassApply(s.data(), 1.0, ms.data());
      for (long long k = 0; k < n3; ++k)
      {
        phi += 0.5 * (x[k] - (*XHat)[k]) * mr[k] + 0.5 * CA * s[k] * ms[k];
        if (g)
        {
          g[k] += mr[k] + CA * ms[k];
        }
      }
      if (Damp)
      {
        const int* outer = I.A.outerIndexPtr();
        const int* inner = I.A.innerIndexPtr();
        const double* kd = I.Newton->DampValues.data();
        for (long long rr = 0; rr < n3; ++rr)
        {
          double t = 0.0;
          for (int k = outer[rr]; k < outer[rr + 1]; ++k)
          {
            t += kd[k] * s[inner[k]];
          }
          phi += 0.5 * s[rr] * t;
          if (g)
          {
            g[rr] += t;
          }
        }
      }
    }
    if (g)
    {
      for (long long k = 0; k < n3; ++k)
      {
        g[k] = I.Free[k] ? g[k] : 0.0;
      }
    }
    return phi;
  }
};

// A's values of the system cM' M + Kd + H(blocks) with the held DOFs' rows and columns
// replaced by the identity, into ns.H (pattern of A, lower part read by the factor).
void FillSystem(CorotationalSolver::Impl& I, double cMass, bool damp)
{
  auto& ns = *I.Newton;
  if (ns.H.rows() != I.A.rows())
  {
    ns.H = I.A; // a symmetric pattern: the row-major A is its column-major transpose
  }
  const int* outer = I.A.outerIndexPtr();
  const int* inner = I.A.innerIndexPtr();
  double* hv = ns.H.valuePtr();
  // ns.H is column-major with A's pattern transposed; A is symmetric in pattern and value,
  // so value k of row r of A is value k of column r of H.
  for (long long r = 0; r < 3 * I.NP; ++r)
  {
    for (int k = outer[r]; k < outer[r + 1]; ++k)
    {
      const int c = inner[k];
      double v = 0.0;
      if (I.Free[r] && I.Free[c])
      {
        const int s = I.AFromS[k];
        v =
          (s >= 0 ? ns.Blocks[s] : 0.0) + cMass * I.MassValues[k] + (damp ? ns.DampValues[k] : 0.0);
      }
      else if (r == c)
      {
        v = 1.0;
      }
      hv[k] = v;
    }
  }
}
} // namespace

// d = -H^-1 g by CG on ns.H preconditioned by the last factor, to 1e-6 relative (an
// inexact Newton direction: the stop rule, on the step, still decides convergence): false
// (d unusable) after RefactorCG iterations or at negative curvature.
constexpr int RefactorCG = 25;
static bool PreconditionedCG(
  CorotationalSolver::Impl& I, const Eigen::Map<const Eigen::VectorXd>& g, Eigen::VectorXd& d)
{
  auto& ns = *I.Newton;
  const Eigen::Index n = g.size();
  d = Eigen::VectorXd::Zero(n);
  Eigen::VectorXd r = -g, z, p, q;
  const double b = r.norm();
  if (b == 0.0)
  {
    return true;
  }
  z = ns.LLT.solve(r);
  p = z;
  double rz = r.dot(z);
  for (int k = 0; k < RefactorCG; ++k)
  {
    q = ns.H * p;
    const double pq = p.dot(q);
    if (!(pq > 0.0))
    {
      return false;
    }
    const double alpha = rz / pq;
    d += alpha * p;
    r -= alpha * q;
    if (r.norm() <= 1e-6 * b)
    {
      return true;
    }
    z = ns.LLT.solve(r);
    const double rz1 = r.dot(z);
    p = z + (rz1 / rz) * p;
    rz = rz1;
  }
  return false;
}

// Dynamic steps: d = -H^-1 g by CG to the solver's relative tolerance (SetSolverControls;
// the stepper's SolverTolerance, 1e-4: an inexact Newton direction, the stop rule on the
// step decides convergence) on ns.H preconditioned by the co-rotated stepper's
// node-block factor (hoembedCorotationalSolverLinear.cxx: a factor of an earlier Newton
// system, made with the nodal rotations of its state, applied rotated by the nodal
// rotations since; half-precision storage, AVX2 triangular solves on two threads). A
// Newton system is mass plus a stiffness that, at moderate strain, mostly rotates with
// the elements, so the rotated factor stays a close preconditioner over many frames,
// and its solves cost a fraction of CHOLMOD's supernodal ones (on 3000 tet10 those took
// ~10 ms each, 7-25 per frame). A new factor (of the current system) when the free DOFs
// or the mass coefficient changed, or after the CG exceeded RotatedCG iterations or met
// negative curvature; false when even a fresh factor does not serve (the caller then
// takes the direct path). Deterministic: iteration counts, never times.
constexpr int RotatedCG = 40;
static long long MNBlocks(const CorotationalSolver::Impl& I)
{
  return I.MN.nonZeros();
}
static bool RotatedFactorCG(CorotationalSolver::Impl& I, double cMass, bool damp,
  const Eigen::Map<const Eigen::VectorXd>& g, Eigen::VectorXd& d, bool projected)
{
  auto& ns = *I.Newton;
  if (ns.HR.rows() != I.A.rows())
  {
    ns.HR = I.A;
  }
  const Eigen::Index n = g.size();
  // the system's blocks (Hessian plus stiffness damping) for the products: a block-row
  // sweep on two threads instead of the scalar sparse product (~9 values per column
  // index instead of 1)
  const long long nb = MNBlocks(I);
  ns.SysBlocks.resize(9 * nb);
  for (long long k = 0; k < 9 * nb; ++k)
  {
    ns.SysBlocks[k] = ns.Blocks[k] + (ns.DampBlocks.empty() ? 0.0 : ns.DampBlocks[k]);
  }
  // p is 0 on the held DOFs (the preconditioner masks): their rows give 0 too
  auto product = [&](const Eigen::VectorXd& p, Eigen::VectorXd& y) {
    I.MassBlockProduct(ns.SysBlocks.data(), cMass, 1.0, I.Free.data(), p, y);
  };
  for (int attempt = 0; attempt < 2; ++attempt)
  {
    I.ComputeRotations();
    I.RotationsValid = false; // Rot, NodeRot serve here only: the co-rotated step redoes them
    bool fresh = false;
    if (attempt == 1 || !I.HaveFactor || !I.Cur || !I.Cur->OK || I.Cur->Free != I.Free ||
      I.Cur->CM != cMass)
    {
      FillSystem(I, cMass, damp);
      std::copy(ns.H.valuePtr(), ns.H.valuePtr() + ns.H.nonZeros(), ns.HR.valuePtr());
      I.FactorMatrix(ns.HR, false, cMass, 0.0);
      fresh = true;
      if (!I.FactorOK())
      {
        return false;
      }
    }
    I.UpdateRelativeRotations();
    d = Eigen::VectorXd::Zero(n);
    Eigen::VectorXd r = -g, z(n), p, q(n);
    const double b = r.norm();
    if (b == 0.0)
    {
      return true;
    }
    // first guess: the Galerkin projection onto the span of the last directions (the
    // system-norm best combination; consecutive frames' directions are alike), as the
    // co-rotated step does: ~half the iterations for a product per vector
    if (!ns.History.empty())
    {
      std::vector<Eigen::VectorXd> V, W;
      for (const Eigen::VectorXd& h0 : ns.History)
      {
        Eigen::VectorXd v = h0;
        for (Eigen::Index k = 0; k < n; ++k)
        {
          v[k] = I.Free[k] ? v[k] : 0.0;
        }
        const double n0 = v.norm();
        for (int pass = 0; pass < 2; ++pass)
        {
          for (const Eigen::VectorXd& u : V)
          {
            v -= u.dot(v) * u;
          }
        }
        const double n1 = v.norm();
        if (n1 > 1e-8 * n0 && n1 > 0.0)
        {
          V.push_back(v / n1);
        }
      }
      const int m = static_cast<int>(V.size());
      if (m > 0)
      {
        W.resize(m, Eigen::VectorXd(n));
        Eigen::MatrixXd Gm(m, m);
        Eigen::VectorXd rhs(m);
        for (int i = 0; i < m; ++i)
        {
          product(V[i], W[i]);
          rhs[i] = V[i].dot(r);
        }
        for (int i = 0; i < m; ++i)
        {
          for (int j = 0; j < m; ++j)
          {
            Gm(i, j) = 0.5 * (V[i].dot(W[j]) + V[j].dot(W[i]));
          }
        }
        Eigen::LDLT<Eigen::MatrixXd> small(Gm);
        const Eigen::VectorXd c = small.solve(rhs);
        if (small.info() == Eigen::Success && c.allFinite())
        {
          for (int i = 0; i < m; ++i)
          {
            d += c[i] * V[i];
            r -= c[i] * W[i];
          }
        }
      }
    }
    if (r.norm() <= I.Tol * b)
    {
      ns.Remember(d);
      return true;
    }
    I.ApplyPrec(r, z);
    p = z;
    double rz = r.dot(z);
    bool ok = false;
    for (int k = 0; k < RotatedCG; ++k)
    {
      product(p, q);
      const double pq = p.dot(q);
      if (!(pq > 0.0))
      {
        break;
      }
      const double alpha = rz / pq;
      d += alpha * p;
      r -= alpha * q;
      if (r.norm() <= I.Tol * b)
      {
        ok = true;
        ns.Remember(d);
        break;
      }
      I.ApplyPrec(r, z);
      const double rz1 = r.dot(z);
      p = z + (rz1 / rz) * p;
      rz = rz1;
    }
    if (ok)
    {
      return true;
    }
    if (fresh || !projected)
    {
      // the exact Hessian failed (negative curvature, or too many iterations): the caller
      // projects it before a new factor is made (a factorisation costs ~100 iterations
      // at 15k DOF; converged steps refactorised at every such failure)
      return false;
    }
  }
  return false;
}

// One Newton solve from I.x (held DOFs already where they stay): exact Hessian first
// (quadratic convergence), the per-point projected one where the exact one is not
// positive definite; backtracking (Armijo) line search on Phi. Returns the iterations
// (negative: failed, with `error`).
static int NewtonSolve(CorotationalSolver::Impl& I, Potential& phi, double cMass, int maxIterations,
  double tolerance, bool untilConverged, std::string& error, bool* backtracked = nullptr)
{
  auto& ns = *I.Newton;
  const long long n3 = 3 * I.NP;
  std::vector<double> g(n3), trial(n3);
  // the scale of "no motion": a relative round-off floor of the mesh size
  double lo = 1e300, hi = -1e300;
  for (double c : I.X)
  {
    lo = std::min(lo, c);
    hi = std::max(hi, c);
  }
  const double floor = 1e-15 * std::max(hi - lo, 1e-300);
  // the energy's round-off: its terms are of the order of the law's stiffness times the
  // volume, and cancel at small strain (under a tiny load the decrease of an exact Newton
  // step is below it, and a plain Armijo test would reject that step)
  double volume = 0.0;
  for (double w : I.HW)
  {
    volume += std::abs(w);
  }
  const double stiffness = std::abs(I.Law.Mu) + std::abs(I.Law.Lambda) + std::abs(I.Law.C10) +
    std::abs(I.Law.C01) + std::abs(I.Law.Kappa);
  const double noise = 1e-12 * stiffness * volume;
  double previous = -1.0;
  const std::vector<double> start = I.x;
  double value = phi.Value(I.x, g.data());
  if (!std::isfinite(value))
  {
    error = "the energy is not finite at the start of the solve (an inverted element with a "
            "material that is undefined there)";
    return -1;
  }
  int it = 0;
  for (; it < maxIterations; ++it)
  {
    Eigen::Map<const Eigen::VectorXd> gm(g.data(), n3);
    Eigen::VectorXd d;
    bool solved = false;
    auto ta = Clock::now();
    bool projectedBlocks = ns.BlocksReady;
    if (!ns.BlocksReady) // (the step's damping pass left the blocks at this x)
    {
      I.HyperGradient(I.x.data(), trial.data(), ns.Blocks.data(), false);
    }
    ns.BlocksReady = false;
    if (cMass <= 0.0)
    {
      FillSystem(I, cMass, phi.Damp); // (the rotated path fills it when it factorises)
    }
    I.T.Assembly += Seconds(ta, Clock::now());
    // Time steps: RotatedFactorCG (exact Hessian, then projected), else the direct path.
    // Static: the last factor as the preconditioner of CG on the new system (a Hessian
    // changes little between iterations and frames): a fresh factorisation costs tens of CG
    // iterations on 3000 tet10. Refactorised when the CG needs more than RefactorCG
    // iterations, meets negative curvature (exact Hessian not positive definite), or the
    // free set changed. Deterministic (iteration counts, not times).
    if (cMass > 0.0)
    {
      solved = RotatedFactorCG(I, cMass, phi.Damp, gm, d, projectedBlocks);
      if (!solved && !projectedBlocks)
      {
        ta = Clock::now();
        I.HyperGradient(I.x.data(), trial.data(), ns.Blocks.data(), true);
        I.T.Assembly += Seconds(ta, Clock::now());
        projectedBlocks = true;
        solved = RotatedFactorCG(I, cMass, phi.Damp, gm, d, true);
      }
      if (!solved)
      {
        FillSystem(I, cMass, phi.Damp); // for the direct path below
      }
    }
    else if (ns.HaveFactor && ns.FactorFree == I.Free)
    {
      solved = PreconditionedCG(I, gm, d);
    }
    for (int pass = 0; pass < 2 && !solved; ++pass)
    {
      if (pass == 1 || projectedBlocks)
      {
        if (!projectedBlocks)
        {
          ta = Clock::now();
          I.HyperGradient(I.x.data(), trial.data(), ns.Blocks.data(), true);
          FillSystem(I, cMass, phi.Damp);
          I.T.Assembly += Seconds(ta, Clock::now());
        }
        projectedBlocks = true;
        pass = 1;
      }
      if (!ns.Analyzed)
      {
#ifdef HOEMBED_HAVE_CHOLMOD
        ns.LLT.cholmod().print = 0; // a not positive definite exact Hessian is expected
#endif
        ns.LLT.analyzePattern(ns.H);
        ns.Analyzed = true;
      }
      auto tf = Clock::now();
      ns.LLT.factorize(ns.H);
      I.T.Factorization += Seconds(tf, Clock::now());
      I.T.Factorizations++;
      solved = ns.LLT.info() == Eigen::Success;
      ns.HaveFactor = solved;
      ns.FactorFree = I.Free;
      if (solved)
      {
        d = -ns.LLT.solve(gm);
      }
    }
    if (!solved)
    {
      error = "the Newton system is singular (clamp more nodes)";
      return -1;
    }
    for (long long k = 0; k < n3; ++k)
    {
      d[k] = I.Free[k] ? d[k] : 0.0;
    }
    const double slope = gm.dot(d);
    I.HyperInvertedCells(I.x.data(), ns.Inverted);
    double t = 1.0, next = value;
    bool accepted = false;
    for (int ls = 0; ls < 40; ++ls, t *= 0.5)
    {
      for (long long k = 0; k < n3; ++k)
      {
        trial[k] = I.x[k] + t * d[k];
      }
      // no cell that is not inverted now may become so (a state with det F <= 0 is
      // refused, however low its energy: the stable Neo-Hookean has no barrier)
      if (I.HyperInvertsMore(trial.data(), ns.Inverted))
      {
        continue;
      }
      next = phi.Value(trial, nullptr);
      // Armijo, with a round-off allowance: near the minimum Phi cannot resolve the
      // decrease of a tiny step
      if (std::isfinite(next) && next <= value + 1e-4 * t * slope + noise + 1e-14 * std::abs(value))
      {
        accepted = true;
        break;
      }
    }
    if (!accepted)
    {
      break; // no decrease left to find: at the minimum to round-off
    }
    if (backtracked && t < 1.0)
    {
      *backtracked = true;
    }
    I.x.swap(trial);
    // the gradient there only serves a next iteration (one Newton iteration per frame:
    // none; the state is the same either way)
    value = it + 1 < maxIterations ? phi.Value(I.x, g.data()) : next;
    double step = 0.0, moved = 0.0;
    for (long long k = 0; k < n3; ++k)
    {
      step = std::max(step, std::abs(t * d[k]));
      moved = std::max(moved, std::abs(I.x[k] - start[k]));
    }
    // converged; or stalled at round-off (no longer shrinking, far below the motion: the
    // stress of a tiny strain is a difference of terms of the order of the stiffness)
    if (step <= tolerance * moved || step <= floor ||
      (previous >= 0.0 && step >= 0.5 * previous && step <= 1e-5 * moved))
    {
      ++it;
      return it;
    }
    previous = step;
  }
  if (untilConverged && it >= maxIterations)
  {
    error = "Newton did not converge in MaxNewtonIterations iterations";
    return -1;
  }
  return it;
}

bool CorotationalSolver::Impl::HyperStep()
{
  auto t0 = Clock::now();
  const double dt = Dt;
  const long long n3 = 3 * NP;
  const std::vector<double> xn = x;
  std::vector<double> xhat(n3);
  for (long long k = 0; k < n3; ++k)
  {
    xhat[k] = x[k] + dt * v[k];
  }
  // held DOFs: prescribed ones on their (speed-limited) reach, clamped ones where they are
  const double limit = PrescribedSpeed * dt;
  for (long long p = 0; p < NP && NumberPrescribed > 0; ++p)
  {
    if (!PrescribedMask[p])
    {
      continue;
    }
    double d[3], n = 0.0;
    for (int i = 0; i < 3; ++i)
    {
      d[i] = X[3 * p + i] + Target[3 * p + i] - x[3 * p + i];
      n += d[i] * d[i];
    }
    n = std::sqrt(n);
    const bool capped = PrescribedSpeed > 0.0 && n > limit;
    for (int i = 0; i < 3; ++i)
    {
      x[3 * p + i] = capped ? x[3 * p + i] + d[i] * (limit / n) : X[3 * p + i] + Target[3 * p + i];
    }
  }
  // the held move may not invert a cell either (it is not part of the line search):
  // a move that would is shortened by halves (to none), and the prescribed nodes catch
  // up in the next steps, like a speed-limited drag
  if (NumberPrescribed > 0)
  {
    std::vector<char> was;
    HyperInvertedCells(xn.data(), was);
    const std::vector<double> full = x;
    double frac = 1.0;
    for (int k = 0; k < 12 && HyperInvertsMore(x.data(), was); ++k)
    {
      frac = k < 11 ? 0.5 * frac : 0.0;
      for (long long j = 0; j < n3; ++j)
      {
        x[j] = xn[j] + frac * (full[j] - xn[j]);
      }
    }
  }
  Potential phi{ *this };
  phi.CM = 1.0 / (dt * dt);
  phi.CA = Alpha / dt;
  phi.XHat = &xhat;
  phi.XN = &xn;
  auto& ns = *Newton;
  ns.Blocks.assign(9 * MN.nonZeros(), 0.0);
  ns.DampBlocks.clear();
  if (Beta > 0.0)
  {
    // stiffness damping: beta/dt times the (projected) Hessian at the step's start
    std::vector<double> g(n3);
    HyperGradient(x.data(), g.data(), ns.Blocks.data(), true);
    ns.DampBlocks.resize(ns.Blocks.size());
    for (size_t k = 0; k < ns.Blocks.size(); ++k)
    {
      ns.DampBlocks[k] = Beta / dt * ns.Blocks[k];
    }
    ns.DampValues.assign(A.nonZeros(), 0.0);
    for (long long k = 0; k < A.nonZeros(); ++k)
    {
      const int s = AFromS[k];
      ns.DampValues[k] = s >= 0 ? Beta / dt * ns.Blocks[s] : 0.0;
    }
    phi.Damp = true;
    ns.BlocksReady = true; // the first Newton iteration's Hessian (projected: positive
                           // semi-definite, equal to the exact one where that is)
  }
  std::string error;
  const int it =
    NewtonSolve(*this, phi, 1.0 / (dt * dt) + Alpha / dt, NewtonMaxIt, NewtonTol, false, error);
  LastNewtonIt = it;
  bool finite = it >= 0;
  for (long long k = 0; k < n3; ++k)
  {
    v[k] = (x[k] - xn[k]) / dt;
    finite = finite && std::isfinite(x[k]) && std::isfinite(v[k]);
  }
  RotationsValid = false;
  T.Solve += Seconds(t0, Clock::now());
  T.Steps++;
  T.Iterations += std::max(it, 0);
  StepCount++;
  return finite;
}

namespace
{
// det F > 0 at every quadrature point of the current positions
bool AllPositive(const CorotationalSolver::Impl& I)
{
  double F[9];
  for (long long e = 0; e < I.NC; ++e)
  {
    for (int q = 0; q < I.HQ; ++q)
    {
      DeformationGradient(I.N, &I.Conn[e * I.N], I.x.data(), &I.HG[(e * I.HQ + q) * I.N * 3], F);
      const double J = F[0] * (F[4] * F[8] - F[5] * F[7]) - F[1] * (F[3] * F[8] - F[5] * F[6]) +
        F[2] * (F[3] * F[7] - F[4] * F[6]);
      if (!(J > 0.0))
      {
        return false;
      }
    }
  }
  return true;
}
} // namespace

bool CorotationalSolver::Impl::HyperStatic(int maxIterations, double tolerance, std::string& error)
{
  // Continuation: the loads (forces and prescribed displacements) applied in S equal
  // increments, each solved by Newton; S = 1, 2, 4, ... until every increment converges
  // without line-search backtracking from a start without inverted quadrature points
  // (the last try, 256 increments, accepts both). A large prescribed displacement applied at once
  // can start from inverted elements (infinite Mooney-Rivlin energy), and St. Venant-Kirchhoff
  // under 30% compression has more than one equilibrium: Newton from rest under the full load
  // reached another one than the path of increasing load (which scikit-fem's incremental
  // reference follows).
  const std::vector<double> x0 = x, fFull = FExt;
  std::vector<double> goal(3 * NP);
  for (long long k = 0; k < 3 * NP; ++k)
  {
    goal[k] = (NumberPrescribed > 0 && PrescribedMask[k / 3]) ? X[k] + Target[k] : x0[k];
  }
  Potential phi{ *this };
  Newton->Blocks.assign(9 * MN.nonZeros(), 0.0);
  int total = 0;
  bool ok = false;
  for (int S = 1; S <= 256 && !ok; S *= 2)
  {
    x = x0;
    ok = true;
    total = 0;
    error.clear();
    for (int s = 1; s <= S && ok; ++s)
    {
      const double frac = static_cast<double>(s) / S;
      for (long long k = 0; k < 3 * NP; ++k)
      {
        FExt[k] = frac * fFull[k];
        if (!Free[k])
        {
          x[k] = x0[k] + frac * (goal[k] - x0[k]); // held: clamped ones stay (goal = x0)
        }
      }
      if (S < 256 && !AllPositive(*this))
      {
        ok = false; // the increment inverts elements before it is solved
        break;
      }
      bool backtracked = false;
      const int it = NewtonSolve(
        *this, phi, 0.0, maxIterations, tolerance, true, error, S < 256 ? &backtracked : nullptr);
      ok = it >= 0 && !backtracked;
      total += std::max(it, 0);
    }
  }
  FExt = fFull;
  LastNewtonIt = total;
  std::fill(v.begin(), v.end(), 0.0);
  std::fill(dv.begin(), dv.end(), 0.0);
  RotationsValid = false;
  return ok;
}

void CorotationalSolver::Impl::HyperVonMises(double* stress) const
{
  // Cauchy stress sigma = P F^T / J at the centroid (|J| floored: an inverted or flat
  // element still gets a finite number)
  ParallelFor(NC, ParallelCells, [&](vtkIdType begin, vtkIdType end) {
    double F[9], P[9];
    for (vtkIdType e = begin; e < end; ++e)
    {
      DeformationGradient(N, &Conn[e * N], x.data(), &G[e * N * 3], F);
      Law.Stress(F, P);
      const double J = F[0] * (F[4] * F[8] - F[5] * F[7]) - F[1] * (F[3] * F[8] - F[5] * F[6]) +
        F[2] * (F[3] * F[7] - F[4] * F[6]);
      const double s = 1.0 / std::max(std::abs(J), 1e-12);
      double sg[9];
      for (int i = 0; i < 3; ++i)
      {
        for (int j = 0; j < 3; ++j)
        {
          sg[3 * i + j] =
            s * (P[3 * i] * F[3 * j] + P[3 * i + 1] * F[3 * j + 1] + P[3 * i + 2] * F[3 * j + 2]);
        }
      }
      const double a = sg[0] - sg[4], b = sg[4] - sg[8], c = sg[8] - sg[0];
      const double vm = std::sqrt(
        0.5 * (a * a + b * b + c * c) + 3.0 * (sg[1] * sg[1] + sg[2] * sg[2] + sg[5] * sg[5]));
      stress[e] = std::isfinite(vm) ? vm : 0.0;
    }
  });
}

void CorotationalSolver::SetMaterial(int material, double c10, double c01)
{
  Impl& I = *this->P;
  I.Mat = static_cast<Material>(material);
  if (I.Mat != Material::Corotated)
  {
    I.Law = HyperelasticLaw::Make(I.Mat, I.Young, I.Poisson, c10, c01);
    I.InitializeHyper();
  }
}

void CorotationalSolver::SetNewtonControls(double tolerance, int maxIterations)
{
  this->P->NewtonTol = tolerance;
  this->P->NewtonMaxIt = std::max(1, maxIterations);
}

int CorotationalSolver::GetLastNewtonIterations() const
{
  return this->P->LastNewtonIt;
}
} // namespace hoembed
