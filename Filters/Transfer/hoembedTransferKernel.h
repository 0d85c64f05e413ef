/**
 * @file hoembedTransferKernel.h
 * @brief The per-frame work of the deformation transfer (paper eq. 4): v' = p' + d n'.
 *
 * Plain C++ kernels (no VTK pipeline code, no Eigen). The transfer is split into
 * - a *plan*, one TransferEntry per surface vertex, built once from the embedding arrays
 *   (cell, parametric coordinates, distance, boundary face) and reused for every frame;
 * - per-frame *coefficient tables*, small (size of the FE mesh): the isoparametric map of
 *   every deformed cell and the smooth normal field of every deformed boundary face, both
 *   as monomial coefficients, contiguous per cell / face, so the per-vertex loop reads one
 *   contiguous block per cell and no node ids;
 * - the per-vertex evaluation over a range [begin, end) (the caller splits the range over
 *   threads; every entry is independent).
 *
 * Coefficient layouts (3 doubles per coefficient vector):
 * - tet10 cell: x(r,s,t) = c1 + cr r + cs s + ct t + crr r^2 + css s^2 + ctt t^2
 *   + crs rs + crt rt + cst st (10 vectors, 30 doubles, in that order); tet4: c1, cr, cs,
 *   ct (4 vectors, 12 doubles). Equal to the VTK shape functions' sum_I N_I x_I.
 * - tri6 boundary face normal field: n(u,v) = a1 + au u + av v + auu u^2 + avv v^2
 *   + auv uv (6 vectors); tri3: a1, au, av (3 vectors). Equal to sum_a N_a nbar_a
 *   (paper eq. 7 before normalisation); the evaluation normalises.
 */
#ifndef hoembedTransferKernel_h
#define hoembedTransferKernel_h

#include "hoembedFiltersTransferModule.h"
#include "hoembedTetMeshTopology.h"

#include <cstdint>

namespace hoembed
{
/// One surface vertex of the plan (48 bytes).
struct TransferEntry
{
  double PC[3];      ///< parametric coordinates (r, s, t) in Cell
  double Distance;   ///< d of v = p + d n (0: no normal offset)
  std::int32_t Cell; ///< FE cell
  std::int32_t Face; ///< 4 * boundary face index + local face of Cell, or -1 (no offset)
};

/// Number of doubles per cell in the map coefficient table (30 for tet10, 12 for tet4).
inline int CellCoefficientSize(int nodesPerCell)
{
  return nodesPerCell == 10 ? 30 : 12;
}
/// Number of doubles per boundary face in the normal coefficient table (18 tri6, 9 tri3).
inline int FaceCoefficientSize(int nodesPerCell)
{
  return nodesPerCell == 10 ? 18 : 9;
}

/**
 * Map coefficients of cells [begin, end): `conn` holds nodesPerCell ids per cell, `points`
 * 3 doubles per node; `coeffs` receives CellCoefficientSize doubles per cell.
 */
HOEMBEDFILTERSTRANSFER_EXPORT void ComputeCellMapCoefficients(const std::int64_t* conn,
  int nodesPerCell, const double* points, std::int64_t begin, std::int64_t end, double* coeffs);

/**
 * Normal-field coefficients of boundary faces [begin, end) of `topo` from nodal normals
 * (3 doubles per node); `coeffs` receives FaceCoefficientSize doubles per face.
 */
HOEMBEDFILTERSTRANSFER_EXPORT void ComputeFaceNormalCoefficients(const TetMeshTopology& topo,
  const double* nodalNormals, std::int64_t begin, std::int64_t end, double* coeffs);

/**
 * Face-local (u, v) (hoembed::TetFaceToTetParametric convention, tri node order of
 * hoembed::TetFaceNodes) of the tet parametric point `pc` on local face `face`: the
 * barycentric coordinates of the face's corners b and c, divided by the sum of those of
 * a, b, c (so a point slightly off the face is projected along the opposite corner).
 */
HOEMBEDFILTERSTRANSFER_EXPORT void TetParametricToFace(int face, const double pc[3], double uv[2]);

/**
 * The boundary face of `cell` on which the parametric point `pc` lies: among the cell's
 * local faces that are boundary faces, the one whose opposite barycentric coordinate is
 * smallest in magnitude, if that is <= tol. Returns 4 * boundary face + local face
 * (the TransferEntry::Face encoding), or -1 when there is none.
 */
HOEMBEDFILTERSTRANSFER_EXPORT std::int32_t DeduceBoundaryFace(
  const TetMeshTopology& topo, std::int64_t cell, const double pc[3], double tol);

/**
 * Deformed positions of plan entries [begin, end): out[3 i..3 i+2] = p' + d n' for entry i
 * (p' from the cell map coefficients, n' the normalised normal field of its boundary face;
 * entries with Face < 0 or Distance == 0 give p'). `faceCoeffs` may be null when no entry
 * has an offset. A degenerate normal (zero interpolated sum) gives p' alone.
 */
HOEMBEDFILTERSTRANSFER_EXPORT void EvaluateTransfer(const TransferEntry* plan, int nodesPerCell,
  const double* cellCoeffs, const double* faceCoeffs, std::int64_t begin, std::int64_t end,
  double* out);
/// The same, writing single precision.
HOEMBEDFILTERSTRANSFER_EXPORT void EvaluateTransfer(const TransferEntry* plan, int nodesPerCell,
  const double* cellCoeffs, const double* faceCoeffs, std::int64_t begin, std::int64_t end,
  float* out);

/**
 * Shading normals transformed from the rest surface (fused with the position transfer):
 * the deformed normal of a material surface element is cof(F) n0 (Nanson), F = J' J0^-1
 * the deformation gradient at p, and cof(F) n0 = cof(J') (J0^T n0) / det J0 with J0, J'
 * = d x / d(r, s, t) of the rest and the deformed cell at p. The rest factor is constant
 * per vertex: ComputeNormalCovectors stores m = J0^T n0 / det J0, normalised, 3 floats
 * per vertex (zero where n0 or det J0 is zero), once per rest state; a frame then needs
 * only J' at p (from the cell map coefficients it already reads) and m:
 * n' = normalise(m_r (J'_s x J'_t) + m_s (J'_t x J'_r) + m_t (J'_r x J'_s)).
 * At rest this gives n0 and under a rigid motion R n0, to round-off. Vertices with a
 * normal offset take F at p too (the offset's own gradient, d dn'/du, is left out).
 */
HOEMBEDFILTERSTRANSFER_EXPORT void ComputeNormalCovectors(const TransferEntry* plan,
  int nodesPerCell, const double* restCellCoeffs, const float* restNormals, std::int64_t begin,
  std::int64_t end, float* covectors);

/**
 * EvaluateTransfer that also writes the transformed shading normals of entries
 * [begin, end) into `normals` (3 floats per vertex; (0, 0, 0) where the covector is zero
 * or the deformed cofactor maps it to zero). The positions are those of EvaluateTransfer,
 * bit for bit. Where det J' <= 0 (the map folds there; cof(J') would turn the normal
 * inside out) or the entry's cell is flagged in `folded` (one byte per cell, may be null:
 * MarkInvertedCells) the normal is left NaN for the caller to recompute from the
 * polygons; returns how many.
 */
HOEMBEDFILTERSTRANSFER_EXPORT std::int64_t EvaluateTransfer(const TransferEntry* plan,
  int nodesPerCell, const double* cellCoeffs, const double* faceCoeffs, const float* covectors,
  const unsigned char* folded, std::int64_t begin, std::int64_t end, double* out, float* normals);
/// The same, writing single precision positions.
HOEMBEDFILTERSTRANSFER_EXPORT std::int64_t EvaluateTransfer(const TransferEntry* plan,
  int nodesPerCell, const double* cellCoeffs, const double* faceCoeffs, const float* covectors,
  const unsigned char* folded, std::int64_t begin, std::int64_t end, float* out, float* normals);

/**
 * Which code EvaluateTransfer runs: 1 its AVX2 copy (where the build has it and the CPU
 * has AVX2), 0 the plain one, -1 (default) decided from the CPU. Both give the same bits;
 * this is for the tests that check so and for timings. Returns whether AVX2 is now used.
 */
HOEMBEDFILTERSTRANSFER_EXPORT bool SetTransferKernelSimd(int mode);

/**
 * Deformed positions of the fallback vertices (vtkEmbeddingCoordinatesFilter's
 * EmbeddingFallback: no normal offset, v = p + J q at rest): for k in [begin, end),
 * i = vertices[k], out[3 i..3 i+2] = x'(pc) + J'(pc) q_k with x' the cell map of plan
 * entry i at its parametric coordinates, J' = dx'/dpc and q_k = offsets[3 k..3 k+2], i.e.
 * p' + F (v - p), F = J' J^-1 the deformation gradient at p.
 */
HOEMBEDFILTERSTRANSFER_EXPORT void EvaluateFallbackTransfer(const TransferEntry* plan,
  int nodesPerCell, const double* cellCoeffs, const std::int64_t* vertices, const double* offsets,
  std::int64_t begin, std::int64_t end, double* out);
/// The same, writing single precision.
HOEMBEDFILTERSTRANSFER_EXPORT void EvaluateFallbackTransfer(const TransferEntry* plan,
  int nodesPerCell, const double* cellCoeffs, const std::int64_t* vertices, const double* offsets,
  std::int64_t begin, std::int64_t end, float* out);

/**
 * Nodal normals rotated to the deformed configuration (paper §5.1): for nodes [begin, end),
 * out_I = normalise(R_I restNormals_I), R_I 9 doubles row-major per node. Nodes with a zero
 * rest normal (interior nodes) get (0, 0, 0).
 */
HOEMBEDFILTERSTRANSFER_EXPORT void RotateNodalNormals(const double* restNormals,
  const double* rotations, std::int64_t begin, std::int64_t end, double* out);

/**
 * Nodal normals pushed forward by the deformation, as material lines: for nodes
 * [begin, end), out_I = normalise(F_I restNormals_I), F_I = dx/dX at node I averaged over
 * the cells of the boundary faces around I (each cell once; tet10: the isoparametric
 * Jacobians of the deformed and the rest cell at the node's parametric point, F =
 * J J_rest^-1; tet4: the constant F of the cell). A rigid motion F = R gives
 * R restNormals_I exactly; a shear tilts the normal with the material, as the deformation
 * itself tilts the lines normal to the rest surface. Interior nodes, nodes with a zero
 * rest normal and nodes whose cells are all degenerate at rest get (0, 0, 0).
 * `connectivity` holds nodesPerCell ids per cell, the points 3 doubles per node.
 */
HOEMBEDFILTERSTRANSFER_EXPORT void DeformNodalNormals(const TetMeshTopology& topology,
  const std::int64_t* connectivity, int nodesPerCell, const double* restPoints,
  const double* points, const double* restNormals, std::int64_t begin, std::int64_t end,
  double* out);

/**
 * Number of cells in [begin, end) that are inverted or degenerate: det J <= 0 at one of the
 * corners or at the centroid (tet10), or the constant det J <= 0 (tet4).
 */
HOEMBEDFILTERSTRANSFER_EXPORT std::int64_t CountInvertedCells(const std::int64_t* conn,
  int nodesPerCell, const double* points, std::int64_t begin, std::int64_t end);
/// The same, also setting flags[c] to 1 for those cells and 0 for the others (flags may be
/// null).
HOEMBEDFILTERSTRANSFER_EXPORT std::int64_t MarkInvertedCells(const std::int64_t* conn,
  int nodesPerCell, const double* points, std::int64_t begin, std::int64_t end,
  unsigned char* flags);
} // namespace hoembed

#endif
