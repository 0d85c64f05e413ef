// hoembed::corotational_detail::BlockFactor: a sparse Cholesky factor in 3x3 node blocks,
// its triangular solves (serial, or in two groups of independent subtrees on two
// threads). See hoembedCorotationalSolverImpl.h.
#include "hoembedCorotationalSolverImpl.h"

#include <algorithm>
#include <vector>

namespace hoembed
{
namespace corotational_detail
{
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
  All.resize(NB);
  for (int J = 0; J < NB; ++J)
  {
    All[J] = J;
  }
  Split = false;
  if (NB >= SplitNodes)
  {
    PlanSplit();
  }
}

template <typename T>
void BlockFactor<T>::PlanSplit()
{
  // elimination tree: the parent of column J is its first off-diagonal block row
  std::vector<int> parent(NB, -1);
  std::vector<long long> work(NB, 0); // blocks in the subtree (plus one per column)
  for (int J = 0; J < NB; ++J)
  {
    int p = NB;
    for (int k = Ptr[J]; k < Ptr[J + 1]; ++k)
    {
      p = std::min(p, Row[k]);
    }
    parent[J] = p < NB ? p : -1;
  }
  std::vector<std::vector<int>> children(NB);
  std::vector<int> frontier;
  for (int J = 0; J < NB; ++J) // parents come after their children
  {
    work[J] += Ptr[J + 1] - Ptr[J] + 1;
    if (parent[J] >= 0)
    {
      work[parent[J]] += work[J];
      children[parent[J]].push_back(J);
    }
    else
    {
      frontier.push_back(J);
    }
  }
  long long total = 0;
  for (int r : frontier)
  {
    total += work[r];
  }
  // Move the heaviest subtree root of the frontier into the top while the frontier cannot
  // be split into two groups within 55 / 45 (or the top would hold over a third).
  std::vector<int> owner(NB, -2); // -1: top, 0 / 1: group
  long long topWork = 0;
  for (;;)
  {
    std::sort(frontier.begin(), frontier.end(), [&](int a, int b) { return work[a] > work[b]; });
    long long bins[2] = { 0, 0 }, sum = 0;
    for (int r : frontier)
    {
      bins[bins[1] < bins[0] ? 1 : 0] += work[r];
      sum += work[r];
    }
    if (frontier.empty() || 3 * topWork > total)
    {
      return; // no useful split
    }
    if (std::max(bins[0], bins[1]) <= 0.55 * sum)
    {
      bins[0] = bins[1] = 0;
      for (int r : frontier)
      {
        const int g = bins[1] < bins[0] ? 1 : 0;
        bins[g] += work[r];
        owner[r] = g;
      }
      break;
    }
    const int c = frontier.front();
    frontier.erase(frontier.begin());
    owner[c] = -1;
    topWork += Ptr[c + 1] - Ptr[c] + 1;
    frontier.insert(frontier.end(), children[c].begin(), children[c].end());
  }
  for (int J = NB - 1; J >= 0; --J)
  {
    if (owner[J] == -2)
    {
      owner[J] = owner[parent[J]]; // a column outside the top and the frontier
    }
  }
  Group[0].clear();
  Group[1].clear();
  Top.clear();
  TopSlot.assign(NB, -1);
  for (int J = 0; J < NB; ++J)
  {
    if (owner[J] < 0)
    {
      TopSlot[J] = static_cast<int>(Top.size());
      Top.push_back(J);
    }
    else
    {
      Group[owner[J]].push_back(J);
    }
  }
  Buffer[0].assign(3 * Top.size(), 0.0);
  Buffer[1].assign(3 * Top.size(), 0.0);
  Split = true;
}

// L y = t on the given columns (ascending); updates of top rows go to `buffer` when given
template <typename T>
void BlockFactor<T>::Forward(const int* cols, std::size_t n, double* t, double* buffer) const
{
  const T* B = Val.data();
  for (std::size_t c = 0; c < n; ++c)
  {
    const int J = cols[c];
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
      const int I = Row[k];
      double* ti = (buffer && TopSlot[I] >= 0) ? buffer + 3 * TopSlot[I] : t + 3 * I;
      ti[0] -= b[0] * y0 + b[1] * y1 + b[2] * y2;
      ti[1] -= b[3] * y0 + b[4] * y1 + b[5] * y2;
      ti[2] -= b[6] * y0 + b[7] * y1 + b[8] * y2;
    }
  }
}

// L^T x = y on the given columns (processed in descending order)
template <typename T>
void BlockFactor<T>::Backward(const int* cols, std::size_t n, double* t) const
{
  const T* B = Val.data();
  for (std::size_t c = n; c-- > 0;)
  {
    const int J = cols[c];
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

template <typename T>
void BlockFactor<T>::Solve(double* t) const
{
  if (!Split)
  {
    Forward(All.data(), All.size(), t, nullptr);
    Backward(All.data(), All.size(), t);
    return;
  }
  // the same arithmetic on 1 or 2 threads (bitwise the same result)
  const bool parallel = vtkSMPTools::GetEstimatedNumberOfThreads() >= 2;
  auto groups = [&](bool forward)
  {
    auto run = [&](vtkIdType begin, vtkIdType end)
    {
      for (vtkIdType g = begin; g < end; ++g)
      {
        if (forward)
        {
          Forward(Group[g].data(), Group[g].size(), t, Buffer[g].data());
        }
        else
        {
          Backward(Group[g].data(), Group[g].size(), t);
        }
      }
    };
    if (parallel)
    {
      vtkSMPTools::For(0, 2, 1, run);
    }
    else
    {
      run(0, 2);
    }
  };
  groups(true);
  for (std::size_t s = 0; s < Top.size(); ++s)
  {
    for (int i = 0; i < 3; ++i)
    {
      t[3 * Top[s] + i] += Buffer[0][3 * s + i] + Buffer[1][3 * s + i];
    }
  }
  std::fill(Buffer[0].begin(), Buffer[0].end(), 0.0);
  std::fill(Buffer[1].begin(), Buffer[1].end(), 0.0);
  Forward(Top.data(), Top.size(), t, nullptr);
  Backward(Top.data(), Top.size(), t);
  groups(false);
}

template struct BlockFactor<double>;
template struct BlockFactor<float>;
} // namespace corotational_detail
} // namespace hoembed
