/**
 * @file hoembedSurfaceCheck.h
 * @brief Is a triangle surface closed, manifold and consistently oriented? (plain C++)
 */
#ifndef hoembedSurfaceCheck_h
#define hoembedSurfaceCheck_h

#include "hoembedFiltersMeshingModule.h"

#include <cstdint>

namespace hoembed
{
struct HOEMBEDFILTERSMESHING_EXPORT SurfaceCheck
{
  using Id = std::int64_t;
  Id BoundaryEdges = 0;           ///< edges in exactly one triangle (the surface is open)
  Id NonManifoldEdges = 0;        ///< edges in more than two triangles
  Id InconsistentEdges = 0;       ///< edges used twice in the same direction (flipped triangles)
  Id DegenerateTriangles = 0;     ///< triangles with a repeated vertex or zero area
  Id ExampleEdge[2] = { -1, -1 }; ///< one offending edge, for messages
  double SignedVolume = 0.0;      ///< divergence-theorem volume (> 0: outward normals)
  double Area = 0.0;

  bool IsClosedManifold() const
  {
    return this->BoundaryEdges == 0 && this->NonManifoldEdges == 0 && this->InconsistentEdges == 0;
  }

  /// Pairs of triangles that intersect or come closer than `relTol` of the bounding-box
  /// diagonal through each other (edge-triangle crossings; neighbours sharing an edge
  /// are not tested, those sharing a vertex only away from it). Sweep and prune on x.
  /// Counting stops at `maxCount`.
  static Id CountSelfIntersections(
    const double* pts, Id npts, const Id* tris, Id ntris, double relTol = 1e-9, Id maxCount = 100);

  /// Check `ntris` triangles (3 point ids each) over `npts` points (3 doubles each).
  /// Linear time (edges bucketed by their smallest point id).
  void Run(const double* pts, Id npts, const Id* tris, Id ntris);
};

/**
 * Does segment p-q cross triangle (a, b, c) (its interior or edges)? Moller-Trumbore;
 * `eps` widens the barycentric and segment-parameter ranges, so that near-touching counts
 * as crossing (0: exact ranges). A segment parallel to the triangle's plane (|det| at most
 * 1e-12 of its scale) does not count: coplanar contact is left to the other edges' tests.
 * The meshing module's one segment-triangle test (a surface's self-intersections, flat
 * boundary faces crossing).
 */
HOEMBEDFILTERSMESHING_EXPORT bool SegmentCrossesTriangle(const double* p, const double* q,
  const double* a, const double* b, const double* c, double eps = 0.0);
} // namespace hoembed

#endif
