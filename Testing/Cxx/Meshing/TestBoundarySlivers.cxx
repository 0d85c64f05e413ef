// hoembed::RemoveBoundarySlivers, which both curving (its first step) and the mesher
// driver's count of the cells a TetGen mesh will keep rely on: a flat tet with two boundary
// faces goes, and the boundary stays closed and manifold (the two faces are replaced by the
// tet's two interior ones: an edge flip); a tet of good shape in the same place stays; a
// tet whose four faces are all boundary (the mesh would lose its only cell) stays.
#include "hoembedCurvedMeshBuilder.h"
#include "hoembedTestUtilities.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <map>
#include <vector>

namespace
{
using Id = std::int64_t;

// Boundary faces (sorted corner triples) of a tet4 mesh: the faces found once.
std::map<std::array<Id, 3>, int> FaceCounts(const std::vector<Id>& tets)
{
  static const int faces[4][3] = { { 0, 1, 2 }, { 0, 1, 3 }, { 0, 2, 3 }, { 1, 2, 3 } };
  std::map<std::array<Id, 3>, int> count;
  for (size_t t = 0; t < tets.size() / 4; ++t)
    for (const auto& f : faces)
    {
      std::array<Id, 3> k{ tets[4 * t + f[0]], tets[4 * t + f[1]], tets[4 * t + f[2]] };
      std::sort(k.begin(), k.end());
      ++count[k];
    }
  return count;
}

// A closed manifold boundary: every edge of the boundary faces is in exactly two of them.
bool BoundaryClosed(const std::vector<Id>& tets)
{
  std::map<std::pair<Id, Id>, int> edges;
  for (const auto& fc : FaceCounts(tets))
  {
    if (fc.second != 1)
      continue;
    const auto& f = fc.first;
    ++edges[{ f[0], f[1] }];
    ++edges[{ f[0], f[2] }];
    ++edges[{ f[1], f[2] }];
  }
  return !edges.empty() &&
    std::all_of(edges.begin(), edges.end(), [](const auto& e) { return e.second == 2; });
}

// An upside-down square pyramid (apex 4 under the square 0 1 3 2, split along 1-2) and a
// fifth tet 0 1 2 3 on its top: its faces 0 1 2 and 1 2 3 are interior, 0 1 3 and 0 2 3
// boundary; corner 3 at height `lift` above the square's plane makes it flat or not.
std::vector<double> Points(double lift)
{
  return { 0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, lift, 0.5, 0.5, -1 };
}
// positively oriented (det of the edges from the first corner > 0)
const std::vector<Id> kPyramid{ 0, 2, 1, 4, 1, 2, 3, 4 };
const std::vector<Id> kTop{ 0, 1, 2, 3 };
} // namespace

int main(int, char*[])
{
  std::vector<Id> tets(kPyramid);
  tets.insert(tets.end(), kTop.begin(), kTop.end());
  HOEMBED_CHECK(BoundaryClosed(tets), "the test mesh should have a closed boundary");

  // Flat: corner 3 barely above the square (scaled Jacobian ~0.03)
  std::vector<Id> flat(tets);
  const Id removed = hoembed::RemoveBoundarySlivers(Points(0.02), flat, 5, 0.2);
  HOEMBED_CHECK(removed == 1 && flat == kPyramid,
    "the flat top tet should go and the pyramid stay (removed %lld, %zu tets left)",
    static_cast<long long>(removed), flat.size() / 4);
  HOEMBED_CHECK(BoundaryClosed(flat), "the boundary should stay closed after the removal");

  // Of good shape (corner 3 one unit up): kept
  std::vector<Id> good(tets);
  HOEMBED_CHECK(hoembed::RemoveBoundarySlivers(Points(1.0), good, 5, 0.2) == 0 && good == tets,
    "a top tet of good shape should stay");

  // A lone flat tet: all four faces are boundary, not two: kept
  std::vector<Id> lone(kTop);
  HOEMBED_CHECK(hoembed::RemoveBoundarySlivers(Points(0.02), lone, 5, 0.2) == 0 && lone == kTop,
    "a lone tet should stay");
  std::printf("TestBoundarySlivers: passed\n");
  return 0;
}
