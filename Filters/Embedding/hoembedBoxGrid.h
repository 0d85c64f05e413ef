/**
 * @file hoembedBoxGrid.h
 * @brief A uniform grid over item boxes (the control-point boxes of the cells or of the
 * boundary faces), for the point query "which boxes hold this point" and the short-range
 * query "which boxes are nearer than r": a few bin lookups instead of a tree descent
 * through many overlapping boxes.
 *
 * Each item is listed in every bin its box meets (in increasing item order). Plain C++
 * kernel, read-only after Build (thread safe).
 */
#ifndef hoembedBoxGrid_h
#define hoembedBoxGrid_h

#include "hoembedAabbTree.h"
#include "hoembedFiltersEmbeddingModule.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace hoembed
{
class HOEMBEDFILTERSEMBEDDING_EXPORT BoxGrid
{
public:
  using Id = std::int64_t;

  /**
   * `boxes`: 6 doubles per item (xmin, ymin, zmin, xmax, ymax, zmax). The bins are cubes
   * sized for about `binsPerItem` bins per item over the boxes' bounding box (1 to 1024
   * per axis). Fewer, larger bins hold more boxes to test per query; more bins list each
   * box more often (the cells: 8; the boundary faces, which fill a surface rather than
   * the volume: 32, the best on the real meshes, Benchmarks/RESULTS.md). Fewer than 2^31
   * items (the bins list them as 32-bit ids).
   */
  void Build(const std::vector<double>& boxes, double binsPerItem = 8.0);

  /// Items whose box contains v (grown by tol), appended to `out` (each once).
  void Containing(const double v[3], double tol, std::vector<Id>& out) const;

  /**
   * An item near v, for a search that has no start: the one whose box is nearest to v
   * among the items of the first non-empty shell of bins around v's bin (v clamped into
   * the grid), -1 for an empty grid. Not necessarily the nearest item of all (a search
   * started from it still has to certify its result).
   */
  Id NearItem(const double v[3]) const;

  /**
   * Call `visit(item)` for every item whose box is closer to v than sqrt(best2) (each
   * once, in bin order), scanning the bins met by the cube of half-width sqrt(best2)
   * around v; `visit` may lower best2 (later items are tested against the lowered
   * value). Returns false, visiting nothing, when best2 is not finite or the cube meets
   * more than `maxBins` bins: a nearest-first tree search serves those better.
   */
  template <typename Visit>
  bool VisitNearer(const double v[3], const double& best2, int maxBins, Visit&& visit) const
  {
    if (this->Offsets.empty())
      return true;
    const double r = std::sqrt(best2);
    if (!(r < std::numeric_limits<double>::infinity()))
      return false;
    const double qlo[3] = { v[0] - r, v[1] - r, v[2] - r };
    const double qhi[3] = { v[0] + r, v[1] + r, v[2] + r };
    int first[3], last[3];
    this->BinRange(qlo, qhi, first, last);
    if (static_cast<double>(last[0] - first[0] + 1) * (last[1] - first[1] + 1) *
        (last[2] - first[2] + 1) >
      maxBins)
      return false;
    const bool single = first[0] == last[0] && first[1] == last[1] && first[2] == last[2];
    const std::int32_t* items = this->Items.data(); // (read once: `visit` writes memory)
    const double* boxes = this->ItemBoxes.data();
    for (int z = first[2]; z <= last[2]; ++z)
      for (int y = first[1]; y <= last[1]; ++y)
        for (int x = first[0]; x <= last[0]; ++x)
        {
          const int bin3[3] = { x, y, z };
          const Id bin = (static_cast<Id>(z) * this->Dims[1] + y) * this->Dims[0] + x;
          const Id end = this->Offsets[bin + 1];
          for (Id k = this->Offsets[bin]; k < end; ++k)
          {
            const Id item = items[k];
            const double* b = boxes + 6 * item;
            // the distance first (it rejects most boxes); a box met in several bins of the
            // query is visited in the first of them only
            if (AabbTree::BoxDistance2(b, v) < best2 && (single || this->FirstBin(b, first, bin3)))
              visit(item);
          }
        }
    return true;
  }

private:
  // bin range of the box [lo, hi], clamped to the grid
  void BinRange(const double lo[3], const double hi[3], int first[3], int last[3]) const
  {
    for (int d = 0; d < 3; ++d)
    {
      // truncation is the floor for the positive values kept (NaN compares false: bin 0)
      const double a = (lo[d] - this->Origin[d]) * this->InvSize;
      const double b = (hi[d] - this->Origin[d]) * this->InvSize;
      const double top = this->Dims[d] - 1;
      first[d] = static_cast<int>(a > 0.0 ? std::min(a, top) : 0.0);
      last[d] = static_cast<int>(b > 0.0 ? std::min(b, top) : 0.0);
    }
  }

  // Whether `bin` is the first bin of a query starting at `first` that the item box `box`
  // meets (an item met in several bins of a query is reported in that one only).
  bool FirstBin(const double* box, const int first[3], const int bin[3]) const
  {
    int ilo[3], ihi[3];
    this->BinRange(box, box + 3, ilo, ihi);
    for (int d = 0; d < 3; ++d)
      if (bin[d] != std::max(ilo[d], first[d]))
        return false;
    return true;
  }

  double Origin[3] = { 0, 0, 0 };
  double InvSize = 0.0;
  int Dims[3] = { 0, 0, 0 };
  std::vector<Id> Offsets;         ///< per bin, into Items (CSR)
  std::vector<std::int32_t> Items; ///< item ids (fewer than 2^31 items: half the memory)
  std::vector<double> ItemBoxes;
};
} // namespace hoembed

#endif
