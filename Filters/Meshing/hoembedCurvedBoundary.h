/**
 * @file hoembedCurvedBoundary.h
 * @brief Move boundary mid-edge nodes of a tet10 mesh onto a target surface while
 *        keeping every element valid (plain C++).
 *
 * Each listed mid-edge node k moves from its straight position S_k to
 * S_k + alpha_k (T_k - S_k). All alpha_k start at 1. An element is acceptable when its
 * Jacobian determinant is provably positive everywhere (hoembed::Tet10JacobianBounds) and
 * its minimum scaled Jacobian is at least hoembed::Tet10RequiredQuality of its straight
 * (tet4) shape: `qualityRatio` times the straight quality, and `minQuality` (a floor a
 * solver can use) unless the straight shape itself is worse. For each unacceptable element the
 * largest common factor beta in [0, 1] (bisection) of its curved nodes' alphas that makes it
 * acceptable is applied; the elements around the nodes that moved are checked again, until all are
 * acceptable (alpha = 0, the straight element, always is when the corners form a valid tet).
 */
#ifndef hoembedCurvedBoundary_h
#define hoembedCurvedBoundary_h

#include "hoembedFiltersMeshingModule.h"

#include <cstdint>
#include <functional>
#include <vector>

namespace hoembed
{
struct HOEMBEDFILTERSMESHING_EXPORT CurvingResult
{
  std::int64_t Curved = 0;   ///< nodes moved all the way to their target
  std::int64_t Relaxed = 0;  ///< nodes pulled back (alpha < 1)
  std::vector<double> Alpha; ///< per listed node
};

/**
 * @param points      tet10 node coordinates (3 per node), updated in place
 * @param conn        tet10 connectivity (10 per cell, VTK order)
 * @param nodes       the mid-edge nodes to move
 * @param targets     their targets (3 per node)
 * @param qualityRatio see above (e.g. 0.2)
 * @param minQuality  see above (e.g. 0.05; 0: no floor)
 */
/// An extra acceptance test of a tet10 (10 nodes, 3 doubles each), e.g. VTK's validator.
using Tet10Check = std::function<bool(const double* x)>;

HOEMBEDFILTERSMESHING_EXPORT CurvingResult CurveMidEdgeNodes(std::vector<double>& points,
  const std::vector<std::int64_t>& conn, const std::vector<std::int64_t>& nodes,
  const std::vector<double>& targets, double qualityRatio, double minQuality,
  const Tet10Check& extra = Tet10Check());

/**
 * Harmonic extension of boundary mid-edge-node displacements into the interior: each
 * interior mid-edge node gets the average displacement of the mid-edge nodes of the
 * elements around it (Jacobi iterations), with the boundary ones held fixed. Spreading
 * the curvature of the boundary over the interior keeps thin boundary elements valid.
 * @param points     tet10 node coordinates (3 per node), straight
 * @param conn       tet10 connectivity
 * @param fixedDisp  3 per node: displacement of the fixed mid-edge nodes
 * @param isFixed    per node: 1 for the boundary mid-edge nodes
 * @param iterations Jacobi sweeps
 * @return the displacement of every mid-edge node (3 per node; zero for corners)
 */
HOEMBEDFILTERSMESHING_EXPORT std::vector<double> ExtendMidNodeDisplacement(
  const std::vector<double>& points, const std::vector<std::int64_t>& conn,
  const std::vector<double>& fixedDisp, const std::vector<char>& isFixed, int iterations);

/**
 * The smallest minimum scaled Jacobian accepted for a curved element whose straight shape
 * scores `straight`: max(qualityRatio * straight, min(minQuality, 0.999 * straight)), with
 * (1 - 1e-12) for 0.999 when the straight shape is at the floor or above.
 * Curving may cost a share of the straight quality (`qualityRatio`) but never go below
 * the floor `minQuality`; a straight shape already below the floor is accepted as it is
 * (0.999, 1 - 1e-12: the straight tet10's sampled value equals the tet4's only up to
 * round-off), so pulling every node back is always acceptable.
 */
HOEMBEDFILTERSMESHING_EXPORT double Tet10RequiredQuality(
  double straight, double qualityRatio, double minQuality);

/// True when the tet10 (10 nodes, 3 doubles each) passes the acceptance test above (and
/// `extra`, when given).
HOEMBEDFILTERSMESHING_EXPORT bool Tet10Acceptable(
  const double* x, double qualityRatio, double minQuality, const Tet10Check& extra = Tet10Check());
} // namespace hoembed

#endif
