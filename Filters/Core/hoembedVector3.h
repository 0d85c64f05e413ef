/**
 * @file hoembedVector3.h
 * @brief Dot and cross products, norms and perpendiculars of 3-vectors (double[3]), for
 *        the kernels.
 *
 * One definition for every kernel: inline, in the written order of the terms, so every
 * caller computes the same bits. vtkMath::Dot/Cross/Normalize/Distance2BetweenPoints and
 * vtkMath::Perpendiculars (theta = 0) evaluate the same expressions in the same order (the
 * kernels are VTK-free; the mesher's outputs stayed bitwise equal when it moved from
 * vtkMath to these, and TestVector3 compares them with vtkMath).
 */
#ifndef hoembedVector3_h
#define hoembedVector3_h

#include <cmath>

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

/// |a - b|^2
inline double Distance2(const double a[3], const double b[3])
{
  return (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
    (a[2] - b[2]) * (a[2] - b[2]);
}

/// v /= |v| unless |v| is 0; returns |v| (divides, as vtkMath::Normalize does)
inline double Normalize(double v[3])
{
  const double norm = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  if (norm != 0.0)
    for (int i = 0; i < 3; ++i)
      v[i] /= norm;
  return norm;
}

/// Two unit vectors p, q with (v, p, q) orthonormal for a non-zero v. The axes are
/// permuted so that the largest component of v comes first (no division by a small
/// number): with (a, b, c) = v / |v| in that order, p = (c, 0, -a) / sqrt(a^2 + c^2) and
/// q = (-ab, a^2 + c^2, -bc) / sqrt(a^2 + c^2), permuted back.
inline void Perpendiculars(const double v[3], double p[3], double q[3])
{
  const double x2 = v[0] * v[0], y2 = v[1] * v[1], z2 = v[2] * v[2];
  const double r = std::sqrt(x2 + y2 + z2);
  int i = 2, j = 0, k = 1;
  if (x2 > y2 && x2 > z2)
  {
    i = 0;
    j = 1;
    k = 2;
  }
  else if (y2 > z2)
  {
    i = 1;
    j = 2;
    k = 0;
  }
  const double a = v[i] / r, b = v[j] / r, c = v[k] / r;
  const double s = std::sqrt(a * a + c * c);
  p[i] = c / s;
  p[j] = 0.0;
  p[k] = -a / s;
  q[i] = -a * b / s;
  q[j] = s;
  q[k] = -b * c / s;
}
} // namespace hoembed

#endif
