/**
 * @file hoembedAabbTree.h
 * @brief A static axis-aligned bounding-box tree over items (the boundary faces), used
 * to certify that a closest point is the global one when the search radius is too large
 * for the face grid (hoembedBoxGrid.h), nearest boxes first.
 *
 * The boxes of curved items are the boxes of their Bezier control points (the convex
 * hull property of the Bernstein form), so an item can never reach outside its box.
 * Traversals use an explicit stack (no recursion). Plain C++ kernel, read-only after
 * Build (thread safe).
 */
#ifndef hoembedAabbTree_h
#define hoembedAabbTree_h

#include "hoembedFiltersEmbeddingModule.h"
#include "hoembedLanes.h"

#include <cstdint>
#include <vector>

namespace hoembed
{
class HOEMBEDFILTERSEMBEDDING_EXPORT AabbTree
{
public:
  using Id = std::int64_t;

  /// `boxes`: 6 doubles per item (xmin, ymin, zmin, xmax, ymax, zmax); copied (a tree
  /// built again reuses its memory).
  void Build(const std::vector<double>& boxes);

  /// Squared distance from v to box b (0 inside). Without a branch per axis (x and y in
  /// the two lanes of a vector register): the gap below the box plus the gap above it,
  /// each clamped at 0 (one of them is 0), the same values as the comparisons one at a
  /// time (a NaN coordinate gives a gap of 0 as before).
  static double BoxDistance2(const double* b, const double v[3])
  {
    using lanes::Pair;
    const Pair zero = { 0.0, 0.0 };
    const Pair vxy = { v[0], v[1] };
    const Pair below = lanes::Load(b) - vxy, above = vxy - lanes::Load(b + 3);
    const Pair e = (below > zero ? below : zero) + (above > zero ? above : zero);
    const double ez =
      (b[2] - v[2] > 0.0 ? b[2] - v[2] : 0.0) + (v[2] - b[5] > 0.0 ? v[2] - b[5] : 0.0);
    return e[0] * e[0] + e[1] * e[1] + ez * ez;
  }

  /**
   * Call `visit(item)` for every item whose box is closer to v than sqrt(best2), nearest
   * boxes first; `visit` may lower best2 (the current best squared distance).
   */
  template <typename Visit>
  void VisitNearer(const double v[3], const double& best2, Visit&& visit) const
  {
    if (this->Nodes.empty())
      return;
    Id stack[128];
    double lb[128];
    int top = 0;
    stack[top] = 0;
    lb[top++] = BoxDistance2(this->Nodes[0].Box, v);
    while (top > 0)
    {
      --top;
      const Id n = stack[top];
      if (lb[top] >= best2)
        continue;
      const Node& node = this->Nodes[n];
      if (node.Count > 0)
      {
        for (Id k = node.First; k < node.First + node.Count; ++k)
        {
          const Id item = this->Items[k];
          if (BoxDistance2(&this->ItemBoxes[6 * item], v) < best2)
            visit(item);
        }
        continue;
      }
      const Id a = node.First, b = node.First + 1;
      const double da = BoxDistance2(this->Nodes[a].Box, v);
      const double db = BoxDistance2(this->Nodes[b].Box, v);
      if (top + 2 > 128)
        continue; // cannot happen for trees of < 2^60 items
      // push the farther first so that the nearer is visited first
      if (da <= db)
      {
        stack[top] = b;
        lb[top++] = db;
        stack[top] = a;
        lb[top++] = da;
      }
      else
      {
        stack[top] = a;
        lb[top++] = da;
        stack[top] = b;
        lb[top++] = db;
      }
    }
  }

  /// Items whose box contains v (grown by tol), appended to `out`.
  void Containing(const double v[3], double tol, std::vector<Id>& out) const;

  Id GetNumberOfItems() const
  {
    return static_cast<Id>(this->Items.size());
  }

private:
  struct Node
  {
    double Box[6];
    Id First = 0; ///< first item (leaf) or first child (inner node; children First, First+1)
    Id Count = 0; ///< number of items (leaf), 0 for inner nodes
  };
  std::vector<Node> Nodes;
  std::vector<Id> Items;
  std::vector<double> ItemBoxes;
};
} // namespace hoembed

#endif
