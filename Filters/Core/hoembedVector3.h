/**
 * @file hoembedVector3.h
 * @brief Dot and cross products of 3-vectors (double[3]), for the kernels.
 *
 * One definition for every kernel: inline, in the written order of the terms, so every
 * caller computes the same bits (vtkMath::Dot/Cross are the same expressions, but the
 * kernels are VTK-free).
 */
#ifndef hoembedVector3_h
#define hoembedVector3_h

namespace hoembed
{
/// a . b
inline double Dot(const double a[3], const double b[3])
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/// c = a x b (c must not alias a or b)
inline void Cross(const double a[3], const double b[3], double c[3])
{
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}
} // namespace hoembed

#endif
