/**
 * @file hoembedCsr.h
 * @brief Compressed rows by key (a counting sort): the one way the kernels build their
 * adjacency lists (vertex -> triangles, node -> boundary faces, grid bin -> boxes, ...).
 */
#ifndef hoembedCsr_h
#define hoembedCsr_h

#include <cstdint>
#include <vector>

namespace hoembed
{
/**
 * `forEach(emit)` calls emit(key, value) for every (key, value) pair, keys in
 * [0, numberOfKeys); it is called twice and must emit the same pairs in the same order.
 * Afterwards the values of key k are values[offsets[k] .. offsets[k + 1]), in emission
 * order. Both vectors keep their capacity (no temporary array either): rebuilding touches
 * no fresh memory.
 */
template <typename T, typename ForEach>
void BuildCsr(std::int64_t numberOfKeys, ForEach&& forEach, std::vector<std::int64_t>& offsets,
  std::vector<T>& values)
{
  offsets.assign(numberOfKeys + 1, 0);
  forEach([&](std::int64_t key, const T&) { ++offsets[key + 1]; });
  for (std::int64_t k = 0; k < numberOfKeys; ++k)
    offsets[k + 1] += offsets[k];
  values.resize(offsets[numberOfKeys]);
  // key k is filled at offsets[k]++, which leaves it at the start of key k + 1: shift back
  forEach([&](std::int64_t key, const T& value) { values[offsets[key]++] = value; });
  for (std::int64_t k = numberOfKeys; k > 0; --k)
    offsets[k] = offsets[k - 1];
  offsets[0] = 0;
}
} // namespace hoembed

#endif
