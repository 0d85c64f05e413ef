/**
 * @file hoembedClosestPointInternal.h
 * @brief Small inline helpers shared by the closest-point kernels (not a public API).
 */
#ifndef hoembedClosestPointInternal_h
#define hoembedClosestPointInternal_h

#include "hoembedClosestPoint.h"
#include "hoembedLanes.h"
#include "hoembedVector3.h"

#include <algorithm>
#include <cmath>

namespace hoembed
{
namespace detail
{

/// Solve A x = b (3x3) by Cramer's rule; false when A is (nearly) singular.
inline bool Solve3(const double A[3][3], const double b[3], double x[3])
{
  const double c00 = A[1][1] * A[2][2] - A[1][2] * A[2][1];
  const double c01 = A[1][2] * A[2][0] - A[1][0] * A[2][2];
  const double c02 = A[1][0] * A[2][1] - A[1][1] * A[2][0];
  const double det = A[0][0] * c00 + A[0][1] * c01 + A[0][2] * c02;
  // singular relative to the product of the columns' sizes: the columns may have
  // different units (the normal-offset system has two tangents, lengths, and a unit
  // normal), so one scale for the whole matrix would make the test depend on the mesh size
  double col[3] = { 0.0, 0.0, 0.0 };
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      col[j] = std::max(col[j], std::fabs(A[i][j]));
  if (!(std::fabs(det) > 1e-14 * col[0] * col[1] * col[2]))
    return false;
  const double inv = 1.0 / det;
  const double c10 = A[0][2] * A[2][1] - A[0][1] * A[2][2];
  const double c11 = A[0][0] * A[2][2] - A[0][2] * A[2][0];
  const double c12 = A[0][1] * A[2][0] - A[0][0] * A[2][1];
  const double c20 = A[0][1] * A[1][2] - A[0][2] * A[1][1];
  const double c21 = A[0][2] * A[1][0] - A[0][0] * A[1][2];
  const double c22 = A[0][0] * A[1][1] - A[0][1] * A[1][0];
  x[0] = (c00 * b[0] + c10 * b[1] + c20 * b[2]) * inv;
  x[1] = (c01 * b[0] + c11 * b[1] + c21 * b[2]) * inv;
  x[2] = (c02 * b[0] + c12 * b[1] + c22 * b[2]) * inv;
  return true;
}

} // namespace detail
} // namespace hoembed

#endif
