/**
 * @file hoembedTransferNormals.h
 * @brief Area-weighted vertex normals of a polygon surface, for rendering the transferred
 *        surface (computed in parallel-friendly ranges, no atomics).
 *
 * Plain C++ kernel. Polygons are given in VTK's offsets/connectivity layout (64-bit). The
 * vertex -> polygon incidence is built once per surface topology; every frame then runs
 * two passes over ranges: polygon normals (Newell's method: the unnormalised normal is
 * twice the area times the unit normal, so the sum is area-weighted), then vertex normals
 * (sum over incident polygons, normalised; (0, 0, 0) for isolated vertices).
 *
 * Triangles take a straight-line copy of the same Newell sums (same terms, same order, so
 * the same bits) instead of the general loop: the loop's variable trip count and
 * wrap-around index cost more than the arithmetic. The incidence lists come in 32-bit
 * polygon ids when the polygons fit (every surface in practice: this halves the vertex
 * pass's gathered index traffic) and in 64-bit ids otherwise.
 */
#ifndef hoembedTransferNormals_h
#define hoembedTransferNormals_h

#include "hoembedFiltersTransferModule.h"

#include <cstdint>
#include <vector>

namespace hoembed
{
/// Vertex -> polygon incidence (CSR): polygons of vertex i are
/// incPolys[incOffsets[i] .. incOffsets[i + 1]). The 32-bit form needs numberOfPolys <=
/// INT32_MAX (the caller checks).
HOEMBEDFILTERSTRANSFER_EXPORT void BuildVertexPolygonIncidence(const std::int64_t* offsets,
  const std::int64_t* conn, std::int64_t numberOfPolys, std::int64_t numberOfPoints,
  std::vector<std::int64_t>& incOffsets, std::vector<std::int64_t>& incPolys);
HOEMBEDFILTERSTRANSFER_EXPORT void BuildVertexPolygonIncidence(const std::int64_t* offsets,
  const std::int64_t* conn, std::int64_t numberOfPolys, std::int64_t numberOfPoints,
  std::vector<std::int64_t>& incOffsets, std::vector<std::int32_t>& incPolys);

/// Unnormalised (area-weighted) normals of polygons [begin, end), 3 doubles each.
HOEMBEDFILTERSTRANSFER_EXPORT void ComputePolygonNormals(const std::int64_t* offsets,
  const std::int64_t* conn, const double* points, std::int64_t begin, std::int64_t end,
  double* polyNormals);
HOEMBEDFILTERSTRANSFER_EXPORT void ComputePolygonNormals(const std::int64_t* offsets,
  const std::int64_t* conn, const float* points, std::int64_t begin, std::int64_t end,
  double* polyNormals);

/// Unit vertex normals of vertices [begin, end) from the polygon normals, as floats.
HOEMBEDFILTERSTRANSFER_EXPORT void ComputeVertexNormals(const std::int64_t* incOffsets,
  const std::int64_t* incPolys, const double* polyNormals, std::int64_t begin, std::int64_t end,
  float* normals);
HOEMBEDFILTERSTRANSFER_EXPORT void ComputeVertexNormals(const std::int64_t* incOffsets,
  const std::int32_t* incPolys, const double* polyNormals, std::int64_t begin, std::int64_t end,
  float* normals);
/// The normal of one vertex (normals[3 vertex ..]) from its incident polygons' Newell
/// normals computed on the spot: the bits ComputePolygonNormals + ComputeVertexNormals give.
HOEMBEDFILTERSTRANSFER_EXPORT void ComputeVertexNormal(const std::int64_t* offsets,
  const std::int64_t* conn, const double* points, const std::int64_t* incOffsets,
  const std::int32_t* incPolys, std::int64_t vertex, float* normals);
HOEMBEDFILTERSTRANSFER_EXPORT void ComputeVertexNormal(const std::int64_t* offsets,
  const std::int64_t* conn, const float* points, const std::int64_t* incOffsets,
  const std::int32_t* incPolys, std::int64_t vertex, float* normals);
HOEMBEDFILTERSTRANSFER_EXPORT void ComputeVertexNormal(const std::int64_t* offsets,
  const std::int64_t* conn, const double* points, const std::int64_t* incOffsets,
  const std::int64_t* incPolys, std::int64_t vertex, float* normals);
HOEMBEDFILTERSTRANSFER_EXPORT void ComputeVertexNormal(const std::int64_t* offsets,
  const std::int64_t* conn, const float* points, const std::int64_t* incOffsets,
  const std::int64_t* incPolys, std::int64_t vertex, float* normals);
} // namespace hoembed

#endif
