// hoembed::EvaluateTransfer with AVX2, four vertices at a time: lane j of every register
// belongs to vertex j of a group of four plan entries, so each lane runs the plain
// kernel's scalar arithmetic (hoembedTransferKernel.cxx: ScalarOps and the block loop
// EvaluateBlocks) on its own vertex: the same operations in the same order,
// no fused multiply-add (this file is compiled for AVX2 without FMA), hence the same bits.
// Called only where the CPU has AVX2 (the dispatch in hoembedTransferKernel.cxx).
//
// Lanes across vertices rather than across the x, y, z of one vector: every lane works, a
// cross product is plain products (no permutes), and the positions, the normal offset and
// the shading normal of a group are computed in one pass with nothing stored between them.
// Consecutive surface vertices mostly share a cell (84% of the groups of four on the live
// benchmark's tail): then the cell's coefficients are broadcast from the table; otherwise
// the four cells' coefficients are first transposed into a small lane-major buffer.
// Results are transposed back to x y z per vertex.
#if defined(HOEMBED_TRANSFER_AVX2)
#pragma GCC target("avx2")
#include "hoembedShapeFunctions.h"
#include "hoembedTransferKernel.h"

#include <immintrin.h>

#include <cstddef>
#include <cstdint>
#include <limits>

namespace hoembed
{
namespace transfer_detail
{
namespace
{
// Group loads (r, s) and (t, d) of an entry as two pairs of doubles
static_assert(offsetof(TransferEntry, Distance) == 3 * sizeof(double),
  "TransferEntry: Distance must follow PC");

// The coefficients of one group's cells, as lane vectors: Get(i) holds coefficient double
// i of lane j's cell in lane j.
struct UniformCoefficients // all four lanes in one cell (or face): broadcast from the table
{
  const double* K;
  __m256d Get(int i) const
  {
    return _mm256_broadcast_sd(K + i);
  }
};
struct LaneCoefficients // lanes in different cells: transposed into Buffer
{
  alignas(32) double Buffer[32][4];
  __m256d Get(int i) const
  {
    return _mm256_load_pd(Buffer[i]);
  }
  // size doubles from each of the rows k[0..3], in chunks of four (the last chunk overlaps
  // the one before rather than reading past a row: the table's last row ends the array)
  void Fill(const double* const k[4], int size)
  {
    for (int c = 0; c < size; c += 4)
    {
      const int o = c + 4 <= size ? c : size - 4;
      const __m256d t0 = _mm256_insertf128_pd(
        _mm256_castpd128_pd256(_mm_loadu_pd(k[0] + o)), _mm_loadu_pd(k[2] + o), 1);
      const __m256d t1 = _mm256_insertf128_pd(
        _mm256_castpd128_pd256(_mm_loadu_pd(k[1] + o)), _mm_loadu_pd(k[3] + o), 1);
      const __m256d t2 = _mm256_insertf128_pd(
        _mm256_castpd128_pd256(_mm_loadu_pd(k[0] + o + 2)), _mm_loadu_pd(k[2] + o + 2), 1);
      const __m256d t3 = _mm256_insertf128_pd(
        _mm256_castpd128_pd256(_mm_loadu_pd(k[1] + o + 2)), _mm_loadu_pd(k[3] + o + 2), 1);
      _mm256_store_pd(Buffer[o], _mm256_unpacklo_pd(t0, t1));
      _mm256_store_pd(Buffer[o + 1], _mm256_unpackhi_pd(t0, t1));
      _mm256_store_pd(Buffer[o + 2], _mm256_unpacklo_pd(t2, t3));
      _mm256_store_pd(Buffer[o + 3], _mm256_unpackhi_pd(t2, t3));
    }
  }
};

inline __m256d Add(__m256d a, __m256d b)
{
  return _mm256_add_pd(a, b);
}
inline __m256d Sub(__m256d a, __m256d b)
{
  return _mm256_sub_pd(a, b);
}
inline __m256d Mul(__m256d a, __m256d b)
{
  return _mm256_mul_pd(a, b);
}

// p' of the four lanes (ScalarOps::Map's sums, in its order).
template <bool Quadratic, typename K>
inline void Map(const K& k, __m256d r, __m256d s, __m256d t, __m256d x[3])
{
  if (Quadratic)
  {
    const __m256d rr = Mul(r, r), ss = Mul(s, s), tt = Mul(t, t);
    const __m256d rs = Mul(r, s), rt = Mul(r, t), st = Mul(s, t);
    for (int d = 0; d < 3; ++d)
    {
      const __m256d A =
        Add(Add(k.Get(d), Mul(k.Get(3 + d), r)), Add(Mul(k.Get(6 + d), s), Mul(k.Get(9 + d), t)));
      const __m256d B = Add(Add(Mul(k.Get(12 + d), rr), Mul(k.Get(15 + d), ss)),
        Add(Mul(k.Get(18 + d), tt), Mul(k.Get(21 + d), rs)));
      const __m256d C = Add(Mul(k.Get(24 + d), rt), Mul(k.Get(27 + d), st));
      x[d] = Add(Add(A, B), C);
    }
  }
  else
  {
    for (int d = 0; d < 3; ++d)
    {
      x[d] =
        Add(Add(k.Get(d), Mul(k.Get(3 + d), r)), Add(Mul(k.Get(6 + d), s), Mul(k.Get(9 + d), t)));
    }
  }
}

// S^q n(u, v) of the four lanes (ScalarOps::Field).
template <bool Quadratic, typename K>
inline void Field(const K& a, __m256d S, __m256d lb, __m256d lc, __m256d n[3])
{
  if (Quadratic)
  {
    const __m256d SS = Mul(S, S), Sb = Mul(S, lb), Sc = Mul(S, lc);
    const __m256d bb = Mul(lb, lb), cc = Mul(lc, lc), bc = Mul(lb, lc);
    for (int d = 0; d < 3; ++d)
    {
      n[d] = Add(Add(Add(Mul(a.Get(d), SS), Mul(a.Get(3 + d), Sb)),
                   Add(Mul(a.Get(6 + d), Sc), Mul(a.Get(9 + d), bb))),
        Add(Mul(a.Get(12 + d), cc), Mul(a.Get(15 + d), bc)));
    }
  }
  else
  {
    for (int d = 0; d < 3; ++d)
    {
      n[d] = Add(Mul(a.Get(d), S), Add(Mul(a.Get(3 + d), lb), Mul(a.Get(6 + d), lc)));
    }
  }
}

// cof(J') m into n, returns det J' (MapJacobian and CofactorDet of the block header).
template <bool Quadratic, typename K>
inline __m256d Cofactor(
  const K& k, __m256d r, __m256d s, __m256d t, const __m256d m[3], __m256d n[3])
{
  __m256d a[3], b[3], c[3];
  const __m256d two = _mm256_set1_pd(2.0);
  for (int d = 0; d < 3; ++d)
  {
    a[d] = k.Get(3 + d);
    b[d] = k.Get(6 + d);
    c[d] = k.Get(9 + d);
    if (Quadratic)
    {
      a[d] = Add(a[d],
        Add(Add(Mul(Mul(two, k.Get(12 + d)), r), Mul(k.Get(21 + d), s)), Mul(k.Get(24 + d), t)));
      b[d] = Add(b[d],
        Add(Add(Mul(Mul(two, k.Get(15 + d)), s), Mul(k.Get(21 + d), r)), Mul(k.Get(27 + d), t)));
      c[d] = Add(c[d],
        Add(Add(Mul(Mul(two, k.Get(18 + d)), t), Mul(k.Get(24 + d), r)), Mul(k.Get(27 + d), s)));
    }
  }
  const __m256d bc[3] = { Sub(Mul(b[1], c[2]), Mul(b[2], c[1])),
    Sub(Mul(b[2], c[0]), Mul(b[0], c[2])), Sub(Mul(b[0], c[1]), Mul(b[1], c[0])) };
  const __m256d ca[3] = { Sub(Mul(c[1], a[2]), Mul(c[2], a[1])),
    Sub(Mul(c[2], a[0]), Mul(c[0], a[2])), Sub(Mul(c[0], a[1]), Mul(c[1], a[0])) };
  const __m256d ab[3] = { Sub(Mul(a[1], b[2]), Mul(a[2], b[1])),
    Sub(Mul(a[2], b[0]), Mul(a[0], b[2])), Sub(Mul(a[0], b[1]), Mul(a[1], b[0])) };
  for (int d = 0; d < 3; ++d)
  {
    n[d] = Add(Add(Mul(m[0], bc[d]), Mul(m[1], ca[d])), Mul(m[2], ab[d]));
  }
  return Add(Add(Mul(a[0], bc[0]), Mul(a[1], bc[1])), Mul(a[2], bc[2]));
}

// (n0 n0 + n1 n1) + n2 n2
inline __m256d Length2(const __m256d n[3])
{
  return Add(Add(Mul(n[0], n[0]), Mul(n[1], n[1])), Mul(n[2], n[2]));
}

// w / sqrt(len2), 0 where len2 is not > 0 (OffsetScales of the block header)
inline __m256d Scale(__m256d len2, __m256d w)
{
  const __m256d positive = _mm256_cmp_pd(len2, _mm256_setzero_pd(), _CMP_GT_OQ);
  const __m256d safe = _mm256_blendv_pd(_mm256_set1_pd(1.0), len2, positive);
  return _mm256_and_pd(positive, _mm256_div_pd(w, _mm256_sqrt_pd(safe)));
}

// Four vertices' x, y, z lanes <-> their 12 doubles x0 y0 z0 x1 | y1 z1 x2 y2 | z2 x3 y3 z3
inline void Interleave(const __m256d v[3], __m256d o[3])
{
  const __m256d xy = _mm256_unpacklo_pd(v[0], v[1]);    // x0 y0 | x2 y2
  const __m256d zx = _mm256_shuffle_pd(v[2], v[0], 10); // z0 x1 | z2 x3
  const __m256d yz = _mm256_shuffle_pd(v[1], v[2], 15); // y1 z1 | y3 z3
  o[0] = _mm256_permute2f128_pd(xy, zx, 0x20);
  o[1] = _mm256_blend_pd(yz, xy, 12);
  o[2] = _mm256_permute2f128_pd(zx, yz, 0x31);
}
inline void Deinterleave(const __m256d o[3], __m256d v[3])
{
  const __m256d xy = _mm256_blend_pd(o[0], o[1], 12);          // x0 y0 | x2 y2
  const __m256d zx = _mm256_permute2f128_pd(o[0], o[2], 0x21); // z0 x1 | z2 x3
  const __m256d yz = _mm256_blend_pd(o[1], o[2], 12);          // y1 z1 | y3 z3
  v[0] = _mm256_shuffle_pd(xy, zx, 10);
  v[1] = _mm256_shuffle_pd(xy, yz, 5);
  v[2] = _mm256_shuffle_pd(zx, yz, 10);
}

inline void Store12(const __m256d o[3], double* p)
{
  _mm256_storeu_pd(p, o[0]);
  _mm256_storeu_pd(p + 4, o[1]);
  _mm256_storeu_pd(p + 8, o[2]);
}
inline void Store12(const __m256d o[3], float* p)
{
  // static_cast<float> of each double: the conversion rounds the same way
  _mm_storeu_ps(p, _mm256_cvtpd_ps(o[0]));
  _mm_storeu_ps(p + 4, _mm256_cvtpd_ps(o[1]));
  _mm_storeu_ps(p + 8, _mm256_cvtpd_ps(o[2]));
}

// The group's `count` (1-4) vertices of the interleaved o (x y z per vertex) to p: a tail
// group goes through a buffer, so nothing past its last vertex is written.
template <typename U>
inline void StoreGroup(const __m256d o[3], U* p, int count)
{
  if (count == 4)
  {
    Store12(o, p);
    return;
  }
  U tmp[12];
  Store12(o, tmp);
  for (int i = 0; i < 3 * count; ++i)
  {
    p[i] = tmp[i];
  }
}

// All ones in the lanes j whose bit j is set in bits (0-15)
inline __m256d LaneMask(int bits)
{
  alignas(32) static const std::int64_t kMasks[16][4] = { { 0, 0, 0, 0 }, { -1, 0, 0, 0 },
    { 0, -1, 0, 0 }, { -1, -1, 0, 0 }, { 0, 0, -1, 0 }, { -1, 0, -1, 0 }, { 0, -1, -1, 0 },
    { -1, -1, -1, 0 }, { 0, 0, 0, -1 }, { -1, 0, 0, -1 }, { 0, -1, 0, -1 }, { -1, -1, 0, -1 },
    { 0, 0, -1, -1 }, { -1, 0, -1, -1 }, { 0, -1, -1, -1 }, { -1, -1, -1, -1 } };
  return _mm256_load_pd(reinterpret_cast<const double*>(kMasks[bits]));
}

// Runs Body(coefficients) with the four rows' coefficients as lane vectors.
template <typename Body>
inline void WithCoefficients(const double* const k[4], int size, Body&& body)
{
  if (k[0] == k[1] && k[0] == k[2] && k[0] == k[3])
  {
    body(UniformCoefficients{ k[0] });
  }
  else
  {
    LaneCoefficients lanes;
    lanes.Fill(k, size);
    body(lanes);
  }
}

// (t, d) of an entry: PC[2] and Distance
inline const double* TD(const TransferEntry* e)
{
  return reinterpret_cast<const double*>(reinterpret_cast<const char*>(e) + 2 * sizeof(double));
}

// Four entries e[0..3] (a tail repeats its last entry: the extra lanes are computed and
// dropped). Writes 12 values at out and, with normals, 12 floats at normals; returns the
// number of normals left NaN among the first `count` lanes.
template <bool Quadratic, typename T>
inline int Group(const TransferEntry* const e[4], int count, const double* cellCoeffs,
  const double* faceCoeffs, const float* cv, const unsigned char* foldedCells, T* out,
  float* normals)
{
  constexpr int csize = Quadratic ? 30 : 12;
  constexpr int fsize = Quadratic ? 18 : 9;
  // (r, s) and (t, d) of each entry are contiguous: two 4x4 transposes' worth of shuffles
  const __m256d rs02 =
    _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(e[0]->PC)), _mm_loadu_pd(e[2]->PC), 1);
  const __m256d rs13 =
    _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(e[1]->PC)), _mm_loadu_pd(e[3]->PC), 1);
  const __m256d td02 =
    _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(TD(e[0]))), _mm_loadu_pd(TD(e[2])), 1);
  const __m256d td13 =
    _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(TD(e[1]))), _mm_loadu_pd(TD(e[3])), 1);
  const __m256d r = _mm256_unpacklo_pd(rs02, rs13), s = _mm256_unpackhi_pd(rs02, rs13);
  const __m256d t = _mm256_unpacklo_pd(td02, td13), dist = _mm256_unpackhi_pd(td02, td13);
  const double* k[4];
  for (int j = 0; j < 4; ++j)
  {
    k[j] = cellCoeffs + csize * static_cast<std::int64_t>(e[j]->Cell);
  }

  __m256d x[3], cof[3], det = _mm256_setzero_pd();
  __m256d m[3];
  if (normals)
  {
    __m128 f[3] = { _mm_loadu_ps(cv), _mm_loadu_ps(cv + 4), _mm_loadu_ps(cv + 8) };
    const __m256d o[3] = { _mm256_cvtps_pd(f[0]), _mm256_cvtps_pd(f[1]), _mm256_cvtps_pd(f[2]) };
    Deinterleave(o, m);
  }
  WithCoefficients(k, csize, [&](const auto& kk) {
    Map<Quadratic>(kk, r, s, t, x);
    if (normals)
    {
      // every vertex with its cell's map, offset vertices included (see the block header)
      det = Cofactor<Quadratic>(kk, r, s, t, m, cof);
    }
  });

  // The normal offset: lanes whose entry has a face and d != 0 (the others keep p' as is).
  // Consecutive vertices mostly agree: no lane has one (49% of the groups of four on the
  // live benchmark's tail), or all four lie on one face (36%): those take no lane masks.
  if (faceCoeffs)
  {
    const int faceBits = (e[0]->Face >= 0 ? 1 : 0) | (e[1]->Face >= 0 ? 2 : 0) |
      (e[2]->Face >= 0 ? 4 : 0) | (e[3]->Face >= 0 ? 8 : 0);
    const int hasBits =
      faceBits & _mm256_movemask_pd(_mm256_cmp_pd(dist, _mm256_setzero_pd(), _CMP_NEQ_UQ));
    if (hasBits != 0)
    {
      const __m256d one = _mm256_set1_pd(1.0);
      const __m256d L[4] = { Sub(Sub(Sub(one, r), s), t), r, s, t };
      // each lane's face; lanes without an offset take the face of the first lane that
      // has one (computed, then dropped by the blend below)
      const TransferEntry* first = e[__builtin_ctz(hasBits)];
      std::int32_t face[4];
      for (int j = 0; j < 4; ++j)
      {
        face[j] = (hasBits >> j & 1 ? e[j] : first)->Face;
      }
      __m256d la, lb, lc, n[3];
      const bool oneFace =
        hasBits == 15 && face[1] == face[0] && face[2] == face[0] && face[3] == face[0];
      if (oneFace)
      {
        const int* corners = TetFaceNodes[face[0] & 3];
        la = L[corners[0]];
        lb = L[corners[1]];
        lc = L[corners[2]];
      }
      else
      {
        // each lane's corners by its local face
        la = lb = lc = _mm256_setzero_pd();
        for (int f = 0; f < 4; ++f)
        {
          const int bits = ((face[0] & 3) == f ? 1 : 0) | ((face[1] & 3) == f ? 2 : 0) |
            ((face[2] & 3) == f ? 4 : 0) | ((face[3] & 3) == f ? 8 : 0);
          const __m256d sel = LaneMask(bits);
          la = _mm256_blendv_pd(la, L[TetFaceNodes[f][0]], sel);
          lb = _mm256_blendv_pd(lb, L[TetFaceNodes[f][1]], sel);
          lc = _mm256_blendv_pd(lc, L[TetFaceNodes[f][2]], sel);
        }
      }
      __m256d S = Add(Add(la, lb), lc);
      S = _mm256_blendv_pd(one, S, _mm256_cmp_pd(S, _mm256_setzero_pd(), _CMP_GT_OQ));
      const double* a[4];
      for (int j = 0; j < 4; ++j)
      {
        a[j] = faceCoeffs + fsize * static_cast<std::int64_t>(face[j] >> 2);
      }
      WithCoefficients(a, fsize, [&](const auto& aa) { Field<Quadratic>(aa, S, lb, lc, n); });
      const __m256d scale = Scale(Length2(n), dist);
      for (int d = 0; d < 3; ++d)
      {
        const __m256d y = Add(x[d], Mul(scale, n[d]));
        x[d] = hasBits == 15 ? y : _mm256_blendv_pd(x[d], y, LaneMask(hasBits));
      }
    }
  }

  __m256d o[3];
  Interleave(x, o);
  StoreGroup(o, out, count);
  if (!normals)
  {
    return 0;
  }
  // Shading normals: cof(J') m normalised; NaN where det J' <= 0 or the cell is folded
  const __m256d scale = Scale(Length2(cof), _mm256_set1_pd(1.0));
  const int folded = !foldedCells
    ? 0
    : (foldedCells[e[0]->Cell] ? 1 : 0) | (foldedCells[e[1]->Cell] ? 2 : 0) |
      (foldedCells[e[2]->Cell] ? 4 : 0) | (foldedCells[e[3]->Cell] ? 8 : 0);
  const __m256d nanMask = _mm256_or_pd(
    LaneMask(folded), _mm256_cmp_pd(det, _mm256_setzero_pd(), _CMP_NGT_UQ)); // !(det > 0)
  const int left = __builtin_popcount(_mm256_movemask_pd(nanMask) & ((1 << count) - 1));
  const __m256d nan = _mm256_set1_pd(std::numeric_limits<double>::quiet_NaN());
  __m256d nv[3];
  for (int d = 0; d < 3; ++d)
  {
    nv[d] = _mm256_blendv_pd(Mul(cof[d], scale), nan, nanMask);
  }
  Interleave(nv, o);
  StoreGroup(o, normals, count);
  return left;
}

template <bool Quadratic, typename T>
std::int64_t Evaluate(const TransferEntry* plan, const double* cellCoeffs, const double* faceCoeffs,
  const float* covectors, const unsigned char* foldedCells, std::int64_t begin, std::int64_t end,
  T* out, float* normals)
{
  std::int64_t left = 0;
  std::int64_t i = begin;
  for (; i + 4 <= end; i += 4)
  {
    const TransferEntry* const e[4] = { plan + i, plan + i + 1, plan + i + 2, plan + i + 3 };
    // the plan read ahead (2.5 KB: 64 entries): some 5-10% faster than the hardware
    // prefetcher alone here
    const char* ahead = reinterpret_cast<const char*>(plan + i + 64);
    _mm_prefetch(ahead, _MM_HINT_T0);
    _mm_prefetch(ahead + 64, _MM_HINT_T0);
    _mm_prefetch(ahead + 128, _MM_HINT_T0);
    left += Group<Quadratic>(e, 4, cellCoeffs, faceCoeffs, normals ? covectors + 3 * i : nullptr,
      foldedCells, out + 3 * i, normals ? normals + 3 * i : nullptr);
  }
  if (i < end)
  {
    // the last 1-3 entries: lanes padded with the last entry, covectors copied to a
    // buffer of four (the arrays end here)
    const int count = static_cast<int>(end - i);
    const TransferEntry* e[4];
    float cv[12] = {};
    for (int j = 0; j < 4; ++j)
    {
      e[j] = plan + i + (j < count ? j : count - 1);
    }
    for (int j = 0; normals && j < 3 * count; ++j)
    {
      cv[j] = covectors[3 * i + j];
    }
    left += Group<Quadratic>(e, count, cellCoeffs, faceCoeffs, cv, foldedCells, out + 3 * i,
      normals ? normals + 3 * i : nullptr);
  }
  return left;
}
} // namespace

namespace
{
template <typename T>
std::int64_t EvaluateByOrder(const TransferEntry* plan, int nodesPerCell, const double* cellCoeffs,
  const double* faceCoeffs, const float* covectors, const unsigned char* folded, std::int64_t begin,
  std::int64_t end, T* out, float* normals)
{
  return nodesPerCell == 10
    ? Evaluate<true>(plan, cellCoeffs, faceCoeffs, covectors, folded, begin, end, out, normals)
    : Evaluate<false>(plan, cellCoeffs, faceCoeffs, covectors, folded, begin, end, out, normals);
}
} // namespace

std::int64_t EvaluateTransferAvx2(const TransferEntry* plan, int nodesPerCell,
  const double* cellCoeffs, const double* faceCoeffs, const float* covectors,
  const unsigned char* folded, std::int64_t begin, std::int64_t end, double* out, float* normals)
{
  return EvaluateByOrder(
    plan, nodesPerCell, cellCoeffs, faceCoeffs, covectors, folded, begin, end, out, normals);
}

std::int64_t EvaluateTransferAvx2(const TransferEntry* plan, int nodesPerCell,
  const double* cellCoeffs, const double* faceCoeffs, const float* covectors,
  const unsigned char* folded, std::int64_t begin, std::int64_t end, float* out, float* normals)
{
  return EvaluateByOrder(
    plan, nodesPerCell, cellCoeffs, faceCoeffs, covectors, folded, begin, end, out, normals);
}
} // namespace transfer_detail
} // namespace hoembed
#endif
