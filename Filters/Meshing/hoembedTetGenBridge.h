/**
 * @file hoembedTetGenBridge.h
 * @brief Quality tetrahedral meshing of a closed triangle surface with TetGen (plain C++).
 *
 * TetGen (AGPL-3.0, or a commercial licence from WIAS) is compiled into this module.
 */
#ifndef hoembedTetGenBridge_h
#define hoembedTetGenBridge_h

#include "hoembedFiltersMeshingModule.h"

#include <cstdint>
#include <string>
#include <vector>

namespace hoembed
{
struct HOEMBEDFILTERSMESHING_EXPORT TetGenParameters
{
  double RadiusEdgeRatio = 1.5;  ///< -q first value
  double MinDihedralAngle = 10.0; ///< -q second value (degrees)
  double MaxVolume = 0.0;         ///< -a value; 0 = no volume bound
  bool PreserveBoundary = false;  ///< -Y: no Steiner points on the boundary
};

struct HOEMBEDFILTERSMESHING_EXPORT TetGenResult
{
  std::vector<double> Points;      ///< 3 per point
  std::vector<std::int64_t> Tets;  ///< 4 per tet, positively oriented (VTK order)
  std::string Error;               ///< empty on success
  std::string Switches;            ///< the TetGen command-line switches used
};

/**
 * Mesh the inside of the closed surface (`pts`: 3 doubles per point; `tris`: 3 ids per
 * triangle). Never throws: TetGen's failures (self-intersecting input, tiny features,
 * internal errors) come back in TetGenResult::Error.
 */
HOEMBEDFILTERSMESHING_EXPORT TetGenResult RunTetGen(const std::vector<double>& pts,
  const std::vector<std::int64_t>& tris, const TetGenParameters& params);
} // namespace hoembed

#endif
