/**
 * @file hoembedFreeNodeFit.h
 * @brief Second chance for pulled-back boundary mid-edge nodes: put the node on its
 *        surface target and move the free (interior) mid-edge nodes of the elements
 *        around it until they are all acceptable again (plain C++).
 *
 * Interior mid-edge nodes are not measured against the surface: they can go anywhere that
 * keeps their elements valid. For each boundary mid-edge node k with alpha_k < 1, the node
 * goes to its target; if an element around it is then not acceptable
 * (hoembed::Tet10Acceptable), each free mid-edge node of those elements is moved by a
 * pattern search (axis steps from a fifth of its edge length, halved on failure) that
 * maximises the worst acceptability margin of the elements around that free node. When
 * every element touched is acceptable the node keeps its target (alpha_k = 1); otherwise
 * all positions are restored. Elements acceptable before stay acceptable, and no moved
 * corner takes an element's straight (tet4) shape below min(minQuality, what it was):
 * later steps measure elements against their straight shape and may straighten them.
 */
#ifndef hoembedFreeNodeFit_h
#define hoembedFreeNodeFit_h

#include "hoembedFiltersMeshingModule.h"

#include <cstdint>
#include <vector>

namespace hoembed
{
/**
 * @param points       tet10 node coordinates, updated in place
 * @param conn         tet10 connectivity (10 per cell)
 * @param nodes        the boundary mid-edge nodes
 * @param targets      their surface targets (3 per node)
 * @param alpha        per node, 1 when on the target; updated
 * @param isFree       per point: 1 for mid-edge nodes that may move anywhere
 * @param qualityRatio see hoembed::Tet10Acceptable
 * @param minQuality   see hoembed::Tet10Acceptable; an element's straight shape before
 *                     the fit sets its bar: moved corners do not lower it, nor take the
 *                     straight shape itself below min(minQuality, what it was)
 * @param evaluationsPerCell work limit: element evaluations per cell of the mesh
 * @return how many nodes reached their target
 */
HOEMBEDFILTERSMESHING_EXPORT std::int64_t FitWithFreeNodes(std::vector<double>& points,
  const std::vector<std::int64_t>& conn, const std::vector<std::int64_t>& nodes,
  const std::vector<double>& targets, std::vector<double>& alpha, const std::vector<char>& isFree,
  double qualityRatio, double minQuality, std::int64_t evaluationsPerCell = 300);
} // namespace hoembed

#endif
