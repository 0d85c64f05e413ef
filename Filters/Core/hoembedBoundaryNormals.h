/**
 * @file hoembedBoundaryNormals.h
 * @brief The smooth normal field of a curved tet-mesh boundary (paper eq. 6-7).
 *
 * Nodal normals: at each boundary node, the angle-weighted average of the exact normals
 * (eq. 6: dx/du x dx/dv of the tri6 patch) of the boundary faces around it. The weight
 * is the patch's angle at the node (pi at mid-edge nodes, where the patch is smooth).
 * The field inside a face interpolates the nodal normals with the face's shape
 * functions (tri6 for tet10, tri3 for tet4) and normalises (eq. 7).
 *
 * Plain C++ kernel; `points` holds 3 doubles per mesh node.
 */
#ifndef hoembedBoundaryNormals_h
#define hoembedBoundaryNormals_h

#include "hoembedCoreModule.h"
#include "hoembedTetMeshTopology.h"

namespace hoembed
{
/**
 * Angle-weighted nodal normals of the boundary. `normals` receives 3 doubles per mesh
 * node (topo.NumberOfPoints); interior nodes get (0, 0, 0). Boundary faces with a
 * degenerate normal at a node do not contribute to it. A node where the contributions
 * cancel (the boundary folds back onto itself there, e.g. a knife edge) gets (0, 0, 0)
 * too: its direction would be round-off, so the field would not move rigidly with the
 * mesh; the interpolated field then uses the face's other nodes.
 */
HOEMBEDCORE_EXPORT void ComputeBoundaryNodeNormals(
  const TetMeshTopology& topo, const double* points, double* normals);

/**
 * Position and exact tangents of boundary face `face` at (u, v): x, dx/du, dx/dv.
 */
HOEMBEDCORE_EXPORT void EvaluateBoundaryFace(const TetMeshTopology& topo, const double* points,
  TetMeshTopology::Id face, const double uv[2], double x[3], double xu[3], double xv[3]);

/**
 * Smooth normal at (u, v) of boundary face `face`: sum_I N_I(u, v) nbar_I, then
 * normalised (eq. 7). `unnormalized`, when not null, receives the sum before
 * normalisation. Returns the length of that sum (0 if degenerate: n is then (0, 0, 0)).
 */
HOEMBEDCORE_EXPORT double InterpolateBoundaryNormal(const TetMeshTopology& topo,
  const double* nodalNormals, TetMeshTopology::Id face, const double uv[2], double n[3],
  double unnormalized[3] = nullptr);
} // namespace hoembed

#endif
