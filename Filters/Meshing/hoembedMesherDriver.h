/**
 * @file hoembedMesherDriver.h
 * @brief The tet10 mesher as one call on plain arrays: checks, the coarse boundary
 *        (coarsening of a clean closed surface, or an envelope of any other), TetGen,
 *        curving onto the fine surface, validity and memory order (plain C++, VTK-free).
 *
 * vtkTet10Mesher reads its input, cleans it into triangles (a VTK step), calls
 * hoembed::RunMesher and writes the result; a pip binding calls the very same function.
 * The steps that need a geometry library other than the kernels here (quadric
 * decimation and low-pass smoothing of the fine surface, closest-point and ray queries,
 * VTK's cell validator) come in through hoembed::MesherServices, so the algorithm (order
 * of steps, retries, acceptance tests, errors) is written once, here.
 */
#ifndef hoembedMesherDriver_h
#define hoembedMesherDriver_h

#include "hoembedCurvedMeshBuilder.h"
#include "hoembedFiltersMeshingModule.h"
#include "hoembedPropertyRange.h"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace hoembed
{
/// Settings of a mesher run (the filter's properties, same meanings and defaults).
struct HOEMBEDFILTERSMESHING_EXPORT MesherOptions
{
  int TargetNumberOfElements = 1000;
  double TargetEdgeLength = 0.0; ///< > 0 overrides TargetNumberOfElements
  int ElementOrder = 2;
  bool CurveBoundary = true;
  bool ProjectCorners = true;
  bool PreserveBoundary = true;
  double RadiusEdgeRatio = 1.5;
  double MinDihedralAngle = 10.0;
  double SurfaceDeviationWarning = 0.05;
  double CurvedQualityRatio = 0.02;
  /// Floor of every curved element's minimum scaled Jacobian (hoembed::Tet10Acceptable);
  /// elements whose straight shape is below it are reported (PoorElementCount).
  double MinimumQuality = 0.05;
  /// Curving never takes an element below min(CurvedQualityTarget, its straight quality):
  /// the mid-edge nodes of such elements are blended back towards straight, just enough
  /// (hoembed::CurvedMeshOptions::QualityTarget). Higher: better elements, a boundary
  /// that follows the surface less closely (the embedding's offsets make up for it).
  /// 0.2 (default): on the wrapped and thin inputs whose median element was 0.09-0.19 it
  /// becomes 0.20-0.29, while 97-99% of the boundary mid-edge nodes of smooth shapes stay
  /// on the surface (0.3: 92-96%; Benchmarks/RESULTS.md, mesher section).
  double CurvedQualityTarget = 0.2;
  /// Distance of the envelope from a surface that is not a clean closed manifold,
  /// relative to the bounding-box diagonal; 0 (default): a quarter of the target element
  /// size, so that a single sheet becomes a solid about one element thick.
  double EnvelopeTolerance = 0.0;
  /// 1: always mesh an envelope (hoembed::WrapSurface), -1: never (a surface that is not
  /// a clean closed manifold is an error, as before the envelope existed), 0 (default):
  /// when the surface is not a clean closed manifold, or its coarsening fails.
  int Wrap = 0;
  /// Work bound of each envelope (hoembed::WrapSurface), in facets its flood fill may
  /// treat; 0 (default): max(3e5, 60 x the input's area over the squared ball size),
  /// 10 to 20 times what it treats on the inputs measured (Benchmarks/RESULTS.md).
  double WrapMaxGates = 0.0;
  /// Work bound of TetGen on the coarsened surface, in tetrahedra created; 0 (default):
  /// TetGen's own (hoembed::TetGenParameters::MaxCreatedTetrahedra). Reaching it falls
  /// back to the envelope.
  double CoarseTetGenMaxCreated = 0.0;
};

/// The settings of the geometry services, the same in every binding (vtkTet10Mesher's
/// VTKServices, the package's services over the VTK Python in use).
struct MesherServiceSettings
{
  /// the windowed-sinc low-pass of the fine surface that a smoothed decimation starts from
  static constexpr int SmoothingIterations = 30;
  static constexpr double SmoothingPassBand = 0.01;
  /// VTK's cell validator on a curved cell of the surface scaled to a unit diagonal (its
  /// tolerances are absolute)
  static constexpr double CellCheckTolerance = 1e-6;
  /// the validator's verdicts (the bits of vtkCellValidator::State, vtkCellStatus in VTK
  /// 9.4 and later) that refuse a curved cell: WrongNumberOfPoints, IntersectingEdges,
  /// IntersectingFaces, FacesAreOrientedIncorrectly. Curved faces are legitimately not
  /// convex: only intersections and flips count.
  static constexpr short RefusedCellStates = 0x01 | 0x02 | 0x04 | 0x20;
  /// the filter's MergeTolerance and MaximumNumberOfElements defaults
  static constexpr double MergeTolerance = 1e-6;
  static constexpr std::int64_t MaximumNumberOfElements = 1000000;
};

/// The valid range of each numeric property of the mesher (MesherOptions, and the
/// filter's MergeTolerance and MaximumNumberOfElements of MesherServiceSettings), written
/// once: CheckMesherOptions (and so RunMesher) refuses a value outside it with its
/// sentence; vtkTet10Mesher, the package (RANGES, check_range) and the ParaView XML's
/// range domains (kept inside by a test) read it from here.
constexpr PropertyRange MesherRanges[] = {
  { "TargetNumberOfElements", 4, 1e7, false, false, true },
  { "MaximumNumberOfElements", 1, NoLimit, false, false, true },
  { "TargetEdgeLength", 0, NoLimit, false, false, false },
  { "ElementOrder", 1, 2, false, false, true },
  { "RadiusEdgeRatio", 1.05, 100, false, false, false },
  { "MinDihedralAngle", 0, 30, false, false, false },
  { "SurfaceDeviationWarning", 0, NoLimit, false, false, false },
  { "CurvedQualityRatio", 0, 1, false, false, false },
  { "MinimumQuality", 0, 1, false, false, false },
  { "CurvedQualityTarget", 0, 1, false, false, false },
  { "EnvelopeTolerance", 0, 1, false, false, false },
  { "Wrap", -1, 1, false, false, true },
  { "WrapMaxGates", 0, NoLimit, false, false, false },
  { "CoarseTetGenMaxCreated", 0, NoLimit, false, false, false },
  { "MergeTolerance", 0, 0.01, false, false, false },
};

/// The sentence refusing `value` for the property `name` (MesherRanges; "" when `value`
/// is in its range, or `name` has none).
HOEMBEDFILTERSMESHING_EXPORT std::string CheckMesherProperty(const std::string& name, double value);

/// The first option of `options` outside its MesherRanges range, as its sentence ("" when
/// all are valid). RunMesher starts with it.
HOEMBEDFILTERSMESHING_EXPORT std::string CheckMesherOptions(const MesherOptions& options);

/// Geometry services on the fine surface that the binding provides.
struct HOEMBEDFILTERSMESHING_EXPORT MesherServices
{
  /// Quadric decimation of the fine surface (or of its low-pass filtered copy when
  /// `smoothed`) by `reduction` (fraction of triangles removed); false on failure (e.g.
  /// cells other than triangles out).
  std::function<bool(
    double reduction, bool smoothed, std::vector<double>& points, std::vector<std::int64_t>& tris)>
    Decimate;
  /// Closest point, ray and neighbourhood queries on the fine surface.
  SurfaceQueries Fine;
  /// Unit normal of the fine surface at its point x (of the triangle nearest to x, in
  /// the triangle's vertex order). Optional; with it, a wrapped sheet goes onto the
  /// envelope side it faces.
  std::function<void(const double x[3], double normal[3])> NormalAt;
  /// Largest distance from the points `query` (3 doubles each, every `stride`-th one) to
  /// the triangles (`points`, `tris`).
  std::function<double(const std::vector<double>& points, const std::vector<std::int64_t>& tris,
    const std::vector<double>& query, std::int64_t stride)>
    MaxDistanceToTriangles;
  /// Extra acceptance test of curved elements (e.g. VTK's cell validator), optional.
  std::function<bool(const double* x10)> ExtraCheck;
  /// Polled during the long steps (the envelope, TetGen, between the curving's steps);
  /// the run stops with an error when it returns true. Optional: without it, the
  /// innermost hoembed::ScopedTetGenAbort of the calling thread is polled.
  std::function<bool()> Abort;
};

struct HOEMBEDFILTERSMESHING_EXPORT MesherResult
{
  std::vector<double> Points;              ///< 3 per node, in memory order
  std::vector<std::int64_t> Conn;          ///< NodesPerCell per cell
  int NodesPerCell = 10;                   ///< 10 (tet10) or 4 (tet4)
  std::vector<double> MinScaledJacobian;   ///< per cell
  std::vector<unsigned char> BoundaryNode; ///< per node
  std::int64_t RelaxedNodeCount = 0;
  std::int64_t CurvedNodeCount = 0;
  double MaxSurfaceDeviation = 0.0;
  std::int64_t EnvelopeNodeCount = 0;      ///< boundary mid-edge nodes left on the envelope
  std::int64_t BoundaryCrossingsFound = 0; ///< curved boundary face pairs crossing, repaired
  std::int64_t BoundaryCrossingsLeft = 0;  ///< crossing pairs left (0 expected)
  /// MinScaledJacobian over the cells: minimum, 1st percentile, median
  double QualityQuantiles[3] = { 0.0, 0.0, 0.0 };
  std::int64_t PoorElementCount = 0; ///< cells below MesherOptions::MinimumQuality
  bool Wrapped = false;              ///< the boundary is an envelope of the surface
  double EnvelopeOffset = 0.0;       ///< its distance from the surface (when Wrapped)
  std::vector<std::string> Warnings;
  std::string Error; ///< empty on success; otherwise nothing else is meaningful
};

/**
 * Mesh the fine triangle surface (`points`: 3 doubles each; `tris`: 3 ids each; already
 * triangulated and merged). `progress` receives fractions in [0, 1].
 */
HOEMBEDFILTERSMESHING_EXPORT MesherResult RunMesher(const std::vector<double>& points,
  const std::vector<std::int64_t>& tris, const MesherOptions& options,
  const MesherServices& services,
  const std::function<void(double)>& progress = std::function<void(double)>());
} // namespace hoembed

#endif
