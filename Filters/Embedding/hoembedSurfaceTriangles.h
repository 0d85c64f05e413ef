/**
 * @file hoembedSurfaceTriangles.h
 * @brief The triangles of a surface given as polygons and strips (VTK cell-array layout).
 *
 * The embedding's flood walks over triangles: polygons of k points are fanned from their
 * first point (k - 2 triangles), triangle strips split into their k - 2 triangles, in the
 * order of the cells (polygons first, then strips), 3 point ids per triangle.
 * Plain C++ over the cell array's offsets and connectivity (32- or 64-bit).
 */
#ifndef hoembedSurfaceTriangles_h
#define hoembedSurfaceTriangles_h

#include "hoembedFiltersEmbeddingModule.h"

#include <cstdint>
#include <string>
#include <vector>

namespace hoembed
{
/// Views of one cell array (nothing owned): NumberOfCells + 1 offsets and the ids, in
/// one of the two widths (or no cells).
struct CellArrayView
{
  std::int64_t NumberOfCells = 0;
  const std::int64_t* Offsets64 = nullptr;
  const std::int64_t* Connectivity64 = nullptr;
  const std::int32_t* Offsets32 = nullptr;
  const std::int32_t* Connectivity32 = nullptr;
  /// Number of ids (the last offset).
  std::int64_t NumberOfIds() const;
};

/// Append the fans of `polygons` then the triangles of `strips` to `triangles`.
HOEMBEDFILTERSEMBEDDING_EXPORT void AppendSurfaceTriangles(
  const CellArrayView& polygons, const CellArrayView& strips, std::vector<std::int64_t>& triangles);

/// The empty string, or what is wrong with `triangles` for a surface of `numberOfPoints`
/// points (a point id out of range; more than 2^31 triangles).
HOEMBEDFILTERSEMBEDDING_EXPORT std::string CheckSurfaceTriangles(
  const std::vector<std::int64_t>& triangles, std::int64_t numberOfPoints);
} // namespace hoembed

#endif
