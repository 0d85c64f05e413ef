// hoembed::corotational_detail::BlockFactor: a sparse Cholesky factor in 3x3 node blocks,
// its triangular solves (serial, or in two groups of independent subtrees on two
// threads). See hoembedCorotationalSolverImpl.h.
#include "hoembedCorotationalSolverImpl.h"

#include <algorithm>
#include <cmath>
#if defined(__AVX2__) && defined(__FMA__)
#include <immintrin.h>
#endif
#include <vector>

namespace hoembed
{
namespace corotational_detail
{
template <typename T>
void BlockFactor<T>::Build(int n, const int* colPtr, const int* rowIdx, const double* val)
{
  Build(n, [&](int c, const int*& rows, const double*& values, int& count) {
    rows = rowIdx + colPtr[c];
    values = val + colPtr[c];
    count = colPtr[c + 1] - colPtr[c];
  });
}

template <typename T>
void BlockFactor<T>::Build(int n, const ColumnSource& columns)
{
  NB = n / 3;
  // row scaling d_i = 1 / sqrt((L L^T)_ii): the stored factor D L has entries in [-1, 1]
  Scale.assign(n, 0.0);
  const int* rowIdx = nullptr;
  const double* val = nullptr;
  int count = 0;
  for (int c = 0; c < n; ++c)
  {
    columns(c, rowIdx, val, count);
    for (int k = 0; k < count; ++k)
    {
      Scale[rowIdx[k]] += val[k] * val[k];
    }
  }
  for (int i = 0; i < n; ++i)
  {
    Scale[i] = Scale[i] > 0.0 ? 1.0 / std::sqrt(Scale[i]) : 1.0;
  }
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
      columns(3 * J + b, rowIdx, val, count);
      for (int k = 0; k < count; ++k)
      {
        const int I = rowIdx[k] / 3, a = rowIdx[k] % 3;
        const double lv = val[k] * Scale[rowIdx[k]];
        if (I == J)
        {
          Djj(a, b) = lv;
          continue;
        }
        if (slot[I] < 0)
        {
          slot[I] = static_cast<int>(Row.size());
          Row.push_back(I);
          Val.insert(Val.end(), 12, T(0));
        }
        Val[12 * slot[I] + 4 * b + a] = static_cast<T>(lv); // column b, row a
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
  Buffer[0].assign(4 * Top.size(), 0.0);
  Buffer[1].assign(4 * Top.size(), 0.0);
  Split = true;
}

#if defined(__AVX2__) && defined(__FMA__)
namespace
{
inline __m256d Load4(const double* p)
{
  return _mm256_loadu_pd(p);
}
inline __m256d Load4(const float* p)
{
  return _mm256_cvtps_pd(_mm_loadu_ps(p));
}
#ifdef HOEMBED_HALF_FACTOR
inline __m256d Load4(const HalfValue* p)
{
  return _mm256_cvtps_pd(_mm_cvtph_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(p))));
}
#endif
inline double Sum4(__m256d v)
{
  const __m128d h = _mm_add_pd(_mm256_castpd256_pd128(v), _mm256_extractf128_pd(v, 1));
  return _mm_cvtsd_f64(_mm_add_sd(h, _mm_unpackhi_pd(h, h)));
}
} // namespace
#endif

// L y = t on the given columns (ascending); t has 4 doubles per node (the 4th unused);
// updates of top rows go to `buffer` (same layout, indexed by TopSlot) when given
template <typename T>
void BlockFactor<T>::Forward(const int* cols, std::size_t n, double* t, double* buffer) const
{
  const T* B = Val.data();
  for (std::size_t c = 0; c < n; ++c)
  {
    const int J = cols[c];
    const double* Di = &DiagInv[9 * J];
    double* tj = t + 4 * J;
    const double y0 = Di[0] * tj[0];
    const double y1 = Di[3] * tj[0] + Di[4] * tj[1];
    const double y2 = Di[6] * tj[0] + Di[7] * tj[1] + Di[8] * tj[2];
    tj[0] = y0;
    tj[1] = y1;
    tj[2] = y2;
#if defined(__AVX2__) && defined(__FMA__)
    const __m256d Y0 = _mm256_set1_pd(y0), Y1 = _mm256_set1_pd(y1), Y2 = _mm256_set1_pd(y2);
#endif
    for (int k = Ptr[J]; k < Ptr[J + 1]; ++k)
    {
      const T* b = B + 12 * k;
      const int I = Row[k];
      double* ti = (buffer && TopSlot[I] >= 0) ? buffer + 4 * TopSlot[I] : t + 4 * I;
#if defined(__AVX2__) && defined(__FMA__)
      __m256d acc = _mm256_loadu_pd(ti);
      acc = _mm256_fnmadd_pd(Load4(b), Y0, acc);
      acc = _mm256_fnmadd_pd(Load4(b + 4), Y1, acc);
      acc = _mm256_fnmadd_pd(Load4(b + 8), Y2, acc);
      _mm256_storeu_pd(ti, acc);
#else
      ti[0] -= b[0] * y0 + b[4] * y1 + b[8] * y2;
      ti[1] -= b[1] * y0 + b[5] * y1 + b[9] * y2;
      ti[2] -= b[2] * y0 + b[6] * y1 + b[10] * y2;
#endif
    }
  }
}

// L^T x = y on the given columns (processed in descending order), t as in Forward
template <typename T>
void BlockFactor<T>::Backward(const int* cols, std::size_t n, double* t) const
{
  const T* B = Val.data();
  for (std::size_t c = n; c-- > 0;)
  {
    const int J = cols[c];
    double* tj = t + 4 * J;
    double s0 = tj[0], s1 = tj[1], s2 = tj[2];
#if defined(__AVX2__) && defined(__FMA__)
    __m256d a0 = _mm256_setzero_pd(), a1 = _mm256_setzero_pd(), a2 = _mm256_setzero_pd();
    for (int k = Ptr[J]; k < Ptr[J + 1]; ++k)
    {
      const T* b = B + 12 * k;
      const __m256d ti = _mm256_loadu_pd(t + 4 * Row[k]); // 4th entry: 0 * padding
      a0 = _mm256_fmadd_pd(Load4(b), ti, a0);
      a1 = _mm256_fmadd_pd(Load4(b + 4), ti, a1);
      a2 = _mm256_fmadd_pd(Load4(b + 8), ti, a2);
    }
    s0 -= Sum4(a0);
    s1 -= Sum4(a1);
    s2 -= Sum4(a2);
#else
    for (int k = Ptr[J]; k < Ptr[J + 1]; ++k)
    {
      const T* b = B + 12 * k;
      const double* ti = t + 4 * Row[k];
      s0 -= b[0] * ti[0] + b[1] * ti[1] + b[2] * ti[2];
      s1 -= b[4] * ti[0] + b[5] * ti[1] + b[6] * ti[2];
      s2 -= b[8] * ti[0] + b[9] * ti[1] + b[10] * ti[2];
    }
#endif
    const double* Di = &DiagInv[9 * J];
    tj[0] = Di[0] * s0 + Di[3] * s1 + Di[6] * s2;
    tj[1] = Di[4] * s1 + Di[7] * s2;
    tj[2] = Di[8] * s2;
  }
}

template <typename T>
void BlockFactor<T>::Solve(double* t3) const
{
  // work on 4 doubles per node (vectorised blocks); the 4th entries stay 0
  Work.resize(4 * static_cast<std::size_t>(NB));
  double* t = Work.data();
  // (L L^T)^-1 = D (DL (DL)^T)^-1 D
  for (int J = 0; J < NB; ++J)
  {
    t[4 * J] = Scale[3 * J] * t3[3 * J];
    t[4 * J + 1] = Scale[3 * J + 1] * t3[3 * J + 1];
    t[4 * J + 2] = Scale[3 * J + 2] * t3[3 * J + 2];
    t[4 * J + 3] = 0.0;
  }
  SolveWork(t);
  for (int J = 0; J < NB; ++J)
  {
    t3[3 * J] = Scale[3 * J] * t[4 * J];
    t3[3 * J + 1] = Scale[3 * J + 1] * t[4 * J + 1];
    t3[3 * J + 2] = Scale[3 * J + 2] * t[4 * J + 2];
  }
}

template <typename T>
void BlockFactor<T>::SolveWork(double* t) const
{
  if (!Split)
  {
    Forward(All.data(), All.size(), t, nullptr);
    Backward(All.data(), All.size(), t);
    return;
  }
  // the same arithmetic on 1 or 2 threads (bitwise the same result)
  const bool parallel = ParallelThreadCount() >= 2;
  auto groups = [&](bool forward) {
    auto run = [&](vtkIdType begin, vtkIdType end) {
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
      ParallelLoop<vtkIdType>(0, 2, 1, run);
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
      t[4 * Top[s] + i] += Buffer[0][4 * s + i] + Buffer[1][4 * s + i];
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
#ifdef HOEMBED_HALF_FACTOR
template struct BlockFactor<HalfValue>;
#endif
} // namespace corotational_detail
} // namespace hoembed
