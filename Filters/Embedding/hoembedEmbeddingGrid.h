/**
 * @file hoembedEmbeddingGrid.h
 * @brief A uniform grid over item boxes (the control-point boxes of the cells), for the
 * point query "which boxes hold this point": one bin lookup instead of a tree descent
 * through many overlapping boxes.
 *
 * Each item is listed in every bin its box meets (in increasing item order). Plain C++
 * kernel, read-only after Build (thread safe).
 */
#ifndef hoembedEmbeddingGrid_h
#define hoembedEmbeddingGrid_h

#include "hoembedFiltersEmbeddingModule.h"

#include <cstdint>
#include <vector>

namespace hoembed
{
class HOEMBEDFILTERSEMBEDDING_EXPORT BoxGrid
{
public:
  using Id = std::int64_t;

  /**
   * `boxes`: 6 doubles per item (xmin, ymin, zmin, xmax, ymax, zmax). The bins are cubes
   * sized for about eight bins per item over the boxes' bounding box (1 to 1024 per
   * axis).
   */
  void Build(const std::vector<double>& boxes);

  /// Items whose box contains v (grown by tol), appended to `out` (each once).
  void Containing(const double v[3], double tol, std::vector<Id>& out) const;

  Id GetNumberOfItems() const { return static_cast<Id>(this->ItemBoxes.size() / 6); }

private:
  // bin range of [lo, hi] along axis d, clamped to the grid
  void BinRange(const double lo[3], const double hi[3], int first[3], int last[3]) const;

  double Origin[3] = { 0, 0, 0 };
  double InvSize = 0.0;
  int Dims[3] = { 0, 0, 0 };
  std::vector<Id> Offsets; ///< per bin, into Items (CSR)
  std::vector<Id> Items;
  std::vector<double> ItemBoxes;
};
} // namespace hoembed

#endif
