// hoembed::EmbeddingMesh (hoembedEmbeddingMesh.h): the boundary faces' lower bound on
// the distance, against closest-point solves and dense samples of each face.
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

// EmbeddingMesh::FaceLowerBound2 (the pruning rule of the boundary search) against the
// distance to each curved boundary face by brute force (7 constrained solves and a dense
// sample of the face): it must never exceed it, and must prune (be positive) often. The
// map shears the faces strongly in their own planes, so a bound that ignored the
// tangential deviation of the curved face from its straight triangle would fail here.
void ShearMap(double x[3])
{
  const double X = x[0], Y = x[1], Z = x[2];
  x[0] = X + 0.25 * std::sin(M_PI * Y) + 0.1 * Z * Z;
  x[1] = Y + 0.25 * std::sin(M_PI * X) - 0.1 * Z;
  x[2] = Z + 0.15 * std::sin(M_PI * X) * std::sin(M_PI * Y);
}

void TestFaceLowerBound()
{
  auto grid = MakeBoxTetMesh(2, 2, 2, 1.0, 1.0, 1.0, 2, ShearMap);
  int npc = 0;
  const auto conn = hoembed_test::MeshConnectivity(grid, npc);
  const auto pts = hoembed_test::PointsOf(grid);
  hoembed::EmbeddingMesh em;
  const std::string err = em.Build(pts.data(), grid->GetNumberOfPoints(),
    reinterpret_cast<const hoembed::EmbeddingMesh::Id*>(conn.data()), grid->GetNumberOfCells(),
    npc);
  HOEMBED_CHECK(err.empty(), "face bound: mesh build: %s", err.c_str());
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  const double starts[7][2] = { { 1.0 / 3, 1.0 / 3 }, { 0.8, 0.1 }, { 0.1, 0.8 }, { 0.1, 0.1 },
    { 0.45, 0.45 }, { 0.45, 0.1 }, { 0.1, 0.45 } };
  int over = 0, positive = 0, tight = 0, total = 0;
  double worst = 0.0;
  const hoembed::EmbeddingMesh::Id nbf = em.Topology.GetNumberOfBoundaryFaces();
  for (hoembed::EmbeddingMesh::Id f = 0; f < nbf; ++f)
  {
    const hoembed::QuadraticMap& m = em.FaceMaps[f];
    double c[3];
    const double centroid[2] = { 1.0 / 3, 1.0 / 3 };
    hoembed::EvaluateMap(m, centroid, c);
    for (int q = 0; q < 40; ++q)
    {
      // points around the face at distances from 0 to ~1 (near its edges too)
      double v[3];
      const double r = q < 20 ? 0.15 * U(rng) : 0.8 * U(rng);
      for (int d = 0; d < 3; ++d)
        v[d] = c[d] + r * (2.0 * U(rng) - 1.0) + 0.3 * (U(rng) - 0.5);
      double best = std::numeric_limits<double>::infinity();
      for (const auto& s0 : starts)
      {
        hoembed::ClosestPointResult res;
        hoembed::ClosestPointOnMap(m, v, s0, res, 200);
        best = std::min(best, res.Distance2);
      }
      for (int i = 0; i <= 60; ++i)
        for (int j = 0; i + j <= 60; ++j)
        {
          const double uv[2] = { i / 60.0, j / 60.0 };
          double x[3];
          hoembed::EvaluateMap(m, uv, x);
          const double e2 = (x[0] - v[0]) * (x[0] - v[0]) + (x[1] - v[1]) * (x[1] - v[1]) +
            (x[2] - v[2]) * (x[2] - v[2]);
          best = std::min(best, e2);
        }
      const double bound = em.FaceLowerBound2(f, v);
      ++total;
      if (bound > best * (1.0 + 1e-9) + 1e-24)
      {
        if (over < 5)
          std::fprintf(stderr, "face bound: face %lld bound %.17g > distance^2 %.17g\n",
            static_cast<long long>(f), bound, best);
        ++over;
      }
      if (best > 0.0)
        worst = std::max(worst, bound / best);
      positive += bound > 0.0;
      tight += bound > 0.5 * best;
    }
  }
  HOEMBED_CHECK(over == 0, "face bound: %d of %d bounds exceed the distance (max ratio %.17g)",
    over, total, worst);
  HOEMBED_CHECK(positive > total / 2, "face bound: only %d of %d bounds positive", positive, total);
  std::printf("face lower bound: %d samples, %d positive, %d above half the distance^2, max "
              "bound/distance^2 %.6f\n",
    total, positive, tight, worst);
}

} // namespace

int main(int, char*[])
{
  TestFaceLowerBound();
  return hoembed_test::Report("TestEmbeddingMesh");
}
