/**
 * @class   vtkDeformationTransferFilter
 * @brief   The deformed fine surface of every frame from a deformed FE mesh and the
 *          surface's embedding: v' = p' + d n' (paper eq. 4).
 *
 * Inputs:
 * - port 0: the embedded surface (vtkPolyData), the output of
 *   vtkEmbeddingCoordinatesFilter or that output read back from a file. Point data:
 *   - `EmbeddingCellId` (vtkIdType, any integer array is accepted): the FE cell;
 *   - `EmbeddingParametricCoords` (3 components): VTK parametric (r, s, t) of p in it;
 *   - `EmbeddingDistance` (1 component, normal-offset only): d;
 *   - `EmbeddingFace` (vtkSignedCharArray, optional): the cell's local face
 *     (hoembed::TetFaceNodes order) on which p lies, -1 for d = 0. When the array is
 *     absent (older files), or -1 where d != 0, the face is deduced from the parametric
 *     coordinates: the boundary face of the cell whose opposite barycentric coordinate is
 *     within FaceTolerance of 0.
 *   - `EmbeddingFallbackOffset` (3 components, optional, normal-offset only): q, nonzero
 *     for the vertices embedded without a normal offset (`EmbeddingFallback` of
 *     vtkEmbeddingCoordinatesFilter).
 *   Field data: `EmbeddingMethod` ("normal-offset" or "barycentric") and
 *   `EmbeddingMeshFingerprint` (hoembed::MeshFingerprint of the rest mesh).
 * - port 1: the deformed FE mesh (vtkUnstructuredGrid): all VTK_QUADRATIC_TETRA, all
 *   VTK_TETRA or all VTK_LAGRANGE_TETRAHEDRON of order 1-4, or all of one hexahedron type
 *   (VTK_LAGRANGE_HEXAHEDRON of order 1-3, VTK_TRIQUADRATIC_HEXAHEDRON,
 *   VTK_QUADRATIC_HEXAHEDRON) (Lagrange tets of order 3-4 and the hexahedra: RECOMPUTE
 *   normals only, the other modes fall back to it with a warning), the same points and cells as the
 * rest mesh of the embedding (its fingerprint must match; coordinates may differ). Optional point
 * data for NormalMode ROTATE_NORMALS: `NodalRotation` (9 components, row-major) and `Displacement`
 * (3 components); for DEFORM_NORMALS: `Displacement`.
 *
 * Output: vtkPolyData with the surface's topology (shared, not copied) and point, cell and
 * field data passed through, except the point arrays named `Embedding*` (the embedding
 * and its diagnostics) and any stale point/cell normals; new points:
 * - p' = sum_I N_I(r, s, t) x'_I, the isoparametric map of the deformed cell (tet10 or
 *   tet4 shape functions; for the barycentric method parametric coordinates outside the
 *   cell extrapolate);
 * - normal-offset with d != 0: v' = p' + d n', n' the smooth normal field of the deformed
 *   boundary face (paper eq. 7, hoembed::InterpolateBoundaryNormal conventions) at the
 *   face coordinates of p. Nodal normals:
 *   - RECOMPUTE_NORMALS (default): hoembed::ComputeBoundaryNodeNormals of the deformed
 *     points (paper eq. 6);
 *   - ROTATE_NORMALS (paper §5.1, end): the rest nodal normals rotated by
 *     `NodalRotation` and normalised. The rest normals are computed from the rest points
 *     x - `Displacement` and kept between frames; they are recomputed only when those
 *     rest points change (by more than 1e-9 of the mesh size) or the topology changes.
 *     Without both arrays the filter warns and recomputes the normals.
 *   - DEFORM_NORMALS (beyond the paper): the rest nodal normals pushed forward by the
 *     deformation gradient F = dx/dX at the node (averaged over the cells of the boundary
 *     faces around it, hoembed::DeformNodalNormals) and normalised: the offset follows the
 *     material line that was normal to the rest surface. It equals the other two modes
 *     for rigid motions and for deformations without shear at the surface (bending), and
 *     follows a shear of the surface layer (a twist tilts the lines normal to the rest
 *     surface; RECOMPUTE_NORMALS keeps the offsets normal to the deformed surface instead,
 *     ROTATE_NORMALS follows only the rotation). Needs `Displacement` (rest points, as
 *     for ROTATE_NORMALS); without it the filter warns and recomputes the normals.
 * - fallback vertices (q != 0): v' = p' + J' q, J' = dx'/d(r, s, t) of the deformed cell
 *   at p: p' + F (v - p) with F the deformation gradient at p, whatever the NormalMode
 *   (they have no normal offset; at rest this rebuilds v to round-off, and a rigid motion
 *   moves them rigidly).
 * - barycentric method: v' = p'.
 * - with ComputePointNormals on, unit vertex normals (float array `Normals`, the active
 *   point normals) for rendering, as PointNormalsMode says:
 *   - RECOMPUTE_POINT_NORMALS (default): area-weighted normals of the output polygons;
 *   - TRANSFORM_POINT_NORMALS: the rest surface's area-weighted normals n0 (from port 0's
 *     points, computed once) carried by the deformation at each vertex's p: cof(F) n0,
 *     F the deformation gradient of the cell map at p (Nanson's formula for a material
 *     surface element), computed in the same per-vertex pass as the positions, with no
 *     pass over the polygons. Equal to the recomputed normals at rest and under a rigid
 *     motion to float round-off; under a deformation they differ by what the map does
 *     between p and v (the offset d n' is not differentiated) and by the discretisation
 *     of the recomputed ones (Benchmarks/RESULTS.md, live loop). Where det F <= 0 or p
 *     lies in an inverted element (the map folds) the vertex's normal is recomputed from
 *     its polygons
 *     (NumberOfFoldedPointNormals). Needs `Displacement` on port 1 (the rest mesh is
 *     x - Displacement); without it the filter warns and recomputes.
 *
 * Time: the mesh's DATA_TIME_STEP is set on the output; TIME_STEPS / TIME_RANGE of port
 * 1 are announced downstream and a requested UPDATE_TIME_STEP is forwarded to port 1, so
 * stepper -> transfer -> writer produces a surface time series.
 *
 * Caching: the mesh topology (adjacency, boundary faces, fingerprint) is rebuilt only when
 * the mesh's cell array changes and then has a different fingerprint; the per-vertex plan
 * only when the surface or its arrays change. A frame then allocates nothing beyond the
 * output arrays: small per-frame tables (size of the FE mesh) are reused.
 *
 * Threading: the per-vertex evaluation, the coefficient tables, the element check and
 * the output normals run in parallel with vtkSMPTools.
 *
 * Errors (vtkErrorMacro, empty output): missing or mis-sized embedding arrays or field
 * data, an unknown method, a fingerprint that differs from the mesh's, mixed or
 * unsupported cell types, cell ids out of range, non-finite embedding values, non-finite
 * deformed coordinates. Warnings: inverted or degenerate deformed elements (det J <= 0 at
 * a corner or the centroid: the transfer is still computed, it is a map), ROTATE_NORMALS
 * without its arrays.
 *
 * @warning The output normals use polygons only (not triangle strips).
 * @sa vtkEmbeddingCoordinatesFilter, vtkCorotationalFEMStepper, hoembedTransferKernel.h
 */
#ifndef vtkDeformationTransferFilter_h
#define vtkDeformationTransferFilter_h

#include "hoembedFiltersTransferModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

#include <memory> // for std::unique_ptr

class vtkFloatArray;
class vtkPoints;
class vtkUnstructuredGrid;

class HOEMBEDFILTERSTRANSFER_EXPORT vtkDeformationTransferFilter : public vtkPolyDataAlgorithm
{
public:
  static vtkDeformationTransferFilter* New();
  vtkTypeMacro(vtkDeformationTransferFilter, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum NormalModes
  {
    RECOMPUTE_NORMALS = 0,
    ROTATE_NORMALS = 1,
    DEFORM_NORMALS = 2
  };

  ///@{
  /**
   * How the deformed nodal normals are obtained: RECOMPUTE_NORMALS (default) from the
   * deformed boundary, ROTATE_NORMALS from the rest normals and `NodalRotation`,
   * DEFORM_NORMALS from the rest normals pushed forward by the nodal deformation gradient
   * (needs `Displacement`).
   */
  vtkSetClampMacro(NormalMode, int, RECOMPUTE_NORMALS, DEFORM_NORMALS);
  vtkGetMacro(NormalMode, int);
  void SetNormalModeToRecompute()
  {
    this->SetNormalMode(RECOMPUTE_NORMALS);
  }
  void SetNormalModeToRotate()
  {
    this->SetNormalMode(ROTATE_NORMALS);
  }
  void SetNormalModeToDeform()
  {
    this->SetNormalMode(DEFORM_NORMALS);
  }
  ///@}

  ///@{
  /** Add area-weighted point normals `Normals` to the output (default off). */
  vtkSetMacro(ComputePointNormals, bool);
  vtkGetMacro(ComputePointNormals, bool);
  vtkBooleanMacro(ComputePointNormals, bool);
  ///@}

  enum PointNormalsModes
  {
    RECOMPUTE_POINT_NORMALS = 0,
    TRANSFORM_POINT_NORMALS = 1
  };

  ///@{
  /**
   * How the output point normals (ComputePointNormals) are obtained:
   * RECOMPUTE_POINT_NORMALS (default) from the deformed polygons, TRANSFORM_POINT_NORMALS
   * from the rest normals carried by the deformation gradient (needs `Displacement`).
   */
  vtkSetClampMacro(PointNormalsMode, int, RECOMPUTE_POINT_NORMALS, TRANSFORM_POINT_NORMALS);
  vtkGetMacro(PointNormalsMode, int);
  void SetPointNormalsModeToRecompute()
  {
    this->SetPointNormalsMode(RECOMPUTE_POINT_NORMALS);
  }
  void SetPointNormalsModeToTransform()
  {
    this->SetPointNormalsMode(TRANSFORM_POINT_NORMALS);
  }
  ///@}

  ///@{
  /** Warn about inverted deformed elements (default on; costs 5 det J per cell). */
  vtkSetMacro(CheckInvertedElements, bool);
  vtkGetMacro(CheckInvertedElements, bool);
  vtkBooleanMacro(CheckInvertedElements, bool);
  ///@}

  ///@{
  /**
   * Largest |barycentric coordinate| of the opposite corner for which a point counts as
   * lying on a face, when the face is deduced (no `EmbeddingFace`); default 1e-6.
   */
  vtkSetMacro(FaceTolerance, double);
  vtkGetMacro(FaceTolerance, double);
  ///@}

  ///@{
  /**
   * Precision of the output points: vtkAlgorithm::DEFAULT_PRECISION (default: that of
   * the surface's points), SINGLE_PRECISION or DOUBLE_PRECISION.
   */
  vtkSetClampMacro(OutputPointsPrecision, int, SINGLE_PRECISION, DEFAULT_PRECISION);
  vtkGetMacro(OutputPointsPrecision, int);
  ///@}

  ///@{
  /** Results of the last run: inverted deformed elements, and how often the topology
   * and the per-vertex plan were (re)built since construction (for cache checks). */
  vtkGetMacro(NumberOfInvertedElements, vtkIdType);
  /// TRANSFORM_POINT_NORMALS: vertices of the last run whose normal came from the polygons
  /// because the deformation folds there (inverted elements).
  vtkGetMacro(NumberOfFoldedPointNormals, vtkIdType);
  vtkGetMacro(TopologyBuildCount, int);
  vtkGetMacro(PlanBuildCount, int);
  ///@}

  /** The deformed mesh on port 1 (the same as SetInputConnection(1, ...)). */
  void SetMeshConnection(vtkAlgorithmOutput* output)
  {
    this->SetInputConnection(1, output);
  }
  void SetMeshData(vtkDataObject* mesh)
  {
    this->SetInputData(1, mesh);
  }

protected:
  vtkDeformationTransferFilter();
  ~vtkDeformationTransferFilter() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  // the settings: their defaults are hoembed::TransferOptions' (the constructor copies
  // them); OutputPointsPrecision is VTK's own (vtkAlgorithm::DesiredOutputPrecision)
  int NormalMode;
  bool ComputePointNormals;
  int PointNormalsMode;
  bool CheckInvertedElements;
  double FaceTolerance;
  int OutputPointsPrecision = DEFAULT_PRECISION;

  vtkIdType NumberOfInvertedElements = 0;
  vtkIdType NumberOfFoldedPointNormals = 0;
  int TopologyBuildCount = 0;
  int PlanBuildCount = 0;

private:
  vtkDeformationTransferFilter(const vtkDeformationTransferFilter&) = delete;
  void operator=(const vtkDeformationTransferFilter&) = delete;

  // The steps of RequestData (the algorithm itself is hoembed::TransferDriver): read the
  // mesh's cells into the driver (cached), read the embedding into its plan (cached),
  // run one frame into `newPoints`, write the output (and its optional normals).
  bool PrepareMesh(vtkUnstructuredGrid* mesh);
  bool PreparePlan(vtkPolyData* surface, vtkUnstructuredGrid* mesh);
  void PreparePolygons(vtkPolyData* surface);
  bool TransferPoints(
    vtkPolyData* surface, vtkUnstructuredGrid* mesh, vtkPoints* newPoints, vtkFloatArray* normals);
  void WriteOutput(
    vtkPolyData* surface, vtkPoints* newPoints, vtkFloatArray* normals, vtkPolyData* output);

  struct Internals;
  std::unique_ptr<Internals> Internal;
};

#endif
