/**
 * @class   vtkEmbeddingCoordinatesFilter
 * @brief   Embedding coordinates of a fine triangle surface in a curved tet10 (or tet4)
 *          FE mesh: exact closest points and the normal-offset representation
 *          v = p + d n of Suwelack et al. 2013.
 *
 * Inputs: port 0, the fine surface (vtkPolyData; its triangles drive the flood of the
 * paper's Algorithm 2; polygons are fanned, strips split, vertices in no triangle and
 * several connected components are fine). Port 1, the rest FE mesh
 * (vtkUnstructuredGrid of VTK_QUADRATIC_TETRA cells, or VTK_TETRA for the baseline, or
 * VTK_LAGRANGE_TETRAHEDRON of order 1-4, or the hexahedra VTK_LAGRANGE_HEXAHEDRON of
 * uniform order 1-3 (the order from the node count: 8, 27, 64), VTK_TRIQUADRATIC_HEXAHEDRON
 * and VTK_QUADRATIC_HEXAHEDRON, in VTK's node order; one cell type per mesh).
 * Lagrange orders 1-2 take the tet4 / tet10 path; orders 3-4 a per-vertex certified
 * search (hoembedLagrangeEmbedding.h: no flood, slower, the same arrays), the hexahedra
 * its tensor-product twin (hoembedLagrangeHexEmbedding.h; EmbeddingFace: 0-5, the
 * faces r = 0, r = 1, s = 0, s = 1, t = 0, t = 1).
 *
 * Output: a shallow copy of the surface with point data
 * - `EmbeddingCellId` (vtkIdTypeArray): the cell holding the point p;
 * - `EmbeddingParametricCoords` (vtkDoubleArray, 3 components): VTK parametric
 *   (r, s, t) of p in that cell;
 * - `EmbeddingDistance` (vtkDoubleArray): the signed offset d along the smooth normal
 *   (0 inside the mesh and for Method barycentric);
 * - `EmbeddingResidual` (vtkDoubleArray): |v - (p + d n)| at rest, recomputed from the
 *   stored coordinates exactly as vtkDeformationTransferFilter rebuilds v;
 * - `EmbeddingFace` (vtkSignedCharArray): the local face (hoembed::TetFaceNodes order) of
 *   the cell on which p lies, -1 inside the mesh (and always for barycentric);
 * - diagnostics `EmbeddingIterations`, `EmbeddingElementsVisited` (vtkIntArray: solver
 *   iterations and faces/cells solved for the vertex) and `EmbeddingClosestDistance`
 *   (vtkDoubleArray: the exact distance to the mesh, 0 inside);
 * - `EmbeddingFallback` (vtkUnsignedCharArray): 1 where the normal offset has no
 *   solution and the closest-point offset is used instead (see below), else 0;
 * - `EmbeddingFallbackOffset` (vtkDoubleArray, 3 components; only when some point has
 *   EmbeddingFallback = 1): the offset q of those points, 0 elsewhere;
 * and field data `EmbeddingMethod` (vtkStringArray: "normal-offset" or "barycentric"),
 * `EmbeddingMeshFingerprint` (vtkStringArray: hoembed::MeshFingerprint of the rest mesh)
 * and `NumberOfFallbackPoints` (vtkIdTypeArray, one value).
 *
 * Normal-offset (default): p is the closest point of the mesh to v. Outside the mesh, p
 * is corrected (paper eq. 8-9) so that v = p + d n holds to 1e-12 of the mesh diagonal with
 * n = hoembed::InterpolateBoundaryNormal on the boundary face (normalised, eq. 7) at p
 * and nodal normals from hoembed::ComputeBoundaryNodeNormals. Barycentric: inside points
 * get their containing cell; outside points the cell of the closest boundary point with
 * extrapolated parametric coordinates (d = 0). For tet4 the extrapolated affine map
 * reproduces v exactly; for a curved tet10 the quadratic map extrapolated beyond its cell
 * may not reach v at all (how often on real scans: Benchmarks/RESULTS.md): the Newton
 * inversion then keeps the nearest point it reaches and EmbeddingResidual says how far v
 * is from it. This is a limit of the barycentric
 * baseline, one reason normal-offset is the default.
 *
 * The closest point is the global one: the flood gives each vertex a start (paper
 * Algorithm 2), the walk across faces/edges refines it (Algorithm 1), and a box grid (a
 * box tree for far points) over the boundary faces certifies it. See hoembedEmbeddingSearch.h and
 * hoembedEmbeddingFlood.h. "Inside the mesh" means inside some cell: where a curved cell pokes
 * through a boundary face of another part of the mesh (close parts of a thin shape), a point in
 * that cell is inside even though it lies on the outer side of its closest boundary face.
 *
 * Threading: the flood runs in patches of the surface in parallel with vtkSMPTools; the
 * mesh preparation (itself parallel) and the surface's ordering for the flood run as two
 * tasks. Progress events are fired (from the calling thread).
 *
 * Memory: the filter keeps its working memory (the prepared mesh's arrays; the flood's, up
 * to 64 MB, about 190k surface vertices) for the next Update, which then touches no fresh
 * pages (kernel page faults were a fifth to a quarter of the time of an Update on the
 * small real surfaces). With ReuseMeshPreparation (default on) it also keeps the prepared
 * mesh itself while the mesh input is unmodified, as VTK's locators keep their search
 * structures: embedding another surface, or the same one changed, in the same FE mesh
 * then skips the preparation (topology, normals, maps, grids, element validation).
 * "Unmodified" is VTK's modification time: of the grid (its points included), of its cell
 * array and of the cell arrays' data; changing the mesh in place needs a Modified() call,
 * as everywhere in VTK.
 *
 * Defaults: Method normal-offset, NumberOfPartitions 0 (automatic), ValidateElements on,
 * ReuseMeshPreparation on.
 *
 * Fallback: the normal-offset representation need not exist everywhere (the smooth normal
 * field can fold or vanish; and for a point so far away that the round-off of d n exceeds
 * the 1e-12 tolerance, e.g. a surface vastly larger than the mesh, no d rebuilds v to
 * it; or v = p + d n holds only with a foot p beyond eight times the closest distance,
 * which would swing v on a long lever). When the correction converges on no face tried
 * (around the closest point, then every face within eight times the distance) to a foot
 * within eight times the distance, the point falls back to its closest point p
 * with the offset v - p: EmbeddingFallback = 1, EmbeddingDistance = 0, EmbeddingFace =
 * -1, EmbeddingCellId / EmbeddingParametricCoords give p, and EmbeddingFallbackOffset
 * holds q = J(pc)^-1 (v - p), the offset in the cell's parametric units (J = dx/dpc
 * at p): p + J q rebuilds v to round-off (EmbeddingResidual = |v - (p + J q)|), and
 * vtkDeformationTransferFilter maps it as p' + J' q = p' + F (v - p), F = J' J^-1 the
 * deformation gradient at p (rigid motions move it rigidly; the smooth normal field,
 * and so NormalMode, plays no part for these points). The filter warns with their
 * number, also available as NumberOfFallbackPoints (on their own ~1000-element meshes:
 * 2 of the thorny tail's vertices on tet10, 29 on tet4; none for bunny_lowres and
 * armadillo_lowres on tet10, 8 and 7 on tet4).
 * @warning Bad input (empty surface or mesh, non-finite coordinates, cells other than
 * tet4/tet10, inverted or degenerate elements, broken topology) is reported with
 * vtkErrorMacro and leaves the output empty. A surface far from the mesh is valid.
 * @sa vtkDeformationTransferFilter, vtkTet10Mesher
 */
#ifndef vtkEmbeddingCoordinatesFilter_h
#define vtkEmbeddingCoordinatesFilter_h

#include "hoembedFiltersEmbeddingModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

#include <memory> // for std::unique_ptr
#include <string> // for std::string

class vtkUnstructuredGrid;

class HOEMBEDFILTERSEMBEDDING_EXPORT vtkEmbeddingCoordinatesFilter : public vtkPolyDataAlgorithm
{
public:
  static vtkEmbeddingCoordinatesFilter* New();
  vtkTypeMacro(vtkEmbeddingCoordinatesFilter, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  // The values of hoembed::EmbeddingMethod (hoembedArrayNames.h), repeated here so that
  // the wrapped class carries them (the wrappers see plain enumerators only).
  enum MethodType
  {
    NORMAL_OFFSET = 0,
    BARYCENTRIC = 1
  };

  ///@{
  /**
   * NORMAL_OFFSET (0, default, the paper's scheme) or BARYCENTRIC (1, the baseline).
   */
  vtkSetClampMacro(Method, int, NORMAL_OFFSET, BARYCENTRIC);
  vtkGetMacro(Method, int);
  void SetMethodToNormalOffset()
  {
    this->SetMethod(NORMAL_OFFSET);
  }
  void SetMethodToBarycentric()
  {
    this->SetMethod(BARYCENTRIC);
  }
  const char* GetMethodAsString();
  ///@}

  ///@{
  /**
   * Number of surface patches flooded independently (in parallel); 0 (default) picks
   * about one per 1000 triangles, at most 256.
   */
  vtkSetMacro(NumberOfPartitions, int);
  vtkGetMacro(NumberOfPartitions, int);
  ///@}

  ///@{
  /**
   * Refuse meshes with inverted or degenerate elements (default on): tet10 by
   * hoembed::Tet10IsValid (det J > 0 over the whole element), tet4 by its determinant.
   */
  vtkSetMacro(ValidateElements, bool);
  vtkGetMacro(ValidateElements, bool);
  vtkBooleanMacro(ValidateElements, bool);
  ///@}

  ///@{
  /**
   * Keep the prepared FE mesh between Updates while the mesh input is unmodified (default
   * on; see the class comment). Off: every Update prepares the mesh anew.
   */
  vtkSetMacro(ReuseMeshPreparation, bool);
  vtkGetMacro(ReuseMeshPreparation, bool);
  vtkBooleanMacro(ReuseMeshPreparation, bool);
  ///@}

  /**
   * How many times this filter has prepared an FE mesh (Updates that reused the prepared
   * mesh do not count).
   */
  vtkGetMacro(NumberOfMeshPreparations, vtkIdType);

  /**
   * Surface points of the last run whose closest-point search on a curved boundary face
   * ran out of its budget (hoembedClosestPointCertify.h): their distance may be a local
   * minimum only. The filter warns when there are any (none on the real meshes of the
   * benchmarks).
   */
  vtkGetMacro(NumberOfUncertifiedPoints, vtkIdType);

  /**
   * Surface points of the last run without a normal offset, embedded by the fallback
   * (closest point and offset v - p; see the class comment, EmbeddingFallback). The
   * filter warns when there are any.
   */
  vtkGetMacro(NumberOfFallbackPoints, vtkIdType);

  ///@{
  /**
   * The rest FE mesh on port 1.
   */
  void SetMeshData(vtkUnstructuredGrid* mesh);
  void SetMeshConnection(vtkAlgorithmOutput* output);
  ///@}

protected:
  vtkEmbeddingCoordinatesFilter();
  ~vtkEmbeddingCoordinatesFilter() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  // The steps of RequestData around hoembed::EmbeddingDriver: prepare the mesh (unless
  // the prepared one serves) and order the surface, write the output arrays.
  bool PrepareMeshAndOrder(vtkUnstructuredGrid* mesh);
  bool WriteOutput(vtkPolyData* surface, vtkPolyData* output);

  // the settings: their defaults are hoembed::EmbeddingOptions' (the constructor copies
  // them)
  int Method;
  int NumberOfPartitions;
  bool ValidateElements;
  bool ReuseMeshPreparation;
  vtkIdType NumberOfUncertifiedPoints = 0;
  vtkIdType NumberOfFallbackPoints = 0;
  vtkIdType NumberOfMeshPreparations = 0;

private:
  /// Working memory kept between Updates (the prepared mesh and what identifies its
  /// input; the flood's arrays up to a cap), so that an Update after the first touches no
  /// fresh pages.
  struct vtkInternals;
  std::unique_ptr<vtkInternals> Internals;

  vtkEmbeddingCoordinatesFilter(const vtkEmbeddingCoordinatesFilter&) = delete;
  void operator=(const vtkEmbeddingCoordinatesFilter&) = delete;
};

#endif
