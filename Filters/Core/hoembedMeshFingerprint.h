/**
 * @file hoembedMeshFingerprint.h
 * @brief A fingerprint of a mesh's topology, to refuse transfers onto a different mesh.
 *
 * FNV-1a (64 bit) over: the number of points, the number of cells, then for each cell its
 * VTK cell type followed by its point ids, every value as a little-endian 64-bit integer.
 * Coordinates are not included: a deformed mesh has the fingerprint of its rest mesh.
 * Written as 16 lowercase hex digits.
 */
#ifndef hoembedMeshFingerprint_h
#define hoembedMeshFingerprint_h

#include "hoembedCoreModule.h"

#include <cstdint>
#include <string>

namespace hoembed
{
class HOEMBEDCORE_EXPORT MeshFingerprint
{
public:
  MeshFingerprint(std::int64_t numberOfPoints, std::int64_t numberOfCells);
  /// Add one cell (in order).
  void AddCell(std::int64_t cellType, const std::int64_t* ids, int numberOfIds);
  /// 16 lowercase hex digits.
  std::string Hex() const;
  std::uint64_t Value() const
  {
    return this->Hash;
  }

private:
  void Add(std::int64_t v);
  std::uint64_t Hash;
};
} // namespace hoembed

#endif
