/**
 * @file hoembedCurvedMeshBuilder.h
 * @brief From a linear tet mesh inside a fine surface to a valid curved tet10 (or tet4)
 *        mesh whose boundary nodes lie on that surface (plain C++, no pipeline code).
 *
 * Steps (see vtkTet10Mesher for the user-level description):
 * 1. flat boundary tets (two boundary faces, poor shape) are removed;
 * 2. boundary corner nodes move to their closest surface point where their tets stay
 *    valid and keep half their quality; then every corner moves (hoembed::OptimiseLinearCorners,
 *    boundary ones along the surface) where the straight tets around it get better, the
 *    worst never worse;
 * 3. mid-edge nodes are added; boundary ones target the surface (where the edge's normal
 *    line meets it, else the closest point), interior ones follow by harmonic extension;
 * 4. nodes are pulled back where elements would be invalid (hoembed::CurveMidEdgeNodes),
 *    and pulled-back boundary nodes get a second chance at other nearby surface points,
 *    and a third by moving the corners and interior mid-edge nodes around them
 *    (hoembed::FitWithFreeNodes);
 * 5. the mid-edge nodes of elements below CurvedMeshOptions::QualityTarget (of their
 *    straight quality) are blended back towards their straight positions, just enough;
 * 6. pairs of curved boundary faces that cross (hoembed::FindCurvedFaceCrossings) get
 *    their mid-edge nodes pulled back until none is left;
 * 7. interior mid-edge nodes of cells that curving bent move to raise those cells towards
 *    their straight quality, never lowering the worst cell around them (the boundary
 *    does not change).
 * The boundary edges whose mid-edge nodes stay pulled back are returned with their
 * surface targets (for diagnostics).
 */
#ifndef hoembedCurvedMeshBuilder_h
#define hoembedCurvedMeshBuilder_h

#include "hoembedFiltersMeshingModule.h"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace hoembed
{
/// Queries on the fine surface.
struct HOEMBEDFILTERSMESHING_EXPORT SurfaceQueries
{
  /// closest point of the surface to x
  std::function<void(const double x[3], double closest[3])> Closest;
  /// first crossing of segment a-b with the surface; false if none
  std::function<bool(const double a[3], const double b[3], double hit[3])> Ray;
  /// vertices of the surface within distance r of x (3 doubles each), optional
  std::function<void(const double x[3], double r, std::vector<double>& points)> VerticesWithin;
  /// does the surface at its point `target` face the direction `outward` (its side seen
  /// from outside)? Optional; used with CurvedMeshOptions::MaxTargetDistance, so that of
  /// the two envelope sides of a wrapped sheet only the one it faces goes onto it.
  std::function<bool(const double target[3], const double outward[3])> Faces;
};

struct HOEMBEDFILTERSMESHING_EXPORT CurvedMeshOptions
{
  int Order = 2;
  bool CurveBoundary = true;
  bool ProjectCorners = true;
  double QualityRatio = 0.1;    ///< see hoembed::Tet10Acceptable
  double MinimumQuality = 0.05; ///< see hoembed::Tet10Acceptable
  double SliverQuality = 0.2;   ///< scaled Jacobian below which flat boundary tets go
  /// sweeps of hoembed::OptimiseLinearCorners over the straight mesh after the corners'
  /// projection (0: off)
  int CornerSweeps = 4;
  /// Curving never takes an element below min(QualityTarget, its straight quality): after
  /// the curving, the mid-edge nodes of the elements below it are blended back towards
  /// their straight positions, just enough (hoembed::CurveMidEdgeNodes); 0: off.
  double QualityTarget = 0.0;
  /// Surface points farther than this from a boundary node are not its target (the node
  /// stays where it is: an envelope bridging a hole or wrapping a sheet); 0: no limit.
  double MaxTargetDistance = 0.0;
  /// extra acceptance test of curved elements (e.g. VTK's cell validator), optional
  std::function<bool(const double* x10)> ExtraCheck;
};

struct HOEMBEDFILTERSMESHING_EXPORT CurvedMesh
{
  std::vector<double> Points;               ///< 3 per node
  std::vector<std::int64_t> Conn;           ///< 10 (Order 2) or 4 per cell
  std::vector<unsigned char> BoundaryNode;  ///< per node
  std::vector<double> LinearPoints;         ///< the straight mesh's corner nodes
  std::vector<std::int64_t> LinearBoundary; ///< its boundary triangles (3 ids each)
  std::int64_t CurvedNodes = 0;             ///< boundary mid-edge nodes on the surface
  std::int64_t RelaxedNodes = 0;            ///< boundary mid-edge nodes pulled back
  std::int64_t EnvelopeNodes = 0;           ///< boundary mid-edge nodes with no surface point near
  std::int64_t RemovedSlivers = 0;
  std::int64_t CrossingPairsFound = 0;    ///< curved boundary face pairs found crossing
  std::int64_t CrossingPairsLeft = 0;     ///< after the repair (0 unless the corners cross)
  std::vector<std::int64_t> RelaxedEdges; ///< corner pairs of the pulled-back boundary edges
  std::vector<double> RelaxedEdgeTargets; ///< their mid-edge nodes' surface targets

  std::string Error; ///< empty on success
};

/**
 * Removes the flat boundary tets of a straight tet4 mesh (BuildCurvedMesh's first step):
 * a tet with exactly two boundary faces and a scaled Jacobian below `qualityThreshold`
 * goes when the edge shared by its two interior faces is not a boundary edge yet, so the
 * boundary stays a closed manifold (an edge flip). Returns how many went.
 */
HOEMBEDFILTERSMESHING_EXPORT std::int64_t RemoveBoundarySlivers(const std::vector<double>& points,
  std::vector<std::int64_t>& tets, std::int64_t numberOfPoints, double qualityThreshold);

HOEMBEDFILTERSMESHING_EXPORT CurvedMesh BuildCurvedMesh(std::vector<double> points,
  std::vector<std::int64_t> tets, const SurfaceQueries& surface, const CurvedMeshOptions& options,
  const std::function<void(double)>& progress = std::function<void(double)>());
} // namespace hoembed

#endif
