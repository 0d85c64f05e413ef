// hoembed::FindCurvedFaceCrossings on hand-made tri6 faces whose answer is known
// analytically: parallel flat faces (apart), a face through another (crossing), a flat
// face above a curved one whose edge bulges through it (crossing only once curved: the
// quadratic edge with its mid-edge node at height 0.3 reaches z = 0.3 at its middle),
// and faces sharing a corner (never compared).
#include "hoembedBoundaryCrossings.h"
#include "hoembedTestUtilities.h"

#include <cstdint>
#include <vector>

namespace
{
using Id = std::int64_t;

// Appends a straight tri6 face (mid-edge nodes at the midpoints) and returns its 6 ids.
std::vector<Id> AddFace(
  std::vector<double>& pts, const double a[3], const double b[3], const double c[3])
{
  const Id base = static_cast<Id>(pts.size() / 3);
  const double* corner[3] = { a, b, c };
  for (auto* p : corner)
    pts.insert(pts.end(), p, p + 3);
  for (int k = 0; k < 3; ++k)
    for (int d = 0; d < 3; ++d)
      pts.push_back(0.5 * (corner[k][d] + corner[(k + 1) % 3][d]));
  return { base, base + 1, base + 2, base + 3, base + 4, base + 5 };
}

size_t Count(const std::vector<double>& pts, const std::vector<Id>& f, const std::vector<Id>& g)
{
  std::vector<Id> faces(f);
  faces.insert(faces.end(), g.begin(), g.end());
  return hoembed::FindCurvedFaceCrossings(pts, faces).size();
}
} // namespace

int main(int, char*[])
{
  const double a0[3] = { 0, 0, 0 }, a1[3] = { 1, 0, 0 }, a2[3] = { 0, 1, 0 };
  {
    std::vector<double> pts;
    auto A = AddFace(pts, a0, a1, a2);
    const double b0[3] = { 0, 0, 0.5 }, b1[3] = { 1, 0, 0.5 }, b2[3] = { 0, 1, 0.5 };
    auto B = AddFace(pts, b0, b1, b2);
    HOEMBED_CHECK(Count(pts, A, B) == 0, "parallel flat faces reported crossing");
  }
  {
    std::vector<double> pts;
    auto A = AddFace(pts, a0, a1, a2);
    const double b0[3] = { 0.2, 0.2, -0.5 }, b1[3] = { 0.3, 0.2, 0.5 }, b2[3] = { 0.2, 0.3, 0.5 };
    auto B = AddFace(pts, b0, b1, b2);
    HOEMBED_CHECK(Count(pts, A, B) == 1, "a face through another not found");
  }
  {
    std::vector<double> pts;
    auto A = AddFace(pts, a0, a1, a2);
    const double b0[3] = { 0.1, -0.2, 0.1 }, b1[3] = { 0.9, -0.2, 0.1 }, b2[3] = { 0.5, 0.4, 0.1 };
    auto B = AddFace(pts, b0, b1, b2);
    HOEMBED_CHECK(Count(pts, A, B) == 0, "flat faces 0.1 apart reported crossing");
    pts[3 * A[3] + 2] = 0.3; // A's edge 01 bulges up to z = 0.3 under B
    HOEMBED_CHECK(Count(pts, A, B) == 1, "curved edge through a face not found");
    pts[3 * A[3] + 2] = 0.05; // below B everywhere: z <= 0.05 < 0.1
    HOEMBED_CHECK(Count(pts, A, B) == 0, "curved face below another reported crossing");
  }
  {
    std::vector<double> pts;
    auto A = AddFace(pts, a0, a1, a2);
    const double b1[3] = { 0.5, 0.5, -0.5 }, b2[3] = { 0.5, 0.5, 0.5 };
    auto B = AddFace(pts, a0, b1, b2);
    B[0] = A[0]; // shares corner a0 (and crosses A away from it): legitimate neighbours
    HOEMBED_CHECK(Count(pts, A, B) == 0, "faces sharing a corner compared");
  }
  return hoembed_test::Report("TestBoundaryCrossings");
}
