/**
 * @file hoembedEmbeddingSearch.h
 * @brief Embedding of one surface vertex in a prepared FE mesh (paper Algorithm 1 and
 * section 5): exact closest point, inside/outside, normal-offset correction.
 *
 * Per vertex v, from a hint (the result of a neighbouring vertex, paper Algorithm 2).
 * When the neighbour's distance to the mesh exceeds its distance to v, v is outside
 * (the distance is 1-Lipschitz) and the inside tests of steps 1 and 3 are skipped.
 * 1. If the hint was inside the mesh: try the hint cell (Newton inversion of the tet
 *    map from the straight tet's coordinates, accepted only inside the cell) and walk up
 *    to 8 cells, each time across the face beyond which the point lies (most negative
 *    barycentric coordinate). (From an outside hint this found v inside in about 1 case
 *    of 10 on the real meshes: those go to step 2 and are located in step 3.)
 * 2. Otherwise the closest boundary point: Algorithm 1 over boundary faces from the hint
 *    face (tri6 closest point; on an edge go to the face across it, at a corner to all
 *    faces around the node), then certification with the face boxes (EmbeddingMesh::
 *    FaceGrid within the best distance when that spans at most 2 x 2 x 2 bins, else the
 *    face tree, EmbeddingMesh::GetFaceTree, nearest boxes first): every face whose
 *    control-point box and lower bound (EmbeddingMesh::FaceLowerBound2) are nearer than
 *    the best distance is solved too, unless the exact expansion at the closest point of
 *    its flat triangle already puts it beyond (PatchFartherThan); then every curved face
 *    solved whose bound still
 *    leaves room below its own solution and the best distance is certified on the whole
 *    face (hoembedClosestPointCertify.h: the squared distance on a curved face is not
 *    convex), by the exact expansion at its solution or else by branch and bound, so the
 *    result is the global minimum over the boundary (to 1e-10 of the diagonal).
 * 3. Inside/outside. First a proof from an outside neighbour: the open balls around it
 *    and around v, each of its certified distance less the certification tolerance,
 *    hold no boundary point; when they meet, their union is connected and lies wholly
 *    outside (as the neighbour does) or wholly inside, so v is outside (no cell tests).
 *    Else from the pseudo-normal at the closest point (face normal, sum of the
 *    two face normals on an edge, angle-weighted node normal at a corner); points that
 *    may be inside are located in a cell: Algorithm 1 over cells from the closest face's
 *    cell (constrained closest point in the cell, Newton inversion from the centroid when
 *    it stops on the cell's border, then the neighbour across the face the solution
 *    lies on; visited stamps, explicit queue), then every cell whose box holds the
 *    point (EmbeddingMesh::CellGrid). A point the pseudo-normal puts outside is still
 *    tested (Newton inversion of the cell's map, given up where the map folds; a
 *    solution outside the element excludes the cell when TetMapExclusionRadius proves
 *    no point of it within the tolerance, with the cell's exclusion rate where that
 *    covers the solution, else the constrained closest point in the cell decides)
 *    against every
 *    cell whose control-point box and straight-face slabs (EmbeddingMesh::CellForms)
 *    hold it: a curved mesh whose boundary crosses itself (a cell poking through a
 *    boundary face elsewhere) has inside points on the outer side of their closest face.
 *    When the closest point p lies inside a face, testing p instead against the cells
 *    other than the face's owner is enough (the ball around v up to the boundary lies
 *    wholly inside or outside the mesh, and the owner holds nothing just outside its
 *    face; see OutsideByFace in the .cxx): about half the cell tests.
 *    Points within 1e-11 of the mesh diagonal of the boundary count as inside.
 *    Points classified outside keep the exact boundary distance.
 * 4. Outside points, normal-offset: Newton on (u, v, d) with x(u, v) + d n(u, v) = v,
 *    n the normalised interpolated nodal normal (eq. 7-9), walking across boundary edges
 *    when the iteration leaves the face; if that fails, the faces around the closest
 *    face's corners, then every face within eight times the distance (4 starts each;
 *    smallest |d| wins); a solution counts only where |d| is within eight times the
 *    distance (a far foot is another solution beyond the normal field's focal distance,
 *    and which one a walk reaches depends on where it starts); if none converges, the closest point
 * with the offset v - p in the cell's parametric units (VertexEmbedding::Fallback). Barycentric:
 * the owning cell of the closest face with extrapolated (unconstrained) parametric coordinates.
 */
#ifndef hoembedEmbeddingSearch_h
#define hoembedEmbeddingSearch_h

#include "hoembedEmbeddingMesh.h"
#include "hoembedArrayNames.h"
#include "hoembedFiltersEmbeddingModule.h"

#include <utility>
#include <vector>

namespace hoembed
{
/// The kernels' `method` argument: the values of the one method enum,
/// hoembed::EmbeddingMethod (hoembedArrayNames.h), which vtkEmbeddingCoordinatesFilter's
/// NORMAL_OFFSET / BARYCENTRIC equal.
constexpr int EMBED_NORMAL_OFFSET = static_cast<int>(EmbeddingMethod::NormalOffset);
constexpr int EMBED_BARYCENTRIC = static_cast<int>(EmbeddingMethod::Barycentric);

struct VertexHint
{
  EmbeddingMesh::Id Face = -1; ///< boundary face
  double UV[2] = { 1.0 / 3.0, 1.0 / 3.0 };
  EmbeddingMesh::Id Cell = -1;
  bool Inside = false;
  /// The neighbour's position and its certified distance to the mesh (when Distance >= 0):
  /// the distance is 1-Lipschitz, so Distance - |v - Point| > 0 proves v outside the mesh;
  /// and an outside neighbour whose boundary-free ball meets v's proves v outside too.
  double Point[3] = { 0, 0, 0 };
  double Distance = -1.0;
};

struct VertexEmbedding
{
  EmbeddingMesh::Id Cell = -1;
  double PC[3] = { 0, 0, 0 };
  double Distance = 0.0;        ///< signed offset along the smooth normal (0 inside)
  double ClosestDistance = 0.0; ///< distance to the mesh (0 inside)
  double Residual = 0.0;        ///< |v - (p + d n)| of the reconstruction
  signed char Face = -1;        ///< local face of Cell the point p lies on, -1 inside
  int Iterations = 0;
  int Visited = 0;
  bool Inside = false;
  /// a curved face's certified search ran out of its budget: the distance may be a
  /// local minimum only (never seen on the real meshes; reported by the filter)
  bool Uncertified = false;
  /// normal-offset: no (u, v, d) on any face tried rebuilds v (v = p + d n has no
  /// solution within the tolerance there); then Distance = 0, Face = -1, p is the closest
  /// point and v = p + J(pc) q, q from hoembed::TetMapOffset (not stored: rare, and this
  /// struct is kept per surface vertex)
  bool Fallback = false;
  EmbeddingMesh::Id BoundaryFace = -1; ///< closest boundary face (-1 if not computed)
  double UV[2] = { 0, 0 };

  /// The hint for a neighbour of the vertex v embedded here.
  VertexHint AsHint(const double v[3]) const;
};

/// Per-thread scratch space (visited stamps, queues).
struct SearchScratch
{
  std::vector<unsigned> FaceStamp, CellStamp;
  unsigned Stamp = 0;
  std::vector<EmbeddingMesh::Id> Queue, Candidates;
  /// a curved boundary face solved during the search, certified after it
  struct SolvedFace
  {
    EmbeddingMesh::Id Face;
    ClosestPointResult Result;
    double Bound; ///< EmbeddingMesh::FaceLowerBound2 for the vertex (< 0: not computed)
  };
  std::vector<SolvedFace> Retry;
  /// per cell: TetMapExclusionRate, computed when first needed (-1: not yet)
  std::vector<double> ExclusionRate;
  void Prepare(const EmbeddingMesh& mesh);
  unsigned NextStamp();
};

/// Embed one vertex (see the file comment).
HOEMBEDFILTERSEMBEDDING_EXPORT void EmbedVertex(const EmbeddingMesh& mesh, int method,
  const double v[3], const VertexHint& hint, VertexEmbedding& out, SearchScratch& scratch);

/**
 * Reference for tests: the distance from v to the mesh by exhaustive search, every
 * boundary face from 7 starts and every cell from 5 starts (0 when some cell contains v
 * within 1e-11 of the diagonal). `face`, `uv` receive the best boundary face.
 */
HOEMBEDFILTERSEMBEDDING_EXPORT double BruteForceDistance(const EmbeddingMesh& mesh,
  const double v[3], EmbeddingMesh::Id* face = nullptr, double* uv = nullptr);

/// |v - (p + d n)| with p the tet map at (cell, pc) and n the smooth normal of local face
/// `face` of the cell at the matching (u, v) (n = 0 when face < 0).
HOEMBEDFILTERSEMBEDDING_EXPORT double ReconstructionResidual(const EmbeddingMesh& mesh,
  const double v[3], EmbeddingMesh::Id cell, const double pc[3], int face, double d);
} // namespace hoembed

#endif
