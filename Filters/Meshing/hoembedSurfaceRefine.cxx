#include "hoembedSurfaceRefine.h"

#include <algorithm>
#include <map>
#include <queue>
#include <utility>

namespace hoembed
{
namespace
{
using Id = std::int64_t;
using Edge = std::pair<Id, Id>; // sorted

Edge MakeEdge(Id a, Id b)
{
  return a < b ? Edge(a, b) : Edge(b, a);
}

struct Candidate
{
  double Length2;
  Edge E;
};

// The heap's order: the longest first; of equal lengths the smaller ids first.
struct Shorter
{
  bool operator()(const Candidate& x, const Candidate& y) const
  {
    if (x.Length2 != y.Length2)
      return x.Length2 < y.Length2;
    return x.E > y.E;
  }
};
} // namespace

std::int64_t BisectLongEdges(
  std::vector<double>& points, std::vector<Id>& tris, double maxLength, std::int64_t maxSplits)
{
  const double limit2 = maxLength * maxLength;
  auto length2 = [&](const Edge& e) {
    double s = 0.0;
    for (int d = 0; d < 3; ++d)
    {
      const double x = points[3 * e.first + d] - points[3 * e.second + d];
      s += x * x;
    }
    return s;
  };
  // Each edge and the triangles that have it (two on a closed manifold; any number is
  // split alike). An ordered map: its iteration, and so the heap's filling, depends only on
  // the ids.
  std::map<Edge, std::vector<Id>> owners;
  for (Id t = 0; t < static_cast<Id>(tris.size() / 3); ++t)
    for (int k = 0; k < 3; ++k)
      owners[MakeEdge(tris[3 * t + k], tris[3 * t + (k + 1) % 3])].push_back(t);

  std::priority_queue<Candidate, std::vector<Candidate>, Shorter> heap;
  auto offer = [&](const Edge& e) {
    const double l2 = length2(e);
    if (l2 > limit2)
      heap.push({ l2, e });
  };
  for (const auto& eo : owners)
    offer(eo.first);

  auto replaceOwner = [&](const Edge& e, Id from, Id to) {
    auto& o = owners[e];
    std::replace(o.begin(), o.end(), from, to);
  };

  std::int64_t splits = 0;
  while (!heap.empty() && splits < maxSplits)
  {
    const Edge e = heap.top().E;
    heap.pop();
    auto it = owners.find(e);
    if (it == owners.end())
      continue; // split already (an edge is offered once, but be safe)
    const std::vector<Id> around = std::move(it->second);
    owners.erase(it);

    const Id m = static_cast<Id>(points.size() / 3);
    for (int d = 0; d < 3; ++d)
      points.push_back(0.5 * (points[3 * e.first + d] + points[3 * e.second + d]));

    for (const Id t : around)
    {
      // The triangle as (x, y, z) with x -> y its edge e in the triangle's own order.
      Id* c = &tris[3 * t];
      int k = 0;
      while (k < 3 && MakeEdge(c[k], c[(k + 1) % 3]) != e)
        ++k;
      if (k == 3)
        continue; // a degenerate triangle (a repeated corner) listed twice: split once
      const Id x = c[k], y = c[(k + 1) % 3], z = c[(k + 2) % 3];
      const Id added = static_cast<Id>(tris.size() / 3);
      // t becomes (x, m, z), the new triangle (m, y, z): both keep t's orientation.
      c[0] = x;
      c[1] = m;
      c[2] = z;
      tris.push_back(m);
      tris.push_back(y);
      tris.push_back(z);
      replaceOwner(MakeEdge(y, z), t, added);
      owners[MakeEdge(x, m)].push_back(t);
      owners[MakeEdge(m, y)].push_back(added);
      auto& mz = owners[MakeEdge(m, z)];
      mz.push_back(t);
      mz.push_back(added);
      offer(MakeEdge(m, z));
    }
    offer(MakeEdge(e.first, m));
    offer(MakeEdge(m, e.second));
    ++splits;
  }
  return splits;
}
} // namespace hoembed
