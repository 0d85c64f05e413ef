/**
 * @file hoembedSurfaceWrap.h
 * @brief A closed, manifold, intersection-free envelope of any triangle soup (CGAL 5.5's
 *        3D Alpha Wrapping), as plain arrays (plain C++, no pipeline code).
 *
 * The envelope is the boundary of the union of the space a ball of radius `alpha` cannot
 * reach from outside, pushed out to `offset` from the input: it is watertight, orientable
 * and free of self-intersections by construction (CGAL's guarantee), so TetGen can mesh
 * it whatever the input was (open, several parts, non-manifold, self-intersecting,
 * inconsistently oriented). Features narrower than about alpha are filled; the envelope's
 * vertices lie at `offset` from the input. Degenerate triangles (repeated vertex, zero
 * area) carry no surface and are left out; every other triangle ends up inside.
 *
 * CGAL is GPL-3.0-or-later (compatible with the AGPL-3.0 TetGen linked in this module).
 */
#ifndef hoembedSurfaceWrap_h
#define hoembedSurfaceWrap_h

#include "hoembedFiltersMeshingModule.h"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace hoembed
{
struct HOEMBEDFILTERSMESHING_EXPORT SurfaceWrapResult
{
  std::vector<double> Points;      ///< 3 per point
  std::vector<std::int64_t> Tris;  ///< 3 per triangle, outward oriented
  std::int64_t UsedTriangles = 0;  ///< non-degenerate input triangles wrapped
  std::uint64_t SteinerPoints = 0; ///< CGAL's work: points inserted by the flood fill
  std::uint64_t Gates = 0;         ///< CGAL's work: gates (facets) treated
  std::string Error;               ///< empty on success
  /// the work bound (SurfaceWrapLimits) or an abort stopped the wrap (Error says which)
  bool Stopped = false;
  bool Aborted = false; ///< it was the abort
};

/// Bounds on the wrap's work (its flood fill runs until no gate is left, which on thin
/// multi-part input can take minutes).
struct HOEMBEDFILTERSMESHING_EXPORT SurfaceWrapLimits
{
  /// Steiner points the flood fill may insert; 0: no bound.
  std::uint64_t MaxSteinerPoints = 0;
  /// Gates (facets) it may treat; 0: no bound.
  std::uint64_t MaxGates = 0;
  /// Polled every 256 gates; the wrap stops when it returns true. Empty: the innermost
  /// hoembed::ScopedTetGenAbort of this thread, if any (how AbortExecute reaches it).
  std::function<bool()> Abort;
};

/**
 * Wrap the triangles `tris` (3 ids each) over `points` (3 doubles each) with a ball of
 * radius `alpha` at distance `offset` (both > 0, in the input's units). Never throws:
 * CGAL's failures, the work bound and an abort come back in SurfaceWrapResult::Error.
 */
HOEMBEDFILTERSMESHING_EXPORT SurfaceWrapResult WrapSurface(const std::vector<double>& points,
  const std::vector<std::int64_t>& tris, double alpha, double offset,
  const SurfaceWrapLimits& limits = SurfaceWrapLimits());
} // namespace hoembed

#endif
