// The block loop of hoembed::EvaluateTransfer, templated on the per-vertex arithmetic
// (Ops: Map, Field, Cofactor). Private to hoembedTransferKernel.cxx (the plain kernel,
// ScalarOps); hoembedTransferKernelAvx2.cxx repeats these operations, in this order, four
// vertices at a time (everything here has internal linkage, so the AVX2 translation unit's
// code cannot stand in for the plain one's).
#ifndef hoembedTransferKernelBlock_h
#define hoembedTransferKernelBlock_h

#include "hoembedShapeFunctions.h"
#include "hoembedTransferKernel.h"

#include <cmath>
#include <cstdint>
#include <limits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace hoembed
{
namespace transfer_detail
{
namespace
{
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

template <typename Ops, typename T>
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
      Ops::Map(cellCoeffs + csize * static_cast<std::int64_t>(e[j].Cell), quadratic, e[j].PC[0],
        e[j].PC[1], e[j].PC[2], x + 3 * j);
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
      Ops::Field(
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
      det[j] = Ops::Cofactor(cellCoeffs + csize * static_cast<std::int64_t>(e[j].Cell), quadratic,
        e[j].PC[0], e[j].PC[1], e[j].PC[2], mv, nj);
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
} // namespace transfer_detail
} // namespace hoembed

#endif
