#include "hoembedEmbeddingFlood.h"
#include "hoembedCsr.h"

#include "hoembedParallel.h"

#include <algorithm>
#include <cstdint>
#include <atomic>
#include <limits>
#include <stdexcept>
#include <thread>

namespace hoembed
{
namespace
{
using Id = EmbeddingMesh::Id;

struct Entry
{
  Id Triangle;
  Id HintVertex; ///< the vertex whose result is the initial guess (-1: none)
  double MaxDistance;
};

struct FloodContext
{
  const EmbeddingMesh* Mesh;
  int Method;
  const double* Points;
  const std::vector<Id>* Triangles;
  std::vector<Id> VertexTriOffsets;
  std::vector<std::int32_t> VertexTris; // triangle ids (< 2^31 triangles)
  Id NumberOfTriangles = 0;
  std::vector<int> Owner; // per vertex: partition, -1 for isolated vertices
  std::vector<char> TriangleState;
  std::vector<char> Done;
  std::vector<char> Expanded;
  Id NumberOfPartitions = 1;
  std::vector<VertexEmbedding>* Out;
  std::atomic<Id> Seeds{ 0 }, Raises{ 0 };
  // per-thread search scratch, prepared for the mesh at its first use in each call
  struct ThreadScratch
  {
    SearchScratch Search;
    std::vector<Entry> FloodQueue, FloodDeferred; // FloodPartition's
    unsigned PreparedInCall = 0;
  };
  ThreadLocal<ThreadScratch> Scratch;
  unsigned Call = 0; // EmbedSurface calls with this context, counting from 1

  ThreadScratch& LocalScratch()
  {
    ThreadScratch& s = this->Scratch.Local();
    if (s.PreparedInCall != this->Call)
    {
      s.Search.Prepare(*this->Mesh);
      s.PreparedInCall = this->Call;
    }
    return s;
  }

  void Embed(Id w, const VertexHint& h, SearchScratch& s)
  {
    EmbedVertex(*this->Mesh, this->Method, this->Points + 3 * w, h, (*this->Out)[w], s);
    this->Done[w] = 1;
  }

  void FloodPartition(Id p)
  {
    ThreadScratch& ts = this->LocalScratch();
    SearchScratch& s = ts.Search;
    const Id ntri = this->NumberOfTriangles;
    const Id b = p * ntri / this->NumberOfPartitions;
    const Id e = (p + 1) * ntri / this->NumberOfPartitions;
    const std::vector<Id>& tri = *this->Triangles;
    const double floor = 1e-3 * this->Mesh->Diagonal;
    // first in, first out: entries from `head` on are waiting (a vector read from the
    // front and emptied when it runs dry, cheaper than a deque's blocks)
    std::vector<Entry>& queue = ts.FloodQueue;
    std::vector<Entry>& deferred = ts.FloodDeferred;
    deferred.clear();
    size_t head = 0;
    for (Id k = b; k < e; ++k)
    {
      const Id t0 = k;
      if (this->TriangleState[t0])
        continue;
      ++this->Seeds;
      this->TriangleState[t0] = 1;
      queue.clear(); // (the last seed's flood has run dry)
      head = 0;
      queue.push_back({ t0, -1, 0.0 });
      double dt = -1.0;
      while (head < queue.size() || !deferred.empty())
      {
        if (head == queue.size())
        {
          queue.clear();
          head = 0;
          double dmin = std::numeric_limits<double>::max();
          for (const Entry& en : deferred)
            dmin = std::min(dmin, en.MaxDistance);
          dt = std::max(2.0 * dt, dmin * (1.0 + 1e-12) + 1e-300);
          ++this->Raises;
          queue.insert(queue.end(), deferred.begin(), deferred.end());
          deferred.clear();
        }
        const Entry en = queue[head++];
        const Id t = en.Triangle;
        Id hv = en.HintVertex; // the vertex whose result starts the next search
        bool mapped = true;
        double maxd = 0.0;
        for (int j = 0; j < 3; ++j)
        {
          const Id w = tri[3 * t + j];
          if (this->Owner[w] != static_cast<int>(p))
            continue;
          if (!this->Done[w])
            this->Embed(
              w, hv >= 0 ? (*this->Out)[hv].AsHint(this->Points + 3 * hv) : VertexHint(), s);
          const double dw = (*this->Out)[w].ClosestDistance;
          if (dt < 0.0)
            dt = std::max(2.0 * dw, floor);
          maxd = std::max(maxd, dw);
          if (dw < dt)
            hv = w;
          else
            mapped = false;
        }
        if (!mapped)
        {
          deferred.push_back({ t, hv, maxd });
          continue;
        }
        // queue the triangles around this triangle's vertices; each vertex of this
        // partition is expanded once (its triangles are queued by its first mapped
        // triangle); vertices of other partitions are expanded too (the flood must cross
        // them: a range of the breadth-first order is a band whose triangles often meet
        // only at vertices owned by the previous range), without the flag, which belongs
        // to their partition's thread
        for (int j = 0; j < 3; ++j)
        {
          const Id w = tri[3 * t + j];
          if (this->Owner[w] == static_cast<int>(p))
          {
            if (this->Expanded[w])
              continue;
            this->Expanded[w] = 1;
          }
          for (Id i = this->VertexTriOffsets[w]; i < this->VertexTriOffsets[w + 1]; ++i)
          {
            const Id n = this->VertexTris[i];
            if (n >= b && n < e && !this->TriangleState[n])
            {
              this->TriangleState[n] = 1;
              queue.push_back({ n, hv, 0.0 });
            }
          }
        }
      }
    }
  }
};
} // namespace

namespace
{
// vertex -> triangles (CSR over `tris`, 3 ids per triangle)
void VertexTriangles(const std::vector<Id>& tris, Id numberOfPoints, std::vector<Id>& offsets,
  std::vector<std::int32_t>& list)
{
  const Id ntri = static_cast<Id>(tris.size() / 3);
  BuildCsr(
    numberOfPoints,
    [&](auto&& emit) {
      for (Id t = 0; t < ntri; ++t)
        for (int j = 0; j < 3; ++j)
          emit(tris[3 * t + j], static_cast<std::int32_t>(t));
    },
    offsets, list);
}
} // namespace

struct EmbedWorkspace::Impl
{
  FloodContext Context; // its arrays are kept; pointers and counters are set per call
  std::vector<Id> Offsets, NewId, OldId, Triangles, Isolated;
  std::vector<std::int32_t> VertexTris, Order;
  std::vector<char> Queued, Expanded;
  std::vector<double> Points;
  std::vector<VertexEmbedding> Results; // without a vertex order: before the scatter
  // what OrderSurface leaves for FloodSurface
  bool Ordered = false;
  Id NumberOfPoints = 0;
  std::vector<Id>* VertexOrder = nullptr; // the caller's (new -> input ids), or null: OldId
};

EmbedWorkspace::EmbedWorkspace() : Internal(new Impl) {}

EmbedWorkspace::~EmbedWorkspace() = default;

std::size_t EmbedWorkspace::GetCapacityInBytes() const
{
  const Impl& w = *this->Internal;
  const FloodContext& c = w.Context;
  auto bytes = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
  return bytes(w.Offsets) + bytes(w.NewId) + bytes(w.OldId) + bytes(w.Triangles) +
    bytes(w.Isolated) + bytes(w.VertexTris) + bytes(w.Order) + bytes(w.Queued) + bytes(w.Expanded) +
    bytes(w.Points) + bytes(w.Results) + bytes(c.VertexTriOffsets) + bytes(c.VertexTris) +
    bytes(c.Owner) + bytes(c.TriangleState) + bytes(c.Done) + bytes(c.Expanded);
}

void EmbedWorkspace::Release()
{
  this->Internal.reset(new Impl);
}

void OrderSurface(const double* points, Id numberOfPoints, const std::vector<Id>& triangles,
  int numberOfPartitions, std::vector<Id>* vertexOrder, EmbedWorkspace& workspace)
{
  EmbedWorkspace::Impl& W = *workspace.Internal;
  const Id ntri = static_cast<Id>(triangles.size() / 3);

  // Breadth-first order of the triangles over the surface (neighbours through shared
  // vertices), one component after the other, and the vertices renumbered by their
  // first appearance in it: consecutive triangles and vertices are then neighbours on the
  // surface whatever the input order. (The real meshes' order is not spatially coherent:
  // contiguous ranges of input triangles gave about one flood seed, i.e. one search
  // without a hint, per triangle, and every access was a cache miss.)
  std::vector<Id>& offsets = W.Offsets;
  std::vector<std::int32_t>& vertexTris = W.VertexTris;
  VertexTriangles(triangles, numberOfPoints, offsets, vertexTris);
  // The vertices are numbered as their triangles are queued (that is their first
  // appearance in the order), and the triangles' new ids written then: the triangle is
  // read again when it is expanded, a few hundred queue places later, still in cache.
  // With a vertex order the new-to-old ids go straight to the caller.
  std::vector<std::int32_t>& order = W.Order;
  std::vector<Id>& newId = W.NewId;
  std::vector<Id>& oldId = vertexOrder ? *vertexOrder : W.OldId;
  std::vector<Id>& tris = W.Triangles;
  order.resize(ntri);
  newId.assign(numberOfPoints, -1);
  oldId.resize(numberOfPoints);
  tris.resize(3 * ntri);
  Id next = 0;
  {
    std::vector<char>& queued = W.Queued;
    std::vector<char>& expanded = W.Expanded;
    queued.assign(ntri, 0);
    expanded.assign(numberOfPoints, 0);
    Id head = 0, tail = 0;
    auto enqueue = [&](Id t) {
      queued[t] = 1;
      for (int j = 0; j < 3; ++j)
      {
        const Id w = triangles[3 * t + j];
        if (newId[w] < 0)
        {
          oldId[next] = w;
          newId[w] = next++;
        }
        tris[3 * tail + j] = newId[w];
      }
      order[tail++] = static_cast<std::int32_t>(t);
    };
    for (Id t0 = 0; t0 < ntri; ++t0)
    {
      if (queued[t0])
        continue;
      enqueue(t0);
      while (head < tail)
      {
        const Id t = order[head++];
        for (int j = 0; j < 3; ++j)
        {
          const Id w = triangles[3 * t + j];
          if (expanded[w])
            continue;
          expanded[w] = 1;
          for (Id i = offsets[w]; i < offsets[w + 1]; ++i)
          {
            const std::int32_t n = vertexTris[i];
            if (!queued[n])
              enqueue(n);
          }
        }
      }
    }
  }
  const Id nOnTriangles = next;
  for (Id w = 0; w < numberOfPoints; ++w)
    if (newId[w] < 0)
    {
      oldId[next] = w;
      newId[w] = next++;
    }
  std::vector<double>& pts = W.Points;
  pts.resize(3 * static_cast<size_t>(numberOfPoints));
  ParallelLoop(Id(0), numberOfPoints, [&](Id b, Id e) {
    for (Id i = b; i < e; ++i)
      for (int d = 0; d < 3; ++d)
        pts[3 * i + d] = points[3 * oldId[i] + d];
  });
  FloodContext& ctx = W.Context;
  ctx.Points = pts.data();
  ctx.Triangles = &tris;
  VertexTriangles(tris, numberOfPoints, ctx.VertexTriOffsets, ctx.VertexTris);

  // partitions: contiguous ranges of the breadth-first order (a range that is not
  // connected just gets more seeds); fixed by the surface, not by the thread count, so
  // results do not depend on the number of threads
  Id P = numberOfPartitions > 0 ? numberOfPartitions : std::min<Id>(256, ntri / 1000);
  P = std::max<Id>(1, std::min<Id>(P, std::max<Id>(ntri, 1)));
  ctx.NumberOfPartitions = P;
  ctx.NumberOfTriangles = ntri;
  ctx.Owner.assign(numberOfPoints, -1);
  for (Id p = 0; p < P; ++p)
    for (Id t = p * ntri / P; t < (p + 1) * ntri / P; ++t)
      for (int j = 0; j < 3; ++j)
      {
        const Id w = tris[3 * t + j];
        if (ctx.Owner[w] < 0)
          ctx.Owner[w] = static_cast<int>(p);
      }
  ctx.TriangleState.assign(ntri, 0);
  ctx.Done.assign(numberOfPoints, 0);
  ctx.Expanded.assign(numberOfPoints, 0);

  // vertices in no triangle: numbered last
  std::vector<Id>& isolated = W.Isolated;
  isolated.clear();
  for (Id i = nOnTriangles; i < numberOfPoints; ++i)
    isolated.push_back(i);

  W.Ordered = true;
  W.NumberOfPoints = numberOfPoints;
  W.VertexOrder = vertexOrder;
}

void FloodSurface(const EmbeddingMesh& mesh, int method, std::vector<VertexEmbedding>& out,
  const std::function<void(double)>& progress, FloodStatistics* stats, EmbedWorkspace& workspace)
{
  EmbedWorkspace::Impl& W = *workspace.Internal;
  if (!W.Ordered)
    throw std::logic_error("hoembed::FloodSurface: the workspace holds no surface order "
                           "(call OrderSurface first, once per FloodSurface)");
  W.Ordered = false;
  const Id numberOfPoints = W.NumberOfPoints;
  std::vector<Id>* vertexOrder = W.VertexOrder;
  const std::vector<Id>& oldId = vertexOrder ? *vertexOrder : W.OldId;
  const std::vector<double>& pts = W.Points;
  const std::vector<Id>& isolated = W.Isolated;
  const Id nIso = static_cast<Id>(isolated.size());
  FloodContext& ctx = W.Context;
  const Id P = ctx.NumberOfPartitions;
  // with a vertex order the results go straight to the caller, in the flood's order
  std::vector<VertexEmbedding>& res = vertexOrder ? out : W.Results;
  res.resize(numberOfPoints); // EmbedVertex writes every field of a vertex it embeds

  ctx.Seeds = 0;
  ctx.Raises = 0;
  ++ctx.Call;
  ctx.Mesh = &mesh;
  ctx.Method = method;
  ctx.Out = &res;

  // parallel floods, one loop over all partitions (no barrier before the last one ends);
  // progress is reported from the calling thread only (it runs partitions too), as the
  // share of partitions finished
  const double triShare = numberOfPoints > 0 ? double(numberOfPoints - nIso) / numberOfPoints : 0.0;
  const std::thread::id caller = std::this_thread::get_id();
  std::atomic<Id> finished{ 0 };
  ParallelLoop(Id(0), P, Id(1), [&](Id begin, Id end) {
    for (Id p = begin; p < end; ++p)
    {
      ctx.FloodPartition(p);
      const Id done = ++finished;
      if (progress && std::this_thread::get_id() == caller)
        progress(triShare * double(done) / double(P));
    }
  });
  // isolated vertices: chunks, each vertex from the previous one
  if (nIso > 0)
  {
    const Id chunk = 256;
    ParallelLoop(Id(0), (nIso + chunk - 1) / chunk, Id(1), [&](Id begin, Id end) {
      SearchScratch& s = ctx.LocalScratch().Search;
      for (Id c = begin; c < end; ++c)
      {
        VertexHint h;
        for (Id k = c * chunk; k < std::min(nIso, (c + 1) * chunk); ++k)
        {
          ctx.Embed(isolated[k], h, s);
          h = res[isolated[k]].AsHint(pts.data() + 3 * isolated[k]);
        }
      }
    });
  }
  if (!vertexOrder)
  {
    out.resize(numberOfPoints);
    for (Id i = 0; i < numberOfPoints; ++i)
      out[oldId[i]] = res[i];
  }
  if (progress)
    progress(1.0);
  if (stats)
  {
    stats->Partitions = P;
    stats->Seeds = ctx.Seeds.load();
    stats->ThresholdRaises = ctx.Raises.load();
    stats->IsolatedVertices = nIso;
  }
}

void EmbedSurface(const EmbeddingMesh& mesh, int method, const double* points, Id numberOfPoints,
  const std::vector<Id>& triangles, std::vector<VertexEmbedding>& out, int numberOfPartitions,
  const std::function<void(double)>& progress, FloodStatistics* stats, std::vector<Id>* vertexOrder,
  EmbedWorkspace* workspace)
{
  EmbedWorkspace local;
  EmbedWorkspace& ws = workspace ? *workspace : local;
  OrderSurface(points, numberOfPoints, triangles, numberOfPartitions, vertexOrder, ws);
  FloodSurface(mesh, method, out, progress, stats, ws);
}
} // namespace hoembed
