/**
 * @file hoembedLanes.h
 * @brief Two doubles in one vector register (GCC/Clang vector extension: SSE2 on x86-64,
 * NEON on AArch64), the kernels' one way to compute x and y side by side, compare
 * without a branch per component, or take two minima at once. Element-wise operations
 * round as the scalar ones do, so a kernel written in lanes gives bitwise the results of
 * its scalar form.
 */
#ifndef hoembedLanes_h
#define hoembedLanes_h

#include <cstring>

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
