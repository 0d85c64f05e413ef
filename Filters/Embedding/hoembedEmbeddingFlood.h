/**
 * @file hoembedEmbeddingFlood.h
 * @brief Paper Algorithm 2: map every vertex of a triangle surface by flooding over its
 * triangles, each vertex starting from the result of an already mapped neighbour.
 *
 * Unrolled into loops with explicit queues (no recursion):
 * 1. The triangles are put in breadth-first order over the surface (neighbours through
 *    shared vertices) and the vertices renumbered by first appearance, so that
 *    consecutive triangles and vertices are near each other whatever the input order;
 *    the order is cut into contiguous ranges (partitions). Each vertex belongs to the
 *    partition of its first triangle.
 * 2. Partitions run in parallel (hoembedParallel.h). In each, a seed triangle per connected
 *    piece starts a flood (crossing vertices of other partitions, which it does not
 *    embed): a triangle is mapped when all its vertices are within the
 *    distance threshold d_t; only then are its neighbours queued, with the last mapped
 *    vertex's result as their initial guess. Deferred triangles are retried after the
 *    queue empties, with d_t raised (doubled, at least to the nearest deferred distance).
 * 3. Vertices in no triangle are mapped afterwards, each from the previous one.
 * Every vertex result is exact on its own (hoembedEmbeddingSearch certifies the global
 * minimum), so the flood order only makes the search fast.
 */
#ifndef hoembedEmbeddingFlood_h
#define hoembedEmbeddingFlood_h

#include "hoembedEmbeddingSearch.h"
#include "hoembedFiltersEmbeddingModule.h"

#include <cstddef>
#include <functional>
#include <memory>
#include <vector>

namespace hoembed
{
struct FloodStatistics
{
  EmbeddingMesh::Id Partitions = 0;
  EmbeddingMesh::Id Seeds = 0;           ///< floods started (>= connected components)
  EmbeddingMesh::Id ThresholdRaises = 0; ///< times d_t was raised
  EmbeddingMesh::Id IsolatedVertices = 0;
};

/**
 * Working memory of EmbedSurface (the breadth-first order, the renumbered triangles, the
 * flood's per-vertex state, the per-thread search scratch), kept between calls so that
 * embedding again reuses it instead of touching fresh pages (each fresh page costs a
 * kernel page fault; on the small real surfaces those were a fifth to a quarter of
 * the time). One call at a
 * time per workspace.
 */
class HOEMBEDFILTERSEMBEDDING_EXPORT EmbedWorkspace
{
public:
  EmbedWorkspace();
  ~EmbedWorkspace();
  EmbedWorkspace(const EmbedWorkspace&) = delete;
  EmbedWorkspace& operator=(const EmbedWorkspace&) = delete;
  /// Bytes held by the per-surface arrays (the per-thread scratch not counted).
  std::size_t GetCapacityInBytes() const;
  /// Free all of it.
  void Release();

  struct Impl;
  std::unique_ptr<Impl> Internal;
};

/**
 * Embed `numberOfPoints` points (3 doubles each) whose triangles are `triangles`
 * (3 ids each; other cells are the caller's business). `numberOfPartitions` <= 0 picks
 * one per ~1000 triangles (at most 256). `progress` (may be empty) is called from the
 * calling thread with values in [0, 1]. With `vertexOrder`, `out` is left in the flood's
 * vertex order and (*vertexOrder)[k] is the input id of out[k] (saves a copy of the results);
 * without it, out[i] belongs to input point i. `workspace` (may be null) is the working
 * memory to use; the results do not depend on it.
 */
HOEMBEDFILTERSEMBEDDING_EXPORT void EmbedSurface(const EmbeddingMesh& mesh, int method,
  const double* points, EmbeddingMesh::Id numberOfPoints,
  const std::vector<EmbeddingMesh::Id>& triangles, std::vector<VertexEmbedding>& out,
  int numberOfPartitions = 0, const std::function<void(double)>& progress = {},
  FloodStatistics* stats = nullptr, std::vector<EmbeddingMesh::Id>* vertexOrder = nullptr,
  EmbedWorkspace* workspace = nullptr);

/**
 * EmbedSurface in two steps, for a caller that has other work to overlap with the first:
 * OrderSurface does the part that depends on the surface only (the breadth-first order,
 * the renumbering, the vertex lists, the partitions and the vertices in no triangle) into
 * `workspace`; FloodSurface then embeds the vertices in `mesh` (the floods and the
 * isolated vertices). The arguments mean what they mean for EmbedSurface; `points`,
 * `triangles` and `*vertexOrder` must stay alive and unchanged until FloodSurface
 * returns. Each FloodSurface needs its own OrderSurface just before it
 * (std::logic_error otherwise). The vtkEmbeddingCoordinatesFilter orders the surface
 * while it prepares the mesh, on two threads.
 */
HOEMBEDFILTERSEMBEDDING_EXPORT void OrderSurface(const double* points,
  EmbeddingMesh::Id numberOfPoints, const std::vector<EmbeddingMesh::Id>& triangles,
  int numberOfPartitions, std::vector<EmbeddingMesh::Id>* vertexOrder, EmbedWorkspace& workspace);
HOEMBEDFILTERSEMBEDDING_EXPORT void FloodSurface(const EmbeddingMesh& mesh, int method,
  std::vector<VertexEmbedding>& out, const std::function<void(double)>& progress,
  FloodStatistics* stats, EmbedWorkspace& workspace);
} // namespace hoembed

#endif
