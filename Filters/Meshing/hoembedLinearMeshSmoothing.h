/**
 * @file hoembedLinearMeshSmoothing.h
 * @brief Corner optimisation of a linear tet mesh before curving (plain C++): each corner
 *        moves where the worst straight scaled Jacobian of the tets around it rises,
 *        boundary corners along the fine surface.
 */
#ifndef hoembedLinearMeshSmoothing_h
#define hoembedLinearMeshSmoothing_h

#include "hoembedCurvedMeshBuilder.h"
#include "hoembedFiltersMeshingModule.h"

#include <cstdint>
#include <vector>

namespace hoembed
{
class TetMeshTopology;

/// Corner -> the tets around it (in tet order): around[off[v] .. off[v + 1]) for the
/// linear mesh `tets` (4 ids each) of nPts points.
HOEMBEDFILTERSMESHING_EXPORT void TetsAroundCorners(const std::vector<std::int64_t>& tets,
  std::int64_t nPts, std::vector<std::int64_t>& off, std::vector<std::int64_t>& around);

/// Moves the corners of the linear mesh (`tets`, 4 ids each, positively oriented) to raise
/// the scaled Jacobian of the tets around each, one corner at a time in id order, for
/// `sweeps` sweeps (deterministic, bounded work: a fixed number of quality evaluations and
/// surface queries per corner and sweep). A move is kept only when the worst tet around
/// the corner does not get worse and the sum of their (capped) qualities rises, so the
/// worst tet of the mesh never gets worse and every tet stays positive.
/// Interior corners move freely; boundary corners that lie on the fine surface (where
/// hoembed::BuildCurvedMesh projected them) slide on it (a step in the tangent plane of
/// their boundary faces, then the closest surface point), not across a crease (a surface
/// point leaving that plane by more than a small angle), and at most a third of their mean edge
/// length from where they started; other boundary corners (all, when `surface.Closest` is
/// empty) stay. The crossing repair of
/// hoembed::BuildCurvedMesh puts boundary corners back at TetGen's positions (`restore`):
/// with the boundary corners there, no tet around a moved corner drops below `floor` (or
/// below what it had, if less). Returns the number of corner moves kept.
HOEMBEDFILTERSMESHING_EXPORT std::int64_t OptimiseLinearCorners(std::vector<double>& pts,
  const std::vector<std::int64_t>& tets, const TetMeshTopology& topo, const SurfaceQueries& surface,
  int sweeps, const std::vector<double>& restore, double floor);
} // namespace hoembed

#endif
