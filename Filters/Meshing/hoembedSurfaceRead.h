/**
 * @file hoembedSurfaceRead.h
 * @brief The mesher's read step on plain arrays: point-id and size checks of the input
 *        surface, then its triangles (polygons and strips triangulated, vertices and
 *        lines dropped) with coincident points merged (plain C++, VTK-free).
 *
 * vtkTet10Mesher and the pip wheel's tet10_mesh both call these functions, so that the
 * checks, their error sentences and the triangulation are written once. Two steps stay
 * with the binding (hoembed::SurfaceReadServices): the ear cut of polygons of more than 4
 * points and the merge of coincident points (VTK build: vtkPolygon::Triangulate and
 * vtkCleanPolyData; wheel: the same classes of the user's pip VTK, from Python).
 */
#ifndef hoembedSurfaceRead_h
#define hoembedSurfaceRead_h

#include "hoembedFiltersMeshingModule.h"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace hoembed
{
/// Cells in VTK's layout: NumberOfCells + 1 offsets into Connectivity.
struct HOEMBEDFILTERSMESHING_EXPORT SurfaceCells
{
  std::int64_t NumberOfCells = 0;
  const std::int64_t* Offsets = nullptr;
  const std::int64_t* Connectivity = nullptr;
};

/// The input surface as given (ids unchecked).
struct HOEMBEDFILTERSMESHING_EXPORT SurfaceInput
{
  std::int64_t NumberOfPoints = 0;
  const double* Points = nullptr; ///< 3 per point
  SurfaceCells Verts, Lines, Polys, Strips;
};

struct HOEMBEDFILTERSMESHING_EXPORT SurfaceReadServices
{
  /// Ear cut of the polygon of `n` points (`ids`: its point ids, `xyz`: their 3n
  /// coordinates): 3 (n - 2) ids local to the polygon (0..n-1) in `local`; false when it
  /// cannot split the polygon (the read step then uses a fan from its first point).
  std::function<bool(
    const std::int64_t* ids, std::int64_t n, const double* xyz, std::vector<std::int64_t>& local)>
    EarCut;
  /// Merge the coincident points of the triangles `tris` (3 input point ids each): the
  /// merged surface's points (3 doubles each, points used by no triangle dropped) and
  /// triangles. False when the result holds cells other than triangles.
  std::function<bool(const std::vector<std::int64_t>& tris, std::vector<double>& points,
    std::vector<std::int64_t>& mergedTris)>
    Merge;
};

/// Empty, or what is wrong with a point id of any cell kind (vertex, line, polygon,
/// strip, in that order): the binding's merge and the triangulation read ids unchecked.
HOEMBEDFILTERSMESHING_EXPORT std::string CheckSurfacePointIds(const SurfaceInput& surface);

/// The element count a request asks for: `target`, or, when `edge` > 0, the volume to
/// mesh over the volume of a regular tet of edge `edge`. Ids must be checked first.
HOEMBEDFILTERSMESHING_EXPORT double EstimatedElements(
  const SurfaceInput& surface, double edge, int target);

/// Empty, or why a request of about EstimatedElements() elements exceeds `maximum`
/// (`maximumName`: what the binding calls that limit, for the sentence).
HOEMBEDFILTERSMESHING_EXPORT std::string CheckEstimatedSize(const SurfaceInput& surface,
  double edge, int target, std::int64_t maximum, const char* maximumName);

/**
 * The read step: checks (empty, non-finite points, no polygons), triangulation (a quad
 * along its shorter diagonal, a larger polygon by the ear cut service else as a fan,
 * strips decomposed as VTK does), the triangles put in an order of the geometry alone
 * (each from its smallest corner by coordinates, then sorted by corners: the same surface
 * stored in any triangle or point order is merged and meshed the same, bit for bit), the
 * merge service, and a check that triangles are
 * left. Returns an error sentence, empty on success (then `points`, `tris` hold the
 * fine surface the mesher takes).
 */
HOEMBEDFILTERSMESHING_EXPORT std::string ReadSurface(const SurfaceInput& surface,
  const SurfaceReadServices& services, std::vector<double>& points,
  std::vector<std::int64_t>& tris);
} // namespace hoembed

#endif
