#include "hoembedSpatialOrder.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace hoembed
{
namespace
{
// The 21 low bits of v spread to every third bit.
std::uint64_t Spread3(std::uint64_t v)
{
  v &= 0x1fffff;
  v = (v | (v << 32)) & 0x1f00000000ffffull;
  v = (v | (v << 16)) & 0x1f0000ff0000ffull;
  v = (v | (v << 8)) & 0x100f00f00f00f00full;
  v = (v | (v << 4)) & 0x10c30c30c30c30c3ull;
  v = (v | (v << 2)) & 0x1249249249249249ull;
  return v;
}
} // namespace

void SpatialOrder(const std::vector<double>& points, const std::vector<std::int64_t>& conn,
  int nodesPerCell, std::vector<std::int64_t>& cellOrder, std::vector<std::int64_t>& pointOrder)
{
  using Id = std::int64_t;
  const Id np = static_cast<Id>(points.size() / 3);
  const Id nc = nodesPerCell > 0 ? static_cast<Id>(conn.size() / nodesPerCell) : 0;
  const int corners = std::min(nodesPerCell, 4);
  // centroids of the corners and their bounding box
  std::vector<double> centre(3 * nc);
  double lo[3], hi[3];
  for (int d = 0; d < 3; ++d)
  {
    lo[d] = std::numeric_limits<double>::max();
    hi[d] = -std::numeric_limits<double>::max();
  }
  for (Id c = 0; c < nc; ++c)
    for (int d = 0; d < 3; ++d)
    {
      double s = 0.0;
      for (int a = 0; a < corners; ++a)
        s += points[3 * conn[nodesPerCell * c + a] + d];
      centre[3 * c + d] = s / corners;
      lo[d] = std::min(lo[d], centre[3 * c + d]);
      hi[d] = std::max(hi[d], centre[3 * c + d]);
    }
  // one scale for all axes (cubic cells of the curve), 2^21 steps over the largest extent
  double ext = 0.0;
  for (int d = 0; d < 3; ++d)
    ext = std::max(ext, hi[d] - lo[d]);
  const double scale = ext > 0.0 && std::isfinite(ext) ? 2097151.0 / ext : 0.0;
  std::vector<std::pair<std::uint64_t, Id>> keyed(nc);
  for (Id c = 0; c < nc; ++c)
  {
    std::uint64_t key = 0;
    for (int d = 0; d < 3; ++d)
    {
      const double q = (centre[3 * c + d] - lo[d]) * scale;
      const auto v = static_cast<std::uint64_t>(q > 0.0 ? std::min(q, 2097151.0) : 0.0);
      key |= Spread3(v) << d;
    }
    keyed[c] = { key, c };
  }
  std::sort(keyed.begin(), keyed.end());
  cellOrder.resize(nc);
  for (Id k = 0; k < nc; ++k)
    cellOrder[k] = keyed[k].second;
  // corner nodes by first use in the new cell order, then the other (mid-edge) nodes the
  // same way, then the unused ones
  std::vector<char> seen(np, 0);
  pointOrder.clear();
  pointOrder.reserve(np);
  for (int pass = 0; pass < 2; ++pass)
    for (Id k = 0; k < nc; ++k)
      for (int a = pass == 0 ? 0 : corners; a < (pass == 0 ? corners : nodesPerCell); ++a)
      {
        const Id i = conn[nodesPerCell * cellOrder[k] + a];
        if (i >= 0 && i < np && !seen[i])
        {
          seen[i] = 1;
          pointOrder.push_back(i);
        }
      }
  for (Id i = 0; i < np; ++i)
    if (!seen[i])
      pointOrder.push_back(i);
}
} // namespace hoembed
