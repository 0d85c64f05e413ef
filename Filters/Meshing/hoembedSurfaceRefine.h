/**
 * @file hoembedSurfaceRefine.h
 * @brief Conforming longest-edge bisection of a triangle surface (plain C++, no pipeline
 *        code): the boundary that TetGen meshes gets edges no longer than a bound, with
 *        no new geometry.
 *
 * TetGen keeps the boundary it is given (PreserveBoundary), so a coarse boundary triangle
 * fixes the size of the cells on it: a surface of few, large triangles (a low-poly model,
 * a cube of 12) has to be refined before it is meshed at a given element size. Splitting
 * every triangle in four moves the boundary's resolution in steps of four (the element
 * count jumps past the target between neighbouring sizes) and keeps large triangles large
 * beside small ones. Bisecting only the edges longer than the bound, the longest first
 * (Rivara's order), follows the size continuously and locally:
 *
 * - The longest edge of the surface is the longest edge of every triangle that has it, so
 *   each split is a longest-edge bisection of each of those triangles (all of them, so no
 *   vertex hangs: the surface stays conforming, closed and manifold if it was), and every
 *   edge it creates is shorter than the edge it split (the median to the longest side is at
 *   most sqrt(3)/2 of it): the process ends, and the smallest angle is at least half the
 *   input's (Rivara's bound).
 * - The new points are edge midpoints: the surface's geometry does not change (no new
 *   self-intersections, the same area and enclosed volume).
 * - Ties in length are broken by the edge's vertex ids, so the result depends only on the
 *   input arrays; lengths scale exactly under a power-of-two scaling, so does the result.
 */
#ifndef hoembedSurfaceRefine_h
#define hoembedSurfaceRefine_h

#include "hoembedFiltersMeshingModule.h"

#include <cstdint>
#include <vector>

namespace hoembed
{
/**
 * Bisects, longest first, every edge of `tris` (3 ids a triangle, into `points`, 3
 * coordinates a point) longer than `maxLength`, in every triangle that has it; new points
 * are appended, triangles keep their orientation. At most `maxSplits` edges are split
 * (a count to reach, or a work bound: the surface is valid and conforming wherever it
 * stops; each split of an edge in two triangles adds two). Returns the number of edges
 * split.
 */
HOEMBEDFILTERSMESHING_EXPORT std::int64_t BisectLongEdges(std::vector<double>& points,
  std::vector<std::int64_t>& tris, double maxLength, std::int64_t maxSplits);
} // namespace hoembed

#endif
