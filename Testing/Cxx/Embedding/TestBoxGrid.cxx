// hoembed::BoxGrid (hoembedBoxGrid.h) against a scan of every box.
#include "hoembedQuadraticMapTestUtilities.h"
#include "hoembedEmbeddingTestUtilities.h"

#include "hoembedBoundaryNormals.h"
#include "hoembedClosestPoint.h"
#include "hoembedElementGeometry.h"
#include "hoembedEmbeddingFlood.h"
#include "hoembedBoxGrid.h"
#include "hoembedEmbeddingSearch.h"
#include "hoembedShapeFunctions.h"
#include "hoembedTetBarycentric.h"
#include "vtkEmbeddingCoordinatesFilter.h"
#include "vtkTet10Mesher.h"

#include "vtkAppendPolyData.h"
#include "vtkCallbackCommand.h"
#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCommand.h"
#include "vtkDoubleArray.h"
#include "vtkExecutive.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkOBJReader.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkQuadraticTetra.h"
#include "vtkSMPTools.h"
#include "vtkSignedCharArray.h"
#include "vtkSphereSource.h"
#include "vtkStringArray.h"
#include "vtkTetra.h"
#include "vtkTransform.h"
#include "vtkTransformPolyDataFilter.h"
#include "vtkXMLPolyDataReader.h"
#include "vtkXMLPolyDataWriter.h"

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>

using hoembed_test::MakeBoxTetMesh;

namespace
{

// hoembed::BoxGrid::Containing (the cells whose boxes may hold a point) and VisitNearer
// (the boundary faces whose boxes are within a distance) against a scan of every box:
// clustered and flat boxes, points on box faces, outside the grid and far away, several
// tolerances and radii; each item once. NearItem: an item for every query of a grid
// that has any, one holding the point when a box does.
void TestBoxGrid()
{
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  int mismatches = 0, duplicates = 0, hits = 0, queries = 0, nearMismatches = 0, nearHits = 0;
  int nearItemMismatches = 0, boxDistanceMismatches = 0;
  {
    hoembed::BoxGrid empty;
    empty.Build({});
    const double origin[3] = { 0, 0, 0 };
    nearItemMismatches += empty.NearItem(origin) != -1;
  }
  for (int trial = 0; trial < 6; ++trial)
  {
    const int n = trial == 0 ? 1 : 40 * trial * trial;
    std::vector<double> boxes(6 * n);
    for (int i = 0; i < n; ++i)
    {
      // a cluster near the origin and a spread; some boxes flat in z
      const double c = i % 3 == 0 ? 0.1 : 1.0;
      for (int d = 0; d < 3; ++d)
      {
        const double a = c * U(rng), w = (trial == 3 && d == 2) ? 0.0 : 0.2 * U(rng);
        boxes[6 * i + d] = a;
        boxes[6 * i + 3 + d] = a + w;
      }
    }
    hoembed::BoxGrid grid;
    grid.Build(boxes);
    for (int q = 0; q < 400; ++q)
    {
      double v[3];
      for (int d = 0; d < 3; ++d)
        v[d] = -0.3 + 1.8 * U(rng);
      if (q % 4 == 1) // on a face of a box
      {
        const int i = static_cast<int>(U(rng) * n) % n;
        for (int d = 0; d < 3; ++d)
          v[d] = boxes[6 * i + d] + U(rng) * (boxes[6 * i + 3 + d] - boxes[6 * i + d]);
        v[q % 3] = boxes[6 * i + (q % 2 ? 3 : 0) + q % 3];
      }
      if (q == 7)
        v[0] = 1e6;
      for (const double tol : { 0.0, 1e-9, 0.05 })
      {
        ++queries;
        std::vector<hoembed::BoxGrid::Id> got, want;
        grid.Containing(v, tol, got);
        for (int i = 0; i < n; ++i)
        {
          bool in = true;
          for (int d = 0; d < 3; ++d)
            in = in && v[d] >= boxes[6 * i + d] - tol && v[d] <= boxes[6 * i + 3 + d] + tol;
          if (in)
            want.push_back(i);
        }
        std::sort(got.begin(), got.end());
        duplicates += std::adjacent_find(got.begin(), got.end()) != got.end();
        got.erase(std::unique(got.begin(), got.end()), got.end());
        mismatches += got != want;
        hits += static_cast<int>(want.size());
        if (tol == 0.0)
        {
          // NearItem: some item, and one whose box holds v when any box does (such a box
          // is listed in v's own bin, the first shell scanned)
          const hoembed::BoxGrid::Id near = grid.NearItem(v);
          if (near < 0 || near >= n ||
            (!want.empty() && hoembed::AabbTree::BoxDistance2(&boxes[6 * near], v) != 0.0))
            ++nearItemMismatches;
        }
      }
      // BoxDistance2 against the distance to the point clamped into the box (the same
      // roundings: equal bit for bit), for every box: inside, on faces, beyond each side
      for (int i = 0; i < n; ++i)
      {
        double s = 0.0;
        for (int d = 0; d < 3; ++d)
        {
          const double c = std::min(std::max(v[d], boxes[6 * i + d]), boxes[6 * i + 3 + d]);
          s += (v[d] - c) * (v[d] - c);
        }
        boxDistanceMismatches += hoembed::AabbTree::BoxDistance2(&boxes[6 * i], v) != s;
      }
      // VisitNearer: every box nearer than the radius (as it stands when the box is
      // reached: a visit may lower it, here to 1.2 times the visited box's distance), once
      for (const double radius : { 0.01, 0.1, 0.3 })
      {
        double best2 = radius * radius;
        std::vector<hoembed::BoxGrid::Id> got;
        if (!grid.VisitNearer(v, best2, 1 << 30, [&](hoembed::BoxGrid::Id item) {
              got.push_back(item);
              const double d2 = hoembed::AabbTree::BoxDistance2(&boxes[6 * item], v);
              if (q % 2)
                best2 = std::min(best2, 1.44 * d2);
            }))
        {
          ++nearMismatches;
          continue;
        }
        ++queries;
        std::sort(got.begin(), got.end());
        duplicates += std::adjacent_find(got.begin(), got.end()) != got.end();
        for (int i = 0; i < n; ++i)
        {
          const double d2 = hoembed::AabbTree::BoxDistance2(&boxes[6 * i], v);
          const bool visited = std::binary_search(got.begin(), got.end(), i);
          // a box nearer than the final radius must be visited; none beyond the first
          if ((d2 < best2 && !visited) || (visited && !(d2 < radius * radius)))
            ++nearMismatches;
        }
        nearHits += static_cast<int>(got.size());
      }
    }
  }
  HOEMBED_CHECK(mismatches == 0, "BoxGrid: %d of %d queries differ from a scan of the boxes",
    mismatches, queries);
  HOEMBED_CHECK(duplicates == 0, "BoxGrid: %d queries report an item twice", duplicates);
  HOEMBED_CHECK(hits > queries, "BoxGrid: only %d hits in %d queries (test setup)", hits, queries);
  HOEMBED_CHECK(nearMismatches == 0,
    "BoxGrid::VisitNearer: %d boxes missed or visited beyond "
    "the radius",
    nearMismatches);
  HOEMBED_CHECK(nearHits > 1000, "BoxGrid::VisitNearer: only %d visits (test setup)", nearHits);
  HOEMBED_CHECK(boxDistanceMismatches == 0,
    "AabbTree::BoxDistance2: %d of the point-box "
    "distances differ from the clamped point's",
    boxDistanceMismatches);
  HOEMBED_CHECK(nearItemMismatches == 0,
    "BoxGrid::NearItem: %d queries without an item, or "
    "with one whose box misses a point some box holds",
    nearItemMismatches);
  std::printf(
    "box grid: %d queries, %d + %d hits, as a scan of every box\n", queries, hits, nearHits);
}

} // namespace

int main(int, char*[])
{
  TestBoxGrid();
  return hoembed_test::Report("TestBoxGrid");
}
