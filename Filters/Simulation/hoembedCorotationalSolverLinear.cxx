#include "hoembedCorotationalSolver.h"
#include "hoembedCorotationalSolverImpl.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace hoembed
{
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
  if (!Analyzed)
  {
    Analyze();
    Analyzed = true;
  }
  double* pv = Permuted.valuePtr();
  for (long long k = 0; k < A0.nonZeros(); ++k)
  {
    if (PermValue[k] >= 0)
    {
      pv[PermValue[k]] = val[k];
    }
  }
  if (Large())
  {
    LargeLLT.factorize(Permuted);
    BuildLargeBlocks();
  }
  else
  {
    SmallLLT.factorize(Permuted);
    if (SmallLLT.info() == Eigen::Success)
    {
      const ColMat& L = SmallLLT.matrixL().nestedExpression();
      SmallBlocks.Build(static_cast<int>(L.cols()), L.outerIndexPtr(), L.innerIndexPtr(),
        L.valuePtr());
    }
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
  T.Factorizations++;
  T.Factorization += FactorSeconds;
  SolveSinceFactor = 0.0;
  IterationsSinceFactor = 0;
  return FactorOK();
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
    const int* perm = nodeAnalysis.Factor() ? static_cast<const int*>(nodeAnalysis.Factor()->Perm) : nullptr;
    for (long long k = 0; k < NP; ++k)
    {
      NodeNew[perm ? perm[k] : k] = static_cast<int>(k);
    }
    cholmod_common& c = LargeLLT.cholmod();
    c.nmethods = 1;
    c.method[0].ordering = CHOLMOD_NATURAL; // the matrix comes permuted
    c.postorder = 0;                        // keep it so (node blocks stay in order)
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
  Permuted.resize(3 * NP, 3 * NP);
  Permuted.setFromTriplets(trip.begin(), trip.end());
  Permuted.makeCompressed();
  PermValue.assign(A.nonZeros(), -1);
  for (long long j = 0; j < Permuted.nonZeros(); ++j)
  {
    PermValue[static_cast<long long>(Permuted.valuePtr()[j])] = static_cast<int>(j);
  }
  if (Large())
  {
    LargeLLT.analyzePattern(Permuted);
  }
  else
  {
    SmallLLT.analyzePattern(Permuted);
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
void CorotationalSolver::Impl::BuildLargeBlocks()
{
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
        [&](int col, const int*& rows, const double*& values, int& count)
        {
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
    SmallBlocks.Solve(t.data());
  }
  else if (UseLargeBlocks)
  {
    LargeBlocks.Solve(t.data());
  }
  else
  {
    t = LargeLLT.solve(t).eval();
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
