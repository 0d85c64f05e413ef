// hoembed::EvaluateTransfer's block kernel with AVX2 per-vertex arithmetic: the three
// components of a vector in the lanes of one 256-bit register (the fourth is slack), so
// a cell map costs 10 vector products instead of 30 scalar ones. The operations and their
// order are those of the plain version (hoembedTransferKernel.cxx, ScalarOps), with no
// fused multiply-add (this file is compiled for AVX2 without FMA): the same bits.
// Called only where the CPU has AVX2 (the dispatch in hoembedTransferKernel.cxx).
#if defined(HOEMBED_TRANSFER_AVX2)
#pragma GCC target("avx2")
#include "hoembedTransferKernelBlock.h"

#include <immintrin.h>

namespace hoembed
{
namespace transfer_detail
{
namespace
{
// The 3 doubles at p (the fourth lane 0, p[3] not read).
inline __m256d Load3(const double* p)
{
  return _mm256_maskload_pd(p, _mm256_set_epi64x(0, -1, -1, -1));
}

// (v1, v2, v0, v3) and (v2, v0, v1, v3)
inline __m256d YZX(__m256d v)
{
  return _mm256_permute4x64_pd(v, _MM_SHUFFLE(3, 0, 2, 1));
}
inline __m256d ZXY(__m256d v)
{
  return _mm256_permute4x64_pd(v, _MM_SHUFFLE(3, 1, 0, 2));
}
inline __m256d Cross(__m256d a, __m256d b)
{
  return _mm256_sub_pd(_mm256_mul_pd(YZX(a), ZXY(b)), _mm256_mul_pd(ZXY(a), YZX(b)));
}
inline __m256d Mul(__m256d a, double s)
{
  return _mm256_mul_pd(a, _mm256_set1_pd(s));
}
inline __m256d Add(__m256d a, __m256d b)
{
  return _mm256_add_pd(a, b);
}

struct Avx2Ops
{
  // x = ((k0 + k1 r) + (k2 s + k3 t)) + ((k4 rr + k5 ss) + (k6 tt + k7 rs)) + (k8 rt + k9 st)
  static void Map(const double* k, bool quadratic, double r, double s, double t, double x[3])
  {
    __m256d v;
    if (quadratic)
    {
      const double rr = r * r, ss = s * s, tt = t * t, rs = r * s, rt = r * t, st = s * t;
      const __m256d A = Add(Add(_mm256_loadu_pd(k), Mul(_mm256_loadu_pd(k + 3), r)),
        Add(Mul(_mm256_loadu_pd(k + 6), s), Mul(_mm256_loadu_pd(k + 9), t)));
      const __m256d B = Add(Add(Mul(_mm256_loadu_pd(k + 12), rr), Mul(_mm256_loadu_pd(k + 15), ss)),
        Add(Mul(_mm256_loadu_pd(k + 18), tt), Mul(_mm256_loadu_pd(k + 21), rs)));
      const __m256d C = Add(Mul(_mm256_loadu_pd(k + 24), rt), Mul(Load3(k + 27), st));
      v = Add(Add(A, B), C);
    }
    else
    {
      v = Add(Add(_mm256_loadu_pd(k), Mul(_mm256_loadu_pd(k + 3), r)),
        Add(Mul(_mm256_loadu_pd(k + 6), s), Mul(Load3(k + 9), t)));
    }
    _mm256_storeu_pd(x, v); // x has a slack double after the block's last vector
  }
  static void Field(const double* a, bool quadratic, double S, double lb, double lc, double n[3])
  {
    __m256d v;
    if (quadratic)
    {
      const double SS = S * S, Sb = S * lb, Sc = S * lc, bb = lb * lb, cc = lc * lc;
      const double bc = lb * lc;
      v = Add(Add(Add(Mul(_mm256_loadu_pd(a), SS), Mul(_mm256_loadu_pd(a + 3), Sb)),
                Add(Mul(_mm256_loadu_pd(a + 6), Sc), Mul(_mm256_loadu_pd(a + 9), bb))),
        Add(Mul(_mm256_loadu_pd(a + 12), cc), Mul(Load3(a + 15), bc)));
    }
    else
    {
      v = Add(
        Mul(_mm256_loadu_pd(a), S), Add(Mul(_mm256_loadu_pd(a + 3), lb), Mul(Load3(a + 6), lc)));
    }
    _mm256_storeu_pd(n, v);
  }
  static double Cofactor(
    const double* k, bool quadratic, double r, double s, double t, const double m[3], double n[3])
  {
    __m256d ja = _mm256_loadu_pd(k + 3), jb = _mm256_loadu_pd(k + 6), jc;
    if (quadratic)
    {
      jc = _mm256_loadu_pd(k + 9);
      const __m256d k4 = _mm256_loadu_pd(k + 12), k5 = _mm256_loadu_pd(k + 15);
      const __m256d k6 = _mm256_loadu_pd(k + 18), k7 = _mm256_loadu_pd(k + 21);
      const __m256d k8 = _mm256_loadu_pd(k + 24), k9 = Load3(k + 27);
      const __m256d two = _mm256_set1_pd(2.0);
      ja = Add(ja, Add(Add(Mul(_mm256_mul_pd(two, k4), r), Mul(k7, s)), Mul(k8, t)));
      jb = Add(jb, Add(Add(Mul(_mm256_mul_pd(two, k5), s), Mul(k7, r)), Mul(k9, t)));
      jc = Add(jc, Add(Add(Mul(_mm256_mul_pd(two, k6), t), Mul(k8, r)), Mul(k9, s)));
    }
    else
    {
      jc = Load3(k + 9);
    }
    const __m256d bc = Cross(jb, jc);
    const __m256d v = Add(Add(Mul(bc, m[0]), Mul(Cross(jc, ja), m[1])), Mul(Cross(ja, jb), m[2]));
    _mm256_storeu_pd(n, v);
    double a4[4], bc4[4];
    _mm256_storeu_pd(a4, ja);
    _mm256_storeu_pd(bc4, bc);
    return Det(a4, bc4);
  }
};
} // namespace

std::int64_t EvaluateTransferAvx2(const TransferEntry* plan, int nodesPerCell,
  const double* cellCoeffs, const double* faceCoeffs, const float* covectors,
  const unsigned char* folded, std::int64_t begin, std::int64_t end, double* out, float* normals)
{
  return EvaluateBlocks<Avx2Ops>(
    plan, nodesPerCell, cellCoeffs, faceCoeffs, covectors, folded, begin, end, out, normals);
}

std::int64_t EvaluateTransferAvx2(const TransferEntry* plan, int nodesPerCell,
  const double* cellCoeffs, const double* faceCoeffs, const float* covectors,
  const unsigned char* folded, std::int64_t begin, std::int64_t end, float* out, float* normals)
{
  return EvaluateBlocks<Avx2Ops>(
    plan, nodesPerCell, cellCoeffs, faceCoeffs, covectors, folded, begin, end, out, normals);
}
} // namespace transfer_detail
} // namespace hoembed
#endif
