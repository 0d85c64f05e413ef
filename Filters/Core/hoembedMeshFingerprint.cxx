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

namespace
{
constexpr std::uint64_t Prime = 1099511628211ull;
constexpr std::uint64_t Prime6 = Prime * Prime * Prime * Prime * Prime * Prime; // mod 2^64

inline std::uint64_t Mix(std::uint64_t h, std::int64_t v)
{
  const std::uint64_t u = static_cast<std::uint64_t>(v);
  if (u < 0x10000u)
  {
    // the six high bytes are 0: h ^= 0 changes nothing, so they only multiply by the
    // prime six times (the same product mod 2^64, a third of the instructions)
    h = (h ^ (u & 0xffu)) * Prime;
    h = (h ^ (u >> 8)) * Prime;
    return h * Prime6;
  }
  for (int b = 0; b < 8; ++b)
  {
    h ^= (u >> (8 * b)) & 0xffu;
    h *= Prime;
  }
  return h;
}
} // namespace

void MeshFingerprint::Add(std::int64_t v)
{
  this->Hash = Mix(this->Hash, v);
}

void MeshFingerprint::AddCell(std::int64_t cellType, const std::int64_t* ids, int numberOfIds)
{
  std::uint64_t h = Mix(this->Hash, cellType);
  for (int i = 0; i < numberOfIds; ++i)
  {
    h = Mix(h, ids[i]);
  }
  this->Hash = h;
}

std::string MeshFingerprint::Hex() const
{
  char buf[17];
  std::snprintf(buf, sizeof(buf), "%016llx", static_cast<unsigned long long>(this->Hash));
  return std::string(buf);
}
} // namespace hoembed
