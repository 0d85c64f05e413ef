// Small helpers shared by the two files of hoembed::LagrangeEmbeddingMesh
// (hoembedLagrangeEmbedding.cxx, hoembedLagrangeFaceSearch.cxx). Private.
#ifndef hoembedLagrangeEmbeddingInternal_h
#define hoembedLagrangeEmbeddingInternal_h

#include <algorithm>

namespace hoembed
{
namespace lagrange_detail
{
inline double Dot(const double a[3], const double b[3])
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

// Euclidean projection of (u, v) onto the reference triangle.
inline void ProjectTriangle(double uv[2])
{
  double u = uv[0], v = uv[1];
  if (u + v > 1.0)
  {
    const double s = 0.5 * (u + v - 1.0);
    u -= s;
    v -= s;
  }
  u = std::max(0.0, u);
  v = std::max(0.0, v);
  if (u > 1.0)
    u = 1.0;
  if (v > 1.0 - u)
    v = 1.0 - u;
  uv[0] = u;
  uv[1] = v;
}

} // namespace lagrange_detail
} // namespace hoembed

#endif
