/**
 * @file hoembedLanes.h
 * @brief Two doubles in one vector register (GCC/Clang vector extension: SSE2 on x86-64,
 * NEON on AArch64), the kernels' one way to compute x and y side by side, compare
 * without a branch per component, or take two minima at once. Element-wise operations
 * round as the scalar ones do, so a kernel written in lanes gives bitwise the results of
 * its scalar form.
 *
 * Supported compilers: GCC (8 or newer) and Clang (10 or newer), on any target they
 * support: the kernels use the extension's arithmetic, comparisons, bit casts and the
 * element-wise ?: on these types. Other compilers (MSVC) stop here with a clear error
 * rather than miscompile: a fallback would have to reproduce those operations
 * bit-for-bit.
 */
#ifndef hoembedLanes_h
#define hoembedLanes_h

#include <cstring>

#if !defined(__GNUC__) && !defined(__clang__)
#error "HOEmbed needs GCC (8+) or Clang (10+): hoembedLanes.h uses their vector extension"
#endif

namespace hoembed
{
namespace lanes
{
typedef double Pair __attribute__((vector_size(16)));    ///< two doubles
typedef long long Mask __attribute__((vector_size(16))); ///< a comparison's result per lane

/// p[0], p[1] (any alignment)
inline Pair Load(const double* p)
{
  Pair v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

/// p[0], p[1] = v
inline void Store(double* p, const Pair& v)
{
  std::memcpy(p, &v, sizeof v);
}
} // namespace lanes
} // namespace hoembed

#endif
