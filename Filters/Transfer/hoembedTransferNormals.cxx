#include "hoembedTransferNormals.h"
#include "hoembedCsr.h"

#include <cmath>

namespace hoembed
{
void BuildVertexPolygonIncidence(const std::int64_t* offsets, const std::int64_t* conn,
  std::int64_t numberOfPolys, std::int64_t numberOfPoints, std::vector<std::int64_t>& incOffsets,
  std::vector<std::int64_t>& incPolys)
{
  BuildCsr(numberOfPoints,
    [&](auto&& emit) {
      for (std::int64_t p = 0; p < numberOfPolys; ++p)
        for (std::int64_t k = offsets[p]; k < offsets[p + 1]; ++k)
          emit(conn[k], p);
    },
    incOffsets, incPolys);
}

namespace
{
template <typename T>
void PolygonNormalsT(const std::int64_t* offsets, const std::int64_t* conn, const T* points,
  std::int64_t begin, std::int64_t end, double* polyNormals)
{
  for (std::int64_t p = begin; p < end; ++p)
  {
    double n[3] = { 0.0, 0.0, 0.0 };
    const std::int64_t first = offsets[p], last = offsets[p + 1];
    for (std::int64_t k = first; k < last; ++k)
    {
      const T* a = points + 3 * conn[k];
      const T* b = points + 3 * conn[k + 1 < last ? k + 1 : first];
      n[0] += (double(a[1]) - double(b[1])) * (double(a[2]) + double(b[2]));
      n[1] += (double(a[2]) - double(b[2])) * (double(a[0]) + double(b[0]));
      n[2] += (double(a[0]) - double(b[0])) * (double(a[1]) + double(b[1]));
    }
    polyNormals[3 * p] = n[0];
    polyNormals[3 * p + 1] = n[1];
    polyNormals[3 * p + 2] = n[2];
  }
}
} // namespace

void ComputePolygonNormals(const std::int64_t* offsets, const std::int64_t* conn,
  const double* points, std::int64_t begin, std::int64_t end, double* polyNormals)
{
  PolygonNormalsT(offsets, conn, points, begin, end, polyNormals);
}

void ComputePolygonNormals(const std::int64_t* offsets, const std::int64_t* conn,
  const float* points, std::int64_t begin, std::int64_t end, double* polyNormals)
{
  PolygonNormalsT(offsets, conn, points, begin, end, polyNormals);
}

void ComputeVertexNormals(const std::int64_t* incOffsets, const std::int64_t* incPolys,
  const double* polyNormals, std::int64_t begin, std::int64_t end, float* normals)
{
  for (std::int64_t i = begin; i < end; ++i)
  {
    double n[3] = { 0.0, 0.0, 0.0 };
    for (std::int64_t k = incOffsets[i]; k < incOffsets[i + 1]; ++k)
    {
      const double* m = polyNormals + 3 * incPolys[k];
      n[0] += m[0];
      n[1] += m[1];
      n[2] += m[2];
    }
    const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    const double inv = len > 0.0 ? 1.0 / len : 0.0;
    normals[3 * i] = static_cast<float>(n[0] * inv);
    normals[3 * i + 1] = static_cast<float>(n[1] * inv);
    normals[3 * i + 2] = static_cast<float>(n[2] * inv);
  }
}
} // namespace hoembed
