/**
 * @file hoembedLagrangeTransfer.h
 * @brief The transfer's per-vertex evaluation on VTK's Lagrange tetrahedra of order 3-4
 * (orders 1 and 2 are tet4 / tet10 node for node and take the tet kernels): v' = x'(pc)
 * + d n'(pc) / |n'(pc)| with n' the deformed mesh's smooth normal field
 * (hoembed::ComputeLagrangeBoundaryNormals, interpolated over the cell's nodes: the
 * interior nodes' normals are zero and their shape functions vanish on the face), x'(pc)
 * where d = 0, and x'(pc) + J'(pc) q for the embedding's fallback vertices.
 *
 * Kept apart from hoembedTransferKernel (tet4/tet10 coefficient tables): the driver
 * dispatches on the node count. Plain C++; any range of vertices, any thread.
 */
#ifndef hoembedLagrangeTransfer_h
#define hoembedLagrangeTransfer_h

#include "hoembedFiltersTransferModule.h"
#include "hoembedLagrangeHex.h"
#include "hoembedLagrangeTet.h"
#include "hoembedTransferKernel.h" // TransferEntry

#include <cstdint>

namespace hoembed
{
/// Vertices [begin, end) of `plan` into `out` (3 per vertex) from the deformed `points`
/// and their nodal normals (both 3 per mesh node).
HOEMBEDFILTERSTRANSFER_EXPORT void EvaluateLagrangeTransfer(const LagrangeTetBasis& b,
  const std::int64_t* conn, const double* points, const double* nodalNormals,
  const TransferEntry* plan, std::int64_t begin, std::int64_t end, double* out);
HOEMBEDFILTERSTRANSFER_EXPORT void EvaluateLagrangeTransfer(const LagrangeTetBasis& b,
  const std::int64_t* conn, const double* points, const double* nodalNormals,
  const TransferEntry* plan, std::int64_t begin, std::int64_t end, float* out);

/// The fallback vertices (ids `vertices`, offsets q 3 each, [begin, end) of that list):
/// x'(pc) + J'(pc) q.
HOEMBEDFILTERSTRANSFER_EXPORT void EvaluateLagrangeFallback(const LagrangeTetBasis& b,
  const std::int64_t* conn, const double* points, const TransferEntry* plan,
  const std::int64_t* vertices, const double* q, std::int64_t begin, std::int64_t end, double* out);
HOEMBEDFILTERSTRANSFER_EXPORT void EvaluateLagrangeFallback(const LagrangeTetBasis& b,
  const std::int64_t* conn, const double* points, const TransferEntry* plan,
  const std::int64_t* vertices, const double* q, std::int64_t begin, std::int64_t end, float* out);

/// Cells [begin, end) whose det J is <= 0 at a corner or the centroid (counted as the tet
/// kernels count theirs).
HOEMBEDFILTERSTRANSFER_EXPORT std::int64_t CountInvertedLagrangeCells(const LagrangeTetBasis& b,
  const std::int64_t* conn, const double* points, std::int64_t begin, std::int64_t end);

/// The same three on hexahedra (hoembedLagrangeHex.h: every cell through its exact tensor
/// form); CountInvertedHexCells looks at the 8 corners and the centre.
HOEMBEDFILTERSTRANSFER_EXPORT void EvaluateHexTransfer(const LagrangeHexBasis& b,
  const std::int64_t* conn, const double* points, const double* nodalNormals,
  const TransferEntry* plan, std::int64_t begin, std::int64_t end, double* out);
HOEMBEDFILTERSTRANSFER_EXPORT void EvaluateHexTransfer(const LagrangeHexBasis& b,
  const std::int64_t* conn, const double* points, const double* nodalNormals,
  const TransferEntry* plan, std::int64_t begin, std::int64_t end, float* out);
HOEMBEDFILTERSTRANSFER_EXPORT void EvaluateHexFallback(const LagrangeHexBasis& b,
  const std::int64_t* conn, const double* points, const TransferEntry* plan,
  const std::int64_t* vertices, const double* q, std::int64_t begin, std::int64_t end, double* out);
HOEMBEDFILTERSTRANSFER_EXPORT void EvaluateHexFallback(const LagrangeHexBasis& b,
  const std::int64_t* conn, const double* points, const TransferEntry* plan,
  const std::int64_t* vertices, const double* q, std::int64_t begin, std::int64_t end, float* out);
HOEMBEDFILTERSTRANSFER_EXPORT std::int64_t CountInvertedHexCells(const LagrangeHexBasis& b,
  const std::int64_t* conn, const double* points, std::int64_t begin, std::int64_t end);
} // namespace hoembed

#endif
