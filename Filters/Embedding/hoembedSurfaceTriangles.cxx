#include "hoembedSurfaceTriangles.h"

#include <algorithm>
#include <limits>
#include <sstream>

namespace hoembed
{
namespace
{
template <typename T>
void Fans(const T* offsets, const T* ids, std::int64_t n, std::vector<std::int64_t>& tris)
{
  for (std::int64_t c = 0; c < n; ++c)
  {
    const T* p = ids + offsets[c];
    const std::int64_t k = static_cast<std::int64_t>(offsets[c + 1] - offsets[c]);
    for (std::int64_t j = 1; j + 1 < k; ++j)
    {
      tris.push_back(p[0]);
      tris.push_back(p[j]);
      tris.push_back(p[j + 1]);
    }
  }
}

template <typename T>
void Strips(const T* offsets, const T* ids, std::int64_t n, std::vector<std::int64_t>& tris)
{
  for (std::int64_t c = 0; c < n; ++c)
  {
    const T* p = ids + offsets[c];
    const std::int64_t k = static_cast<std::int64_t>(offsets[c + 1] - offsets[c]);
    for (std::int64_t j = 0; j + 2 < k; ++j)
    {
      tris.push_back(p[j]);
      tris.push_back(p[j + 1]);
      tris.push_back(p[j + 2]);
    }
  }
}
} // namespace

std::int64_t CellArrayView::NumberOfIds() const
{
  if (this->NumberOfCells <= 0)
  {
    return 0;
  }
  return this->Offsets64 ? this->Offsets64[this->NumberOfCells]
                         : static_cast<std::int64_t>(this->Offsets32[this->NumberOfCells]);
}

void AppendSurfaceTriangles(
  const CellArrayView& polys, const CellArrayView& strips, std::vector<std::int64_t>& tris)
{
  // a polygon or strip of k points gives k - 2 triangles
  std::int64_t ntri = 0;
  for (const CellArrayView* ca : { &polys, &strips })
  {
    ntri += std::max<std::int64_t>(0, ca->NumberOfIds() - 2 * ca->NumberOfCells);
  }
  tris.reserve(tris.size() + 3 * static_cast<size_t>(ntri));
  if (polys.NumberOfCells > 0)
  {
    if (polys.Offsets64)
      Fans(polys.Offsets64, polys.Connectivity64, polys.NumberOfCells, tris);
    else
      Fans(polys.Offsets32, polys.Connectivity32, polys.NumberOfCells, tris);
  }
  if (strips.NumberOfCells > 0)
  {
    if (strips.Offsets64)
      Strips(strips.Offsets64, strips.Connectivity64, strips.NumberOfCells, tris);
    else
      Strips(strips.Offsets32, strips.Connectivity32, strips.NumberOfCells, tris);
  }
}

std::string CheckSurfaceTriangles(const std::vector<std::int64_t>& tris, std::int64_t ns)
{
  if (tris.size() / 3 > static_cast<size_t>(std::numeric_limits<int>::max()))
  {
    return "The surface has more than 2^31 triangles, which is not supported.";
  }
  for (std::int64_t id : tris)
  {
    if (id < 0 || id >= ns)
    {
      std::ostringstream os;
      os << "A surface polygon refers to point " << id << ", out of range [0, " << ns << ").";
      return os.str();
    }
  }
  return std::string();
}
} // namespace hoembed
