#include "hoembedEmbeddingTree.h"

#include <algorithm>
#include <limits>

namespace hoembed
{
void AabbTree::Build(const std::vector<double>& boxes)
{
  const Id n = static_cast<Id>(boxes.size() / 6);
  this->ItemBoxes = boxes;
  this->Items.resize(n);
  this->Nodes.clear();
  if (n == 0)
    return;
  std::vector<double> centers(3 * n);
  for (Id i = 0; i < n; ++i)
  {
    this->Items[i] = i;
    for (int d = 0; d < 3; ++d)
      centers[3 * i + d] = 0.5 * (boxes[6 * i + d] + boxes[6 * i + 3 + d]);
  }
  this->Nodes.reserve(2 * n);
  this->Nodes.emplace_back();
  struct Task
  {
    Id Node, Begin, End;
  };
  std::vector<Task> tasks{ { 0, 0, n } };
  const Id leafSize = 4;
  while (!tasks.empty())
  {
    const Task t = tasks.back();
    tasks.pop_back();
    double box[6] = { std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
      std::numeric_limits<double>::max(), -std::numeric_limits<double>::max(),
      -std::numeric_limits<double>::max(), -std::numeric_limits<double>::max() };
    double cmin[3] = { box[0], box[1], box[2] }, cmax[3] = { box[3], box[4], box[5] };
    for (Id k = t.Begin; k < t.End; ++k)
    {
      const Id it = this->Items[k];
      for (int d = 0; d < 3; ++d)
      {
        box[d] = std::min(box[d], boxes[6 * it + d]);
        box[d + 3] = std::max(box[d + 3], boxes[6 * it + 3 + d]);
        cmin[d] = std::min(cmin[d], centers[3 * it + d]);
        cmax[d] = std::max(cmax[d], centers[3 * it + d]);
      }
    }
    std::copy(box, box + 6, this->Nodes[t.Node].Box);
    if (t.End - t.Begin <= leafSize)
    {
      this->Nodes[t.Node].First = t.Begin;
      this->Nodes[t.Node].Count = t.End - t.Begin;
      continue;
    }
    int axis = 0;
    for (int d = 1; d < 3; ++d)
      if (cmax[d] - cmin[d] > cmax[axis] - cmin[axis])
        axis = d;
    const Id mid = (t.Begin + t.End) / 2;
    std::nth_element(this->Items.begin() + t.Begin, this->Items.begin() + mid,
      this->Items.begin() + t.End,
      [&](Id a, Id b) { return centers[3 * a + axis] < centers[3 * b + axis]; });
    const Id child = static_cast<Id>(this->Nodes.size());
    this->Nodes[t.Node].First = child;
    this->Nodes[t.Node].Count = 0;
    this->Nodes.emplace_back();
    this->Nodes.emplace_back();
    tasks.push_back({ child, t.Begin, mid });
    tasks.push_back({ child + 1, mid, t.End });
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
