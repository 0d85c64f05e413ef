/**
 * @file hoembedSpatialOrder.h
 * @brief A memory order for a mesh in which elements near each other in space are near
 * each other in the arrays: cells sorted along a Morton (Z-order) curve through their
 * corner centroids, nodes numbered in the order the sorted cells first use them (corner
 * nodes first, then mid-edge nodes: a tet4 mesh on the same corners gets the same corner
 * numbering).
 *
 * Searches that move through space (the embedding's walks, box grids and flood) then
 * touch a few cache lines and pages instead of scattered ones. Plain C++ kernel.
 */
#ifndef hoembedSpatialOrder_h
#define hoembedSpatialOrder_h

#include "hoembedCoreModule.h"

#include <cstdint>
#include <vector>

namespace hoembed
{
/**
 * `points` 3 doubles per node, `conn` nodesPerCell ids per cell (the first 4 are the
 * corners), node ids in [0, numberOfPoints). On return, `cellOrder[k]` is the old id of
 * the k-th cell in the new order and `pointOrder[k]` the old id of the k-th node: the
 * corner nodes (the first 4 of each cell) in order of first use, then the other nodes in
 * order of first use, then the nodes no cell uses in their relative order. Ties are broken by the
 * old id: the result depends on the input alone.
 */
HOEMBEDCORE_EXPORT void SpatialOrder(const std::vector<double>& points,
  const std::vector<std::int64_t>& conn, int nodesPerCell, std::vector<std::int64_t>& cellOrder,
  std::vector<std::int64_t>& pointOrder);
} // namespace hoembed

#endif
