/**
 * @class   vtkTet10Mesher
 * @brief   A coarse, valid, curved quadratic tetrahedral (tet10) mesh from a fine closed
 *          triangle surface.
 *
 * Input (port 0): any triangle surface (vtkPolyData), typically 10k-1M triangles: closed
 * or open, one or several parts, manifold or not, self-intersecting or not. Polygons and
 * triangle strips are triangulated first (every polygon: quads along the shorter diagonal,
 * larger ones by ear cut, else as a fan), points closer than MergeTolerance merged;
 * vertices and lines are ignored. A clean closed
 * manifold (every edge in exactly two consistently oriented triangles, enclosing a
 * volume) is coarsened (steps 2-3); any other surface, and a clean one whose coarsening
 * fails, is wrapped first: CGAL's 3D Alpha Wrapping (hoembed::WrapSurface) makes a
 * closed, manifold, intersection-free envelope at EnvelopeTolerance from it, which
 * TetGen meshes by construction; one FE solid per wrapped solid (parts closer than the
 * element size merge, nested parts fill the part around them, parts smaller than the
 * tolerance are absorbed in a small solid of their own). Boundary nodes then move onto
 * the surface where it is within twice the offset and faces them (its triangles' normals
 * point to their side), and stay on the envelope elsewhere (holes bridged, the far side
 * of a wrapped sheet, flipped patches); field data `EnvelopeNodeCount`. Output: a
 * vtkUnstructuredGrid of VTK_QUADRATIC_TETRA cells (ElementOrder 2, default) or VTK_TETRA cells
 * (ElementOrder 1, the paper's linear baseline on the same corner nodes).
 *
 * Steps:
 * 0. Checks before any VTK filter sees the input: properties finite (NaN quality bounds
 *    are refused), every cell's point ids in range, and the estimated element count
 *    within MaximumNumberOfElements. During TetGen and the envelope, AbortExecute is
 *    polled (through progress events), and between the steps; TetGen's and the
 *    envelope's work is bounded (hoembed::RunTetGen, hoembed::WrapSurface): a run that
 *    does not end becomes an error naming the step. A clean closed surface with parts
 *    thinner than the element size (TetGen's mesh of its coarsened surface mostly
 *    slivers, TetGen's work bound, or curved faces still crossing after the repair) is
 *    meshed through its envelope instead, and if curved faces still cross there the
 *    boundary stays straight: no crossing pair is ever left (a warning says which).
 * 1. Checks: non-empty, finite coordinates, triangles after triangulation (points and
 *    lines alone enclose nothing: an error). Problems are reported with vtkErrorMacro
 *    naming the filter, and the output stays empty. All steps run in hoembed::RunMesher
 *    (VTK-free); the filter only reads, cleans, and writes.
 * 2. Coarsening: the surface is decimated (quadric error) to the number of boundary
 *    triangles that a mesh of TargetNumberOfElements quality tets has, or to the edge
 *    length TargetEdgeLength when that is set (> 0).
 * 3. TetGen (compiled in; AGPL-3) meshes the coarse surface with the radius-edge ratio
 *    bound RadiusEdgeRatio, the dihedral-angle bound MinDihedralAngle and a volume bound
 *    from the target edge length.
 * 4. Boundary corner nodes are moved to their closest point on the fine surface where
 *    that keeps their linear tets valid; mid-edge nodes are added at edge midpoints.
 * 5. CurveBoundary (default on): every boundary mid-edge node moves to its closest point
 *    on the fine surface. Where that would make an element's Jacobian determinant
 *    non-positive anywhere (a conservative Bernstein bound, see
 *    hoembed::Tet10IsValid), the element's curved mid-edge nodes are pulled back towards
 *    the straight position, just enough (bisection on the fraction of the move). Nodes
 *    pulled back then get second chances: other points of the fine surface near them,
 *    and moves of the corners and interior mid-edge nodes around them (a pattern search
 *    that keeps every element acceptable; corners may leave the surface slightly, only
 *    mid-edge nodes are put on it). Acceptable means valid and a minimum scaled Jacobian of
 *    at least CurvedQualityRatio times the straight shape's and at least MinimumQuality
 *    (unless the straight shape is worse: it is then kept). Last, the mid-edge nodes of
 *    elements below min(CurvedQualityTarget, their straight shape's) are blended back
 *    towards straight (interior ones first), just enough. Finally the interior mid-edge
 *    nodes of elements that curving bent move (a pattern search) to lift them towards
 *    their straight shape's quality without lowering the worst element around them.
 *    The read step first puts the triangles in an order of their coordinates alone, so
 *    the same surface gives the same mesh bit for bit whatever its storage order.
 * 6. Memory order (hoembed::SpatialOrder): cells sorted along a Morton curve through
 *    their corner centroids, nodes numbered in the order those cells first use them, so
 *    elements near each other in space are near each other in the arrays (the embedding's
 *    searches read less scattered memory).
 *
 * Output arrays:
 * - cell data `MinScaledJacobian` (double): hoembed::Tet10MinScaledJacobian, or the
 *   tet4 scaled Jacobian.
 * - point data `BoundaryNode` (unsigned char): 1 for nodes on the boundary.
 * - field data `RelaxedNodeCount` (vtkIdType): boundary mid-edge nodes not moved all the
 *   way onto the fine surface; `CurvedNodeCount`: those that are;
 *   `MaxSurfaceDeviation` (double): the largest distance from a fine-surface vertex to the
 *   coarse straight boundary, relative to the bounding-box diagonal (a large value means
 *   thin parts were not resolved: a warning is issued above 5%); `EnvelopeNodeCount`
 *   (vtkIdType): boundary mid-edge nodes left on the envelope (no surface near);
 *   `EnvelopeOffset` (double): the envelope's distance from the surface (0: not wrapped);
 *   `MinScaledJacobianQuantiles` (3 doubles): minimum, 1st percentile and median of
 *   `MinScaledJacobian`; `PoorElementCount` (vtkIdType): cells below MinimumQuality.
 *
 * Progress events are fired during the steps above.
 *
 * @warning TetGen is AGPL-3.0 licensed (or commercially licensed by WIAS); CGAL's alpha
 * wrapping is GPL-3.0-or-later.
 * @sa vtkEmbeddingCoordinatesFilter, vtkCorotationalFEMStepper
 */
#ifndef vtkTet10Mesher_h
#define vtkTet10Mesher_h

#include "hoembedFiltersMeshingModule.h" // for export macro
#include "vtkUnstructuredGridAlgorithm.h"

class vtkPolyData;

class HOEMBEDFILTERSMESHING_EXPORT vtkTet10Mesher : public vtkUnstructuredGridAlgorithm
{
public:
  static vtkTet10Mesher* New();
  vtkTypeMacro(vtkTet10Mesher, vtkUnstructuredGridAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Approximate number of elements wanted (default 1000). Ignored when
   * TargetEdgeLength > 0.
   */
  vtkSetMacro(TargetNumberOfElements, int);
  vtkGetMacro(TargetNumberOfElements, int);
  ///@}

  ///@{
  /**
   * The largest mesh the filter makes (default 1,000,000 elements). The element count is
   * estimated before any work (TargetNumberOfElements, or the enclosed volume over the
   * volume of a regular tet of edge TargetEdgeLength); a larger estimate is refused with
   * an error giving the estimate, its memory and this limit. Raise it for larger meshes.
   */
  vtkSetMacro(MaximumNumberOfElements, vtkIdType);
  vtkGetMacro(MaximumNumberOfElements, vtkIdType);
  ///@}

  ///@{
  /**
   * Target edge length in the units of the input (default 0: derived from
   * TargetNumberOfElements and the enclosed volume).
   */
  vtkSetMacro(TargetEdgeLength, double);
  vtkGetMacro(TargetEdgeLength, double);
  ///@}

  ///@{
  /** 2 (default): VTK_QUADRATIC_TETRA; 1: VTK_TETRA on the same corner nodes. */
  vtkSetMacro(ElementOrder, int);
  vtkGetMacro(ElementOrder, int);
  ///@}

  ///@{
  /** Move boundary mid-edge nodes onto the fine surface (default on). */
  vtkSetMacro(CurveBoundary, bool);
  vtkGetMacro(CurveBoundary, bool);
  vtkBooleanMacro(CurveBoundary, bool);
  ///@}

  ///@{
  /** Move boundary corner nodes onto the fine surface where valid (default on). */
  vtkSetMacro(ProjectCorners, bool);
  vtkGetMacro(ProjectCorners, bool);
  vtkBooleanMacro(ProjectCorners, bool);
  ///@}

  ///@{
  /**
   * Keep the coarse surface's triangles as the mesh boundary: TetGen adds no points on
   * it (its -Y switch; without it if TetGen fails). Default on: TetGen then no longer
   * splits coarse facets into triangles much smaller than their distance to the fine
   * surface, so more boundary mid-edge nodes reach the surface (98.6-99.7% on the real
   * meshes of Benchmarks/bench_mesher.py against 85-99% off) and thin shapes keep their
   * element count; the boundary has fewer, larger triangles.
   */
  vtkSetMacro(PreserveBoundary, bool);
  vtkGetMacro(PreserveBoundary, bool);
  vtkBooleanMacro(PreserveBoundary, bool);
  ///@}

  ///@{
  /** TetGen radius-edge ratio bound (default 1.5; TetGen's -q first value). */
  vtkSetMacro(RadiusEdgeRatio, double);
  vtkGetMacro(RadiusEdgeRatio, double);
  ///@}

  ///@{
  /** TetGen minimum dihedral angle in degrees (default 10; TetGen's -q second value). */
  vtkSetMacro(MinDihedralAngle, double);
  vtkGetMacro(MinDihedralAngle, double);
  ///@}

  ///@{
  /**
   * Maximum distance from the fine surface to the coarse boundary, relative to the
   * bounding-box diagonal, above which a warning is issued (default 0.05).
   */
  vtkSetMacro(SurfaceDeviationWarning, double);
  vtkGetMacro(SurfaceDeviationWarning, double);
  ///@}

  ///@{
  /**
   * Curved elements must keep at least this fraction of the minimum scaled Jacobian of
   * their straight shape (default 0.02); below it their mid-edge nodes are pulled back.
   * 0 asks only for validity (det J > 0 everywhere).
   */
  vtkSetMacro(CurvedQualityRatio, double);
  vtkGetMacro(CurvedQualityRatio, double);
  ///@}

  ///@{
  /**
   * Floor of every curved element's minimum scaled Jacobian (default 0.05, a quality a
   * solver can use): curving pulls mid-edge nodes back (partially, just enough) rather
   * than go below it, trading surface fidelity (RelaxedNodeCount) for quality. An element
   * whose straight shape is already below it stays straight there, and a warning gives
   * the count and the figures (field data `PoorElementCount`). 0: no floor.
   */
  vtkSetMacro(MinimumQuality, double);
  vtkGetMacro(MinimumQuality, double);
  ///@}

  ///@{
  /**
   * Quality target of the curving (default 0.2, hoembed::MesherOptions): curving never
   * takes an element below min(CurvedQualityTarget, its straight shape's minimum scaled
   * Jacobian); the mid-edge nodes of an element that would go below are blended back
   * towards their straight positions, just enough. Higher: better elements, a boundary
   * that follows the surface less closely (the embedding's offsets make up for it).
   * 0: only CurvedQualityRatio and MinimumQuality.
   */
  vtkSetMacro(CurvedQualityTarget, double);
  vtkGetMacro(CurvedQualityTarget, double);
  ///@}

  ///@{
  /**
   * Distance of the envelope from an input that is not a clean closed manifold, relative
   * to the bounding-box diagonal (default 0: a quarter of the target element size, so
   * that a single open sheet becomes a solid about one element thick). Smaller values
   * follow the surface more closely and need more elements where the surface is a sheet.
   */
  vtkSetMacro(EnvelopeTolerance, double);
  vtkGetMacro(EnvelopeTolerance, double);
  ///@}

  ///@{
  /**
   * Points closer than this, relative to the bounding-box diagonal, are merged before
   * anything else (default 1e-6: shared vertices that an exporter rounded differently,
   * seen in STL files, would otherwise leave false boundary edges). 0 merges only
   * coincident points.
   */
  vtkSetMacro(MergeTolerance, double);
  vtkGetMacro(MergeTolerance, double);
  ///@}

  ///@{
  /** Statistics of the last run (also in field data). */
  vtkGetMacro(RelaxedNodeCount, vtkIdType);
  vtkGetMacro(CurvedNodeCount, vtkIdType);
  vtkGetMacro(MaxSurfaceDeviation, double);
  vtkGetMacro(EnvelopeNodeCount, vtkIdType);
  ///@}

protected:
  vtkTet10Mesher();
  ~vtkTet10Mesher() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  /// Properties finite (the clamp macros let NaN through; errors reported); false: refuse
  /// the request before any work. RequestData then checks the input's point ids and
  /// estimated size (hoembed::CheckSurfacePointIds, hoembed::CheckEstimatedSize).
  bool CheckRequest(vtkPolyData* input);

  // the settings: their defaults are hoembed::MesherOptions' and, for the read step's
  // MergeTolerance and MaximumNumberOfElements, hoembed::MesherServiceSettings' (the
  // constructor copies them)
  int TargetNumberOfElements;
  vtkIdType MaximumNumberOfElements;
  double TargetEdgeLength;
  int ElementOrder;
  bool CurveBoundary;
  bool ProjectCorners;
  bool PreserveBoundary;
  double RadiusEdgeRatio;
  double MinDihedralAngle;
  double SurfaceDeviationWarning;
  double CurvedQualityRatio;
  double MinimumQuality;
  double CurvedQualityTarget;
  double EnvelopeTolerance;
  double MergeTolerance;

  vtkIdType RelaxedNodeCount = 0;
  vtkIdType CurvedNodeCount = 0;
  double MaxSurfaceDeviation = 0.0;
  vtkIdType EnvelopeNodeCount = 0;

private:
  vtkTet10Mesher(const vtkTet10Mesher&) = delete;
  void operator=(const vtkTet10Mesher&) = delete;
};

#endif
