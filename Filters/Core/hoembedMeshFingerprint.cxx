#include "hoembedMeshFingerprint.h"

#include <cstdio>

namespace hoembed
{
MeshFingerprint::MeshFingerprint(std::int64_t numberOfPoints, std::int64_t numberOfCells)
  : Hash(14695981039346656037ull)
{
  this->Add(numberOfPoints);
  this->Add(numberOfCells);
}

void MeshFingerprint::Add(std::int64_t v)
{
  std::uint64_t u = static_cast<std::uint64_t>(v);
  for (int b = 0; b < 8; ++b)
  {
    this->Hash ^= (u >> (8 * b)) & 0xffu;
    this->Hash *= 1099511628211ull;
  }
}

void MeshFingerprint::AddCell(std::int64_t cellType, const std::int64_t* ids, int numberOfIds)
{
  this->Add(cellType);
  for (int i = 0; i < numberOfIds; ++i)
  {
    this->Add(ids[i]);
  }
}

std::string MeshFingerprint::Hex() const
{
  char buf[17];
  std::snprintf(buf, sizeof(buf), "%016llx", static_cast<unsigned long long>(this->Hash));
  return std::string(buf);
}
} // namespace hoembed
