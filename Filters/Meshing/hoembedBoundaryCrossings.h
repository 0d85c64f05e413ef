/**
 * @file hoembedBoundaryCrossings.h
 * @brief Certified search for crossings between the curved (quadratic, tri6) boundary
 *        faces of a tet10 mesh (plain C++).
 *
 * A tri6 face is a quadratic Bézier triangle: it lies in the convex hull of its six
 * control points (corners, and 2 m - (a + b) / 2 for the mid-edge node m of edge ab), so
 * the box of those points bounds it. Two faces whose boxes are disjoint are proven
 * apart; otherwise the larger one is split into four (its exact quadratic sub-patches)
 * and the test repeats, down to `maxDepth` levels. A pair whose sub-patch boxes still
 * overlap there is reported: it crosses, or comes closer than the sub-patches' size (not
 * proven apart; a repair then errs on the safe side). Two straight faces (mid-edge nodes
 * at their edges' midpoints) are flat triangles: an edge-triangle crossing test decides. Faces
 * sharing a corner are not compared (their contact along the shared edge or corner is legitimate).
 */
#ifndef hoembedBoundaryCrossings_h
#define hoembedBoundaryCrossings_h

#include "hoembedFiltersMeshingModule.h"

#include <array>
#include <cstdint>
#include <vector>

namespace hoembed
{
/**
 * @param points 3 doubles per node
 * @param faces  6 node ids per face: corners a, b, c, then the mid-edge nodes of ab, bc, ca
 * @param maxDepth subdivision levels at most (each splits a patch into 4)
 * @return the pairs of face indices (i < j) that cross or are not proven apart
 */
HOEMBEDFILTERSMESHING_EXPORT std::vector<std::array<std::int64_t, 2>> FindCurvedFaceCrossings(
  const std::vector<double>& points, const std::vector<std::int64_t>& faces, int maxDepth = 10);
} // namespace hoembed

#endif
