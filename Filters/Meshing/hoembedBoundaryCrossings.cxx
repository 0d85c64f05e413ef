#include "hoembedBoundaryCrossings.h"

#include "hoembedSurfaceCheck.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace hoembed
{
namespace
{
using Id = std::int64_t;

// A quadratic triangle by its six Lagrange nodes (corners 0-2, mids 01, 12, 20).
struct Patch
{
  double X[6][3];
};

struct Box
{
  double Lo[3], Hi[3];
  bool Overlaps(const Box& o) const
  {
    for (int d = 0; d < 3; ++d)
      if (this->Hi[d] < o.Lo[d] || o.Hi[d] < this->Lo[d])
        return false;
    return true;
  }
  double Size() const
  {
    return std::max(
      { this->Hi[0] - this->Lo[0], this->Hi[1] - this->Lo[1], this->Hi[2] - this->Lo[2] });
  }
};

// Box of the Bézier control net (bounds the patch: convex hull property).
Box ControlBox(const Patch& p)
{
  Box b;
  for (int d = 0; d < 3; ++d)
  {
    b.Lo[d] = b.Hi[d] = p.X[0][d];
  }
  static const int edge[3][2] = { { 0, 1 }, { 1, 2 }, { 2, 0 } };
  for (int k = 0; k < 6; ++k)
    for (int d = 0; d < 3; ++d)
    {
      double v = p.X[k][d];
      if (k >= 3)
        v = 2.0 * p.X[k][d] - 0.5 * (p.X[edge[k - 3][0]][d] + p.X[edge[k - 3][1]][d]);
      b.Lo[d] = std::min(b.Lo[d], v);
      b.Hi[d] = std::max(b.Hi[d], v);
    }
  return b;
}

// The patch at parametric (u, v) (corner 0 at (0,0), 1 at (1,0), 2 at (0,1)).
void Eval(const Patch& p, double u, double v, double x[3])
{
  const double w = 1.0 - u - v;
  const double N[6] = { w * (2 * w - 1), u * (2 * u - 1), v * (2 * v - 1), 4 * w * u, 4 * u * v,
    4 * v * w };
  for (int d = 0; d < 3; ++d)
  {
    x[d] = 0.0;
    for (int k = 0; k < 6; ++k)
      x[d] += N[k] * p.X[k][d];
  }
}

// The four quadratic sub-patches of the midpoint split (exact: a quadratic restricted to
// a sub-triangle is a quadratic).
void Split(const Patch& p, Patch out[4])
{
  static const double C[4][3][2] = { { { 0, 0 }, { 0.5, 0 }, { 0, 0.5 } },
    { { 0.5, 0 }, { 1, 0 }, { 0.5, 0.5 } }, { { 0, 0.5 }, { 0.5, 0.5 }, { 0, 1 } },
    { { 0.5, 0.5 }, { 0, 0.5 }, { 0.5, 0 } } };
  for (int s = 0; s < 4; ++s)
  {
    for (int k = 0; k < 3; ++k)
      Eval(p, C[s][k][0], C[s][k][1], out[s].X[k]);
    for (int k = 0; k < 3; ++k)
    {
      const int a = k, b = (k + 1) % 3;
      Eval(p, 0.5 * (C[s][a][0] + C[s][b][0]), 0.5 * (C[s][a][1] + C[s][b][1]), out[s].X[3 + k]);
    }
  }
}

// Two flat triangles intersect when an edge of one crosses the other.
bool FlatTrianglesCross(const Patch& a, const Patch& b)
{
  for (int k = 0; k < 3; ++k)
    if (SegmentCrossesTriangle(a.X[k], a.X[(k + 1) % 3], b.X[0], b.X[1], b.X[2]) ||
      SegmentCrossesTriangle(b.X[k], b.X[(k + 1) % 3], a.X[0], a.X[1], a.X[2]))
      return true;
  return false;
}

// A straight face: every mid-edge node at its edge's midpoint (to round-off).
bool IsFlat(const Patch& p)
{
  static const int edge[3][2] = { { 0, 1 }, { 1, 2 }, { 2, 0 } };
  double scale = 0.0;
  for (int d = 0; d < 3; ++d)
    scale = std::max(scale, std::fabs(p.X[1][d] - p.X[0][d]) + std::fabs(p.X[2][d] - p.X[0][d]));
  for (int k = 0; k < 3; ++k)
    for (int d = 0; d < 3; ++d)
      if (std::fabs(p.X[3 + k][d] - 0.5 * (p.X[edge[k][0]][d] + p.X[edge[k][1]][d])) >
        1e-13 * scale)
        return false;
  return true;
}

// True: crossing, or not proven apart at maxDepth; false: proven apart. An explicit
// stack, no recursion.
bool PatchesMeet(const Patch& a0, const Patch& b0, int maxDepth)
{
  struct Item
  {
    Patch A, B;
    int Depth;
  };
  std::vector<Item> stack;
  stack.push_back({ a0, b0, 0 });
  while (!stack.empty())
  {
    Item it = stack.back();
    stack.pop_back();
    const Box ba = ControlBox(it.A), bb = ControlBox(it.B);
    if (!ba.Overlaps(bb))
      continue;
    if (it.Depth >= maxDepth)
      return true; // crossing, or not proven apart at this depth
    Patch sub[4];
    const bool splitA = ba.Size() >= bb.Size();
    Split(splitA ? it.A : it.B, sub);
    for (int s = 0; s < 4; ++s)
      stack.push_back(
        splitA ? Item{ sub[s], it.B, it.Depth + 1 } : Item{ it.A, sub[s], it.Depth + 1 });
  }
  return false;
}
} // namespace

std::vector<std::array<Id, 2>> FindCurvedFaceCrossings(
  const std::vector<double>& points, const std::vector<Id>& faces, int maxDepth)
{
  const Id nf = static_cast<Id>(faces.size() / 6);
  std::vector<Patch> patch(nf);
  std::vector<Box> box(nf);
  for (Id f = 0; f < nf; ++f)
  {
    for (int k = 0; k < 6; ++k)
      for (int d = 0; d < 3; ++d)
        patch[f].X[k][d] = points[3 * faces[6 * f + k] + d];
    box[f] = ControlBox(patch[f]);
  }
  // Sweep and prune along x.
  std::vector<Id> order(nf);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](Id a, Id b) { return box[a].Lo[0] < box[b].Lo[0]; });
  std::vector<std::array<Id, 2>> out;
  for (Id i = 0; i < nf; ++i)
  {
    const Id f = order[i];
    for (Id j = i + 1; j < nf && box[order[j]].Lo[0] <= box[f].Hi[0]; ++j)
    {
      const Id g = order[j];
      if (!box[f].Overlaps(box[g]))
        continue;
      bool shared = false;
      for (int a = 0; a < 3 && !shared; ++a)
        for (int b = 0; b < 3 && !shared; ++b)
          shared = faces[6 * f + a] == faces[6 * g + b];
      if (shared)
        continue;
      // Two straight faces: the flat test decides exactly; otherwise the certified one.
      const bool meet = IsFlat(patch[f]) && IsFlat(patch[g])
        ? FlatTrianglesCross(patch[f], patch[g])
        : PatchesMeet(patch[f], patch[g], maxDepth);
      if (meet)
        out.push_back({ std::min(f, g), std::max(f, g) });
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}
} // namespace hoembed
