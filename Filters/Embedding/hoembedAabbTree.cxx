#include "hoembedAabbTree.h"

#include <algorithm>
#include <limits>
#include <utility>

namespace hoembed
{
void AabbTree::Build(const std::vector<double>& boxes)
{
  const Id n = static_cast<Id>(boxes.size() / 6);
  this->ItemBoxes.assign(boxes.begin(), boxes.end());
  const double* ib = this->ItemBoxes.data();
  this->Items.resize(n);
  this->Nodes.clear();
  if (n == 0)
    return;
  std::vector<double> centers(3 * n);
  for (Id i = 0; i < n; ++i)
  {
    this->Items[i] = i;
    for (int d = 0; d < 3; ++d)
      centers[3 * i + d] = 0.5 * (ib[6 * i + d] + ib[6 * i + 3 + d]);
  }
  this->Nodes.reserve(2 * n);
  this->Nodes.emplace_back();
  struct Task
  {
    Id Node, Begin, End;
  };
  // the split key of each item of a node, next to it: the same comparisons (hence the
  // same permutation from nth_element) as comparing centers through the item ids
  struct Keyed
  {
    double Key;
    Id Item;
  };
  std::vector<Keyed> keyed(n);
  std::vector<Task> tasks{ { 0, 0, n } };
  const Id leafSize = 4;
  const double big = std::numeric_limits<double>::max();
  // top down: the split of each node (median of the item centres along the axis where
  // they spread most); boxes afterwards, bottom up
  while (!tasks.empty())
  {
    const Task t = tasks.back();
    tasks.pop_back();
    if (t.End - t.Begin <= leafSize)
    {
      this->Nodes[t.Node].First = t.Begin;
      this->Nodes[t.Node].Count = t.End - t.Begin;
      continue;
    }
    double cmin[3] = { big, big, big }, cmax[3] = { -big, -big, -big };
    for (Id k = t.Begin; k < t.End; ++k)
    {
      const double* c = &centers[3 * this->Items[k]];
      for (int d = 0; d < 3; ++d)
      {
        cmin[d] = std::min(cmin[d], c[d]);
        cmax[d] = std::max(cmax[d], c[d]);
      }
    }
    int axis = 0;
    for (int d = 1; d < 3; ++d)
      if (cmax[d] - cmin[d] > cmax[axis] - cmin[axis])
        axis = d;
    const Id mid = (t.Begin + t.End) / 2;
    for (Id k = t.Begin; k < t.End; ++k)
      keyed[k] = { centers[3 * this->Items[k] + axis], this->Items[k] };
    std::nth_element(keyed.begin() + t.Begin, keyed.begin() + mid, keyed.begin() + t.End,
      [](const Keyed& a, const Keyed& b) { return a.Key < b.Key; });
    for (Id k = t.Begin; k < t.End; ++k)
      this->Items[k] = keyed[k].Item;
    const Id child = static_cast<Id>(this->Nodes.size());
    this->Nodes[t.Node].First = child;
    this->Nodes[t.Node].Count = 0;
    this->Nodes.emplace_back();
    this->Nodes.emplace_back();
    tasks.push_back({ child, t.Begin, mid });
    tasks.push_back({ child + 1, mid, t.End });
  }
  // children come after their parent: boxes of leaves from their items, of inner nodes
  // from their two children (the same minima and maxima as over all their items)
  for (Id i = static_cast<Id>(this->Nodes.size()) - 1; i >= 0; --i)
  {
    Node& node = this->Nodes[i];
    double* box = node.Box;
    for (int d = 0; d < 3; ++d)
    {
      box[d] = big;
      box[d + 3] = -big;
    }
    if (node.Count > 0)
    {
      for (Id k = node.First; k < node.First + node.Count; ++k)
      {
        const double* b = ib + 6 * this->Items[k];
        for (int d = 0; d < 3; ++d)
        {
          box[d] = std::min(box[d], b[d]);
          box[d + 3] = std::max(box[d + 3], b[d + 3]);
        }
      }
      continue;
    }
    const double* a = this->Nodes[node.First].Box;
    const double* b = this->Nodes[node.First + 1].Box;
    for (int d = 0; d < 3; ++d)
    {
      box[d] = std::min(a[d], b[d]);
      box[d + 3] = std::max(a[d + 3], b[d + 3]);
    }
  }
}

void AabbTree::Containing(const double v[3], double tol, std::vector<Id>& out) const
{
  if (this->Nodes.empty())
    return;
  auto inside = [&](const double* b) {
    for (int d = 0; d < 3; ++d)
      if (v[d] < b[d] - tol || v[d] > b[d + 3] + tol)
        return false;
    return true;
  };
  // fixed stack (no allocation per query): the tree is balanced (median splits), so its
  // depth is about log2(n / 4) and the stack holds at most depth + 1 entries
  Id stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0)
  {
    const Node& node = this->Nodes[stack[--top]];
    if (!inside(node.Box))
      continue;
    if (node.Count > 0)
    {
      for (Id k = node.First; k < node.First + node.Count; ++k)
        if (inside(&this->ItemBoxes[6 * this->Items[k]]))
          out.push_back(this->Items[k]);
      continue;
    }
    if (top + 2 > 128)
      continue; // cannot happen for trees of < 2^60 items
    stack[top++] = node.First;
    stack[top++] = node.First + 1;
  }
}
} // namespace hoembed
