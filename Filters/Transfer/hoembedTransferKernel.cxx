#include "hoembedTransferKernel.h"

#include "hoembedElementGeometry.h"
#include "hoembedQuadraticMap.h"
#include "hoembedShapeFunctions.h"

#include <cmath>
#include <cstdint>
#include <limits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace hoembed
{
namespace
{
// The coefficient tables hold Core's monomial maps (MakeTetMap, MakeTriangleMap: the one
// expansion of the shape functions) in the per-vertex loop's layout: x = C + sum_i L_i xi_i
// + sum_i (Q_ii / 2) xi_i^2 + sum_{i<j} Q_ij xi_i xi_j. Halving is exact.
void StoreMap(const QuadraticMap& m, bool quadratic, double* k)
{
  const int dim = m.Dim;
  for (int d = 0; d < 3; ++d)
  {
    k[d] = m.C[d];
    for (int i = 0; i < dim; ++i)
      k[3 * (1 + i) + d] = m.L[i][d];
    if (!quadratic)
      continue;
    for (int i = 0; i < dim; ++i)
      k[3 * (1 + dim + i) + d] = 0.5 * m.Q[i][i][d];
    int c = 1 + 2 * dim;
    for (int i = 0; i < dim; ++i)
      for (int j = i + 1; j < dim; ++j, ++c)
        k[3 * c + d] = m.Q[i][j][d];
  }
}
} // namespace

void ComputeCellMapCoefficients(const std::int64_t* conn, int nodesPerCell, const double* points,
  std::int64_t begin, std::int64_t end, double* coeffs)
{
  const int csize = CellCoefficientSize(nodesPerCell);
  double x[30];
  QuadraticMap m;
  for (std::int64_t c = begin; c < end; ++c)
  {
    const std::int64_t* ids = conn + nodesPerCell * c;
    for (int a = 0; a < nodesPerCell; ++a)
      for (int d = 0; d < 3; ++d)
        x[3 * a + d] = points[3 * ids[a] + d];
    MakeTetMap(x, nodesPerCell, m);
    StoreMap(m, nodesPerCell == 10, coeffs + csize * c);
  }
}

void ComputeFaceNormalCoefficients(const TetMeshTopology& topo, const double* nodalNormals,
  std::int64_t begin, std::int64_t end, double* coeffs)
{
  const int npf = topo.GetNodesPerFace();
  const int fsize = npf == 6 ? 18 : 9;
  double n[18];
  QuadraticMap m;
  for (std::int64_t f = begin; f < end; ++f)
  {
    const TetMeshTopology::Id* fn = &topo.BoundaryFaceNodes[npf * f];
    for (int a = 0; a < npf; ++a)
      for (int d = 0; d < 3; ++d)
        n[3 * a + d] = nodalNormals[3 * fn[a] + d];
    MakeTriangleMap(n, npf, m);
    StoreMap(m, npf == 6, coeffs + fsize * f);
  }
}

void TetParametricToFace(int face, const double pc[3], double uv[2])
{
  const double L[4] = { 1.0 - pc[0] - pc[1] - pc[2], pc[0], pc[1], pc[2] };
  const double la = L[TetFaceNodes[face][0]];
  const double lb = L[TetFaceNodes[face][1]];
  const double lc = L[TetFaceNodes[face][2]];
  const double sum = la + lb + lc;
  const double inv = sum != 0.0 ? 1.0 / sum : 1.0;
  uv[0] = lb * inv;
  uv[1] = lc * inv;
}

std::int32_t DeduceBoundaryFace(
  const TetMeshTopology& topo, std::int64_t cell, const double pc[3], double tol)
{
  const double L[4] = { 1.0 - pc[0] - pc[1] - pc[2], pc[0], pc[1], pc[2] };
  std::int32_t best = -1;
  double bestValue = tol;
  for (int f = 0; f < 4; ++f)
  {
    const TetMeshTopology::Id b = topo.CellBoundaryFace[4 * cell + f];
    if (b < 0)
    {
      continue;
    }
    const double value = std::fabs(L[TetFaceOpposite[f]]);
    if (value <= bestValue)
    {
      bestValue = value;
      best = static_cast<std::int32_t>(4 * b + f);
    }
  }
  return best;
}

namespace
{
// p' of one entry from its cell's map coefficients.
inline void MapPoint(const TransferEntry& e, bool quadratic, const double* cellCoeffs, double x[3])
{
  const double r = e.PC[0], s = e.PC[1], t = e.PC[2];
  if (quadratic)
  {
    const double* k = cellCoeffs + 30 * static_cast<std::int64_t>(e.Cell);
    const double rr = r * r, ss = s * s, tt = t * t, rs = r * s, rt = r * t, st = s * t;
    for (int d = 0; d < 3; ++d)
    {
      // Summed as a tree: short dependency chains.
      x[d] = ((k[d] + k[3 + d] * r) + (k[6 + d] * s + k[9 + d] * t)) +
        ((k[12 + d] * rr + k[15 + d] * ss) + (k[18 + d] * tt + k[21 + d] * rs)) +
        (k[24 + d] * rt + k[27 + d] * st);
    }
  }
  else
  {
    const double* k = cellCoeffs + 12 * static_cast<std::int64_t>(e.Cell);
    for (int d = 0; d < 3; ++d)
    {
      x[d] = (k[d] + k[3 + d] * r) + (k[6 + d] * s + k[9 + d] * t);
    }
  }
}

// The plain kernel: the per-vertex arithmetic (ScalarOps) and the block loop over the plan
// (EvaluateBlocks). hoembedTransferKernelAvx2.cxx repeats these operations, in this order,
// four vertices at a time: they fix each output's bits.
// Barycentric coordinate of the face corners (a, b, c) as indices into L = (L0, r, s, t).
struct FaceCorners
{
  int A, B, C;
};
const FaceCorners kFaceCorners[4] = { { TetFaceNodes[0][0], TetFaceNodes[0][1],
                                        TetFaceNodes[0][2] },
  { TetFaceNodes[1][0], TetFaceNodes[1][1], TetFaceNodes[1][2] },
  { TetFaceNodes[2][0], TetFaceNodes[2][1], TetFaceNodes[2][2] },
  { TetFaceNodes[3][0], TetFaceNodes[3][1], TetFaceNodes[3][2] } };

// scale = w / sqrt(len2) (0 where len2 = 0), two entries at a time with SSE2.
inline void OffsetScales(const double* len2, const double* w, double* scale, int m)
{
  int j = 0;
#if defined(__SSE2__)
  const __m128d zero = _mm_setzero_pd();
  const __m128d one = _mm_set1_pd(1.0);
  for (; j + 1 < m; j += 2)
  {
    const __m128d l = _mm_loadu_pd(len2 + j);
    const __m128d positive = _mm_cmpgt_pd(l, zero);
    const __m128d safe = _mm_or_pd(_mm_and_pd(positive, l), _mm_andnot_pd(positive, one));
    const __m128d q = _mm_div_pd(_mm_loadu_pd(w + j), _mm_sqrt_pd(safe));
    _mm_storeu_pd(scale + j, _mm_and_pd(positive, q));
  }
#endif
  for (; j < m; ++j)
  {
    scale[j] = len2[j] > 0.0 ? w[j] / std::sqrt(len2[j]) : 0.0;
  }
}

// The columns a = dx/dr, b = dx/ds, c = dx/dt of a cell map at (r, s, t) from its
// monomial coefficients (the header's layout; Q_ii / 2 is stored, hence the 2).
inline void MapJacobian(const double* k, bool quadratic, double r, double s, double t, double a[3],
  double b[3], double c[3])
{
  for (int d = 0; d < 3; ++d)
  {
    a[d] = k[3 + d];
    b[d] = k[6 + d];
    c[d] = k[9 + d];
    if (quadratic)
    {
      a[d] += (2.0 * k[12 + d] * r + k[21 + d] * s) + k[24 + d] * t;
      b[d] += (2.0 * k[15 + d] * s + k[21 + d] * r) + k[27 + d] * t;
      c[d] += (2.0 * k[18 + d] * t + k[24 + d] * r) + k[27 + d] * s;
    }
  }
}

// cof(J) m = m0 (b x c) + m1 (c x a) + m2 (a x b) for J = [a b c].
inline void CofactorTimes(
  const double a[3], const double b[3], const double c[3], const double m[3], double n[3])
{
  const double bc[3] = { b[1] * c[2] - b[2] * c[1], b[2] * c[0] - b[0] * c[2],
    b[0] * c[1] - b[1] * c[0] };
  const double ca[3] = { c[1] * a[2] - c[2] * a[1], c[2] * a[0] - c[0] * a[2],
    c[0] * a[1] - c[1] * a[0] };
  const double ab[3] = { a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
    a[0] * b[1] - a[1] * b[0] };
  for (int d = 0; d < 3; ++d)
  {
    n[d] = (m[0] * bc[d] + m[1] * ca[d]) + m[2] * ab[d];
  }
}

// det [a b c] = a . (b x c), bc = b x c given (the sign decides; one order for all Ops).
inline double Det(const double a[3], const double bc[3])
{
  return (a[0] * bc[0] + a[1] * bc[1]) + a[2] * bc[2];
}

// cof([a b c]) m into n; returns det [a b c].
inline double CofactorDet(
  const double a[3], const double b[3], const double c[3], const double m[3], double n[3])
{
  CofactorTimes(a, b, c, m, n);
  const double bc[3] = { b[1] * c[2] - b[2] * c[1], b[2] * c[0] - b[0] * c[2],
    b[0] * c[1] - b[1] * c[0] };
  return Det(a, bc);
}

struct ScalarOps
{
  static void Map(const double* k, bool quadratic, double r, double s, double t, double x[3])
  {
    if (quadratic)
    {
      const double rr = r * r, ss = s * s, tt = t * t, rs = r * s, rt = r * t, st = s * t;
      for (int d = 0; d < 3; ++d)
      {
        // Summed as a tree: short dependency chains.
        x[d] = ((k[d] + k[3 + d] * r) + (k[6 + d] * s + k[9 + d] * t)) +
          ((k[12 + d] * rr + k[15 + d] * ss) + (k[18 + d] * tt + k[21 + d] * rs)) +
          (k[24 + d] * rt + k[27 + d] * st);
      }
    }
    else
    {
      for (int d = 0; d < 3; ++d)
      {
        x[d] = (k[d] + k[3 + d] * r) + (k[6 + d] * s + k[9 + d] * t);
      }
    }
  }
  static void Field(const double* a, bool quadratic, double S, double lb, double lc, double n[3])
  {
    if (quadratic)
    {
      const double SS = S * S, Sb = S * lb, Sc = S * lc, bb = lb * lb, cc = lc * lc;
      const double bc = lb * lc;
      for (int d = 0; d < 3; ++d)
      {
        n[d] = ((a[d] * SS + a[3 + d] * Sb) + (a[6 + d] * Sc + a[9 + d] * bb)) +
          (a[12 + d] * cc + a[15 + d] * bc);
      }
    }
    else
    {
      for (int d = 0; d < 3; ++d)
      {
        n[d] = a[d] * S + (a[3 + d] * lb + a[6 + d] * lc);
      }
    }
  }
  static double Cofactor(
    const double* k, bool quadratic, double r, double s, double t, const double m[3], double n[3])
  {
    double ja[3], jb[3], jc[3];
    MapJacobian(k, quadratic, r, s, t, ja, jb, jc);
    return CofactorDet(ja, jb, jc, m, n);
  }
};

template <typename T>
std::int64_t EvaluateBlocks(const TransferEntry* plan, int nodesPerCell, const double* cellCoeffs,
  const double* faceCoeffs, const float* covectors, const unsigned char* foldedCells,
  std::int64_t begin, std::int64_t end, T* out, float* normals)
{
  // Blocks of vertices in short passes (positions; normals; scales; sums) rather than one
  // long dependency chain per vertex: the out-of-order core overlaps many vertices, and
  // the square roots and divisions run two at a time.
  //
  // The face coordinates are u = lb / S, v = lc / S with lb, lc, S = la + lb + lc the
  // barycentric coordinates of the face's corners (S = 1 on the face). The normal field
  // is a polynomial of degree q (2 for tri6, 1 for tri3) in (u, v); it is evaluated as
  // S^q n(u, v), a homogeneous polynomial in (S, lb, lc): no division, and the factor
  // S^q > 0 disappears in the normalisation.

  constexpr int kBlock = 64;
  const bool quadratic = nodesPerCell == 10;
  const int csize = quadratic ? 30 : 12;
  const int fsize = quadratic ? 18 : 9;
  double x[3 * kBlock], n[3 * kBlock], w[kBlock], len2[kBlock], scale[kBlock];
  std::int64_t left = 0;
  for (std::int64_t b = begin; b < end; b += kBlock)
  {
    const int m = static_cast<int>(end - b < kBlock ? end - b : kBlock);
    const TransferEntry* e = plan + b;
    for (int j = 0; j < m; ++j)
    {
      ScalarOps::Map(cellCoeffs + csize * static_cast<std::int64_t>(e[j].Cell), quadratic,
        e[j].PC[0], e[j].PC[1], e[j].PC[2], x + 3 * j);
    }
    int offsets = 0;
    for (int j = 0; faceCoeffs && j < m; ++j)
    {
      double* nj = n + 3 * j;
      const bool has = e[j].Face >= 0 && e[j].Distance != 0.0;
      w[j] = has ? e[j].Distance : 0.0;
      if (!has)
      {
        nj[0] = nj[1] = nj[2] = 0.0;
        len2[j] = 0.0;
        continue;
      }
      ++offsets;
      const double r = e[j].PC[0], s = e[j].PC[1], t = e[j].PC[2];
      const double L[4] = { 1.0 - r - s - t, r, s, t };
      const FaceCorners& fc = kFaceCorners[e[j].Face & 3];
      const double lb = L[fc.B], lc = L[fc.C];
      double S = L[fc.A] + lb + lc;
      S = S > 0.0 ? S : 1.0;
      ScalarOps::Field(
        faceCoeffs + fsize * static_cast<std::int64_t>(e[j].Face >> 2), quadratic, S, lb, lc, nj);
      len2[j] = nj[0] * nj[0] + nj[1] * nj[1] + nj[2] * nj[2];
    }
    if (offsets > 0)
    {
      OffsetScales(len2, w, scale, m);
      for (int j = 0; j < m; ++j)
      {
        // only the vertices with an offset: the others keep p' as is (adding 0 would turn
        // a -0 into +0 depending on which other vertices share the block); a select, not
        // a branch, so that the loop stays vectorised
        const bool has = w[j] != 0.0;
        for (int d = 0; d < 3; ++d)
        {
          const double y = x[3 * j + d] + scale[j] * n[3 * j + d];
          x[3 * j + d] = has ? y : x[3 * j + d];
        }
      }
    }
    T* o = out + 3 * b;
    for (int j = 0; j < 3 * m; ++j)
    {
      o[j] = static_cast<T>(x[j]);
    }
    if (!normals)
    {
      continue;
    }
    // Shading normals: cof(J'(p)) m, normalised (the cell's coefficients are still in
    // cache from the position pass). The n and len2 buffers are free again.
    const float* cv = covectors + 3 * b;
    double det[kBlock];
    for (int j = 0; j < m; ++j)
    {
      const double mv[3] = { cv[3 * j], cv[3 * j + 1], cv[3 * j + 2] };
      double* nj = n + 3 * j;
      // every vertex with its cell's map, offset vertices included: the gradient of the
      // normal-offset map itself (d dn/du terms) was tried, closer to the recomputed
      // normals but costlier than recomputing them (Benchmarks/RESULTS.md, live loop)
      det[j] = ScalarOps::Cofactor(cellCoeffs + csize * static_cast<std::int64_t>(e[j].Cell),
        quadratic, e[j].PC[0], e[j].PC[1], e[j].PC[2], mv, nj);
      len2[j] = nj[0] * nj[0] + nj[1] * nj[1] + nj[2] * nj[2];
      w[j] = 1.0;
    }
    OffsetScales(len2, w, scale, m);
    float* no = normals + 3 * b;
    for (int j = 0; j < m; ++j)
    {
      no[3 * j] = static_cast<float>(n[3 * j] * scale[j]);
      no[3 * j + 1] = static_cast<float>(n[3 * j + 1] * scale[j]);
      no[3 * j + 2] = static_cast<float>(n[3 * j + 2] * scale[j]);
      // det J' <= 0: the map folds at p, and cof(J') turns the normal inside out; or the
      // cell is inverted somewhere (`foldedCells`), where F varies too fast for a normal taken
      // at p alone: left to the caller (NaN), which recomputes it from the polygons
      if (!(det[j] > 0.0) || (foldedCells && foldedCells[e[j].Cell]))
      {
        no[3 * j] = no[3 * j + 1] = no[3 * j + 2] = std::numeric_limits<float>::quiet_NaN();
        ++left;
      }
    }
  }
  return left;
}
} // namespace

namespace transfer_detail
{
// hoembedTransferKernelAvx2.cxx: the plain kernel's operations, in its order, four vertices
// to an AVX2 register (the same bits).
std::int64_t EvaluateTransferAvx2(const TransferEntry* plan, int nodesPerCell,
  const double* cellCoeffs, const double* faceCoeffs, const float* covectors,
  const unsigned char* folded, std::int64_t begin, std::int64_t end, double* out, float* normals);
std::int64_t EvaluateTransferAvx2(const TransferEntry* plan, int nodesPerCell,
  const double* cellCoeffs, const double* faceCoeffs, const float* covectors,
  const unsigned char* folded, std::int64_t begin, std::int64_t end, float* out, float* normals);
} // namespace transfer_detail

namespace
{
int SimdSetting = -1; // -1: decide from the CPU; 0: plain; 1: AVX2

bool UseAvx2()
{
#if defined(HOEMBED_TRANSFER_AVX2)
  if (SimdSetting < 0)
  {
    __builtin_cpu_init();
    SimdSetting = __builtin_cpu_supports("avx2") ? 1 : 0;
  }
  return SimdSetting == 1;
#else
  return false;
#endif
}

bool Avx2Available()
{
#if defined(HOEMBED_TRANSFER_AVX2)
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2");
#else
  return false;
#endif
}

template <typename T>
std::int64_t EvaluateTransferT(const TransferEntry* plan, int nodesPerCell,
  const double* cellCoeffs, const double* faceCoeffs, const float* covectors,
  const unsigned char* folded, std::int64_t begin, std::int64_t end, T* out, float* normals)
{
#if defined(HOEMBED_TRANSFER_AVX2)
  if (UseAvx2())
  {
    return transfer_detail::EvaluateTransferAvx2(
      plan, nodesPerCell, cellCoeffs, faceCoeffs, covectors, folded, begin, end, out, normals);
  }
#endif
  return EvaluateBlocks(
    plan, nodesPerCell, cellCoeffs, faceCoeffs, covectors, folded, begin, end, out, normals);
}

template <typename T>
void EvaluateFallbackTransferT(const TransferEntry* plan, int nodesPerCell,
  const double* cellCoeffs, const std::int64_t* vertices, const double* offsets, std::int64_t begin,
  std::int64_t end, T* out)
{
  const bool quadratic = nodesPerCell == 10;
  for (std::int64_t k = begin; k < end; ++k)
  {
    const std::int64_t i = vertices[k];
    const TransferEntry& e = plan[i];
    const double* q = offsets + 3 * k;
    double x[3];
    MapPoint(e, quadratic, cellCoeffs, x);
    // J' q from the monomial coefficients (see the header's layout)
    const double* c =
      cellCoeffs + CellCoefficientSize(nodesPerCell) * static_cast<std::int64_t>(e.Cell);
    const double r = e.PC[0], s = e.PC[1], t = e.PC[2];
    for (int d = 0; d < 3; ++d)
    {
      double jr = c[3 + d], js = c[6 + d], jt = c[9 + d];
      if (quadratic)
      {
        jr += 2.0 * c[12 + d] * r + c[21 + d] * s + c[24 + d] * t;
        js += 2.0 * c[15 + d] * s + c[21 + d] * r + c[27 + d] * t;
        jt += 2.0 * c[18 + d] * t + c[24 + d] * r + c[27 + d] * s;
      }
      out[3 * i + d] = static_cast<T>(x[d] + (jr * q[0] + js * q[1] + jt * q[2]));
    }
  }
}
} // namespace

bool SetTransferKernelSimd(int mode)
{
  SimdSetting = mode < 0 ? -1 : (mode > 0 && Avx2Available() ? 1 : 0);
  return UseAvx2();
}

void EvaluateFallbackTransfer(const TransferEntry* plan, int nodesPerCell, const double* cellCoeffs,
  const std::int64_t* vertices, const double* offsets, std::int64_t begin, std::int64_t end,
  double* out)
{
  EvaluateFallbackTransferT(plan, nodesPerCell, cellCoeffs, vertices, offsets, begin, end, out);
}

void EvaluateFallbackTransfer(const TransferEntry* plan, int nodesPerCell, const double* cellCoeffs,
  const std::int64_t* vertices, const double* offsets, std::int64_t begin, std::int64_t end,
  float* out)
{
  EvaluateFallbackTransferT(plan, nodesPerCell, cellCoeffs, vertices, offsets, begin, end, out);
}

void EvaluateTransfer(const TransferEntry* plan, int nodesPerCell, const double* cellCoeffs,
  const double* faceCoeffs, std::int64_t begin, std::int64_t end, double* out)
{
  EvaluateTransferT(plan, nodesPerCell, cellCoeffs, faceCoeffs, nullptr, nullptr, begin, end, out,
    static_cast<float*>(nullptr));
}

void EvaluateTransfer(const TransferEntry* plan, int nodesPerCell, const double* cellCoeffs,
  const double* faceCoeffs, std::int64_t begin, std::int64_t end, float* out)
{
  EvaluateTransferT(plan, nodesPerCell, cellCoeffs, faceCoeffs, nullptr, nullptr, begin, end, out,
    static_cast<float*>(nullptr));
}

std::int64_t EvaluateTransfer(const TransferEntry* plan, int nodesPerCell, const double* cellCoeffs,
  const double* faceCoeffs, const float* covectors, const unsigned char* folded, std::int64_t begin,
  std::int64_t end, double* out, float* normals)
{
  return EvaluateTransferT(
    plan, nodesPerCell, cellCoeffs, faceCoeffs, covectors, folded, begin, end, out, normals);
}

std::int64_t EvaluateTransfer(const TransferEntry* plan, int nodesPerCell, const double* cellCoeffs,
  const double* faceCoeffs, const float* covectors, const unsigned char* folded, std::int64_t begin,
  std::int64_t end, float* out, float* normals)
{
  return EvaluateTransferT(
    plan, nodesPerCell, cellCoeffs, faceCoeffs, covectors, folded, begin, end, out, normals);
}

void ComputeNormalCovectors(const TransferEntry* plan, int nodesPerCell,
  const double* restCellCoeffs, const float* restNormals, std::int64_t begin, std::int64_t end,
  float* covectors)
{
  const bool quadratic = nodesPerCell == 10;
  const int csize = CellCoefficientSize(nodesPerCell);
  for (std::int64_t i = begin; i < end; ++i)
  {
    const TransferEntry& e = plan[i];
    const double* k = restCellCoeffs + csize * static_cast<std::int64_t>(e.Cell);
    double a[3], b[3], c[3];
    MapJacobian(k, quadratic, e.PC[0], e.PC[1], e.PC[2], a, b, c);
    const double n0[3] = { restNormals[3 * i], restNormals[3 * i + 1], restNormals[3 * i + 2] };
    // J0^T n0 / det J0 = (a.n0, b.n0, c.n0) / det J0; only its direction is kept (the
    // frame normalises), with the sign of det J0.
    const double det = a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2]) +
      a[2] * (b[0] * c[1] - b[1] * c[0]);
    double m[3] = { a[0] * n0[0] + a[1] * n0[1] + a[2] * n0[2],
      b[0] * n0[0] + b[1] * n0[1] + b[2] * n0[2], c[0] * n0[0] + c[1] * n0[1] + c[2] * n0[2] };
    const double len = std::sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
    const double scale = det != 0.0 && len > 0.0 && std::isfinite(len) && std::isfinite(det)
      ? (det > 0.0 ? 1.0 : -1.0) / len
      : 0.0;
    for (int d = 0; d < 3; ++d)
    {
      covectors[3 * i + d] = static_cast<float>(m[d] * scale);
    }
  }
}

void RotateNodalNormals(const double* restNormals, const double* rotations, std::int64_t begin,
  std::int64_t end, double* out)
{
  for (std::int64_t i = begin; i < end; ++i)
  {
    const double* n = restNormals + 3 * i;
    const double* R = rotations + 9 * i;
    double m[3];
    for (int d = 0; d < 3; ++d)
    {
      m[d] = R[3 * d] * n[0] + R[3 * d + 1] * n[1] + R[3 * d + 2] * n[2];
    }
    const double len = std::sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
    for (int d = 0; d < 3; ++d)
    {
      out[3 * i + d] = len > 0.0 ? m[d] / len : 0.0;
    }
  }
}

namespace
{
// dx/dxi of a cell (tet10 at parametric point pc, tet4 constant), gathered from `points`.
void CellJacobian(const std::int64_t* ids, int nodesPerCell, const double* points,
  const double pc[3], double J[3][3])
{
  if (nodesPerCell == 4)
  {
    for (int d = 0; d < 3; ++d)
    {
      for (int k = 0; k < 3; ++k)
      {
        J[d][k] = points[3 * ids[k + 1] + d] - points[3 * ids[0] + d];
      }
    }
    return;
  }
  double x[30];
  for (int a = 0; a < 10; ++a)
  {
    for (int d = 0; d < 3; ++d)
    {
      x[3 * a + d] = points[3 * ids[a] + d];
    }
  }
  Tet10Jacobian(x, pc, J);
}
} // namespace

void DeformNodalNormals(const TetMeshTopology& topo, const std::int64_t* conn, int nodesPerCell,
  const double* restPoints, const double* points, const double* restNormals, std::int64_t begin,
  std::int64_t end, double* out)
{
  constexpr int kMaxCells = 64; // cells remembered per node to count each once
  for (std::int64_t i = begin; i < end; ++i)
  {
    double* o = out + 3 * i;
    o[0] = o[1] = o[2] = 0.0;
    const double* n0 = restNormals + 3 * i;
    if (!topo.IsBoundaryNode(i) || (n0[0] == 0.0 && n0[1] == 0.0 && n0[2] == 0.0))
    {
      continue;
    }
    double Fn[3] = { 0.0, 0.0, 0.0 }; // sum over the cells of F n0
    std::int64_t seen[kMaxCells];
    int nseen = 0;
    for (auto k = topo.NodeFaceOffsets[i]; k < topo.NodeFaceOffsets[i + 1]; ++k)
    {
      const std::int64_t cell = topo.BoundaryFaceCell[topo.NodeFaces[k]];
      bool again = false;
      for (int s = 0; s < nseen && !again; ++s)
      {
        again = seen[s] == cell;
      }
      if (again)
      {
        continue;
      }
      if (nseen < kMaxCells)
      {
        seen[nseen++] = cell;
      }
      const std::int64_t* ids = conn + static_cast<std::int64_t>(nodesPerCell) * cell;
      int local = -1;
      for (int a = 0; a < nodesPerCell && local < 0; ++a)
      {
        local = ids[a] == i ? a : -1;
      }
      if (local < 0)
      {
        continue;
      }
      const double* pc = Tet10NodeParametric[local]; // corners: the same for tet4
      double J0[3][3], J[3][3];
      CellJacobian(ids, nodesPerCell, restPoints, pc, J0);
      CellJacobian(ids, nodesPerCell, points, pc, J);
      const double det = Determinant3(J0);
      if (!(std::fabs(det) > 0.0))
      {
        continue;
      }
      // m = J0^-1 n0 (Cramer), then F n0 = J m
      double inv[3][3];
      inv[0][0] = (J0[1][1] * J0[2][2] - J0[1][2] * J0[2][1]) / det;
      inv[0][1] = (J0[0][2] * J0[2][1] - J0[0][1] * J0[2][2]) / det;
      inv[0][2] = (J0[0][1] * J0[1][2] - J0[0][2] * J0[1][1]) / det;
      inv[1][0] = (J0[1][2] * J0[2][0] - J0[1][0] * J0[2][2]) / det;
      inv[1][1] = (J0[0][0] * J0[2][2] - J0[0][2] * J0[2][0]) / det;
      inv[1][2] = (J0[0][2] * J0[1][0] - J0[0][0] * J0[1][2]) / det;
      inv[2][0] = (J0[1][0] * J0[2][1] - J0[1][1] * J0[2][0]) / det;
      inv[2][1] = (J0[0][1] * J0[2][0] - J0[0][0] * J0[2][1]) / det;
      inv[2][2] = (J0[0][0] * J0[1][1] - J0[0][1] * J0[1][0]) / det;
      double m[3];
      for (int r = 0; r < 3; ++r)
      {
        m[r] = inv[r][0] * n0[0] + inv[r][1] * n0[1] + inv[r][2] * n0[2];
      }
      for (int r = 0; r < 3; ++r)
      {
        Fn[r] += J[r][0] * m[0] + J[r][1] * m[1] + J[r][2] * m[2];
      }
    }
    const double len = std::sqrt(Fn[0] * Fn[0] + Fn[1] * Fn[1] + Fn[2] * Fn[2]);
    if (len > 0.0 && std::isfinite(len))
    {
      for (int d = 0; d < 3; ++d)
      {
        o[d] = Fn[d] / len;
      }
    }
  }
}

std::int64_t MarkInvertedCells(const std::int64_t* conn, int nodesPerCell, const double* points,
  std::int64_t begin, std::int64_t end, unsigned char* flags)
{
  static const double kSamples[5][3] = { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 },
    { 0.25, 0.25, 0.25 } };
  std::int64_t count = 0;
  double x[30];
  for (std::int64_t c = begin; c < end; ++c)
  {
    const std::int64_t* ids = conn + nodesPerCell * c;
    for (int a = 0; a < nodesPerCell; ++a)
    {
      for (int d = 0; d < 3; ++d)
      {
        x[3 * a + d] = points[3 * ids[a] + d];
      }
    }
    bool inverted = false;
    if (nodesPerCell == 4)
    {
      inverted = !(Tet4JacobianDeterminant(x) > 0.0);
    }
    else
    {
      for (int k = 0; k < 5 && !inverted; ++k)
      {
        inverted = !(Tet10JacobianDeterminant(x, kSamples[k]) > 0.0);
      }
    }
    count += inverted ? 1 : 0;
    if (flags)
    {
      flags[c] = inverted ? 1 : 0;
    }
  }
  return count;
}

std::int64_t CountInvertedCells(const std::int64_t* conn, int nodesPerCell, const double* points,
  std::int64_t begin, std::int64_t end)
{
  return MarkInvertedCells(conn, nodesPerCell, points, begin, end, nullptr);
}
} // namespace hoembed
