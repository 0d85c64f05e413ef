#include "hoembedBoxGrid.h"
#include "hoembedCsr.h"
#include "hoembedLanes.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

namespace hoembed
{
void BoxGrid::Build(const std::vector<double>& boxes, double binsPerItem)
{
  const Id n = static_cast<Id>(boxes.size() / 6);
  this->ItemBoxes.assign(boxes.begin(), boxes.end());
  this->Offsets.clear();
  this->Items.clear();
  this->Dims[0] = this->Dims[1] = this->Dims[2] = 0;
  if (n == 0)
    return;
  double lo[3], hi[3];
  for (int d = 0; d < 3; ++d)
  {
    lo[d] = std::numeric_limits<double>::max();
    hi[d] = -std::numeric_limits<double>::max();
  }
  for (Id i = 0; i < n; ++i)
    for (int d = 0; d < 3; ++d)
    {
      lo[d] = std::min(lo[d], boxes[6 * i + d]);
      hi[d] = std::max(hi[d], boxes[6 * i + 3 + d]);
    }
  // cubic bins, binsPerItem per item over the bounding box (flat or thin meshes: the
  // volume of the box padded by a tenth of its largest extent)
  const double ext = std::max({ hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2] });
  double volume = 1.0;
  for (int d = 0; d < 3; ++d)
    volume *= hi[d] - lo[d] + 0.1 * ext;
  double size = std::cbrt(volume / (binsPerItem * static_cast<double>(n)));
  if (!(size > 0.0) || !std::isfinite(size))
    size = ext > 0.0 ? ext : 1.0;
  for (int d = 0; d < 3; ++d)
  {
    this->Origin[d] = lo[d];
    this->Dims[d] =
      static_cast<int>(std::min(1024.0, std::max(1.0, std::ceil((hi[d] - lo[d]) / size))));
  }
  this->InvSize = 1.0 / size;
  const Id bins = static_cast<Id>(this->Dims[0]) * this->Dims[1] * this->Dims[2];
  auto forBins = [&](Id i, auto&& f) {
    int first[3], last[3];
    this->BinRange(&boxes[6 * i], &boxes[6 * i + 3], first, last);
    for (int z = first[2]; z <= last[2]; ++z)
      for (int y = first[1]; y <= last[1]; ++y)
        for (int x = first[0]; x <= last[0]; ++x)
          f((static_cast<Id>(z) * this->Dims[1] + y) * this->Dims[0] + x);
  };
  BuildCsr(
    bins,
    [&](auto&& emit) {
      for (Id i = 0; i < n; ++i)
        forBins(i, [&](Id b) { emit(b, static_cast<std::int32_t>(i)); });
    },
    this->Offsets, this->Items);
}

void BoxGrid::Containing(const double v[3], double tol, std::vector<Id>& out) const
{
  if (this->Offsets.empty())
    return;
  const double qlo[3] = { v[0] - tol, v[1] - tol, v[2] - tol };
  const double qhi[3] = { v[0] + tol, v[1] + tol, v[2] + tol };
  int first[3], last[3];
  this->BinRange(qlo, qhi, first, last);
  const bool single = first[0] == last[0] && first[1] == last[1] && first[2] == last[2];
  // The box test without a branch per comparison (x and y in the two lanes of a vector
  // register, z apart; the same comparisons as one at a time): the outcomes follow no
  // pattern, and each branch on them was a misprediction in two of five items.
  using lanes::Mask;
  using lanes::Pair;
  const Pair vxy = { v[0], v[1] };
  const Pair txy = { tol, tol };
  const double vz = v[2];
  const std::int32_t* items = this->Items.data();
  const double* boxes = this->ItemBoxes.data();
  for (int z = first[2]; z <= last[2]; ++z)
    for (int y = first[1]; y <= last[1]; ++y)
      for (int x = first[0]; x <= last[0]; ++x)
      {
        const Id bin = (static_cast<Id>(z) * this->Dims[1] + y) * this->Dims[0] + x;
        const Id end = this->Offsets[bin + 1];
        for (Id k = this->Offsets[bin]; k < end; ++k)
        {
          const Id item = items[k];
          const double* b = boxes + 6 * item;
          const Mask away = (vxy < lanes::Load(b) - txy) | (vxy > lanes::Load(b + 3) + txy);
          if ((away[0] | away[1]) | (vz < b[2] - tol) | (vz > b[5] + tol))
            continue;
          const int bin3[3] = { x, y, z };
          if (!single && !this->FirstBin(b, first, bin3))
            continue; // met again in a later bin of the query
          out.push_back(item);
        }
      }
}
BoxGrid::Id BoxGrid::NearItem(const double v[3]) const
{
  if (this->Items.empty())
    return -1;
  int c[3];
  this->BinRange(v, v, c, c);
  const int reach = std::max({ this->Dims[0], this->Dims[1], this->Dims[2] });
  for (int s = 0; s <= reach; ++s)
  {
    // the bins at Chebyshev distance s from c (clamped to the grid)
    int lo[3], hi[3];
    for (int d = 0; d < 3; ++d)
    {
      lo[d] = std::max(0, c[d] - s);
      hi[d] = std::min(this->Dims[d] - 1, c[d] + s);
    }
    Id best = -1;
    double best2 = std::numeric_limits<double>::infinity();
    for (int z = lo[2]; z <= hi[2]; ++z)
      for (int y = lo[1]; y <= hi[1]; ++y)
        for (int x = lo[0]; x <= hi[0]; ++x)
        {
          if (std::max({ std::abs(x - c[0]), std::abs(y - c[1]), std::abs(z - c[2]) }) != s)
            continue; // an inner shell, already scanned
          const Id bin = (static_cast<Id>(z) * this->Dims[1] + y) * this->Dims[0] + x;
          for (Id k = this->Offsets[bin]; k < this->Offsets[bin + 1]; ++k)
          {
            const Id item = this->Items[k];
            const double d2 = AabbTree::BoxDistance2(&this->ItemBoxes[6 * item], v);
            if (d2 < best2)
            {
              best2 = d2;
              best = item;
            }
          }
        }
    if (best >= 0)
      return best;
  }
  return -1;
}
} // namespace hoembed
