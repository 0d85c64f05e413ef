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
    // CHOLMOD's own choice (AMD / METIS, postordered) on the node graph
    LargeFactorization nodeAnalysis;
    nodeAnalysis.cholmod().nmethods = 2; // both, the one with the least fill wins
    nodeAnalysis.cholmod().method[0].ordering = CHOLMOD_AMD;
    nodeAnalysis.cholmod().method[1].ordering = CHOLMOD_METIS;
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

template <typename T>
void BlockFactor<T>::Build(int n, const int* colPtr, const int* rowIdx, const double* val)
{
  NB = n / 3;
  DiagInv.assign(9 * NB, 0.0);
  Ptr.assign(NB + 1, 0);
  Row.clear();
  Val.clear();
  std::vector<int> slot(NB, -1);
  for (int J = 0; J < NB; ++J)
  {
    Eigen::Matrix3d Djj = Eigen::Matrix3d::Zero();
    for (int b = 0; b < 3; ++b)
    {
      for (int k = colPtr[3 * J + b]; k < colPtr[3 * J + b + 1]; ++k)
      {
        const int I = rowIdx[k] / 3, a = rowIdx[k] % 3;
        if (I == J)
        {
          Djj(a, b) = val[k];
          continue;
        }
        if (slot[I] < 0)
        {
          slot[I] = static_cast<int>(Row.size());
          Row.push_back(I);
          Val.insert(Val.end(), 9, T(0));
        }
        Val[9 * slot[I] + 3 * a + b] = static_cast<T>(val[k]);
      }
    }
    for (int k = Ptr[J]; k < static_cast<int>(Row.size()); ++k)
    {
      slot[Row[k]] = -1;
    }
    Ptr[J + 1] = static_cast<int>(Row.size());
    Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> inv(&DiagInv[9 * J]);
    inv = Djj.triangularView<Eigen::Lower>().solve(Eigen::Matrix3d::Identity());
  }
}

template <typename T>
void BlockFactor<T>::Solve(double* t) const
{
  const T* B = Val.data();
  for (int J = 0; J < NB; ++J) // L y = t
  {
    const double* Di = &DiagInv[9 * J];
    double* tj = t + 3 * J;
    const double y0 = Di[0] * tj[0];
    const double y1 = Di[3] * tj[0] + Di[4] * tj[1];
    const double y2 = Di[6] * tj[0] + Di[7] * tj[1] + Di[8] * tj[2];
    tj[0] = y0;
    tj[1] = y1;
    tj[2] = y2;
    for (int k = Ptr[J]; k < Ptr[J + 1]; ++k)
    {
      const T* b = B + 9 * k;
      double* ti = t + 3 * Row[k];
      ti[0] -= b[0] * y0 + b[1] * y1 + b[2] * y2;
      ti[1] -= b[3] * y0 + b[4] * y1 + b[5] * y2;
      ti[2] -= b[6] * y0 + b[7] * y1 + b[8] * y2;
    }
  }
  for (int J = NB - 1; J >= 0; --J) // L^T x = y
  {
    double* tj = t + 3 * J;
    double s0 = tj[0], s1 = tj[1], s2 = tj[2];
    for (int k = Ptr[J]; k < Ptr[J + 1]; ++k)
    {
      const T* b = B + 9 * k;
      const double* ti = t + 3 * Row[k];
      s0 -= b[0] * ti[0] + b[3] * ti[1] + b[6] * ti[2];
      s1 -= b[1] * ti[0] + b[4] * ti[1] + b[7] * ti[2];
      s2 -= b[2] * ti[0] + b[5] * ti[1] + b[8] * ti[2];
    }
    const double* Di = &DiagInv[9 * J];
    tj[0] = Di[0] * s0 + Di[3] * s1 + Di[6] * s2;
    tj[1] = Di[4] * s1 + Di[7] * s2;
    tj[2] = Di[8] * s2;
  }
}

template struct BlockFactor<double>;
template struct BlockFactor<float>;

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
  cholmod_factor* F = cholmod_copy_factor(LargeLLT.Factor(), &c);
  if (!F)
  {
    return;
  }
  if (cholmod_change_factor(CHOLMOD_REAL, 1, 0, 1, 1, F, &c) && F->is_ll && !F->is_super &&
    static_cast<long long>(F->n) == 3 * NP)
  {
    const int* perm = static_cast<const int*>(F->Perm);
    bool blocked = true; // the factor is in the order of the permuted matrix
    for (long long k = 0; perm && blocked && k < 3 * NP; ++k)
    {
      blocked = perm[k] == k;
    }
    if (blocked)
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
        SymmetricTimes(D, &Ke[e * D * D], l, w);
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
} // namespace hoembed
