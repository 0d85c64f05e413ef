#include "hoembedTransferNormals.h"
#include "hoembedCsr.h"

#include <cmath>

namespace hoembed
{
namespace
{
template <typename Id>
void IncidenceT(const std::int64_t* offsets, const std::int64_t* conn, std::int64_t numberOfPolys,
  std::int64_t numberOfPoints, std::vector<std::int64_t>& incOffsets, std::vector<Id>& incPolys)
{
  BuildCsr(
    numberOfPoints,
    [&](auto&& emit) {
      for (std::int64_t p = 0; p < numberOfPolys; ++p)
        for (std::int64_t k = offsets[p]; k < offsets[p + 1]; ++k)
          emit(conn[k], static_cast<Id>(p));
    },
    incOffsets, incPolys);
}

// The Newell normal of polygon p.
template <typename T>
inline void PolygonNormal(const std::int64_t* offsets, const std::int64_t* conn, const T* points,
  std::int64_t p, double out[3])
{
  const std::int64_t first = offsets[p], last = offsets[p + 1];
  if (last - first == 3)
  {
    // The general loop below unrolled: edges (a, b), (b, c), (c, a) in that order.
    const T* a = points + 3 * conn[first];
    const T* b = points + 3 * conn[first + 1];
    const T* c = points + 3 * conn[first + 2];
    double n0 = (double(a[1]) - double(b[1])) * (double(a[2]) + double(b[2]));
    double n1 = (double(a[2]) - double(b[2])) * (double(a[0]) + double(b[0]));
    double n2 = (double(a[0]) - double(b[0])) * (double(a[1]) + double(b[1]));
    n0 += (double(b[1]) - double(c[1])) * (double(b[2]) + double(c[2]));
    n1 += (double(b[2]) - double(c[2])) * (double(b[0]) + double(c[0]));
    n2 += (double(b[0]) - double(c[0])) * (double(b[1]) + double(c[1]));
    n0 += (double(c[1]) - double(a[1])) * (double(c[2]) + double(a[2]));
    n1 += (double(c[2]) - double(a[2])) * (double(c[0]) + double(a[0]));
    n2 += (double(c[0]) - double(a[0])) * (double(c[1]) + double(a[1]));
    out[0] = n0;
    out[1] = n1;
    out[2] = n2;
    return;
  }
  double n[3] = { 0.0, 0.0, 0.0 };
  for (std::int64_t k = first; k < last; ++k)
  {
    const T* a = points + 3 * conn[k];
    const T* b = points + 3 * conn[k + 1 < last ? k + 1 : first];
    n[0] += (double(a[1]) - double(b[1])) * (double(a[2]) + double(b[2]));
    n[1] += (double(a[2]) - double(b[2])) * (double(a[0]) + double(b[0]));
    n[2] += (double(a[0]) - double(b[0])) * (double(a[1]) + double(b[1]));
  }
  out[0] = n[0];
  out[1] = n[1];
  out[2] = n[2];
}

template <typename T>
void PolygonNormalsT(const std::int64_t* offsets, const std::int64_t* conn, const T* points,
  std::int64_t begin, std::int64_t end, double* polyNormals)
{
  for (std::int64_t p = begin; p < end; ++p)
  {
    PolygonNormal(offsets, conn, points, p, polyNormals + 3 * p);
  }
}

// One vertex's normal from its incident polygons, as VertexNormalsT sums them.
template <typename T, typename Id>
void OneVertexNormalT(const std::int64_t* offsets, const std::int64_t* conn, const T* points,
  const std::int64_t* incOffsets, const Id* incPolys, std::int64_t i, float* normals)
{
  double n[3] = { 0.0, 0.0, 0.0 };
  for (std::int64_t k = incOffsets[i]; k < incOffsets[i + 1]; ++k)
  {
    double m[3];
    PolygonNormal(offsets, conn, points, static_cast<std::int64_t>(incPolys[k]), m);
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

template <typename Id>
void VertexNormalsT(const std::int64_t* incOffsets, const Id* incPolys, const double* polyNormals,
  std::int64_t begin, std::int64_t end, float* normals)
{
  for (std::int64_t i = begin; i < end; ++i)
  {
    double n[3] = { 0.0, 0.0, 0.0 };
    for (std::int64_t k = incOffsets[i]; k < incOffsets[i + 1]; ++k)
    {
      const double* m = polyNormals + 3 * static_cast<std::int64_t>(incPolys[k]);
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
} // namespace

void BuildVertexPolygonIncidence(const std::int64_t* offsets, const std::int64_t* conn,
  std::int64_t numberOfPolys, std::int64_t numberOfPoints, std::vector<std::int64_t>& incOffsets,
  std::vector<std::int64_t>& incPolys)
{
  IncidenceT(offsets, conn, numberOfPolys, numberOfPoints, incOffsets, incPolys);
}

void BuildVertexPolygonIncidence(const std::int64_t* offsets, const std::int64_t* conn,
  std::int64_t numberOfPolys, std::int64_t numberOfPoints, std::vector<std::int64_t>& incOffsets,
  std::vector<std::int32_t>& incPolys)
{
  IncidenceT(offsets, conn, numberOfPolys, numberOfPoints, incOffsets, incPolys);
}

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

void ComputeVertexNormal(const std::int64_t* offsets, const std::int64_t* conn,
  const double* points, const std::int64_t* incOffsets, const std::int32_t* incPolys,
  std::int64_t vertex, float* normals)
{
  OneVertexNormalT(offsets, conn, points, incOffsets, incPolys, vertex, normals);
}
void ComputeVertexNormal(const std::int64_t* offsets, const std::int64_t* conn, const float* points,
  const std::int64_t* incOffsets, const std::int32_t* incPolys, std::int64_t vertex, float* normals)
{
  OneVertexNormalT(offsets, conn, points, incOffsets, incPolys, vertex, normals);
}
void ComputeVertexNormal(const std::int64_t* offsets, const std::int64_t* conn,
  const double* points, const std::int64_t* incOffsets, const std::int64_t* incPolys,
  std::int64_t vertex, float* normals)
{
  OneVertexNormalT(offsets, conn, points, incOffsets, incPolys, vertex, normals);
}
void ComputeVertexNormal(const std::int64_t* offsets, const std::int64_t* conn, const float* points,
  const std::int64_t* incOffsets, const std::int64_t* incPolys, std::int64_t vertex, float* normals)
{
  OneVertexNormalT(offsets, conn, points, incOffsets, incPolys, vertex, normals);
}

void ComputeVertexNormals(const std::int64_t* incOffsets, const std::int64_t* incPolys,
  const double* polyNormals, std::int64_t begin, std::int64_t end, float* normals)
{
  VertexNormalsT(incOffsets, incPolys, polyNormals, begin, end, normals);
}

void ComputeVertexNormals(const std::int64_t* incOffsets, const std::int32_t* incPolys,
  const double* polyNormals, std::int64_t begin, std::int64_t end, float* normals)
{
  VertexNormalsT(incOffsets, incPolys, polyNormals, begin, end, normals);
}
} // namespace hoembed
